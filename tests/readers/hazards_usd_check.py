"""Reads the floor patches' friction back from a world's USD export with usd-core, and the
SDF's split collision meshes with trimesh, and compares both with ground_truth/hazards.json.

usage: hazards_usd_check.py WORLD_DIR

USD: every collider prim (PhysicsCollisionAPI) is bound, with purpose "physics", to a
UsdPhysics material; its friction is read through UsdPhysics.MaterialAPI. A collider bound to
a patch material must hold only up-facing faces lying in tiles patched with that material;
every patched tile must have such faces; no rock collider may hold an up-facing face in a
patched tile. SDF: each collision OBJ named in gazebo/world.sdf "...-collision-<material>.obj"
is read with trimesh and must hold only up-facing faces of that material's tiles.
Prints a line per material; exits non-zero on a disagreement.
"""
import json
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import trimesh
from pxr import Usd, UsdGeom, UsdPhysics, UsdShade

world = Path(sys.argv[1])
doc = json.loads((world / "ground_truth/hazards.json").read_text())
pitch = json.loads((world / "topology.json").read_text())["tile_pitch_m"]
patch = {}
for p in doc["patches"]:
    x0, y0, x1, y1 = p["bounds"]
    patch[(p["cell"]["level"], round((x0 + x1) / 2 / pitch), round((y0 + y1) / 2 / pitch))] = p
assert patch, "no patches in ground_truth/hazards.json"


def faces(points, tris, material):
    """Per face: centroid, and up-facing (normal within 45 degrees of up; faces within 1e-3 of
    45 degrees count as up for a material collider and as not up for the rock: the exporter
    decides from its own points, and the .usda text keeps about seven digits of them, which
    tilts a collision face of a few centimetres by up to a few 1e-4)."""
    a, b, c = points[tris[:, 0]], points[tris[:, 1]], points[tris[:, 2]]
    n = np.cross(b - a, c - a)
    length = np.linalg.norm(n, axis=1)
    slack = 1e-3 * length if material else -1e-3 * length
    up = (length > 0) & (n[:, 2] > np.sqrt(0.5) * length - slack)
    centre = (a + b + c) / 3
    return centre, up


def tile_of(centre, level_of_z):
    return (level_of_z(centre[2]), round(centre[0] / pitch), round(centre[1] / pitch))


def level_of_z(z):
    # The level whose nominal floor (as the patches record it) is nearest to the face.
    return min(floors, key=lambda f: abs(f[0] - z))[1]


floors = sorted({(p["floor_z"], p["cell"]["level"]) for p in doc["patches"]})
stage = Usd.Stage.Open(str(world / "usd/world.usda"))
covered = {}
colliders = 0
for prim in stage.Traverse():
    if not prim.HasAPI(UsdPhysics.CollisionAPI) or not prim.IsA(UsdGeom.Mesh):
        continue
    colliders += 1
    material, _ = UsdShade.MaterialBindingAPI(prim).ComputeBoundMaterial("physics")
    assert material, f"{prim.GetPath()} has no physics material"
    api = UsdPhysics.MaterialAPI(material.GetPrim())
    mu = api.GetDynamicFrictionAttr().Get()
    hazard = material.GetPrim().GetAttribute("subtgraph:hazard")
    name = hazard.Get() if hazard and hazard.HasAuthoredValue() else None
    mesh = UsdGeom.Mesh(prim)
    xf = np.array(UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(0))
    pts = np.array(mesh.GetPointsAttr().Get(), dtype=float)
    pts = pts @ xf[:3, :3] + xf[3, :3]
    tris = np.array(mesh.GetFaceVertexIndicesAttr().Get()).reshape(-1, 3)
    centre, up = faces(pts, tris, name is not None)
    if name is None:
        assert abs(mu - 0.7) < 1e-6, (prim.GetPath(), mu)
        for cen in centre[up]:
            key = tile_of(cen, level_of_z)
            assert key not in patch, f"{prim.GetPath()}: rock floor face in patched tile {key}"
        continue
    assert up.all(), f"{prim.GetPath()}: a {name} collider holds faces that are not floor"
    for cen in centre:
        key = tile_of(cen, level_of_z)
        assert key in patch and patch[key]["material"] == name, (str(prim.GetPath()), key, name)
        assert abs(mu - patch[key]["friction"]) < 1e-6, (str(prim.GetPath()), mu, patch[key])
        covered[key] = name
missing = set(patch) - set(covered)
assert not missing, f"{len(missing)} patched tiles have no collider of their material in USD"

sdf = ET.parse(world / "gazebo/world.sdf")
sdf_covered = set()
for col in sdf.iter("collision"):
    uri = col.find("geometry/mesh/uri")
    if uri is None or "-collision-" not in uri.text:
        continue
    word = uri.text.rsplit("-collision-", 1)[1].removesuffix(".obj")
    m = trimesh.load(world / "gazebo" / uri.text, force="mesh", process=False)
    centre, up = faces(np.asarray(m.vertices, dtype=float), np.asarray(m.faces), word != "rock")
    if word == "rock":
        for cen in centre[up]:
            assert tile_of(cen, level_of_z) not in patch, (uri.text, cen)
        continue
    assert up.all(), uri.text
    for cen in centre:
        key = tile_of(cen, level_of_z)
        assert key in patch and patch[key]["material"] == word, (uri.text, key)
        sdf_covered.add(key)
assert sdf_covered == set(patch), f"SDF covers {len(sdf_covered)} of {len(patch)} patches"

for material in sorted({p["material"] for p in doc["patches"]}):
    n = sum(1 for m in covered.values() if m == material)
    mus = sorted({p["friction"] for p in doc["patches"] if p["material"] == material})
    print(f"{material}: {n} tiles, friction {mus} as usd-core reads it; {colliders} colliders")
