"""Checks a sequence's cameras (`subtgraph sense --camera`) with programs that did not write it.

    camera_check.py SEQUENCE WORLD

- OpenCV reads every image: RGB (or grey) PNG, float32 depth TIFF, 16-bit class PNG, int32
  instance TIFF, each of the camera's size;
- every sampled depth pixel, turned into a ray by OpenCV with the calibration Kalibr's
  camchain.yaml gives (cv2.undistortPoints, or cv2.fisheye.undistortPoints for an equidistant
  lens) and moved by the camera's ground-truth pose (camera/<cam>/ground_truth.tum), lies on
  the world's visual surface (trimesh's nearest point on mesh/world.obj and services.obj);
- the class of each sampled rock pixel names the kind of the tile its point lies in, as
  ground_truth/semantic_labels.json gives it;
- each frame's difficulty: OpenCV's FAST (threshold 20, no suppression) finds as many corners
  as the label says, and the mean grey value is the label's;
- the bag (rosbags): an Image per camera and frame whose pixels are the PNG's, and CameraInfo
  with the camchain's intrinsics; a TUM RGB-D folder's depth (16 bits, 5,000 a metre) is the
  TIFF's within its step.

Prints one JSON line of what it measured.
"""
import json
import sys
from pathlib import Path

import cv2
import numpy as np
import trimesh
import yaml

seq = Path(sys.argv[1])
world = Path(sys.argv[2])
meta = json.loads((seq / "sequence.json").read_text())
cam = meta["camera"]
model = cam["model"]
legend = {c["id"]: c for c in cam["legend"]}
chain = yaml.safe_load((seq / "camera/camchain.yaml").read_text())
frames = meta["camera_frames"]
assert len(frames) == cam["frame_count"], (len(frames), cam["frame_count"])

meshes = [trimesh.load(world / "mesh/world.obj", force="mesh", process=False)]
if (world / "mesh/services.obj").exists():
    meshes.append(trimesh.load(world / "mesh/services.obj", force="mesh", process=False))
surface = trimesh.util.concatenate(meshes)
query = trimesh.proximity.ProximityQuery(surface)

labels_doc = json.loads((world / "ground_truth/semantic_labels.json").read_text())
pitch = labels_doc["tile_pitch_m"]
tiles = labels_doc["tiles"]
# Each level's grid origin, from its tiles' own positions (each within its cell): columns run
# east (x), rows south (y falls as the row grows).
level_h = labels_doc["level_height_m"]
origins = {}
for lv in {t["level"] for t in tiles}:
    mine = [t for t in tiles if t["level"] == lv]
    origins[lv] = (float(np.median([t["position"][0] - t["col"] * pitch for t in mine])),
                   float(np.median([t["position"][1] + t["row"] * pitch for t in mine])))
kind_at = {(t["level"], t["row"], t["col"]): (t["position"][2], t["kind"]) for t in tiles}


def kinds_near(p):
    """The kinds of the tiles whose cell holds p's plane position, on a level near its height."""
    out = []
    for lv, (ox, oy) in origins.items():
        cell = (lv, int(round((oy - p[1]) / pitch)), int(round((p[0] - ox) / pitch)))
        if cell in kind_at and abs(kind_at[cell][0] - p[2]) < level_h:
            out.append(kind_at[cell][1])
    return out


def quat_to_matrix(q):
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


rng = np.random.default_rng(1)
worst = 0.0
checked = 0
kinds_ok = kinds_all = 0
images = 0
for ci, c in enumerate(model["cameras"]):
    name = c["name"]
    k = chain[f"cam{ci}"]
    fu, fv, pu, pv = k["intrinsics"]
    K = np.array([[fu, 0, pu], [0, fv, pv], [0, 0, 1.0]])
    D = np.array(k["distortion_coeffs"], dtype=np.float64)
    fisheye = k["distortion_model"] == "equidistant"
    w, h = k["resolution"]
    truth = np.loadtxt(seq / f"camera/{name}/ground_truth.tum", ndmin=2)
    assert len(truth) == len(frames), (len(truth), len(frames))
    for fi, f in enumerate(frames):
        stamp = int(round(f["time"] * 1e9))
        base = seq / f"camera/{name}"
        rgb = cv2.imread(str(base / f"rgb/{stamp}.png"), cv2.IMREAD_UNCHANGED)
        depth = cv2.imread(str(base / f"depth/{stamp}.tiff"), cv2.IMREAD_UNCHANGED)
        cls = cv2.imread(str(base / f"labels/{stamp}.png"), cv2.IMREAD_UNCHANGED)
        inst = cv2.imread(str(base / f"instances/{stamp}.tiff"), cv2.IMREAD_UNCHANGED)
        assert rgb is not None and depth is not None and cls is not None and inst is not None
        assert rgb.shape[:2] == (h, w) and rgb.dtype == np.uint8, rgb.shape
        assert depth.shape == (h, w) and depth.dtype == np.float32, (depth.shape, depth.dtype)
        assert cls.shape == (h, w) and cls.dtype == np.uint16, (cls.shape, cls.dtype)
        assert inst.shape == (h, w) and inst.dtype == np.int32, (inst.shape, inst.dtype)
        images += 1
        # Difficulty, recomputed by OpenCV.
        grey = rgb if rgb.ndim == 2 else cv2.cvtColor(rgb, cv2.COLOR_BGR2GRAY)
        fast = cv2.FastFeatureDetector_create(20, False)
        d = f["cameras"][ci]
        found = len(fast.detect(grey))
        assert found == d["keypoints"], (name, fi, found, d["keypoints"])
        if not fisheye:
            assert abs(float(grey.mean()) - d["mean_brightness"]) < 2e-3, (grey.mean(), d)
        # Depth pixels on the surface.
        vs, us = np.nonzero(depth > 0)
        if len(us) == 0:
            continue
        pick = rng.choice(len(us), size=min(60, len(us)), replace=False)
        px = np.stack([us[pick], vs[pick]], axis=1).astype(np.float64).reshape(-1, 1, 2)
        if fisheye:
            norm = cv2.fisheye.undistortPoints(px, K, D).reshape(-1, 2)
        else:
            norm = cv2.undistortPoints(px, K, D).reshape(-1, 2)
        z = depth[vs[pick], us[pick]].astype(np.float64)
        pts = np.stack([norm[:, 0] * z, norm[:, 1] * z, z], axis=1)
        t = truth[fi]
        assert abs(t[0] - f["time"]) < 1e-6
        R = quat_to_matrix(t[4:8])
        world_pts = pts @ R.T + t[1:4]
        dist = np.abs(query.signed_distance(world_pts))
        # Artifacts are not in the OBJ files (they are their own models in every format).
        art = (inst[vs[pick], us[pick]] > 0) & (
            inst[vs[pick], us[pick]] < cam["instances"]["first_service"])
        dist = dist[~art]
        if len(dist):
            worst = max(worst, float(dist.max()))
            checked += len(dist)
        for (p, cid) in zip(world_pts[~art], cls[vs[pick], us[pick]][~art]):
            c_ = legend[int(cid)]
            if c_["surface"] != "rock" or "tile_kind" not in c_:
                continue
            kinds_all += 1
            if c_["tile_kind"] in kinds_near(p):
                kinds_ok += 1

