"""The closed loop as a Gymnasium environment: ``subtgraph/Explore-v0``.

    import gymnasium as gym, subtgraph
    env = gym.make("subtgraph/Explore-v0", preset="cave", seed=7, platform="ground", lidar="vlp-16")
    obs, info = env.reset(seed=7)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    vec = gym.make_vec("subtgraph/Explore-v0", num_envs=8, preset="mine")   # a different world per env

One robot (a ``sense`` platform: ``ground``, a Jackal-sized wheeled robot, or ``aerial``, a small
quadrotor) in a world made from a preset, a pipeline, a world folder or a dataset folder, driven
by velocity commands within its speed, acceleration and turn limits; a ground robot follows its
floor and stops at slopes, steps and gaps it cannot take; a motion into rock is refused (the
robot stops short; ``on_collision="end"`` ends the episode instead), never passed through. Its
LiDAR (any ``sense`` model) scans the world's surface as its head turns, its scans build a voxel
map, artifacts in view are detected and reported to the base station at the entrance over a
radio after the DARPA SubT virtual competition's (breadcrumbs dropped as the baseline does).
No simulator runs: the Rust core (``subtgraph-explore``) steps it thousands of times a second.

The action is ``float32 [2]`` (ground: forward speed, turn rate) or ``[3]`` (aerial: and climb
rate), each in ``[-1, 1]`` as a share of the platform's limit (a negative speed reverses, at
most the platform's reverse limit). Values outside the box are clipped to it, as Gymnasium's
``ClipAction`` does; an action with a NaN, or of another shape, is refused with a ``ValueError``.

Observations (a ``Dict``, each optional through ``observations=``): ``scan`` (the ranges image,
``float32 [rings, columns]`` metres, 0 for no return; or with ``scan="points"`` the same rays as
sensor-frame points ``[rings * columns, 3]``), ``imu`` (specific force and angular rate, body
frame), ``pose`` (``x y z yaw pitch roll`` from the spawn; leave it out for SLAM in the loop),
``map`` (the voxel map around the robot, ``uint8 [nz, ny, nx]``: 0 unknown, 1 free, 2
occupied) and ``artifacts`` (those in view, nearest first: body-frame centre and class number).

Rewards are named terms with weights (``rewards={"explore": 0.1, ...}``): ``explore`` (cubic
metres newly known free), ``detect`` (artifacts detected), ``report`` (reports delivered),
``distance`` (metres driven), ``collision`` (refused motions), ``time`` (each step).
"""

from __future__ import annotations

import math
import os
from typing import Any, Sequence

import numpy as np

try:
    import gymnasium as gym
    from gymnasium import spaces
except ImportError as e:  # pragma: no cover - said when the module is used
    raise ImportError(
        "subtgraph.explore needs gymnasium: pip install gymnasium"
    ) from e

from . import _native
from .errors import ConfigError

OBSERVATIONS = ("scan", "imu", "pose", "map", "artifacts")
"""The observations an environment may give."""

ARTIFACT_CLASSES = (
    "survivor",
    "backpack",
    "cell-phone",
    "drill",
    "fire-extinguisher",
    "gas",
    "vent",
    "helmet",
    "rope",
    "cube",
)
"""Class numbers of the ``artifacts`` observation: 1 is the first."""


def _world_folders(dataset: str | os.PathLike) -> list[str]:
    """The world folders of a dataset folder (those with a world.toml), in name order."""
    root = os.fspath(dataset)
    if not os.path.isdir(root):
        raise ConfigError(f"dataset={root!r}: no such folder; give a folder made by `subtgraph dataset`")
    found = sorted(
        os.path.join(root, name)
        for name in os.listdir(root)
        if os.path.isfile(os.path.join(root, name, "world.toml"))
    )
    if not found:
        raise ConfigError(f"dataset={root!r} holds no world folder (none has a world.toml)")
    return found


