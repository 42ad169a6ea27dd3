//! `subtgraph score --trajectory` on synthetic runs whose answers are formulas: identical
//! (every error 0), a jump of known size, a scale error (0 after Sim(3) alignment) and a
//! constant yaw drift (APE and RPE by closed form); every number of each also compared with
//! evo on the same files and options (`tests/readers/trajectory_check.py`, to 1e-6 relative).
//! KITTI files give what the same poses in TUM give; a sensor sequence folder is read as its
//! ground truth; bad input is refused naming the file and line, and nothing is written.

use crate::common;

use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use common::{arg, fails, ok, read_with_python};
use serde_json::Value;

/// `(t, position, quaternion [x y z w])`.
type Row = (f64, [f64; 3], [f64; 4]);

fn yaw(a: f64) -> [f64; 4] {
    [0.0, 0.0, (a / 2.0).sin(), (a / 2.0).cos()]
}

/// `a b` for `[x y z w]` quaternions.
fn mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    let [ax, ay, az, aw] = a;
    let [bx, by, bz, bw] = b;
    [
        aw * bx + ax * bw + ay * bz - az * by,
        aw * by - ax * bz + ay * bw + az * bx,
        aw * bz + ax * by - ay * bx + az * bw,
        aw * bw - ax * bx - ay * by - az * bz,
    ]
}

fn write_tum(path: &Path, rows: &[Row]) -> PathBuf {
    let mut s = String::from("# t x y z qx qy qz qw\n");
    for (t, p, q) in rows {
        let _ = writeln!(
            s,
            "{t} {} {} {} {} {} {} {}",
            p[0], p[1], p[2], q[0], q[1], q[2], q[3]
        );
    }
    std::fs::write(path, s).unwrap();
    path.to_path_buf()
}

/// The same poses as KITTI rows, with `times` beside them under `times_name`.
fn write_kitti(path: &Path, rows: &[Row], times_name: &str) {
    let (mut poses, mut times) = (String::new(), String::new());
    for (t, p, q) in rows {
        let [x, y, z, w] = *q;
        let r = [
            [
                1.0 - 2.0 * (y * y + z * z),
                2.0 * (x * y - z * w),
                2.0 * (x * z + y * w),
            ],
            [
                2.0 * (x * y + z * w),
                1.0 - 2.0 * (x * x + z * z),
                2.0 * (y * z - x * w),
            ],
            [
                2.0 * (x * z - y * w),
                2.0 * (y * z + x * w),
                1.0 - 2.0 * (x * x + y * y),
            ],
        ];
        let _ = writeln!(
            poses,
            "{} {} {} {} {} {} {} {} {} {} {} {}",
            r[0][0],
            r[0][1],
            r[0][2],
            p[0],
            r[1][0],
            r[1][1],
            r[1][2],
            p[1],
            r[2][0],
            r[2][1],
            r[2][2],
            p[2]
        );
        let _ = writeln!(times, "{t}");
    }
    std::fs::write(path, poses).unwrap();
    std::fs::write(path.with_file_name(times_name), times).unwrap();
}

/// A winding, climbing reference: 3D positions and orientations that turn about every axis,
/// so no alignment is degenerate. `n` poses at 10 Hz.
fn reference(n: usize) -> Vec<Row> {
    (0..n).map(|k| at(k as f64 * 0.1)).collect()
}

/// The reference's pose at time `s`.
fn at(s: f64) -> Row {
    let p = [
        6.0 * s + 8.0 * (0.07 * s).sin(),
        5.0 * (0.11 * s).sin() + 0.5 * s,
        0.4 * s + (0.3 * s).cos(),
    ];
    let h = 0.05 * (0.2 * s).sin();
    let pitch = [h.sin(), 0.0, 0.0, h.cos()];
    (s, p, mul(yaw(0.3 * s), pitch))
}

fn json(out: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(out.join("trajectory.json")).unwrap()).unwrap()
}

fn num(v: &Value, path: &str) -> f64 {
    path.split('.')
        .fold(v, |v, k| &v[k])
        .as_f64()
        .unwrap_or_else(|| panic!("{path} is not a number: {v}"))
}

/// Scores `est` against `reference` with `flags`, checks it with evo (when evo is
/// installed), and returns trajectory.json.
fn score(dir: &Path, name: &str, reference: &Path, est: &Path, flags: &[&str]) -> Value {
    let out = dir.join(name);
    let mut args = vec![
        "score",
        arg(reference),
        "--trajectory",
        arg(est),
        "--out",
        arg(&out),
    ];
    args.extend_from_slice(flags);
    ok(&args);
    read_with_python(&["evo"], "trajectory_check.py", &[arg(&out)]);
    json(&out)
}

