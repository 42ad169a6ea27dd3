"""Checks a world folder's ground_truth/ files with the readers their users have (numpy, PIL,
yaml, networkx, csv, json) against the grid (occupancy.npy, world.toml, topology.json) and,
when the world has geometry, against an independent numpy ray parity on mesh/collision.obj
(loaded with trimesh, which also checks it is closed).

usage: ground_truth_check.py WORLD_DIR mesh|grid
Prints one line per file checked; exits non-zero (AssertionError) on the first disagreement.
"""

import csv
import json
import math
import sys
import tomllib
from pathlib import Path

import networkx as nx
import numpy as np
from plane_squares import plane_squares
import yaml
from PIL import Image

world = Path(sys.argv[1])
with_mesh = sys.argv[2] == "mesh"
gt = world / "ground_truth"

codes = np.load(world / "occupancy.npy")
levels, rows, cols = codes.shape
toml = tomllib.loads((world / "world.toml").read_text())
pitch = toml["world"]["tile_pitch"]
lh = toml["world"]["level_height"]
seed = toml["world"]["seed"]
topo = json.loads((world / "topology.json").read_text())
KINDS = {1: "dead-end", 2: "straight", 3: "corner", 4: "t-junction", 5: "intersection",
         11: "shaft-up", 111: "shaft-landing"}
# With world.connections = "ramp" both ends of a ramp are labelled `ramp`.
RAMPS = toml["world"].get("connections") == "ramp"


def label_kind(code):
    return "ramp" if RAMPS and code in (11, 111) else KINDS[code]

# Directions: east +col, north -row, west -col, south +row.
STEPS = {"east": (0, 1), "north": (-1, 0), "west": (0, -1), "south": (1, 0)}


def centre(level, row, col):
    return np.array([col * pitch, (rows - 1 - row) * pitch, level * lh])


def cell_of(x, y):
    """(row, col) of the cell square holding (x, y), half-open like the exporter."""
    return rows - 1 - np.floor(y / pitch + 0.5).astype(int), np.floor(x / pitch + 0.5).astype(int)


def occupied(level, r, c):
    inside = (r >= 0) & (r < rows) & (c >= 0) & (c < cols)
    out = np.zeros(np.shape(r), dtype=bool)
    out[inside] = codes[level][r[inside], c[inside]] != 0
    return out


def in_ramp_block(level, r, c):
    """Whether (r, c) is one of the three empty cells beside a ramp's end on `level` that its
    spiral turns in (topology.json's shaft `block`): empty in the grid, free in the mesh."""
    out = np.zeros(np.shape(r), dtype=bool)
    for s in topo["shafts"]:
        if "block" not in s:
            continue
        dr, dc = s["block"]
        for end in (s["up"], s["landing"]):
            if end["level"] == level:
                for a, b in ((dr, 0), (0, dc), (dr, dc)):
                    out |= (r == end["row"] + a) & (c == end["col"] + b)
    return out


mesh = None
if with_mesh:
    import trimesh

    mesh = trimesh.load(world / "mesh/collision.obj", process=True)
    assert mesh.is_watertight, "the collision surface is closed"


SQUARES = {}


def crossings(points):
    """Heights where the vertical line through each point crosses the collision surface: our
    own numpy ray parity, in floating point (trimesh.contains needs rtree, not installed)."""
    tri = mesh.triangles  # (T, 3, 3)
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    lo, hi = tri[:, :, :2].min(axis=1), tri[:, :, :2].max(axis=1)
    area = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    if not SQUARES:
        SQUARES.update(plane_squares(lo, hi, 4.0))
    out = []
    # Lines through shared edges would count twice in this simple test: nudge them off by a
    # few micrometres (the exporter's own test is exact on edges).
    for p in np.asarray(points, dtype=float) + [3.1e-6, 1.7e-6, 0.0]:
        near = SQUARES.get((math.floor(p[0] / 4.0), math.floor(p[1] / 4.0)), np.zeros(0, np.int64))
        m = near[(lo[near, 0] <= p[0]) & (p[0] <= hi[near, 0]) & (lo[near, 1] <= p[1]) & (p[1] <= hi[near, 1]) & (area[near] != 0)]
        A, B, C, S = a[m], b[m], c[m], area[m]

        def edge(u, v):
            return (v[:, 0] - u[:, 0]) * (p[1] - u[:, 1]) - (v[:, 1] - u[:, 1]) * (p[0] - u[:, 0])

        wa, wb, wc = edge(B, C), edge(C, A), edge(A, B)
        inside = ((wa >= 0) & (wb >= 0) & (wc >= 0)) | ((wa <= 0) & (wb <= 0) & (wc <= 0))
        z = (wa * A[:, 2] + wb * B[:, 2] + wc * C[:, 2]) / S
        out.append(np.sort(z[inside]))
    return out


