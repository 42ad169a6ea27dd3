"""The Gymnasium environment `subtgraph/Explore-v0`: Gymnasium's own checker, seeded
rollouts, vector environments with a world each, trajectories kept out of the rock (trimesh
against the world's collision surface), and bad actions and options refused or clipped as
Gymnasium documents. On a small cave, so the whole module takes seconds."""

import math
import textwrap

import numpy as np
import pytest

gym = pytest.importorskip("gymnasium")

import subtgraph  # noqa: E402  (registers the environment)
from subtgraph.explore import ExploreEnv  # noqa: E402

SMALL = textwrap.dedent(
    """
    [world]
    seed = 5
    levels = 1
    rows = 20
    cols = 20
    tile_pitch = 16.0
    level_height = 16.0

    [topology]
    loops = 1
    t_junctions = 1
    intersections = 1

    [route]
    type = "parabolic"

    [tileset]
    type = "cave"
    width = 5.0
    height = 4.0
    resolution = 8
    collision_resolution = 8
    rocks = 0

    [artifacts]
    count = 6
    min_distance_from_start = 10
    min_spacing = 5
    """
)


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    path = tmp_path_factory.mktemp("explore") / "small-cave.toml"
    path.write_text(SMALL)
    return path


def test_gymnasium_checks_the_environment(small):
    from gymnasium.utils.env_checker import check_env

    env = gym.make(
        "subtgraph/Explore-v0",
        pipeline=small,
        observations=("scan", "imu", "pose", "map", "artifacts"),
        max_steps=200,
    )
    check_env(env.unwrapped, skip_render_check=True)
    obs, info = env.reset(seed=3)
    assert env.observation_space.contains(obs)
    assert obs["scan"].shape == (16, 180)
    assert (obs["scan"] > 0).mean() > 0.5, "most rays return inside a cave"
    assert info["artifacts"] == 6
    env.close()


def rollout(env, seed, steps=60):
    obs, _ = env.reset(seed=seed)
    rng = np.random.default_rng(seed)
    out = [obs["scan"].copy()]
    rewards = []
    for _ in range(steps):
        obs, r, term, trunc, info = env.step(rng.uniform(-1, 1, env.action_space.shape).astype(np.float32))
        out.append(obs["scan"].copy())
        rewards.append(r)
        if term or trunc:
            break
    return np.stack(out), np.array(rewards)


def test_the_same_seed_gives_the_same_rollout(small):
    a = ExploreEnv(pipeline=small)
    b = ExploreEnv(pipeline=small)
    sa, ra = rollout(a, 11)
    sb, rb = rollout(b, 11)
    assert np.array_equal(sa, sb) and np.array_equal(ra, rb)
    # Another seed: other range noise.
    sc, _ = rollout(b, 12)
    assert not np.array_equal(sa, sc)
    # The same environment reset again repeats itself.
    sd, rd = rollout(a, 11)
    assert np.array_equal(sa, sd) and np.array_equal(ra, rd)


def test_a_vector_env_has_a_world_each(small):
    vec = gym.make_vec("subtgraph/Explore-v0", num_envs=2, pipeline=small, max_steps=50)
    seeds = [e.unwrapped.description["world_seed"] for e in vec.envs]
    assert seeds == [5, 6]
    obs, _ = vec.reset(seed=1)
    assert obs["scan"].shape == (2, 16, 180)
    obs, r, term, trunc, info = vec.step(vec.action_space.sample())
    assert r.shape == (2,)
    vec.close()


def test_the_robot_never_enters_the_rock(small):
    """Drives forward into whatever is ahead, turning now and then: every pose's clearance
    point keeps the platform's clearance from the collision surface, by trimesh."""
    trimesh = pytest.importorskip("trimesh")
    pytest.importorskip("rtree")
    env = ExploreEnv(pipeline=small, observations=("pose",), max_steps=400)
    env.reset(seed=0)
    positions, refused = [], 0
    for k in range(400):
        action = np.array([1.0, 0.6 if (k // 40) % 2 else -0.2], dtype=np.float32)
        _, _, term, trunc, info = env.step(action)
        positions.append(info["position"])
        refused += info["refused"] is not None
        if term or trunc:
            break
    assert refused > 0, "driving ahead meets rock"
    world = subtgraph.generate(pipeline=small)
    v, f = world.mesh.collision
    mesh = trimesh.Trimesh(np.asarray(v, dtype=float), np.asarray(f), process=True)
    points = np.array(positions) + np.array([0.0, 0.0, 0.55])
    _, d, _ = trimesh.proximity.closest_point(mesh, points)
    assert d.min() >= 0.3 - 1e-6, d.min()
    assert mesh.contains(points).all()


def test_bad_actions_and_options_are_refused_or_clipped(small, tmp_path):
    env = ExploreEnv(pipeline=small, observations=("pose",))
    env.reset(seed=1)
    with pytest.raises(ValueError, match="not finite"):
        env.step(np.array([math.nan, 0.0], dtype=np.float32))
    with pytest.raises(ValueError, match="shape"):
        env.step(np.zeros(3, dtype=np.float32))
    # Beyond the box: clipped, the same as the box's edge.
    a = ExploreEnv(pipeline=small, observations=("pose",))
    b = ExploreEnv(pipeline=small, observations=("pose",))
    a.reset(seed=2)
    b.reset(seed=2)
    for _ in range(20):
        oa = a.step(np.array([7.0, -3.0], dtype=np.float32))[0]
        ob = b.step(np.array([1.0, -1.0], dtype=np.float32))[0]
    assert np.array_equal(oa["pose"], ob["pose"])
    with pytest.raises(subtgraph.ConfigError, match="'gps'"):
        ExploreEnv(pipeline=small, observations=("scan", "gps"))
    with pytest.raises(subtgraph.ConfigError, match="bogus.*explore"):
        ExploreEnv(pipeline=small, rewards={"bogus": 1.0})
    with pytest.raises(subtgraph.ConfigError, match="submarine"):
        ExploreEnv(pipeline=small, platform="submarine")
    with pytest.raises(TypeError, match="colour"):
        ExploreEnv(pipeline=small, colour="red")
    bare = tmp_path / "bare"
    subtgraph.generate(pipeline=small).export(bare, formats=["obj"])
    with pytest.raises(subtgraph.Error, match="ground-truth"):
        ExploreEnv(world=bare)


def test_rewards_are_named_terms(small):
    env = ExploreEnv(pipeline=small, rewards={"explore": 0.0, "time": -1.0, "collision": 0.0, "detect": 0.0, "report": 0.0})
    env.reset(seed=4)
    _, r, _, _, info = env.step(np.zeros(2, dtype=np.float32))
    assert r == -1.0 and info["reward_terms"]["time"] == 1.0
