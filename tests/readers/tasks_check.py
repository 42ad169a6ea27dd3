"""Checks a world folder's tasks/ (MovingAI .map and .scen files) against MovingAI's own
definition, written from https://movingai.com/benchmarks/formats.html and not from
subtgraph's code: an octile map ('.' and 'G' passable, '@' 'O' 'T' not; (0, 0) the upper-left
corner), eight moves, straight ones costing 1 and diagonal ones sqrt(2), no corner cutting (a
diagonal move needs both cells it passes between passable). A plain heapq A* with the octile
distance reproduces every optimal length to the files' 8 decimals; every start and goal is
passable; MAPF instances have distinct starts and distinct goals. With `mesh`, 300 passable
cells per level are checked to be inside the collision surface 1 m above the floor, and 300 rock
cells beside passable ones outside it (numpy ray parity on mesh/collision.obj, as
ground_truth_check.py checks the ROS maps).

usage: tasks_check.py WORLD_DIR mesh|grid
Prints one line per level; exits non-zero (AssertionError) on the first disagreement.
"""

import heapq
import json
import math
import sys
import tomllib
from pathlib import Path

import numpy as np
from plane_squares import plane_squares

world = Path(sys.argv[1])
with_mesh = sys.argv[2] == "mesh"
tasks = world / "tasks"
meta = json.loads((tasks / "tasks.json").read_text())
toml = tomllib.loads((world / "world.toml").read_text())
assert meta["format"] == "subtgraph-tasks/1"
assert meta["seed"] == toml["world"]["seed"]
lh = toml["world"]["level_height"]
SQRT2 = math.sqrt(2.0)


def read_map(path):
    lines = path.read_text().split("\n")
    assert lines[0] == "type octile", lines[0]
    kv = dict(line.split(" ") for line in lines[1:3])
    h, w = int(kv["height"]), int(kv["width"])
    assert lines[3] == "map"
    grid = lines[4:4 + h]
    assert all(len(r) == w for r in grid), "every row has width characters"
    assert lines[4 + h:] == [""], "nothing after the rows"
    chars = set("".join(grid))
    assert chars <= set(".@"), f"only '.' and '@' are written, found {chars}"
    return w, h, np.array([[c in ".G" for c in r] for r in grid], dtype=bool)


def read_scen(path, map_name, w, h):
    lines = path.read_text().split("\n")
    assert lines[0] in ("version 1", "version 1.0"), lines[0]
    assert lines[-1] == ""
    rows = []
    for n, line in enumerate(lines[1:-1], start=2):
        f = line.split("\t")
        assert len(f) == 9, f"{path.name}:{n}: 9 tab-separated fields, got {len(f)}"
        assert f[1] == map_name and (int(f[2]), int(f[3])) == (w, h), f"{path.name}:{n}: {f[1:4]}"
        assert len(f[8].split(".")[1]) == 8, f"{path.name}:{n}: 8 decimals, got {f[8]}"
        rows.append((int(f[0]), int(f[4]), int(f[5]), int(f[6]), int(f[7]), float(f[8])))
    return rows


def astar(free, w, h, start, goal):
    """MovingAI's optimal octile length from start (x, y) to goal, None if unreachable. Cells
    are numbered y * (w + 2) + x on the map framed by a row and a column of rock on every side
    (FLAT), so that a move never leaves the map."""
    flat = FLAT[id(free)]
    row = w + 2
    straight = [(d, 1.0) for d in (-1, 1, -row, row)]
    # A diagonal move and the two straight cells it passes between (no corner cutting).
    diagonal = [(dx + dy * row, dx, dy * row) for dx in (-1, 1) for dy in (-1, 1)]
    gx, gy = goal
    s, g_cell = (start[1] + 1) * row + start[0] + 1, (gy + 1) * row + gx + 1

    def hval(i):
        y, x = divmod(i, row)
        dx, dy = abs(x - 1 - gx), abs(y - 1 - gy)
        return max(dx, dy) + (SQRT2 - 1.0) * min(dx, dy)

    best = {s: 0.0}
    heap = [(hval(s), 0.0, s)]
    done = set()
    while heap:
        _, g, i = heapq.heappop(heap)
        if i in done:
            continue
        done.add(i)
        if i == g_cell:
            return g
        steps = [(i + d, g + c) for d, c in straight if flat[i + d]]
        steps += [(i + d, g + SQRT2) for d, a, b in diagonal if flat[i + d] and flat[i + a] and flat[i + b]]
        for n, ng in steps:
            if ng < best.get(n, math.inf):
                best[n] = ng
                heapq.heappush(heap, (ng + hval(n), ng, n))
    return None


FLAT = {}


