"""Measures a world's ramps (declines) from its files alone, and checks their grade.

Usage: decline_check.py WORLD_FOLDER MAX_GRADE_DEGREES

For every edge of kind "ramp" in ground_truth/graph.json (its polyline runs along the
spiral's floor from the foot's node to the landing's), with its spiral block from
topology.json (the foot cell and the cell `block` beside it diagonally; the spiral turns round
the block's centre):
- the centreline, resampled every metre, never climbs steeper than MAX_GRADE (+0.05 degree);
- the exported visual mesh's floor (mesh/world.obj, read with trimesh; a ray cast down from
  1 m above each resampled point) is within 0.15 m of the centreline all along the climb,
  and its grade between floor points 2 m apart is within MAX_GRADE + 0.5 degree (the lattice's
  interpolation);
and prints one JSON line per ramp: its radius about the block's centre and its grade over the
steady climb (20 % to 80 % of its rise), least and greatest, and the mesh floor's steepest.
Exits non-zero with a line starting FAIL on the first failure.
"""
import json
import math
import os
import sys

import numpy as np
import trimesh


def resample(line, step):
    line = np.asarray(line, dtype=float)
    d = np.r_[0, np.cumsum(np.linalg.norm(np.diff(line[:, :2], axis=0), axis=1))]
    s = np.arange(0, d[-1], step)
    return np.stack([np.interp(s, d, line[:, k]) for k in range(3)], axis=1)


def grades(points):
    run = np.linalg.norm(np.diff(points[:, :2], axis=0), axis=1)
    return np.degrees(np.arctan2(np.diff(points[:, 2]), run))


def main():
    folder, most = sys.argv[1], float(sys.argv[2])
    graph = json.load(open(os.path.join(folder, "ground_truth", "graph.json")))
    topo = json.load(open(os.path.join(folder, "topology.json")))
    pitch, rows = topo["tile_pitch_m"], topo["rows"]
    mesh = trimesh.load(os.path.join(folder, "mesh", "world.obj"), force="mesh", process=False)
    nodes = {n["id"]: n for n in graph["nodes"]}
    ramps = [e for e in graph["edges"] if e["kind"] == "ramp"]
    if not ramps:
        sys.exit("FAIL: the world has no ramp")
    for e in ramps:
        foot = nodes[e["from"]]
        shaft = next(s for s in topo["shafts"]
                     if (s["up"]["level"], s["up"]["row"], s["up"]["col"])
                     == (foot["level"], foot["row"], foot["col"]))
        dr, dc = shaft["block"]
        up = shaft["up"]
        centre = np.array([(up["col"] + 0.5 * dc) * pitch,
                           (rows - 1 - up["row"] - 0.5 * dr) * pitch])
        line = resample(e["polyline"], 1.0)
        g = grades(line)
        if g.max() > most + 0.05:
            sys.exit(f"FAIL: ramp {e['id']}: its centreline climbs at {g.max():.2f} degrees, "
                     f"beyond {most}")
        z = line[:, 2]
        rise = z[-1] - z[0]
        steady = line[(z > z[0] + 0.2 * rise) & (z < z[0] + 0.8 * rise)]
        radius = np.linalg.norm(steady[:, :2] - centre, axis=1)
        sg = grades(steady)
        # The floor under the climb, from the mesh near the block only.
        near = np.linalg.norm(mesh.triangles_center[:, :2] - centre, axis=1) < pitch
        block = mesh.submesh([np.nonzero(near)[0]], append=True)
        climb = line[(z > z[0] + 0.05 * rise) & (z < z[0] + 0.95 * rise)]
        origins = climb + [0.0, 0.0, 1.0]
        hits, rays, _ = block.ray.intersects_location(
            origins, np.tile([0.0, 0.0, -1.0], (len(origins), 1)))
        floor = np.full(len(origins), -np.inf)
        for h, r in zip(hits, rays):
            if h[2] <= origins[r][2]:
                floor[r] = max(floor[r], h[2])
        off = np.abs(floor - climb[:, 2])
        if not np.all(off < 0.15):
            k = int(np.argmax(off))
            sys.exit(f"FAIL: ramp {e['id']}: the mesh's floor under {climb[k].tolist()} is "
                     f"at {floor[k]:.3f}, not on the centreline")
        on_floor = np.c_[climb[:, :2], floor][::2]
        fg = grades(on_floor)
        if fg.max() > most + 0.5:
            sys.exit(f"FAIL: ramp {e['id']}: the mesh's floor climbs at {fg.max():.2f} degrees")
        print(json.dumps({
            "id": e["id"],
            "radius": [float(radius.min()), float(radius.max())],
            "grade": [float(sg.min()), float(sg.max())],
            "centreline_steepest": float(g.max()),
            "floor_steepest": float(fg.max()),
            "floor_off": float(off.max()),
        }))
    print(f"OK: {len(ramps)} ramp(s) within {most} degrees")


main()
