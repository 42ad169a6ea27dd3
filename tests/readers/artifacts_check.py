"""Checks a world's artifacts (`[artifacts]`) with the programs that read them.

usage: artifacts_check.py WORLD_DIR placement|mujoco|pybullet|usd|gltf

- placement: ground_truth/artifacts.json and .csv agree; every artifact follows world.toml's
  [artifacts] rules (classes, count, distance from the start, spacing, tile kinds) and, by
  our own numpy ray parity on mesh/collision.obj (independent of the exporter's exact test),
  stands on the floor (under every point of its footprint the floor is at most 0.1 m below its
  base, never above) with its whole box in free space.
- mujoco: mujoco/world.xml has a free body per artifact at its recorded pose with its box; each
  raised 0.5 m and dropped is at rest within 0.3 m of its recorded pose 5 s later; its pad's
  top is at its base.
- pybullet: urdf/world.urdf has a link per artifact at its recorded pose with its box; a
  dynamic copy of that box raised 0.5 m and dropped (the link's own collision switched off)
  comes to rest within 0.3 m.
- usd: usd/world.usda has /World/Artifacts/<name>, a rigid body with a mass and a cube
  collider, whose box in the world frame matches the recorded pose and size, on its pad.
- gltf: mesh/world.glb has a node per artifact (trimesh) whose box matches the recorded one.
Prints one line per check; exits non-zero (AssertionError) on the first disagreement.
"""

import csv
import json
import math
import sys
import tomllib
from pathlib import Path

import numpy as np
from plane_squares import plane_squares

world = Path(sys.argv[1])
mode = sys.argv[2]
doc = json.loads((world / "ground_truth/artifacts.json").read_text())
arts = doc["artifacts"]
DROP = 0.5
REST = 0.3



def footprint(a, n=5):
    """Points of the artifact's footprint (n x n, corners included) at its base height."""
    (x, y, z), (l, w, _), yaw = a["position"], a["size"], a["yaw"]
    c, s = math.cos(yaw), math.sin(yaw)
    out = []
    for u in np.linspace(-0.5, 0.5, n):
        for v in np.linspace(-0.5, 0.5, n):
            out.append([x + c * u * l - s * v * w, y + s * u * l + c * v * w, z])
    return np.array(out)


def check_placement():
    toml = tomllib.loads((world / "world.toml").read_text())
    rules = toml["artifacts"]
    assert doc["count"] == len(arts) == rules["count"], "count as world.toml records it"
    kinds = {"dead-end": {"dead-end"}, "chamber": {"t-junction", "intersection"}}
    topo = json.loads((world / "topology.json").read_text())
    for a in arts:
        assert a["class"] in rules["classes"], a["class"]
        assert a["placement"] in rules["placement"], a["placement"]
        assert a["tile_kind"] in kinds.get(a["placement"], {"dead-end", "straight", "corner", "t-junction", "intersection"})
        assert a["distance_from_start_m"] >= rules["min_distance_from_start"]
        graph = a["graph"]
        if "node" in graph:
            assert topo["nodes"][graph["node"]["node"]]["cell"] == a["cell"]
        else:
            assert a["cell"] in topo["edges"][graph["edge"]["edge"]]["cells"]
    pos = np.array([a["position"] for a in arts])
    for i in range(len(arts)):
        for j in range(i):
            assert np.linalg.norm(pos[i] - pos[j]) >= rules["min_spacing"] - 1e-9, "spacing"
    print(f"placement rules: {len(arts)} artifacts, classes, tiles, distances and spacing as world.toml says")

    import trimesh

    mesh = trimesh.load(world / "mesh/collision.obj", process=True)
    assert mesh.is_watertight
    tri = mesh.triangles
    a_, b_, c_ = tri[:, 0], tri[:, 1], tri[:, 2]
    lo, hi = tri[:, :, :2].min(axis=1), tri[:, :, :2].max(axis=1)
    area = (b_[:, 0] - a_[:, 0]) * (c_[:, 1] - a_[:, 1]) - (b_[:, 1] - a_[:, 1]) * (c_[:, 0] - a_[:, 0])

    squares = plane_squares(lo, hi, 4.0)

    def crossings(p):
        p = p + [3.1e-6, 1.7e-6, 0.0]
        near = squares.get((math.floor(p[0] / 4.0), math.floor(p[1] / 4.0)), np.zeros(0, np.int64))
        m = near[(lo[near, 0] <= p[0]) & (p[0] <= hi[near, 0]) & (lo[near, 1] <= p[1]) & (p[1] <= hi[near, 1]) & (area[near] != 0)]
        A, B, C, S = a_[m], b_[m], c_[m], area[m]

        def edge(u, v):
            return (v[:, 0] - u[:, 0]) * (p[1] - u[:, 1]) - (v[:, 1] - u[:, 1]) * (p[0] - u[:, 0])

        wa, wb, wc = edge(B, C), edge(C, A), edge(A, B)
        inside = ((wa >= 0) & (wb >= 0) & (wc >= 0)) | ((wa <= 0) & (wb <= 0) & (wc <= 0))
        return np.sort(((wa * A[:, 2] + wb * B[:, 2] + wc * C[:, 2]) / S)[inside])

    worst = 0.0
    for a in arts:
        base, h = a["position"][2], a["size"][2]
        for p in footprint(a):
            zs = crossings(p)
            assert len(zs) % 2 == 0, f"{a['name']}: the surface is open at {p}"
            # The free stretch holding a point just above the base: its floor and roof.
            stretches = zs.reshape(-1, 2)
            held = [s for s in stretches if s[0] <= base + 1e-3 and base + 1e-3 <= s[1]]
            assert held, f"{a['name']}: {p} at its base is inside the rock (crossings {zs})"
            floor, roof = held[0]
            assert floor >= base - 0.1 - 1e-3, f"{a['name']}: floats {base - floor:.3f} m above the floor at {p}"
            assert roof >= base + h, f"{a['name']}: its top is in the rock at {p}"
            worst = max(worst, base - floor)
    print(f"placement on the collision surface: every footprint point on the floor (gap at most {worst:.3f} m), every box free")
    rows = list(csv.DictReader(open(world / "ground_truth/artifacts.csv")))
    assert len(rows) == len(arts)
    for r, a in zip(rows, arts):
        assert r["class"] == a["class"] and r["name"] == a["name"]
        assert max(abs(float(r[k]) - a["position"][i]) for i, k in enumerate("xyz")) < 1e-3, "the CSV agrees"
    print("artifacts.csv agrees with artifacts.json")


