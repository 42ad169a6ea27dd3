//! `subtgraph report` over score folders of many worlds and two methods: real trajectory
//! scores of a few worlds and synthetic score folders of 30, every number of `report.json`
//! recomputed by numpy and scipy from the score and world folders themselves
//! (`tests/readers/report_check.py`); twice the drift found by the paired test; the same bytes
//! again; mismatched runs refused naming the folder; `index.html` rendered by headless
//! Chromium.

use crate::common;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;

use common::{arg, fails, ok, read_with_python};
use serde_json::{Value, json};

/// `count` worlds of two presets (no mesh: the report reads only their topology and
/// `world.toml`), sorted by name.
fn worlds(dir: &Path, count: usize) -> Vec<PathBuf> {
    let out = dir.join("worlds");
    let per = (count / 2).to_string();
    ok(&[
        "dataset",
        "--preset",
        "cave",
        "--preset",
        "mine",
        "--count",
        &per,
        "--no-mesh",
        "--out",
        arg(&out),
    ]);
    let mut w: Vec<PathBuf> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.join("world.toml").is_file())
        .collect();
    w.sort();
    assert_eq!(w.len(), count);
    w
}

/// A score folder as `score --trajectory` writes it (its summary and the manifest that says
/// `complete score`), with the numbers given.
fn synthetic_score(folder: &Path, world: &Path, numbers: &Value, failed: bool) {
    std::fs::create_dir_all(folder).unwrap();
    let mut doc = json!({
        "format": "subtgraph-trajectory-score/1",
        "world_or_sequence": arg(world),
        "options": {"align": "none", "max_diff_s": 0.01},
        "failed": failed,
    });
    for (k, v) in numbers.as_object().unwrap() {
        doc[k] = v.clone();
    }
    let text = serde_json::to_string_pretty(&doc).unwrap() + "\n";
    std::fs::write(folder.join("trajectory.json"), &text).unwrap();
    std::fs::write(
        folder.join(".subtgraph-files"),
        format!("complete score\n{} trajectory.json\n", text.len()),
    )
    .unwrap();
}

/// A number from 0 to 1 for `k`, the same on every run (no random crate in the tests).
fn unit(k: u64) -> f64 {
    let mut z = k.wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ 0xD1B5_4A32_D192_ED03;
    z = (z ^ (z >> 29)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    (z >> 11) as f64 / (1u64 << 53) as f64
}

fn loops(world: &Path) -> f64 {
    let t: Value =
        serde_json::from_slice(&std::fs::read(world.join("topology.json")).unwrap()).unwrap();
    t["per_level"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["achieved"]["loops"].as_f64().unwrap())
        .sum()
}

/// Two methods over `worlds`: `lio` drifts 0.5 to 1.5 % plus 0.2 % per loop, `lio-2x` twice
/// that; APE in proportion; points (integers, so tied) fall with drift; `lio-2x` fails where
/// its drift passes 3 %.
fn two_methods(dir: &Path, worlds: &[PathBuf]) -> [PathBuf; 2] {
    let [a, b] = [dir.join("runs/lio"), dir.join("runs/lio-2x")];
    for (i, w) in worlds.iter().enumerate() {
        let drift = 0.5 + unit(i as u64) + 0.2 * loops(w);
        for (folder, k) in [(&a, 1.0), (&b, 2.0)] {
            let d = k * drift;
            let numbers = json!({
                "final_drift_percent": d,
                "ape_m": {"rmse": 0.9 * d + 0.05 * unit(100 + i as u64), "count": 500},
                "points_mean": (10.0 - 2.0 * d).max(0.0).floor(),
            });
            let name = w.file_name().unwrap();
            synthetic_score(&folder.join(name), w, &numbers, d > 3.0);
        }
    }
    [a, b]
}

fn report(out: &Path) -> Value {
    serde_json::from_slice(&std::fs::read(out.join("report.json")).unwrap()).unwrap()
}

fn paired<'a>(r: &'a Value, metric: &str) -> &'a Value {
    r["paired"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["metric"] == metric)
        .unwrap_or_else(|| panic!("no paired row for {metric}"))
}

/// Every `src` and `href` of `index.html` that is not a web address names a file or folder
/// that exists, relative to the report folder.
fn assert_links_resolve(out: &Path) {
    let html = std::fs::read_to_string(out.join("index.html")).unwrap();
    assert!(!html.contains("<script"), "no scripts");
    for attr in ["src=\"", "href=\""] {
        for piece in html.split(attr).skip(1) {
            let target = &piece[..piece.find('"').unwrap()];
            assert!(
                !target.contains("://"),
                "nothing from the network: {target}"
            );
            assert!(
                out.join(target).exists(),
                "index.html links to {target}, which is missing"
            );
        }
    }
}

