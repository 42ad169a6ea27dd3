"""Reads the floor patches back from a world's URDF export with PyBullet.

usage: hazards_pybullet_check.py WORLD_DIR

Loads urdf/world.urdf as PyBullet does; each `hazard-<part>-<material>` link must have the
material's friction as PyBullet's getDynamicsInfo reports it. Then casts a ray down at the
node of every tile with a floor patch (ground_truth/hazards.json) and of as many unpatched
tiles (positions from ground_truth/semantic_labels.json, on each tile's own passage floor): a patched tile's ray must hit its material's
link, an unpatched one the world's rock link. Prints a line per material; exits non-zero on a
disagreement.
"""
import json
import sys
from pathlib import Path

import pybullet as p

world = Path(sys.argv[1])
doc = json.loads((world / "ground_truth/hazards.json").read_text())
labels = json.loads((world / "ground_truth/semantic_labels.json").read_text())["tiles"]
p.connect(p.DIRECT)
body = p.loadURDF(str(world / "urdf/world.urdf"), useFixedBase=True)
link_material = {}
for j in range(p.getNumJoints(body)):
    name = p.getJointInfo(body, j)[12].decode()
    if not name.startswith("hazard-"):
        continue
    material = next(m for m in ("wet-rock", "mud", "ice", "sand") if name.endswith("-" + m))
    mu = p.getDynamicsInfo(body, j)[1]
    want = next(x["friction"] for x in doc["patches"] if x["material"] == material)
    assert abs(mu - want) < 1e-6, (name, mu, want)
    link_material[j] = material
assert link_material, "no hazard links in the URDF"


def hit(x, y, z):
    r = p.rayTest([x, y, z + 1.5], [x, y, z - 3.0])[0]
    return (r[1], r[0] == body) if r[0] >= 0 else None


patched = {(q["cell"]["level"], q["cell"]["row"], q["cell"]["col"]) for q in doc["patches"]}
counts, hits = {}, 0
# Each tile's node on its own passage's floor (ground truth): a corner's passage bends away
# from the tile centre, and floors slope up from the level's nominal height (floor_z).
anchor = {(t["level"], t["row"], t["col"]): t["position"] for t in labels}
for q in doc["patches"]:
    h = hit(*anchor[(q["cell"]["level"], q["cell"]["row"], q["cell"]["col"])])
    if h is None:
        continue
    hits += 1
    assert h[1] and link_material.get(h[0]) == q["material"], (q["cell"], h)
    counts[q["material"]] = counts.get(q["material"], 0) + 1
assert hits >= 0.9 * len(doc["patches"]), f"only {hits} of {len(doc['patches'])} rays hit"
rock = 0
for t in labels:
    if (t["level"], t["row"], t["col"]) in patched or t["kind"] in ("shaft-up", "shaft-landing"):
        continue
    h = hit(*t["position"])
    if h is not None:
        assert h == (-1, True), (t, h)
        rock += 1
    if rock >= len(patched):
        break
assert rock > 0
for m in sorted(counts):
    mu = next(x["friction"] for x in doc["patches"] if x["material"] == m)
    print(f"{m}: {counts[m]} tile floors hit on its link, lateral friction {mu} as PyBullet reads it; {rock} rock floors hit on the world link")
