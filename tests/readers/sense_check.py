"""Checks a sensor sequence (`subtgraph sense`) with programs that did not write it.

    sense_check.py SEQUENCE MESH.obj [--noiseless]

- rosbags reads the bag: its topics, types and counts are the ones sequence.json lists, every
  point cloud has its driver's fields;
- every return of a sample of scans, moved by the ground truth's pose at its own time (the
  /ground_truth/odom messages interpolated, then /tf_static's LiDAR mount), lies on the mesh
  (trimesh's nearest point on MESH.obj) within the range noise;
- the KITTI scans are the bag's returns, float for float, and kitti/poses.txt and
  ground_truth.tum are the odometry's pose at each scan's start composed with the mount;
- with --noiseless: the IMU's gyroscope is the odometry's orientation differentiated, its
  accelerometer the IMU mount's position differentiated twice, minus gravity, in its frame.

Prints one JSON line of what it measured.
"""
import json
import sys
from pathlib import Path

import numpy as np
import trimesh
from rosbags.highlevel import AnyReader

seq = Path(sys.argv[1])
mesh = trimesh.load(sys.argv[2], force="mesh", process=False)
noiseless = "--noiseless" in sys.argv[3:]
meta = json.loads((seq / "sequence.json").read_text())
scans = meta["scan_count"]
sigma = meta["lidar"]["range_noise_m"]
driver = meta["lidar"]["driver"]
fields_of = {
    "ouster": ["x", "y", "z", "intensity", "t", "reflectivity", "ring", "ambient", "range"],
    "velodyne": ["x", "y", "z", "intensity", "ring", "time"],
    "livox": ["x", "y", "z", "intensity", "tag", "line", "timestamp"],
}
DTYPES = {1: "i1", 2: "u1", 3: "i2", 4: "u2", 5: "i4", 6: "u4", 7: "f4", 8: "f8"}


def quat_to_matrix(q):
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def slerp(q0, q1, f):
    d = np.dot(q0, q1)
    if d < 0:
        q1, d = -q1, -d
    if d > 0.9995:
        q = q0 + f * (q1 - q0)
        return q / np.linalg.norm(q)
    a = np.arccos(d)
    return (np.sin((1 - f) * a) * q0 + np.sin(f * a) * q1) / np.sin(a)


