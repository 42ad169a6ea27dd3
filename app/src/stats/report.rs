//! The statistics of each group and of all worlds together, and the files that hold them.

use serde::Serialize;
use std::collections::BTreeMap;

use subtgraph_core::tile::TileKind;

pub use subtgraph_plot::Summary;

use super::metrics::{self, Mirror, Packed};
use super::{Crop, Group, Sample};

/// Means of eqs. 20-22 over levels.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct MirrorMeans {
    /// Levels measured (empty levels are left out).
    pub levels: usize,
    /// Mean IoU with the horizontal mirror.
    pub horizontal: f64,
    /// Mean IoU with the vertical mirror.
    pub vertical: f64,
    /// Mean over the three rotations.
    pub rotational: f64,
}

/// Pairwise IoU of level 0 over the pairs of a group.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Pairwise {
    /// Pairs with at least one occupied cell on the compared area.
    pub pairs: usize,
    /// Mean true IoU.
    pub mean: f64,
    /// Smallest.
    pub min: f64,
    /// Largest.
    pub max: f64,
    /// Mean of the paper's eq. 19 as printed (divides by the sum of the areas; at most 0.5).
    pub eq19_as_printed_mean: f64,
}

/// Requested against achieved, for one structure.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Constraint {
    /// Levels with a request on record.
    pub levels: usize,
    /// Requested, summed over levels.
    pub requested: u64,
    /// What the requests bring (a loop's arms add four T-junctions), summed.
    pub expected: u64,
    /// Counted on the grids, summed.
    pub achieved: u64,
    /// Levels whose achieved count is at least the expected one.
    pub satisfied_levels: usize,
    /// Levels whose achieved count is exactly the expected one.
    pub exact_levels: usize,
}

/// Graph statistics.
#[derive(Clone, Debug, Default, Serialize)]
pub struct GraphStats {
    /// Independent cycles per world.
    pub cycles: Summary,
    /// Share of nodes (%) by degree: `1` .. `4`, `5+`.
    pub degree_percent: BTreeMap<String, f64>,
    /// Corridor lengths in cells.
    pub corridor_length_cells: Summary,
}

/// The statistics of one group (or of all worlds).
#[derive(Clone, Debug, Default, Serialize)]
pub struct GroupStats {
    /// Group name (`all` for every world).
    pub name: String,
    /// Worlds.
    pub worlds: usize,
    /// Eqs. 20-22.
    pub mirror: MirrorMeans,
    /// Eq. 19, true union, and as printed.
    pub pairwise_iou: Pairwise,
    /// Share of tiles (%) per kind.
    pub tile_mix_percent: BTreeMap<String, f64>,
    /// The same in the original's five kinds (shaft ends counted as dead ends).
    pub tile_mix_paper_percent: BTreeMap<String, f64>,
    /// Occupied cells per world.
    pub cells: Summary,
    /// Levels per world.
    pub levels: Summary,
    /// Total passage length per world, metres.
    pub length_m: Summary,
    /// Total corridor length per world, cells.
    pub length_cells: Summary,
    /// Per structure.
    pub constraints: BTreeMap<String, Constraint>,
    /// Graph statistics.
    pub graph: GraphStats,
}

/// A world of the original tool's found in several files (its encodings), counted once.
#[derive(Clone, Debug, Serialize)]
pub struct Merged {
    /// Its group.
    pub group: String,
    /// Its name.
    pub world: String,
    /// The file it was measured from (the spatial encoding when there is one that loads).
    pub used: String,
    /// Its other files, left out.
    pub left_out: Vec<String>,
}

