"""Issue 22 item 2: a world's ground-truth centrelines are smooth and stand in the free space.

For each world folder given: every corridor and ramp edge of ground_truth/graph.json, sampled
every metre along its polyline (horizontal distance), turns at most LIMIT degrees from one
metre to the next, away from NEAR metres of its two end nodes; and every point of every
corridor's polyline stands on a floor of mesh/collision.obj (read with numpy, obj_reader.py), with room
above it: the vertical line through the point crosses the surface at most TOL below and
above it on a triangle facing up (a floor seen from the passage), and nothing else within a
metre above that floor (but a vertical shaft's landing node, over the shaft's hole). Facing, not parity, so the open surfaces of mesh tiles (the DARPA
tiles') are read too. Our own vertical ray test, on triangles bucketed in the plane.

usage: centreline_check.py LIMIT WORLD_DIR...
Prints one line per world; exits non-zero (AssertionError) on the first failure.
"""

import json
import math
import sys
from pathlib import Path

import numpy as np
from obj_reader import read_obj
from plane_squares import plane_squares

NEAR = 12.5
TOL = 0.3
BUCKET = 2.0


def resample(line, step=1.0):
    pts = np.asarray(line, dtype=float)[:, :2]
    seg = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    s = np.concatenate([[0.0], np.cumsum(seg)])
    at = np.arange(0.0, s[-1] + 1e-9, step)
    return np.stack([np.interp(at, s, pts[:, 0]), np.interp(at, s, pts[:, 1])], axis=1)


def worst_turn(graph):
    nodes = {n["id"]: np.asarray(n["position"][:2]) for n in graph["nodes"]}
    worst = (0.0, None, None)
    for e in graph["edges"]:
        if e["kind"] not in ("corridor", "ramp") or len(e["polyline"]) < 2:
            continue
        s = resample(e["polyline"])
        if len(s) < 3:
            continue
        heading = np.arctan2(np.diff(s[:, 1]), np.diff(s[:, 0]))
        turn = np.abs(np.diff(heading))
        turn = np.degrees(np.minimum(turn, 2 * np.pi - turn))
        mid = s[1:-1]
        far = np.ones(len(mid), dtype=bool)
        for n in (e["from"], e["to"]):
            far &= np.linalg.norm(mid - nodes[n], axis=1) >= NEAR
        if far.any():
            k = np.argmax(np.where(far, turn, -1.0))
            if turn[k] > worst[0]:
                worst = (float(turn[k]), e["id"], mid[k].tolist())
    return worst


class Soup:
    """The collision surface's triangles, bucketed by squares of the plane."""

    def __init__(self, triangles):
        self.tri = np.asarray(triangles, dtype=float)
        a, b, c = self.tri[:, 0], self.tri[:, 1], self.tri[:, 2]
        self.area = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
        lo, hi = self.tri[:, :, :2].min(axis=1), self.tri[:, :, :2].max(axis=1)
        self.buckets = plane_squares(lo, hi, BUCKET, keep=np.nonzero(self.area != 0)[0])

    def crossings(self, x, y):
        """(height, faces up) of every crossing of the vertical line through (x, y), sorted."""
        x, y = x + 3.1e-6, y + 1.7e-6  # off shared edges
        ts = self.buckets.get((math.floor(x / BUCKET), math.floor(y / BUCKET)))
        if ts is None:
            return []
        tri, area = self.tri[ts], self.area[ts]
        a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]

        def o(u, v):
            return (v[:, 0] - u[:, 0]) * (y - u[:, 1]) - (v[:, 1] - u[:, 1]) * (x - u[:, 0])

        wa, wb, wc = o(b, c), o(c, a), o(a, b)
        inside = ((wa >= 0) & (wb >= 0) & (wc >= 0)) | ((wa <= 0) & (wb <= 0) & (wc <= 0))
        z = (wa * a[:, 2] + wb * b[:, 2] + wc * c[:, 2]) / area
        return sorted(zip(z[inside].tolist(), (area[inside] > 0).tolist()))

    def on_floor(self, p):
        hits = self.crossings(p[0], p[1])
        floors = [h for h in hits if h[1] and abs(h[0] - p[2]) <= TOL]
        for f, _ in floors:
            above = [h[0] for h in hits if h[0] > f + 1e-6]
            if not above or above[0] >= f + 1.0:
                return True
        return False


limit = float(sys.argv[1])
for world in map(Path, sys.argv[2:]):
    graph = json.loads((world / "ground_truth/graph.json").read_text())
    turn, edge, at = worst_turn(graph)
    assert turn <= limit, f"{world.name}: edge {edge} turns {turn:.1f} degrees in a metre at {at}"
    soup = Soup(read_obj(world / "mesh/collision.obj").corners())
    checked = 0
    # A vertical shaft's landing node stands over the shaft's hole (its collar, issue 24): not
    # on a floor.
    collars = {n["id"] for n in graph["nodes"] if n["kind"] == "shaft-landing"}
    for e in graph["edges"]:
        if e["kind"] != "corridor":
            continue
        line = e["polyline"]
        ends = {0: e["from"], len(line) - 1: e["to"]}
        for k, p in enumerate(line):
            if ends.get(k) in collars:
                continue
            # A point on a tile's seam may lie between two tiles' surfaces: the floor just
            # beside it counts.
            near = [(0, 0), (0.05, 0), (-0.05, 0), (0, 0.05), (0, -0.05)]
            assert any(soup.on_floor((p[0] + dx, p[1] + dy, p[2])) for dx, dy in near), (
                f"{world.name}: edge {e['id']} point {p} is not on a floor with room above it"
            )
            checked += 1
    print(f"{world.name}: worst turn {turn:.1f} degrees per metre; {checked} centreline points on floors")
