"""Checks a textured subtgraph world with the readers simulators and tools use.

Usage: textures_check.py WORLD_FOLDER
       textures_check.py --orb PLAIN.png TEXTURED.png RATIO

The world is expected to hold mesh/textures/, mesh/world.glb, usd/world.usda,
mujoco/world.xml, gazebo/world.sdf with its part meshes (generate --format gltf,usd,mjcf,sdf).
Prints one line per check and exits non-zero on the first failure:
- every image under mesh/textures/ decodes (Pillow), is square, and repeats without a seam:
  the jump across its wrap-around edges is no larger than between neighbouring pixels inside;
- every albedo has contrast and corners: OpenCV's ORB finds keypoints in it (when cv2 is
  installed);
- glTF: every material has a baseColorTexture, metallicRoughnessTexture and normalTexture
  whose image URI is a file beside the GLB that decodes, and trimesh loads the GLB with a
  PBR material holding the albedo image;
- USD (usd-core): the stage opens, every UsdUVTexture's `inputs:file` resolves to an
  existing file, every Material's surface reads its diffuse colour from a texture, and every
  visual mesh has `primvars:st`;
- MuJoCo: the model compiles with its textures (ntex > 0, each texture's size that of its PNG)
  and every visual geom has a textured material;
- MTL (the part meshes Gazebo's SDF names): every map_Kd, norm and map_Pr file exists.
The seam check is shown able to fail: some image cut short (not a whole repeat) must fail it.

With --orb: OpenCV's ORB (cv2.ORB_create, 5000 features at most) on two pictures of the same
view, plain and textured; prints both counts and fails unless the textured one has at least
RATIO times the plain one's keypoints.
"""
import json
import os
import re
import struct
import sys

import numpy as np
from PIL import Image


def fail(msg):
    print("FAIL", msg)
    sys.exit(1)


def seam(a):
    """Whether image array `a` jumps across its wrap-around edges."""
    # The jump across the wrap against the jumps between the columns (rows) beside it: a
    # crack running across the edge raises all of them, a seam only the wrap.
    cols = np.abs(np.diff(a, axis=1)).mean(axis=(0, 2))
    rows = np.abs(np.diff(a, axis=0)).mean(axis=(1, 2))
    inside_x = max(cols[0], cols[-1], cols.mean())
    inside_y = max(rows[0], rows[-1], rows.mean())
    wrap_x = np.abs(a[:, 0] - a[:, -1]).mean()
    wrap_y = np.abs(a[0] - a[-1]).mean()
    if wrap_x > 1.5 * inside_x + 1.0 or wrap_y > 1.5 * inside_y + 1.0:
        return f"({wrap_x:.2f}, {wrap_y:.2f} against {inside_x:.2f}, {inside_y:.2f} inside)"
    return None


def seamless(path):
    a = np.asarray(Image.open(path).convert("RGB")).astype(float)
    if a.shape[0] != a.shape[1]:
        fail(f"{path}: not square {a.shape}")
    why = seam(a)
    if why:
        fail(f"{path}: a seam at the edge {why}")
    return a


