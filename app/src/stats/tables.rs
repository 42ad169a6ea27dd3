//! The report's tables: `stats.json`, `groups.csv`, `worlds.csv`, the pairwise IoU
//! matrices, and the summary printed on standard output.

use std::fmt::Write as _;
use std::path::Path;

use subtgraph_core::tile::TileKind;

use super::report::{PAPER_KINDS, Stats};
use super::{Group, Sample};
use crate::Error;
use crate::folder::write_file_atomically;

fn f(v: f64) -> String {
    format!("{v:.4}")
}

fn save(out: &Path, file: &str, text: &str) -> Result<(), Error> {
    write_file_atomically(&out.join(file), text.as_bytes())
        .map_err(Error::io(format!("writing {}", out.join(file).display())))
}

pub(super) fn write(stats: &Stats, groups: &[Group], out: &Path) -> Result<(), Error> {
    let mut json = serde_json::to_string_pretty(stats).expect("plain data serializes");
    json.push('\n');
    save(out, "stats.json", &json)?;

    let mut csv = String::from(
        "group,worlds,mirror_horizontal,mirror_vertical,mirror_rotational,pairwise_iou_mean,pairwise_iou_eq19_as_printed_mean",
    );
    for k in PAPER_KINDS {
        let _ = write!(csv, ",percent_{k}");
    }
    csv.push_str(",percent_shaft_ends,cells_mean,length_m_mean,cycles_mean\n");
    for g in stats.groups.iter().chain([&stats.all]) {
        let _ = write!(
            csv,
            "{},{},{},{},{},{},{}",
            g.name,
            g.worlds,
            f(g.mirror.horizontal),
            f(g.mirror.vertical),
            f(g.mirror.rotational),
            f(g.pairwise_iou.mean),
            f(g.pairwise_iou.eq19_as_printed_mean)
        );
        for k in PAPER_KINDS {
            let _ = write!(csv, ",{:.2}", g.tile_mix_percent[k]);
        }
        let _ = writeln!(
            csv,
            ",{:.2},{:.1},{:.1},{:.3}",
            g.tile_mix_percent["shaft-up"] + g.tile_mix_percent["shaft-landing"],
            g.cells.mean,
            g.length_m.mean,
            g.graph.cycles.mean
        );
    }
    save(out, "groups.csv", &csv)?;

    let samples: Vec<&Sample> = groups.iter().flat_map(|g| &g.samples).collect();
    let mut csv = String::from(
        "group,world,levels,rows,cols,cells,length_cells,length_m,cycles,mirror_horizontal,mirror_vertical,mirror_rotational",
    );
    for k in TileKind::ALL {
        let _ = write!(csv, ",tiles_{}", k.name());
    }
    csv.push('\n');
    for (s, m) in samples.iter().zip(&stats.world_mirror) {
        let first = s.levels.first();
        let _ = write!(
            csv,
            "{},{},{},{},{},{},{},{:.1},{}",
            s.group,
            s.name,
            s.levels.len(),
            first.map_or(0, |l| l.rows),
            first.map_or(0, |l| l.cols),
            s.cells,
            s.length_cells,
            s.length_m,
            s.cycles
        );
        match m {
            Some(m) => {
                let _ = write!(
                    csv,
                    ",{},{},{}",
                    f(m.horizontal),
                    f(m.vertical),
                    f(m.rotational)
                );
            }
            None => csv.push_str(",,,"),
        }
        for t in s.tiles {
            let _ = write!(csv, ",{t}");
        }
        csv.push('\n');
    }
    save(out, "worlds.csv", &csv)?;

    for (file, pick) in [
        ("pairwise-iou.csv", 0),
        ("pairwise-iou-eq19-as-printed.csv", 1),
    ] {
        let mut csv = String::from("world");
        for s in &samples {
            let _ = write!(csv, ",{}/{}", s.group, s.name);
        }
        csv.push('\n');
        for (s, row) in samples.iter().zip(&stats.matrix) {
            let _ = write!(csv, "{}/{}", s.group, s.name);
            for v in row {
                match v {
                    Some(v) => {
                        let _ = write!(csv, ",{}", f(if pick == 0 { v.0 } else { v.1 }));
                    }
                    None => csv.push(','),
                }
            }
            csv.push('\n');
        }
        save(out, file, &csv)?;
    }
    Ok(())
}

pub(super) fn summary(stats: &Stats, out: &Path) -> String {
    let w = stats
        .groups
        .iter()
        .map(|g| g.name.len())
        .max()
        .unwrap_or(0)
        .max(5);
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{:<w$} {:>6} {:>8} {:>8} {:>9} {:>9}  tile mix % (dead end / straight / corner / T / X)",
        "group", "worlds", "mirror H", "mirror V", "rotations", "mean IoU"
    );
    for g in stats.groups.iter().chain([&stats.all]) {
        let mix: Vec<String> = PAPER_KINDS
            .iter()
            .map(|k| format!("{:.1}", g.tile_mix_paper_percent[*k]))
            .collect();
        let _ = writeln!(
            t,
            "{:<w$} {:>6} {:>8.3} {:>8.3} {:>9.3} {:>9.3}  {}",
            g.name,
            g.worlds,
            g.mirror.horizontal,
            g.mirror.vertical,
            g.mirror.rotational,
            g.pairwise_iou.mean,
            mix.join(" / ")
        );
    }
    if !stats.merged_encodings.is_empty() {
        let files: usize = stats
            .merged_encodings
            .iter()
            .map(|m| 1 + m.left_out.len())
            .sum();
        let spatial = stats
            .merged_encodings
            .iter()
            .filter(|m| m.used.contains("spatial"))
            .count();
        let _ = writeln!(
            t,
            "note: {} world(s) were found in several encodings ({files} files of the original's spatial, topological, structural grids): each is counted once, {spatial} of them from the spatial encoding (the rest from the next that loads); stats.json lists them (merged_encodings)",
            stats.merged_encodings.len()
        );
    }
    let _ = write!(
        t,
        "wrote {}: stats.json, groups.csv, worlds.csv, pairwise-iou*.csv, plots (SVG and PNG)",
        out.display()
    );
    t
}
