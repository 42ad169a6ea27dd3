"""The collision budget of a world folder, measured apart from subtgraph's code: how far the
visual surface (mesh/world.obj) lies from the collision surface (mesh/collision.obj), per class
of surface, by trimesh.

Points are drawn uniformly by area on world.obj (numpy's generator, `--seed`), and each one's
distance to the nearest point of collision.obj is trimesh's closest point
(`trimesh.proximity.closest_point`). Each point is classed by the normal of the visual
triangle it lies on (as wound: into the passage):

- `floor` faces up (its normal within 45 degrees of up), `roof` faces down (within 45 degrees
  of down), `walls` the rest;
- `floor_by_routes`: floor points within 1 m (3D) of a corridor or shaft polyline of
  ground_truth/graph.json (the floors a robot drives on);
- `elsewhere`: every point that is not `floor_by_routes`.

Prints one JSON object: per class the count and the median, 90th and 99th percentile and
largest distance, metres. With `--budget`, also compares the tool's own
ground_truth/collision_budget.json against these numbers (each class's median, p90 and p99
within `--tolerance` metres or 25 %, whichever is larger: two independent samples of a
distribution), and with `--hold FLOOR,ELSEWHERE` checks the p99 of `floor_by_routes` and
`elsewhere` against those bounds (metres). Exits non-zero naming the first failure.

With `--parts`, also the same numbers over two parts of the surface the budget's classes cut
across (issue 39 asks where they stand): `rock_pile`, the points on triangles of a `rock-pile`
material (the cave's rubble and rock piles, painted so), and `squeeze`, the points inside tiles
that ground_truth/semantic_labels.json gives the `squeeze` feature (within half a tile pitch
across, half a level height up or down, of the tile's position); each split into its floors by
the routes and the rest.

Usage: collision_budget_check.py WORLD [--samples N] [--seed S] [--budget] [--tolerance M]
                                       [--hold 0.03,0.15] [--parts]
"""
import argparse
import json
import sys
from pathlib import Path

import numpy as np
import trimesh
from obj_reader import read_obj
from scipy.spatial import cKDTree

CLASSES = ["floor_by_routes", "floor", "walls", "roof", "elsewhere"]
#: The normal's z beyond which a triangle faces up (floor) or down (roof): 45 degrees.
FACING = np.sqrt(0.5)
#: Metres from a route's polyline within which a floor is one a robot drives on.
REACH = 1.0


def fail(msg):
    print(f"collision_budget_check: {msg}", file=sys.stderr)
    sys.exit(1)


def sample(vertices, triangles, count, rng):
    """`count` points uniform by area on the triangles, and the triangle each lies on."""
    corners = vertices[triangles]
    area = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]), axis=1)
    face = rng.choice(len(triangles), size=count, p=area / area.sum())
    r1, r2 = rng.random(count), rng.random(count)
    flip = r1 + r2 > 1.0
    r1[flip], r2[flip] = 1.0 - r1[flip], 1.0 - r2[flip]
    a, b, c = corners[face, 0], corners[face, 1], corners[face, 2]
    points = a + r1[:, None] * (b - a) + r2[:, None] * (c - a)
    return points, face, float(area.sum())


def route_points(world):
    """The graph's polylines densified to points at most 0.1 m apart."""
    graph = json.loads((world / "ground_truth" / "graph.json").read_text())
    out = []
    for e in graph["edges"]:
        line = np.asarray(e["polyline"], dtype=float)
        for p, q in zip(line[:-1], line[1:]):
            n = max(1, int(np.ceil(np.linalg.norm(q - p) / 0.1)))
            t = np.arange(n)[:, None] / n
            out.append(p + t * (q - p))
        out.append(line[-1:])
    return np.vstack(out)


def squeeze_mask(world, points):
    """Which points lie in a tile with the `squeeze` feature."""
    labels = json.loads((world / "ground_truth" / "semantic_labels.json").read_text())
    pitch, lh = float(labels["tile_pitch_m"]), float(labels["level_height_m"])
    mask = np.zeros(len(points), bool)
    for t in labels["tiles"]:
        if "squeeze" not in t.get("features", []):
            continue
        c = np.asarray(t["position"], dtype=float)
        d = np.abs(points - c)
        mask |= (d[:, 0] <= pitch / 2) & (d[:, 1] <= pitch / 2) & (d[:, 2] <= lh / 2)
    return mask