def check_images(world):
    folder = os.path.join(world, "mesh", "textures")
    names = sorted(os.listdir(folder))
    if not names:
        fail("mesh/textures/ is empty")
    try:
        import cv2
    except ImportError:
        cv2 = None
    told = 0
    for n in names:
        a = seamless(os.path.join(folder, n))
        told += seam(a[: a.shape[0] * 2 // 3, : a.shape[1] * 2 // 3]) is not None
        if n.endswith("-albedo.png"):
            if a.std() < 8.0:
                fail(f"{n}: too flat (std {a.std():.1f})")
            if cv2 is not None:
                grey = cv2.cvtColor(a.astype(np.uint8), cv2.COLOR_RGB2GRAY)
                k = cv2.ORB_create(nfeatures=5000).detect(grey, None)
                if len(k) < 50:
                    fail(f"{n}: ORB finds only {len(k)} keypoints")
                print(f"ok {n}: {len(k)} ORB keypoints, seamless")
    if told == 0:
        fail("the seam check tells no image cut short (not a whole repeat) from a whole one")
    print(f"ok {len(names)} images decode and repeat without a seam ({told} cut short would not)")


def glb_json(path):
    with open(path, "rb") as f:
        data = f.read()
    length, kind = struct.unpack_from("<I4s", data, 12)
    if kind != b"JSON":
        fail("GLB without a JSON chunk")
    return json.loads(data[20 : 20 + length])


def check_gltf(world):
    glb = os.path.join(world, "mesh", "world.glb")
    doc = glb_json(glb)
    images = doc.get("images", [])
    textures = doc.get("textures", [])
    for m in doc["materials"]:
        if m["name"].startswith("artifact-"):
            continue
        pbr = m["pbrMetallicRoughness"]
        for key, slot in [("baseColorTexture", pbr), ("metallicRoughnessTexture", pbr), ("normalTexture", m)]:
            if key not in slot:
                fail(f"glTF material {m['name']} has no {key}")
            uri = images[textures[slot[key]["index"]]["source"]]["uri"]
            path = os.path.join(os.path.dirname(glb), uri)
            Image.open(path).load()
    print(f"ok glTF: {len(doc['materials'])} materials with 3 maps each, {len(images)} images decode")
    import trimesh

    scene = trimesh.load(glb)
    found = 0
    for g in scene.geometry.values():
        mat = getattr(g.visual, "material", None)
        img = getattr(mat, "baseColorTexture", None)
        if img is not None and img.size[0] > 0:
            found += 1
    if found == 0:
        fail("trimesh loads the GLB without any albedo image")
    print(f"ok trimesh: {found} of {len(scene.geometry)} geometries carry their albedo image")


def check_usd(world):
    from pxr import Sdf, Usd, UsdGeom, UsdShade

    stage = Usd.Stage.Open(os.path.join(world, "usd", "world.usda"))
    files = 0
    for prim in stage.Traverse():
        if prim.IsA(UsdShade.Shader):
            shader = UsdShade.Shader(prim)
            if shader.GetIdAttr().Get() == "UsdUVTexture":
                asset = shader.GetInput("file").Get()
                if not asset.resolvedPath or not os.path.exists(asset.resolvedPath):
                    fail(f"USD: {prim.GetPath()} file {asset.path} does not resolve")
                Image.open(asset.resolvedPath).load()
                files += 1
        if prim.IsA(UsdShade.Material) and "Looks" in str(prim.GetPath()):
            surface = UsdShade.Material(prim).ComputeSurfaceSource()[0]
            diffuse = surface.GetInput("diffuseColor")
            if not diffuse.HasConnectedSource():
                fail(f"USD: {prim.GetPath()} has no diffuse texture")
        if prim.IsA(UsdGeom.Mesh) and "Visual" in str(prim.GetPath()):
            if not UsdGeom.PrimvarsAPI(prim).HasPrimvar("st"):
                fail(f"USD: {prim.GetPath()} has no primvars:st")
    if files == 0:
        fail("USD: no UsdUVTexture")
    print(f"ok USD: {files} UsdUVTexture files resolve")


def check_mujoco(world):
    import mujoco

    model = mujoco.MjModel.from_xml_path(os.path.join(world, "mujoco", "world.xml"))
    if model.ntex == 0:
        fail("MuJoCo: no textures")
    for t in range(model.ntex):
        name = mujoco.mj_id2name(model, mujoco.mjtObj.mjOBJ_TEXTURE, t)
        w, h = int(model.tex_width[t]), int(model.tex_height[t])
        if w <= 1 or h <= 1:
            fail(f"MuJoCo: texture {name} is {w} x {h}")
    visual = [g for g in range(model.ngeom) if model.geom_group[g] == 1 and model.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH]
    untextured = [g for g in visual if model.geom_matid[g] < 0 or model.mat_texid[model.geom_matid[g]].max() < 0]
    if not visual or untextured:
        fail(f"MuJoCo: {len(untextured)} of {len(visual)} visual geoms without a textured material")
    print(f"ok MuJoCo: compiled with {model.ntex} textures, {len(visual)} visual geoms textured")


def check_mtl(world):
    count = 0
    for root, _, names in os.walk(os.path.join(world, "mesh")):
        for n in names:
            if not n.endswith(".mtl"):
                continue
            for line in open(os.path.join(root, n)):
                m = re.match(r"(map_Kd|norm|map_Pr) (.+)", line.strip())
                if m:
                    path = os.path.normpath(os.path.join(root, m.group(2)))
                    if not os.path.exists(path):
                        fail(f"{n}: {m.group(1)} {m.group(2)} does not exist")
                    count += 1
    if count == 0:
        fail("no MTL names a texture")
    print(f"ok MTL: {count} maps exist")


def orb(paths, ratio):
    import cv2

    counts = []
    for p in paths:
        grey = cv2.imread(p, cv2.IMREAD_GRAYSCALE)
        counts.append(len(cv2.ORB_create(nfeatures=5000).detect(grey, None)))
    print(f"ORB keypoints: plain {counts[0]}, textured {counts[1]}")
    if counts[1] < ratio * max(counts[0], 1):
        fail(f"textured has {counts[1]} keypoints, under {ratio} x {counts[0]}")


def main():
    if sys.argv[1] == "--orb":
        orb(sys.argv[2:4], float(sys.argv[4]))
        return
    world = sys.argv[1]
    check_images(world)
    check_gltf(world)
    check_usd(world)
    check_mujoco(world)
    check_mtl(world)


if __name__ == "__main__":
    main()
