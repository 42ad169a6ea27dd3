"""Finds a mine's services in the physics formats of a world folder, apart from subtgraph's
code, and checks them against mesh/services.obj read line by line here:

- MuJoCo (mujoco/world.xml, loaded from another working directory): per material, the
  geoms named `*-services-<material>-*` are visual only (contype 0, conaffinity 0, group 1)
  in the material's colour (world.mtl's Kd); their meshes hold as many faces and vertices as
  that material's copies in services.obj, and in the world frame (MuJoCo's own geom pose
  times its recentred vertices) the same bounds;
- PyBullet (urdf/world.urdf): the world body's visual shapes include one per material, a
  file under mesh/services/ in the material's colour, whose mesh (trimesh) has the same
  faces and bounds; no collision shape of the world names a services file.

Usage: services_formats_check.py WORLD [--mujoco] [--pybullet]. Prints a JSON summary; exits
non-zero naming the first failure.
"""
import json
import os
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

import numpy as np
from obj_reader import read_obj

TOLERANCE = 2e-3  # metres: the OBJ's 0.1 mm digits and float32 in the simulators


def fail(msg):
    print(f"services_formats_check: {msg}", file=sys.stderr)
    sys.exit(1)


def read_mtl(path):
    """Kd per material of an MTL file."""
    colours, name = {}, None
    for line in path.read_text().splitlines():
        parts = line.split()
        if parts[:1] == ["newmtl"]:
            name = parts[1]
        elif parts[:1] == ["Kd"] and name:
            colours[name] = np.array([float(v) for v in parts[1:4]])
    return colours


def read_obj_by_material(path):
    """Per `usemtl` group of an OBJ: (faces, distinct vertices used, bounds min, bounds max)."""
    obj = read_obj(path)
    out = {}
    for m, tris in obj.by_material().items():
        used = np.unique(tris)
        v = obj.vertices[used]
        out[m] = (obj.faces[m], len(used), v.min(axis=0), v.max(axis=0))
    return out


def same_bounds(a_lo, a_hi, b_lo, b_hi):
    return np.abs(a_lo - b_lo).max() <= TOLERANCE and np.abs(a_hi - b_hi).max() <= TOLERANCE


def quat_matrix(q):
    w, x, y, z = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def check_mujoco(world, obj, colours):
    import mujoco
    model = mujoco.MjModel.from_xml_path(str(world / "mujoco" / "world.xml"))
    found = defaultdict(lambda: [0, 0, np.full(3, np.inf), np.full(3, -np.inf)])
    for i in range(model.ngeom):
        g = model.geom(i)
        if "-services-" not in g.name:
            continue
        material = g.name.split("-services-")[1].rsplit("-", 1)[0]
        if material not in obj:
            fail(f"MuJoCo geom {g.name}: no material {material} in services.obj")
        if g.contype[0] != 0 or g.conaffinity[0] != 0 or g.group[0] != 1:
            fail(f"MuJoCo geom {g.name}: contype {g.contype[0]} conaffinity "
                 f"{g.conaffinity[0]} group {g.group[0]}, not visual only")
        if model.geom_bodyid[i] != 0:
            fail(f"MuJoCo geom {g.name} is on a body that may move")
        if np.abs(g.rgba[:3] - colours[material]).max() > 1e-3:
            fail(f"MuJoCo geom {g.name}: colour {g.rgba[:3]}, world.mtl's {material} is "
                 f"{colours[material]}")
        mesh = g.dataid[0]
        start, n = model.mesh_vertadr[mesh], model.mesh_vertnum[mesh]
        local = model.mesh_vert[start:start + n].astype(float)
        placed = local @ quat_matrix(g.quat).T + g.pos
        f = found[material]
        f[0] += int(model.mesh_facenum[mesh])
        f[1] += int(n)
        f[2] = np.minimum(f[2], placed.min(axis=0))
        f[3] = np.maximum(f[3], placed.max(axis=0))
    if set(found) != set(obj):
        fail(f"MuJoCo has services of {sorted(found)}, services.obj of {sorted(obj)}")
    for m, (faces, verts, lo, hi) in found.items():
        if (faces, verts) != obj[m][:2]:
            fail(f"MuJoCo {m}: {faces} faces, {verts} vertices; services.obj "
                 f"{obj[m][0]}, {obj[m][1]}")
        if not same_bounds(lo, hi, obj[m][2], obj[m][3]):
            fail(f"MuJoCo {m}: bounds {lo}..{hi}, services.obj {obj[m][2]}..{obj[m][3]}")
    return {m: v[0] for m, v in found.items()}


def check_pybullet(world, obj, colours):
    import pybullet as p
    import trimesh
    p.connect(p.DIRECT)
    body = p.loadURDF(str(world / "urdf" / "world.urdf"), useFixedBase=True)
    found = {}
    for shape in p.getVisualShapeData(body):
        if shape[1] != -1:
            continue
        path = Path(shape[4].decode())
        if "services" not in path.parts:
            continue
        material = path.stem
        if not path.is_file():
            fail(f"PyBullet visual {path} is not a file")
        if material not in obj:
            fail(f"PyBullet visual {path}: no material {material} in services.obj")
        if np.abs(np.array(shape[7][:3]) - colours[material]).max() > 1e-3:
            fail(f"PyBullet visual {path}: colour {shape[7]}, world.mtl's {colours[material]}")
        mesh = trimesh.load(path, force="mesh", process=False)
        lo, hi = mesh.vertices.min(axis=0), mesh.vertices.max(axis=0)
        if len(mesh.faces) != obj[material][0]:
            fail(f"{path}: {len(mesh.faces)} faces, services.obj {obj[material][0]}")
        if not same_bounds(lo, hi, obj[material][2], obj[material][3]):
            fail(f"{path}: bounds {lo}..{hi}, services.obj {obj[material][2]}..{obj[material][3]}")
        found[material] = len(mesh.faces)
    if set(found) != set(obj):
        fail(f"PyBullet shows services of {sorted(found)}, services.obj has {sorted(obj)}")
    for shape in p.getCollisionShapeData(body, -1):
        if b"services" in shape[4]:
            fail(f"PyBullet collides with {shape[4].decode()}")
    return found


def main():
    world = Path(sys.argv[1]).resolve()
    os.chdir(tempfile.gettempdir())  # not the world folder: paths must resolve by themselves
    obj = read_obj_by_material(world / "mesh" / "services.obj")
    colours = read_mtl(world / "mesh" / "world.mtl")
    summary = {"services_obj_faces": {m: v[0] for m, v in obj.items()}}
    if "--mujoco" in sys.argv:
        summary["mujoco_faces"] = check_mujoco(world, obj, colours)
    if "--pybullet" in sys.argv:
        summary["pybullet_faces"] = check_pybullet(world, obj, colours)
    print(json.dumps(summary))


if __name__ == "__main__":
    main()
