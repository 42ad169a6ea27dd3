"""Rays and LiDAR scans from Python (``World.raycast``, ``World.lidar_scan``), checked with
trimesh, which computes the same things its own way."""

import numpy as np
import pytest

import subtgraph


@pytest.fixture(scope="module")
def cave():
    return subtgraph.generate(preset="cave", seed=7)


def inside(world):
    """A point in a passage: the ground truth's start node (on the passage's floor, where
    its axis runs), a metre up."""
    import json

    graph = json.loads(world.files(["graph"])["ground_truth/graph.json"])
    x, y, z = graph["nodes"][graph["start"]]["position"]
    return np.array([x, y, z + 1.0])


def trimesh_of(world):
    """The surface rays meet: the visual one (the cave has no services)."""
    trimesh = pytest.importorskip("trimesh")
    v, f = world.mesh.visual
    return trimesh.Trimesh(vertices=np.asarray(v, float), faces=np.asarray(f), process=False)


def test_rays_from_inside_meet_the_rock_where_trimesh_says(cave):
    rng = np.random.default_rng(3)
    d = rng.normal(size=(300, 3))
    o = np.repeat(inside(cave)[None], len(d), axis=0)
    r = cave.raycast(o, d)
    assert r.shape == (300,)
    # The world is closed: every ray meets rock.
    assert np.isfinite(r).all()
    mesh = trimesh_of(cave)
    pytest.importorskip("rtree")
    unit = d / np.linalg.norm(d, axis=1)[:, None]
    hits = o + r[:, None] * unit
    _, dist, _ = mesh.nearest.on_surface(hits)
    assert dist.max() < 1e-3, dist.max()
    # And trimesh's own ray test finds the same first hits.
    loc, idx, _ = mesh.ray.intersects_location(o[:40], unit[:40], multiple_hits=True)
    for i in range(40):
        mine = r[i]
        theirs = np.linalg.norm(loc[idx == i] - o[i], axis=1).min()
        assert abs(mine - theirs) < 1e-3, (i, mine, theirs)
    # Beyond max_range: inf.
    far = cave.raycast(o[:5], d[:5], max_range=0.01)
    assert np.isinf(far).all()


def test_a_lidar_scan_lands_on_the_rock_when_moved_by_its_pose(cave):
    pose = np.eye(4)
    yaw = 0.7
    pose[:3, :3] = [[np.cos(yaw), -np.sin(yaw), 0], [np.sin(yaw), np.cos(yaw), 0], [0, 0, 1]]
    pose[:3, 3] = inside(cave)
    pts = cave.lidar_scan(pose, "os1-32")
    assert pts.ndim == 2 and pts.shape[1] == 3
    # Nearly every one of the 32 x 1024 rays returns in a closed cave.
    assert 30000 < len(pts) <= 32 * 1024
    world = pts @ pose[:3, :3].T + pose[:3, 3]
    mesh = trimesh_of(cave)
    pytest.importorskip("rtree")
    _, dist, _ = mesh.nearest.on_surface(world[:: max(1, len(world) // 2000)])
    assert dist.max() < 1e-3, dist.max()
    # With noise: the same rays, ranges off by centimetres, the same for the same seed.
    noisy = cave.lidar_scan(pose, "os1-32", noise=True, seed=5)
    assert np.array_equal(noisy, cave.lidar_scan(pose, "os1-32", noise=True, seed=5))
    assert not np.array_equal(noisy, cave.lidar_scan(pose, "os1-32", noise=True, seed=6))
    vlp = cave.lidar_scan(pose, "vlp-16")
    assert 25000 < len(vlp) <= 16 * 1800


def test_bad_rays_and_models_are_refused_with_what_to_change(cave):
    with pytest.raises(ValueError, match="one direction per origin"):
        cave.raycast(np.zeros((3, 3)), np.ones((2, 3)))
    with pytest.raises(ValueError, match="unknown LiDAR model 'os9'"):
        cave.lidar_scan(np.eye(4), "os9")
    with pytest.raises(ValueError, match="4 x 4"):
        cave.lidar_scan(np.eye(3))
    bare = subtgraph.generate(preset="cave", seed=7, mesh=False)
    with pytest.raises(ValueError, match="no mesh"):
        bare.raycast(np.zeros((1, 3)), np.ones((1, 3)))


def test_item17_nan_zero_and_infinite_rays_and_non_rigid_poses_are_refused(cave):
    """Issue 37 item 17: a ray with a NaN, infinite or zero direction, or a NaN origin, is a
    ValueError naming its row (it returned NaN, neither a refusal nor the documented inf); a
    LiDAR pose that is not a rigid transform (zero, scaled, sheared, mirrored, a bottom row
    other than 0 0 0 1) is a ValueError (it returned an empty scan)."""
    o = np.repeat(inside(cave)[None], 4, axis=0)
    good = np.array([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0], [1.0, 1.0, 0]])
    assert np.isfinite(cave.raycast(o, good)).all()
    for bad in ([0.0, 0.0, 0.0], [np.nan, 1.0, 0.0], [np.inf, 0.0, 0.0], [1e-320, 0.0, 0.0]):
        d = good.copy()
        d[2] = bad
        with pytest.raises(ValueError, match="direction 2"):
            cave.raycast(o, d)
    nan_origin = o.copy()
    nan_origin[1, 0] = np.nan
    with pytest.raises(ValueError, match="origin 1"):
        cave.raycast(nan_origin, good)
    pose = np.eye(4)
    pose[:3, 3] = inside(cave)
    assert len(cave.lidar_scan(pose)) > 1000
    scaled = pose.copy()
    scaled[:3, :3] *= 2.0
    sheared = pose.copy()
    sheared[0, 1] = 0.5
    mirrored = pose.copy()
    mirrored[2, 2] = -1.0
    bottom = pose.copy()
    bottom[3] = [0, 0, 1, 1]
    zero = np.zeros((4, 4))
    for bad in (zero, scaled, sheared, mirrored, bottom):
        with pytest.raises(ValueError, match="rigid"):
            cave.lidar_scan(bad)
