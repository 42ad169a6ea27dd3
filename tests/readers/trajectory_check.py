"""Checks a `subtgraph score --trajectory` folder against evo on the same files and options.

Usage: trajectory_check.py SCORE_DIR

Reads SCORE_DIR/trajectory.json (which names the reference and estimate files, TUM or ROS 2
bags, and the options), runs evo's APE and RPE on the same files with the same options
(association with --t_max_diff, --align_origin / -a / -as, --delta N --delta_unit f, and
--delta 10/100 --delta_unit m --pairs_from_reference), and compares every number: APE and RPE statistics,
the per-pose APE, aligned positions and RPE of errors.csv, the final drift, the points and the
failure flag (these last three computed with numpy from evo's per-pose errors and its aligned
trajectory). Agreement is to 1e-6 relative (1e-9 absolute for values near 0). One `evo_ape`
command-line run with --save_results is compared too, so the library calls used for the rest
are the command line's own (`evo_ape tum`, or `evo_ape bag2` when both are topics of one bag).
Bags are read by evo's own bag reader (rosbags), which takes each message's header stamp.
With `--associate interpolate` (which evo does not do) the reference is interpolated here at
the estimate's times with numpy (positions) and scipy's Slerp (orientations), and evo scores
the pairs as they are. Prints one line per checked group; exits non-zero on a mismatch.
"""

import copy
import csv
import json
import math
import os
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

import numpy as np
from evo.core import filters, metrics, sync
from evo.core.trajectory import PoseTrajectory3D
from evo.main_ape import ape
from evo.main_rpe import rpe
from evo.tools import file_interface

REL, ABS = 1e-6, 1e-9
STATS = ["rmse", "mean", "median", "std", "min", "max", "sse"]


def close(a, b):
    return abs(a - b) <= max(ABS, REL * max(abs(a), abs(b)))


def same(what, ours, theirs):
    if not close(ours, theirs):
        sys.exit(f"MISMATCH {what}: subtgraph {ours!r}, evo {theirs!r}")


def same_stats(what, ours, theirs):
    for k in STATS:
        same(f"{what}.{k}", ours[k], theirs[k])


def read(file):
    """A trajectory.json `reference`/`estimate` entry as evo reads it."""
    if file["format"] == "tum":
        return file_interface.read_tum_trajectory_file(file["file"])
    assert file["format"] == "ros2-bag", f"the evo check reads TUM files and bags, not {file}"
    from rosbags.rosbag2 import Reader

    with Reader(file["file"]) as reader:
        return file_interface.read_bag_trajectory(reader, file["topic"])


def interpolated(ref, est, max_gap):
    """The reference interpolated at the estimate's times (numpy for positions, scipy's Slerp
    for orientations) where the two reference poses around a time are at most max_gap apart,
    and the estimate's poses at those times."""
    from scipy.spatial.transform import Rotation, Slerp

    t_ref, t_est = ref.timestamps, est.timestamps
    keep, at = [], []
    for i, t in enumerate(t_est):
        j = int(np.searchsorted(t_ref, t, side="left"))
        if j == len(t_ref):
            continue
        if t_ref[j] == t or (j > 0 and t_ref[j] - t_ref[j - 1] <= max_gap):
            keep.append(i)
            at.append(t)
    at = np.array(at)
    xyz = np.column_stack([np.interp(at, t_ref, ref.positions_xyz[:, a]) for a in range(3)])
    wxyz = ref.orientations_quat_wxyz
    slerp = Slerp(t_ref, Rotation.from_quat(wxyz[:, [1, 2, 3, 0]]))
    quat = slerp(at).as_quat()[:, [3, 0, 1, 2]]
    synced_ref = PoseTrajectory3D(xyz, quat, at)
    e = np.array(keep)
    synced_est = PoseTrajectory3D(
        est.positions_xyz[e], est.orientations_quat_wxyz[e], est.timestamps[e]
    )
    return synced_ref, synced_est


