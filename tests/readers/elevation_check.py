"""Checks the hills of a subtgraph world built from mesh tiles with an `elevation` tile.

Usage: elevation_check.py WORLD_FOLDER RISE ELEVATION_OBJ

Reads mesh/collision.obj with trimesh, ground_truth/graph.json and semantic_labels.json, the
elevation tile's own file (OBJ, Y up, as the DARPA conversions are) and urdf/world.urdf in
PyBullet. The hill's ends are labelled `elevation`, its lifted straights `raised`. Checks,
exiting non-zero on the first failure:
- every graph node and every corridor polyline point stands on a floor of the collision
  surface: a ray down from half a metre above it first meets a surface facing up within a
  metre, and nothing crosses the metre above that floor (numpy ray casting; the DARPA
  tiles' surface is not closed, so floors are told by their facing);
- over every end of a hill, the polyline climbs RISE (within 15 %) between the tile's two
  seams, and every point over a raised tile stands at least RISE - 15 % over the level;
- no stretch of polyline over a hill (points at least 4 m apart horizontally) is steeper than
  the elevation tile's own floor is along its middle (4 m runs), plus 3 degrees (the climb
  snapped to the other tiles' 3.2 m collision grid, a staircase, reached 29.8);
- a ball (radius 0.3 m) released 0.8 m over the node of every raised tile, after 5 simulated
  seconds in PyBullet, is still over that tile, at least RISE - 15 % over the level: it did
  not fall through the lifted floor.
Prints what it measured.
"""
import json
import math
import os
import sys
import tempfile

import numpy as np
import trimesh

folder = os.path.abspath(sys.argv[1])
RISE = float(sys.argv[2])
tile_file = sys.argv[3]
TOL = 0.15 * RISE
RUN = 4.0

topology = json.load(open(os.path.join(folder, "topology.json")))
pitch, lh = topology["tile_pitch_m"], topology["level_height_m"]
graph = json.load(open(os.path.join(folder, "ground_truth", "graph.json")))
labels = json.load(open(os.path.join(folder, "ground_truth", "semantic_labels.json")))
mesh = trimesh.load(os.path.join(folder, "mesh", "collision.obj"), force="mesh", process=False)
tri = np.asarray(mesh.triangles)


BUCKET = 10.0


def buckets_of(tri):
    """Triangle indices by the squares of BUCKET metres their boxes meet."""
    lo = np.floor(tri[:, :, :2].min(axis=1) / BUCKET).astype(int)
    hi = np.floor(tri[:, :, :2].max(axis=1) / BUCKET).astype(int)
    out = {}
    for k, (l, h) in enumerate(zip(lo.tolist(), hi.tolist())):
        for bx in range(l[0], h[0] + 1):
            for by in range(l[1], h[1] + 1):
                out.setdefault((bx, by), []).append(k)
    return {key: np.array(v) for key, v in out.items()}


def crossings_of(tri, x, y, buckets=None):
    """(height, faces up) of every crossing of the vertical line through (x, y), sorted."""
    x, y = x + 3.1e-6, y + 1.7e-6
    if buckets is not None:
        tri = tri[buckets.get((math.floor(x / BUCKET), math.floor(y / BUCKET)), np.zeros(0, dtype=int))]
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    m = ((np.minimum(np.minimum(a[:, 0], b[:, 0]), c[:, 0]) <= x)
         & (np.maximum(np.maximum(a[:, 0], b[:, 0]), c[:, 0]) >= x)
         & (np.minimum(np.minimum(a[:, 1], b[:, 1]), c[:, 1]) <= y)
         & (np.maximum(np.maximum(a[:, 1], b[:, 1]), c[:, 1]) >= y))
    A, B, C = a[m], b[m], c[m]
    area = (B[:, 0] - A[:, 0]) * (C[:, 1] - A[:, 1]) - (B[:, 1] - A[:, 1]) * (C[:, 0] - A[:, 0])

    def edge(u, v):
        return (v[:, 0] - u[:, 0]) * (y - u[:, 1]) - (v[:, 1] - u[:, 1]) * (x - u[:, 0])

    wa, wb, wc = edge(B, C), edge(C, A), edge(A, B)
    inside = (((wa >= 0) & (wb >= 0) & (wc >= 0)) | ((wa <= 0) & (wb <= 0) & (wc <= 0))) & (area != 0)
    z = (wa * A[:, 2] + wb * B[:, 2] + wc * C[:, 2])[inside] / area[inside]
    up = area[inside] > 0
    order = np.argsort(z, kind="stable")
    return list(zip(z[order], up[order]))