fn near(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} but {b} expected");
}

#[test]
fn identical_trajectories_score_zero_with_every_alignment() {
    let dir = tempfile::tempdir().unwrap();
    let rows = reference(300);
    let r = write_tum(&dir.path().join("ref.tum"), &rows);
    let e = write_tum(&dir.path().join("est.tum"), &rows);
    for align in ["none", "se3", "sim3"] {
        let j = score(dir.path(), align, &r, &e, &["--align", align]);
        assert_eq!(j["associated_poses"], 300);
        for what in [
            "ape_m.max",
            "rpe.translation_m.max",
            "rpe.rotation_deg.max",
            "final_drift_m",
        ] {
            near(num(&j, what), 0.0, 1e-9, &format!("{align}: {what}"));
        }
        assert_eq!(num(&j, "points_mean"), 10.0);
        assert_eq!(j["failed"], false);
    }
}

#[test]
fn a_jump_gives_its_size_as_ape_from_there_on() {
    let dir = tempfile::tempdir().unwrap();
    let rows = reference(200);
    let n = rows.len() as f64;
    let mut jumped = rows.clone();
    for row in &mut jumped[1..] {
        row.1[0] += 0.4;
    }
    let r = write_tum(&dir.path().join("ref.tum"), &rows);
    let e = write_tum(&dir.path().join("est.tum"), &jumped);
    let j = score(dir.path(), "jump", &r, &e, &[]);
    near(num(&j, "ape_m.max"), 0.4, 1e-9, "max APE");
    near(num(&j, "ape_m.median"), 0.4, 1e-9, "median APE");
    near(num(&j, "ape_m.mean"), 0.4 * (n - 1.0) / n, 1e-9, "mean APE");
    near(
        num(&j, "ape_m.rmse"),
        (0.16 * (n - 1.0) / n).sqrt(),
        1e-9,
        "APE RMSE",
    );
    near(
        num(&j, "rpe.translation_m.max"),
        0.4,
        1e-9,
        "RPE max: the jump",
    );
    near(
        num(&j, "rpe.translation_m.mean"),
        0.4 / (n - 1.0),
        1e-9,
        "RPE mean",
    );
    let length = num(&j, "path_length_m");
    near(
        num(&j, "final_drift_percent"),
        40.0 / length,
        1e-9,
        "final drift",
    );
    // 0.4 m earns 3 points (at most 50 cm); the first pose, on the reference, 10.
    near(
        num(&j, "points_mean"),
        (10.0 + 3.0 * (n - 1.0)) / n,
        1e-12,
        "points",
    );
    assert_eq!(
        j["failed"], false,
        "0.4 m is within the default jump limit of 1 m"
    );
    let j = score(dir.path(), "jump-flagged", &r, &e, &["--fail-jump", "0.3"]);
    assert_eq!(j["failed"], true);
    assert_eq!(j["failure"]["kind"], "jump");
    assert_eq!(j["failure"]["pose"], 1);
    let j = score(dir.path(), "diverged", &r, &e, &["--fail-ape", "0.2"]);
    assert_eq!(j["failure"]["kind"], "divergence");
    assert_eq!(j["failure"]["pose"], 1);
}

#[test]
fn a_scale_error_vanishes_with_sim3_alignment_only() {
    let dir = tempfile::tempdir().unwrap();
    let rows = reference(250);
    let scaled: Vec<Row> = rows
        .iter()
        .map(|&(t, p, q)| (t, p.map(|x| 1.5 * x + 2.0), q))
        .collect();
    let r = write_tum(&dir.path().join("ref.tum"), &rows);
    let e = write_tum(&dir.path().join("est.tum"), &scaled);
    let j = score(
        dir.path(),
        "sim3",
        &r,
        &e,
        &["--align", "sim3", "--delta", "5"],
    );
    near(num(&j, "ape_m.max"), 0.0, 1e-9, "APE after Sim(3)");
    near(num(&j, "alignment.scale"), 1.0 / 1.5, 1e-12, "scale");
    near(
        num(&j, "rpe.translation_m.max"),
        0.0,
        1e-9,
        "RPE after Sim(3)",
    );
    let j = score(dir.path(), "se3", &r, &e, &["--align", "se3"]);
    assert!(
        num(&j, "ape_m.rmse") > 1.0,
        "a rigid alignment cannot undo a scale: {j}"
    );
    score(dir.path(), "none", &r, &e, &["--align", "none"]);
}

