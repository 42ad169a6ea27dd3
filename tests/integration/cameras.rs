//! `subtgraph sense --camera`: lamp-lit images with depth, classes and instances, checked by
//! the programs that read them (OpenCV, trimesh, rosbags: tests/readers/camera_check.py;
//! COLMAP through pycolmap, evo: tests/readers/colmap_check.py), the same on one and three
//! threads, and refused with a clear error and nothing written when the input is wrong.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::{self, arg, fails, ok, read_with_python, small_cave_pipeline};

/// A small cave world folder with ground truth, in `dir`; `extra` goes into its pipeline.
fn cave_world(dir: &Path, name: &str, levels: u32, extra: &str) -> PathBuf {
    let sub = dir.join(format!("{name}-pipeline"));
    std::fs::create_dir_all(&sub).unwrap();
    let pipeline = small_cave_pipeline(&sub, levels, extra);
    let out = dir.join(name);
    ok(&[
        "generate",
        arg(&pipeline),
        "--out",
        arg(&out),
        "--format",
        "ground-truth",
    ]);
    out
}

fn sense(world: &Path, out: &Path, extra: &[&str]) -> String {
    let mut args = vec!["sense", arg(world), "--out", arg(out)];
    args.extend_from_slice(extra);
    ok(&args)
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_slice(&std::fs::read(path).unwrap()).unwrap()
}

#[test]
fn camera_sequences_are_what_opencv_trimesh_and_rosbags_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let world = cave_world(dir.path(), "cave", 2, "");
    let readers = ["cv2", "trimesh", "rtree", "yaml", "rosbags"];
    for (name, extra) in [
        // A stereo pair beside the LiDAR: the camera folder, EuRoC, the bag.
        ("stereo", &["--camera", "stereo", "--duration", "1"][..]),
        // RGB-D alone: the camera folder, TUM RGB-D, the bag with depth.
        (
            "d435i",
            &[
                "--camera",
                "d435i",
                "--lidar",
                "none",
                "--camera-rate",
                "15",
                "--duration",
                "1",
            ][..],
        ),
        // A fisheye pair on the aerial platform, lamps brighter, a little ambient light.
        (
            "fisheye",
            &[
                "--camera",
                "fisheye-stereo",
                "--platform",
                "aerial",
                "--route",
                "levels",
                "--lidar",
                "none",
                "--camera-rate",
                "5",
                "--duration",
                "1",
                "--lamp-lumens",
                "3000",
                "--ambient",
                "0.5",
            ][..],
        ),
        // The D435i's colour camera as it is, its rows exposed one after another, with motion
        // blur (standing still: the same geometry).
        (
            "rolling",
            &[
                "--camera",
                "d435i",
                "--lidar",
                "none",
                "--rolling-shutter",
                "--motion-blur",
                "--camera-rate",
                "4",
                "--duration",
                "1",
            ][..],
        ),
    ] {
        let seq = dir.path().join(name);
        let said = sense(&world, &seq, extra);
        assert!(said.contains("cameras:"), "{said}");
        let meta = json(&seq.join("sequence.json"));
        let frames = meta["camera_frames"].as_array().unwrap();
        assert_eq!(
            frames.len() as u64,
            meta["camera"]["frame_count"].as_u64().unwrap()
        );
        assert!(!seq.join("camera/.frames.jsonl").exists());
        if let Some(out) = read_with_python(&readers, "camera_check.py", &[arg(&seq), arg(&world)])
        {
            eprintln!("{name}: {out}");
            let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
            assert!(v["max_distance_m"].as_f64().unwrap() < 2e-3, "{v}");
        }
    }
    // Lamp-lit: the first frames are lit, well exposed, with corners to track.
    let meta = json(&dir.path().join("stereo/sequence.json"));
    let f = &meta["camera_frames"][0]["cameras"][0];
    assert!(f["lit_share"].as_f64().unwrap() > 0.3, "{f}");
    assert!(f["keypoints"].as_u64().unwrap() > 50, "{f}");
    // With the LiDAR the TUM ground truth is still the LiDAR's; without, the first camera's.
    assert!(meta["lidar"].is_object());
    let d = json(&dir.path().join("d435i/sequence.json"));
    assert!(d["lidar"].is_null());
    assert!(
        d["outputs"]["ground_truth"]
            .as_str()
            .unwrap()
            .contains("camera")
    );
    assert!(dir.path().join("d435i/tum/associations.txt").is_file());
    assert!(!dir.path().join("d435i/kitti").exists());
    assert!(dir.path().join("stereo/euroc/mav0/cam1/data.csv").is_file());
}

#[test]
fn camera_sequences_are_the_same_on_one_and_three_threads() {
    let dir = tempfile::tempdir().unwrap();
    let world = cave_world(dir.path(), "cave", 1, "");
    let mut folders = Vec::new();
    for threads in ["1", "3"] {
        let out = dir.path().join(format!("t{threads}"));
        let status = Command::new(common::binary())
            .args([
                "sense",
                arg(&world),
                "--out",
                arg(&out),
                "--duration",
                "0.6",
            ])
            .args(["--camera", "stereo", "--camera-rate", "5"])
            .env("RAYON_NUM_THREADS", threads)
            .output()
            .unwrap();
        assert!(status.status.success(), "{status:?}");
        folders.push(out);
    }
    common::assert_same_files(&folders[0], &folders[1], &[]);
}