def agree_with_mesh(points, claimed, what):
    """Inside by parity of the crossings above each point must match `claimed`, except for
    points within 1 mm (vertically) of the surface. Returns how many were that close."""
    close = 0
    for p, zs, say in zip(points, crossings(points), claimed):
        if len(zs) and np.abs(zs - p[2]).min() < 1e-3:
            close += 1
            continue
        assert len(zs) % 2 == 0, f"{what}: the surface is open above {p}"
        inside = (zs > p[2]).sum() % 2 == 1
        assert inside == say, f"{what}: {p} is {'inside' if inside else 'outside'} the collision surface, the file says {say}"
    return close


# --- graph -------------------------------------------------------------------------------
g = json.loads((gt / "graph.json").read_text())
assert g["seed"] == seed and "x east" in g["frame"]
assert len(g["nodes"]) == len(topo["nodes"]) and len(g["edges"]) == len(topo["edges"])


def on_floor(points, what, collars=()):
    """Issue 15: every point stands in free space on a floor: half a metre above it is inside
    the passages (parity), and a ray down from there hits the surface within a metre. The
    points numbered in `collars` (a vertical shaft's landing, issue 24: over the shaft's axis at
    its floor's height) need only be in free space."""
    points = np.asarray(points, dtype=float)
    above = points + [0, 0, 0.5]
    for k, (p, zs) in enumerate(zip(points, crossings(above))):
        if k in collars:
            continue
        below = zs[zs <= p[2] + 0.5]
        assert len(below) and p[2] + 0.5 - below.max() <= 1.0, f"{what}: no floor under {p.tolist()}"
    agree_with_mesh(above, np.ones(len(above), dtype=bool), what)


def collars_of(items):
    """The indices of the shaft landings among graph nodes or label tiles."""
    return {k for k, n in enumerate(items) if n["kind"] == "shaft-landing"}


for n, t in zip(g["nodes"], topo["nodes"]):
    assert n["kind"] == KINDS[codes[n["level"], n["row"], n["col"]]] == t["kind"]
    c = centre(n["level"], n["row"], n["col"])
    if mesh is None:
        assert np.allclose(n["position"], c)
    else:
        # On the floor of the tile's own passage, inside the tile's square.
        assert np.abs(np.array(n["position"][:2]) - c[:2]).max() <= pitch / 2 + 1e-6
if mesh is not None:
    on_floor([n["position"] for n in g["nodes"]], "graph nodes", collars_of(g["nodes"]))
G = nx.read_graphml(gt / "graph.graphml")
assert G.number_of_nodes() == len(topo["nodes"]) and G.number_of_edges() == len(topo["edges"])
assert G.graph["seed"] == seed
for n in g["nodes"]:
    a = G.nodes[f"n{n['id']}"]
    assert isinstance(a["level"], int) and isinstance(a["x"], float) and a["kind"] == n["kind"]
    assert abs(a["x"] - n["position"][0]) < 1e-3 and abs(a["z"] - n["position"][2]) < 1e-3
