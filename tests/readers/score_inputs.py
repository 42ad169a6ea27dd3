"""Builds synthetic runs with known answers for `subtgraph score`, from a world's ground truth.

usage: score_inputs.py WORLD_DIR OUT_DIR

Writes into OUT_DIR:
- reports.csv and reports.json (the same reports): for each artifact in turn one of
  * a report 4.9 m from it in a random direction (scores),
  * a report 5.1 m from it (a false report: the world's artifacts are 15 m apart or more, so
    no other one is within 5 m),
  * a report at it with another class (wrong class),
  * a report 1 m from it, then a second one 2 m from it later (scores, then a duplicate);
  the reports are written in shuffled order with increasing times per artifact;
- expected.json: the score, the outcome counts, and which artifacts are found;
- map files: a cloud with one point at the centre of every free voxel (numpy's unpackbits of
  ground_truth/free_space.npy) of every other corridor edge of the graph (by id), as PLY
  binary and ASCII, PCD binary, ASCII and binary_compressed (compressed here by `lzf` below,
  written from the LZF format's description, not from subtgraph's reader), and an occupancy
  .npy; expected.json lists those edges (coverage 1) and the rest (coverage 0), and each
  level's share.
A voxel belongs to the level whose floor is below it by a quarter level height (or the one
under it when that level has rock there), and to the cell of that level holding its centre.
"""

import csv
import json
import math
import sys
from pathlib import Path

import numpy as np

world, out = Path(sys.argv[1]), Path(sys.argv[2])
out.mkdir(parents=True, exist_ok=True)
rng = np.random.default_rng(7)
arts = json.loads((world / "ground_truth/artifacts.json").read_text())["artifacts"]
topo = json.loads((world / "topology.json").read_text())

CLASSES = ["survivor", "backpack", "cell-phone", "drill", "fire-extinguisher", "gas", "vent",
           "helmet", "rope", "cube"]


def lzf(data: bytes) -> bytes:
    """LZF compression (liblzf's format, PCL's binary_compressed): runs of up to 32 literal
    bytes (a control byte of run length - 1), and back-references of 3 to 264 bytes up to
    8192 back (length - 2 in the control byte's top 3 bits, 7 meaning a further byte, then
    the distance - 1 in 13 bits), found greedily through the last place each 3 bytes were."""
    out, literal, last, i, n = bytearray(), bytearray(), {}, 0, len(data)

    def flush():
        nonlocal literal
        while literal:
            run, literal = literal[:32], literal[32:]
            out.append(len(run) - 1)
            out.extend(run)

    while i < n:
        key = data[i:i + 3]
        j = last.get(key) if len(key) == 3 else None
        if len(key) == 3:
            last[key] = i
        if j is not None and i - j - 1 < 8192:
            length = 3
            while i + length < n and length < 264 and data[j + length] == data[i + length]:
                length += 1
            flush()
            back, code = i - j - 1, length - 2
            if code < 7:
                out.append((code << 5) | (back >> 8))
            else:
                out.append((7 << 5) | (back >> 8))
                out.append(code - 7)
            out.append(back & 0xFF)
            i += length
        else:
            literal.append(data[i])
            i += 1
    flush()
    return bytes(out)


def offset(p, d):
    v = rng.normal(size=3)
    v /= np.linalg.norm(v)
    return [p[k] + d * v[k] for k in range(3)]


reports, found = [], []
expected = {"scored": 0, "duplicate": 0, "wrong_class": 0, "false_reports": 0}
for i, a in enumerate(arts):
    p, kind = a["position"], i % 4
    t = 10.0 * i
    if kind == 0:
        reports.append((t, a["class"], offset(p, 4.9)))
        expected["scored"] += 1
        found.append(a["id"])
    elif kind == 1:
        reports.append((t, a["class"], offset(p, 5.1)))
        expected["false_reports"] += 1
    elif kind == 2:
        other = next(c for c in CLASSES if c != a["class"])
        reports.append((t, other, p))
        expected["wrong_class"] += 1
    else:
        reports.append((t, a["class"], offset(p, 1.0)))
        reports.append((t + 5.0, a["class"], offset(p, 2.0)))
        expected["scored"] += 1
        expected["duplicate"] += 1
        found.append(a["id"])
order = rng.permutation(len(reports))
rows = [reports[k] for k in order]
with open(out / "reports.csv", "w", newline="") as f:
    w = csv.writer(f)
    w.writerow(["time", "class", "x", "y", "z"])
    for t, c, (x, y, z) in rows:
        w.writerow([t, c, x, y, z])
(out / "reports.json").write_text(json.dumps(
    [{"time": t, "class": c, "x": x, "y": y, "z": z} for t, c, (x, y, z) in rows]))

