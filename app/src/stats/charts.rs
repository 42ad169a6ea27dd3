//! The plots of a report, each written as SVG and PNG: IoU heatmaps (all worlds and per
//! group), mirror asymmetry, tile mix, sizes, corridor lengths, cycles, node degrees and
//! constraint satisfaction.

use std::path::Path;

use super::Group;
use super::report::{GroupStats, PAPER_KINDS, Stats, Summary};
use crate::Error;
use crate::folder::write_file_atomically;
use subtgraph_plot::{Figure, PALETTE, Rgb, bars, boxes, heatmap};

fn save(out: &Path, stem: &str, figure: &Figure) -> Result<(), Error> {
    write_file_atomically(&out.join(format!("{stem}.svg")), figure.to_svg().as_bytes())
        .map_err(Error::io(format!("writing {stem}.svg")))?;
    let png = subtgraph_plot::to_png(figure, 2.0);
    write_file_atomically(&out.join(format!("{stem}.png")), &png)
        .map_err(Error::io(format!("writing {stem}.png")))
}

/// A file-name-safe form of a group name.
fn slug(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '-'
            }
        })
        .collect()
}

/// Writes every plot of the report.
pub fn write_all(stats: &Stats, groups: &[Group], out: &Path) -> Result<(), Error> {
    let gs: &[GroupStats] = &stats.groups;
    let color = |i: usize| PALETTE[i % PALETTE.len()];

    // Heatmaps: every world, then each group's.
    let mut blocks = Vec::new();
    let mut start = 0;
    for g in groups {
        blocks.push((g.name.clone(), start, g.samples.len()));
        start += g.samples.len();
    }
    let true_iou = |rows: std::ops::Range<usize>| -> Vec<Vec<Option<f64>>> {
        stats.matrix[rows.clone()]
            .iter()
            .map(|r| r[rows.clone()].iter().map(|v| v.map(|v| v.0)).collect())
            .collect()
    };
    save(
        out,
        "iou-heatmap-all",
        &heatmap(
            "Pairwise IoU of level 0, all worlds",
            "world (by group)",
            &true_iou(0..start),
            &blocks,
        ),
    )?;
    for (name, s, len) in &blocks {
        save(
            out,
            &format!("iou-heatmap-{}", slug(name)),
            &heatmap(
                &format!("Pairwise IoU of level 0, {name}"),
                "world (by name)",
                &true_iou(*s..s + len),
                &[(name.clone(), 0, *len)],
            ),
        )?;
    }

    let series = |f: &dyn Fn(&GroupStats) -> Vec<f64>| -> Vec<(String, Rgb, Vec<f64>)> {
        gs.iter()
            .enumerate()
            .map(|(i, g)| (g.name.clone(), color(i), f(g)))
            .collect()
    };
    save(
        out,
        "mirror-asymmetry",
        &bars(
            "Mirror asymmetry (paper eqs. 20-22): IoU of each level with its mirror",
            "transformation",
            "mean IoU over levels",
            &[
                "horizontal mirror",
                "vertical mirror",
                "rotations 90/180/270",
            ]
            .map(String::from),
            &series(&|g| vec![g.mirror.horizontal, g.mirror.vertical, g.mirror.rotational]),
        ),
    )?;
    save(
        out,
        "tile-mix",
        &bars(
            "Tile appearance distribution",
            "tile kind (shaft ends counted as dead ends)",
            "share of tiles (%)",
            &PAPER_KINDS.map(String::from),
            &series(&|g| {
                PAPER_KINDS
                    .iter()
                    .map(|k| g.tile_mix_paper_percent[*k])
                    .collect()
            }),
        ),
    )?;
    let summaries = |f: &dyn Fn(&GroupStats) -> Summary| -> Vec<(String, Summary)> {
        gs.iter().map(|g| (g.name.clone(), f(g))).collect()
    };
    save(
        out,
        "size-cells",
        &boxes(
            "Environment size: occupied cells per world",
            "occupied cells",
            &summaries(&|g| g.cells),
        ),
    )?;
    save(
        out,
        "size-length",
        &boxes(
            "Environment size: total passage length per world",
            "passage length (m)",
            &summaries(&|g| g.length_m),
        ),
    )?;
    save(
        out,
        "size-levels",
        &boxes(
            "Environment size: levels per world",
            "levels",
            &summaries(&|g| g.levels),
        ),
    )?;
    save(
        out,
        "corridor-length",
        &boxes(
            "Corridor lengths (between graph nodes)",
            "corridor length (cells)",
            &summaries(&|g| g.graph.corridor_length_cells),
        ),
    )?;
    save(
        out,
        "cycles",
        &boxes(
            "Independent cycles per world",
            "cycles (edges - cells + pieces, per level, summed)",
            &summaries(&|g| g.graph.cycles),
        ),
    )?;
    save(
        out,
        "node-degree",
        &bars(
            "Node degree distribution of the topological graph",
            "degree (corridors and shafts at the node)",
            "share of nodes (%)",
            &["1", "2", "3", "4", "5+"].map(String::from),
            &series(&|g| {
                ["1", "2", "3", "4", "5+"]
                    .iter()
                    .map(|d| g.graph.degree_percent[*d])
                    .collect()
            }),
        ),
    )?;
    let structures = ["t-junction", "intersection", "loop"];
    let mut constraint_series = Vec::new();
    for (i, g) in gs.iter().enumerate() {
        if g.constraints.is_empty() {
            continue;
        }
        let per_world = |pick: fn(&super::report::Constraint) -> u64| -> Vec<f64> {
            structures
                .iter()
                .map(|s| {
                    g.constraints
                        .get(*s)
                        .map_or(0.0, |c| pick(c) as f64 / g.worlds.max(1) as f64)
                })
                .collect()
        };
        let base = color(i);
        let pale = base.map(|v| ((u16::from(v) + 2 * 255) / 3) as u8);
        constraint_series.push((
            format!("{} requested", g.name),
            pale,
            per_world(|c| c.requested),
        ));
        constraint_series.push((
            format!("{} achieved", g.name),
            base,
            per_world(|c| c.achieved),
        ));
    }
    if !constraint_series.is_empty() {
        save(
            out,
            "constraints",
            &bars(
                "Constraint satisfaction: requested and achieved structures",
                "structure",
                "mean per world (levels summed)",
                &structures.map(String::from),
                &constraint_series,
            ),
        )?;
    }
    Ok(())
}