/// The estimate turns `d` radians more than the reference each step of a straight line `l`
/// metres a step: after `k` steps it is at `l Σ_{i<k} e^{i i d}`, a chord of a circle.
fn drifted_chord(l: f64, d: f64, k: usize) -> [f64; 2] {
    if k == 0 {
        return [0.0, 0.0];
    }
    let (k, h) = (k as f64, d / 2.0);
    let r = l * (k * h).sin() / h.sin();
    [r * ((k - 1.0) * h).cos(), r * ((k - 1.0) * h).sin()]
}

#[test]
fn a_constant_yaw_drift_matches_its_closed_form() {
    let dir = tempfile::tempdir().unwrap();
    let (l, d, n) = (0.5, 0.05 * PI / 180.0, 450);
    let rows: Vec<Row> = (0..n)
        .map(|k| {
            (
                k as f64 * 0.1,
                [k as f64 * l, 0.0, 0.0],
                [0.0, 0.0, 0.0, 1.0],
            )
        })
        .collect();
    // 3 ms late, as a real estimate is: associated within the default 10 ms.
    let drifted: Vec<Row> = (0..n)
        .map(|k| {
            let [x, y] = drifted_chord(l, d, k);
            (k as f64 * 0.1 + 0.003, [x, y, 0.0], yaw(k as f64 * d))
        })
        .collect();
    let r = write_tum(&dir.path().join("ref.tum"), &rows);
    let e = write_tum(&dir.path().join("est.tum"), &drifted);
    let j = score(dir.path(), "yaw", &r, &e, &["--fail-ape", "1000"]);
    let ape: Vec<f64> = (0..n)
        .map(|k| {
            let [x, y] = drifted_chord(l, d, k);
            (x - k as f64 * l).hypot(y)
        })
        .collect();
    near(num(&j, "ape_m.max"), ape[n - 1], 1e-9, "max APE");
    near(num(&j, "final_drift_m"), ape[n - 1], 1e-9, "final drift");
    let mean = ape.iter().sum::<f64>() / n as f64;
    near(num(&j, "ape_m.mean"), mean, 1e-9, "mean APE");
    near(
        num(&j, "rpe.translation_m.max"),
        0.0,
        1e-9,
        "RPE translation per frame",
    );
    near(
        num(&j, "rpe.rotation_deg.mean"),
        0.05,
        1e-9,
        "RPE rotation per frame",
    );
    // Over 10 m: pairs 20 steps apart, each off by the chord's error after 20 steps.
    let [x, y] = drifted_chord(l, d, 20);
    let seg = &j["segments"][0];
    assert_eq!(num(seg, "delta"), 10.0);
    near(
        num(seg, "translation_m.max"),
        (x - 10.0).hypot(y),
        1e-9,
        "10 m RPE",
    );
    near(
        num(seg, "translation_m.min"),
        (x - 10.0).hypot(y),
        1e-9,
        "10 m RPE",
    );
    near(
        num(seg, "translation_percent"),
        10.0 * (x - 10.0).hypot(y),
        1e-7,
        "10 m %",
    );
    near(
        num(seg, "rotation_deg_per_100m"),
        20.0 * 0.05 * 10.0,
        1e-7,
        "deg/100 m",
    );
    let seg = &j["segments"][1];
    near(
        num(seg, "rotation_deg_per_100m"),
        200.0 * 0.05,
        1e-7,
        "deg/100 m over 100 m",
    );
}

#[test]
fn an_estimate_at_another_rate_is_associated_as_evo_does() {
    let dir = tempfile::tempdir().unwrap();
    let rows = reference(400);
    // 20 Hz with up to ±15 ms of jitter and a slow drift: some poses fall outside the
    // default 10 ms of every reference pose, some two land on the same one.
    let est: Vec<Row> = (0..800)
        .map(|k| {
            let kf = k as f64;
            let t = 0.05 * kf + 0.015 * (1.7 * kf).sin();
            let (_, p, q) = at(t);
            (t, [p[0] + 0.002 * kf, p[1], p[2]], mul(q, yaw(0.0005 * kf)))
        })
        .collect();
    let r = write_tum(&dir.path().join("ref.tum"), &rows);
    let e = write_tum(&dir.path().join("est.tum"), &est);
    for (align, delta) in [("none", "1"), ("se3", "5"), ("sim3", "2")] {
        let j = score(
            dir.path(),
            align,
            &r,
            &e,
            &["--align", align, "--delta", delta],
        );
        let pairs = j["associated_poses"].as_u64().unwrap();
        assert!(pairs > 100 && pairs < 400, "{align}: {pairs} pairs");
    }
    let j = score(dir.path(), "wide", &r, &e, &["--max-diff", "0.05"]);
    assert_eq!(
        j["associated_poses"], 400,
        "every reference pose within 50 ms"
    );
}

