"""Opens a world's usd/world.usda with usd-core (the USD library Isaac Sim is built on) and
checks what a simulator (Isaac Sim) relies on: Z up, metres and kilograms stated, one
PhysicsScene, physics materials with friction and restitution, every collider (every guide
mesh) with PhysicsCollisionAPI, PhysicsMeshCollisionAPI approximation "none" and a bound
physics material, no rigid body, every instance's prototype resolving to meshes reached
through instance proxies, valid topology, per-vertex normals and st, materials on every face;
prints a JSON summary.

usage: usd_check.py WORLD_FOLDER [--parts DIR] [--min-instances N]
  --parts DIR         compare each part's visual mesh with DIR/<part>.obj (points and faces)
  --min-instances N   require at least N instanceable prims
"""
import json
import sys
from pathlib import Path

import numpy as np
from obj_reader import read_obj
from pxr import Usd, UsdGeom, UsdPhysics, UsdShade


def obj_counts(path):
    obj = read_obj(path)
    return len(obj.vertices), sum(obj.faces.values())


def fail(msg):
    print(f"FAIL: {msg}")
    sys.exit(1)


def main():
    folder = Path(sys.argv[1])
    args = sys.argv[2:]
    parts_dir = Path(args[args.index("--parts") + 1]) if "--parts" in args else None
    min_instances = int(args[args.index("--min-instances") + 1]) if "--min-instances" in args else 0

    stage = Usd.Stage.Open(str(folder / "usd" / "world.usda"))
    if stage is None:
        fail("Usd.Stage.Open returned nothing")
    if UsdGeom.GetStageUpAxis(stage) != UsdGeom.Tokens.z:
        fail(f"upAxis {UsdGeom.GetStageUpAxis(stage)}")
    if UsdGeom.GetStageMetersPerUnit(stage) != 1.0:
        fail(f"metersPerUnit {UsdGeom.GetStageMetersPerUnit(stage)}")
    if not UsdPhysics.StageHasAuthoredKilogramsPerUnit(stage) or UsdPhysics.GetStageKilogramsPerUnit(stage) != 1.0:
        fail("kilogramsPerUnit is not stated as 1")
    if not stage.GetDefaultPrim() or stage.GetDefaultPrim().GetPath() != "/World":
        fail("defaultPrim is not /World")
    scenes = [p for p in stage.Traverse() if p.IsA(UsdPhysics.Scene)]
    if len(scenes) != 1:
        fail(f"{len(scenes)} physics scenes")
    physics_materials = [p for p in stage.Traverse() if p.HasAPI(UsdPhysics.MaterialAPI)]
    if not physics_materials:
        fail("no physics material (PhysicsMaterialAPI)")
    for m in physics_materials:
        api = UsdPhysics.MaterialAPI(m)
        for attr in (api.GetStaticFrictionAttr(), api.GetDynamicFrictionAttr(), api.GetRestitutionAttr()):
            if attr.Get() is None:
                fail(f"{m.GetPath()}: {attr.GetName()} is not set")

    visual_faces = collision_faces = instances = colliders = proxies = 0
    visual = {}
    for prim in Usd.PrimRange(stage.GetPseudoRoot(), Usd.TraverseInstanceProxies()):
        if prim.IsInstance():
            instances += 1
            prototype = prim.GetPrototype()
            if not prototype or not any(p.IsA(UsdGeom.Mesh) for p in Usd.PrimRange(prototype)):
                fail(f"{prim.GetPath()}: its prototype does not resolve to a mesh")
        if prim.IsInstanceProxy() and prim.IsA(UsdGeom.Mesh):
            proxies += 1
        if prim.HasAPI(UsdPhysics.RigidBodyAPI):
            fail(f"{prim.GetPath()} is a rigid body; the cave is static")
        if not prim.IsA(UsdGeom.Mesh):
            continue
        mesh = UsdGeom.Mesh(prim)
        points = mesh.GetPointsAttr().Get()
        counts = mesh.GetFaceVertexCountsAttr().Get()
        indices = mesh.GetFaceVertexIndicesAttr().Get()
        ok, why = UsdGeom.Mesh.ValidateTopology(indices, counts, len(points))
        if not ok:
            fail(f"{prim.GetPath()}: {why}")
        purpose = UsdGeom.Imageable(prim).ComputePurpose()
        if (purpose == UsdGeom.Tokens.guide or prim.GetName() == "collision") and not prim.HasAPI(UsdPhysics.CollisionAPI):
            fail(f"{prim.GetPath()} looks like a collider but lacks PhysicsCollisionAPI")
        if prim.HasAPI(UsdPhysics.CollisionAPI):
            colliders += 1
            bound, _ = UsdShade.MaterialBindingAPI(prim).ComputeBoundMaterial("physics")
            if not bound or not bound.GetPrim().HasAPI(UsdPhysics.MaterialAPI):
                fail(f"{prim.GetPath()}: no physics material bound (purpose physics)")
            collision_faces += len(counts)
            if not prim.HasAPI(UsdPhysics.MeshCollisionAPI):
                fail(f"{prim.GetPath()} lacks PhysicsMeshCollisionAPI")
            approx = UsdPhysics.MeshCollisionAPI(prim).GetApproximationAttr().Get()
            if approx != "none":
                fail(f"{prim.GetPath()} approximation {approx}, not none")
            if UsdGeom.Imageable(prim).ComputePurpose() != UsdGeom.Tokens.guide:
                fail(f"{prim.GetPath()}: the collider would be rendered")
            continue
        visual_faces += len(counts)
        if len(mesh.GetNormalsAttr().Get()) != len(points) or mesh.GetNormalsInterpolation() != "vertex":
            fail(f"{prim.GetPath()}: normals are not per vertex")
        st = UsdGeom.PrimvarsAPI(prim).GetPrimvar("st")
        if len(st.Get()) != len(points) or st.GetInterpolation() != "vertex":
            fail(f"{prim.GetPath()}: st is not per vertex")
        lo, hi = (np.array(e) for e in mesh.GetExtentAttr().Get())
        pts = np.asarray(points)
        if (pts < lo - 1e-3).any() or (pts > hi + 1e-3).any():
            fail(f"{prim.GetPath()}: points outside the extent {lo} {hi}")
        # Every face's material resolves to a UsdPreviewSurface.
        subsets = UsdShade.MaterialBindingAPI(prim).GetMaterialBindSubsets()
        targets = subsets if subsets else [prim]
        if subsets:
            ok, why = UsdGeom.Subset.ValidateFamily(mesh, UsdGeom.Tokens.face, "materialBind")
            if not ok:
                fail(f"{prim.GetPath()}: {why}")
            if sum(len(s.GetIndicesAttr().Get()) for s in subsets) != len(counts):
                fail(f"{prim.GetPath()}: subsets do not cover every face")
        for t in targets:
            target = t.GetPrim() if hasattr(t, "GetPrim") else t
            material, _ = UsdShade.MaterialBindingAPI(target).ComputeBoundMaterial()
            if not material:
                fail(f"{target.GetPath()}: no bound material")
            shader = material.ComputeSurfaceSource()[0]
            if not shader or shader.GetIdAttr().Get() != "UsdPreviewSurface":
                fail(f"{material.GetPath()}: no UsdPreviewSurface")
        if not prim.IsInstanceProxy() and prim.GetName() == "visual":
            visual[prim.GetParent().GetName()] = (len(points), len(counts))

    _, world_faces = obj_counts(folder / "mesh" / "world.obj")
    _, collision_obj_faces = obj_counts(folder / "mesh" / "collision.obj")
    if visual_faces != world_faces:
        fail(f"{visual_faces} visual faces in USD, {world_faces} in world.obj")
    if collision_faces != collision_obj_faces:
        fail(f"{collision_faces} collision faces in USD, {collision_obj_faces} in collision.obj")
    if parts_dir is not None:
        objs = sorted(p for p in parts_dir.glob("*.obj") if not p.stem.endswith("-collision"))
        if len(objs) != len(visual):
            fail(f"{len(objs)} part OBJs, {len(visual)} part meshes: {sorted(visual)}")
        for o in objs:
            name = o.stem.replace("-", "_")
            if visual.get(name) != obj_counts(o):
                fail(f"{name}: USD {visual.get(name)} (points, faces), OBJ {obj_counts(o)}")
    if instances < min_instances:
        fail(f"{instances} instances, expected at least {min_instances}")
    if instances and proxies < instances:
        fail(f"{instances} instances but {proxies} meshes reached through instance proxies")
    print(json.dumps({
        "visual_faces": visual_faces,
        "collision_faces": collision_faces,
        "colliders": colliders,
        "instances": instances,
        "instance_proxy_meshes": proxies,
        "physics_materials": len(physics_materials),
        "parts": len(visual),
    }))


main()
