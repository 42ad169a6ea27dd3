"""The world from Python: the same bytes as the command line, numpy views, graph, meshes,
in-memory simulator files, the atomic folder, datasets and statistics."""

import gc
import os
import pathlib

import numpy as np
import pytest

import subtgraph

from conftest import BUILD, ROOT


def tree(folder):
    """{relative path: bytes} of every file under a folder."""
    folder = pathlib.Path(folder)
    return {
        str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()
    }


def test_a_world_from_python_is_byte_for_byte_the_command_lines(cli, tmp_path):
    cli("generate", "--preset", "cave", "--seed", "7", "--format", "mjcf,ground-truth",
        "--out", tmp_path / "cli")
    world = subtgraph.generate(preset="cave", seed=7, formats=["mjcf", "ground-truth"])
    world.export(tmp_path / "py")
    a, b = tree(tmp_path / "cli"), tree(tmp_path / "py")
    assert sorted(a) == sorted(b)
    different = [p for p in a if a[p] != b[p]]
    assert not different, different
    assert np.array_equal(np.load(tmp_path / "cli" / "occupancy.npy"), world.occupancy)


def test_pipelines_from_a_file_a_string_and_a_dict_make_the_same_world(tmp_path):
    text = (ROOT / "examples" / "exact-loops.toml").read_text()
    from_file = subtgraph.generate(pipeline=ROOT / "examples" / "exact-loops.toml", mesh=False)
    from_text = subtgraph.generate(pipeline=text, mesh=False)
    import tomllib

    from_dict = subtgraph.generate(pipeline=tomllib.loads(text), mesh=False)
    for w in (from_text, from_dict):
        assert np.array_equal(w.occupancy, from_file.occupancy)
        assert w.graph == from_file.graph
    assert from_file.seed == 42 and from_file.shape == (2, 48, 48)
    again = subtgraph.generate(pipeline=from_file.pipeline, mesh=False)
    assert np.array_equal(again.occupancy, from_file.occupancy)


DEEP = r"""
import subtgraph, sys
def nest(n, make):
    v = 1
    for _ in range(n):
        v = make(v)
    return v
loop = {}
loop["again"] = loop
for case in [
    {"world": {"seed": 1}, "extra": nest(20_000, lambda v: {"a": v})},
    {"world": {"seed": 1}, "route": {"type": "sine", "x": nest(20_000, lambda v: [v])}},
    {"world": {"seed": 1}, "extra": loop},
    {"world": {"seed": 1}, "extra": nest(5_000, lambda v: {"a": v})},
]:
    try:
        subtgraph.generate(pipeline=case, mesh=False)
    except subtgraph.ConfigError as e:
        print(e.key[:40], "|", "nest more than 64 deep" in str(e), "|", str(e)[-120:].replace("\n", " "))
    else:
        sys.exit("accepted")
"""


def test_a_deeply_nested_dict_is_refused_not_a_crash():
    """Issue 21 item 6: a pipeline dict nested 20,000 deep overflowed the stack (exit 139,
    the interpreter gone); one that contains itself too. The depth is refused before the
    walk goes down, naming the key."""
    import subprocess
    import sys

    run = subprocess.run([sys.executable, "-c", DEEP], capture_output=True, text=True)
    assert run.returncode == 0, (run.returncode, run.stderr[-2000:])
    lines = run.stdout.strip().splitlines()
    assert len(lines) == 4, run.stdout
    for line, key in zip(lines, ["extra.a.a.a", "route.x[0][0]", "extra.again.again", "extra.a.a"]):
        assert line.startswith(key), line
        assert "| True |" in line, line


def test_arrays_are_read_only_views_that_keep_the_world_alive():
    world = subtgraph.generate(preset="mine", seed=3)
    occ = world.occupancy
    assert occ.dtype == np.uint8 and occ.shape == world.shape
    assert np.shares_memory(occ, world.occupancy), "a second access copied"
    assert not occ.flags.writeable and not occ.flags.owndata
    with pytest.raises(ValueError):
        occ[0, 0, 0] = 1
    assert set(np.unique(occ)) <= set(subtgraph.KINDS)
    tiles = world.tiles
    assert tiles.shape == (*world.shape, 3)
    assert np.array_equal(tiles[..., 0], occ)
    # Openings agree with the neighbours: bit 0 east.
    l, r, c = np.argwhere(tiles[..., 1] & 1)[0]
    assert occ[l, r, c + 1] != 0
    v, f = world.mesh.visual
    cv, cf = world.mesh.collision
    assert v.dtype == np.float32 and v.shape[1] == 3
    assert f.dtype == np.uint32 and f.shape[1] == 3 and f.max() < len(v)
    assert 0 < len(cf) < len(f) and cf.max() < len(cv)
    assert world.mesh.normals.shape == v.shape
    assert world.mesh.materials.shape == (len(f),)
    assert world.mesh.materials.max() < len(world.mesh.material_names)
    expected = occ.copy(), v.copy()
    del world
    gc.collect()
    # The views still read the world's memory: it lives as long as they do.
    assert np.array_equal(occ, expected[0]) and np.array_equal(v, expected[1])


