"""Checks each artifact's `visible_from_axis` (ground_truth/artifacts.json) against the
collision mesh (mesh/collision.obj, read by trimesh): the segment from its `sight_from` eye to
0.3 m before its centre crosses no collision triangle exactly when the artifact is marked
visible (segments within 0.15 m of a triangle's plane crossing are not judged: the flag is
sampled every 0.2 m).

usage: visibility_check.py WORLD_DIR

Prints a summary; exits non-zero on a disagreement.
"""
import json
import sys
from pathlib import Path

import numpy as np
import trimesh

world = Path(sys.argv[1])
arts = json.loads((world / "ground_truth/artifacts.json").read_text())["artifacts"]
mesh = trimesh.load(world / "mesh/collision.obj", force="mesh", process=False)
all_tri = mesh.vertices[mesh.faces]
lo, hi = all_tri.min(axis=1), all_tri.max(axis=1)


def crossings(p, q):
    """Parameters t in [0, 1] where the segment p-q crosses a triangle (Moller-Trumbore), of
    the triangles whose bounding box meets the segment's (no other can cross it)."""
    near = np.all((hi >= np.minimum(p, q) - 1e-9) & (lo <= np.maximum(p, q) + 1e-9), axis=1)
    tri = all_tri[near]
    d = q - p
    e1, e2 = tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    h = np.cross(d, e2)
    a = (e1 * h).sum(axis=1)
    ok = np.abs(a) > 1e-12
    f = np.zeros_like(a)
    f[ok] = 1.0 / a[ok]
    s = p - tri[:, 0]
    u = f * (s * h).sum(axis=1)
    qv = np.cross(s, e1)
    v = f * (qv * d).sum(axis=1)
    t = f * (qv * e2).sum(axis=1)
    hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= 0) & (t <= 1)
    return t[hit]


seen = hidden = skipped = 0
for a in arts:
    eye = np.array(a["sight_from"])
    c = np.array(a["position"]) + [0, 0, 0.5 * a["size"][2]]
    length = np.linalg.norm(c - eye)
    if length <= 0.3:
        assert a["visible_from_axis"], a
        seen += 1
        continue
    end = eye + (c - eye) * (length - 0.3) / length
    ts = crossings(eye, end) * (length - 0.3)
    # A crossing within a sampling step of the eye or of the end is not judged.
    clear = len(ts) == 0
    near = len(ts) > 0 and all(t < 0.15 or t > length - 0.3 - 0.15 for t in ts)
    if near:
        skipped += 1
        continue
    assert a["visible_from_axis"] == clear, (a["name"], a["visible_from_axis"], ts)
    if clear:
        seen += 1
    else:
        hidden += 1
print(f"visibility: {seen} artifacts seen from the axis, {hidden} hidden, {skipped} not judged, as the collision mesh says")
