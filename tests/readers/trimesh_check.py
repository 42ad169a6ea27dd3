"""Loads a world's mesh/world.obj, mesh/collision.obj and mesh/world.glb with trimesh and
checks that they describe the same closed surface; prints a JSON summary.

usage: trimesh_check.py WORLD_FOLDER
"""
import json
import sys
from pathlib import Path

import numpy as np
import trimesh


def fail(msg):
    print(f"FAIL: {msg}")
    sys.exit(1)


def surface(path):
    """The file's triangles as one mesh, vertices merged by position (tiles and primitives
    each bring their own copies of shared vertices)."""
    mesh = trimesh.load(str(path), force="mesh", process=False)
    mesh.merge_vertices(merge_tex=True, merge_norm=True)
    return mesh


def main():
    folder = Path(sys.argv[1])
    world = surface(folder / "mesh" / "world.obj")
    collision = surface(folder / "mesh" / "collision.obj")
    # The GLB as a scene: a node per part, a primitive per material.
    scene = trimesh.load(str(folder / "mesh" / "world.glb"), force="scene", process=False)
    if len(scene.graph.nodes_geometry) < 1:
        fail("no geometry in the GLB")
    glb = surface(folder / "mesh" / "world.glb")
    # trimesh keeps glTF's Y up: (x, y, z) ours = (x, -z, y) glTF.
    v = glb.vertices
    ours = np.column_stack([v[:, 0], -v[:, 2], v[:, 1]])
    for name, m in [("world.obj", world), ("collision.obj", collision), ("world.glb", glb)]:
        if not m.is_watertight:
            fail(f"{name} is not watertight")
        if not m.is_winding_consistent:
            fail(f"{name} winding is not consistent")
    if len(glb.faces) != len(world.faces):
        fail(f"{len(glb.faces)} GLB triangles, {len(world.faces)} OBJ triangles")
    lo, hi = ours.min(axis=0), ours.max(axis=0)
    if not (np.allclose(lo, world.bounds[0], atol=2e-3) and np.allclose(hi, world.bounds[1], atol=2e-3)):
        fail(f"GLB bounds {lo} {hi}, OBJ bounds {world.bounds}")
    # Same orientation: the glTF (converted back) encloses the passage like the OBJ does
    # (normals point into the passage, so the enclosed volume is negative in both).
    if np.sign(glb.volume) != np.sign(world.volume) or not np.isclose(glb.volume, world.volume, rtol=1e-3):
        fail(f"GLB volume {glb.volume}, OBJ volume {world.volume}")
    print(json.dumps({
        "triangles": len(world.faces),
        "collision_triangles": len(collision.faces),
        "glb_nodes": len(scene.graph.nodes_geometry),
        "volume": float(world.volume),
        "collision_volume": float(collision.volume),
        "bounds": world.bounds.tolist(),
    }))


main()
