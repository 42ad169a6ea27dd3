//! Cameras in dust (issue 39 item 3): with `--conditions` and `--camera` together, each pixel's
//! light is dimmed by the dust along its ray and the lamps' light scattered back adds a veil
//! that grows with their power. OpenCV and numpy read the images (tests/readers/haze_check.py);
//! the exposure is fixed (a camera table whose shortest and longest exposure agree, no gain), so
//! the grey levels compare across sequences. The same bytes on 1 and 3 threads, and
//! `--conditions none` renders what no option does.

use std::path::{Path, PathBuf};
use std::process::Command;

use crate::common::{arg, assert_same_files, ok, read_with_python, small_cave_pipeline};

/// One grey camera, 320 x 240, its exposure fixed at 8 ms with no gain.
const FIXED_EXPOSURE: &str = "name = \"fixed\"\nrate_hz = 10\n[sensor]\npixel_um = 3.0\n\
    full_well_e = 10000\nread_noise_e = 2\nquantum_efficiency = 0.6\ncolour = false\n\
    f_number = 2.0\nexposure_ms = [8.0, 8.0]\nmax_gain_db = 0\n[[camera]]\nwidth = 320\n\
    height = 240\nfocal = [230.0, 230.0]\ncentre = [159.5, 119.5]\ndistortion = \"radtan\"\n\
    coefficients = [0.0, 0.0, 0.0, 0.0]\n";

/// Dust standing along the whole route.
const DUST: &str = "[[conditions]]\ntype = \"dust\"\nat = \"route\"\ndensity_mg_m3 = 400\n";

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// `sense` with the fixed-exposure camera and no LiDAR, 1 s (10 frames), `extra` after.
fn camera_sequence(world: &Path, out: &Path, table: &Path, extra: &[&str], threads: &str) {
    let mut args = vec![
        "sense",
        arg(world),
        "--out",
        arg(out),
        "--camera",
        arg(table),
        "--lidar",
        "none",
        "--duration",
        "1",
    ];
    args.extend_from_slice(extra);
    let o = Command::new(env!("CARGO_BIN_EXE_subtgraph"))
        .args(&args)
        .env("RAYON_NUM_THREADS", threads)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

#[test]
fn dust_veils_the_cameras_and_the_veil_grows_with_the_lamps() {
    let dir = tempfile::tempdir().unwrap();
    let pipeline = small_cave_pipeline(dir.path(), 1, "");
    let world = dir.path().join("cave");
    ok(&[
        "generate",
        arg(&pipeline),
        "--out",
        arg(&world),
        "--format",
        "ground-truth",
    ]);
    let table = write(dir.path(), "fixed.toml", FIXED_EXPOSURE);
    let dust = write(dir.path(), "dust.toml", DUST);
    let seq = |name: &str| dir.path().join(name);
    for (name, lumens, conditions) in [
        ("clean-low", "400", None),
        ("dust-low", "400", Some(&dust)),
        ("clean-high", "1600", None),
        ("dust-high", "1600", Some(&dust)),
    ] {
        let mut extra = vec!["--lamp-lumens", lumens];
        if let Some(c) = conditions {
            extra.extend(["--conditions", arg(c)]);
        }
        camera_sequence(&world, &seq(name), &table, &extra, "1");
    }
    // Clear air is what it was: --conditions none, and no option, the same images.
    camera_sequence(
        &world,
        &seq("none-low"),
        &table,
        &["--lamp-lumens", "400", "--conditions", "none"],
        "1",
    );
    assert_same_files(&seq("clean-low/camera"), &seq("none-low/camera"), &[]);
    // The same bytes on 3 threads.
    camera_sequence(
        &world,
        &seq("dust-low-3"),
        &table,
        &["--lamp-lumens", "400", "--conditions", arg(&dust)],
        "3",
    );
    assert_same_files(&seq("dust-low/camera"), &seq("dust-low-3/camera"), &[]);

    let named: Vec<String> = ["clean-low", "dust-low", "clean-high", "dust-high"]
        .iter()
        .map(|n| format!("{n}={}", seq(n).display()))
        .collect();
    let args: Vec<&str> = named.iter().map(String::as_str).collect();
    let Some(out) = read_with_python(&["cv2", "numpy"], "haze_check.py", &args) else {
        return;
    };
    eprintln!("{out}");
    let v: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    let get = |seq: &str, key: &str| v[seq][key].as_f64().unwrap();
    for level in ["low", "high"] {
        let (clean, dusty) = (format!("clean-{level}"), format!("dust-{level}"));
        // Lower contrast in dust, its dark end lifted by the veil.
        assert!(
            get(&dusty, "contrast") < 0.9 * get(&clean, "contrast"),
            "{level}: contrast {} in dust against {} in clean air: {v}",
            get(&dusty, "contrast"),
            get(&clean, "contrast")
        );
        assert!(get(&dusty, "dark") > get(&clean, "dark"), "{level}: {v}");
    }
    // The veil over the far surfaces grows with the lamps' power (four times the light: the
    // 8-bit values are gamma-encoded, so less than four times the grey levels).
    let lift = |level: &str, key: &str| {
        get(&format!("dust-{level}"), key) - get(&format!("clean-{level}"), key)
    };
    assert!(lift("low", "far_mean") > 5.0, "no veil at 400 lm: {v}");
    assert!(
        lift("high", "far_mean") > 1.5 * lift("low", "far_mean"),
        "the veil at 1,600 lm ({}) is not 1.5 times that at 400 lm ({}): {v}",
        lift("high", "far_mean"),
        lift("low", "far_mean")
    );
    // Brightest where the lamps' beams cross the view, the image's middle, not its sides.
    for level in ["low", "high"] {
        assert!(
            lift(level, "near_lamp") > 1.5 * lift(level, "edge"),
            "{level}: the veil in the middle {} against {} at the sides: {v}",
            lift(level, "near_lamp"),
            lift(level, "edge")
        );
    }
}
