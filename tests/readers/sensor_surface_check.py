"""Which surface a noiseless `subtgraph sense` sequence saw, measured apart from subtgraph's code
(issue 39 item 1): every return checked, moved into the world's frame by the ground truth, lies
on the visual surface (mesh/world.obj, with mesh/services.obj when the world has it) by
trimesh's closest point, and is compared with its distance to the collision copy
(mesh/collision.obj), which a LiDAR casting there would lie on instead.

    sensor_surface_check.py SEQUENCE WORLD [--standing-scans N] [--moving-scans N] [--per-scan N]

Two ways in, each independent of the other:

- KITTI: `N` scans taken standing (a scan whose row of `kitti/poses.txt` is the next one's: the
  platform did not move while it was fired, so every return was fired from that pose), each
  `kitti/velodyne/NNNNNN.bin` point moved by its row (`--per-scan` of them, evenly spread);
- the bag (rosbags): `N` scans of the moving part, each return moved by the
  /ground_truth/odom pose at its own firing time (interpolated; Ouster's `t` field, Velodyne's
  `time`, Livox's `timestamp`) composed with /tf_static's LiDAR mount; `--per-scan` returns of
  each, evenly spread.

Prints one JSON object: the returns checked, their largest and 99th percentile distance to
the visual surface, and the share of them farther than 5 mm from the collision surface, with
its median and 99th percentile distance there (metres). Asserts nothing: the test holds the
numbers to their bounds.
"""
import argparse
import json
from pathlib import Path

import numpy as np
import trimesh
from obj_reader import read_obj
from rosbags.highlevel import AnyReader

DTYPES = {1: "i1", 2: "u1", 3: "i2", 4: "u2", 5: "i4", 6: "u4", 7: "f4", 8: "f8"}
#: Metres beyond which a return is "off" the collision surface (the visual surface's returns
#: lie within the OBJ's 0.1 mm rounding of it when the two agree).
OFF = 0.005


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


def load_mesh(paths):
    """One trimesh of the OBJ files' triangles (read by obj_reader, numpy only)."""
    vs, ts, base = [], [], 0
    for p in paths:
        o = read_obj(p)
        vs.append(o.vertices)
        ts.append(o.triangles + base)
        base += len(o.vertices)
    return trimesh.Trimesh(np.vstack(vs), np.vstack(ts), process=False)