edges = G.edges(data=True)
by_id = {d["edge_id"]: (u, v, d) for u, v, d in edges}
for e, t in zip(g["edges"], topo["edges"]):
    u, v, d = by_id[e["id"]]
    assert {u, v} == {f"n{t['from']}", f"n{t['to']}"} and d["kind"] == t["kind"]
    line = np.array(json.loads(d["polyline"]))
    if t["kind"] == "ramp" and mesh is not None:
        # A ramp's length is the length driven along its spiral (topology.json: the level height).
        driven = np.linalg.norm(np.diff(line, axis=0), axis=1).sum()
        assert abs(d["length_m"] - driven) < 1e-2 and driven > 2 * t["length_m"], (driven, t)
    else:
        assert abs(d["length_m"] - t["length_m"]) < 1e-3
    assert d["length_cells"] == t["length_cells"]
    assert np.allclose(line, np.array(e["polyline"]), atol=1e-3)
    # Least width and height (issue 15): numbers in both files with a mesh, absent without.
    if mesh is None:
        assert e["min_width_m"] is None and "min_width_m" not in d
    else:
        assert 0 < e["min_width_m"] <= 2 * pitch and 0 < e["min_height_m"]
        assert abs(d["min_width_m"] - e["min_width_m"]) < 1e-3
        assert abs(d["min_height_m"] - e["min_height_m"]) < 1e-3
    ends = [g["nodes"][t["from"]]["position"], g["nodes"][t["to"]]["position"]]
    assert np.allclose(line[[0, -1]], ends, atol=1e-3), "a polyline runs from node to node"
    if mesh is None:
        assert len(line) == len(t["cells"])
        for p, c in zip(line, t["cells"]):
            assert np.allclose(p, centre(c["level"], c["row"], c["col"]), atol=1e-3)
        if t["kind"] == "corridor":
            assert abs(np.linalg.norm(np.diff(line, axis=0), axis=1).sum() - t["length_m"]) < 1e-2
    elif t["kind"] == "corridor":
        # Along the passage through every cell of the corridor, on its floor.
        r, cc = cell_of(line[:, 0], line[:, 1])
        assert occupied(t["cells"][0]["level"], r, cc).all(), "the polyline stays in its cells"
        ends = {0: t["from"], len(line) - 1: t["to"]}
        on_floor(line, f"edge {e['id']}",
                 {k for k, n in ends.items() if g["nodes"][n]["kind"] == "shaft-landing"})
print(f"graph: {G.number_of_nodes()} nodes, {G.number_of_edges()} edges, as topology.json"
      + ("; every node and polyline point on the floor of its passage" if mesh is not None else ""))

# --- semantic labels ---------------------------------------------------------------------
labels = json.loads((gt / "semantic_labels.json").read_text())
assert labels["seed"] == seed
with open(gt / "semantic_labels.csv", newline="") as f:
    table = list(csv.DictReader(f))
assert len(table) == len(labels["tiles"]) == int((codes != 0).sum())
for row, t in zip(table, labels["tiles"]):
    l, r, c = int(row["level"]), int(row["row"]), int(row["col"])
    assert int(row["code"]) == codes[l, r, c] != 0 and row["kind"] == label_kind(codes[l, r, c]) == t["kind"]
    opens = set(row["openings"].split())
    # Chambers and squeezes (issue 15), refuge bays, services and mesh panels (issue 24): the
    # CSV's column, when present, says what the JSON does.
    assert set(t.get("features", [])) <= {"chamber", "squeeze", "refuge-bay", "rock-bolt", "duct",
                                          "pipe", "cable", "light", "mesh-panels"}
    if "features" in row:
        assert set(row["features"].split()) == set(t.get("features", []))
    else:
        assert "features" not in t
    assert opens == set(t["openings"])
    for name, (dr, dc) in STEPS.items():
        rr, cc = r + dr, c + dc
        neighbour = 0 <= rr < rows and 0 <= cc < cols and codes[l, rr, cc] != 0
        assert (name in opens) == neighbour, (l, r, c, name)
    at = np.array([float(row["x"]), float(row["y"]), float(row["z"])])
    assert np.allclose(at, t["position"], atol=1e-3)
    if mesh is None:
        assert np.allclose(at, centre(l, r, c), atol=1e-3)
    else:
        assert np.abs(at[:2] - centre(l, r, c)[:2]).max() <= pitch / 2 + 1e-6
if mesh is not None:
    on_floor([t["position"] for t in labels["tiles"]], "semantic label positions",
             collars_of(labels["tiles"]))
print(f"semantic labels: {len(table)} tiles, one per occupied cell with its code and openings")