#[test]
fn real_trajectory_scores_are_summarised_as_numpy_and_scipy_compute_them() {
    let dir = tempfile::tempdir().unwrap();
    let worlds = worlds(dir.path(), 4);
    // A straight, gently winding reference; each method's estimate drifts in x and z, the
    // second method twice as fast, more on each later world.
    for (i, w) in worlds.iter().enumerate() {
        let (mut reference, mut estimates) = (String::new(), [String::new(), String::new()]);
        for k in 0..200 {
            let t = k as f64 * 0.1;
            let (x, y) = (20.0 + 2.5 * t, 30.0 + 5.0 * (0.1 * t).sin());
            let _ = writeln!(reference, "{t} {x} {y} 1 0 0 0 1");
            for (m, e) in estimates.iter_mut().enumerate() {
                let d = 0.01 * (m + 1) as f64 * (i + 1) as f64 * t;
                let _ = writeln!(e, "{t} {} {y} {} 0 0 0 1", x + d, 1.0 + 0.3 * d);
            }
        }
        let r = dir.path().join(format!("ref{i}.tum"));
        std::fs::write(&r, reference).unwrap();
        for (m, e) in estimates.iter().enumerate() {
            let est = dir.path().join(format!("est{i}-{m}.tum"));
            std::fs::write(&est, e).unwrap();
            let out = dir.path().join(format!("runs/m{m}/{i}"));
            ok(&[
                "score",
                arg(w),
                "--trajectory",
                arg(&est),
                "--reference",
                arg(&r),
                "--out",
                arg(&out),
            ]);
        }
    }
    let out = dir.path().join("report");
    let printed = ok(&[
        "report",
        &format!("slow={}", arg(&dir.path().join("runs/m1"))),
        &format!("fast={}", arg(&dir.path().join("runs/m0"))),
        "--out",
        arg(&out),
    ]);
    assert!(
        printed.contains("2 method(s), 4 world(s), 8 run(s)"),
        "{printed}"
    );
    let r = report(&out);
    // The report's numbers of each run are the score folder's own.
    for run in r["runs"].as_array().unwrap() {
        let folder = PathBuf::from(run["score_folders"][0].as_str().unwrap());
        let t: Value =
            serde_json::from_slice(&std::fs::read(folder.join("trajectory.json")).unwrap())
                .unwrap();
        assert_eq!(run["metrics"]["trajectory.ape_m.rmse"], t["ape_m"]["rmse"]);
        assert_eq!(
            run["metrics"]["trajectory.final_drift_percent"],
            t["final_drift_percent"]
        );
        assert_eq!(run["failed"], t["failed"]);
    }
    // Four worlds, every difference the same sign: the exact test's smallest p, 2 / 2^4.
    let rmse = paired(&r, "trajectory.ape_m.rmse");
    assert_eq!(
        (rmse["a"].as_str(), rmse["b"].as_str()),
        (Some("fast"), Some("slow"))
    );
    assert_eq!(rmse["a_lower"], 1.0);
    assert_eq!(rmse["wilcoxon"]["method"], "exact");
    assert_eq!(rmse["wilcoxon"]["p"], 0.125);
    assert!(r["constant"]["trajectory.ape_m.count"] == 200.0);
    assert_links_resolve(&out);
    read_with_python(&["numpy", "scipy"], "report_check.py", &[arg(&out)]);
    // The same bytes again, on three threads.
    let again = dir.path().join("again");
    let status = Command::new(env!("CARGO_BIN_EXE_subtgraph"))
        .args([
            "report",
            &format!("slow={}", arg(&dir.path().join("runs/m1"))),
        ])
        .args([&format!("fast={}", arg(&dir.path().join("runs/m0")))])
        .args(["--out", arg(&again)])
        .env("RAYON_NUM_THREADS", "3")
        .output()
        .unwrap();
    assert!(status.status.success(), "{status:?}");
    common::assert_same_files(&out, &again, &[]);
}

