"""Independent check of `subtgraph score --segmentation` (tests/integration/segmentation.rs).

    segmentation_check.py write WORLD LEVEL DIR
        writes, from the world's own files, DIR/level-N.png (the perfect map: each free pixel
        of ground_truth/maps/level-N.pgm labelled from ground_truth/semantic_labels.json by
        the tile square it is in),
        DIR/shifted-level-N.png (the same moved 8 pixels east) and DIR/corrupt-level-N.npy
        (int16; a seeded tenth of the pixels relabelled 0, 1 or 5, one junction tile erased, a
        dead end painted on a straight tile).
    segmentation_check.py check WORLD LEVEL MAP SCORE_DIR
        recomputes the confusion matrix, per-class IoU/precision/recall and node matching
        with numpy and scipy.ndimage, and compares them with SCORE_DIR/segmentation.json and
        confusion.csv to 1e-9.

The label table (docs/src/scoring.md): 0 not labelled, 1 corridor (straight, corner),
2 junction (t-junction), 3 intersection, 4 dead end, 5 shaft/ramp (shaft-up, shaft-landing,
ramp). Written here from the documentation, not from the Rust code.
"""

import csv
import json
import math
import sys
from pathlib import Path

import numpy as np
from PIL import Image
from scipy import ndimage

TABLE = {
    "straight": 1,
    "corner": 1,
    "t-junction": 2,
    "intersection": 3,
    "dead-end": 4,
    "shaft-up": 5,
    "shaft-landing": 5,
    "ramp": 5,
}
NAMES = ["unlabelled", "corridor", "junction", "intersection", "dead_end", "shaft_ramp"]


def ros_map(world, level):
    base = Path(world) / "ground_truth" / "maps" / f"level-{level}"
    img = np.array(Image.open(str(base) + ".pgm"))
    meta = {}
    for line in open(str(base) + ".yaml"):
        if ":" in line and not line.startswith("#"):
            k, v = line.split(":", 1)
            meta[k.strip()] = v.strip()
    res = float(meta["resolution"])
    ox, oy, _ = [float(x) for x in meta["origin"].strip("[]").split(",")]
    h, w = img.shape
    xs = ox + (np.arange(w) + 0.5) * res
    ys = oy + (h - 1 - np.arange(h) + 0.5) * res
    return img == 254, xs, ys


def truth(world, level):
    free, xs, ys = ros_map(world, level)
    labels = json.load(open(Path(world) / "ground_truth" / "semantic_labels.json"))
    pitch = labels["tile_pitch_m"]
    half = pitch / 2
    # Each tile's square on the grid: its cell's centre, placed by the level's offset, read from
    # a node of topology.json on that level (its cell, and its position rounded to the grid:
    # a node stands on its own passage, within its tile). Not the tile's node position, which
    # with a mesh is where its passage runs, not the middle of its square.
    topo = json.load(open(Path(world) / "topology.json"))
    nrows = topo["rows"]
    node = next(n for n in topo["nodes"] if n["cell"]["level"] == level)
    oc = round(node["position"][0] / pitch) - node["cell"]["col"]
    orow = nrows - 1 - round(node["position"][1] / pitch) - node["cell"]["row"]
    out = np.zeros(free.shape, dtype=np.uint8)
    for t in labels["tiles"]:
        if t["level"] != level:
            continue
        cx, cy = (t["col"] + oc) * pitch, (nrows - 1 - (t["row"] + orow)) * pitch
        cols = (xs >= cx - half) & (xs < cx + half)
        rows = (ys >= cy - half) & (ys < cy + half)
        out[np.ix_(rows, cols)] = TABLE[t["kind"]]
    out[~free] = 0
    return out, free, xs, ys


def write(world, level, folder):
    folder = Path(folder)
    t, _, _, _ = truth(world, level)
    Image.fromarray(t, mode="L").save(folder / f"level-{level}.png")
    Image.fromarray(np.roll(t, 8, axis=1), mode="L").save(folder / f"shifted-level-{level}.png")
    rng = np.random.default_rng(7)
    c = t.astype(np.int16)
    pick = rng.random(c.shape) < 0.1
    c[pick] = rng.choice(np.array([0, 1, 5], dtype=np.int16), size=int(pick.sum()))
    # One junction's pixels erased: a node the map misses.
    lab, _ = ndimage.label(t == 2)
    c[lab == 1] = 0
    # A dead end painted in the middle of a straight tile: a node the world has not.
    _, _, xs, ys = truth(world, level)
    labels = json.load(open(Path(world) / "ground_truth" / "semantic_labels.json"))
    s = next(t for t in labels["tiles"] if t["level"] == level and t["kind"] == "straight")
    col = int(np.argmin(abs(xs - s["position"][0])))
    row = int(np.argmin(abs(ys - s["position"][1])))
    c[row - 4:row + 4, col - 4:col + 4] = 4
    np.save(folder / f"corrupt-level-{level}.npy", c)
    print(f"wrote maps {t.shape[1]} x {t.shape[0]}, classes {sorted(set(np.unique(t).tolist()))}")


