"""Refuge bays of a mine, found in its exported OBJ apart from the tile sets' code, and
compared with the cells its semantic labels say have one.

    python refuge_bay_check.py WORLD

For every straight cell of the topology, the wall vertices 1.0-2.5 m above the floor (fitted as wall_relief_check.py does) are split
into the middle of the cell (within 1 m of its centre along the passage) and its ends (more
than 5 m from it). A side of the cell has a recess when its middle reaches more than 1.5 m
further from the passage's axis than its ends do (the median distance of the ends' vertices).
Prints JSON: the cells with a recess, the cells labelled `refuge-bay`, and how many straight
cells were looked at; exits 1 when the two sets differ.
"""

import json
import sys

import numpy as np

from wall_relief_check import (
    buckets,
    floor_fit,
    labelled,
    read_obj,
    straight_cells,
    wall_vertices,
)


def main():
    world = sys.argv[1]
    topology = json.load(open(f"{world}/topology.json"))
    verts, groups = read_obj(f"{world}/mesh/world.obj")
    walls_by = buckets(verts[wall_vertices(groups)], topology)
    all_by = buckets(verts, topology)
    pitch = topology["tile_pitch_m"]
    rows = topology["rows"]
    found = set()
    looked = 0
    for cell, axis in straight_cells(topology):
        at = (cell["level"], cell["row"], cell["col"])
        k = at[0] * 1_000_000 + at[1] * 1000 + at[2]
        if k not in walls_by:
            continue
        looked += 1
        w = walls_by[k]
        centre = np.array([cell["col"] * pitch, (rows - 1 - cell["row"]) * pitch])
        along = w[:, axis] - centre[axis]
        across = w[:, 1 - axis] - centre[1 - axis]
        z = w[:, 2] - floor_fit(all_by[k], axis, centre)(along)
        band = (z > 1.0) & (z < 2.5)
        for side in (across < 0, across > 0):
            ends = band & side & (np.abs(along) > 5.0) & (np.abs(along) < 0.5 * pitch)
            middle = band & side & (np.abs(along) < 1.0)
            if ends.sum() < 5 or middle.sum() < 1:
                continue
            if np.abs(across[middle]).max() > np.median(np.abs(across[ends])) + 1.5:
                found.add(at)
    bays = labelled(world, "refuge-bay")
    out = {
        "recesses": sorted(found),
        "labelled": sorted(bays),
        "straight_cells": looked,
    }
    print(json.dumps(out))
    if found != bays:
        print(
            f"recesses without a label: {sorted(found - bays)}; labels without a recess: "
            f"{sorted(bays - found)}",
            file=sys.stderr,
        )
        sys.exit(1)


if __name__ == "__main__":
    main()
