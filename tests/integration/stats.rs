//! `subtgraph stats` on grids of known content: IoU, mirror asymmetry and tile counts
//! computed by hand, foreign files skipped with a warning, empty input refused, and every
//! output read back (JSON, CSV, SVG as XML, PNG with the `png` crate and Pillow).

use crate::common;

use std::path::Path;

use common::{arg, fails, ok, subtgraph};
use subtgraph::core::npy;

/// An 8 x 8 grid (0/1, the original's structural encoding) from rows of `#` and `.`.
fn grid(dir: &Path, file: &str, rows: &[&str]) {
    assert_eq!(rows.len(), 8);
    let data: Vec<u8> = rows
        .iter()
        .flat_map(|r| r.bytes().map(|b| u8::from(b == b'#')))
        .collect();
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join(file), npy::encode_u8(&[8, 8], &data)).unwrap();
}

/// A bar along row `row`, columns 1 to 6: symmetric left-right.
fn bar(row: usize) -> Vec<String> {
    (0..8)
        .map(|r| if r == row { ".######." } else { "........" }.to_owned())
        .collect()
}

/// An L: column 1 and row 6, rows and columns 1 to 6 (11 cells).
const L: [&str; 8] = [
    "........", ".#......", ".#......", ".#......", ".#......", ".#......", ".######.", "........",
];

fn rows(v: &[String]) -> Vec<&str> {
    v.iter().map(String::as_str).collect()
}

fn group<'a>(stats: &'a serde_json::Value, name: &str) -> &'a serde_json::Value {
    stats["groups"]
        .as_array()
        .unwrap()
        .iter()
        .find(|g| g["name"] == name)
        .unwrap_or_else(|| panic!("no group {name}"))
}

fn close(v: &serde_json::Value, expected: f64) -> bool {
    (v.as_f64().unwrap() - expected).abs() < 1e-9
}

#[test]
fn known_grids_give_the_values_computed_by_hand() {
    let tmp = tempfile::tempdir().unwrap();
    let same = tmp.path().join("same");
    grid(&same, "a.npy", &rows(&bar(3)));
    grid(&same, "b.npy", &rows(&bar(3)));
    let apart = tmp.path().join("apart");
    grid(&apart, "a.npy", &rows(&bar(3)));
    grid(&apart, "b.npy", &rows(&bar(5)));
    let ell = tmp.path().join("ell");
    grid(&ell, "l.npy", &L);
    // Foreign and broken files are skipped, naming them.
    std::fs::write(ell.join("notes.txt"), b"not a grid").unwrap();
    std::fs::write(ell.join("broken.npy"), b"\x93NUMPY garbage").unwrap();
    // The original's topological encoding (10 node, 1 edge), a folder per world.
    let original = tmp.path().join("original");
    let mut codes = vec![0u8; 64];
    codes[3 * 8 + 1..3 * 8 + 7].copy_from_slice(&[10, 1, 1, 1, 1, 10]);
    std::fs::create_dir_all(original.join("world_1")).unwrap();
    std::fs::write(
        original.join("world_1/topological.npy"),
        npy::encode_u8(&[8, 8], &codes),
    )
    .unwrap();
    let report = tmp.path().join("report");
    let out = subtgraph(&[
        "stats",
        arg(&same),
        arg(&apart),
        arg(&ell),
        arg(&original),
        "--out",
        arg(&report),
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("skipping") && stderr.contains("notes.txt"),
        "{stderr}"
    );
    assert!(stderr.contains("broken.npy"), "{stderr}");

    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(report.join("stats.json")).unwrap()).unwrap();
    let s = group(&stats, "same");
    assert_eq!(s["worlds"], 2);
    assert!(close(&s["pairwise_iou"]["mean"], 1.0));
    // Eq. 19 as printed divides by the sum: identical worlds score one half.
    assert!(close(&s["pairwise_iou"]["eq19_as_printed_mean"], 0.5));
    // The bar is its own left-right mirror; upside down it lands on row 4: no overlap.
    assert!(close(&s["mirror"]["horizontal"], 1.0));
    assert!(close(&s["mirror"]["vertical"], 0.0));
    // Turned 90 or 270 degrees it is a column sharing one cell of 11; at 180, row 4.
    assert!(close(
        &s["mirror"]["rotational"],
        (1.0 / 11.0 + 0.0 + 1.0 / 11.0) / 3.0
    ));
    // Two dead ends and four straights per bar.
    assert!(close(&s["tile_mix_percent"]["dead-end"], 100.0 / 3.0));
    assert!(close(&s["tile_mix_percent"]["straight"], 200.0 / 3.0));
    assert!(close(&s["cells"]["mean"], 6.0));

    assert!(close(&group(&stats, "apart")["pairwise_iou"]["mean"], 0.0));
    let l = group(&stats, "ell");
    assert_eq!(l["worlds"], 1, "only l.npy is a world");
    // Mirrored either way the L keeps one arm (6 cells) of 16 covered.
    assert!(close(&l["mirror"]["horizontal"], 6.0 / 16.0));
    assert!(close(&l["mirror"]["vertical"], 6.0 / 16.0));
    assert!(close(&l["tile_mix_percent"]["corner"], 100.0 / 11.0));
    let o = group(&stats, "original");
    assert_eq!(o["worlds"], 1);
    assert!(close(&o["mirror"]["horizontal"], 1.0));
    assert!(close(&o["tile_mix_percent"]["straight"], 200.0 / 3.0));
    assert_eq!(stats["all"]["worlds"], 6);

    // CSVs: rectangular, with the same numbers.
    let groups = std::fs::read_to_string(report.join("groups.csv")).unwrap();
    let lines: Vec<&str> = groups.lines().collect();
    assert_eq!(lines.len(), 6, "header, four groups, all");
    let width = lines[0].split(',').count();
    assert!(lines.iter().all(|l| l.split(',').count() == width));
    assert!(
        lines[1].starts_with("same,2,1.0000,0.0000,"),
        "{}",
        lines[1]
    );
    let matrix = std::fs::read_to_string(report.join("pairwise-iou.csv")).unwrap();
    assert_eq!(matrix.lines().count(), 7);
    assert!(
        matrix
            .lines()
            .nth(1)
            .unwrap()
            .starts_with("same/a,1.0000,1.0000,")
    );
    let worlds = std::fs::read_to_string(report.join("worlds.csv")).unwrap();
    assert_eq!(worlds.lines().count(), 7);
    assert!(worlds.contains("original,world_1,1,8,8,6,5,"), "{worlds}");

    // Plots: PNGs decode and are not blank; SVGs are XML (checked by Python below).
    for name in [
        "mirror-asymmetry",
        "tile-mix",
        "iou-heatmap-all",
        "iou-heatmap-same",
        "size-cells",
    ] {
        let bytes = std::fs::read(report.join(format!("{name}.png"))).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        let mut reader = png::Decoder::new(std::io::Cursor::new(bytes))
            .read_info()
            .unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert!(info.width >= 800 && info.height >= 500);
        assert!(buf.iter().any(|&b| b < 100), "{name}.png has dark ink");
        let svg = std::fs::read_to_string(report.join(format!("{name}.svg"))).unwrap();
        assert!(svg.starts_with("<svg ") && svg.trim_end().ends_with("</svg>"));
    }
    if let Some(n) = common::read_with_python(&["PIL"], "stats_report.py", &[arg(&report)]) {
        assert!(n.trim().parse::<usize>().unwrap() >= 10, "{n}");
    }
}

