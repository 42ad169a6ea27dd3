"""Finds a mine's services (rock bolts, duct, pipes, cable, lights) in a world folder, apart
from subtgraph's code: the baked copies in mesh/services.obj (trimesh: one closed part per
copy, counted by material), the instances in mesh/world.glb (trimesh's scene graph: nodes per
mesh) and in usd/ (usd-core: the PointInstancer's prototypes and protoIndices), and checks:

- the three formats hold the same copies of each part, and the GLB and USD store each part's
  mesh once (a handful of prototypes, not one mesh per bolt);
- every bolt plate (its USD position: where the plate meets the rock) lies within 5 cm of the
  rock of mesh/world.obj (trimesh's closest point);
- the duct hangs below the back: a ray up from a duct's top meets the rock above it, and
  one down from its bottom the floor at least 1.7 m below (trimesh's ray caster, on
  world.obj);
- the semantic labels name the services on the tiles that carry them.

Usage: services_check.py WORLD [--sample N]. Prints a JSON summary; exits non-zero naming the
first failure.
"""
import json
import re
import sys
from collections import Counter
from pathlib import Path

import numpy as np
from obj_reader import read_obj
import trimesh
from pxr import Usd, UsdGeom

NAMES = ["rock-bolt", "duct", "pipe", "cable", "light"]
MATERIALS = {"mine-bolt": "rock-bolt", "mine-duct": "duct", "mine-pipe": "pipe",
             "mine-cable": "cable", "mine-light": "light"}


def fail(msg):
    print(f"services_check: {msg}", file=sys.stderr)
    sys.exit(1)


def obj_faces_by_material(path):
    """Faces per `usemtl` group of an OBJ."""
    return Counter(read_obj(path).faces)


def near(mesh, centroids, points, radius, xy=False):
    """The part of `mesh` whose triangles' centres lie within `radius` of a point (in the
    plane with `xy`): ray and distance queries on a few thousand triangles, not millions."""
    from scipy.spatial import cKDTree
    k = 2 if xy else 3
    tree = cKDTree(centroids[:, :k])
    keep = sorted({i for hits in tree.query_ball_point(points[:, :k], radius) for i in hits})
    return mesh.submesh([keep], append=True)


def quat_rotate(q, v):
    """Rotates v by the unit quaternion q = (real, i, j, k)."""
    w, x, y, z = q
    u = np.array([x, y, z])
    return v + 2.0 * np.cross(u, np.cross(u, v) + w * v)


