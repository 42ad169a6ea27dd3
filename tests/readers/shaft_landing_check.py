"""Checks that a vertical shaft's landing stands on the shaft's axis, and that the straight
line from the foot's node to the landing's stays inside the shaft with clearance.

Usage: shaft_landing_check.py WORLD_FOLDER CLEARANCE_M

For every edge of kind "shaft" in ground_truth/graph.json (from the foot's node F to the
landing's node L; the shaft is sunk round the foot cell's centre, from topology.json's grid):
- L is within 0.05 m (horizontally) of the axis;
- the segment from 1.5 m above F to L, sampled every 0.2 m, is at least CLEARANCE_M from the
  exported collision mesh (mesh/collision.obj, read with trimesh: its closest points), and a
  ray up the axis from 1.5 m above F meets no rock below L's height (so the segment is in the
  shaft, not in rock clear of the surface).
Prints one JSON line per shaft (landing offset, least clearance) and exits non-zero with a line
starting FAIL on the first failure.
"""
import json
import os
import sys

import numpy as np
import trimesh


def main():
    folder, clearance = sys.argv[1], float(sys.argv[2])
    graph = json.load(open(os.path.join(folder, "ground_truth", "graph.json")))
    topo = json.load(open(os.path.join(folder, "topology.json")))
    pitch, rows = topo["tile_pitch_m"], topo["rows"]
    mesh = trimesh.load(os.path.join(folder, "mesh", "collision.obj"), force="mesh",
                        process=False)
    nodes = {n["id"]: n for n in graph["nodes"]}
    shafts = [e for e in graph["edges"] if e["kind"] == "shaft"]
    if not shafts:
        sys.exit("FAIL: the world has no shaft")
    for e in shafts:
        foot, landing = nodes[e["from"]], nodes[e["to"]]
        axis = np.array([foot["col"] * pitch, (rows - 1 - foot["row"]) * pitch])
        f, l = np.array(foot["position"]), np.array(landing["position"])
        off = float(np.linalg.norm(l[:2] - axis))
        if off > 0.05:
            sys.exit(f"FAIL: shaft {e['id']}: the landing {l.tolist()} is {off:.2f} m from the "
                     f"axis {axis.tolist()}")
        near = np.linalg.norm(mesh.triangles_center[:, :2] - axis, axis=1) < pitch
        local = mesh.submesh([np.nonzero(near)[0]], append=True)
        start = f + [0.0, 0.0, 1.5]
        n = int(np.ceil(np.linalg.norm(l - start) / 0.2))
        points = start + np.linspace(0.0, 1.0, n + 1)[:, None] * (l - start)
        _, distance, _ = trimesh.proximity.closest_point(local, points)
        least = float(distance.min())
        if least < clearance:
            k = int(np.argmin(distance))
            sys.exit(f"FAIL: shaft {e['id']}: {points[k].tolist()} on the line from the foot "
                     f"{f.tolist()} to the landing {l.tolist()} is {distance[k]:.2f} m from rock")
        up = np.array([[axis[0], axis[1], start[2]]])
        hits, _, _ = local.ray.intersects_location(up, np.array([[0.0, 0.0, 1.0]]))
        below = [h for h in hits if h[2] < l[2]]
        if below:
            sys.exit(f"FAIL: shaft {e['id']}: rock across the shaft at {below[0].tolist()}")
        print(json.dumps({"id": e["id"], "landing_off": off, "clearance": least}))
    print(f"OK: {len(shafts)} shaft(s) with their landing on the axis")


main()
