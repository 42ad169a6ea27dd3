"""A MuJoCo loop that generates a new cave for every episode, from memory: no files.

Each reset makes a world (milliseconds for the layout, under a second with its meshes), loads
its MJCF from a string (collision height fields, no visual meshes: what physics needs), drops
a ball at the first robot's spawn pose and rolls it for a few seconds. The seed of episode k is k, so a run is
reproducible.

    python examples/python/mujoco_episodes.py --episodes 3
"""

import argparse
import math

import mujoco

import subtgraph

BALL = """
  <worldbody>
    <body name="ball" pos="{x} {y} {z}">
      <freejoint/>
      <geom type="sphere" size="0.4" mass="20" rgba="0.9 0.3 0.1 1" contype="1" conaffinity="1"/>
    </body>
  </worldbody>
</mujoco>
"""


def episode(seed, seconds):
    world = subtgraph.generate(preset="cave", seed=seed)
    # The first robot's spawn pose: on the floor of the start tile's own passage (a cave's
    # passage bends away from the cell centre, and its floor slopes).
    poses = world.ground_truth(formats=["spawn-poses"])["ground_truth/spawn_poses.json"]
    spawn = poses["robots"][0]["spawn"]
    (x, y, z), yaw = spawn["position"], spawn["yaw"]
    # The world's MJCF with a ball appended before its closing tag.
    xml = world.mjcf().rsplit("</mujoco>", 1)[0] + BALL.format(x=x, y=y, z=z + 2.0)
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    data.qvel[0] = 2.0 * math.cos(yaw)  # roll along the passage
    data.qvel[1] = 2.0 * math.sin(yaw)
    steps = int(seconds / model.opt.timestep)
    lowest = z + 2.0
    for _ in range(steps):
        mujoco.mj_step(model, data)
        lowest = min(lowest, data.qpos[2])
    return world, data.qpos[:3].copy(), lowest - z


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--episodes", type=int, default=5)
    ap.add_argument("--seconds", type=float, default=2.0)
    args = ap.parse_args()
    for k in range(args.episodes):
        world, end, lowest = episode(k, args.seconds)
        print(
            f"episode {k}: {world.shape[1]} x {world.shape[2]} cells, {len(world.graph['nodes'])} "
            f"nodes; ball ended at ({end[0]:.1f}, {end[1]:.1f}, {end[2]:.2f}), "
            f"lowest {lowest:+.2f} m from the floor"
        )
        # Resting on the floor, never through it.
        assert lowest > -0.5, "the ball fell through the floor"


if __name__ == "__main__":
    main()
