"""Renders a world's inside view with Blender headless (Cycles, CPU) from its exported glTF, for
scripts/measure-textures.

Usage: blender -b --factory-startup --python measure-textures-render.py -- WORLD OUT.png SAMPLES

The camera stands where `subtgraph preview --inside` puts it: 1.5 m above the start node's floor
(ground_truth/graph.json), looking along its first passage (the first polyline point at least a
quarter of a tile pitch away), tilted 8 degrees down, 90 degrees across, 640 x 480 pixels; a
point lamp 0.3 m above it and a dim grey world light the passage.
"""
import json
import math
import os
import sys

import numpy

# Debian's Blender 3.4 glTF importer still uses numpy.bool, which numpy 1.24 removed.
if not hasattr(numpy, "bool"):
    numpy.bool = bool

import bpy  # noqa: E402
from mathutils import Vector  # noqa: E402


def start_pose(world):
    topo = json.load(open(os.path.join(world, "topology.json")))
    graph = json.load(open(os.path.join(world, "ground_truth", "graph.json")))
    node = topo["start"]
    pitch = topo["tile_pitch_m"]
    floor = graph["nodes"][node]["position"]
    along = None
    for e in graph["edges"]:
        line = list(e["polyline"])
        if e["to"] == node and e["from"] != node:
            line.reverse()
        elif e["from"] != node:
            continue
        far = None
        for p in line:
            d = (p[0] - floor[0], p[1] - floor[1])
            if d[0] ** 2 + d[1] ** 2 >= (0.25 * pitch) ** 2:
                far = p
                break
        far = far or line[-1]
        d = (far[0] - floor[0], far[1] - floor[1])
        n = math.hypot(*d)
        if n > 1e-9:
            along = (d[0] / n, d[1] / n)
            break
    along = along or (1.0, 0.0)
    return Vector((floor[0], floor[1], floor[2] + 1.5)), along


def main():
    args = sys.argv[sys.argv.index("--") + 1 :]
    world, out, samples = args[0], args[1], int(args[2])
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=os.path.join(world, "mesh", "world.glb"))
    eye, along = start_pose(world)
    scene = bpy.context.scene
    cam_data = bpy.data.cameras.new("camera")
    cam_data.angle = math.radians(90.0)
    cam_data.sensor_fit = "HORIZONTAL"
    cam_data.clip_start = 0.05
    cam = bpy.data.objects.new("camera", cam_data)
    scene.collection.objects.link(cam)
    cam.location = eye
    tilt = math.radians(8.0)
    forward = Vector((along[0] * math.cos(tilt), along[1] * math.cos(tilt), -math.sin(tilt)))
    cam.rotation_euler = forward.to_track_quat("-Z", "Y").to_euler()
    scene.camera = cam
    lamp_data = bpy.data.lights.new("lamp", "POINT")
    lamp_data.energy = 100.0
    lamp_data.shadow_soft_size = 0.05
    lamp = bpy.data.objects.new("lamp", lamp_data)
    lamp.location = eye + Vector((0.0, 0.0, 0.3))
    scene.collection.objects.link(lamp)
    world_data = bpy.data.worlds.new("world")
    world_data.use_nodes = True
    world_data.node_tree.nodes["Background"].inputs[0].default_value = (0.05, 0.05, 0.05, 1.0)
    scene.world = world_data
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    # Debian's Blender has no OpenImageDenoise: samples alone keep the noise down.
    scene.cycles.use_denoising = False
    scene.render.resolution_x = 640
    scene.render.resolution_y = 480
    scene.render.resolution_percentage = 100
    scene.view_settings.view_transform = "Standard"
    scene.render.image_settings.file_format = "PNG"
    scene.render.filepath = out
    bpy.ops.render.render(write_still=True)


main()