def stats(d):
    if len(d) == 0:
        return {"count": 0}
    q = np.quantile(d, [0.5, 0.9, 0.99])
    return {"count": int(len(d)), "median_m": float(q[0]), "p90_m": float(q[1]),
            "p99_m": float(q[2]), "max_m": float(d.max())}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("world")
    ap.add_argument("--samples", type=int, default=200_000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--budget", action="store_true")
    ap.add_argument("--tolerance", type=float, default=0.005)
    ap.add_argument("--hold", default=None)
    ap.add_argument("--parts", action="store_true")
    args = ap.parse_args()
    world = Path(args.world)

    visual = read_obj(world / "mesh" / "world.obj")
    collision = read_obj(world / "mesh" / "collision.obj")
    rng = np.random.default_rng(args.seed)
    points, face, area = sample(visual.vertices, visual.triangles, args.samples, rng)
    corners = visual.vertices[visual.triangles[face]]
    normal = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-30)

    mesh = trimesh.Trimesh(collision.vertices, collision.triangles, process=False)
    _, distance, _ = trimesh.proximity.closest_point(mesh, points)

    floor = normal[:, 2] >= FACING
    roof = normal[:, 2] <= -FACING
    walls = ~(floor | roof)
    near, _ = cKDTree(route_points(world)).query(points, distance_upper_bound=REACH)
    by_routes = floor & np.isfinite(near)
    masks = {"floor_by_routes": by_routes, "floor": floor, "walls": walls, "roof": roof,
             "elsewhere": ~by_routes}
    out = {"world": str(world), "samples": args.samples, "seed": args.seed,
           "visual_area_m2": area, "visual_triangles": int(len(visual.triangles)),
           "collision_triangles": int(len(collision.triangles)),
           "classes": {k: stats(distance[m]) for k, m in masks.items()}}

    if args.parts:
        material = visual.material[face]
        piles = np.array(["rock-pile" in (m or "") for m in visual.materials] + [False])
        on_pile = piles[material]
        in_squeeze = squeeze_mask(world, points)
        out["parts"] = {}
        for name, m in [("rock_pile", on_pile), ("squeeze", in_squeeze)]:
            out["parts"][name] = {"all": stats(distance[m]),
                                  "floor_by_routes": stats(distance[m & by_routes]),
                                  "elsewhere": stats(distance[m & ~by_routes])}

    if args.budget:
        path = world / "ground_truth" / "collision_budget.json"
        ours = json.loads(path.read_text())
        compared = {}
        for k in CLASSES:
            mine = ours["classes"].get(k)
            theirs = out["classes"][k]
            if theirs["count"] < 200:
                continue
            if mine is None or mine.get("count", 0) == 0:
                fail(f"{path} has no {k} class but trimesh finds {theirs['count']} points there")
            for q in ["median_m", "p90_m", "p99_m"]:
                a, b = mine[q], theirs[q]
                allowed = max(args.tolerance, 0.25 * b)
                compared[f"{k}.{q}"] = [a, b]
                if abs(a - b) > allowed:
                    fail(f"{k} {q}: collision_budget.json says {a:.4f} m, trimesh measures {b:.4f} m "
                         f"(allowed {allowed:.4f} m)")
        out["compared"] = compared

    if args.hold:
        floor_p99, elsewhere_p99 = (float(x) for x in args.hold.split(","))
        got = out["classes"]
        if got["floor_by_routes"].get("p99_m", 0.0) > floor_p99:
            fail(f"floors by the routes: p99 {got['floor_by_routes']['p99_m']:.4f} m > {floor_p99} m")
        if got["elsewhere"].get("p99_m", 0.0) > elsewhere_p99:
            fail(f"everything else: p99 {got['elsewhere']['p99_m']:.4f} m > {elsewhere_p99} m")
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