assert checked > 0
assert worst < 2e-3, f"a depth pixel lies {worst} m off the surface"
assert kinds_all == 0 or kinds_ok / kinds_all > 0.95, (kinds_ok, kinds_all)

out = {"images": images, "depth_pixels": checked, "max_distance_m": worst,
       "tile_kinds_agree": kinds_ok, "tile_kinds_checked": kinds_all}

bag = seq / "bag"
if bag.exists():
    from rosbags.highlevel import AnyReader

    seen = {}
    with AnyReader([bag]) as reader:
        conns = [c for c in reader.connections if c.msgtype in
                 ("sensor_msgs/msg/Image", "sensor_msgs/msg/CameraInfo")]
        for conn, ts, raw in reader.messages(connections=conns):
            msg = reader.deserialize(raw, conn.msgtype)
            seen[conn.topic] = seen.get(conn.topic, 0) + 1
            if conn.msgtype == "sensor_msgs/msg/CameraInfo":
                name = conn.topic.split("/")[1]
                ci = [c["name"] for c in model["cameras"]].index(name)
                fu, fv, pu, pv = chain[f"cam{ci}"]["intrinsics"]
                assert np.allclose(msg.k, [fu, 0, pu, 0, fv, pv, 0, 0, 1]), msg.k
            elif conn.topic.endswith("/image_raw") and "depth" not in conn.topic:
                name = conn.topic.split("/")[1]
                stamp = msg.header.stamp.sec * 10**9 + msg.header.stamp.nanosec
                png = cv2.imread(str(seq / f"camera/{name}/rgb/{stamp}.png"), cv2.IMREAD_UNCHANGED)
                data = np.frombuffer(msg.data, dtype=np.uint8).reshape(png.shape)
                if png.ndim == 3:
                    png = cv2.cvtColor(png, cv2.COLOR_BGR2RGB)
                assert (data == png).all(), conn.topic
    for c in model["cameras"]:
        assert seen.get(f"/{c['name']}/image_raw") == len(frames), seen
    out["bag_images"] = sum(v for k_, v in seen.items() if k_.endswith("image_raw"))

tum = seq / "tum"
if tum.exists():
    pairs = [l.split() for l in (tum / "associations.txt").read_text().splitlines() if l.strip()]
    assert len(pairs) == len(frames)
    lo, hi = model["depth_range_m"]
    for t_rgb, rgb, t_d, dep in pairs[:: max(1, len(pairs) // 5)]:
        d16 = cv2.imread(str(tum / dep), cv2.IMREAD_UNCHANGED)
        assert d16.dtype == np.uint16
        stamp = int(round(float(t_rgb) * 1e9))
        truth = cv2.imread(str(seq / f"camera/cam0/depth/{stamp}.tiff"), cv2.IMREAD_UNCHANGED)
        ok = (truth >= lo) & (truth <= min(hi, 13.1))
        assert np.abs(d16[ok] / 5000.0 - truth[ok]).max() <= 0.5 / 5000 + 1e-6
        assert (d16[~ok] == 0).all()
    out["tum_pairs"] = len(pairs)

euroc = seq / "euroc/mav0"
if euroc.exists():
    for c in model["cameras"]:
        rows = (euroc / c["name"] / "data.csv").read_text().splitlines()[1:]
        assert len(rows) == len(frames)
        first = rows[0].split(",")
        assert (euroc / c["name"] / "data" / first[1]).exists()
        y = yaml.safe_load((euroc / c["name"] / "sensor.yaml").read_text())
        assert y["resolution"] == chain[f"cam{[x['name'] for x in model['cameras']].index(c['name'])}"]["resolution"]
    imu = np.loadtxt(euroc / "imu0/data.csv", delimiter=",", comments="#")
    assert imu.shape[1] == 7 and len(imu) > 0
    out["euroc_imu"] = len(imu)

print(json.dumps(out))