def main():
    out = Path(sys.argv[1])
    doc = json.loads((out / "trajectory.json").read_text())
    opt = doc["options"]
    ref_file, est_file = doc["reference"]["file"], doc["estimate"]["file"]
    ref = read(doc["reference"])
    est = read(doc["estimate"])
    if opt["associate"] == "interpolate":
        ref, est = interpolated(ref, est, opt["max_gap_s"])
    else:
        ref, est = sync.associate_trajectories(ref, est, max_diff=opt["max_diff_s"])
    assert doc["associated_poses"] == ref.num_poses, (doc["associated_poses"], ref.num_poses)
    align = {
        "none": dict(align_origin=True),
        "se3": dict(align=True),
        "sim3": dict(align=True, correct_scale=True),
    }[opt["align"]]

    # APE, through the library and once through the command line.
    res = ape(copy.deepcopy(ref), copy.deepcopy(est), metrics.PoseRelation.translation_part, **align)
    same_stats("ape_m", doc["ape_m"], res.stats)
    cli_flags = {"none": ["--align_origin"], "se3": ["-a"], "sim3": ["-as"]}[opt["align"]]
    formats = (doc["reference"]["format"], doc["estimate"]["format"])
    cli_args = None
    if opt["associate"] == "interpolate":
        pass  # evo's command line cannot interpolate
    elif formats == ("tum", "tum"):
        cli_args = ["tum", ref_file, est_file]
    elif formats == ("ros2-bag", "ros2-bag") and ref_file == est_file:
        cli_args = ["bag2", ref_file, doc["reference"]["topic"], doc["estimate"]["topic"]]
    if cli_args is not None:
        with tempfile.TemporaryDirectory() as tmp:
            z = os.path.join(tmp, "ape.zip")
            evo_ape = Path(sys.executable).parent / "evo_ape"
            subprocess.run(
                [str(evo_ape), *cli_args, *cli_flags, "--t_max_diff",
                 repr(opt["max_diff_s"]), "--save_results", z, "--no_warnings"],
                check=True, capture_output=True,
            )
            with zipfile.ZipFile(z) as f:
                cli_stats = json.loads(f.read("stats.json"))
        same_stats(f"ape_m (evo_ape {cli_args[0]} command line)", doc["ape_m"], cli_stats)
    print(f"ape ok: rmse {res.stats['rmse']}")

    errors = res.np_arrays["error_array"]
    aligned = res.trajectories[est.name or "estimate"].positions_xyz
    ref_assoc = res.trajectories[ref.name or "reference"]
    rows = list(csv.DictReader(open(out / "errors.csv")))
    assert len(rows) == len(errors), (len(rows), len(errors))
    for k, row in enumerate(rows):
        same(f"errors.csv row {k} ape_m", float(row["ape_m"]), errors[k])
        for a, c in enumerate("xyz"):
            same(f"errors.csv row {k} {c}_estimate", float(row[f"{c}_estimate"]), aligned[k][a])
    print(f"errors.csv ok: {len(rows)} poses")

    # RPE over frames: translation and rotation, and the per-pose column.
    d = opt["delta_frames"]
    for rel, key, col in [
        (metrics.PoseRelation.translation_part, "translation_m", "rpe_m"),
        (metrics.PoseRelation.rotation_angle_deg, "rotation_deg", "rpe_deg"),
    ]:
        r = rpe(copy.deepcopy(ref), copy.deepcopy(est), rel, delta=d,
                delta_unit=metrics.Unit.frames, **align)
        same_stats(f"rpe.{key}", doc["rpe"][key], r.stats)
        ids = filters.filter_pairs_by_index(ref.poses_se3, d)
        for (i, j), e in zip(ids, r.np_arrays["error_array"]):
            same(f"errors.csv row {j} {col}", float(rows[j][col]), e)
    print(f"rpe over {d} frame(s) ok")

    # RPE over 10 m and 100 m of the reference's path.
    for seg in doc["segments"]:
        delta = seg["delta"]
        for rel, key, per in [
            (metrics.PoseRelation.translation_part, "translation_m", "translation_percent"),
            (metrics.PoseRelation.rotation_angle_deg, "rotation_deg", "rotation_deg_per_100m"),
        ]:
            try:
                r = rpe(copy.deepcopy(ref), copy.deepcopy(est), rel, delta=delta,
                        delta_unit=metrics.Unit.meters, pairs_from_reference=True, **align)
            except filters.FilterException:
                assert seg[key] is None and seg[per] is None, (
                    f"evo finds no pair {delta} m apart, subtgraph does: {seg}"
                )
                continue
            same_stats(f"segments[{delta} m].{key}", seg[key], r.stats)
            same(f"segments[{delta} m].{per}", seg[per], r.stats["mean"] / delta * 100.0)
        print(f"rpe over {delta} m ok")

    # Final drift, points and the failure flag, from evo's errors and aligned trajectory.
    length = ref_assoc.path_length
    same("path_length_m", doc["path_length_m"], length)
    same("final_drift_m", doc["final_drift_m"], errors[-1])
    same("final_drift_percent", doc["final_drift_percent"], 100.0 * errors[-1] / length)
    thresholds = opt["points_thresholds_m"]

    def points(e):
        return next((p for limit, p in thresholds if e <= limit), 0)

    same("points_mean", doc["points_mean"], float(np.mean([points(e) for e in errors])))
    assert doc["points_final"] == points(errors[-1]), (doc["points_final"], errors[-1])
    ref_xyz = ref_assoc.positions_xyz
    first = None
    for k in range(len(errors)):
        if errors[k] > opt["fail_ape_m"]:
            first = ("divergence", k)
            break
        if k > 0:
            step = np.linalg.norm(aligned[k] - aligned[k - 1])
            truth = np.linalg.norm(ref_xyz[k] - ref_xyz[k - 1])
            if step - truth > opt["fail_jump_m"]:
                first = ("jump", k)
                break
    ours = doc["failure"]
    assert doc["failed"] == (first is not None), (doc["failed"], first)
    if first is not None:
        assert (ours["kind"], ours["pose"]) == first, (ours, first)
    print(f"drift, points and failure ok: failure {first}")


if __name__ == "__main__":
    main()
