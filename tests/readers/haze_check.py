"""What dust does to camera images (issue 39 item 3), measured by OpenCV and numpy on the PNG
and TIFF files `subtgraph sense --camera` wrote, apart from subtgraph's code.

    haze_check.py NAME=SEQUENCE [NAME=SEQUENCE ...] [--far M]

For each sequence, over every frame of the first camera (camera/cam0/rgb/*.png, grey as OpenCV
converts it, and the float32 depth TIFF beside each):

- `contrast`: the RMS contrast, the standard deviation of the grey levels over their mean,
  over the pixels that see a surface;
- `dark`: the 5th percentile of the grey levels over those pixels (a veil lifts the dark end);
- `far_mean`: the mean grey level over the pixels whose surface lies beyond `--far` metres
  (default 4), which the lamps light least and a veil of scattered lamp light brightens most;
- `near_lamp` and `edge`: the mean grey level of the image's middle third (where the lamps'
  beams cross the view) and of its outer columns.

Prints one JSON object by NAME. Asserts only that the files are there and read.
"""
import argparse
import json
from pathlib import Path

import cv2
import numpy as np


def measure(seq, far):
    base = Path(seq) / "camera" / "cam0"
    rgbs = sorted((base / "rgb").glob("*.png"))
    assert rgbs, f"no images in {base / 'rgb'}"
    grey_all, seen_all, far_all, mid, edge = [], [], [], [], []
    for p in rgbs:
        img = cv2.imread(str(p), cv2.IMREAD_UNCHANGED)
        assert img is not None, p
        grey = cv2.cvtColor(img, cv2.COLOR_BGR2GRAY) if img.ndim == 3 else img
        grey = grey.astype(np.float64)
        depth = cv2.imread(str(base / "depth" / (p.stem + ".tiff")), cv2.IMREAD_UNCHANGED)
        assert depth is not None and depth.shape == grey.shape, p
        seen = depth > 0
        grey_all.append(grey[seen])
        far_all.append(grey[seen & (depth > far)])
        h, w = grey.shape
        mid.append(grey[h // 3: 2 * h // 3, w // 3: 2 * w // 3].ravel())
        edge.append(np.concatenate([grey[:, : w // 8].ravel(), grey[:, -w // 8:].ravel()]))
        seen_all.append(seen.mean())
    g = np.concatenate(grey_all)
    f = np.concatenate(far_all)
    return {
        "frames": len(rgbs),
        "mean": float(g.mean()),
        "contrast": float(g.std() / max(g.mean(), 1e-9)),
        "dark": float(np.percentile(g, 5)),
        "far_pixels": int(len(f)),
        "far_mean": float(f.mean()) if len(f) else None,
        "near_lamp": float(np.concatenate(mid).mean()),
        "edge": float(np.concatenate(edge).mean()),
        "seen_share": float(np.mean(seen_all)),
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("sequences", nargs="+")
    ap.add_argument("--far", type=float, default=4.0)
    args = ap.parse_args()
    out = {}
    for s in args.sequences:
        name, path = s.split("=", 1)
        out[name] = measure(path, args.far)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