#[test]
fn kitti_files_score_as_the_same_poses_in_tum() {
    let dir = tempfile::tempdir().unwrap();
    let rows = reference(200);
    let est: Vec<Row> = rows
        .iter()
        .enumerate()
        .map(|(k, &(t, p, q))| {
            let k = k as f64;
            (
                t,
                [p[0] + 0.01 * k, p[1] - 0.2 * (0.1 * k).sin(), p[2]],
                mul(q, yaw(0.001 * k)),
            )
        })
        .collect();
    let r = write_tum(&dir.path().join("ref.tum"), &rows);
    let e = write_tum(&dir.path().join("est.tum"), &est);
    let tum = score(dir.path(), "tum", &r, &e, &["--align", "se3"]);
    let kr = dir.path().join("kitti-ref").join("poses.txt");
    std::fs::create_dir(kr.parent().unwrap()).unwrap();
    write_kitti(&kr, &rows, "times.txt");
    let ke = dir.path().join("est.kitti");
    write_kitti(&ke, &est, "est-times.txt");
    let out = dir.path().join("kitti");
    let times = dir.path().join("est-times.txt");
    ok(&[
        "score",
        arg(&kr),
        "--trajectory",
        arg(&ke),
        "--times",
        arg(&times),
        "--align",
        "se3",
        "--out",
        arg(&out),
    ]);
    let kitti = json(&out);
    assert_eq!(kitti["estimate"]["format"], "kitti");
    assert_eq!(kitti["reference"]["format"], "kitti");
    for what in [
        "ape_m.rmse",
        "ape_m.max",
        "rpe.translation_m.rmse",
        "rpe.rotation_deg.mean",
        "final_drift_percent",
    ] {
        let (a, b) = (num(&tum, what), num(&kitti, what));
        assert!(
            (a - b).abs() <= 1e-9 * a.abs().max(1.0),
            "{what}: TUM {a}, KITTI {b}"
        );
    }
}

#[test]
fn a_sequence_folder_is_scored_against_its_ground_truth() {
    let dir = tempfile::tempdir().unwrap();
    let rows = reference(100);
    let seq = dir.path().join("sequence");
    std::fs::create_dir(&seq).unwrap();
    write_tum(&seq.join("ground_truth.tum"), &rows);
    let e = write_tum(&dir.path().join("est.tum"), &rows);
    let out = dir.path().join("a");
    ok(&[
        "score",
        arg(&seq),
        "--trajectory",
        arg(&e),
        "--out",
        arg(&out),
    ]);
    assert!(
        json(&out)["reference"]["file"]
            .as_str()
            .unwrap()
            .ends_with("ground_truth.tum")
    );
    let world = dir.path().join("world");
    std::fs::create_dir(&world).unwrap();
    let out = dir.path().join("b");
    let err = fails(&[
        "score",
        arg(&world),
        "--trajectory",
        arg(&e),
        "--out",
        arg(&out),
    ]);
    assert!(err.contains("--reference"), "{err}");
    assert!(!out.exists());
    let gt = seq.join("ground_truth.tum");
    ok(&[
        "score",
        arg(&world),
        "--trajectory",
        arg(&e),
        "--reference",
        arg(&gt),
        "--out",
        arg(&out),
    ]);
}

