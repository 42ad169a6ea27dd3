"""Runs real odometry on a sensor sequence (`subtgraph sense`) with its own command-line tools,
and scores it with evo's.

    odometry_check.py SEQUENCE WORKDIR [--runs kiss-bag,kiss-kitti,genz-bag,genz-kitti]
                      [--delta METRES]

- KISS-ICP (LiDAR only): `kiss_icp_pipeline SEQUENCE/bag --topic /points` and
  `kiss_icp_pipeline SEQUENCE/kitti/velodyne` (the KITTI scans);
- GenZ-LIO (LiDAR-inertial): `genz_lio_pipeline run SEQUENCE/bag` and
  `genz_lio_pipeline run SEQUENCE/kitti/velodyne` (its folder reader takes the IMU from
  imu.csv beside the scans), with its packaged configuration for the sequence's driver, the
  topics, beam count, rate and LiDAR-to-IMU extrinsic taken from sequence.json;
- evo: `evo_rpe` (translation error over DELTA metres of path, default 10) and `evo_ape` (after
  an SE(3) alignment) against the ground truth at the instants each method's poses are for.
  GenZ-LIO stamps its poses at each scan's end (it deskews to it): ground_truth.tum's poses,
  at the scans' starts, are those instants. KISS-ICP deskews to the middle of each scan and
  stamps it with the scan's start (the bag) or gives no time (KITTI): its poses are compared
  with the ground truth half a scan later, the bag's /ground_truth/odom (100 Hz) composed with
  the LiDAR's mount (/tf_static).

Prints one JSON line: per run, the drift (mean RPE over DELTA metres, as a percentage of
DELTA), the APE RMSE and the path length, or the error the tool ended with.
"""
import json
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import yaml

seq = Path(sys.argv[1]).resolve()
work = Path(sys.argv[2]).resolve()
work.mkdir(parents=True, exist_ok=True)
args = sys.argv[3:]
runs = "kiss-bag,kiss-kitti,genz-bag,genz-kitti"
delta = 10.0
for i, a in enumerate(args):
    if a == "--runs":
        runs = args[i + 1]
    if a == "--delta":
        delta = float(args[i + 1])
runs = runs.split(",")
bin_dir = Path(sys.executable).parent
meta = json.loads((seq / "sequence.json").read_text())


def run(cmd, cwd):
    p = subprocess.run([str(c) for c in cmd], cwd=cwd, capture_output=True, text=True)
    if p.returncode != 0:
        raise RuntimeError(f"{cmd[0]} failed ({p.returncode}): {p.stderr[-2000:]}{p.stdout[-1000:]}")
    return p.stdout


def stat(text, name):
    m = re.search(rf"^\s*{name}\s+([-0-9.eE+]+)\s*$", text, re.M)
    if not m:
        raise RuntimeError(f"evo printed no {name}: {text[-1500:]}")
    return float(m.group(1))


def score(fmt, truth, estimate):
    try:
        ape = run([bin_dir / "evo_ape", fmt, truth, estimate, "--align"], work)
    except RuntimeError as e:
        # A straight route has no rotation for Umeyama's alignment to find: align the first
        # poses instead.
        if "Degenerate covariance" not in str(e):
            raise
        ape = run([bin_dir / "evo_ape", fmt, truth, estimate, "--align_origin"], work)
    if fmt == "tum":
        gt = np.loadtxt(truth)[:, 1:4]
        est = np.loadtxt(estimate)[:, 1:4]
    else:
        gt = np.loadtxt(truth).reshape(-1, 3, 4)[:, :, 3]
        est = np.loadtxt(estimate).reshape(-1, 3, 4)[:, :, 3]
    length = float(np.linalg.norm(np.diff(gt, axis=0), axis=1).sum())
    out = {
        "ape_rmse_m": stat(ape, "rmse"),
        "path_length_m": length,
        "estimated_length_m": float(np.linalg.norm(np.diff(est, axis=0), axis=1).sum()),
    }
    try:
        rpe = run([bin_dir / "evo_rpe", fmt, truth, estimate, "--delta", delta, "--delta_unit",
                   "m", "--pose_relation", "trans_part"], work)
        out["drift_percent"] = 100.0 * stat(rpe, "mean") / delta
        out["rpe_max_m"] = stat(rpe, "max")
    except RuntimeError as e:
        # evo finds no pair of poses DELTA apart along the estimate: the method thinks it
        # barely moved. Its drift is then its APE over the path driven.
        if "empty index list" not in str(e):
            raise
        out["drift_percent"] = 100.0 * out["ape_rmse_m"] / length
        out["lost"] = True
    return out