class ExploreEnv(gym.Env):
    """One robot exploring a subtgraph world; see the module's documentation.

    The robot's voxel map is built while the ``map`` observation or the ``explore`` reward needs
    it (``build_map`` forces it either way).

    The world: ``preset`` (``cave``, ``mine``, ``lava-tube``) or ``pipeline`` (a file), made with
    ``seed`` (default: the pipeline's own) plus ``world_index``, ``[artifacts]`` added when the
    pipeline has none (``artifacts=False`` keeps it without); or ``world`` (a world folder made
    with ``--format ground-truth``); or ``dataset`` (a dataset folder: its ``world_index``-th
    world, in name order). ``gym.make_vec`` gives env ``i`` the world ``world_index=i``.
    """

    metadata = {"render_modes": []}

    def __init__(
        self,
        preset: str | None = None,
        seed: int | None = None,
        *,
        pipeline: str | os.PathLike | None = None,
        world: str | os.PathLike | None = None,
        dataset: str | os.PathLike | None = None,
        world_index: int = 0,
        platform: str = "ground",
        lidar: str = "vlp-16",
        lidar_columns: int | None = None,
        observations: Sequence[str] = ("scan", "imu", "pose"),
        scan: str = "ranges",
        control_rate: float = 10.0,
        map_voxel: float = 0.5,
        map_shape: Sequence[int] = (8, 32, 32),
        max_steps: int = 3000,
        on_collision: str = "refuse",
        rewards: dict[str, float] | None = None,
        breadcrumbs: int = 6,
        noiseless: bool = False,
        artifacts: bool = True,
        max_artifacts: int = 8,
        build_map: bool | None = None,
        render_mode: str | None = None,
    ) -> None:
        unknown = [o for o in observations if o not in OBSERVATIONS]
        if unknown:
            raise ConfigError(
                f"observations={list(observations)!r}: unknown {unknown!r}; choose among {list(OBSERVATIONS)}"
            )
        if scan not in ("ranges", "points"):
            raise ConfigError(f"scan={scan!r}: choose 'ranges' (a ranges image) or 'points'")
        if render_mode is not None:
            raise ConfigError(f"render_mode={render_mode!r}: this environment does not render (None)")
        if len(map_shape) != 3 or not all(isinstance(n, int) and 1 <= n <= 256 for n in map_shape):
            raise ConfigError(f"map_shape={tuple(map_shape)!r}: three whole numbers from 1 to 256 (nz, ny, nx)")
        if not (isinstance(max_artifacts, int) and 1 <= max_artifacts <= 64):
            raise ConfigError(f"max_artifacts={max_artifacts!r}: a whole number from 1 to 64")
        if world_index < 0:
            raise ConfigError(f"world_index={world_index}: 0 or more")
        if dataset is not None:
            if world is not None or preset is not None or pipeline is not None:
                raise ConfigError("give dataset= alone, without preset=, pipeline= or world=")
            folders = _world_folders(dataset)
            world = folders[world_index % len(folders)]
        if world is not None and seed is not None:
            raise ConfigError("seed= picks a preset's or pipeline's world; a world folder has its own (leave seed= out)")
        self.observations = tuple(observations)
        self.scan_kind = scan
        self.map_shape = tuple(map_shape)
        self.max_artifacts = max_artifacts
        self.render_mode = None
        self._core = _native.ExploreCore(
            preset=preset,
            pipeline=None if pipeline is None else os.fspath(pipeline),
            world=None if world is None else os.fspath(world),
            seed=seed,
            world_index=0 if world is not None else int(world_index),
            platform=platform,
            lidar=lidar,
            lidar_columns=lidar_columns,
            control_rate=float(control_rate),
            map_voxel=float(map_voxel),
            max_steps=int(max_steps),
            on_collision=on_collision,
            rewards=rewards,
            breadcrumbs=int(breadcrumbs),
            noiseless=bool(noiseless),
            build_map=bool(
                build_map
                if build_map is not None
                else "map" in observations or (rewards or {}).get("explore", 0.1) != 0
            ),
            artifacts=bool(artifacts),
        )
        d = self._core.describe()
        self.description = d
        flies = d["flies"]
        n = 3 if flies else 2
        self.action_space = spaces.Box(-1.0, 1.0, shape=(n,), dtype=np.float32)
        parts: dict[str, spaces.Space] = {}
        rings, columns, far = d["rings"], d["columns"], float(d["max_range"])
        if "scan" in self.observations:
            if scan == "ranges":
                parts["scan"] = spaces.Box(0.0, far, shape=(rings, columns), dtype=np.float32)
            else:
                parts["scan"] = spaces.Box(-far, far, shape=(rings * columns, 3), dtype=np.float32)
        if "imu" in self.observations:
            # Far beyond what a platform can do: a crash on an IMU's 16 g range is 160 m/s^2.
            parts["imu"] = spaces.Box(-1000.0, 1000.0, shape=(6,), dtype=np.float32)
        if "pose" in self.observations:
            # Metres from the spawn (a world is at most a few kilometres across) and radians.
            parts["pose"] = spaces.Box(-1e5, 1e5, shape=(6,), dtype=np.float32)
        if "map" in self.observations:
            parts["map"] = spaces.Box(0, 2, shape=self.map_shape, dtype=np.uint8)
        if "artifacts" in self.observations:
            r = float(d["detection_range"])
            parts["artifacts"] = spaces.Box(
                low=np.array([[-r, -r, -r, 0.0]] * max_artifacts, dtype=np.float32),
                high=np.array([[r, r, r, float(len(ARTIFACT_CLASSES))]] * max_artifacts, dtype=np.float32),
                dtype=np.float32,
            )
        if not parts:
            raise ConfigError("observations=(): name at least one of " + ", ".join(OBSERVATIONS))
        self.observation_space = spaces.Dict(parts)
        self._limits = np.array(
            [d["max_speed"], d["max_yaw_rate"], d["max_climb"]][:n], dtype=np.float64
        )
        self._reverse = float(d["max_reverse"])

    def _observe(self) -> dict[str, np.ndarray]:
        core = self._core
        obs: dict[str, np.ndarray] = {}
        if "scan" in self.observations:
            obs["scan"] = core.ranges() if self.scan_kind == "ranges" else core.points()
        if "imu" in self.observations:
            obs["imu"] = core.imu()
        if "pose" in self.observations:
            obs["pose"] = core.pose()
        if "map" in self.observations:
            obs["map"] = core.local_map(*self.map_shape)
        if "artifacts" in self.observations:
            a = core.artifacts_in_view(self.max_artifacts)
            r = float(self.description["detection_range"])
            a[:, :3] = np.clip(a[:, :3], -r, r)
            obs["artifacts"] = a
        return obs

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None):
        super().reset(seed=seed)
        if options:
            raise ConfigError(f"reset(options={options!r}): this environment takes no reset options")
        self._core.reset(int(self.np_random.integers(0, 2**63 - 1)))
        info = dict(self._core.totals())
        return self._observe(), info

    def _command(self, action) -> tuple[float, float, float]:
        a = np.asarray(action, dtype=np.float64)
        if a.shape != self.action_space.shape:
            raise ValueError(
                f"action of shape {a.shape}: this environment takes {self.action_space.shape} "
                "(forward speed, turn rate" + (", climb rate" if a.shape == (3,) else "") + "), each in [-1, 1]"
            )
        if not np.all(np.isfinite(a)):
            raise ValueError(f"action {a.tolist()} is not finite: every value must be a number in [-1, 1]")
        a = np.clip(a, -1.0, 1.0)
        speed = a[0] * (self._limits[0] if a[0] >= 0 else self._reverse)
        yaw = a[1] * self._limits[1]
        climb = a[2] * self._limits[2] if len(a) > 2 else 0.0
        return float(speed), float(yaw), float(climb)

    def step(self, action):
        speed, yaw, climb = self._command(action)
        reward, terminated, truncated, info = self._core.step(speed, yaw, climb)
        info.update(self._core.totals())
        return self._observe(), float(reward), bool(terminated), bool(truncated), info


