"""Reads the floor friction of every tile back from a world's MuJoCo export and compares it
with ground_truth/hazards.json.

usage: hazards_check.py WORLD_DIR

Every floor height field (an upright hfield geom) of a patched tile must have the patch's
friction as MuJoCo compiled it (geom_friction[0]); every other floor MuJoCo's default 1.0.
Also checks the shares: each material covers round(share x eligible tiles) tiles, as
world.toml's [hazards] asks. Prints a line per material; exits non-zero on a disagreement.
"""
import json
import sys
import tomllib
from pathlib import Path

import mujoco
import numpy as np

world = Path(sys.argv[1])
doc = json.loads((world / "ground_truth/hazards.json").read_text())
topo = json.loads((world / "topology.json").read_text())
pitch = topo["tile_pitch_m"]
patch = {}
for p in doc["patches"]:
    x0, y0, x1, y1 = p["bounds"]
    patch[(p["cell"]["level"], round((x0 + x1) / 2 / pitch), round((y0 + y1) / 2 / pitch))] = p
model = mujoco.MjModel.from_xml_path(str(world / "mujoco/world.xml"))
data = mujoco.MjData(model)
mujoco.mj_forward(model, data)
seen, floors = {}, 0
for g in range(model.ngeom):
    if model.geom_type[g] != mujoco.mjtGeom.mjGEOM_HFIELD:
        continue
    upright = abs(data.geom_xmat[g][8] - 1.0) < 1e-9
    if not upright:
        continue  # a roof
    floors += 1
    name = model.hfield(model.geom_dataid[g]).name  # level-N-floor-T
    level = int(name.split("-")[1])
    x, y, _ = model.geom_pos[g]
    key = (level, round(x / pitch), round(y / pitch))
    mu = model.geom_friction[g][0]
    if key in patch:
        assert abs(mu - patch[key]["friction"]) < 1e-9, (name, mu, patch[key])
        seen[key] = patch[key]["material"]
    else:
        assert mu == 1.0, (name, mu)
assert len(seen) == len(patch), f"{len(patch) - len(seen)} patches have no floor in the MJCF"
toml = tomllib.loads((world / "world.toml").read_text())
eligible = sum(1 for n in np.load(world / "occupancy.npy").ravel() if n not in (0, 11, 111)) - 1
for material, share in toml["hazards"]["friction"].items():
    n = sum(1 for m in seen.values() if m == material)
    assert n == round(share * eligible), (material, n, share, eligible)
    mus = {p["friction"] for p in doc["patches"] if p["material"] == material}
    print(f"{material}: {n} of {floors} tile floors, friction {sorted(mus)} as MuJoCo reads it")