# --- ROS maps ----------------------------------------------------------------------------
for level in range(levels):
    meta = yaml.safe_load((gt / f"maps/level-{level}.yaml").read_text())
    assert meta["image"] == f"level-{level}.pgm" and meta["mode"] == "trinary" and meta["negate"] == 0
    assert meta["occupied_thresh"] == 0.65 and meta["free_thresh"] == 0.196
    img = Image.open(gt / f"maps/level-{level}.pgm")
    assert img.format == "PPM" and img.mode == "L"
    a = np.asarray(img)
    assert set(np.unique(a)) <= {0, 254}
    # map_server's reading: p = (255 - v) / 255; free below free_thresh, occupied above.
    p = (255 - a.astype(float)) / 255
    assert ((p < meta["free_thresh"]) == (a == 254)).all() and ((p > meta["occupied_thresh"]) == (a == 0)).all()
    res, (ox, oy, yaw) = meta["resolution"], meta["origin"]
    h, w = a.shape
    xs = ox + (np.arange(w) + 0.5) * res
    ys = oy + (h - 1 - np.arange(h) + 0.5) * res  # row 0 is north
    X, Y = np.meshgrid(xs, ys)
    r, c = cell_of(X, Y)
    in_cells = occupied(level, r, c) | in_ramp_block(level, r, c)
    free = a == 254
    assert not (free & ~in_cells).any(), \
        "free pixels only over occupied cells of this level (and its ramps' spiral blocks)"
    # Every tile's node (its own passage's floor: a cave's corner bends away from the cell
    # centre) is free on its level's map (a ramp's cells have the spiral's rock pillar at
    # their centre, and their nodes where the spiral leaves the level).
    nodes = np.array([t["position"][:2] for t in labels["tiles"]
                      if t["level"] == level and not (RAMPS and t["kind"] == "ramp")])
    if len(nodes):
        px = np.floor((nodes[:, 0] - ox) / res).astype(int)
        py = h - 1 - np.floor((nodes[:, 1] - oy) / res).astype(int)
        assert free[py, px].all(), "every tile's node is free"
    if mesh is None:
        assert (free == in_cells).all(), "without a mesh the map is the cells' squares"
        checked = "the cells' squares"
    else:
        rng = np.random.default_rng(level)
        pick = np.concatenate([rng.choice(np.flatnonzero(free), 1000),
                               rng.choice(np.flatnonzero(in_cells & ~free), 1000)])
        # The map is a slice 1 m above the floor under each pixel: the level's nominal floor,
        # or where a free stretch starts above it (sloping floors). Free stretches are the
        # crossings' pairs (outside below the lowest), as the mesh is closed.
        nominal = level * lh
        near = 0
        pts = np.column_stack([X.flat[pick], Y.flat[pick], np.zeros(len(pick))])
        for p, zs, say in zip(pts, crossings(pts), free.flat[pick]):
            assert len(zs) % 2 == 0, f"map level {level}: the surface is open above {p}"
            stretches = [(zs[k], zs[k + 1]) for k in range(0, len(zs), 2) if zs[k] < nominal + 0.75 * lh]
            slices = [max(z0, nominal) + 1.0 for z0, _ in stretches]
            if any(min(abs(z - z0), abs(z - z1)) < 1e-3 for (z0, z1), z in zip(stretches, slices)):
                near += 1
                continue
            inside = any(z0 < z < z1 for (z0, z1), z in zip(stretches, slices))
            assert inside == say, f"map level {level}: {p[:2]} is {'free' if inside else 'rock'} 1 m above its floor, the file says {say}"
        checked = f"numpy ray parity at 2000 pixels ({near} within 1 mm of the surface)"
    print(f"ros map level {level}: {w} x {h} at {res} m, {int(free.sum())} free pixels, agrees with {checked}")

# --- free space --------------------------------------------------------------------------
fmeta = json.loads((gt / "free_space.json").read_text())
assert fmeta["seed"] == seed and fmeta["axes"] == ["z", "y", "x"]
packed = np.load(gt / "free_space.npy")
nz, ny, nx_ = fmeta["shape"]
assert packed.dtype == np.uint8 and list(packed.shape) == fmeta["packed_shape"]
vox = np.unpackbits(packed, axis=2, count=nx_).astype(bool)
assert vox.shape == (nz, ny, nx_) and int(vox.sum()) == fmeta["free_voxels"]
v = fmeta["voxel_m"]
o = np.array(fmeta["origin"])
zc = o[2] + (np.arange(nz) + 0.5) * v
yc = o[1] + (np.arange(ny) + 0.5) * v
xc = o[0] + (np.arange(nx_) + 0.5) * v
if mesh is None:
    # Independent: each occupied cell's square from its floor up half a level; a shaft's foot
    # up into the landing above.
    expect = np.zeros_like(vox)
    Y2, X2 = np.meshgrid(yc, xc, indexing="ij")
    r, c = cell_of(X2, Y2)
    for level in range(levels):
        occ = occupied(level, r, c)
        shaft = np.zeros_like(occ)
        ok = (r >= 0) & (r < rows) & (c >= 0) & (c < cols)
        shaft[ok] = codes[level][r[ok], c[ok]] == 11
        top = np.where(shaft, level * lh + 1.5 * lh, level * lh + 0.5 * lh)
        for k, z in enumerate(zc):
            expect[k] |= occ & (z > level * lh) & (z < top)
    assert (vox == expect).all(), f"{int((vox != expect).sum())} voxels differ from the grid's cells"
    checked = "every voxel against the cells"
