"""Checks a world's comms table (`--format comms`) against trimesh's own ray test.

    comms_check.py WORLD [SAMPLE]

Reads ground_truth/comms.csv and .json, the tiles' node positions from
ground_truth/semantic_labels.json and the collision surface mesh/collision.obj (trimesh).
For every row of a sample (every pair when there are at most SAMPLE rows, 400 by default;
else evenly spaced rows, both kinds): the antennas are the two tiles' positions raised by
antenna_m, their distance is the row's (to the CSV's 1 mm), and trimesh's ray from the first
antenna towards the second hits the surface before the second exactly when the row says the
line is blocked, at the row's blocked_at_m (to 2 mm, plus the OBJ's 0.1 mm rounding seen along
a grazing ray). Also: every pair of tiles within range_m
is listed once, no pair beyond it, and the summary's counts are the CSV's. Prints one line;
exits non-zero on a mismatch.
"""
import csv
import json
import sys
from pathlib import Path

import numpy as np
import trimesh

world = Path(sys.argv[1])
sample = int(sys.argv[2]) if len(sys.argv) > 2 else 400
meta = json.loads((world / "ground_truth/comms.json").read_text())
labels = json.loads((world / "ground_truth/semantic_labels.json").read_text())
tiles = labels["tiles"] if isinstance(labels, dict) and "tiles" in labels else labels
pos = {(t["level"], t["row"], t["col"]): np.array(t["position"], dtype=float) for t in tiles}
up = np.array([0.0, 0.0, meta["antenna_m"]])
rows = list(csv.DictReader(open(world / "ground_truth/comms.csv")))
assert meta["pairs"] == len(rows), (meta["pairs"], len(rows))
assert meta["in_sight"] == sum(r["line_of_sight"] == "1" for r in rows)
assert meta["tiles"] == len(pos), (meta["tiles"], len(pos))

# Every pair within range, once.
keys = sorted(pos)
ant = np.array([pos[k] + up for k in keys])
d = np.linalg.norm(ant[:, None, :] - ant[None, :, :], axis=2)
i, j = np.nonzero(np.triu(d <= meta["range_m"], k=1))
want = {(keys[a], keys[b]) for a, b in zip(i, j) if d[a, b] > 0}
cell = lambda r, s: (int(r[f"level_{s}"]), int(r[f"row_{s}"]), int(r[f"col_{s}"]))
got = [(cell(r, "a"), cell(r, "b")) for r in rows]
assert len(set(got)) == len(got), "a pair listed twice"
assert set(got) == want, (len(set(got) - want), len(want - set(got)))

mesh = trimesh.load(world / "mesh/collision.obj", process=False, force="mesh")
if len(rows) > sample:
    picks = sorted(set(np.linspace(0, len(rows) - 1, sample).astype(int).tolist()))
else:
    picks = list(range(len(rows)))
origins, dirs, dist = [], [], []
for k in picks:
    r = rows[k]
    a, b = pos[cell(r, "a")] + up, pos[cell(r, "b")] + up
    n = np.linalg.norm(b - a)
    assert abs(n - float(r["distance_m"])) <= 1.5e-3, (r, n)
    origins.append(a)
    dirs.append((b - a) / n)
    dist.append(n)
origins, dirs, dist = np.array(origins), np.array(dirs), np.array(dist)
locations, ray_ids, tri_ids = mesh.ray.intersects_location(origins, dirs, multiple_hits=True)
first = np.full(len(picks), np.inf)
cosine = np.ones(len(picks))
normals = mesh.face_normals
for loc, ray, tri in zip(locations, ray_ids, tri_ids):
    t = float(np.dot(loc - origins[ray], dirs[ray]))
    if 0 <= t < first[ray]:
        first[ray] = t
        cosine[ray] = abs(float(np.dot(normals[tri], dirs[ray])))
seen = blocked = 0
for n, k in enumerate(picks):
    r = rows[k]
    hit = first[n] <= dist[n]
    assert hit == (r["line_of_sight"] == "0"), (r, first[n], dist[n])
    if hit:
        blocked += 1
        # The CSV's millimetre, and the OBJ's 0.1 mm vertices seen along a grazing ray.
        tol = 2e-3 + 1e-4 / max(cosine[n], 1e-3)
        assert abs(first[n] - float(r["blocked_at_m"])) <= tol, (r, first[n], cosine[n])
    else:
        seen += 1
print(f"{world.name}: {len(rows)} pairs within {meta['range_m']} m, all listed; {len(picks)} checked with trimesh ({seen} in sight, {blocked} blocked)")
