"""Checks a `subtgraph report` folder against numpy and scipy, from the score folders and
world folders themselves.

Usage: report_check.py REPORT_DIR

Re-reads every score folder report.json names (its top-level JSON files, flattened to
FILE-STEM.KEY.KEY numbers, arrays and the options/reference/estimate subtrees left out) and
every world folder (topology.json, world.toml, ground_truth/hazards.json), then recomputes:
- per method and scope: np.mean, np.median; the bootstrap interval by the documented scheme
  (SplitMix64 at the seed, index (u * n) >> 64, np.percentile of the resample means at 2.5
  and 97.5), written here again from its description;
- success rates and scipy.stats.binomtest(...).proportion_ci(method="wilson");
- per pair of methods: the differences, the shares, and scipy.stats.wilcoxon(a, b) with its
  defaults (statistic and p-value);
- per method, metric and parameter: scipy.stats.linregress (slope, intercept, r);
- per method and parameter: failures per bin with np.unique (at most 6 values) or
  np.histogram (5 equal bins, the last closed).
Agreement to 1e-9 relative (1e-12 absolute). Prints one line per group checked; exits non-zero
on the first mismatch.
"""

import json
import math
import sys
import tomllib
from pathlib import Path

import numpy as np
from scipy import stats

REL, ABS = 1e-9, 1e-12
NOT_METRICS = {"options", "reference", "estimate"}
PARAMETERS = [
    "loops",
    "t_junctions",
    "intersections",
    "levels",
    "passage_length_m",
    "sloped_share",
    "hazard_patches",
]
MASK = (1 << 64) - 1


def close(a, b):
    if a is None or b is None:
        return a is None and b is None
    return abs(a - b) <= max(ABS, REL * max(abs(a), abs(b)))


def same(what, ours, theirs):
    if isinstance(ours, (list, tuple)) or isinstance(theirs, (list, tuple)):
        if ours is None or theirs is None or len(ours) != len(theirs):
            sys.exit(f"MISMATCH {what}: report {ours!r}, check {theirs!r}")
        for k, (a, b) in enumerate(zip(ours, theirs)):
            same(f"{what}[{k}]", a, b)
        return
    if not close(ours, theirs):
        sys.exit(f"MISMATCH {what}: report {ours!r}, check {theirs!r}")


def flatten(prefix, v, top, out):
    if isinstance(v, bool) or v is None or isinstance(v, (str, list)):
        return
    if isinstance(v, (int, float)):
        out[prefix] = float(v)
        return
    for k, x in v.items():
        if top and k in NOT_METRICS:
            continue
        flatten(f"{prefix}.{k}", x, False, out)


def score_numbers(folder):
    listed = (Path(folder) / ".subtgraph-files").read_text().splitlines()
    assert "complete score" in listed, f"{folder} is not a score folder"
    out, failed = {}, None
    for line in listed:
        if line.startswith("#") or line.startswith("complete"):
            continue
        name = line.split(" ", 1)[1]
        if "/" in name or not name.endswith(".json"):
            continue
        doc = json.loads((Path(folder) / name).read_text())
        flatten(name[: -len(".json")], doc, True, out)
        if isinstance(doc.get("failed"), bool):
            failed = bool(failed) or doc["failed"]
    return out, failed


def world_parameters(world):
    world = Path(world)
    topo = json.loads((world / "topology.json").read_text())
    total = sum(e["length_m"] for e in topo["edges"])
    sloped = sum(e["length_m"] for e in topo["edges"] if e["kind"] != "corridor")
    hazards = world / "ground_truth" / "hazards.json"
    patches = len(json.loads(hazards.read_text())["patches"]) if hazards.exists() else 0
    achieved = [lvl["achieved"] for lvl in topo["per_level"]]
    source = tomllib.loads((world / "world.toml").read_text()).get("generated", {}).get("source", "")
    preset = source.split()[1] if source.startswith("preset ") else "custom"
    return preset, [
        float(sum(a["loops"] for a in achieved)),
        float(sum(a["t_junctions"] for a in achieved)),
        float(sum(a["intersections"] for a in achieved)),
        float(topo["levels"]),
        float(topo["total_length_m"]),
        sloped / total if total > 0 else 0.0,
        float(patches),
    ]