#[test]
fn datasets_and_world_folders_report_constraints_and_graphs() {
    let tmp = tempfile::tempdir().unwrap();
    let data = tmp.path().join("data");
    ok(&[
        "dataset",
        "--preset",
        "cave",
        "--preset",
        "mine",
        "--count",
        "3",
        "--seed",
        "4",
        "--no-mesh",
        "--out",
        arg(&data),
    ]);
    let report = tmp.path().join("report");
    // A dataset folder, and one of its worlds on its own.
    let text = ok(&[
        "stats",
        arg(&data),
        arg(&data.join("cave-0001")),
        "--out",
        arg(&report),
        "--crop",
        "pad",
    ]);
    // A dataset of two sources is a group per source.
    assert!(
        text.contains("data:cave") && text.contains("data:mine"),
        "{text}"
    );
    assert!(text.contains("cave-0001"), "{text}");
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(report.join("stats.json")).unwrap()).unwrap();
    assert_eq!(stats["crop"], "pad");
    assert_eq!(group(&stats, "data:mine")["levels"]["mean"], 3.0);
    let g = group(&stats, "data:cave");
    assert_eq!(g["worlds"], 3);
    let index: serde_json::Value =
        serde_json::from_slice(&std::fs::read(data.join("index.json")).unwrap()).unwrap();
    let sum = |key: &str, shape: &str| -> u64 {
        index
            .as_array()
            .unwrap()
            .iter()
            .filter(|r| r["source"] == "cave")
            .map(|r| r[key][shape].as_u64().unwrap())
            .sum()
    };
    for shape in ["t-junction", "intersection", "loop"] {
        let c = &g["constraints"][shape];
        assert_eq!(c["requested"].as_u64().unwrap(), sum("requested", shape));
        assert_eq!(c["achieved"].as_u64().unwrap(), sum("achieved", shape));
        assert_eq!(c["levels"], 3);
    }
    let degrees: f64 = g["graph"]["degree_percent"]
        .as_object()
        .unwrap()
        .values()
        .map(|v| v.as_f64().unwrap())
        .sum();
    assert!((degrees - 100.0).abs() < 1e-9);
    let cells: f64 = index
        .as_array()
        .unwrap()
        .iter()
        .filter(|r| r["source"] == "cave")
        .map(|r| r["occupied_cells"].as_f64().unwrap())
        .sum::<f64>()
        / 3.0;
    assert!(close(&g["cells"]["mean"], cells));
    assert!(report.join("constraints.svg").is_file());
    // The same inputs give the same report, byte for byte.
    let again = tmp.path().join("again");
    ok(&[
        "stats",
        arg(&data),
        arg(&data.join("cave-0001")),
        "--out",
        arg(&again),
        "--crop",
        "pad",
    ]);
    assert!(common::folder_bytes(&report) == common::folder_bytes(&again));
    assert!(report.join("constraints.png").is_file());
}