def check_rows(rows, free, w, h, what):
    FLAT[id(free)] = np.pad(free, 1).ravel().tolist()
    for k, (bucket, sx, sy, gx, gy, length) in enumerate(rows):
        assert free[sy, sx] and free[gy, gx], f"{what} row {k}: start and goal passable"
        assert (sx, sy) != (gx, gy)
        got = astar(free, w, h, (sx, sy), (gx, gy))
        assert got is not None, f"{what} row {k}: goal reachable from start"
        assert abs(got - length) <= 5e-9 + 1e-12 * got, f"{what} row {k}: A* gives {got:.10f}, file {length}"
        assert bucket == int(length // 4), f"{what} row {k}: bucket {bucket} for length {length}"


mesh = None
if with_mesh:
    import trimesh

    mesh = trimesh.load(world / "mesh/collision.obj", process=True)
    assert mesh.is_watertight, "the collision surface is closed"


BUCKET = 4.0


def buckets():
    """The collision surface's triangles (those not edge-on from above) by the squares of the
    plane, BUCKET metres a side, their bounding boxes cover: a point's vertical line meets
    only triangles of its square."""
    tri = mesh.triangles
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    area = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    lo, hi = tri[:, :, :2].min(axis=1), tri[:, :, :2].max(axis=1)
    return tri, area, plane_squares(lo, hi, BUCKET, keep=np.nonzero(area != 0)[0])


def crossings(points):
    """Heights where the vertical line through each point crosses the collision surface."""
    out = []
    for p in np.asarray(points, dtype=float) + [3.1e-6, 1.7e-6, 0.0]:
        ts = BUCKETS[2].get((math.floor(p[0] / BUCKET), math.floor(p[1] / BUCKET)))
        if ts is None:
            out.append(np.zeros(0))
            continue
        tri, S = BUCKETS[0][ts], BUCKETS[1][ts]
        A, B, C = tri[:, 0], tri[:, 1], tri[:, 2]

        def edge(u, v):
            return (v[:, 0] - u[:, 0]) * (p[1] - u[:, 1]) - (v[:, 1] - u[:, 1]) * (p[0] - u[:, 0])

        wa, wb, wc = edge(B, C), edge(C, A), edge(A, B)
        inside = ((wa >= 0) & (wb >= 0) & (wc >= 0)) | ((wa <= 0) & (wb <= 0) & (wc <= 0))
        z = (wa * A[:, 2] + wb * B[:, 2] + wc * C[:, 2]) / S
        out.append(np.sort(z[inside]))
    return out


BUCKETS = buckets() if mesh is not None else None

res = meta["resolution_m"]
ox, oy = meta["origin"]
total = 0
for lv in meta["levels"]:
    level = lv["level"]
    assert lv["map"] == f"level-{level}.map"
    w, h, free = read_map(tasks / lv["map"])
    assert (w, h) == (lv["width"], lv["height"]) and int(free.sum()) == lv["free_cells"]
    rows = read_scen(tasks / lv["scen"], lv["map"], w, h)
    assert len(rows) == lv["problems"]
    assert [r[0] for r in rows] == sorted(r[0] for r in rows), "single-agent rows sorted by bucket"
    check_rows(rows, free, w, h, f"level {level} {lv['scen']}")
    total += len(rows)
    for name in lv["instances"]:
        agents = read_scen(tasks / name, lv["map"], w, h)
        assert len(agents) >= lv["agents"]
        starts = {(r[1], r[2]) for r in agents}
        goals = {(r[3], r[4]) for r in agents}
        assert len(starts) == len(agents) and len(goals) == len(agents), f"{name}: distinct starts and goals"
        check_rows(agents, free, w, h, name)
        total += len(agents)
    checked = ""
    if mesh is not None:
        # Cell (x, y)'s centre in world metres, as tasks.json states; 1 m above the floor
        # under it (the nominal one, or where a free stretch starts above it on a slope).
        rng = np.random.default_rng(level)
        ys, xs = np.nonzero(free)
        pick = rng.choice(len(xs), min(300, len(xs)), replace=False)
        # Rock cells beside free ones, where a map that shrank or grew the passages would err.
        grown = free.copy()
        grown[1:, :] |= free[:-1, :]
        grown[:-1, :] |= free[1:, :]
        grown[:, 1:] |= free[:, :-1]
        grown[:, :-1] |= free[:, 1:]
        rys, rxs = np.nonzero(grown & ~free)
        rpick = rng.choice(len(rxs), min(300, len(rxs)), replace=False)
        cx = np.concatenate([xs[pick], rxs[rpick]])
        cy = np.concatenate([ys[pick], rys[rpick]])
        says = np.concatenate([np.ones(len(pick), bool), np.zeros(len(rpick), bool)])
        pts = np.column_stack([ox + (cx + 0.5) * res, oy + (h - cy - 0.5) * res, np.zeros(len(cx))])
        nominal = level * lh
        near = 0
        for p, zs, say in zip(pts, crossings(pts), says):
            assert len(zs) % 2 == 0, f"level {level}: the surface is open above {p}"
            stretches = [(zs[k], zs[k + 1]) for k in range(0, len(zs), 2) if zs[k] < nominal + 0.75 * lh]
            slices = [max(z0, nominal) + meta["slice_height_m"] for z0, _ in stretches]
            if any(min(abs(z - z0), abs(z - z1)) < 1e-3 for (z0, z1), z in zip(stretches, slices)):
                near += 1
                continue
            inside = any(z0 < z < z1 for (z0, z1), z in zip(stretches, slices))
            assert inside == say, \
                f"level {level}: the cell at {p[:2]} is {'inside' if inside else 'outside'} a passage 1 m above its floor, the map says {'free' if say else 'rock'}"
        checked = (f"; {len(pick)} passable cells inside the collision surface and {len(rpick)} rock "
                   f"cells beside them outside ({near} within 1 mm)")
    print(f"tasks level {level}: {w} x {h} at {res} m, {lv['problems']} problems and "
          f"{len(lv['instances'])} x {lv['agents']} agents reproduced by A*{checked}")
print(f"tasks: {total} optimal lengths reproduced")