def check_mujoco():
    import mujoco

    model = mujoco.MjModel.from_xml_path(str(world / "mujoco/world.xml"))
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    adr = {}
    for a in arts:
        b = model.body(f"artifact-{a['name']}")
        g = model.geom(f"artifact-{a['name']}")
        assert np.allclose(2 * g.size, a["size"], atol=1e-3), (g.size, a["size"])
        pad = model.geom(f"artifact-pad-{a['name']}")
        top = data.geom_xpos[pad.id][2] + pad.size[2]
        assert abs(top - a["position"][2]) < 1e-3, "the pad's top is the artifact's base"
        assert np.allclose(data.xpos[b.id], a["position"], atol=1e-3), (data.xpos[b.id], a["position"])
        j = model.body_jntadr[b.id]
        assert model.jnt_type[j] == mujoco.mjtJoint.mjJNT_FREE
        adr[a["name"]] = (b.id, model.jnt_qposadr[j])
    for name, (_, q) in adr.items():
        data.qpos[q + 2] += DROP
    mujoco.mj_forward(model, data)
    steps = int(5.0 / model.opt.timestep)
    for _ in range(steps):
        mujoco.mj_step(model, data)
    worst = 0.0
    for a in arts:
        b, _ = adr[a["name"]]
        d = np.linalg.norm(data.xpos[b] - a["position"])
        assert d <= REST, f"{a['name']} ({a['placement']}) came to rest {d:.3f} m from its recorded pose: {data.xpos[b]} vs {a['position']}"
        assert np.linalg.norm(data.cvel[b]) < 0.1, f"{a['name']} still moves"
        worst = max(worst, d)
    print(f"mujoco: {len(arts)} free bodies dropped from {DROP} m rest within {worst:.3f} m of their poses")


