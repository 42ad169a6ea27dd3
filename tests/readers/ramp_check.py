"""A ball placed on a ramp between levels rolls down it and stays inside, in MuJoCo or PyBullet.

Usage: ramp_check.py WORLD_FOLDER --engine mujoco|pybullet [--at FRACTION] [--reach METRES]

The ramp: the first edge of kind "ramp" in ground_truth/graph.json, whose polyline runs along
the spiral's floor from the foot's node to the landing's. A free sphere of radius 0.3 m is
dropped 0.5 m above that floor line where it has climbed FRACTION (default 0.6) of its rise
(from the foot's node to the line's highest point: on the climb, never on the level stretches
a ramp may have before and after its spiral, where a ball rightly stays), and left to roll
for 20 simulated seconds under gravity alone (MuJoCo loads mujoco/world.xml, which must
collide as meshes under the spiral: the default height fields give a ramp's tiles convex slabs,
since a height field holds one floor per line and the spiral has several; PyBullet loads
urdf/world.urdf).

Checks, exiting non-zero with a line starting FAIL on the first failure:
- it rolls down: it ends at least a quarter of its starting height above the foot lower;
- it stays inside: every 0.1 s it is within REACH (default 4 m: half the passage's width and
  the ball) in 3-D of the stretch of the ramp's floor line within 6 m (along it) of where it
  was last, or, once back at the foot, within 1.5 m of the foot's level floor (rolling on
  along the level, or up a wall and back). A ball that fell through a
  turn's floor to the turn below would be a turn's drop away from that stretch, one that
  left through a wall farther than REACH. Never below the foot's floor minus 1 m.
"""
import json
import os
import sys
import tempfile

import numpy as np

RADIUS = 0.3
MASS = 10.0


def option(argv, name, default):
    return argv[argv.index(name) + 1] if name in argv else default


def climbed(line, fraction):
    """The first point of `line` that has risen `fraction` of its rise above its first point."""
    target = line[0, 2] + fraction * (line[:, 2].max() - line[0, 2])
    for k in range(len(line) - 1):
        a, b = line[k, 2], line[k + 1, 2]
        if a < target <= b:
            t = (target - a) / (b - a)
            return line[k] + t * (line[k + 1] - line[k])
    return line[int(np.argmax(line[:, 2]))]


def distance_to_line(p, line, lo, hi):
    """Distance from p to segments lo..hi of line, and the nearest segment's index."""
    a, b = line[lo:hi], line[lo + 1:hi + 1]
    d = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-12), 0, 1)
    q = a + t[:, None] * d
    dist = np.linalg.norm(q - p, axis=1)
    k = int(np.argmin(dist))
    return float(dist[k]), lo + k


def main():
    argv = sys.argv
    folder = os.path.abspath(argv[1])
    engine = option(argv, "--engine", "mujoco")
    fraction = float(option(argv, "--at", "0.6"))
    reach = float(option(argv, "--reach", "4.0"))
    graph = json.load(open(os.path.join(folder, "ground_truth", "graph.json")))
    ramps = [e for e in graph["edges"] if e["kind"] == "ramp"]
    if not ramps:
        sys.exit("FAIL: no ramp in ground_truth/graph.json")
    line = np.array(ramps[0]["polyline"], float)
    foot = line[0]
    start = climbed(line, fraction) + [0, 0, 0.5]
    print(f"ramp: {len(line)} points, {ramps[0]['length_m']:.1f} m, foot {foot.round(2).tolist()}, "
          f"ball at {start.round(2).tolist()}")
    os.chdir(tempfile.gettempdir())
    if engine == "mujoco":
        import mujoco

        spec = mujoco.MjSpec.from_file(os.path.join(folder, "mujoco", "world.xml"))
        # A height field holds one floor per line and the spiral has several: no field may
        # stand under the spiral (the default MJCF gives a ramp's tiles convex slabs).
        pitch = json.load(open(os.path.join(folder, "topology.json")))["tile_pitch_m"]
        fields = 0
        for g in spec.geoms:
            if g.type == mujoco.mjtGeom.mjGEOM_HFIELD:
                fields += 1
                d = np.abs(line[:, :2] - np.array(g.pos[:2])).max(axis=1).min()
                if d < pitch / 2 - 0.01:
                    sys.exit(f"FAIL: a height field ({g.name}) stands under the ramp's spiral")
        print(f"MJCF: {fields} height fields, none under the spiral")
        body = spec.worldbody.add_body(name="ball", pos=start)
        body.add_freejoint(name="ball")
        body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[RADIUS, 0, 0], mass=MASS)
        model = spec.compile()
        model.opt.timestep = 0.004
        data = mujoco.MjData(model)
        dt = model.opt.timestep

        def position():
            return data.qpos[:3].copy()

        def step(n):
            mujoco.mj_step(model, data, nstep=n)
    else:
        import pybullet as p

        p.connect(p.DIRECT)
        p.loadURDF(os.path.join(folder, "urdf", "world.urdf"), useFixedBase=True)
        shape = p.createCollisionShape(p.GEOM_SPHERE, radius=RADIUS)
        ball = p.createMultiBody(MASS, shape, -1, list(start))
        p.changeDynamics(ball, -1, rollingFriction=0.001)
        p.setGravity(0, 0, -9.81)
        dt = 1.0 / 240.0

        def position():
            return np.array(p.getBasePositionAndOrientation(ball)[0])

        def step(n):
            for _ in range(n):
                p.stepSimulation()

    per = max(1, int(round(0.1 / dt)))
    lowest = start[2]
    arc = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(line, axis=0), axis=1))])
    _, seg = distance_to_line(start, line, 0, len(line) - 1)
    home = False
    for k in range(200):
        step(per)
        pos = position()
        lowest = min(lowest, pos[2])
        window = np.nonzero(np.abs(arc - arc[seg]) <= 6.0)[0]
        lo, hi = int(window[0]), min(int(window[-1]), len(line) - 2) + 1
        near_line, seg = distance_to_line(pos, line, lo, hi)
        home = home or (seg == 0 and abs(pos[2] - RADIUS - foot[2]) < 1.0)
        if pos[2] < foot[2] - 1.0:
            sys.exit(f"FAIL: the ball fell below the foot's floor: {pos.round(2).tolist()} at {k / 10:.1f} s")
        if near_line > reach and not (home and abs(pos[2] - RADIUS - foot[2]) < 1.5):
            sys.exit(f"FAIL: the ball left the ramp: {pos.round(2).tolist()} is {near_line:.2f} m "
                     f"from its floor line at {k / 10:.1f} s")
    end = position()
    drop = start[2] - end[2]
    if end[2] > foot[2] + 0.75 * (start[2] - foot[2]):
        sys.exit(f"FAIL: the ball did not roll down: from {start.round(2).tolist()} to {end.round(2).tolist()}")
    print(f"{engine}: rolled {drop:.2f} m down to {end.round(2).tolist()} (lowest {lowest:.2f} m), "
          f"inside the ramp")
    print("OK")


main()