def splitmix(seed):
    state = seed

    def next_u64():
        nonlocal state
        state = (state + 0x9E3779B97F4A7C15) & MASK
        z = state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK
        return z ^ (z >> 31)

    return next_u64


def bootstrap(x, seed, b):
    n = len(x)
    if n < 2:
        return None
    draw = splitmix(seed)
    x = np.asarray(x)
    idx = np.array([[(draw() * n) >> 64 for _ in range(n)] for _ in range(b)])
    means = x[idx].sum(axis=1) / n
    lo, hi = np.percentile(means, [2.5, 97.5])
    return [float(lo), float(hi)]


def bins(all_values, x, failed):
    values = np.unique(all_values)
    x, failed = np.asarray(x), np.asarray(failed)
    if len(values) <= 6:
        return [(v, v, int((x == v).sum()), int(((x == v) & failed).sum())) for v in values]
    runs, edges = np.histogram(x, bins=5, range=(values[0], values[-1]))
    fails, _ = np.histogram(x[failed], bins=5, range=(values[0], values[-1]))
    return [(edges[k], edges[k + 1], int(runs[k]), int(fails[k])) for k in range(5)]


def main():
    out = Path(sys.argv[1])
    rep = json.loads((out / "report.json").read_text())
    seed, b = rep["seed"], rep["resamples"]
    worlds = rep["worlds"]
    for w in worlds:
        preset, params = world_parameters(w["path"])
        assert preset == w["preset"], (w["name"], preset, w["preset"])
        same(f"{w['name']} parameters", [w["parameters"][p] for p in PARAMETERS], params)
    print(f"world parameters: {len(worlds)} worlds")
    runs = []
    for r in rep["runs"]:
        numbers, failed = {}, None
        for f in r["score_folders"]:
            n, fl = score_numbers(f)
            numbers.update(n)
            if fl is not None:
                failed = bool(failed) or fl
        assert failed == r["failed"], (r, failed)
        runs.append((r["method"], r["world"], numbers, failed))
    metrics = sorted({m for _, _, n, _ in runs for m in n})
    constant = {m for m in metrics if len({n[m] for _, _, n, _ in runs if m in n}) == 1}
    assert sorted(rep["metrics"]) == sorted(set(metrics) - constant), "metrics"
    assert sorted(rep["constant"]) == sorted(constant), "constants"
    for (_, _, n, _), r in zip(runs, rep["runs"]):
        assert set(r["metrics"]) == set(n), r["metrics"].keys()
        for m in n:
            same(f"run {r['method']} world {r['world']} {m}", r["metrics"][m], n[m])
    print(f"runs: {len(runs)} re-read from their score folders, {len(rep['metrics'])} metrics")

    presets = sorted({w["preset"] for w in worlds})
    scopes = [("all", None)] + ([(f"preset {p}", p) for p in presets] if len(presets) > 1 else [])
    methods = sorted({m for m, _, _, _ in runs})
    assert rep["methods"] == methods
    summary = {(s["method"], s["scope"], s["metric"]): s for s in rep["summary"]}
    success = {(s["method"], s["scope"]): s for s in rep["success"]}
    checked = 0
    for m in methods:
        for scope, preset in scopes:
            here = [r for r in runs if r[0] == m and (preset is None or worlds[r[1]]["preset"] == preset)]
            here.sort(key=lambda r: r[1])
            for metric in rep["metrics"]:
                x = [r[2][metric] for r in here if metric in r[2]]
                if not x:
                    assert (m, scope, metric) not in summary
                    continue
                s = summary[(m, scope, metric)]
                what = f"{m} {scope} {metric}"
                assert s["n"] == len(x), what
                same(f"{what} mean", s["mean"], float(np.mean(x)))
                same(f"{what} median", s["median"], float(np.median(x)))
                same(f"{what} ci95", s["ci95"], bootstrap(x, seed, b))
                if s["ci95"] is not None:
                    assert s["ci95"][0] <= s["mean"] <= s["ci95"][1], what
                checked += 1
            flags = [r[3] for r in here if r[3] is not None]
            if flags:
                s = success[(m, scope)]
                k = len(flags) - sum(flags)
                ci = stats.binomtest(k, len(flags)).proportion_ci(0.95, method="wilson")
                assert s["runs"] == len(flags) and s["failures"] == sum(flags), s
                same(f"{m} {scope} success", s["rate"], k / len(flags))
                same(f"{m} {scope} wilson", s["wilson95"], [ci.low, ci.high])
            else:
                assert (m, scope) not in success
    print(f"summaries: {checked} mean/median/bootstrap intervals; {len(success)} Wilson intervals")

    paired = {(p["a"], p["b"], p["metric"]): p for p in rep["paired"]}
    tests = 0
    for i, a in enumerate(methods):
        for bm in methods[i + 1:]:
            ra = {r[1]: r for r in runs if r[0] == a}
            rb = {r[1]: r for r in runs if r[0] == bm}
            for metric in rep["metrics"]:
                common = [w for w in sorted(ra) if w in rb and metric in ra[w][2] and metric in rb[w][2]]
                if not common:
                    continue
                x = np.array([ra[w][2][metric] for w in common])
                y = np.array([rb[w][2][metric] for w in common])
                d = x - y
                p = paired[(a, bm, metric)]
                what = f"{a}-{bm} {metric}"
                assert p["n"] == len(d), what
                same(f"{what} mean difference", p["mean_difference"], float(np.mean(d)))
                same(f"{what} median difference", p["median_difference"], float(np.median(d)))
                same(f"{what} shares", [p["a_lower"], p["b_lower"], p["equal"]],
                     [float(np.mean(d < 0)), float(np.mean(d > 0)), float(np.mean(d == 0))])
                if np.all(d == 0):
                    assert p["wilcoxon"] is None, what
                    continue
                res = stats.wilcoxon(x, y)
                same(f"{what} wilcoxon statistic", p["wilcoxon"]["statistic"], float(res.statistic))
                same(f"{what} wilcoxon p", p["wilcoxon"]["p"], float(res.pvalue))
                tests += 1
    print(f"paired: {len(rep['paired'])} comparisons, {tests} Wilcoxon tests as scipy's")

    trends = {(t["method"], t["metric"], t["parameter"]): t for t in rep["trends"]}
    fits = 0
    for m in methods:
        here = sorted((r for r in runs if r[0] == m), key=lambda r: r[1])
        for metric in rep["metrics"]:
            have = [r for r in here if metric in r[2]]
            y = np.array([r[2][metric] for r in have])
            for p in PARAMETERS:
                x = np.array([worlds[r[1]]["parameters"][p] for r in have])
                t = trends[(m, metric, p)]
                if len(x) < 2 or np.all(x == x[0]):
                    assert t["line"] is None, (m, metric, p)
                    continue
                fit = stats.linregress(x, y)
                same(f"{m} {metric} {p} slope", t["line"]["slope"], float(fit.slope))
                same(f"{m} {metric} {p} intercept", t["line"]["intercept"], float(fit.intercept))
                r = None if np.all(y == y[0]) else float(fit.rvalue)
                if r is not None:
                    # r to 1e-9 absolute: it is near 0 when nothing trends.
                    assert abs(t["line"]["r"] - r) <= 1e-9, (m, metric, p, t["line"]["r"], r)
                fits += 1
    print(f"trends: {fits} least-squares lines as scipy's linregress")

    fb = {(f["method"], f["parameter"]): f["bins"] for f in rep["failure_bins"]}
    for m in methods:
        flagged = sorted((r for r in runs if r[0] == m and r[3] is not None), key=lambda r: r[1])
        if not flagged:
            continue
        for k, p in enumerate(PARAMETERS):
            every = [w["parameters"][p] for w in worlds]
            x = [worlds[r[1]]["parameters"][p] for r in flagged]
            want = bins(every, x, [r[3] for r in flagged])
            got = fb[(m, p)]
            assert len(got) == len(want), (m, p, got, want)
            for g, (lo, hi, n, f) in zip(got, want):
                same(f"{m} {p} bin edges", [g["from"], g["to"]], [float(lo), float(hi)])
                assert (g["runs"], g["failures"]) == (n, f), (m, p, g, n, f)
    print(f"failure bins: {len(fb)} as numpy's")


if __name__ == "__main__":
    main()