buckets = buckets_of(tri)


def on_floor(p):
    for dx, dy in [(0, 0), (0.05, 0), (-0.05, 0), (0, 0.05), (0, -0.05)]:
        hits = crossings_of(tri, p[0] + dx, p[1] + dy, buckets)
        probe = p[2] + 0.5
        below = [h for h in hits if h[0] <= probe]
        if not below:
            continue
        floor = below[-1][0]
        up = any(abs(h[0] - floor) < 1e-6 and h[1] for h in hits)
        above = [h for h in hits if h[0] > floor + 1e-6]
        if up and probe - floor <= 1.0 and (not above or above[0][0] >= floor + 1.0):
            return True
    return False


# --- every node and polyline point on a floor ----------------------------------------------
points = [n["position"] for n in graph["nodes"]]
for e in graph["edges"]:
    if e["kind"] == "corridor":
        points.extend(e["polyline"])
for p in points:
    if not on_floor(p):
        sys.exit(f"FAIL: {p} does not stand on a floor")
print(f"{len(points)} node and polyline points stand on floors")

# --- the hills -----------------------------------------------------------------------------
hill = {(t["level"], t["row"], t["col"]): t for t in labels["tiles"]
        if "elevation" in t.get("features", []) or "raised" in t.get("features", [])}
ends = [k for k, t in hill.items() if "elevation" in t["features"]]
raised = [k for k, t in hill.items() if "raised" in t["features"]]
if not ends:
    sys.exit("FAIL: the world has no hill")
# Cells as the exporter's: x = col * pitch, y = (rows - 1 - row) * pitch.
grid_rows = int(np.load(os.path.join(folder, "occupancy.npy")).shape[1])


def cell_of(level, x, y):
    return (level, grid_rows - 1 - math.floor(y / pitch + 0.5), math.floor(x / pitch + 0.5))


def level_of(z):
    return max(0, math.floor((z + 0.25 * lh) / lh))


lines = [e["polyline"] for e in graph["edges"] if e["kind"] == "corridor"]


def points_in(cell):
    return [p for line in lines for p in line if cell_of(cell[0], p[0], p[1]) == cell
            and level_of(p[2] - (RISE if cell in hill else 0)) == cell[0]]


climbs = []
for c in ends:
    ps = points_in(c)
    if len(ps) < 3:
        sys.exit(f"FAIL: hill end {c}: only {len(ps)} polyline points over it")
    zs = [p[2] - c[0] * lh for p in ps]
    climb = max(zs) - min(zs)
    climbs.append(climb)
    if abs(climb - RISE) > TOL:
        sys.exit(f"FAIL: hill end {c}: the polyline climbs {climb:.2f} m over it, not {RISE} m")
low_raised = min((p[2] - c[0] * lh for c in raised for p in points_in(c)), default=RISE)
if low_raised < RISE - TOL:
    sys.exit(f"FAIL: a point over a raised tile stands {low_raised:.2f} m over its level")
print(f"{len(ends) // 2} hills ({len(raised)} raised tiles): the polylines climb "
      f"{min(climbs):.2f} to {max(climbs):.2f} m over their ends (rise {RISE}); points over "
      f"raised tiles stand at least {low_raised:.2f} m up")