/// Everything the report holds.
#[derive(Clone, Debug, Serialize)]
pub struct Stats {
    /// Format tag.
    pub format: &'static str,
    /// `common` or `pad`.
    pub crop: &'static str,
    /// What the IoU numbers are.
    pub note: &'static str,
    /// How the original's grids in several encodings are counted.
    pub encodings_note: &'static str,
    /// The worlds found in several encodings, each counted once.
    pub merged_encodings: Vec<Merged>,
    /// Per group, in input order.
    pub groups: Vec<GroupStats>,
    /// Every world together.
    pub all: GroupStats,
    /// Mean true IoU between worlds of group i and group j (i == j: distinct pairs).
    pub between_groups_iou: Vec<Vec<Option<f64>>>,
    /// Per world, in group order: its mirror means.
    #[serde(skip)]
    pub world_mirror: Vec<Option<MirrorMeans>>,
    /// Pairwise (true IoU, eq. 19 as printed) of level 0, all worlds in group order.
    #[serde(skip)]
    pub matrix: Vec<Vec<Option<(f64, f64)>>>,
}

/// The original's five tile kinds, with shaft ends counted as dead ends.
pub const PAPER_KINDS: [&str; 5] = [
    "dead-end",
    "straight",
    "corner",
    "t-junction",
    "intersection",
];

pub(super) fn compute(groups: &[Group], crop: Crop) -> Stats {
    let samples: Vec<&Sample> = groups.iter().flat_map(|g| &g.samples).collect();
    let packed: Vec<Option<Packed>> = samples
        .iter()
        .map(|s| s.levels.first().map(Packed::new))
        .collect();
    let n = samples.len();
    let mut matrix = vec![vec![None; n]; n];
    for i in 0..n {
        for j in i..n {
            let v = match (&packed[i], &packed[j]) {
                (Some(a), Some(b)) => a.iou(b, crop == Crop::Common),
                _ => None,
            };
            matrix[i][j] = v;
            matrix[j][i] = v;
        }
    }
    let world_mirror: Vec<Option<MirrorMeans>> = samples
        .iter()
        .map(|s| {
            mirror_means(
                &s.levels
                    .iter()
                    .filter_map(metrics::mirror)
                    .collect::<Vec<_>>(),
            )
        })
        .collect();
    let mut start = 0;
    let mut ranges = Vec::new();
    for g in groups {
        ranges.push(start..start + g.samples.len());
        start += g.samples.len();
    }
    let group_stats = groups
        .iter()
        .zip(&ranges)
        .map(|(g, r)| stats_of(&g.name, &samples[r.clone()], &matrix, r.clone()))
        .collect();
    let between = ranges
        .iter()
        .map(|a| {
            ranges
                .iter()
                .map(|b| {
                    let values: Vec<f64> = a
                        .clone()
                        .flat_map(|i| b.clone().map(move |j| (i, j)))
                        .filter(|(i, j)| i != j)
                        .filter_map(|(i, j)| matrix[i][j].map(|v| v.0))
                        .collect();
                    (!values.is_empty()).then(|| values.iter().sum::<f64>() / values.len() as f64)
                })
                .collect()
        })
        .collect();
    Stats {
        format: "subtgraph-stats/1",
        crop: crop.name(),
        note: "IoU is the true |A and B| / |A or B|; eq19_as_printed is the paper's formula as printed (divides by |A| + |B|, at most 0.5). Pairwise IoU compares level 0; mirror asymmetry averages every level.",
        encodings_note: "The original tool saves each world in three encodings (spatial, topological, structural). Grid files whose names differ only by the encoding (world_12_spatial.npy, world_12_topological.npy; subtgraph.spatial.npy, ...), or that are the only grids of one folder, are one world, counted once and measured from its spatial encoding (else topological, else structural); merged_encodings lists each such world and the files left out.",
        merged_encodings: samples
            .iter()
            .filter_map(|s| {
                let (used, left_out) = s.encodings.clone()?;
                Some(Merged {
                    group: s.group.clone(),
                    world: s.name.clone(),
                    used,
                    left_out,
                })
            })
            .collect(),
        groups: group_stats,
        all: stats_of("all", &samples, &matrix, 0..n),
        between_groups_iou: between,
        world_mirror,
        matrix,
    }
}

fn mirror_means(m: &[Mirror]) -> Option<MirrorMeans> {
    if m.is_empty() {
        return None;
    }
    let mean = |f: fn(&Mirror) -> f64| m.iter().map(f).sum::<f64>() / m.len() as f64;
    Some(MirrorMeans {
        levels: m.len(),
        horizontal: mean(|m| m.horizontal),
        vertical: mean(|m| m.vertical),
        rotational: mean(|m| m.rotational),
    })
}