def kitti_returns(seq, meta, scans, per_scan):
    """World-frame returns of up to `scans` KITTI scans taken standing (`per_scan` of each,
    evenly spread): scans whose pose is the next scan's to the last digit, so the platform did
    not move while they were fired (sequence.json's `still` phase includes the start of the
    first move)."""
    poses = np.loadtxt(seq / "kitti" / "poses.txt").reshape(-1, 3, 4)
    standing = [i for i in range(len(poses) - 1) if np.array_equal(poses[i], poses[i + 1])]
    standing = standing[:: max(1, len(standing) // max(1, scans))][:scans]
    out = []
    for i in standing:
        kp = np.fromfile(seq / "kitti" / "velodyne" / f"{i:06d}.bin", dtype=np.float32).reshape(-1, 4)
        kp = kp[np.linspace(0, len(kp) - 1, min(len(kp), per_scan)).astype(int)]
        xyz = kp[:, :3].astype(np.float64)
        out.append(xyz @ poses[i, :, :3].T + poses[i, :, 3])
    return (np.vstack(out) if out else np.zeros((0, 3))), len(standing)


def bag_returns(seq, meta, moving, per_scan):
    """World-frame returns of `moving` scans after the still ones, each at its firing time."""
    driver = meta["lidar"]["driver"]
    first = sum(1 for s in meta["scans"] if s.get("phase") == "still")
    scans = meta["scan_count"]
    want = set(np.linspace(first, scans - 1, max(1, moving)).astype(int).tolist()) if scans > first else set()
    odom_t, odom_p, odom_q, tf, clouds = [], [], [], {}, {}
    index = 0
    with AnyReader([seq / "bag"]) as reader:
        for conn, _, raw in reader.messages():
            if conn.topic not in ("/ground_truth/odom", "/tf_static", "/points"):
                continue
            m = reader.deserialize(raw, conn.msgtype)
            if conn.topic == "/ground_truth/odom":
                s = m.header.stamp
                odom_t.append(s.sec + s.nanosec * 1e-9)
                p, q = m.pose.pose.position, m.pose.pose.orientation
                odom_p.append([p.x, p.y, p.z])
                odom_q.append([q.x, q.y, q.z, q.w])
            elif conn.topic == "/tf_static":
                for t in m.transforms:
                    tr, r = t.transform.translation, t.transform.rotation
                    tf[t.child_frame_id] = (np.array([tr.x, tr.y, tr.z]),
                                            quat_to_matrix([r.x, r.y, r.z, r.w]))
            else:
                if index in want:
                    dtype = np.dtype({"names": [f.name for f in m.fields],
                                      "formats": [DTYPES[f.datatype] for f in m.fields],
                                      "offsets": [f.offset for f in m.fields],
                                      "itemsize": m.point_step})
                    s = m.header.stamp
                    clouds[index] = (s.sec + s.nanosec * 1e-9, np.frombuffer(bytes(m.data), dtype=dtype))
                index += 1
    odom_t, odom_p, odom_q = np.array(odom_t), np.array(odom_p), np.array(odom_q)
    mount_t, mount_r = tf[meta["frames"]["lidar"]]

    def pose(t):
        i = int(np.clip(np.searchsorted(odom_t, t) - 1, 0, len(odom_t) - 2))
        f = (t - odom_t[i]) / (odom_t[i + 1] - odom_t[i])
        return odom_p[i] + f * (odom_p[i + 1] - odom_p[i]), quat_to_matrix(slerp(odom_q[i], odom_q[i + 1], f))

    out = []
    for stamp, arr in clouds.values():
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
        for i in np.linspace(0, len(pts) - 1, min(len(pts), per_scan)).astype(int):
            p, r = pose(times[i])
            out.append(p + r @ (mount_t + mount_r @ pts[i]))
    return (np.array(out) if out else np.zeros((0, 3))), len(clouds)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("sequence")
    ap.add_argument("world")
    ap.add_argument("--standing-scans", type=int, default=4)
    ap.add_argument("--moving-scans", type=int, default=8)
    ap.add_argument("--per-scan", type=int, default=1500)
    args = ap.parse_args()
    seq, world = Path(args.sequence), Path(args.world)
    meta = json.loads((seq / "sequence.json").read_text())

    surfaces = [world / "mesh" / "world.obj"]
    if (world / "mesh" / "services.obj").exists():
        surfaces.append(world / "mesh" / "services.obj")
    visual = load_mesh(surfaces)
    collision = load_mesh([world / "mesh" / "collision.obj"])

    still, still_scans = kitti_returns(seq, meta, args.standing_scans, args.per_scan)
    moving, moving_scans = bag_returns(seq, meta, args.moving_scans, args.per_scan)
    out = {"surfaces": [p.name for p in surfaces], "visual_triangles": int(len(visual.faces)),
           "collision_triangles": int(len(collision.faces))}
    every = []
    for name, pts, scans in [("kitti_standing", still, still_scans), ("bag_moving", moving, moving_scans)]:
        if len(pts) == 0:
            out[name] = {"scans": scans, "returns": 0}
            continue
        _, dv, _ = trimesh.proximity.closest_point(visual, pts)
        _, dc, _ = trimesh.proximity.closest_point(collision, pts)
        every.append((dv, dc))
        out[name] = {
            "scans": scans,
            "returns": int(len(pts)),
            "visual_max_m": float(dv.max()),
            "visual_p99_m": float(np.quantile(dv, 0.99)),
            "collision_off_share": float(np.mean(dc > OFF)),
            "collision_median_m": float(np.median(dc)),
            "collision_p99_m": float(np.quantile(dc, 0.99)),
        }
    if every:
        dv = np.concatenate([d[0] for d in every])
        dc = np.concatenate([d[1] for d in every])
        out["returns"] = int(len(dv))
        out["visual_max_m"] = float(dv.max())
        out["collision_off_share"] = float(np.mean(dc > OFF))
        out["collision_p99_m"] = float(np.quantile(dc, 0.99))
    print(json.dumps(out))


if __name__ == "__main__":
    main()