#[test]
fn bad_camera_input_is_refused_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let world = cave_world(dir.path(), "cave", 1, "");
    let out = dir.path().join("seq");
    let table = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let good = "name = \"t\"\nrate_hz = 10\n[sensor]\npixel_um = 3.0\nfull_well_e = 8000\n\
        read_noise_e = 3\nquantum_efficiency = 0.5\ncolour = true\nf_number = 2.0\n\
        exposure_ms = [0.02, 20.0]\nmax_gain_db = 12\n[[camera]]\nwidth = 320\nheight = 240\n\
        focal = [250.0, 250.0]\ncentre = [159.5, 119.5]\ndistortion = \"radtan\"\n\
        coefficients = [0.0, 0.0, 0.0, 0.0]\n";
    let zero = table("zero.toml", &good.replace("[250.0, 250.0]", "[0.0, 250.0]"));
    let folds = table(
        "folds.toml",
        &good.replace("[0.0, 0.0, 0.0, 0.0]", "[-2.0, 0.0, 0.0, 0.0]"),
    );
    let unknown = table("unknown.toml", &good.replace("max_gain_db", "gain_max_db"));
    let huge = table("huge.toml", &good.replace("width = 320", "width = 40000"));
    let (zero, folds, unknown, huge) = (arg(&zero), arg(&folds), arg(&unknown), arg(&huge));
    let cases: &[(&[&str], &str)] = &[
        (&["--camera", "zed-2"], "unknown camera model 'zed-2'"),
        (&["--camera", zero], "focal length of cam0"),
        (&["--camera", folds], "does not fold the image"),
        (&["--camera", unknown], "gain_max_db"),
        (&["--camera", huge], "resolution of cam0"),
        (
            &["--camera", "stereo", "--camera-rate", "1000"],
            "rate_hz of camera 'stereo'",
        ),
        (
            &["--camera", "d435i", "--camera-rate", "0"],
            "rate_hz of camera 'd435i'",
        ),
        (&["--lidar", "none"], "a sequence needs a LiDAR or a camera"),
        (
            &["--camera", "stereo", "--lidar", "none", "--format", "kitti"],
            "--format kitti",
        ),
        (
            &["--camera", "stereo", "--format", "tum-rgbd"],
            "an RGB-D camera",
        ),
        (&["--format", "euroc"], "--format euroc"),
        (&["--camera", "stereo", "--lamp-lumens=-5"], "--lamp-lumens"),
        (
            &["--camera", "stereo", "--max-disk", "50M"],
            "camera frames of",
        ),
    ];
    for (extra, says) in cases {
        let mut args = vec!["sense", arg(&world), "--out", arg(&out)];
        args.extend_from_slice(extra);
        let e = fails(&args);
        assert!(e.contains(says), "{extra:?}: {e}");
        assert!(!out.exists(), "{extra:?} wrote {}", out.display());
    }
    // dataset --sense-camera is checked before any world is made.
    let fresh = dir.path().join("fresh");
    let pipeline = small_cave_pipeline(dir.path(), 1, "");
    let e = fails(&[
        "dataset",
        arg(&pipeline),
        "--count",
        "1",
        "--sense",
        "--sense-camera",
        "zed-2",
        "--out",
        arg(&fresh),
    ]);
    assert!(e.contains("unknown camera model 'zed-2'"), "{e}");
    assert!(!fresh.exists());
}

#[test]
fn colmap_registers_a_lamp_lit_route_and_nothing_of_a_dark_textureless_one() {
    // COLMAP (pycolmap) from the images alone registers the lamp-lit frames of a driven route,
    // and nothing in a world without textures with the lamps off (the negative control). Its
    // camera centres after a similarity alignment (evo) are printed, not asserted: on the
    // cave they are metres off (docs/src/cameras.md says what was found).
    let Some(_) = common::python_with(&["pycolmap", "evo", "cv2"]) else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let world = cave_world(dir.path(), "cave", 1, "");
    let camera = [
        "--camera",
        "mono",
        "--lidar",
        "none",
        "--camera-rate",
        "5",
        "--duration",
        "7",
    ];
    let lit = dir.path().join("lit");
    sense(&world, &lit, &camera);
    let plain = cave_world(dir.path(), "plain", 1, "textures = \"none\"\n");
    let dark = dir.path().join("dark");
    let mut off = camera.to_vec();
    off.extend(["--lamp-lumens", "0"]);
    sense(&plain, &dark, &off);
    let run = |seq: &Path, work: &str| -> serde_json::Value {
        let out = read_with_python(
            &["pycolmap", "evo", "cv2"],
            "colmap_check.py",
            &[
                arg(seq),
                arg(&dir.path().join(work)),
                "--from",
                "2.0",
                "--overlap",
                "4",
            ],
        )
        .unwrap();
        eprintln!("{work}: {out}");
        serde_json::from_str(out.trim()).unwrap()
    };
    let good = run(&lit, "colmap-lit");
    let registered = good["registered"].as_u64().unwrap();
    let images = good["images"].as_u64().unwrap();
    assert!(registered * 10 >= images * 8, "{good}");
    let bad = run(&dark, "colmap-dark");
    assert!(bad["registered"].as_u64().unwrap() < 3, "{bad}");
}
