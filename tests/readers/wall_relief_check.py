"""Wall relief of a world's straight passages, measured on its exported OBJ against a passage
fitted here, apart from the tile sets' code.

    python wall_relief_check.py WORLD [--min-cm X] [--max-cm Y] [--json OUT]

For every straight cell of the world's topology (topology.json: a corridor cell whose two
neighbours on its edge lie in line with it), the vertices of the wall-material triangles
(every `usemtl` group of world.obj whose name ends in `-wall`) inside the cell's slab along
the passage are split into the two sides. Each side's vertices between 1.2 m and 3.0 m above
the floor (a quadratic along the passage fitted to the lowest vertices near its axis) are fitted with a
plane `across = a + b * along + c * z` by least squares: the passage as designed, straight and
plumb-ish. The relief is what is left: the RMS of the residuals over every side of every
straight cell, in centimetres; cells the semantic labels give a refuge bay are left out. With --min-cm / --max-cm the check fails (exit 1) outside.
"""

import argparse
import csv
import json
import sys

import numpy as np
import obj_reader


def read_obj(path):
    """Vertices (N x 3) and, per material name, its triangles (M x 3, zero-based)."""
    obj = obj_reader.read_obj(path)
    return obj.vertices, obj.by_material()


def wall_vertices(groups):
    """Indices of the vertices of the rock walls and back: every material group whose name
    ends in `-wall` (the mine's `meshed-wall`, the rock under its mesh panels, too)."""
    walls = [groups[n] for n in groups if n.endswith("-wall")]
    if not walls:
        raise SystemExit("no material group ending in -wall in world.obj")
    return np.unique(np.concatenate([np.asarray(t).reshape(-1) for t in walls]))


def straight_cells(topology):
    """(cell, axis) for every corridor cell in line with both its neighbours: axis 0 when the
    passage runs along x (east), 1 along y (north)."""
    found = []
    for e in topology["edges"]:
        cells = e["cells"]
        for i in range(1, len(cells) - 1):
            a, c, b = cells[i - 1], cells[i], cells[i + 1]
            if not (a["level"] == c["level"] == b["level"]):
                continue
            if a["row"] == c["row"] == b["row"]:
                found.append((c, 0))
            elif a["col"] == c["col"] == b["col"]:
                found.append((c, 1))
    return found


def labelled(world, feature):
    """(level, row, col) of the cells whose semantic labels list `feature` (none without
    ground truth)."""
    path = f"{world}/ground_truth/semantic_labels.csv"
    try:
        rows = list(csv.DictReader(open(path)))
    except FileNotFoundError:
        return set()
    return {
        (int(r["level"]), int(r["row"]), int(r["col"]))
        for r in rows
        if feature in (r.get("features") or "").split()
    }


def buckets(v, topology):
    """Vertices by the cell they lie in: {level * 1e6 + row * 1e3 + col: vertices}."""
    pitch = topology["tile_pitch_m"]
    rows = topology["rows"]
    lh = topology["level_height_m"]
    col = np.floor(v[:, 0] / pitch + 0.5).astype(np.int64)
    row = rows - 1 - np.floor(v[:, 1] / pitch + 0.5).astype(np.int64)
    level = np.floor((v[:, 2] + 0.25 * lh) / lh).astype(np.int64)
    k = level * 1_000_000 + row * 1000 + col
    order = np.argsort(k, kind="stable")
    ks = k[order]
    starts = np.flatnonzero(np.r_[True, ks[1:] != ks[:-1]])
    ends = np.r_[starts[1:], len(ks)]
    return {int(ks[s]): v[order[s:e]] for s, e in zip(starts, ends)}


def floor_fit(v, axis, centre):
    """The floor under the passage's axis in one cell, as a function of the distance along it:
    a quadratic fitted to the lowest vertices (any material) within 2 m of the axis (the
    floor's slopes rise and fall smoothly over a pitch or more)."""
    along = v[:, axis] - centre[axis]
    across = v[:, 1 - axis] - centre[1 - axis]
    near = np.abs(across) < 2.0
    z = v[near, 2]
    low = z < z.min() + 1.5
    coef = np.polyfit(along[near][low], z[low], 2)
    return lambda s: np.polyval(coef, s)


def measure(world):
    topology = json.load(open(f"{world}/topology.json"))
    # A refuge bay's recess is not relief: its cells are left out (refuge_bay_check.py finds
    # the recesses themselves).
    bays = labelled(world, "refuge-bay")
    verts, groups = read_obj(f"{world}/mesh/world.obj")
    wall_v = verts[wall_vertices(groups)]
    pitch = topology["tile_pitch_m"]
    rows = topology["rows"]
    residuals = []
    sides = 0
    walls_by = buckets(wall_v, topology)
    all_by = buckets(verts, topology)
    for cell, axis in straight_cells(topology):
        if (cell["level"], cell["row"], cell["col"]) in bays:
            continue
        k = cell["level"] * 1_000_000 + cell["row"] * 1000 + cell["col"]
        if k not in walls_by:
            continue
        centre = np.array([cell["col"] * pitch, (rows - 1 - cell["row"]) * pitch])
        w = walls_by[k]
        along = w[:, axis] - centre[axis]
        across = w[:, 1 - axis] - centre[1 - axis]
        z = w[:, 2] - floor_fit(all_by[k], axis, centre)(along)
        band = (z > 1.2) & (z < 3.0) & (np.abs(along) < 0.5 * pitch)
        for side in (across < 0, across > 0):
            m = band & side
            if m.sum() < 30:
                continue
            a = np.c_[np.ones(m.sum()), along[m], z[m]]
            coef, *_ = np.linalg.lstsq(a, across[m], rcond=None)
            residuals.append(across[m] - a @ coef)
            sides += 1
    if not residuals:
        raise SystemExit(f"{world}: no straight passage walls found")
    r = np.concatenate(residuals)
    return {
        "relief_rms_cm": float(100.0 * np.sqrt(np.mean(r * r))),
        "sides": sides,
        "vertices": int(r.size),
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("world")
    ap.add_argument("--min-cm", type=float)
    ap.add_argument("--max-cm", type=float)
    ap.add_argument("--json")
    args = ap.parse_args()
    out = measure(args.world)
    print(json.dumps(out))
    if args.json:
        json.dump(out, open(args.json, "w"))
    rms = out["relief_rms_cm"]
    if args.min_cm is not None and rms < args.min_cm:
        print(f"wall relief {rms:.1f} cm RMS is below {args.min_cm} cm", file=sys.stderr)
        sys.exit(1)
    if args.max_cm is not None and rms > args.max_cm:
        print(f"wall relief {rms:.1f} cm RMS is above {args.max_cm} cm", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