#[test]
fn thirty_worlds_the_paired_test_finds_twice_the_drift() {
    let dir = tempfile::tempdir().unwrap();
    let worlds = worlds(dir.path(), 30);
    let [a, b] = two_methods(dir.path(), &worlds);
    let out = dir.path().join("report");
    let printed = ok(&[
        "report",
        &format!("lio={}", arg(&a)),
        &format!("lio-2x={}", arg(&b)),
        "--out",
        arg(&out),
    ]);
    assert!(
        printed.contains("2 method(s), 30 world(s), 60 run(s)"),
        "{printed}"
    );
    let r = report(&out);
    let drift = paired(&r, "trajectory.final_drift_percent");
    let p = drift["wilcoxon"]["p"].as_f64().unwrap();
    assert!(p < 0.01, "the paired test finds twice the drift: p = {p}");
    assert_eq!(
        drift["wilcoxon"]["method"], "exact",
        "30 differences, no ties"
    );
    assert_eq!(drift["a_lower"], 1.0, "lio drifts less on every world");
    // Tied integer points: the normal approximation with the tie correction.
    assert_eq!(
        paired(&r, "trajectory.points_mean")["wilcoxon"]["method"],
        "normal"
    );
    // Drift was made to grow with loops: the fitted line says so.
    let trend = r["trends"]
        .as_array()
        .unwrap()
        .iter()
        .find(|t| {
            t["method"] == "lio"
                && t["metric"] == "trajectory.final_drift_percent"
                && t["parameter"] == "loops"
        })
        .unwrap();
    assert!(trend["line"]["slope"].as_f64().unwrap() > 0.1, "{trend}");
    // lio never fails, lio-2x where its drift passes 3 %; per preset too.
    let success: Vec<&Value> = r["success"].as_array().unwrap().iter().collect();
    assert!(
        success
            .iter()
            .any(|s| s["method"] == "lio" && s["scope"] == "all" && s["rate"] == 1.0)
    );
    assert!(success.iter().any(|s| s["scope"] == "preset mine"));
    assert!(
        success
            .iter()
            .any(|s| s["method"] == "lio-2x" && s["failures"].as_u64() > Some(0))
    );
    assert!(out.join("plots/failure-rate.png").is_file());
    assert!(
        out.join("plots/trajectory-final_drift_percent.png")
            .is_file()
    );
    assert_links_resolve(&out);
    read_with_python(&["numpy", "scipy"], "report_check.py", &[arg(&out)]);
}

#[test]
fn a_runs_csv_names_the_same_runs_lists_unpaired_worlds_and_merges_kinds() {
    let dir = tempfile::tempdir().unwrap();
    let worlds = worlds(dir.path(), 6);
    let [a, b] = two_methods(dir.path(), &worlds);
    // One world scored by lio only.
    std::fs::remove_dir_all(b.join(worlds[0].file_name().unwrap())).unwrap();
    let mut csv = String::from("world,method,score_folder\n");
    for w in &worlds {
        let name = w.file_name().unwrap().to_str().unwrap();
        let _ = writeln!(csv, "worlds/{name},lio,runs/lio/{name}");
        if w != &worlds[0] {
            let _ = writeln!(csv, ",lio-2x,runs/lio-2x/{name}");
        }
    }
    std::fs::write(dir.path().join("runs.csv"), csv).unwrap();
    let from_csv = dir.path().join("from-csv");
    ok(&[
        "report",
        "--runs",
        arg(&dir.path().join("runs.csv")),
        "--out",
        arg(&from_csv),
    ]);
    let from_args = dir.path().join("from-args");
    ok(&[
        "report",
        &format!("lio={}", arg(&a)),
        &format!("lio-2x={}", arg(&b)),
        "--out",
        arg(&from_args),
    ]);
    let (x, y) = (report(&from_csv), report(&from_args));
    assert_eq!(x["summary"], y["summary"]);
    assert_eq!(x["paired"], y["paired"]);
    let unpaired = &x["unpaired"];
    assert_eq!(unpaired.as_array().unwrap().len(), 1, "{unpaired}");
    assert_eq!(unpaired[0]["missing_from"], "lio-2x");
    assert_eq!(paired(&x, "trajectory.final_drift_percent")["n"], 5);
    read_with_python(&["numpy", "scipy"], "report_check.py", &[arg(&from_csv)]);
    // An artifact score of the same runs (score.json, as `score --reports` writes it) adds
    // its numbers to lio's trajectory scores: two kinds, one run per world.
    let mut csv = std::fs::read_to_string(dir.path().join("runs.csv")).unwrap();
    for (i, w) in worlds.iter().enumerate() {
        let name = w.file_name().unwrap().to_str().unwrap();
        let folder = dir.path().join("runs/lio-artifacts").join(name);
        std::fs::create_dir_all(&folder).unwrap();
        let doc = json!({
            "format": "subtgraph-score/1",
            "world": arg(w),
            "score": i % 4,
            "artifacts_total": 5,
            "outcomes": {"scored": i % 4, "duplicate": 0, "wrong_class": i % 2, "false_reports": 1},
            "mean_error_m": 0.5 + 0.1 * i as f64,
            "artifacts": [{"id": 0, "found": true}],
            "map": null,
        });
        let text = serde_json::to_string_pretty(&doc).unwrap() + "\n";
        std::fs::write(folder.join("score.json"), &text).unwrap();
        std::fs::write(
            folder.join(".subtgraph-files"),
            format!("complete score\n{} score.json\n", text.len()),
        )
        .unwrap();
        let _ = writeln!(csv, ",lio,runs/lio-artifacts/{name}");
    }
    std::fs::write(dir.path().join("runs.csv"), csv).unwrap();
    let mixed = dir.path().join("mixed");
    let printed = ok(&[
        "report",
        "--runs",
        arg(&dir.path().join("runs.csv")),
        "--out",
        arg(&mixed),
    ]);
    assert!(printed.contains("6 world(s), 11 run(s)"), "{printed}");
    let m = report(&mixed);
    let lio = m["runs"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["method"] == "lio")
        .unwrap();
    assert_eq!(lio["score_folders"].as_array().unwrap().len(), 2);
    for k in [
        "score.score",
        "score.mean_error_m",
        "trajectory.final_drift_percent",
    ] {
        assert!(lio["metrics"].get(k).is_some(), "{k} in {lio}");
    }
    assert_eq!(m["constant"]["score.artifacts_total"], 5.0);
    read_with_python(&["numpy", "scipy"], "report_check.py", &[arg(&mixed)]);
}

