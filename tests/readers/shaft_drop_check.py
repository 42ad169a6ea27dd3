"""Drops a ball down every shaft of a subtgraph world in PyBullet (urdf/world.urdf).

Usage: shaft_drop_check.py WORLD_FOLDER

For every shaft edge of ground_truth/graph.json (from the foot's node F to the landing's node
L), checks, exiting non-zero on the first failure:
- a ray across from 1 m above the landing's node to the point over the foot's node at that
  height hits nothing (the landing's floor leads to the shaft's top);
- a ray down from there first hits the foot's floor, near F's height (the shaft is open all
  the way down: no rock, no ledge across it);
- a ball (radius 0.3 m) released there touches nothing, and after 10 simulated seconds rests
  on the foot's floor within half a pitch of F.
"""
import json
import os
import sys
import tempfile

import pybullet as p

RADIUS = 0.3


def main():
    folder = os.path.abspath(sys.argv[1])
    graph = json.load(open(os.path.join(folder, "ground_truth", "graph.json")))
    topology = json.load(open(os.path.join(folder, "topology.json")))
    pitch = topology["tile_pitch_m"]
    urdf = os.path.join(folder, "urdf", "world.urdf")
    os.chdir(tempfile.gettempdir())
    p.connect(p.DIRECT)
    world = p.loadURDF(urdf, useFixedBase=True)
    nodes = {n["id"]: n for n in graph["nodes"]}
    shafts = [e for e in graph["edges"] if e["kind"] == "shaft"]
    if not shafts:
        sys.exit("FAIL: the world has no shaft")
    for e in shafts:
        foot, landing = nodes[e["from"]]["position"], nodes[e["to"]]["position"]
        top = [foot[0], foot[1], landing[2] + 1.0]
        across = p.rayTest([landing[0], landing[1], landing[2] + 1.0], top)[0]
        if across[0] != -1:
            sys.exit(f"FAIL: shaft {e['id']}: rock at {across[3]} between the landing {landing} and the shaft's top {top}")
        down = p.rayTest(top, [foot[0], foot[1], foot[2] - 5.0])[0]
        print(f"shaft {e['id']}: foot {foot}, landing {landing}; down from {top} the ray hits {down[3]}")
        if down[0] != world or abs(down[3][2] - foot[2]) > 1.4:
            sys.exit(f"FAIL: shaft {e['id']}: the way down from {top} stops at {down[3]}, not on the foot's floor at {foot[2]}")
        ball = p.createMultiBody(0.5, p.createCollisionShape(p.GEOM_SPHERE, radius=RADIUS), -1, top)
        # Little air damping (PyBullet's 0.5 would hold the fall to 4 m/s), rolling friction so
        # that it comes to rest.
        p.changeDynamics(ball, -1, linearDamping=0.04, angularDamping=0.5, rollingFriction=0.01)
        p.performCollisionDetection()
        if p.getContactPoints(bodyA=ball):
            sys.exit(f"FAIL: shaft {e['id']}: the ball touches the world where it is released")
        p.setGravity(0, 0, -9.81)
        for _ in range(240 * 10):
            p.stepSimulation()
        at, _ = p.getBasePositionAndOrientation(ball)
        print(f"  after 10 s the ball is at {[round(v, 3) for v in at]}")
        if abs(at[2] - (down[3][2] + RADIUS)) > 1.0:
            sys.exit(f"FAIL: shaft {e['id']}: the ball is at z {at[2]:.3f}, not on the foot's floor at {down[3][2]:.3f}")
        if max(abs(at[0] - foot[0]), abs(at[1] - foot[1])) > pitch / 2:
            sys.exit(f"FAIL: shaft {e['id']}: the ball left the foot's tile")
        p.removeBody(ball)
    print(f"OK: {len(shafts)} shaft(s), a ball falls from each landing's height to its foot")


main()
