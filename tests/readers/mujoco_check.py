"""Loads a subtgraph world's mujoco/world.xml in MuJoCo and drops a ball in a corridor.

Usage: mujoco_check.py WORLD_FOLDER [--one-mesh] [--lift METRES]

--lift raises the drop point for tile sets whose floor is not at the cell's nominal height.

Checks, printing one line per check and exiting non-zero on the first failure:
- the model loads from a working directory other than the world folder (meshdir is relative);
- a free ball (radius 0.2 m) added 1.5 m above the floor at the middle cell of a corridor
  touches nothing at t = 0, and after 5 simulated seconds rests on that corridor's floor:
  its height within 0.6 m of floor + radius (the floor of a cave is uneven), still within
  half a tile pitch of the cell, slow;
- mujoco/level-1.xml, when there is one, loads alone and holds part of the world.
With --one-mesh the world's whole collision surface is instead one mesh geom (what a naive
export does): MuJoCo collides it as its convex hull, so the same drop must fail. The test runs
both, so it is known able to fail.
"""
import json
import os
import sys
import tempfile
import time

import mujoco
import numpy as np

from corridor import corridor_cell

RADIUS = 0.2


def floor_height(model, data, at, ball):
    """The height of the first collision surface below `at` (MuJoCo's own ray cast, through
    geom groups 0 and 3, where collision geoms are, not through the ball)."""
    geomid = np.zeros(1, np.int32)
    groups = np.array([1, 0, 0, 1, 0, 0], np.uint8)
    d = mujoco.mj_ray(model, data, at, np.array([0.0, 0.0, -1.0]), groups, 1, ball, geomid)
    return at[2] - d if d >= 0 else None


def lift(argv):
    """The --lift METRES argument, 0 without it."""
    return float(argv[argv.index("--lift") + 1]) if "--lift" in argv else 0.0


def main():
    folder = os.path.abspath(sys.argv[1])
    one_mesh = "--one-mesh" in sys.argv
    topology = json.load(open(os.path.join(folder, "topology.json")))
    cell, pos = corridor_cell(topology)
    pos = np.array(pos)
    pos[2] += lift(sys.argv)
    pitch = topology["tile_pitch_m"]
    os.chdir(tempfile.gettempdir())  # not the world folder: paths must resolve by themselves
    path = os.path.join(folder, "mujoco", "world.xml")
    t = time.time()
    spec = mujoco.MjSpec.from_file(path)
    if one_mesh:
        spec = mujoco.MjSpec()
        spec.compiler.meshdir = os.path.join(folder, "mesh")
        spec.add_mesh(name="all", file="collision.obj")
        spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_MESH, meshname="all")
    start = pos + np.array([0.0, 0.0, 1.5])
    ball = spec.worldbody.add_body(name="ball", pos=start)
    ball.add_freejoint(name="ball")
    ball.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[RADIUS, 0, 0], density=100)
    model = spec.compile()
    print(f"loaded {path} in {time.time() - t:.2f} s: {model.ngeom} geoms, {model.nmesh} meshes")
    # Damp the probe so it settles on a curved floor instead of rocking for ever.
    model.dof_damping[:] = 5.0
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    floor = floor_height(model, data, start, model.body("ball").id)
    print(f"corridor cell {cell}, floor below the drop point at {floor}")
    if data.ncon != 0:
        sys.exit(f"FAIL: the ball touches {data.ncon} geoms at t = 0 (the passage is not hollow)")
    if floor is None:
        sys.exit("FAIL: no collision surface below the drop point")
    steps = int(5.0 / model.opt.timestep)
    for _ in range(steps):
        mujoco.mj_step(model, data)
    at = data.qpos[:3].copy()
    speed = float(np.linalg.norm(data.qvel[:3]))
    print(f"after 5 s the ball is at {at.round(3).tolist()}, speed {speed:.3f} m/s")
    if abs(at[2] - (floor + RADIUS)) > 0.6:
        sys.exit(f"FAIL: the ball is at z {at[2]:.3f}, not on the floor at {floor:.3f}")
    if np.max(np.abs(at[:2] - pos[:2])) > pitch / 2:
        sys.exit("FAIL: the ball left the corridor's cell")
    if speed > 0.2:
        sys.exit(f"FAIL: the ball is still moving at {speed:.3f} m/s")
    # One level alone: every part file is a complete model.
    part = os.path.join(folder, "mujoco", "level-1.xml")
    if os.path.exists(part):
        one = mujoco.MjModel.from_xml_path(part)
        print(f"level-1.xml alone: {one.ngeom} geoms")
        if not 1 < one.ngeom < model.ngeom - 1:
            sys.exit("FAIL: level-1.xml alone is not one level of the world")
    print("OK")


main()