def check_pybullet():
    import os
    import tempfile

    import pybullet as p

    urdf = str((world / "urdf/world.urdf").resolve())
    os.chdir(tempfile.gettempdir())
    p.connect(p.DIRECT)
    body = p.loadURDF(urdf, useFixedBase=True)
    p.setGravity(0, 0, -9.81)
    links = {}
    for j in range(p.getNumJoints(body)):
        name = p.getJointInfo(body, j)[12].decode()
        links[name] = j
    dropped = []
    for a in arts:
        link = links[f"artifact-{a['name']}"]
        pos, orn = p.getLinkState(body, link, computeForwardKinematics=True)[4:6]
        assert np.allclose(pos, a["position"], atol=1e-3), (pos, a["position"])
        shape = p.getCollisionShapeData(body, link)[0]
        assert shape[2] == p.GEOM_BOX and np.allclose(shape[3], a["size"], atol=1e-3), shape
        p.setCollisionFilterGroupMask(body, link, 0, 0)
        half = [0.5 * s for s in a["size"]]
        col = p.createCollisionShape(p.GEOM_BOX, halfExtents=half)
        c = a["centre"]
        box = p.createMultiBody(baseMass=a["mass_kg"], baseCollisionShapeIndex=col,
                                basePosition=[c[0], c[1], c[2] + DROP],
                                baseOrientation=a["quaternion_xyzw"])
        dropped.append((a, box))
    for _ in range(240 * 3):
        p.stepSimulation()
    worst = 0.0
    for a, box in dropped:
        pos = np.array(p.getBasePositionAndOrientation(box)[0])
        d = np.linalg.norm(pos - np.array(a["centre"]))
        assert d <= REST, f"{a['name']} ({a['placement']}) came to rest {d:.3f} m from its recorded pose"
        worst = max(worst, d)
    print(f"pybullet: {len(arts)} artifact boxes dropped from {DROP} m rest within {worst:.3f} m of their poses")


def check_usd():
    from pxr import Usd, UsdGeom, UsdPhysics

    stage = Usd.Stage.Open(str(world / "usd/world.usda"))
    cache = UsdGeom.BBoxCache(Usd.TimeCode.Default(), [UsdGeom.Tokens.default_])
    for a in arts:
        prim = stage.GetPrimAtPath(f"/World/Artifacts/{a['name'].replace('-', '_')}")
        assert prim.IsValid(), a["name"]
        pad = stage.GetPrimAtPath(f"/World/Artifacts/{a['name'].replace('-', '_')}_pad")
        assert pad.IsA(UsdGeom.Cube) and pad.HasAPI(UsdPhysics.CollisionAPI)
        top = cache.ComputeWorldBound(pad).ComputeAlignedRange().GetMax()[2]
        assert abs(top - a["position"][2]) < 1e-3, "the pad's top is the artifact's base"
        assert prim.HasAPI(UsdPhysics.RigidBodyAPI) and prim.HasAPI(UsdPhysics.MassAPI)
        assert abs(UsdPhysics.MassAPI(prim).GetMassAttr().Get() - a["mass_kg"]) < 1e-6
        assert prim.GetAttribute("subtgraph:class").Get() == a["class"]
        cube = prim.GetChild("box")
        assert cube.IsA(UsdGeom.Cube) and cube.HasAPI(UsdPhysics.CollisionAPI)
        m = UsdGeom.Xformable(prim).ComputeLocalToWorldTransform(Usd.TimeCode.Default())
        t = m.ExtractTranslation()
        assert np.allclose(list(t), a["position"], atol=1e-3), (t, a["position"])
        box = cache.ComputeWorldBound(cube).ComputeAlignedRange()
        lo, hi = np.array(box.GetMin()), np.array(box.GetMax())
        assert abs(lo[2] - a["position"][2]) < 1e-3 and abs(hi[2] - lo[2] - a["size"][2]) < 1e-3
        assert np.allclose((lo + hi)[:2] / 2, a["position"][:2], atol=1e-3)
    print(f"usd: {len(arts)} rigid bodies with cube colliders at their poses")


def check_gltf():
    import trimesh

    scene = trimesh.load(world / "mesh/world.glb")
    for a in arts:
        node = f"artifact-{a['name']}"
        transform, geometry = scene.graph.get(node)
        box = scene.geometry[geometry].copy()
        box.apply_transform(transform)
        # glTF is Y up: (x, y, z) -> (x, z, -y).
        lo, hi = box.bounds
        centre = (lo + hi) / 2
        c = a["centre"]
        assert np.allclose(centre, [c[0], c[2], -c[1]], atol=1e-3), (centre, c)
        assert abs(hi[1] - lo[1] - a["size"][2]) < 1e-3, "height along Y"
        assert abs(box.volume - np.prod(a["size"])) < 1e-4, "the box's volume"
    print(f"gltf: {len(arts)} artifact nodes with their boxes")


{"placement": check_placement, "mujoco": check_mujoco, "pybullet": check_pybullet,
 "usd": check_usd, "gltf": check_gltf}[mode]()