fn stats_of(
    name: &str,
    samples: &[&Sample],
    matrix: &[Vec<Option<(f64, f64)>>],
    range: std::ops::Range<usize>,
) -> GroupStats {
    let mirrors: Vec<Mirror> = samples
        .iter()
        .flat_map(|s| s.levels.iter().filter_map(metrics::mirror))
        .collect();
    let pairs: Vec<(f64, f64)> = range
        .clone()
        .flat_map(|i| (i + 1..range.end).map(move |j| (i, j)))
        .filter_map(|(i, j)| matrix[i][j])
        .collect();
    let pairwise = if pairs.is_empty() {
        Pairwise::default()
    } else {
        let k = pairs.len() as f64;
        Pairwise {
            pairs: pairs.len(),
            mean: pairs.iter().map(|p| p.0).sum::<f64>() / k,
            min: pairs.iter().map(|p| p.0).fold(f64::INFINITY, f64::min),
            max: pairs.iter().map(|p| p.0).fold(0.0, f64::max),
            eq19_as_printed_mean: pairs.iter().map(|p| p.1).sum::<f64>() / k,
        }
    };
    let mut tiles = [0usize; 7];
    for s in samples {
        for (t, v) in tiles.iter_mut().zip(s.tiles) {
            *t += v;
        }
    }
    let all_tiles = tiles.iter().sum::<usize>().max(1) as f64;
    let tile_mix_percent = TileKind::ALL
        .iter()
        .zip(tiles)
        .map(|(k, v)| (k.name().to_owned(), 100.0 * v as f64 / all_tiles))
        .collect();
    let paper = |k: &str| match k {
        "dead-end" => tiles[0] + tiles[5] + tiles[6],
        _ => {
            tiles[TileKind::ALL
                .iter()
                .position(|t| t.name() == k)
                .unwrap_or(0)]
        }
    };
    let tile_mix_paper_percent = PAPER_KINDS
        .iter()
        .map(|k| ((*k).to_owned(), 100.0 * paper(k) as f64 / all_tiles))
        .collect();
    let mut constraints: BTreeMap<String, Constraint> = BTreeMap::new();
    for s in samples {
        for level in &s.constraints {
            for (shape, &(req, exp, ach)) in level {
                let c = constraints.entry(shape.clone()).or_default();
                c.levels += 1;
                c.requested += req;
                c.expected += exp;
                c.achieved += ach;
                c.satisfied_levels += usize::from(ach >= exp);
                c.exact_levels += usize::from(ach == exp);
            }
        }
    }
    let degrees: Vec<usize> = samples.iter().flat_map(|s| s.degrees.clone()).collect();
    let nodes = degrees.len().max(1) as f64;
    let degree_percent = ["1", "2", "3", "4", "5+"]
        .iter()
        .enumerate()
        .map(|(i, label)| {
            let d = i + 1;
            let count = degrees
                .iter()
                .filter(|&&x| if d == 5 { x >= 5 } else { x == d })
                .count();
            ((*label).to_owned(), 100.0 * count as f64 / nodes)
        })
        .collect();
    let of =
        |f: &dyn Fn(&Sample) -> f64| Summary::of(&samples.iter().map(|s| f(s)).collect::<Vec<_>>());
    GroupStats {
        name: name.to_owned(),
        worlds: samples.len(),
        mirror: mirror_means(&mirrors).unwrap_or_default(),
        pairwise_iou: pairwise,
        tile_mix_percent,
        tile_mix_paper_percent,
        cells: of(&|s| s.cells as f64),
        levels: of(&|s| s.levels.len() as f64),
        length_m: of(&|s| s.length_m),
        length_cells: of(&|s| s.length_cells as f64),
        constraints,
        graph: GraphStats {
            cycles: of(&|s| f64::from(s.cycles)),
            degree_percent,
            corridor_length_cells: Summary::of(
                &samples
                    .iter()
                    .flat_map(|s| s.corridors.iter().map(|&c| c as f64))
                    .collect::<Vec<_>>(),
            ),
        },
    }
}