#[test]
fn nothing_usable_is_an_error() {
    let tmp = tempfile::tempdir().unwrap();
    let empty = tmp.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    std::fs::write(empty.join("readme.md"), b"# hi").unwrap();
    let report = tmp.path().join("report");
    let e = fails(&["stats", arg(&empty), "--out", arg(&report)]);
    assert!(e.contains("no worlds found"), "{e}");
    assert!(e.contains("readme.md"), "the skipped file is named: {e}");
    assert!(!report.exists(), "no report without worlds");
    let e = fails(&[
        "stats",
        arg(&tmp.path().join("missing")),
        "--out",
        arg(&report),
    ]);
    assert!(e.contains("does not exist"), "{e}");
    let e = fails(&[
        "stats",
        arg(&empty),
        "--out",
        arg(&report),
        "--crop",
        "middle",
    ]);
    assert!(e.contains("--crop common"), "{e}");
}

/// A bar along row `row` from column `from` to column 6 in one of the original's encodings:
/// spatial (1 dead end, 2 straight), topological (10 node, 1 edge) or structural (0/1).
fn bar_in(dir: &Path, file: &str, row: usize, from: usize, encoding: &str) {
    let mut codes = vec![0u8; 64];
    for c in from..=6 {
        let end = c == from || c == 6;
        codes[row * 8 + c] = match (encoding, end) {
            ("spatial", true) => 1,
            ("spatial", false) => 2,
            ("topological", true) => 10,
            _ => 1,
        };
    }
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join(file), npy::encode_u8(&[8, 8], &codes)).unwrap();
}

#[test]
fn a_world_saved_in_three_encodings_is_one_world() {
    const ENCODINGS: [&str; 3] = ["spatial", "topological", "structural"];
    let tmp = tempfile::tempdir().unwrap();
    // Flat: world_1 (a bar of 6 cells) and world_2 (5 of those cells), each in three files.
    let flat = tmp.path().join("flat");
    for e in ENCODINGS {
        bar_in(&flat, &format!("world_1_{e}.npy"), 3, 1, e);
        bar_in(&flat, &format!("world_2_{e}.npy"), 3, 2, e);
    }
    // The original's own layout: a folder per world, `pkl/subtgraph.ENCODING` (as .npy).
    let nested = tmp.path().join("nested");
    for e in ENCODINGS {
        bar_in(
            &nested.join("2024-01-01-a/pkl"),
            &format!("subtgraph.{e}.npy"),
            3,
            1,
            e,
        );
        bar_in(&nested.join("2024-01-01-b"), &format!("{e}.npy"), 3, 2, e);
    }
    let report = tmp.path().join("report");
    let out = subtgraph(&["stats", arg(&flat), arg(&nested), "--out", arg(&report)]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stderr}");
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(report.join("stats.json")).unwrap()).unwrap();
    for name in ["flat", "nested"] {
        let g = group(&stats, name);
        assert_eq!(g["worlds"], 2, "{name}: two worlds, not six files");
        // One pair: 5 shared cells of 6; copies of one world would add pairs of IoU 1.
        assert_eq!(g["pairwise_iou"]["pairs"], 1, "{name}");
        assert!(close(&g["pairwise_iou"]["mean"], 5.0 / 6.0), "{name}: {g}");
    }
    // The report says which file each world was measured from: the spatial encoding.
    let merged = stats["merged_encodings"].as_array().unwrap();
    assert_eq!(merged.len(), 4, "{merged:?}");
    for m in merged {
        assert!(m["used"].as_str().unwrap().contains("spatial"), "{m}");
        assert_eq!(m["left_out"].as_array().unwrap().len(), 2, "{m}");
    }
    let worlds = std::fs::read_to_string(report.join("worlds.csv")).unwrap();
    for w in [
        "flat,world_1,",
        "flat,world_2,",
        "nested,2024-01-01-a,",
        "nested,2024-01-01-b,",
    ] {
        assert!(worlds.contains(w), "{w}: {worlds}");
    }
    assert!(
        stdout.contains("4 world(s) were found in several encodings") && stdout.contains("spatial"),
        "the summary says so: {stdout}"
    );

    // A broken spatial file falls back to the next encoding, with a warning naming it.
    std::fs::write(flat.join("world_1_spatial.npy"), b"\x93NUMPY garbage").unwrap();
    let out = subtgraph(&["stats", arg(&flat), "--out", arg(&report)]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(stderr.contains("world_1_spatial.npy"), "{stderr}");
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(report.join("stats.json")).unwrap()).unwrap();
    assert_eq!(group(&stats, "flat")["worlds"], 2);
    let used: Vec<&str> = stats["merged_encodings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["used"].as_str().unwrap())
        .collect();
    assert!(used.contains(&"world_1_topological.npy"), "{used:?}");
}
