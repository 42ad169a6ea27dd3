"""Imports a subtgraph mesh (mesh/world.glb or mesh/world.obj) into Blender, headless, and
reports what Blender made of it.

Usage: blender -b --factory-startup --python blender_check.py -- FILE

Blender's own importers (glTF: io_import_scene_gltf2; OBJ: the C++ importer `wm.obj_import`)
read FILE into an empty scene; the script prints one line, `RESULT ` followed by JSON: the
mesh objects' names, their total face count, and the names of the materials on them (Blender
suffixes a duplicate name with .001: stripped). It exits non-zero if the importer fails or
makes no mesh.
"""
import json
import sys

import numpy

# Debian's Blender 3.4 glTF importer still uses numpy.bool, which numpy 1.24 removed.
if not hasattr(numpy, "bool"):
    numpy.bool = bool

import bpy  # noqa: E402


def main():
    path = sys.argv[sys.argv.index("--") + 1]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if path.endswith((".glb", ".gltf")):
        result = bpy.ops.import_scene.gltf(filepath=path)
    else:
        result = bpy.ops.wm.obj_import(filepath=path)
    if "FINISHED" not in result:
        print(f"FAIL: importing {path}: {result}")
        sys.exit(1)
    meshes = [o for o in bpy.context.scene.objects if o.type == "MESH"]
    if not meshes:
        print(f"FAIL: {path} made no mesh object")
        sys.exit(1)
    materials = sorted({m.name.split(".")[0] for o in meshes for m in o.data.materials if m})
    print("RESULT " + json.dumps({
        "objects": sorted(o.name for o in meshes),
        "faces": sum(len(o.data.polygons) for o in meshes),
        "materials": materials,
    }))


main()
