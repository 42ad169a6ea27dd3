"""Trains Stable-Baselines3's PPO on `subtgraph/Explore-v0` for a few thousand steps and
compares the policy with a random one on the same worlds (the example of
docs/src/closed-loop.md, run once and measured there; PyTorch is too heavy for the test suite).

    python examples/python/ppo_explore.py [--steps 20000] [--envs 4]

Four copies of the small cave of examples/explore/small-cave.toml, a world each (seeds 5 to 8),
step in this process; the policy sees the ranges image, the IMU and the pose and is rewarded for
new free space (the default reward). Prints the training speed and the mean return of 10
evaluation episodes of the trained and of a random policy on a fifth world (seed 9).
"""
import argparse
import pathlib
import time

import gymnasium as gym
import numpy as np
from stable_baselines3 import PPO
from stable_baselines3.common.vec_env import DummyVecEnv

import subtgraph  # noqa: F401  (registers the environment)

HERE = pathlib.Path(__file__).resolve().parent
PIPELINE = HERE.parent / "explore" / "small-cave.toml"


def evaluate(env, policy, episodes):
    returns = []
    for k in range(episodes):
        obs, _ = env.reset(seed=1000 + k)
        done, total = False, 0.0
        while not done:
            action = policy(obs)
            obs, r, term, trunc, _ = env.step(action)
            total += r
            done = term or trunc
        returns.append(total)
    return float(np.mean(returns)), float(np.std(returns))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=20000)
    ap.add_argument("--envs", type=int, default=4)
    a = ap.parse_args()
    kw = dict(pipeline=PIPELINE, max_steps=300, observations=("scan", "imu", "pose"))
    # Stable-Baselines3 steps its own vector class, not Gymnasium's (`gym.make_vec`): the same
    # worlds, env i the pipeline's seed plus i.
    vec = DummyVecEnv([
        (lambda i=i: gym.make("subtgraph/Explore-v0", world_index=i, **kw)) for i in range(a.envs)
    ])
    model = PPO("MultiInputPolicy", vec, n_steps=256, batch_size=256, seed=0, verbose=0, device="cpu")
    t = time.perf_counter()
    model.learn(total_timesteps=a.steps)
    took = time.perf_counter() - t
    print(f"PPO: {a.steps} steps in {took:.0f} s ({a.steps / took:.0f} steps/s, training included)")
    test = gym.make("subtgraph/Explore-v0", world_index=4, **kw)
    trained = evaluate(test, lambda o: model.predict(o, deterministic=True)[0], 10)
    rng = np.random.default_rng(0)
    random = evaluate(test, lambda o: rng.uniform(-1, 1, 2).astype(np.float32), 10)
    print(f"mean return over 10 episodes of 300 steps on an unseen world: PPO {trained[0]:.1f} (sd {trained[1]:.1f}), random {random[0]:.1f} (sd {random[1]:.1f})")


if __name__ == "__main__":
    main()
