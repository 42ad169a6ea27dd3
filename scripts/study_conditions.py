"""The conditions study's Python half (scripts/study-conditions runs it).

    study_conditions.py run kiss|genz SEQUENCE WORK   one method on a KITTI sequence: WORK/estimate.tum
    study_conditions.py analyse OUT                   per-segment errors against the labels

`run`: KISS-ICP (`kiss_icp_pipeline SEQUENCE/kitti/velodyne`, its defaults, one thread) or
GenZ-LIO (`genz_lio_pipeline run SEQUENCE/kitti/velodyne`, its packaged configuration for the
driver told about the sequence, as tests/readers/odometry_check.py does, one thread), the
estimate written as TUM. KISS-ICP deskews each scan to its middle: its poses are stamped half
a scan after the scan's start (`score --associate interpolate` then compares them with the
ground truth at that instant). GenZ-LIO stamps its poses at each scan's end.

`analyse`: every estimate cut into segments of SEGMENT seconds of sensor time (from SKIP
seconds in: past the still start and the first second of driving); a segment
where the platform moved at least MOVED metres *slides* when the method's estimate of the
distance driven is under SLIDE of the true one. Each segment's labels from sequence.json: the
share of its scans labelled degenerate, the median degeneracy score, the median
*along-travel* score (the Hessian's translation constraint along the direction the platform
moved, over the strongest: `(l0 c^2 + l1 (1 - c^2)) / l2` with `c` the cosine between the
travel and the weakest direction, `l0 <= l1 <= l2` the translation eigenvalues), and the mean
obscured share. Thresholds are fitted on odd seeds (best F1 for "slides when the score is
under the threshold") and judged on even seeds: precision and recall as a held-out test.
Prints a JSON summary and writes OUT/segments.csv.
"""
import csv
import json
import subprocess
import sys
from pathlib import Path

import numpy as np

SEGMENT = 5.0
MOVED = 2.0
# Segments begin this long after the sequence's start: past the still start and the first
# second of driving, where KISS-ICP's constant-velocity guess still lags the acceleration.
SKIP = 3.0
SLIDE = 0.9


def sh(cmd, cwd, log):
    with open(log, "a") as f:
        p = subprocess.run([str(c) for c in cmd], cwd=cwd, stdout=f, stderr=subprocess.STDOUT)
    if p.returncode != 0:
        raise SystemExit(f"{cmd[0]} failed ({p.returncode}): see {log}")


def run(method, seq, work):
    import yaml
    seq, work = Path(seq).resolve(), Path(work).resolve()
    work.mkdir(parents=True, exist_ok=True)
    log = work / "log.txt"
    bin_dir = Path(sys.executable).parent
    meta = json.loads((seq / "sequence.json").read_text())
    times = np.loadtxt(seq / "kitti" / "times.txt", ndmin=1)
    period = meta["scan_period_s"]
    if method == "kiss":
        cfg = work / "kiss.yaml"
        cfg.write_text(yaml.safe_dump({"registration": {"max_num_threads": 1}}))
        sh([bin_dir / "kiss_icp_pipeline", seq / "kitti" / "velodyne", "--config", cfg], work, log)
        poses = np.loadtxt(next(work.glob("results/*/velodyne_poses_kitti.txt"))).reshape(-1, 3, 4)
        rows = []
        for t, m in zip(times, poses):
            rows.append([t + period / 2, *m[:, 3], *quaternion(m[:, :3])])
        np.savetxt(work / "estimate.tum", np.array(rows), fmt="%.9f")
    else:
        driver = meta["lidar"]["driver"]
        packaged = {"ouster": "default/ouster.yaml", "velodyne": "default/velodyne.yaml",
                    "livox": "default/mid360.yaml"}[driver]
        base = work / "genz-packaged.yaml"
        sh([bin_dir / "genz_lio_pipeline", "export-config", packaged, base], work, log)
        cfg = yaml.safe_load(base.read_text())
        pre = cfg["preprocess"]
        pre["lidar_type"] = {"ouster": "ouster", "velodyne": "velodyne", "livox": "livox_pcl"}[driver]
        pat = meta["lidar"]["pattern"]
        pre["scan_line"] = int(pat.get("lines") or len(pat["elevations_deg"]))
        pre["scan_rate"] = int(round(meta["lidar"]["rate_hz"]))
        pre["blind_min"] = max(0.1, meta["lidar"]["range_m"][0])
        ext = meta["extrinsics"]
        lidar = np.array(ext["base_link_to_lidar"]["translation"])
        imu = np.array(ext["base_link_to_imu"]["translation"])
        cfg["mapping"]["extrinsic_t"] = (lidar - imu).tolist()
        cfg["mapping"]["extrinsic_r"] = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
        cfg["runtime"]["max_threads"] = 1
        (work / "genz.yaml").write_text(yaml.safe_dump(cfg))
        sh([bin_dir / "genz_lio_pipeline", "run", seq / "kitti" / "velodyne", "-c", work / "genz.yaml",
            "-o", work / "out", "-f", "tum"], work, log)
        est = next((work / "out").glob("*_tum.txt"))
        (work / "estimate.tum").write_text(est.read_text())


