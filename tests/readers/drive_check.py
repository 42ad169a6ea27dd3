"""Drives a ball along a subtgraph world's ground-truth route in MuJoCo or PyBullet.

Usage: drive_check.py WORLD_FOLDER --engine mujoco|pybullet [--gap | --wall] [--speed M_PER_S]
                      [--to-level L]

The route: ground_truth/graph.json, from the start node to the dead end of the start's level
farthest from it by path length (Dijkstra over the corridors of that level), along the
corridors' polylines: with a mesh, the middle of each tile's own passage on its floor (its
axis, from the collision surface), without one the cell centres. When
ground_truth/spawn_poses.json was computed from the collision surface, the route starts at the
first robot's spawn pose and ends at its goal pose (on the floor: a dead end's centre can be
rock where a tile caps its passage early).

The body: a free sphere of radius 0.3 m, pushed by a simple velocity controller (a horizontal
force proportional to the velocity error towards the next waypoint, capped at twice its
weight, so a wall or a step at a seam stops it as it would stop a robot). It loads
mujoco/world.xml (height fields by default) or urdf/world.urdf, dropped just above the floor
at the start.

Checks, exiting non-zero with a line starting FAIL on the first failure:
- every waypoint is reached within 1 m (horizontally), each within three times the
  straight-line time from the previous one plus 5 s (no invisible wall at tile or part seams);
- the ball never falls below the floor: its centre stays above the lowest floor under the
  route's waypoints (MuJoCo's or PyBullet's own ray casts) minus 1 m;
- the whole drive takes at most three times the route's straight-line time plus 10 s.

--to-level L: the route goes on by ramps (edges of kind "ramp", along their spiral floor) to
the dead end of level L farthest from the start; a waypoint then counts as reached within 1 m
horizontally and 1.5 m in height of its floor point (a spiral passes over its own waypoints),
and the ball must stay above the floor under the waypoint it drives to (minus 1 m) all along.

--gap removes the floor of one tile in the middle of the route from the collision world
(MuJoCo: that tile's floor height field stops colliding; PyBullet: the collision mesh's floor
triangles in that tile are dropped): the ball falls through, so the drive must fail. The test
runs it, so the check is known able to fail.
--wall adds an invisible wall instead: a static box 0.2 m thick across the passage on the
seam between that tile and the next on the route (as a badly joined tile or part would
leave): the ball is stopped there, so the drive must fail too.
"""
import heapq
import json
import os
import sys
import tempfile
import time

import numpy as np

RADIUS = 0.3
MASS = 10.0
REACH = 1.0


def option(argv, name, default):
    return argv[argv.index(name) + 1] if name in argv else default


def route(graph, to_level=None):
    """The waypoints (cell centres) from the start node to the farthest dead end of its level,
    or, with to_level, of that level by ramps."""
    nodes = {n["id"]: n for n in graph["nodes"]}
    start = graph["start"]
    level = nodes[start]["level"]
    goal_level = level if to_level is None else to_level
    adjacent = {}
    for e in graph["edges"]:
        if to_level is not None and e["kind"] in ("corridor", "ramp"):
            pass
        elif e["kind"] != "corridor" or nodes[e["from"]]["level"] != level:
            continue
        elif nodes[e["to"]]["level"] != level:
            continue
        line = [tuple(p) for p in e["polyline"]]
        adjacent.setdefault(e["from"], []).append((e["to"], e["length_m"], line))
        adjacent.setdefault(e["to"], []).append((e["from"], e["length_m"], line[::-1]))
    dist, back = {start: 0.0}, {}
    queue = [(0.0, start)]
    while queue:
        d, n = heapq.heappop(queue)
        if d > dist[n]:
            continue
        for m, length, line in adjacent.get(n, []):
            if d + length < dist.get(m, float("inf")):
                dist[m] = d + length
                back[m] = (n, line)
                heapq.heappush(queue, (d + length, m))
    ends = [n for n in dist if nodes[n]["kind"] == "dead-end" and n != start
            and nodes[n]["level"] == goal_level]
    if not ends:
        sys.exit(f"FAIL: no dead end of level {goal_level} is reachable from the start")
    goal = max(ends, key=lambda n: (dist[n], -n))
    lines, n = [], goal
    while n != start:
        n, line = back[n]
        lines.append(line)
    points = []
    for line in reversed(lines):
        for p in line:
            if not points or points[-1] != p:
                points.append(p)
    return np.array(points, float), goal, dist[goal]


