"""Loads a subtgraph world's urdf/world.urdf in PyBullet and drops a ball in a corridor.

Usage: pybullet_check.py WORLD_FOLDER [--convex] [--lift METRES]

--lift raises the drop point for tile sets whose floor is not at the cell's nominal height.

Checks, exiting non-zero on the first failure:
- loadURDF(useFixedBase=True) from a working directory other than the world folder (mesh
  paths are relative to the URDF file);
- ray casts from 1.5 m above the floor at the middle cell of a corridor: down they hit the
  floor near the cell's floor height, up they hit the roof at a plausible height (1.5 m
  above the floor or more, below the next level: the tunnel is hollow, not a convex hull);
- a ball (radius 0.2 m) dropped there touches nothing at first and after 5 simulated seconds
  rests on that floor, still within half a pitch of the cell.
With --convex the URDF is loaded with its concave="yes" attributes removed (what a plain URDF
does): PyBullet then collides each part as its convex hull and the checks must fail.
"""
import json
import os
import sys
import tempfile

import pybullet as p

from corridor import corridor_cell

RADIUS = 0.2


def lift(argv):
    """The --lift METRES argument, 0 without it."""
    return float(argv[argv.index("--lift") + 1]) if "--lift" in argv else 0.0


def main():
    folder = os.path.abspath(sys.argv[1])
    convex = "--convex" in sys.argv
    topology = json.load(open(os.path.join(folder, "topology.json")))
    cell, (x, y, z) = corridor_cell(topology)
    z += lift(sys.argv)
    pitch = topology["tile_pitch_m"]
    urdf = os.path.join(folder, "urdf", "world.urdf")
    if convex:
        text = open(urdf).read().replace(' concave="yes"', "")
        urdf = os.path.join(folder, "urdf", "world-convex.urdf")
        open(urdf, "w").write(text)
    os.chdir(tempfile.gettempdir())  # not the world folder: paths must resolve by themselves
    p.connect(p.DIRECT)
    world = p.loadURDF(urdf, useFixedBase=True)
    if convex:
        os.remove(urdf)
    print(f"loaded {urdf}: {len(p.getCollisionShapeData(world, -1))} collision shapes")
    top = [x, y, z + 1.5]
    down = p.rayTest(top, [x, y, z - 5])[0]
    height = topology["level_height_m"]
    up = p.rayTest(top, [x, y, z + height])[0]
    print(f"corridor cell {cell}: ray down hits {down[3]} (object {down[0]}), up hits {up[3]} (object {up[0]})")
    if down[0] != world or up[0] != world:
        sys.exit("FAIL: a ray from inside the corridor hits no floor or no roof")
    floor, roof = down[3][2], up[3][2]
    if abs(floor - z) > 1.4:
        sys.exit(f"FAIL: the floor is at {floor:.3f}, far from the cell's {z}")
    if not 1.5 <= roof - floor < height:
        sys.exit(f"FAIL: the roof is {roof - floor:.3f} m above the floor")
    ball = p.createMultiBody(0.5, p.createCollisionShape(p.GEOM_SPHERE, radius=RADIUS), -1, top)
    p.changeDynamics(ball, -1, linearDamping=0.5, angularDamping=0.5, rollingFriction=0.01)
    p.performCollisionDetection()
    if p.getContactPoints(bodyA=ball):
        sys.exit("FAIL: the ball touches the world at t = 0 (the passage is not hollow)")
    p.setGravity(0, 0, -9.81)
    for _ in range(240 * 5):
        p.stepSimulation()
    at, _ = p.getBasePositionAndOrientation(ball)
    speed = sum(v * v for v in p.getBaseVelocity(ball)[0]) ** 0.5
    print(f"after 5 s the ball is at {[round(v, 3) for v in at]}, speed {speed:.3f} m/s")
    if abs(at[2] - (floor + RADIUS)) > 0.6:
        sys.exit(f"FAIL: the ball is at z {at[2]:.3f}, not on the floor at {floor:.3f}")
    if max(abs(at[0] - x), abs(at[1] - y)) > pitch / 2:
        sys.exit("FAIL: the ball left the corridor's cell")
    if speed > 0.2:
        sys.exit(f"FAIL: the ball is still moving at {speed:.3f} m/s")
    print("OK")


main()
