"""How flat the floor of a world's straight passages is where a robot drives, measured on its
exported OBJ against a floor fitted here, apart from the tile sets' code.

    python floor_flatness_check.py WORLD [--half-width M] [--max-cm X]

For every straight cell of the world's topology (as in wall_relief_check.py: a corridor cell in
line with both its neighbours), the vertices of the floor-material triangles (the `usemtl`
group whose name ends in `-floor`) within `--half-width` metres (default 2) of the passage's
axis, the part a robot drives on clear of the walls, are fitted with a smooth floor by least
squares: a quadratic along the passage plus a plane across it (the floors' slopes rise and
fall over a pitch or more; a drift's floor is flat across). What is left is the floor's
roughness where it should have none: printed as JSON (median, 95th percentile and largest
residual, centimetres). With --max-cm the check fails (exit 1) when the 95th percentile is
larger: the largest residuals are the feet of the few rocks on a drift's floor (their vertices
are shared with floor triangles), which stand up by decimetres whatever the walls.

Wall relief that reaches the floor (through the lattice's interpolation between a point on the
floor and one above it) shows here as steps of centimetres from one lattice cell to the next.
"""

import argparse
import json
import sys

import numpy as np

from wall_relief_check import buckets, read_obj, straight_cells


def measure(world, half_width):
    topology = json.load(open(f"{world}/topology.json"))
    verts, groups = read_obj(f"{world}/mesh/world.obj")
    floor = next(n for n in groups if n.endswith("-floor"))
    by_cell = buckets(verts[np.unique(groups[floor])], topology)
    pitch = topology["tile_pitch_m"]
    rows = topology["rows"]
    residuals = []
    worst = (0.0, None)
    cells = 0
    for cell, axis in straight_cells(topology):
        k = cell["level"] * 1_000_000 + cell["row"] * 1000 + cell["col"]
        if k not in by_cell:
            continue
        v = by_cell[k]
        centre = np.array([cell["col"] * pitch, (rows - 1 - cell["row"]) * pitch])
        along = v[:, axis] - centre[axis]
        across = v[:, 1 - axis] - centre[1 - axis]
        # Clear of the walls and of the cell's ends (where a bend or junction may begin).
        m = (np.abs(across) < half_width) & (np.abs(along) < 0.4 * pitch)
        if m.sum() < 20:
            continue
        s, t, z = along[m], across[m], v[m, 2]
        a = np.c_[np.ones(m.sum()), s, s * s, t, s * t]
        coef, *_ = np.linalg.lstsq(a, z, rcond=None)
        r = z - a @ coef
        residuals.append(r)
        cells += 1
        i = int(np.argmax(np.abs(r)))
        if abs(r[i]) > worst[0]:
            worst = (abs(float(r[i])), v[m][i].tolist())
    if not residuals:
        raise SystemExit(f"{world}: no straight passage floors found")
    r = 100.0 * np.abs(np.concatenate(residuals))
    return {
        "floor_median_cm": float(np.median(r)),
        "floor_p95_cm": float(np.percentile(r, 95)),
        "floor_max_cm": float(r.max()),
        "worst_at": worst[1],
        "cells": cells,
        "vertices": int(r.size),
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("world")
    ap.add_argument("--half-width", type=float, default=2.0)
    ap.add_argument("--max-cm", type=float)
    args = ap.parse_args()
    out = measure(args.world, args.half_width)
    print(json.dumps(out))
    if args.max_cm is not None and out["floor_p95_cm"] > args.max_cm:
        print(
            f"FAIL: 5 % of the floor departs {out['floor_p95_cm']:.1f} cm or more from a smooth "
            f"floor (more than {args.max_cm} cm; the most, {out['floor_max_cm']:.1f} cm, at "
            f"{out['worst_at']})",
            file=sys.stderr,
        )
        sys.exit(1)


if __name__ == "__main__":
    main()