def genz_config(out):
    """GenZ-LIO's packaged configuration for this driver, told about this sequence."""
    driver = meta["lidar"]["driver"]
    packaged = {"ouster": "default/ouster.yaml", "velodyne": "default/velodyne.yaml",
                "livox": "default/mid360.yaml"}[driver]
    base = work / f"genz-{driver}.yaml"
    if not base.exists():
        run([bin_dir / "genz_lio_pipeline", "export-config", packaged, base], work)
    cfg = yaml.safe_load(base.read_text())
    cfg["common"]["lidar_topic"] = "/points"
    cfg["common"]["imu_topic"] = "/imu"
    pre = cfg["preprocess"]
    pre["lidar_type"] = {"ouster": "ouster", "velodyne": "velodyne", "livox": "livox_pcl"}[driver]
    pre["scan_line"] = int(meta["lidar"]["pattern"].get("lines") or len(meta["lidar"]["pattern"]["elevations_deg"]))
    pre["scan_rate"] = int(round(meta["lidar"]["rate_hz"]))
    pre["blind_min"] = max(0.1, meta["lidar"]["range_m"][0])
    ext = meta["extrinsics"]
    lidar = np.array(ext["base_link_to_lidar"]["translation"])
    imu = np.array(ext["base_link_to_imu"]["translation"])
    # The mounts are not rotated: the LiDAR in the IMU's frame is the difference of positions.
    for k in ("base_link_to_lidar", "base_link_to_imu"):
        assert np.allclose(ext[k]["quaternion_xyzw"], [0, 0, 0, 1]), ext
    cfg["mapping"]["extrinsic_t"] = (lidar - imu).tolist()
    cfg["mapping"]["extrinsic_r"] = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    # One thread: the same poses every run (and no fight with a loaded machine's other work).
    cfg["runtime"]["max_threads"] = 1
    out.write_text(yaml.safe_dump(cfg))
    return out


def mid_scan_truth():
    """The LiDAR's pose half a scan after each scan's start, from the bag's odometry: TUM
    (stamped with the scan's start, as KISS-ICP stamps) and KITTI lines."""
    from rosbags.highlevel import AnyReader
    period = meta["scan_period_s"]
    odom = []
    with AnyReader([seq / "bag"]) as reader:
        conns = [c for c in reader.connections if c.topic in ("/ground_truth/odom", "/tf_static")]
        for c, _, raw in reader.messages(connections=conns):
            m = reader.deserialize(raw, c.msgtype)
            if c.topic == "/tf_static":
                for t in m.transforms:
                    if t.child_frame_id == meta["frames"]["lidar"]:
                        tr = t.transform.translation
                        mount = np.array([tr.x, tr.y, tr.z])
            else:
                s, p, q = m.header.stamp, m.pose.pose.position, m.pose.pose.orientation
                odom.append([s.sec + s.nanosec * 1e-9, p.x, p.y, p.z, q.x, q.y, q.z, q.w])
    odom = np.array(odom)
    starts = np.loadtxt(seq / "ground_truth.tum")[:, 0]
    tum, kitti = [], []
    for t0 in starts:
        i = int(np.argmin(np.abs(odom[:, 0] - (t0 + period / 2))))
        assert abs(odom[i, 0] - (t0 + period / 2)) < 1e-6, "odometry every half scan"
        x, y, z, w = odom[i, 4:8]
        r = np.array([
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ])
        p = odom[i, 1:4] + r @ mount
        tum.append([t0, *p, x, y, z, w])
        kitti.append(np.c_[r, p].ravel())
    np.savetxt(work / "mid_scan.tum", np.array(tum), fmt="%.9f")
    np.savetxt(work / "mid_scan_kitti.txt", np.array(kitti), fmt="%.9e")
    return work / "mid_scan.tum", work / "mid_scan_kitti.txt"


def kiss_config():
    """KISS-ICP's defaults (dumped by the tool itself), on one thread."""
    path = work / "kiss.yaml"
    if not path.exists():
        path.write_text(yaml.safe_dump({"registration": {"max_num_threads": 1}}))
    return path


result = {"delta_m": delta}
if any(r.startswith("kiss") for r in runs):
    mid_tum, mid_kitti = mid_scan_truth()
for name in runs:
    here = work / name
    here.mkdir(exist_ok=True)
    try:
        if name == "kiss-bag":
            run([bin_dir / "kiss_icp_pipeline", seq / "bag", "--topic", "/points",
                 "--config", kiss_config()], here)
            est = next(here.glob("results/*/bag_poses_tum.txt"))
            result[name] = score("tum", mid_tum, est)
        elif name == "kiss-kitti":
            run([bin_dir / "kiss_icp_pipeline", seq / "kitti" / "velodyne", "--config", kiss_config()],
                here)
            est = next(here.glob("results/*/velodyne_poses_kitti.txt"))
            result[name] = score("kitti", mid_kitti, est)
        elif name in ("genz-bag", "genz-kitti"):
            cfg = genz_config(here / "genz.yaml")
            data = seq / "bag" if name == "genz-bag" else seq / "kitti" / "velodyne"
            run([bin_dir / "genz_lio_pipeline", "run", data, "-c", cfg, "-o", here / "out",
                 "-f", "tum"], here)
            est = next((here / "out").glob("*_tum.txt"))
            result[name] = score("tum", seq / "ground_truth.tum", est)
        else:
            raise SystemExit(f"unknown run {name}")
    except (RuntimeError, StopIteration) as e:
        result[name] = {"error": str(e)[-600:]}
print(json.dumps(result))
