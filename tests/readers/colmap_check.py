"""Reconstructs a camera sequence's first camera with COLMAP (pycolmap) from its images alone,
then scores the camera centres against the ground truth with evo (a similarity alignment,
as `evo_ape tum gt est -as` does).

    colmap_check.py SEQUENCE WORK [--from SECONDS]

SIFT features on the CPU, matched sequentially (each image with its 10 successors), mapped
incrementally with the true intrinsics held fixed (Kalibr's camchain.yaml). Images stamped
before --from (the platform standing still) are left out. Prints one JSON line: images,
registered, and the APE's RMSE in metres after the Sim(3) alignment (null when fewer than
three images were registered).
"""
import json
import shutil
import sys
from pathlib import Path

import numpy as np
import pycolmap
import yaml
from evo.core import metrics, sync
from evo.core.trajectory import PoseTrajectory3D

seq = Path(sys.argv[1])
work = Path(sys.argv[2])
start = float(sys.argv[sys.argv.index("--from") + 1]) if "--from" in sys.argv else 0.0
shutil.rmtree(work, ignore_errors=True)
images = work / "images"
images.mkdir(parents=True)
meta = json.loads((seq / "sequence.json").read_text())
name = meta["camera"]["model"]["cameras"][0]["name"]
chain = yaml.safe_load((seq / "camera/camchain.yaml").read_text())["cam0"]
truth = {}
for line in (seq / f"camera/{name}/ground_truth.tum").read_text().splitlines():
    if not line.strip() or line.startswith("#"):
        continue
    v = [float(x) for x in line.split()]
    truth[int(round(v[0] * 1e9))] = v
for f in meta["camera_frames"]:
    if f["time"] + 1e-9 < start:
        continue
    stamp = int(round(f["time"] * 1e9))
    shutil.copy(seq / f"camera/{name}/rgb/{stamp}.png", images / f"{stamp:020d}.png")
names = sorted(p.name for p in images.iterdir())

fu, fv, pu, pv = chain["intrinsics"]
k = chain["distortion_coeffs"]
if chain["distortion_model"] == "equidistant":
    model, params = "OPENCV_FISHEYE", [fu, fv, pu, pv, *k]
else:
    model, params = "OPENCV", [fu, fv, pu, pv, *k]
db = work / "database.db"
reader = pycolmap.ImageReaderOptions()
reader.camera_model = model
reader.camera_params = ",".join(str(x) for x in params)
pycolmap.extract_features(db, images, camera_mode=pycolmap.CameraMode.SINGLE,
                          reader_options=reader, device=pycolmap.Device.cpu)
if "--exhaustive" in sys.argv:
    pycolmap.match_exhaustive(db, device=pycolmap.Device.cpu)
else:
    pairing = pycolmap.SequentialPairingOptions()
    pairing.overlap = int(sys.argv[sys.argv.index("--overlap") + 1]) if "--overlap" in sys.argv else 10
    pycolmap.match_sequential(db, pairing_options=pairing, device=pycolmap.Device.cpu)
options = pycolmap.IncrementalPipelineOptions()
options.ba_refine_focal_length = False
options.ba_refine_principal_point = False
options.ba_refine_extra_params = False
out = work / "sparse"
out.mkdir()
maps = pycolmap.incremental_mapping(db, images, out, options)
best = max(maps.values(), key=lambda r: sum(1 for i in r.images.values() if i.has_pose),
           default=None)
registered = sum(1 for i in best.images.values() if i.has_pose) if best is not None else 0
result = {"images": len(names), "registered": registered, "ape_rmse_m": None}
if best is not None and registered >= 3:
    est = []
    for image in best.images.values():
        if not image.has_pose:
            continue
        stamp = int(image.name.split(".")[0])
        c = image.projection_center()
        est.append((stamp / 1e9, c))
    est.sort()
    ts = np.array([t for t, _ in est])
    xyz = np.array([c for _, c in est])
    quat = np.tile([1.0, 0.0, 0.0, 0.0], (len(ts), 1))
    ref_rows = [truth[int(round(t * 1e9))] for t in ts]
    ref = PoseTrajectory3D(np.array([r[1:4] for r in ref_rows]),
                           np.array([[r[7], r[4], r[5], r[6]] for r in ref_rows]), ts)
    estimate = PoseTrajectory3D(xyz, quat, ts)
    ref, estimate = sync.associate_trajectories(ref, estimate)
    estimate.align(ref, correct_scale=True)
    ape = metrics.APE(metrics.PoseRelation.translation_part)
    ape.process_data((ref, estimate))
    result["ape_rmse_m"] = float(ape.get_statistic(metrics.StatisticsType.rmse))
    result["path_m"] = float(np.sum(np.linalg.norm(np.diff(ref.positions_xyz, axis=0), axis=1)))
print(json.dumps(result))