# Free voxels and their graph regions.
fs = json.loads((world / "ground_truth/free_space.json").read_text())
nz, ny, nx = fs["shape"]
v, o = fs["voxel_m"], fs["origin"]
free = np.unpackbits(np.load(world / "ground_truth/free_space.npy"), axis=2, count=nx).astype(bool)
z, y, x = np.nonzero(free)
cx, cy, cz = o[0] + (x + 0.5) * v, o[1] + (y + 0.5) * v, o[2] + (z + 0.5) * v
pitch, lh, rows_, cols_ = topo["tile_pitch_m"], topo["level_height_m"], topo["rows"], topo["cols"]
levels = topo["levels"]
offsets = {}
for n in topo["nodes"]:
    lvl = n["cell"]["level"]
    if lvl not in offsets:
        col = round(n["position"][0] / pitch)
        row = rows_ - 1 - round(n["position"][1] / pitch)
        offsets[lvl] = (row - n["cell"]["row"], col - n["cell"]["col"])
region = -np.ones((levels, rows_, cols_), dtype=np.int64)  # edge id, or -2 for a node
for e in topo["edges"]:
    for c in e["cells"]:
        region[c["level"], c["row"], c["col"]] = e["id"]
for n in topo["nodes"]:
    c = n["cell"]
    region[c["level"], c["row"], c["col"]] = -2
edge_of = np.full(len(cx), -1, dtype=np.int64)
level_of = np.full(len(cx), -1, dtype=np.int64)
guess = np.clip(np.floor(cz / lh + 0.25).astype(int), 0, levels - 1)
for step in (0, 1):
    lvl = guess - step
    todo = (level_of < 0) & (lvl >= 0)
    for L in range(levels):
        m = todo & (lvl == L)
        if not m.any():
            continue
        r0, c0 = offsets.get(L, (0, 0))
        col = np.floor(cx[m] / pitch + 0.5).astype(int) - c0
        row = rows_ - 1 - np.floor(cy[m] / pitch + 0.5).astype(int) - r0
        ok = (row >= 0) & (row < rows_) & (col >= 0) & (col < cols_)
        reg = np.full(m.sum(), -1)
        reg[ok] = region[L, row[ok], col[ok]]
        idx = np.nonzero(m)[0]
        hit = reg != -1
        level_of[idx[hit]] = L
        edge_of[idx[hit]] = np.where(reg[hit] >= 0, reg[hit], -2)
# A corridor between two neighbouring nodes has no cells, so no free space, of its own (its
# share is 0 of 0): only corridors with space of their own can be covered.
with_space = set(np.unique(edge_of[edge_of >= 0]).tolist())
corridors = [e["id"] for e in topo["edges"] if e["kind"] == "corridor" and e["id"] in with_space]
chosen = set(corridors[::2])
pick = np.isin(edge_of, list(chosen))
pts = np.stack([cx[pick], cy[pick], cz[pick]], 1).astype("<f4")
per_level = []
for L in range(levels):
    on = level_of == L
    per_level.append(float((pick & on).sum()) / float(on.sum()) if on.any() else 0.0)
header = (f"ply\nformat binary_little_endian 1.0\nelement vertex {len(pts)}\n"
          "property float x\nproperty float y\nproperty float z\nend_header\n")
(out / "map-binary.ply").write_bytes(header.encode() + pts.tobytes())
ascii_pts = "".join(f"{a!r} {b!r} {c!r}\n" for a, b, c in pts.tolist())
(out / "map-ascii.ply").write_text(header.replace("binary_little_endian", "ascii") + ascii_pts)
pcd = (f"VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH {len(pts)}\n"
       f"HEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS {len(pts)}\n")
(out / "map-binary.pcd").write_bytes((pcd + "DATA binary\n").encode() + pts.tobytes())
(out / "map-ascii.pcd").write_text(pcd + "DATA ascii\n" + ascii_pts)
# binary_compressed: every x, then every y, then every z, LZF-compressed after the two sizes.
fields = np.ascontiguousarray(pts.T).tobytes()
packed = lzf(fields)
(out / "map-compressed.pcd").write_bytes(
    (pcd + "DATA binary_compressed\n").encode()
    + np.array([len(packed), len(fields)], dtype="<u4").tobytes() + packed)
occ = np.zeros((nz, ny, nx), dtype=np.uint8)
occ[z[pick], y[pick], x[pick]] = 1
np.save(out / "map.npy", occ)
(out / "expected.json").write_text(json.dumps({
    "reports": expected, "found": found, "covered_edges": sorted(chosen),
    "uncovered_edges": sorted(set(e["id"] for e in topo["edges"]) - chosen),
    "level_shares": per_level, "points": int(len(pts)),
}))
print(f"{len(rows)} reports, {len(pts)} map points on {len(chosen)} of {len(corridors)} corridors")