def make_vector_env(num_envs: int = 1, *, asynchronous: bool = False, **kwargs):
    """``gym.make_vec``'s vector entry point: ``num_envs`` environments, env ``i`` in the world
    ``world_index=i`` (a preset's or pipeline's seed plus ``i``, or a dataset's ``i``-th world),
    stepped in this process (``SyncVectorEnv``) or in one process each (``asynchronous=True``)."""
    if not (isinstance(num_envs, int) and num_envs >= 1):
        raise ConfigError(f"num_envs={num_envs!r}: a whole number, 1 or more")
    first = int(kwargs.pop("world_index", 0))
    kwargs.pop("max_episode_steps", None)
    fns = [
        (lambda i=i: ExploreEnv(world_index=first + i, **kwargs)) for i in range(num_envs)
    ]
    if asynchronous:
        return gym.vector.AsyncVectorEnv(fns)
    return gym.vector.SyncVectorEnv(fns)


def register() -> None:
    """Registers ``subtgraph/Explore-v0`` (done on ``import subtgraph`` when gymnasium is
    installed)."""
    if "subtgraph/Explore-v0" in gym.registry:
        return
    gym.register(
        id="subtgraph/Explore-v0",
        entry_point="subtgraph.explore:ExploreEnv",
        vector_entry_point="subtgraph.explore:make_vector_env",
    )