#[test]
fn bad_input_is_refused_naming_the_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let good = "0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n2 2 0 0 0 0 0 1\n3 3 0 0 0 0 0 1\n";
    let r = dir.path().join("ref.tum");
    std::fs::write(&r, good).unwrap();
    let cases: &[(&str, &str, &str)] = &[
        (
            "unsorted",
            "0 0 0 0 0 0 0 1\n2 1 0 0 0 0 0 1\n1 2 0 0 0 0 0 1\n",
            "line 3: unsorted time 1",
        ),
        (
            "duplicate",
            "0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n1 2 0 0 0 0 0 1\n",
            "line 3: duplicate time 1",
        ),
        (
            "nan",
            "0 0 0 0 0 0 0 1\n1 NaN 0 0 0 0 0 1\n",
            "line 2: NaN is not a finite number",
        ),
        (
            "inf",
            "# comment\n0 0 0 0 0 0 0 1\n1 1 inf 0 0 0 0 1\n",
            "line 3: inf is not a finite number",
        ),
        (
            "quaternion",
            "0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0.1 1\n",
            "line 2: the quaternion",
        ),
        (
            "columns",
            "0 0 0 0 0 0 0 1\n1 1 0 0 0 0 1\n",
            "line 2: 7 numbers",
        ),
        (
            "text",
            "0 0 0 0 0 0 0 1\n1 x 0 0 0 0 0 1\n",
            "line 2: 'x' is not a number",
        ),
        (
            "one pose",
            "0 0 0 0 0 0 0 1\n",
            "1 pose(s): a trajectory needs at least 2",
        ),
        ("empty", "# nothing\n", "no poses"),
        (
            "no overlap",
            "100 0 0 0 0 0 0 1\n101 1 0 0 0 0 0 1\n102 1 0 0 0 0 0 1\n",
            "0 pose pair(s) within --max-diff",
        ),
        (
            "kitti rotation",
            "1 0 0 0 0 1 0 0 0 0 1 0\n2 0 0 0 0 1 0 0 0 0 1 0\n",
            "line 2: the 3x3 part is not a rotation",
        ),
        (
            "millimetres",
            "0 0 0 0 0 0 0 1\n1 1000 0 0 0 0 0 1\n2 2000 0 0 0 0 0 1\n3 3000 0 0 0 0 0 1\n",
            "millimetres where metres are expected? Give both in metres, or score with --align sim3",
        ),
        (
            "nanoseconds",
            "0 0 0 0 0 0 0 1\n1000000000 1 0 0 0 0 0 1\n2000000000 2 0 0 0 0 0 1\n3000000000 3 0 0 0 0 0 1\n",
            "nanoseconds where seconds are expected? Give both in seconds",
        ),
    ];
    for (name, text, message) in cases {
        let e = dir.path().join(format!("{}.txt", name.replace(' ', "-")));
        std::fs::write(&e, text).unwrap();
        if name.starts_with("kitti") {
            std::fs::write(e.with_file_name("times.txt"), "0\n1\n").unwrap();
        }
        let out = dir.path().join(format!("out-{}", name.replace(' ', "-")));
        let err = fails(&[
            "score",
            arg(&r),
            "--trajectory",
            arg(&e),
            "--out",
            arg(&out),
        ]);
        let file = if *name == "no overlap" { "" } else { arg(&e) };
        assert!(err.contains(message) && err.contains(file), "{name}: {err}");
        assert!(!out.exists(), "{name}: {} was written", out.display());
    }
    // A KITTI file without times, and one with too few.
    let k = dir.path().join("k").join("poses.txt");
    std::fs::create_dir(k.parent().unwrap()).unwrap();
    std::fs::write(&k, "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n").unwrap();
    let out = dir.path().join("out-k");
    let err = fails(&[
        "score",
        arg(&r),
        "--trajectory",
        arg(&k),
        "--out",
        arg(&out),
    ]);
    assert!(err.contains("--times"), "{err}");
    std::fs::write(k.with_file_name("times.txt"), "0\n").unwrap();
    let err = fails(&[
        "score",
        arg(&r),
        "--trajectory",
        arg(&k),
        "--out",
        arg(&out),
    ]);
    assert!(err.contains("1 times for the 2 poses"), "{err}");
    assert!(!out.exists());
}

#[test]
fn the_same_run_gives_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let rows = reference(120);
    let est: Vec<Row> = rows
        .iter()
        .map(|&(t, p, q)| (t, [p[0] + 0.1 * t, p[1], p[2]], q))
        .collect();
    let r = write_tum(&dir.path().join("ref.tum"), &rows);
    let e = write_tum(&dir.path().join("est.tum"), &est);
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    for out in [&a, &b] {
        ok(&[
            "score",
            arg(&r),
            "--trajectory",
            arg(&e),
            "--align",
            "sim3",
            "--out",
            arg(out),
        ]);
    }
    // The command line names its own --out, so trajectory.json differs there only.
    common::assert_same_files(&a, &b, &["trajectory.json"]);
    let strip = |p: &Path| {
        let mut j = json(p);
        j["command"] = Value::Null;
        j
    };
    assert_eq!(strip(&a), strip(&b));
    assert!(a.join("trajectory.png").is_file() && a.join("errors.csv").is_file());
}