# --- slopes --------------------------------------------------------------------------------
def tile_grade():
    """The elevation tile's steepest floor along its middle line (its passage runs along x or
    y in the file), over 4 m runs, degrees."""
    t = trimesh.load(tile_file, force="mesh", process=False)
    v = np.asarray(t.vertices)
    v = np.column_stack([v[:, 0], -v[:, 2], v[:, 1]])  # Y up to Z up
    ft = v[np.asarray(t.faces)]
    lo, hi = v.min(axis=0), v.max(axis=0)
    along_y = hi[1] - lo[1] > hi[0] - lo[0]
    mid = 0.5 * (lo + hi)
    profile = []
    for s in np.arange(-0.45 * pitch, 0.45 * pitch, 0.5):
        x, y = (mid[0], s) if along_y else (s, mid[1])
        hits = crossings_of(ft, x, y)
        floor = next((hits[k][0] for k in range(len(hits) - 1) if hits[k][1] and not hits[k + 1][1]), None)
        if floor is not None:
            profile.append((s, floor))
    worst = 0.0
    for i, (s0, z0) in enumerate(profile):
        for s1, z1 in profile[i + 1:]:
            if s1 - s0 >= RUN:
                worst = max(worst, math.degrees(math.atan2(abs(z1 - z0), s1 - s0)))
                break
    return worst


SLACK = 3.0
limit = tile_grade() + SLACK
steepest = 0.0
for line in lines:
    last = None
    for p in line:
        if cell_of(level_of(p[2] - RISE), p[0], p[1]) not in hill and cell_of(level_of(p[2]), p[0], p[1]) not in hill:
            last = None
            continue
        if last is None:
            last = p
            continue
        run = math.hypot(p[0] - last[0], p[1] - last[1])
        if run >= RUN:
            steepest = max(steepest, math.degrees(math.atan2(abs(p[2] - last[2]), run)))
            last = p
if steepest > limit:
    sys.exit(f"FAIL: a polyline over a hill is {steepest:.1f} degrees steep; the tile's floor at most {limit - SLACK:.1f}")
print(f"steepest polyline over a hill: {steepest:.1f} degrees (the tile's floor: {limit - SLACK:.1f})")

# --- a ball on every raised tile -----------------------------------------------------------
import pybullet as pb  # noqa: E402

os.chdir(tempfile.gettempdir())
pb.connect(pb.DIRECT)
pb.loadURDF(os.path.join(folder, "urdf", "world.urdf"), useFixedBase=True)
pb.setGravity(0, 0, -9.81)
rested = 0
for c in raised:
    at = hill[c]["position"]
    ball = pb.createMultiBody(0.5, pb.createCollisionShape(pb.GEOM_SPHERE, radius=0.3), -1,
                              [at[0], at[1], at[2] + 0.8])
    pb.changeDynamics(ball, -1, linearDamping=0.04, angularDamping=0.5, rollingFriction=0.01)
    for _ in range(240 * 5):
        pb.stepSimulation()
    p, _ = pb.getBasePositionAndOrientation(ball)
    if p[2] - c[0] * lh < RISE - TOL or cell_of(c[0], p[0], p[1]) != c:
        sys.exit(f"FAIL: a ball released over {at} on raised tile {c} is at {p} after 5 s")
    rested += 1
    pb.removeBody(ball)
print(f"PyBullet (URDF triangle mesh): a ball rests on each of {rested} raised tiles after 5 s")

# --- the same in MuJoCo, on the height fields ----------------------------------------------
xml = os.path.join(folder, "mujoco", "world.xml")
if os.path.exists(xml):
    import mujoco

    spec = mujoco.MjSpec.from_file(xml)
    for k, c in enumerate(raised):
        at = hill[c]["position"]
        body = spec.worldbody.add_body(name=f"ball{k}", pos=[at[0], at[1], at[2] + 0.8])
        body.add_freejoint()
        body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[0.3, 0, 0], mass=0.5)
    model = spec.compile()
    model.opt.timestep = 0.004
    data = mujoco.MjData(model)
    mujoco.mj_step(model, data, nstep=int(5 / 0.004))
    for k, c in enumerate(raised):
        p = data.xpos[model.body(f"ball{k}").id]
        if p[2] - c[0] * lh < RISE - TOL or cell_of(c[0], p[0], p[1]) != c:
            sys.exit(f"FAIL: MuJoCo: a ball released over raised tile {c} is at {p.tolist()} after 5 s")
    print(f"MuJoCo (height fields): a ball rests on each of {len(raised)} raised tiles after 5 s")
print("OK")