def corners(points):
    """Indices of the waypoints where the route turns by more than 30 degrees (a polyline
    along the middle of a real passage bends a little at almost every point)."""
    out = set()
    for i in range(1, len(points) - 1):
        a, b = points[i, :2] - points[i - 1, :2], points[i + 1, :2] - points[i, :2]
        if abs(a[0] * b[1] - a[1] * b[0]) > 0.5 * np.linalg.norm(a) * np.linalg.norm(b):
            out.add(i)
    return out


def gap_cell(points, turning, centre, pitch):
    """The waypoint, on a straight stretch near the middle of the route and at least 2 m inside
    its tile (a waypoint on a seam between two tiles would keep the neighbour's floor under it),
    whose tile loses its floor. `centre` is any tile's centre (a node's position in topology.json: cell centres)."""
    middle = len(points) // 2

    def inside(p):
        off = (np.asarray(p[:2]) - np.asarray(centre[:2]) + pitch / 2) % pitch - pitch / 2
        return bool(np.all(np.abs(off) < pitch / 2 - 2.0))

    for k in sorted(range(1, len(points) - 1), key=lambda i: (abs(i - middle), i)):
        if k not in turning and inside(points[k]):
            return k
    sys.exit("FAIL: the route is too short to cut a gap in")


def wall_box(points, k, pitch):
    """The centre, half sizes and yaw of a wall across the route on the seam after waypoint k."""
    a, b = points[k], points[k + 1]
    d = b[:2] - a[:2]
    centre = [float(a[0] + b[0]) / 2, float(a[1] + b[1]) / 2, float(a[2]) + 2.0]
    return centre, [0.1, pitch / 2, 4.0], float(np.arctan2(d[1], d[0]))


class Mujoco:
    def __init__(self, folder, start, gap, pitch, wall=None):
        import mujoco

        self.mj = mujoco
        spec = mujoco.MjSpec.from_file(os.path.join(folder, "mujoco", "world.xml"))
        if gap is not None:
            cut = 0
            for g in spec.geoms:
                if g.type == mujoco.mjtGeom.mjGEOM_HFIELD and "-floor-" in g.hfieldname:
                    if np.max(np.abs(np.array(g.pos[:2]) - gap[:2])) < pitch / 2 - 1e-6:
                        g.contype, g.conaffinity = 0, 0
                        cut += 1
            if cut == 0:
                sys.exit(f"FAIL: no floor height field found under {gap.tolist()} to cut")
        if wall is not None:
            centre, half, yaw = wall
            spec.worldbody.add_geom(type=mujoco.mjtGeom.mjGEOM_BOX, pos=centre, size=half,
                                    quat=[np.cos(yaw / 2), 0, 0, np.sin(yaw / 2)], group=4)
        body = spec.worldbody.add_body(name="ball", pos=start)
        body.add_freejoint(name="ball")
        body.add_geom(type=mujoco.mjtGeom.mjGEOM_SPHERE, size=[RADIUS, 0, 0], mass=MASS)
        self.model = spec.compile()
        self.model.opt.timestep = 0.004
        self.data = mujoco.MjData(self.model)
        self.ball = self.model.body("ball").id
        mujoco.mj_forward(self.model, self.data)
        self.dt = self.model.opt.timestep

    def floor(self, at):
        geomid = np.zeros(1, np.int32)
        groups = np.array([1, 0, 0, 1, 0, 0], np.uint8)
        d = self.mj.mj_ray(self.model, self.data, np.asarray(at, float),
                           np.array([0.0, 0.0, -1.0]), groups, 1, self.ball, geomid)
        return at[2] - d if d >= 0 else None

    def state(self):
        return self.data.qpos[:3].copy(), self.data.qvel[:3].copy()

    def step(self, force, n):
        self.data.xfrc_applied[self.ball, :3] = force
        self.mj.mj_step(self.model, self.data, nstep=n)


