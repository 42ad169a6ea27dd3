"""The examples under examples/python run, small, and make what they say (checked with the
programs that read their output)."""

import json
import subprocess
import sys

from conftest import ROOT

EXAMPLES = ROOT / "examples" / "python"


def run(name, *args, cwd):
    done = subprocess.run([sys.executable, str(EXAMPLES / name), *map(str, args)],
                          capture_output=True, text=True, cwd=cwd)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_mujoco_episodes(tmp_path):
    out = run("mujoco_episodes.py", "--episodes", "2", "--seconds", "1", cwd=tmp_path)
    assert out.count("episode ") == 2
    assert list(tmp_path.iterdir()) == [], "the MuJoCo loop wrote files"


def test_networkx_dataset(tmp_path):
    out = run("networkx_dataset.py", tmp_path / "d", "--count", "2", cwd=tmp_path)
    rows = {line.split()[0]: line.split() for line in out.splitlines()[2:]}
    assert set(rows) == {"mine", "cave", "lava-tube"}
    assert all(int(r[1]) == 2 and float(r[2]) > 1 for r in rows.values())


def test_custom_route(tmp_path):
    run("custom_route.py", tmp_path / "spiral", cwd=tmp_path)
    toml = (tmp_path / "spiral" / "world.toml").read_text()
    assert 'type = "spiral"' in toml and 'type = "l-bend"' in toml
    assert (tmp_path / "spiral" / "mesh" / "world.obj").is_file()


def test_isaac_terrains(tmp_path):
    from pxr import Usd, UsdPhysics

    run("isaac_terrains.py", tmp_path / "t", "--count", "2", "--max-levels", "2",
        "--max-length", "1800", cwd=tmp_path)
    listing = json.loads((tmp_path / "t" / "terrains.json").read_text())["terrains"]
    assert [t["difficulty"] for t in listing] == [0.0, 1.0]
    assert [t["levels"] for t in listing] == [1, 2]
    for t in listing:
        stage = Usd.Stage.Open(t["usd_path"])
        colliders = [p for p in stage.Traverse() if p.HasAPI(UsdPhysics.CollisionAPI)]
        assert colliders, t["usd_path"]
        assert t["spawn_poses"]