def quaternion(r):
    """x y z w of a rotation matrix (Shepperd's method)."""
    t = np.trace(r)
    if t > 0:
        s = np.sqrt(t + 1.0) * 2
        return [(r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s, 0.25 * s]
    i = int(np.argmax(np.diag(r)))
    j, k = (i + 1) % 3, (i + 2) % 3
    s = np.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k]) * 2
    q = [0.0, 0.0, 0.0, (r[k, j] - r[j, k]) / s]
    q[i] = 0.25 * s
    q[j] = (r[j, i] + r[i, j]) / s
    q[k] = (r[k, i] + r[i, k]) / s
    return q


def segments(seq, est_path):
    """Per segment: the true and estimated distance and the labels of its scans."""
    meta = json.loads((seq / "sequence.json").read_text())
    gt = np.loadtxt(seq / "ground_truth.tum", ndmin=2)
    est = np.loadtxt(est_path, ndmin=2)
    t = est[:, 0]
    inside = (t >= gt[0, 0]) & (t <= gt[-1, 0])
    t, e = t[inside], est[inside, 1:4]
    g = np.stack([np.interp(t, gt[:, 0], gt[:, k]) for k in (1, 2, 3)], axis=1)
    scans = meta["scans"]
    stimes = np.array([s["time"] for s in scans])
    # Travel direction at each scan from the ground truth.
    vel = np.gradient(gt[:, 1:4], gt[:, 0], axis=0)
    out = []
    t0 = gt[0, 0] + SKIP
    k = 0
    while len(t) and t0 + k * SEGMENT < t[-1]:
        a, b = t0 + k * SEGMENT, t0 + (k + 1) * SEGMENT
        k += 1
        m = (t >= a) & (t < b)
        if m.sum() < 3:
            continue
        true = float(np.linalg.norm(np.diff(g[m], axis=0), axis=1).sum())
        if true < MOVED:
            continue
        moved = float(np.linalg.norm(np.diff(e[m], axis=0), axis=1).sum())
        sel = [i for i, st in enumerate(stimes) if a <= st < b and scans[i]["degeneracy"]]
        if not sel:
            continue
        score = [scans[i]["degeneracy"]["score"] for i in sel]
        degenerate = [scans[i]["degeneracy"]["degenerate"] for i in sel]
        along = []
        for i in sel:
            d = scans[i]["degeneracy"]
            l0, l1, l2 = d["translation_eigenvalues"]
            v = vel[min(i, len(vel) - 1)]
            n = np.linalg.norm(v)
            if n < 0.2 or l2 <= 0:
                continue
            c = float(np.dot(v / n, d["weakest_translation"]))
            along.append((max(l0, 0.0) * c * c + l1 * (1 - c * c)) / l2)
        obscured = [scans[i].get("conditions", {}).get("obscured", 0.0) for i in sel]
        out.append({
            "start_s": round(a, 2),
            "true_m": true,
            "estimated_m": moved,
            "ratio": moved / true,
            "slides": moved / true < SLIDE,
            "degenerate_share": float(np.mean(degenerate)),
            "score_median": float(np.median(score)),
            "along_median": float(np.median(along)) if along else float("nan"),
            "obscured_mean": float(np.mean(obscured)),
        })
    return out


def pr(rows, key, threshold):
    tp = sum(1 for r in rows if r[key] < threshold and r["slides"])
    fp = sum(1 for r in rows if r[key] < threshold and not r["slides"])
    fn = sum(1 for r in rows if r[key] >= threshold and r["slides"])
    precision = tp / (tp + fp) if tp + fp else float("nan")
    recall = tp / (tp + fn) if tp + fn else float("nan")
    return {"threshold": threshold, "tp": tp, "fp": fp, "fn": fn,
            "precision": precision, "recall": recall}


def fit(rows, key):
    """The threshold with the best F1 on `rows`."""
    values = sorted({r[key] for r in rows if np.isfinite(r[key])})
    best, best_f1 = None, -1.0
    for i in range(len(values)):
        thr = values[i] + (values[i + 1] - values[i]) / 2 if i + 1 < len(values) else values[i] * 1.01 + 1e-9
        s = pr(rows, key, thr)
        p, r = s["precision"], s["recall"]
        f1 = 2 * p * r / (p + r) if p + r > 0 and np.isfinite(p) and np.isfinite(r) else 0.0
        if f1 > best_f1:
            best, best_f1 = thr, f1
    return best