class Bullet:
    def __init__(self, folder, start, gap, pitch, wall=None):
        import pybullet as p

        self.p = p
        urdf = os.path.join(folder, "urdf", "world.urdf")
        self.tmp = tempfile.TemporaryDirectory()
        if gap is not None:
            urdf = self.cut(urdf, gap, pitch)
        p.connect(p.DIRECT)
        self.world = p.loadURDF(urdf, useFixedBase=True)
        if wall is not None:
            centre, half, yaw = wall
            box = p.createCollisionShape(p.GEOM_BOX, halfExtents=half)
            p.createMultiBody(0, box, -1, centre, p.getQuaternionFromEuler([0, 0, yaw]))
        shape = p.createCollisionShape(p.GEOM_SPHERE, radius=RADIUS)
        self.ball = p.createMultiBody(MASS, shape, -1, list(start))
        p.changeDynamics(self.ball, -1, rollingFriction=0.001)
        p.setGravity(0, 0, -9.81)
        self.dt = 1.0 / 240.0

    def cut(self, urdf, gap, pitch):
        """A copy of the URDF whose collision meshes lack the floor triangles of gap's tile."""
        text = open(urdf).read()
        base = os.path.dirname(urdf)
        cut = 0
        for i, piece in enumerate(text.split('<collision')[1:]):
            name = piece.split('filename="', 1)[1].split('"', 1)[0]
            path = os.path.normpath(os.path.join(base, name))
            vertices, kept = [], []
            for line in open(path):
                if line.startswith("v "):
                    vertices.append([float(v) for v in line.split()[1:4]])
                if line.startswith("f "):
                    ids = [int(w.split("/")[0]) for w in line.split()[1:]]
                    c = np.mean([vertices[k - 1 if k > 0 else k] for k in ids], axis=0)
                    if np.max(np.abs(c[:2] - gap[:2])) < pitch / 2 and c[2] < gap[2] + 1.5:
                        cut += 1
                        continue
                kept.append(line)
            copy = os.path.join(self.tmp.name, f"collision-{i}.obj")
            open(copy, "w").write("".join(kept))
            text = text.replace(f'filename="{name}"', f'filename="{copy}"', 1)
        if cut == 0:
            sys.exit(f"FAIL: no floor triangle found under {gap.tolist()} to cut")
        # Every other mesh by its absolute path, so the copy can live outside the world folder.
        text = text.replace('filename="../', f'filename="{os.path.dirname(base)}/')
        out = os.path.join(self.tmp.name, "world-gap.urdf")
        open(out, "w").write(text)
        return out

    def floor(self, at):
        hit = self.p.rayTest(list(at), [at[0], at[1], at[2] - 50])[0]
        return hit[3][2] if hit[0] == self.world else None

    def state(self):
        pos, _ = self.p.getBasePositionAndOrientation(self.ball)
        vel, _ = self.p.getBaseVelocity(self.ball)
        return np.array(pos), np.array(vel)

    def step(self, force, n):
        for _ in range(n):
            pos, _ = self.p.getBasePositionAndOrientation(self.ball)
            self.p.applyExternalForce(self.ball, -1, list(force), pos, self.p.WORLD_FRAME)
            self.p.stepSimulation()