def test_the_graph_matches_topology_json_and_is_one_connected_network(tmp_path):
    import json

    import networkx as nx

    world = subtgraph.generate(preset="lava-tube", seed=7, mesh=False)
    world.export(tmp_path / "w")
    on_disk = json.loads((tmp_path / "w" / "topology.json").read_text())
    assert world.graph["nodes"] == on_disk["nodes"]
    assert world.graph["edges"] == on_disk["edges"]
    g = world.to_networkx()
    assert g.number_of_nodes() == len(on_disk["nodes"])
    assert g.number_of_edges() == len(on_disk["edges"])
    assert nx.is_connected(g)
    shafts = [e for _, _, e in g.edges(data=True) if e["kind"] == "shaft"]
    assert len(shafts) == len(world.shafts) > 0
    levels = world.levels
    assert len(levels) == world.shape[0]
    assert all(l["components"] == 1 for l in levels)


def test_mjcf_loads_in_mujoco_from_memory():
    import mujoco

    world = subtgraph.generate(preset="cave", seed=11)
    model = mujoco.MjModel.from_xml_string(world.mjcf())
    data = mujoco.MjData(model)
    mujoco.mj_step(model, data)
    assert model.nhfield > 0 and model.nmesh == 0
    xml, assets = world.mjcf_with_assets()
    model = mujoco.MjModel.from_xml_string(xml, assets)
    meshes = [name for name in assets if name.endswith(".msh")]
    textures = [name for name in assets if name.endswith(".png")]
    assert model.nmesh == len(meshes) > 0
    # The procedural textures travel with the meshes, and MuJoCo takes them in.
    assert textures and model.ntex > 0
    assert len(meshes) + len(textures) == len(assets)


def test_sdf_urdf_and_usd_strings():
    import xml.etree.ElementTree as ET

    world = subtgraph.generate(preset="cave", seed=5)
    assert ET.fromstring(world.sdf()).tag == "sdf"
    assert ET.fromstring(world.urdf()).tag == "robot"
    from pxr import Sdf

    layer = Sdf.Layer.CreateAnonymous(".usda")
    assert layer.ImportFromString(world.usd())
    files = world.files(["sdf"])
    assert "gazebo/world.sdf" in files and any(p.endswith(".obj") or p.endswith(".dae") or p.endswith(".stl") for p in files)


def test_ground_truth_is_decoded():
    world = subtgraph.generate(preset="cave", seed=7)
    gt = world.ground_truth()
    poses = gt["ground_truth/spawn_poses.json"]
    assert poses
    free = gt["ground_truth/free_space.npy"]
    assert isinstance(free, np.ndarray) and free.size > 0
    ros = gt["ground_truth/maps/level-0.pgm"]
    # The same pixels as Pillow reads from the file.
    import io

    from PIL import Image

    raw = world.files(["ros-map"])["ground_truth/maps/level-0.pgm"]
    assert np.array_equal(ros, np.asarray(Image.open(io.BytesIO(raw))))
    assert set(np.unique(ros)) <= {0, 205, 254} and (ros == 254).any()


def test_export_never_touches_a_users_files(tmp_path):
    world = subtgraph.generate(preset="cave", seed=7, mesh=False)
    mine = tmp_path / "w"
    mine.mkdir()
    (mine / "notes.md").write_text("mine")
    with pytest.raises(subtgraph.FolderError, match="already exists"):
        world.export(mine)
    with pytest.raises(subtgraph.FolderError, match="not a folder written by subtgraph"):
        world.export(mine, force=True)
    assert tree(mine) == {"notes.md": b"mine"}
    # A world folder holding a file of yours is not replaced either.
    world.export(tmp_path / "ours")
    (tmp_path / "ours" / "notes.md").write_text("mine too")
    with pytest.raises(subtgraph.FolderError, match="notes.md"):
        world.export(tmp_path / "ours", force=True)
    assert (tmp_path / "ours" / "notes.md").read_text() == "mine too"
    assert sorted(os.listdir(tmp_path)) == ["ours", "w"], "a temporary folder was left behind"
    # A folder subtgraph wrote is replaced with force.
    (tmp_path / "ours" / "notes.md").unlink()
    subtgraph.generate(preset="cave", seed=8, mesh=False).export(tmp_path / "ours", force=True)
    assert "seed = 8" in (tmp_path / "ours" / "world.toml").read_text()