else:
    # Independent: numpy ray parity at sampled voxel centres, free ones and rock ones near passages.
    rng = np.random.default_rng(7)
    free_idx = np.argwhere(vox)
    rock_idx = np.argwhere(~vox & np.roll(vox, 2, axis=2))  # rock 1 m beside free space
    pick = np.concatenate([free_idx[rng.choice(len(free_idx), 2000)], rock_idx[rng.choice(len(rock_idx), 2000)]])
    pts = np.column_stack([xc[pick[:, 2]], yc[pick[:, 1]], zc[pick[:, 0]]])
    near = agree_with_mesh(pts, vox[pick[:, 0], pick[:, 1], pick[:, 2]], "free space")
    volume = int(vox.sum()) * v**3
    checked = f"numpy ray parity at 4000 voxels ({near} within 1 mm), volume {volume:.0f} vs mesh {abs(mesh.volume):.0f} m^3"
print(f"free space: {nz} x {ny} x {nx_} voxels of {v} m, {int(vox.sum())} free, agrees with {checked}")

# --- spawn poses -------------------------------------------------------------------------
sp = json.loads((gt / "spawn_poses.json").read_text())
assert sp["seed"] == seed and sp["source"] == ("collision-mesh" if with_mesh else "grid")
robots = sp["robots"]
assert len(robots) == sp["robots_requested"]
start = sp["start"]
assert codes[start["level"], start["row"], start["col"]] == 1 and start["level"] == 0
opening = [n for n, (dr, dc) in STEPS.items()
           if 0 <= start["row"] + dr < rows and 0 <= start["col"] + dc < cols
           and codes[0, start["row"] + dr, start["col"] + dc] != 0]
facing = {"east": 0.0, "north": math.pi / 2, "west": math.pi, "south": -math.pi / 2}[opening[0]]
P = np.array([r["spawn"]["position"] for r in robots])
for r in robots:
    assert abs(r["spawn"]["yaw"] - facing) < 1e-9
    q = r["spawn"]["quaternion_xyzw"]
    assert abs(2 * math.atan2(q[2], q[3]) - facing) < 1e-9
d = np.linalg.norm(P[:, None, :2] - P[None, :, :2], axis=2) + np.eye(len(P)) * 1e9
assert d.min() >= sp["spacing_m"] - 1e-9, "robots keep their spacing"
if mesh is None:
    assert np.allclose(P[:, 2], 0.0)
    r, c = cell_of(P[:, 0], P[:, 1])
    assert occupied(0, r, c).all()
else:
    above = P + [0, 0, 0.5]
    for k, hits in enumerate(crossings(above)):
        floor = hits[hits <= above[k, 2]].max()
        assert abs(floor - P[k, 2]) < 1e-3, f"robot {k} at z {P[k, 2]}, floor below it at {floor}"
    ring = [P[k] + [0.9 * sp["clearance_m"] * math.cos(t), 0.9 * sp["clearance_m"] * math.sin(t), 0.5]
            for k in range(len(P)) for t in np.linspace(0, 2 * math.pi, 16, endpoint=False)]
    agree_with_mesh(np.array(ring), np.ones(len(ring), dtype=bool), "clearance round the robots")
    agree_with_mesh(above, np.ones(len(above), dtype=bool), "robots")
# Goals: the farthest nodes by path length over the graph, distinct.
dist = nx.single_source_dijkstra_path_length(G, f"n{g['start']}", weight="length_m")
eligible = sorted((-dd, int(n[1:])) for n, dd in dist.items()
                  if n != f"n{g['start']}" and G.nodes[n]["kind"] not in ("shaft-up", "shaft-landing"))
want = [n for _, n in eligible[: len(robots)]]
got = [r["goal"]["node"] for r in robots]
assert got == want and len(set(got)) == len(got), (got, want)
for r in robots:
    assert abs(r["goal"]["path_length_m"] - dist[f"n{r['goal']['node']}"]) < 1e-3
print(f"spawn poses: {len(robots)} robots >= {sp['spacing_m']} m apart on the floor, goals {got} farthest by path")