def main():
    world = Path(sys.argv[1])
    sample = int(sys.argv[sys.argv.index("--sample") + 1]) if "--sample" in sys.argv else 300

    # --- USD: the PointInstancer -------------------------------------------------------
    stage = Usd.Stage.Open(str(world / "usd" / "world.usda"))
    prim = stage.GetPrimAtPath("/World/Services")
    if not prim or not prim.IsA(UsdGeom.PointInstancer):
        fail("no PointInstancer at /World/Services in usd/world.usda")
    inst = UsdGeom.PointInstancer(prim)
    targets = inst.GetPrototypesRel().GetTargets()
    protos = [t.name.replace("_", "-") for t in targets]
    idx = np.array(inst.GetProtoIndicesAttr().Get())
    pos = np.array(inst.GetPositionsAttr().Get(), dtype=float)
    ori = inst.GetOrientationsAttr().Get()
    ori = np.array([[q.GetReal(), *q.GetImaginary()] for q in ori], dtype=float)
    scales = np.array(inst.GetScalesAttr().Get(), dtype=float)
    if not (len(idx) == len(pos) == len(ori) == len(scales)):
        fail("the PointInstancer's arrays differ in length")
    usd_counts = {protos[k]: int((idx == k).sum()) for k in range(len(protos))}
    usd_faces = {}
    for t in targets:
        mesh = UsdGeom.Mesh(stage.GetPrimAtPath(t))
        usd_faces[t.name.replace("_", "-")] = len(mesh.GetFaceVertexCountsAttr().Get())

    # --- OBJ: the baked copies -------------------------------------------------------------
    faces = obj_faces_by_material(world / "mesh" / "services.obj")
    obj_counts = {}
    for material, n in faces.items():
        name = MATERIALS.get(material)
        if name is None:
            fail(f"services.obj has material {material}")
        if n % usd_faces[name]:
            fail(f"{n} faces of {material}: not whole copies of {usd_faces[name]}")
        obj_counts[name] = n // usd_faces[name]
    baked = trimesh.load(world / "mesh" / "services.obj", force="mesh", process=False)
    baked.merge_vertices()
    # Every copy closed: every edge of the baked mesh has two faces, wound opposite ways.
    if not baked.is_watertight or not baked.is_winding_consistent:
        fail("services.obj is not made of closed parts")
    copies = sum(obj_counts.values())
    if copies != len(idx):
        fail(f"services.obj: {copies} copies, {len(idx)} instances in USD")

    # --- GLB: nodes sharing a mesh ---------------------------------------------------------
    scene = trimesh.load(world / "mesh" / "world.glb", force="scene", process=False)
    glb_counts, glb_meshes = Counter(), set()
    for node in scene.graph.nodes_geometry:
        _, geometry = scene.graph[node]
        name = re.sub(r"(_\d+)+$", "", node)
        if name in NAMES:
            glb_counts[name] += 1
            glb_meshes.add(geometry)
    if dict(glb_counts) != usd_counts or obj_counts != usd_counts:
        fail(f"copies differ: OBJ {obj_counts}, GLB {dict(glb_counts)}, USD {usd_counts}")

    # --- geometry against the rock of world.obj ---------------------------------------------
    rock = trimesh.load(world / "mesh" / "world.obj", force="mesh", process=False)
    centroids = rock.triangles_center
    rng = np.random.default_rng(0)
    bolts = np.flatnonzero(idx == protos.index("rock-bolt"))
    picked = rng.choice(bolts, size=min(sample, len(bolts)), replace=False)
    _, dist, _ = trimesh.proximity.closest_point(near(rock, centroids, pos[picked], 3), pos[picked])
    if dist.max() > 0.05:
        fail(f"a bolt plate {dist.max():.3f} m from the rock")
    # Plates face out of the rock: their +z axis points into the passage (toward the axis).
    ducts = np.flatnonzero(idx == protos.index("duct"))
    picked = rng.choice(ducts, size=min(sample, len(ducts)), replace=False)
    centres, radii = [], []
    for i in picked:
        x = quat_rotate(ori[i], np.array([1.0, 0.0, 0.0]))
        centres.append(pos[i] + 0.5 * scales[i][0] * x)
        radii.append(max(scales[i][1], scales[i][2]))
    centres, radii = np.array(centres), np.array(radii)
    up = np.tile([0.0, 0.0, 1.0], (len(centres), 1))
    rock = near(rock, centroids, centres, 2, xy=True)
    above = centres + up * (radii[:, None] + 0.01)
    locs, rays, _ = rock.ray.intersects_location(above, up, multiple_hits=False)
    if len(set(rays.tolist())) != len(centres):
        fail("a ray up from a duct's top meets no rock: the duct pokes through the back")
    below = centres - up * (radii[:, None] + 0.01)
    locs, rays, _ = rock.ray.intersects_location(below, -up, multiple_hits=False)
    clearance = np.full(len(centres), np.inf)
    clearance[rays] = below[rays, 2] - locs[:, 2]
    if clearance.min() < 1.7:
        fail(f"a duct's bottom {clearance.min():.2f} m above the floor")
    gap = []
    locs, rays, _ = rock.ray.intersects_location(above, up, multiple_hits=False)
    gap = locs[:, 2] - above[rays, 2]

    # --- labels --------------------------------------------------------------------------
    labels = json.loads((world / "ground_truth" / "semantic_labels.json").read_text())
    labelled = Counter(f for t in labels["tiles"] for f in t.get("features", []) if f in NAMES)
    for name, n in usd_counts.items():
        if n and not labelled[name]:
            fail(f"no tile labelled {name}")

    print(json.dumps({
        "prototypes": len(protos),
        "glb_meshes": len(glb_meshes),
        "instances": usd_counts,
        "copies": copies,
        "bolt_rock_distance_max_m": round(float(dist.max()), 4),
        "duct_floor_clearance_min_m": round(float(clearance.min()), 3),
        "duct_back_gap_min_m": round(float(gap.min()), 3),
        "labelled_tiles": dict(labelled),
    }))


if __name__ == "__main__":
    main()
