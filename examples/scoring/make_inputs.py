#!/usr/bin/env python3
"""Makes the scoring example's inputs from a world made with `cave.toml`: a team's artifact
reports (`reports.csv`) and the map its robot built (`explored.ply`), written beside this file.

    subtgraph generate examples/scoring/cave.toml --out worlds/scored
    python3 examples/scoring/make_inputs.py worlds/scored

Only the standard library, and the same files on every run. The reports cover every outcome
the DARPA rule knows: most artifacts reported within a few metres, one reported twice, one
under another class, one report where nothing lies, and one artifact never reported. The map
is every third vertex of the collision surface within 20 m of the start's first corridors, as a lidar map
of the part of the cave the robot drove through would be, plus a few points off in the rock
(map errors).
"""

import csv
import json
import math
import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent


def reports(world):
    with open(world / "ground_truth" / "artifacts.csv", newline="") as f:
        artifacts = list(csv.DictReader(f))
    rows = []
    t = 60.0
    # Offsets of 0.5 to 4.5 m: each within the rule's 5 m.
    for i, a in enumerate(artifacts[:-1]):
        d = 0.5 + (i % 5)
        angle = 0.7 * i
        x = float(a["x"]) + d * math.cos(angle)
        y = float(a["y"]) + d * math.sin(angle)
        rows.append((t, a["class"], x, y, float(a["z"]) + 0.3))
        t += 95.0
    first = artifacts[0]
    rows.append((t, first["class"], float(first["x"]) + 1.0, float(first["y"]), float(first["z"])))
    t += 40.0
    second = artifacts[1]
    other = "rope" if second["class"] != "rope" else "helmet"
    rows.append((t, other, float(second["x"]), float(second["y"]) - 1.5, float(second["z"])))
    t += 40.0
    rows.append((t, "survivor", float(first["x"]) + 60.0, float(first["y"]) + 60.0, float(first["z"])))
    with open(HERE / "reports.csv", "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["time", "class", "x", "y", "z"])
        for r in rows:
            w.writerow([f"{r[0]:.1f}", r[1], f"{r[2]:.3f}", f"{r[3]:.3f}", f"{r[4]:.3f}"])


def explored_map(world):
    graph = json.loads((world / "ground_truth" / "graph.json").read_text())
    start = graph["start"]
    route = []
    for e in graph["edges"]:
        if start in (e["from"], e["to"]):
            route.extend(e["polyline"])
    points = []
    with open(world / "mesh" / "collision.obj") as f:
        vertices = (line for line in f if line.startswith("v "))
        for i, line in enumerate(vertices):
            # Every third vertex: the file stays small.
            if i % 3 == 0:
                x, y, z = map(float, line.split()[1:4])
                if any((x - p[0]) ** 2 + (y - p[1]) ** 2 < 400.0 for p in route[::4]):
                    points.append((x, y, z))
    # Map errors: points 3 m below the floor under the first few route points.
    points.extend((p[0], p[1], p[2] - 3.0) for p in route[:20])
    with open(HERE / "explored.ply", "w") as f:
        f.write("ply\nformat ascii 1.0\ncomment the example map of docs/src/scoring.md\n")
        f.write(f"element vertex {len(points)}\n")
        f.write("property float x\nproperty float y\nproperty float z\nend_header\n")
        for p in points:
            f.write(f"{p[0]:.3f} {p[1]:.3f} {p[2]:.3f}\n")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    world = pathlib.Path(sys.argv[1])
    reports(world)
    explored_map(world)


if __name__ == "__main__":
    main()
