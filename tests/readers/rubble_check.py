"""Checks a world's rubble fields and drops (ground_truth/hazards.json `regions`) against the
collision surface every format exports (mesh/collision.obj, read by trimesh) and against
MuJoCo's physics.

usage: rubble_check.py WORLD_DIR [balls]

- rays (straight down onto the collision mesh: the highest surface under the start point):
  over every rubble rock the surface is above the floor by at least a third of the rock's
  radius; along a passable field's lane, and at the node of every corridor tile without a
  hazard, it is the floor (within FLOOR_TOL of the floor's height: on a lane, the floor as the
  nearest rocks have it, rising at most MAX_GRADE between them, as floors slope); at a drop's
  centre it is at least half the pit's depth below the floor;
- balls: in MuJoCo (mujoco/world.xml), a ball (radius BALL m) dropped from 1 m above the
  highest rock onto the rock nearest the middle of each rubble field comes to rest (3 s) with
  its bottom above the floor by more than the floor's relief (ON_ROCKS): it lies on rocks. On a
  sloping floor a ball may roll off a field's downhill end: at least ON_ROCKS_SHARE of the balls
  must lie on rocks, and none may end below the floor (through the surface). Use with
  rubble_passable = false (no lane to roll into).

Prints one summary line per check; exits non-zero on the first disagreement.
"""
import json
import sys
from pathlib import Path

import numpy as np
import trimesh
from plane_squares import plane_squares

FLOOR_TOL = 0.45
BALL = 0.5
# A ball on the floor rests with its bottom within the floor's relief (at most 0.03 of the
# passage width: 0.26 m on the cave preset) of the floor's height.
ON_ROCKS = 0.3
ON_ROCKS_SHARE = 0.9
# The steepest floor grade the cave tile set makes by default (its `grade` high end), degrees.
MAX_GRADE = 12.0

world = Path(sys.argv[1])
doc = json.loads((world / "ground_truth/hazards.json").read_text())
labels = json.loads((world / "ground_truth/semantic_labels.json").read_text())
regions = doc["regions"]
mesh = trimesh.load(world / "mesh/collision.obj", force="mesh", process=False)
tri = mesh.vertices[mesh.faces]
lo, hi = tri.min(axis=1), tri.max(axis=1)
E = 1e-4  # the mesh's coordinates are 32-bit floats
BUCKET = 2.0

# A vertical line meets only the triangles of its square (boxes grown by E).
SQUARES = plane_squares(lo[:, :2] - E, hi[:, :2] + E, BUCKET)


def down(x, y, z):
    """Height of the highest collision surface under (x, y) below z, or None."""
    e = E
    near = SQUARES.get((int(np.floor(x / BUCKET)), int(np.floor(y / BUCKET))), np.zeros(0, np.int64))
    m = (lo[near, 0] <= x + e) & (hi[near, 0] >= x - e) & (lo[near, 1] <= y + e) & (hi[near, 1] >= y - e)
    m &= lo[near, 2] < z
    m = near[m]
    a, b, c = tri[m, 0], tri[m, 1], tri[m, 2]
    d = (b[:, 1] - c[:, 1]) * (a[:, 0] - c[:, 0]) + (c[:, 0] - b[:, 0]) * (a[:, 1] - c[:, 1])
    ok = d != 0
    a, b, c, d = a[ok], b[ok], c[ok], d[ok]
    l1 = ((b[:, 1] - c[:, 1]) * (x - c[:, 0]) + (c[:, 0] - b[:, 0]) * (y - c[:, 1])) / d
    l2 = ((c[:, 1] - a[:, 1]) * (x - c[:, 0]) + (a[:, 0] - c[:, 0]) * (y - c[:, 1])) / d
    l3 = 1 - l1 - l2
    eps = -1e-6  # a point on a shared edge belongs to both triangles
    inside = (l1 >= eps) & (l2 >= eps) & (l3 >= eps)
    zs = l1[inside] * a[inside, 2] + l2[inside] * b[inside, 2] + l3[inside] * c[inside, 2]
    zs = zs[zs < z]
    return float(zs.max()) if len(zs) else None