#[test]
fn mismatched_runs_are_refused_naming_the_folder_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let worlds = worlds(dir.path(), 2);
    let [a, b] = two_methods(dir.path(), &worlds);
    let out = dir.path().join("report");
    let lio = format!("lio={}", arg(&a));
    // The same world twice for one method.
    let twice = a.join("twice");
    synthetic_score(
        &twice,
        &worlds[0],
        &json!({"final_drift_percent": 1.0}),
        false,
    );
    let err = fails(&["report", &lio, "--out", arg(&out)]);
    assert!(
        err.contains("twice") && err.contains("keep one score folder"),
        "{err}"
    );
    std::fs::remove_dir_all(&twice).unwrap();
    // A folder that is not a score: a world folder.
    let err = fails(&[
        "report",
        &format!("w={}", arg(&worlds[0])),
        "--out",
        arg(&out),
    ]);
    assert!(
        err.contains("is not a score folder") || err.contains("neither a score folder"),
        "{err}"
    );
    // A folder of score folders holding something else.
    std::fs::create_dir_all(b.join("notes")).unwrap();
    let err = fails(&["report", &format!("x={}", arg(&b)), "--out", arg(&out)]);
    assert!(
        err.contains("notes") && err.contains("is not a score folder"),
        "{err}"
    );
    // A CSV row with two columns, named by its line.
    let csv = dir.path().join("runs.csv");
    std::fs::write(
        &csv,
        "world,method,score_folder\n,lio,runs/lio/x\nlio,runs/lio/y\n",
    )
    .unwrap();
    let err = fails(&["report", "--runs", arg(&csv), "--out", arg(&out)]);
    assert!(err.contains("line 2") || err.contains("line 3"), "{err}");
    // A trajectory scored against a bare reference file records no world: refused as an
    // argument, saying how to give it; placed by a CSV that names its world.
    let bare = dir.path().join("bare/run");
    let reference = dir.path().join("ref.tum");
    std::fs::write(&reference, "0 0 0 0 0 0 0 1\n").unwrap();
    synthetic_score(
        &bare,
        &reference,
        &json!({"final_drift_percent": 1.0}),
        false,
    );
    let err = fails(&["report", &format!("m={}", arg(&bare)), "--out", arg(&out)]);
    assert!(
        err.contains("ref.tum") && err.contains("--runs CSV"),
        "{err}"
    );
    std::fs::write(
        &csv,
        format!(
            "world,method,score_folder\n{},m,bare/run\n",
            arg(&worlds[0])
        ),
    )
    .unwrap();
    let placed = dir.path().join("placed");
    ok(&["report", "--runs", arg(&csv), "--out", arg(&placed)]);
    assert_eq!(report(&placed)["worlds"][0]["path"], arg(&worlds[0]));
    // Not METHOD=FOLDER.
    let err = fails(&["report", arg(&a), "--out", arg(&out)]);
    assert!(err.contains("METHOD=FOLDER"), "{err}");
    assert!(!out.exists(), "nothing written");
    // --force replaces a report, never a world.
    ok(&["report", &lio, "--out", arg(&out)]);
    ok(&["report", &lio, "--out", arg(&out), "--force"]);
    let err = fails(&["report", &lio, "--out", arg(&worlds[1]), "--force"]);
    assert!(
        err.contains("world folder") && err.contains("report"),
        "{err}"
    );
    assert!(worlds[1].join("world.toml").is_file());
}

