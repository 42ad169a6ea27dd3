"""Checks an exploration run folder (`subtgraph explore`) against the world it ran in, with
numpy and trimesh only: nothing of subtgraph's own code.

    explore_check.py WORLD RUN [SCORE]

- Every pose of every robot-N.tum stays in free space with the platform's clearance: the
  clearance point (run.json's clearance_height_m above the pose, a ground robot's floor) is at
  least clearance_m from mesh/collision.obj (trimesh's closest points) and inside the closed
  surface (its ray-parity containment), checked on an even sample of poses.
- Every radio link run.json's radio.csv reports up is a line of sight: trimesh's own ray
  test from one antenna meets the collision surface no nearer than the other (on an even
  sample), and its distance is the rows's.
- The artifacts found, recomputed: the reports of reports.csv whose robot had a link at that
  instant (connectivity.csv), matched to ground_truth/artifacts.json by DARPA's rule (taken in
  time order, the nearest not-yet-found artifact of the class within 5 m scores), counted.
- The explored share, recomputed: explored.npy's voxels that ground_truth/free_space.npy calls
  free, over its free voxels (numpy's unpackbits).
With SCORE (the folder `subtgraph score WORLD --run RUN` wrote): both numbers equal its
score.json's score and run.json's explored coverage. Prints a JSON line of what it found;
exits non-zero on a mismatch.
"""
import csv
import json
import sys
from pathlib import Path

import numpy as np
import trimesh

world, run = Path(sys.argv[1]), Path(sys.argv[2])
score = Path(sys.argv[3]) if len(sys.argv) > 3 else None
meta = json.loads((run / "run.json").read_text())
# Vertices merged (process), so the closed surface is watertight for `contains`.
mesh = trimesh.load(world / "mesh/collision.obj", process=True, force="mesh")
clearance = meta["platform"]["clearance_m"]
lift = meta["platform"]["clearance_height_m"]
out = {}

# Poses in free space with the clearance.
points = []
for tum in sorted(run.glob("robot-*.tum")):
    poses = np.loadtxt(tum, ndmin=2)
    assert poses.shape[1] == 8, (tum, poses.shape)
    assert np.all(np.diff(poses[:, 0]) > 0), f"{tum}: times not increasing"
    pick = np.unique(np.linspace(0, len(poses) - 1, min(len(poses), 300)).astype(int))
    points.append(poses[pick, 1:4] + np.array([0.0, 0.0, lift]))
points = np.concatenate(points)
_, distance, _ = trimesh.proximity.closest_point(mesh, points)
inside = mesh.contains(points)
# The OBJ rounds vertices to 0.1 mm.
assert distance.min() >= clearance - 2e-3, f"a pose {distance.min():.4f} m from rock, clearance {clearance}"
assert inside.all(), f"{(~inside).sum()} poses outside the passages"
out["poses_checked"] = int(len(points))
out["least_clearance_m"] = round(float(distance.min()), 4)

# Radio links up are lines of sight.
links = list(csv.DictReader(open(run / "radio.csv")))
if links:
    pick = np.unique(np.linspace(0, len(links) - 1, min(len(links), 1500)).astype(int))
    a = np.array([[float(links[k][c]) for c in ("ax", "ay", "az")] for k in pick])
    b = np.array([[float(links[k][c]) for c in ("bx", "by", "bz")] for k in pick])
    d = np.linalg.norm(b - a, axis=1)
    want = np.array([float(links[k]["distance_m"]) for k in pick])
    assert np.all(np.abs(d - want) <= 2e-3), "a link's distance is not its antennas'"
    keep = d > 1e-6
    a, b, d = a[keep], b[keep], d[keep]
    hits, rays, _ = mesh.ray.intersects_location(a, (b - a) / d[:, None], multiple_hits=True)
    if len(rays):
        t = np.linalg.norm(hits - a[rays], axis=1)
        # Hits short of the far antenna (by more than the OBJ's rounding seen along a ray).
        blocked = t < d[rays] - 5e-3
        assert not blocked.any(), f"{blocked.sum()} links up pass through rock"
    out["links_checked"] = int(len(d))

# Artifacts found over a link, by DARPA's rule.
truth = json.loads((world / "ground_truth/artifacts.json").read_text())["artifacts"]
linked = set()
for r in csv.DictReader(open(run / "connectivity.csv")):
    if r["hops"] != "":
        linked.add((round(float(r["time"]) * 1000), r["robot"]))
reports = [r for r in csv.DictReader(open(run / "reports.csv"))]
counted = [r for r in reports if (round(float(r["time"]) * 1000), r["robot"]) in linked]
counted.sort(key=lambda r: float(r["time"]))
found = set()
for r in counted:
    p = np.array([float(r["x"]), float(r["y"]), float(r["z"])])
    near = [
        (np.linalg.norm(p - np.array(t["position"])), t["id"])
        for t in truth
        if t["class"] == r["class"] and t["id"] not in found
    ]
    near = [n for n in near if n[0] <= 5.0]
    if near:
        found.add(min(near)[1])
out["reports"] = len(reports)
out["reports_over_a_link"] = len(counted)
out["artifacts_found"] = len(found)

# The explored share of the free space.
fs = json.loads((world / "ground_truth/free_space.json").read_text())
nz, ny, nx = fs["shape"]
free = np.unpackbits(np.load(world / "ground_truth/free_space.npy"), axis=2, count=nx).astype(bool)
explored = np.unpackbits(np.load(run / "explored.npy"), axis=2, count=nx).astype(bool)
share = float((free & explored).sum()) / float(free.sum())
out["explored_share"] = round(share, 6)

if score is not None:
    s = json.loads((score / "score.json").read_text())
    assert s["score"] == len(found), (s["score"], len(found))
    r = json.loads((score / "run.json").read_text())
    assert abs(r["explored"]["coverage"] - share) < 1e-9, (r["explored"]["coverage"], share)
    assert r["reports_without_link"] == len(reports) - len(counted)
print(json.dumps(out))