def check_rays():
    rubble = [r for r in regions if r["kind"] == "rubble"]
    drops = [r for r in regions if r["kind"] == "drop"]
    assert rubble or drops, "no regions"
    rocks = 0
    for r in rubble:
        assert r["rocks"], r
        for x, y, z, rad in r["rocks"]:
            b = r["bounds"]
            assert b[0] <= x - rad + 1e-6 and x + rad <= b[2] + 1e-6, (r["cell"], x, b)
            assert b[1] <= y - rad + 1e-6 and y + rad <= b[3] + 1e-6, (r["cell"], y, b)
            hit = down(x, y, r["z"][1] + 1.0)
            assert hit is not None and hit > r["floor_z"] + rad / 3, (r["cell"], [x, y, z, rad], hit)
            rocks += 1
        if "gap" in r:
            g = r["gap"]
            along_x = (g[2] - g[0]) > (g[3] - g[1])
            for t in np.linspace(0.15, 0.85, 6):
                if along_x:
                    x, y = g[0] + t * (g[2] - g[0]), 0.5 * (g[1] + g[3])
                else:
                    x, y = 0.5 * (g[0] + g[2]), g[1] + t * (g[3] - g[1])
                hit = down(x, y, r["z"][1] + 1.0)
                # A rock's centre is half its radius above the floor under it.
                floor = min(rz - 0.5 * rad + np.tan(np.radians(MAX_GRADE)) * np.hypot(rx - x, ry - y)
                            for rx, ry, rz, rad in r["rocks"])
                assert hit is not None and hit < floor + FLOOR_TOL, (r["cell"], "lane", x, y, hit, floor)
    for r in drops:
        b = r["bounds"]
        x, y = 0.5 * (b[0] + b[2]), 0.5 * (b[1] + b[3])
        depth = r["z"][1] - r["z"][0]
        hit = down(x, y, r["floor_z"] + 1.0)
        assert hit is not None and hit < r["floor_z"] - 0.5 * depth, (r["cell"], "pit", hit, depth)
    hazard = {(r["cell"]["level"], r["cell"]["row"], r["cell"]["col"]) for r in regions}
    plain = 0
    for t in labels["tiles"]:
        if t["kind"] not in ("straight", "corner") or (t["level"], t["row"], t["col"]) in hazard:
            continue
        if t.get("hazard"):
            continue
        # The tile's node, on its passage's floor.
        x, y, z = t["position"]
        hit = down(x, y, z + 2.0)
        assert hit is not None and abs(hit - z) < FLOOR_TOL, ((t["level"], t["row"], t["col"]), hit, z)
        plain += 1
    print(f"rays: {rocks} rocks in {len(rubble)} rubble fields above the floor, "
          f"{len(drops)} pits below it, {plain} plain corridor tiles on the floor")


def check_balls():
    import mujoco

    rubble = [r for r in regions if r["kind"] == "rubble"]
    spec = mujoco.MjSpec.from_file(str(world / "mujoco/world.xml"))
    starts = []
    for i, r in enumerate(rubble):
        rocks = np.array(r["rocks"])
        # The rock nearest the middle of the field.
        mid = rocks[:, :2].mean(axis=0)
        x, y = rocks[np.argmin(((rocks[:, :2] - mid) ** 2).sum(axis=1)), :2]
        z = r["z"][1] + 1.0 + BALL
        body = spec.worldbody.add_body(name=f"ball-{i}", pos=[x, y, z])
        body.add_freejoint()
        body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[BALL, 0, 0], mass=2.0)
        starts.append(r)
    m = spec.compile()
    d = mujoco.MjData(m)
    for _ in range(int(3.0 / m.opt.timestep)):
        mujoco.mj_step(m, d)
    on_rocks = []
    for i, r in enumerate(starts):
        x, y, z = d.body(f"ball-{i}").xpos
        above = z - BALL - r["floor_z"]
        # Never through the floor: the surface under the ball's centre is under its bottom.
        under = down(x, y, z)
        assert under is not None and z - BALL > under - 0.05, (r["cell"], "ball below the floor", z, under)
        if above > ON_ROCKS:
            on_rocks.append(above)
    share = len(on_rocks) / len(starts)
    assert share >= ON_ROCKS_SHARE, f"only {len(on_rocks)} of {len(starts)} balls rest on rocks"
    print(f"balls: {len(on_rocks)} of {len(starts)} balls dropped on rubble rest on rocks, the lowest "
          f"{min(on_rocks):.2f} m above the floor; the rest rolled off onto the floor")


check_rays()
if "balls" in sys.argv[2:]:
    check_balls()