#[test]
fn with_a_world_the_error_increase_is_placed_on_its_graph_edge() {
    let dir = tempfile::tempdir().unwrap();
    let pipeline = dir.path().join("p.toml");
    std::fs::write(
        &pipeline,
        "[world]\nseed = 5\nlevels = 1\nrows = 20\ncols = 20\ntile_pitch = 16.0\nlevel_height = 16.0\n\n\
         [topology]\nloops = 1\nt_junctions = 1\nintersections = 1\n\n[route]\ntype = \"parabolic\"\n",
    )
    .unwrap();
    let world = dir.path().join("world");
    ok(&["generate", arg(&pipeline), "--out", arg(&world)]);
    let topo: Value =
        serde_json::from_slice(&std::fs::read(world.join("topology.json")).unwrap()).unwrap();
    let (p, rows) = (num(&topo, "tile_pitch_m"), num(&topo, "rows"));
    let node = &topo["nodes"][0];
    let cell = |c: &Value| (num(c, "row"), num(c, "col"));
    let (nr, nc) = cell(&node["cell"]);
    let (oc, or) = (
        (node["position"][0].as_f64().unwrap() / p).round() - nc,
        rows - 1.0 - (node["position"][1].as_f64().unwrap() / p).round() - nr,
    );
    // The longest edge on the one level, walked cell centre to cell centre, 1 m a pose.
    let edge = topo["edges"]
        .as_array()
        .unwrap()
        .iter()
        .max_by_key(|e| e["cells"].as_array().unwrap().len())
        .unwrap();
    let centres: Vec<[f64; 2]> = edge["cells"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| {
            let (r, c) = cell(c);
            [(c + oc) * p, (rows - 1.0 - (r + or)) * p]
        })
        .collect();
    let m = centres.len();
    assert!(m >= 6, "a long edge: {edge}");
    let steps = p as usize;
    let mut reference = Vec::new();
    let mut estimate = Vec::new();
    for (i, w) in centres.windows(2).enumerate() {
        for s in 0..steps {
            let f = s as f64 / steps as f64;
            let xy = [
                w[0][0] + f * (w[1][0] - w[0][0]),
                w[0][1] + f * (w[1][1] - w[0][1]),
            ];
            // The estimate rises 2 m while the robot is between the edge's third cell and its
            // third last, well inside its corridor tiles; level before and after.
            let along = i as f64 + f;
            let rise = 2.0 * ((along - 2.0) / (m as f64 - 5.0)).clamp(0.0, 1.0);
            let t = reference.len() as f64 * 0.1;
            reference.push((t, [xy[0], xy[1], 1.0], [0.0, 0.0, 0.0, 1.0]));
            estimate.push((t, [xy[0], xy[1], 1.0 + rise], [0.0, 0.0, 0.0, 1.0]));
        }
    }
    let r = write_tum(&dir.path().join("ref.tum"), &reference);
    let e = write_tum(&dir.path().join("est.tum"), &estimate);
    let out = dir.path().join("scored");
    let printed = ok(&[
        "score",
        arg(&world),
        "--trajectory",
        arg(&e),
        "--reference",
        arg(&r),
        "--out",
        arg(&out),
    ]);
    let j = json(&out);
    let worst = &j["graph"]["largest_increases"][0];
    assert_eq!(worst["region"], "edge", "{worst}");
    assert_eq!(worst["id"], edge["id"], "{worst}");
    near(
        num(worst, "ape_increase_m"),
        2.0,
        1e-9,
        "the edge's increase",
    );
    let second = &j["graph"]["largest_increases"][1];
    near(
        num(second, "ape_increase_m"),
        0.0,
        1e-9,
        "no other stretch grew",
    );
    assert!(printed.contains("largest APE increase: edge"), "{printed}");
    // The level's picture: its tiles, and the estimate from dark (0 m) to yellow (2 m).
    assert!(!out.join("trajectory-level-1.png").exists(), "one level");
    let mut reader = png::Decoder::new(std::io::BufReader::new(
        std::fs::File::open(out.join("trajectory-level-0.png")).unwrap(),
    ))
    .read_info()
    .unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.color_type.samples();
    let px: Vec<&[u8]> = buf[..info.buffer_size()].chunks_exact(channels).collect();
    let count = |f: &dyn Fn(&[u8]) -> bool| px.iter().filter(|c| f(c)).count();
    let tiles = count(&|c| c[..3] == [222, 222, 222]);
    let yellow = count(&|c| c[0] > 220 && c[1] > 200 && c[2] < 90);
    let dark = count(&|c| c[0] < 80 && c[1] < 40 && c[2] > 60 && c[2] < 110);
    assert!(
        tiles > px.len() / 50 && yellow > 10 && dark > 10,
        "{tiles} tile, {yellow} yellow and {dark} dark pixels of {}",
        px.len()
    );
    // The increases add up to the final APE.
    let csv = std::fs::read_to_string(out.join("graph.csv")).unwrap();
    let total: f64 = csv
        .lines()
        .skip(1)
        .map(|l| l.rsplit(',').next().unwrap().parse::<f64>().unwrap())
        .sum();
    near(
        total,
        num(&j, "final_drift_m"),
        1e-9,
        "sum of the increases",
    );
    // The same run in millimetres, or in an odometry frame 10 km away, is not in the world's
    // frame: refused, saying so, and nothing written.
    for (name, f) in [("mm", 1000.0), ("far", 1.0)] {
        let moved: Vec<Row> = reference
            .iter()
            .map(|&(t, p, q)| {
                let shift = if name == "far" { 10_000.0 } else { 0.0 };
                (t, [p[0] * f + shift, p[1] * f, p[2] * f], q)
            })
            .collect();
        let m = write_tum(&dir.path().join(format!("{name}.tum")), &moved);
        let out = dir.path().join(format!("scored-{name}"));
        let e = fails(&[
            "score",
            arg(&world),
            "--trajectory",
            arg(&m),
            "--reference",
            arg(&m),
            "--out",
            arg(&out),
        ]);
        assert!(
            e.contains("outside the world") && e.contains("must be in the world frame in metres"),
            "{name}: {e}"
        );
        assert!(!out.exists());
    }
}