def test_item12_export_never_writes_into_the_current_folder_or_one_holding_it(tmp_path, monkeypatch):
    """Issue 37 item 12: World.export(".") (or "..", or the current folder by its path) is
    refused: the world went into a new subfolder named after the current folder."""
    world = subtgraph.generate(preset="cave", seed=7, mesh=False)
    here = tmp_path / "a" / "b"
    here.mkdir(parents=True)
    (here / "notes.md").write_text("mine")
    monkeypatch.chdir(here)
    for out in (".", "..", "./", here, tmp_path / "a"):
        for force in (False, True):
            with pytest.raises(subtgraph.FolderError, match="current folder"):
                world.export(out, force=force)
    assert tree(tmp_path) == {"a/b/notes.md": b"mine"}


def test_stats_never_replaces_a_world_or_what_it_reads(tmp_path):
    # Issue 21 item 1: stats([w], w2) replaced the world w2 with a report.
    for name, seed in (("a", 1), ("b", 2)):
        subtgraph.generate(preset="cave", seed=seed, mesh=False).export(tmp_path / name)
    before = tree(tmp_path / "b")
    with pytest.raises(subtgraph.FolderError, match="world folder"):
        subtgraph.stats([tmp_path / "a"], tmp_path / "b")
    with pytest.raises(subtgraph.FolderError, match="reads"):
        subtgraph.stats([tmp_path / "a"], tmp_path / "a")
    assert tree(tmp_path / "b") == before
    assert "worlds" in subtgraph.stats([tmp_path / "a", tmp_path / "b"], tmp_path / "report")
    subtgraph.stats([tmp_path / "a"], tmp_path / "report")


def test_export_formats_are_recorded_in_world_toml(cli, tmp_path):
    world = subtgraph.generate(preset="cave", seed=7)
    world.export(tmp_path / "w", formats=["urdf", "graph"])
    assert (tmp_path / "w" / "urdf" / "world.urdf").is_file()
    assert (tmp_path / "w" / "ground_truth" / "graph.json").is_file()
    assert not (tmp_path / "w" / "mesh" / "world.obj").exists()
    # world.toml makes the same folder again through the command line.
    cli("generate", tmp_path / "w" / "world.toml", "--out", tmp_path / "again")
    a, b = tree(tmp_path / "w"), tree(tmp_path / "again")
    assert sorted(a) == sorted(b)
    # world.toml differs in its provenance (where it was made from), and so the manifest of sizes.
    assert [p for p in a if p not in ("world.toml", ".subtgraph-files") and a[p] != b[p]] == []
    # Geometry formats need a mesh.
    flat = subtgraph.generate(preset="cave", seed=7, mesh=False)
    with pytest.raises(subtgraph.Error, match="mesh=True"):
        flat.export(tmp_path / "flat", formats=["mjcf"])
    assert not (tmp_path / "flat").exists()


def test_dataset_and_stats(tmp_path):
    summary = subtgraph.dataset(tmp_path / "d", presets=["cave", "mine"], count=2, seed=5,
                                mesh=False, jobs=2)
    assert summary == {"made": 4, "skipped": 0, "indexed": 4}
    again = subtgraph.dataset(tmp_path / "d", presets=["cave", "mine"], count=2, seed=5,
                              mesh=False)
    assert again["made"] == 0 and again["skipped"] == 4
    text = subtgraph.stats([tmp_path / "d"], tmp_path / "report")
    assert "cave" in text and (tmp_path / "report").is_dir()


def test_presets_and_components():
    assert set(subtgraph.presets()) == {"mine", "cave", "lava-tube"}
    assert "[world]" in subtgraph.preset_text("cave")
    names = {(c["kind"], c["name"]) for c in subtgraph.components()}
    assert ("exporter", "mjcf") in names and ("route descriptor", "harmonic") in names


def test_plugins_load_from_python():
    lib = BUILD / "libsubtgraph_plugin_meander.so"
    if not lib.exists():
        pytest.skip(f"{lib} is missing: build it with `scripts/build` (scripts/test does)")
    added = subtgraph.load_plugin(lib)
    assert "meander" in added
    world = subtgraph.generate(pipeline={"world": {"seed": 4}, "route": {"type": "meander", "wavelength": 6}},
                               mesh=False)
    assert world.occupancy.any()
    with pytest.raises(subtgraph.PluginError, match="no such file"):
        subtgraph.load_plugin(ROOT / "no-such-plugin.so")


def test_geometry_formats_without_a_mesh_are_left_out_with_a_warning(tmp_path):
    with pytest.warns(UserWarning, match="skipping exporter 'mjcf'"):
        world = subtgraph.generate(preset="cave", seed=3, mesh=False, formats=["mjcf", "graph"])
    assert sorted(world.files()) == ["ground_truth/graph.graphml", "ground_truth/graph.json"]
    with pytest.warns(UserWarning, match="skipping exporter 'usd'"):
        subtgraph.dataset(tmp_path / "d", presets=["cave"], count=1, mesh=False, formats=["usd"])
    assert not list((tmp_path / "d").rglob("*.usda"))