def main():
    argv = sys.argv
    folder = os.path.abspath(argv[1])
    engine = option(argv, "--engine", "mujoco")
    speed = float(option(argv, "--speed", "3.0"))
    graph = json.load(open(os.path.join(folder, "ground_truth", "graph.json")))
    topology = json.load(open(os.path.join(folder, "topology.json")))
    pitch = topology["tile_pitch_m"]
    to_level = option(argv, "--to-level", None)
    to_level = None if to_level is None else int(to_level)
    points, goal, length = route(graph, to_level)
    # The start and the goal on the floor, where the ground truth put them (from the collision
    # surface): a dead end's centre can be rock where a tile caps its passage early.
    spawn_file = os.path.join(folder, "ground_truth", "spawn_poses.json")
    if os.path.exists(spawn_file):
        poses = json.load(open(spawn_file))
        robot = poses["robots"][0]
        if poses["source"] == "collision-mesh":
            points[0] = robot["spawn"]["position"]
            if robot["goal"]["node"] == goal:
                points[-1] = robot["goal"]["pose"]["position"]
            print("start and goal from ground_truth/spawn_poses.json")
    turning = corners(points)
    k = gap_cell(points, turning, topology["nodes"][0]["position"], pitch)
    gap = points[k] if "--gap" in argv else None
    wall = wall_box(points, k, pitch) if "--wall" in argv else None
    print(f"route: {len(points)} waypoints, {length:.0f} m by the graph, to dead end {goal}"
          + (f"; floor cut under {gap.tolist()}" if gap is not None else "")
          + (f"; a wall across the route at {wall[0]}" if wall is not None else ""))
    os.chdir(tempfile.gettempdir())  # not the world folder: paths must resolve by themselves
    t = time.time()
    sim = (Mujoco if engine == "mujoco" else Bullet)(folder, points[0] + [0, 0, 1.5], gap, pitch,
                                                       wall)
    floors = [sim.floor(p + [0, 0, 1.5]) for p in points]
    found = [f for f in floors if f is not None]
    if floors[0] is None or not found:
        sys.exit("FAIL: no floor under the start")
    lowest = min(found) - 1.0
    if to_level is not None and None in floors:
        sys.exit(f"FAIL: no floor under waypoint {floors.index(None)}")
    print(f"{engine}: loaded in {time.time() - t:.2f} s; floors under the waypoints "
          f"{min(found):.2f} .. {max(found):.2f} m ({floors.count(None)} without)")
    # Settle on the floor at the start.
    sim.step(np.zeros(3), int(1.0 / sim.dt))
    straight = float(np.sum(np.linalg.norm(np.diff(points[:, :2], axis=0), axis=1)))
    budget = 3.0 * straight / speed + 10.0
    every = 5  # control period in steps
    clock, i, since, worst = 0.0, 1, 0.0, 0.0
    t = time.time()
    while i < len(points):
        pos, vel = sim.state()
        under = lowest if to_level is None else min(floors[i - 1], floors[i]) - 1.0
        if pos[2] < under:
            sys.exit(f"FAIL: the ball fell below the floor at {pos.round(2).tolist()} "
                     f"(lowest floor {under + 1.0:.2f} m) on the way to waypoint {i} "
                     f"{points[i].tolist()}")
        to = points[i][:2] - pos[:2]
        level = to_level is None or abs(pos[2] - RADIUS - points[i][2]) < 1.5
        if np.linalg.norm(to) < REACH and level:
            worst = max(worst, since / (np.linalg.norm(points[i][:2] - points[i - 1][:2]) / speed))
            i, since = i + 1, 0.0
            continue
        allowed = 3.0 * np.linalg.norm(points[i][:2] - points[i - 1][:2]) / speed + 5.0
        if since > allowed or clock > budget:
            sys.exit(f"FAIL: stuck at {pos.round(2).tolist()} on the way to waypoint {i} "
                     f"{points[i].tolist()} after {since:.1f} s (allowed {allowed:.1f} s; "
                     f"{clock:.0f} s of {budget:.0f} s in all)")
        want = speed * to / np.linalg.norm(to)
        force = np.zeros(3)
        force[:2] = 4.0 * MASS * (want - vel[:2])
        cap = 2.0 * MASS * 9.81
        norm = np.linalg.norm(force)
        if norm > cap:
            force *= cap / norm
        sim.step(force, every)
        clock += every * sim.dt
        since += every * sim.dt
    print(f"reached all {len(points)} waypoints in {clock:.1f} simulated s "
          f"(straight line {straight / speed:.1f} s, {clock / (straight / speed):.2f} x; "
          f"slowest leg {worst:.2f} x) in {time.time() - t:.1f} s")
    print("OK")


main()