/// Writes `topics` (`topic:type:file.tum`) into a ROS 2 bag with rosbags; `false` when the
/// Python readers are missing (the test then skips, as [`read_with_python`] says).
fn write_bag(bag: &Path, zstd: bool, topics: &[String]) -> bool {
    let mut args = vec![arg(bag)];
    if zstd {
        args.push("--zstd");
    }
    args.extend(topics.iter().map(String::as_str));
    read_with_python(&["rosbags"], "write_bag.py", &args).is_some()
}

#[test]
fn a_ros2_bag_scores_as_the_same_poses_in_tum_and_as_evo_reads_it() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let rows = reference(300);
    let est: Vec<Row> = rows
        .iter()
        .enumerate()
        .map(|(k, &(t, p, q))| {
            let k = k as f64;
            (
                t + 0.004,
                [p[0] + 0.01 * k, p[1] + 0.1 * (0.05 * k).sin(), p[2]],
                mul(q, yaw(0.0008 * k)),
            )
        })
        .collect();
    let r = write_tum(&d.join("ref.tum"), &rows);
    let e = write_tum(&d.join("est.tum"), &est);
    let spec = |topic: &str, kind: &str, file: &Path| format!("{topic}:{kind}:{}", arg(file));
    // One zstd bag with both trajectories (as Odometry and PoseStamped) and a topic that is no
    // pose; one uncompressed bag of the estimate alone, as a TransformStamped.
    let both = d.join("both");
    let alone = d.join("alone");
    if !write_bag(
        &both,
        true,
        &[
            spec("/ground_truth", "nav_msgs/msg/Odometry", &r),
            spec("/slam/pose", "geometry_msgs/msg/PoseStamped", &e),
            spec("/notes", "std_msgs/msg/String", &e),
        ],
    ) || !write_bag(
        &alone,
        false,
        &[spec(
            "/tf_estimate",
            "geometry_msgs/msg/TransformStamped",
            &e,
        )],
    ) {
        return;
    }
    let from_tum = score(d, "tum", &r, &e, &["--align", "se3"]);
    // Both topics of one bag: checked against `evo_ape bag2` too.
    let from_bag = score(
        d,
        "bag",
        &both,
        &both,
        &[
            "--topic",
            "/slam/pose",
            "--reference-topic",
            "/ground_truth",
            "--align",
            "se3",
        ],
    );
    // The estimate's only pose topic is found without --topic.
    let mixed = score(d, "mixed", &r, &alone, &["--align", "se3"]);
    assert_eq!(mixed["estimate"]["topic"], "/tf_estimate");
    assert_eq!(from_bag["estimate"]["format"], "ros2-bag");
    for j in [&from_bag, &mixed] {
        assert_eq!(j["associated_poses"], 300);
        for what in [
            "ape_m.rmse",
            "ape_m.max",
            "rpe.translation_m.mean",
            "final_drift_m",
        ] {
            near(num(j, what), num(&from_tum, what), 1e-12, what);
        }
    }
    // Which topic, when there are two; a topic that is not a pose; a cut file; SQLite storage.
    let out = d.join("refused");
    // The refusal `score` gives for `bag` as the trajectory, with every other argument valid.
    let refused = |bag: &Path| {
        fails(&[
            "score",
            arg(&r),
            "--trajectory",
            arg(bag),
            "--out",
            arg(&out),
        ])
    };
    let e1 = refused(&both);
    assert!(
        e1.contains("2 pose topics") && e1.contains("--topic") && e1.contains("/slam/pose"),
        "{e1}"
    );
    let e2 = fails(&[
        "score",
        arg(&r),
        "--trajectory",
        arg(&both),
        "--topic",
        "/notes",
        "--out",
        arg(&out),
    ]);
    assert!(
        e2.contains("/notes is std_msgs/msg/String, not a pose"),
        "{e2}"
    );
    let mcap = std::fs::read_dir(&alone)
        .unwrap()
        .flatten()
        .map(|f| f.path())
        .find(|p| p.extension().is_some_and(|x| x == "mcap"))
        .unwrap();
    let bytes = std::fs::read(&mcap).unwrap();
    let cut = d.join("cut.mcap");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let e3 = refused(&cut);
    assert!(
        e3.contains("cut.mcap") && e3.contains("not a readable MCAP file"),
        "{e3}"
    );
    let sqlite = d.join("sqlite");
    std::fs::create_dir(&sqlite).unwrap();
    std::fs::write(
        sqlite.join("metadata.yaml"),
        "rosbag2_bagfile_information:\n  relative_file_paths:\n    - sqlite_0.db3\n",
    )
    .unwrap();
    std::fs::write(sqlite.join("sqlite_0.db3"), b"SQLite format 3\0").unwrap();
    let e4 = refused(&sqlite);
    assert!(
        e4.contains("SQLite storage") && e4.contains("ros2 bag convert"),
        "{e4}"
    );
    // A bag that is not there, and a folder that is no bag.
    let missing = d.join("missing.mcap");
    let e5 = refused(&missing);
    assert!(e5.contains("missing.mcap: no such file or folder"), "{e5}");
    let empty = d.join("empty");
    std::fs::create_dir(&empty).unwrap();
    let e6 = refused(&empty);
    assert!(e6.contains("a folder, but not a ROS 2 bag"), "{e6}");
    assert!(!out.exists(), "nothing written for refused input");
}