odom_t, odom_p, odom_q = [], [], []
clouds = {}
imu = []
tf = {}
counts = {}
want = set(range(0, scans, max(1, scans // 8)))
with AnyReader([seq / "bag"]) as reader:
    types = {c.topic: c.msgtype for c in reader.connections}
    expected = {
        "/points": "sensor_msgs/msg/PointCloud2",
        "/imu": "sensor_msgs/msg/Imu",
        "/ground_truth/odom": "nav_msgs/msg/Odometry",
        "/tf_static": "tf2_msgs/msg/TFMessage",
    }
    for topic, t in expected.items():
        assert types.get(topic) == t, (topic, types)
    index = 0
    for conn, stamp, raw in reader.messages():
        m = reader.deserialize(raw, conn.msgtype)
        counts[conn.topic] = counts.get(conn.topic, 0) + 1
        if conn.topic == "/ground_truth/odom":
            s = m.header.stamp
            odom_t.append(s.sec + s.nanosec * 1e-9)
            p, q = m.pose.pose.position, m.pose.pose.orientation
            odom_p.append([p.x, p.y, p.z])
            odom_q.append([q.x, q.y, q.z, q.w])
        elif conn.topic == "/tf_static":
            for t in m.transforms:
                tr, r = t.transform.translation, t.transform.rotation
                tf[t.child_frame_id] = (np.array([tr.x, tr.y, tr.z]), quat_to_matrix([r.x, r.y, r.z, r.w]))
        elif conn.topic == "/imu":
            s = m.header.stamp
            a, g = m.linear_acceleration, m.angular_velocity
            imu.append([s.sec + s.nanosec * 1e-9, a.x, a.y, a.z, g.x, g.y, g.z])
        elif conn.topic == "/points":
            names = [f.name for f in m.fields]
            assert names == fields_of[driver], names
            if index in want:
                dtype = np.dtype({
                    "names": names,
                    "formats": [DTYPES[f.datatype] for f in m.fields],
                    "offsets": [f.offset for f in m.fields],
                    "itemsize": m.point_step,
                })
                arr = np.frombuffer(bytes(m.data), dtype=dtype)
                assert len(arr) == m.width * m.height
                s = m.header.stamp
                clouds[index] = (s.sec + s.nanosec * 1e-9, arr, m.header.frame_id)
            index += 1
assert counts["/points"] == scans, (counts, scans)
assert counts["/tf_static"] == 1
odom_t, odom_p, odom_q = np.array(odom_t), np.array(odom_p), np.array(odom_q)
assert np.all(np.diff(odom_t) > 0)


def base_pose(t):
    i = int(np.clip(np.searchsorted(odom_t, t) - 1, 0, len(odom_t) - 2))
    f = (t - odom_t[i]) / (odom_t[i + 1] - odom_t[i])
    p = odom_p[i] + f * (odom_p[i + 1] - odom_p[i])
    q = slerp(odom_q[i], odom_q[i + 1], f)
    return p, quat_to_matrix(q)


lidar_frame = meta["frames"]["lidar"]
mount_t, mount_r = tf[lidar_frame]
distances = []
returns_checked = 0
for k, (stamp, arr, frame) in clouds.items():
    assert frame == lidar_frame
    if driver == "ouster":
        valid = arr["range"] > 0
        times = stamp + arr["t"][valid].astype(np.float64) * 1e-9
    elif driver == "velodyne":
        valid = np.ones(len(arr), bool)
        times = stamp + arr["time"].astype(np.float64)
    else:
        valid = np.ones(len(arr), bool)
        times = arr["timestamp"] * 1e-9
    pts = np.stack([arr["x"], arr["y"], arr["z"]], axis=1)[valid].astype(np.float64)
    # A sample of returns, evenly spread over the scan.
    pick = np.linspace(0, len(pts) - 1, min(len(pts), 1500)).astype(int)
    world = []
    for i in pick:
        p, r = base_pose(times[i])
        world.append(p + r @ (mount_t + mount_r @ pts[i]))
    _, d, _ = mesh.nearest.on_surface(np.array(world))
    distances.append(d)
    returns_checked += len(pick)
    # The KITTI scan is the bag's returns, float for float.
    kitti = seq / "kitti" / "velodyne" / f"{k:06d}.bin"
    if kitti.exists():
        kp = np.fromfile(kitti, dtype=np.float32).reshape(-1, 4)
        bag_xyz = np.stack([arr["x"], arr["y"], arr["z"]], axis=1)[valid]
        if driver == "ouster":
            # The bag's cloud is organized a row per ring; the KITTI scan in firing order
            # (column by column): compare as sets of rows, sorted.
            a = np.sort(bag_xyz.view([("", np.float32)] * 3).ravel())
            b = np.sort(np.ascontiguousarray(kp[:, :3]).view([("", np.float32)] * 3).ravel())
            assert np.array_equal(a, b), k
        else:
            assert np.array_equal(bag_xyz, kp[:, :3]), k
distances = np.concatenate(distances)
tolerance = 4.0 * sigma + 0.01
assert distances.max() < tolerance, (distances.max(), tolerance)

# Ground-truth files: the odometry's pose at each scan's start composed with the mount.
tum = np.loadtxt(seq / "ground_truth.tum")
assert len(tum) == scans
worst_pose = 0.0
for row in tum[:: max(1, scans // 50)]:
    p, r = base_pose(row[0])
    want_p = p + r @ mount_t
    worst_pose = max(worst_pose, np.linalg.norm(want_p - row[1:4]))
assert worst_pose < 1e-3, worst_pose
if (seq / "kitti").exists():
    poses = np.loadtxt(seq / "kitti" / "poses.txt").reshape(-1, 3, 4)
    assert len(poses) == scans
    assert np.abs(poses[:, :, 3] - tum[:, 1:4]).max() < 1e-6
    assert len(list((seq / "kitti" / "velodyne").glob("*.bin"))) == scans

# The platform kept its clearance: the free radius about its clearance point, along the whole
# route (every odometry message), is at least what sequence.json says it needs.
platform = meta["platform"]
points = []
for i in range(0, len(odom_t), 5):
    r = quat_to_matrix(odom_q[i])
    points.append(odom_p[i] + r @ np.array([0.0, 0.0, platform["clearance_height"]]))
_, free, _ = mesh.nearest.on_surface(np.array(points))
assert free.min() >= platform["clearance"] - 0.01, (free.min(), platform["clearance"])

result = {
    "scans": scans,
    "least_clearance_m": float(free.min()),
    "returns_checked": returns_checked,
    "max_distance_m": float(distances.max()),
    "rms_distance_m": float(np.sqrt(np.mean(distances ** 2))),
    "tolerance_m": tolerance,
    "worst_pose_m": float(worst_pose),
    "topics": counts,
}

if noiseless:
    # The IMU against the odometry differentiated: rates from neighbouring orientations,
    # specific force from the IMU mount's position differentiated twice, plus gravity.
    imu = np.array(imu)
    imu_t, imu_r = tf["imu_link"]
    h = odom_t[1] - odom_t[0]
    worst_g, worst_a = 0.0, 0.0
    for i in range(2, len(odom_t) - 2, 7):
        t = odom_t[i]
        j = np.argmin(np.abs(imu[:, 0] - t))
        if abs(imu[j, 0] - t) > 1e-6:
            continue
        r0, r1 = quat_to_matrix(odom_q[i - 1]), quat_to_matrix(odom_q[i + 1])
        r = quat_to_matrix(odom_q[i])
        w = r.T @ (r1 - r0) / (2 * h)
        omega = np.array([w[2, 1] - w[1, 2], w[0, 2] - w[2, 0], w[1, 0] - w[0, 1]]) / 2
        pos = [odom_p[i + k] + quat_to_matrix(odom_q[i + k]) @ imu_t for k in (-1, 0, 1)]
        acc = (pos[0] - 2 * pos[1] + pos[2]) / h ** 2 + np.array([0, 0, 9.80665])
        f = imu_r.T @ (r.T @ acc)
        worst_g = max(worst_g, np.abs(imu_r.T @ omega - imu[j, 4:7]).max())
        worst_a = max(worst_a, np.abs(f - imu[j, 1:4]).max())
    assert worst_g < 2e-3, worst_g
    assert worst_a < 2e-2, worst_a
    result["imu_gyro_error"] = worst_g
    result["imu_accel_error"] = worst_a

print(json.dumps(result))