/// Headless Chromium (Debian's `chromium`), or `None` with a message.
fn chromium() -> Option<&'static str> {
    ["chromium", "chromium-browser", "google-chrome"]
        .into_iter()
        .find(|c| {
            Command::new(c)
                .arg("--version")
                .output()
                .is_ok_and(|o| o.status.success())
        })
        .or_else(|| {
            eprintln!("skipping: no chromium here (scripts/test installs Debian's `chromium`)");
            None
        })
}

#[test]
fn index_html_renders_offline_in_headless_chromium() {
    let Some(browser) = chromium() else { return };
    let dir = tempfile::tempdir().unwrap();
    let worlds = worlds(dir.path(), 10);
    let [a, b] = two_methods(dir.path(), &worlds);
    let out = dir.path().join("report");
    ok(&[
        "report",
        &format!("lio={}", arg(&a)),
        &format!("lio-2x={}", arg(&b)),
        "--out",
        arg(&out),
    ]);
    let shot = dir.path().join("shot.png");
    let url = format!(
        "file://{}",
        arg(&out.join("index.html").canonicalize().unwrap())
    );
    let run = Command::new(browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--enable-logging=stderr",
            "--v=0",
        ])
        .arg(format!("--screenshot={}", arg(&shot)))
        .args(["--window-size=1280,900", &url])
        .env("HOME", dir.path())
        .output()
        .unwrap();
    let log = String::from_utf8_lossy(&run.stderr);
    assert!(
        run.status.success() && shot.is_file(),
        "chromium failed:\n{log}"
    );
    for bad in ["CONSOLE", "ERR_FILE_NOT_FOUND", "Uncaught", "net::ERR"] {
        assert!(
            !log.lines().any(|l| l.contains(bad)),
            "console error rendering index.html: {}",
            log.lines().find(|l| l.contains(bad)).unwrap()
        );
    }
    // The first plot (the failure rates) sits below the success table: its bars, in the
    // plots' first two colours, fill part of the lower half of the screenshot.
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&shot).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = info.line_size / info.width as usize;
    let near = |p: &[u8], c: [u8; 3]| p.iter().zip(c).all(|(a, b)| a.abs_diff(b) < 12);
    let mut coloured = 0;
    for y in info.height as usize / 2..info.height as usize {
        for x in 0..info.width as usize {
            let p = &buf[y * info.line_size + x * channels..][..3];
            coloured += usize::from(near(p, [31, 119, 180]) || near(p, [255, 127, 14]));
        }
    }
    assert!(
        coloured > 500,
        "the first plot is not on the screenshot ({coloured} pixels of its colours)"
    );
}

/// A score of a real sensor sequence is placed on the world the sequence was made from (the
/// sequence's `sequence.json` records it as `{"folder": ...}`): before, `report` refused it as
/// "not a world folder nor a sensor sequence of one".
#[test]
fn a_score_of_a_sensor_sequence_is_placed_on_its_world() {
    let dir = tempfile::tempdir().unwrap();
    let pipeline = common::small_cave_pipeline(dir.path(), 1, "");
    let world = dir.path().join("world");
    ok(&[
        "generate",
        arg(&pipeline),
        "--format",
        "ground-truth",
        "--out",
        arg(&world),
    ]);
    let seq = dir.path().join("seq");
    ok(&["sense", arg(&world), "--duration", "2", "--out", arg(&seq)]);
    let runs = dir.path().join("runs/exact");
    let score = runs.join("small-cave");
    ok(&[
        "score",
        arg(&seq),
        "--trajectory",
        arg(&seq.join("ground_truth.tum")),
        "--out",
        arg(&score),
    ]);
    let out = dir.path().join("report");
    let method = format!("exact={}", runs.display());
    ok(&["report", &method, "--out", arg(&out)]);
    let r = report(&out);
    assert_eq!(r["worlds"].as_array().unwrap().len(), 1, "{}", r["worlds"]);
    assert_eq!(r["worlds"][0]["name"], "world", "{}", r["worlds"]);
    assert_eq!(r["runs"][0]["world"], 0, "{}", r["runs"]);
    assert_eq!(r["runs"][0]["method"], "exact");
}