def analyse(out):
    out = Path(out)
    rows = []
    for est in sorted(out.glob("runs/*/*/estimate.tum")):
        method_cond, name = est.parent.parent.name, est.parent.name
        method, cond = method_cond.split("-")
        preset, seed = name.rsplit("-", 1)
        seq = out / "sequences" / cond / name
        for s in segments(seq, est):
            rows.append({"method": method, "condition": cond, "preset": preset, "seed": int(seed), **s})
    with open(out / "segments.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    summary = {"segment_s": SEGMENT, "slides_below": SLIDE, "segments": len(rows)}
    for method in ("kiss", "genz"):
        for cond in ("clean", "dust"):
            sel = [r for r in rows if r["method"] == method and r["condition"] == cond]
            if not sel:
                continue
            by = {}
            for preset in sorted({r["preset"] for r in sel}):
                p = [r for r in sel if r["preset"] == preset]
                by[preset] = {
                    "segments": len(p),
                    "slide_share": float(np.mean([r["slides"] for r in p])),
                    "ratio_median": float(np.median([r["ratio"] for r in p])),
                    "obscured_mean": float(np.mean([r["obscured_mean"] for r in p])),
                }
            summary[f"{method}-{cond}"] = by
    # The label against LiDAR-only odometry's slides (KISS-ICP), clean and dusty together.
    lidar_only = [r for r in rows if r["method"] == "kiss"]
    calib = {"segments": len(lidar_only), "slides": sum(r["slides"] for r in lidar_only)}
    calib["today (a segment slides when half its scans are degenerate, score < 0.02)"] = pr(
        [dict(r, frac=1 - r["degenerate_share"]) for r in lidar_only], "frac", 0.5 + 1e-9)
    for key in ("score_median", "along_median"):
        train = [r for r in lidar_only if r["seed"] % 2 == 1 and np.isfinite(r[key])]
        test = [r for r in lidar_only if r["seed"] % 2 == 0 and np.isfinite(r[key])]
        if not train or not test:
            continue
        thr = fit(train, key)
        calib[key] = {"fitted_on_odd_seeds": pr(train, key, thr),
                      "held_out_even_seeds": pr(test, key, thr),
                      "all": pr(lidar_only, key, thr)}
    summary["label_calibration_kiss"] = calib
    summary["dust_minus_clean"] = paired(out)
    print(json.dumps(summary, indent=1))


def paired(out):
    """Per method: the dusty run's error minus the clean one's on the same world (APE RMSE,
    final drift), their mean with a 95 % bootstrap interval (2000 resamples, seed 0), and
    the Wilcoxon p `subtgraph report` gives (OUT/report-METHOD/paired.csv, when written)."""
    res = {}
    for method in ("kiss", "genz"):
        scores = {}
        for cond in ("clean", "dust"):
            for f in (out / "scores" / f"{method}-{cond}").glob("*/trajectory.json"):
                d = json.loads(f.read_text())
                scores.setdefault(f.parent.name, {})[cond] = d
        both = sorted(w for w, v in scores.items() if len(v) == 2)
        if not both:
            continue
        rng = np.random.default_rng(0)
        m = {"worlds": len(both)}
        for key, get in (("ape_rmse_m", lambda d: d["ape_m"]["rmse"]),
                         ("final_drift_percent", lambda d: d["final_drift_percent"])):
            diff = np.array([get(scores[w]["dust"]) - get(scores[w]["clean"]) for w in both])
            boots = rng.choice(diff, size=(2000, len(diff)), replace=True).mean(axis=1)
            m[key] = {"clean_mean": float(np.mean([get(scores[w]["clean"]) for w in both])),
                      "dust_mean": float(np.mean([get(scores[w]["dust"]) for w in both])),
                      "mean_difference": float(diff.mean()),
                      "ci95": [float(np.percentile(boots, 2.5)), float(np.percentile(boots, 97.5))],
                      "dust_worse_share": float(np.mean(diff > 0))}
        csv_path = out / f"report-{method}" / "paired.csv"
        if csv_path.exists():
            for row in csv.DictReader(open(csv_path)):
                if row["metric"] in ("trajectory.ape_m.rmse", "trajectory.final_drift_percent"):
                    m[row["metric"] + ".wilcoxon_p"] = float(row["p"])
        res[method] = m
    return res


if __name__ == "__main__":
    if sys.argv[1] == "run":
        run(sys.argv[2], sys.argv[3], sys.argv[4])
    elif sys.argv[1] == "analyse":
        analyse(sys.argv[2])
    else:
        raise SystemExit(__doc__)