#[test]
fn interpolated_association_scores_every_estimate_pose_as_scipy_interpolates() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A reference on which interpolation is exact: constant velocity along a line, constant
    // turn rate about z, at 10 Hz; an estimate at 7 Hz on the same motion, plus a drift.
    let truth = |t: f64| -> Row { (t, [6.0 * t, 2.0 * t, 0.4 * t], yaw(0.3 * t)) };
    let rows: Vec<Row> = (0..300).map(|k| truth(k as f64 * 0.1)).collect();
    let on_it: Vec<Row> = (0..200).map(|k| truth(0.05 + k as f64 / 7.0)).collect();
    let drifted: Vec<Row> = on_it
        .iter()
        .enumerate()
        .map(|(k, &(t, p, q))| (t, [p[0], p[1] + 0.002 * k as f64, p[2]], q))
        .collect();
    let r = write_tum(&d.join("ref.tum"), &rows);
    let exact = write_tum(&d.join("exact.tum"), &on_it);
    let e = write_tum(&d.join("est.tum"), &drifted);
    let j = score(d, "exact", &r, &exact, &["--associate", "interpolate"]);
    assert_eq!(
        j["associated_poses"], 200,
        "every estimate pose in the span"
    );
    near(
        num(&j, "ape_m.max"),
        0.0,
        1e-9,
        "interpolation is exact here",
    );
    // Nearest association of the same poses pairs fewer, and each with an error.
    let n = score(d, "nearest", &r, &exact, &["--max-diff", "0.05"]);
    assert!(num(&n, "ape_m.mean") > 0.05, "{n}");
    for align in ["none", "se3"] {
        let j = score(
            d,
            &format!("drift-{align}"),
            &r,
            &e,
            &["--associate", "interpolate", "--align", align],
        );
        if align == "none" {
            near(num(&j, "final_drift_m"), 0.002 * 199.0, 1e-9, "drift");
        }
    }
    // A gap in the reference longer than --max-gap: the estimate poses inside it are left out.
    let gappy: Vec<Row> = rows
        .iter()
        .filter(|row| !(10.0..20.0).contains(&row.0))
        .copied()
        .collect();
    let g = write_tum(&d.join("gappy.tum"), &gappy);
    let j = score(
        d,
        "gap",
        &g,
        &e,
        &["--associate", "interpolate", "--max-gap", "0.5"],
    );
    let inside = on_it.iter().filter(|r| r.0 > 9.9 && r.0 < 20.0).count();
    assert_eq!(j["associated_poses"], (200 - inside) as u64);
}