def load(path):
    if str(path).endswith(".npy"):
        return np.load(path).astype(np.int64)
    return np.array(Image.open(path)).astype(np.int64)


def near(a, b, what):
    if a is None or b is None:
        assert a is None and b is None, f"{what}: ours {a}, numpy {b}"
        return
    assert abs(a - b) <= 1e-9, f"{what}: ours {a}, numpy {b}"


def check(world, level, map_path, score_dir):
    t, free, xs, ys = truth(world, level)
    p = load(map_path)
    doc = json.load(open(Path(score_dir) / "segmentation.json"))
    conf = np.zeros((6, 6), dtype=np.int64)
    np.add.at(conf, (t[free].astype(np.int64), p[free]), 1)
    assert doc["confusion"] == conf.tolist(), f"confusion: ours {doc['confusion']}, numpy {conf.tolist()}"
    with open(Path(score_dir) / "confusion.csv") as f:
        rows = list(csv.reader(f))
    assert rows[0][1:] == NAMES, rows[0]
    assert [[int(v) for v in r[1:]] for r in rows[1:]] == conf.tolist()
    ious = []
    for c in range(1, 6):
        tp = int(((t == c) & (p == c) & free).sum())
        fp = int(((t != c) & (p == c) & free).sum())
        fn = int(((t == c) & (p != c) & free).sum())
        iou = tp / (tp + fp + fn) if tp + fp + fn else None
        near(doc[f"iou.{NAMES[c]}"], iou, f"iou.{NAMES[c]}")
        near(doc[f"precision.{NAMES[c]}"], tp / (tp + fp) if tp + fp else None, f"precision {c}")
        near(doc[f"recall.{NAMES[c]}"], tp / (tp + fn) if tp + fn else None, f"recall {c}")
        if iou is not None:
            ious.append(iou)
    near(doc["iou_mean"], float(np.mean(ious)) if ious else None, "iou_mean")
    near(doc["pixel_accuracy"], float(np.trace(conf) / conf.sum()), "pixel_accuracy")
    # Nodes: 4-connected regions of each node class, centroids of their pixel centres.
    found = []
    for c in (2, 3, 4):
        lab, n = ndimage.label(p == c)
        for k in range(1, n + 1):
            r, q = np.nonzero(lab == k)
            found.append((float(xs[q].mean()), float(ys[r].mean())))
    topo = json.load(open(Path(world) / "topology.json"))
    nodes = [n["position"][:2] for n in topo["nodes"]
             if n["cell"]["level"] == level and TABLE.get(n["kind"], 0) in (2, 3, 4)]
    radius = doc["options"]["node_radius_m"]
    pairs = sorted((math.dist(a, b), i, j) for i, a in enumerate(found)
                   for j, b in enumerate(nodes) if math.dist(a, b) <= radius)
    ua, ub, matched = set(), set(), []
    for d, i, j in pairs:
        if i not in ua and j not in ub:
            ua.add(i)
            ub.add(j)
            matched.append(d)
    assert doc["nodes_detected"] == len(found), (doc["nodes_detected"], len(found))
    assert doc["nodes_truth"] == len(nodes), (doc["nodes_truth"], len(nodes))
    assert doc["nodes_matched"] == len(matched), (doc["nodes_matched"], len(matched))
    near(doc["node_precision"], len(matched) / len(found) if found else None, "node_precision")
    near(doc["node_recall"], len(matched) / len(nodes) if nodes else None, "node_recall")
    near(doc["node_error_mean_m"], float(np.mean(matched)) if matched else None, "node_error_mean_m")
    present = [NAMES[c] for c in range(1, 6) if (t == c).any()]
    print(f"agrees: {int(free.sum())} pixels, classes {present}, iou_mean {doc['iou_mean']}, "
          f"nodes {len(matched)}/{len(nodes)} matched of {len(found)} detected")


if __name__ == "__main__":
    if sys.argv[1] == "write":
        write(sys.argv[2], int(sys.argv[3]), sys.argv[4])
    else:
        check(sys.argv[2], int(sys.argv[3]), sys.argv[4], sys.argv[5])
