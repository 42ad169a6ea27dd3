//! `subtgraph score WORLD --segmentation level-N.png|.npy --out DIR`: grades a topometric
//! segmentation (GRID-FAST's kind: each pixel of a top-down map labelled corridor, junction,
//! intersection, dead end or shaft/ramp) against the world's own tile kinds.
//!
//! - The map is on the grid of the level's ROS map (`ground_truth/maps/level-N.pgm` + `.yaml`:
//!   same size, resolution and origin, row 0 north); the ground truth is
//!   `ground_truth/semantic_labels.json` rasterised onto it (`read.rs`). Only the ROS map's
//!   free pixels are graded: a label drawn in rock is neither right nor wrong.
//! - Per class: IoU, precision and recall; the confusion matrix (rows truth, columns predicted).
//! - Nodes: each 4-connected region of one predicted node class (junction, intersection, dead
//!   end) is a detected node at its centroid, matched to the level's graph nodes of those
//!   classes within `--node-radius` (closest pairs first, each once): node precision, recall
//!   and mean localisation error.
//! - Output: `segmentation.json` (flat metrics at the top level) and `confusion.csv`, in a score
//!   folder written like every folder the tool writes.

pub mod matching;
pub mod read;

use std::fmt;
use std::path::{Path, PathBuf};

use serde_json::{Map, Value, json};

use crate::Error;
use crate::folder::{Kind, Out};

/// The label table: pixel value = index.
pub const CLASSES: [&str; 6] = [
    "unlabelled",
    "corridor",
    "junction",
    "intersection",
    "dead_end",
    "shaft_ramp",
];
/// A T-junction's value.
pub const JUNCTION: u8 = 2;
/// An intersection's value.
pub const INTERSECTION: u8 = 3;
/// A dead end's value.
pub const DEAD_END: u8 = 4;

/// What `score --segmentation` is asked.
#[derive(Clone, Debug)]
pub struct SegmentationRequest {
    /// The world folder.
    pub world: PathBuf,
    /// The labelled map (PNG or `.npy`).
    pub segmentation: PathBuf,
    /// Its level; `None` reads it from the file name (`level-N`).
    pub level: Option<usize>,
    /// A detected node within this distance of a graph node may match it, metres; `None` is
    /// half the tile pitch.
    pub node_radius: Option<f64>,
    /// The output folder.
    pub out: PathBuf,
    /// Replace a score folder the tool wrote.
    pub force: bool,
}

/// What the segmentation scored; [`fmt::Display`] is the summary the command line prints.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentationScore {
    /// The level graded.
    pub level: usize,
    /// Mean IoU over the classes present in the truth or the map.
    pub iou_mean: Option<f64>,
    /// Per class 1..=5: `(IoU, precision, recall)`.
    pub classes: Vec<(Option<f64>, Option<f64>, Option<f64>)>,
    /// Detected nodes, graph nodes, matched.
    pub nodes: [usize; 3],
    /// Mean distance of the matched nodes, metres.
    pub node_error_mean_m: Option<f64>,
    /// The score folder written.
    pub out: PathBuf,
}

fn ratio(a: u64, b: u64) -> Option<f64> {
    (b > 0).then(|| a as f64 / b as f64)
}

impl fmt::Display for SegmentationScore {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let pct = |x: Option<f64>| x.map_or("-".to_owned(), |v| format!("{:.1} %", 100.0 * v));
        write!(
            f,
            "segmentation of level {}: mean IoU {}",
            self.level,
            pct(self.iou_mean)
        )?;
        for (k, (iou, _, _)) in self.classes.iter().enumerate() {
            write!(f, "; {} {}", CLASSES[k + 1], pct(*iou))?;
        }
        let [p, t, m] = self.nodes;
        write!(
            f,
            "\nnodes: {m} of {t} graph nodes found, {p} detected (precision {}, recall {})",
            pct(ratio(m as u64, p as u64)),
            pct(ratio(m as u64, t as u64))
        )?;
        if let Some(e) = self.node_error_mean_m {
            write!(f, ", mean error {e:.2} m")?;
        }
        write!(f, "\nwrote {}", self.out.display())
    }
}

/// The level in a file name `...level-N...`.
fn level_in_name(path: &Path) -> Option<usize> {
    let name = path.file_stem()?.to_str()?;
    let at = name.rfind("level-")? + "level-".len();
    let digits: String = name[at..]
        .chars()
        .take_while(char::is_ascii_digit)
        .collect();
    digits.parse().ok()
}

/// Detected nodes: the centroid (world x, y) of each 4-connected region of one node class,
/// regions in the raster order of their first pixel.
fn detected(pred: &[u8], grid: &read::MapGrid) -> Vec<[f64; 2]> {
    let (w, h) = (grid.width, grid.height);
    let mut seen = vec![false; pred.len()];
    let mut out = Vec::new();
    for start in 0..pred.len() {
        let c = pred[start];
        if seen[start] || !matches!(c, JUNCTION | INTERSECTION | DEAD_END) {
            continue;
        }
        seen[start] = true;
        let (mut stack, mut sum, mut n) = (vec![start], [0.0, 0.0], 0usize);
        while let Some(k) = stack.pop() {
            let (r, col) = (k / w, k % w);
            let [x, y] = grid.centre(r, col);
            sum = [sum[0] + x, sum[1] + y];
            n += 1;
            let mut near = Vec::with_capacity(4);
            if r > 0 {
                near.push(k - w);
            }
            if r + 1 < h {
                near.push(k + w);
            }
            if col > 0 {
                near.push(k - 1);
            }
            if col + 1 < w {
                near.push(k + 1);
            }
            for q in near {
                if !seen[q] && pred[q] == c {
                    seen[q] = true;
                    stack.push(q);
                }
            }
        }
        out.push([sum[0] / n as f64, sum[1] / n as f64]);
    }
    out
}

impl SegmentationRequest {
    /// Scores the segmentation and writes the score folder (`--out` checked before anything
    /// is read; nothing written on bad input).
    pub fn run(&self) -> Result<SegmentationScore, Error> {
        if let Some(r) = self.node_radius
            && !(r.is_finite() && r >= 0.0)
        {
            return Err(Error::Usage(
                "--node-radius must be a number of metres, 0 or more".to_owned(),
            ));
        }
        let reading: Vec<&Path> = vec![&self.world, &self.segmentation];
        let out = Out {
            path: &self.out,
            kind: Kind::Score,
            force: self.force,
            reading: &reading,
        };
        out.check()?;
        let level = match self.level.or_else(|| level_in_name(&self.segmentation)) {
            Some(l) => l,
            None => {
                return Err(Error::Usage(format!(
                    "{}: no level in the file name (like level-0.png): give it with --level N",
                    self.segmentation.display()
                )));
            }
        };
        let cells = crate::score::world::cells(&self.world)?;
        if level >= cells.levels {
            return Err(Error::Input(format!(
                "{}: level {level}, but {} has {} level(s) (0 to {}): give the right level with --level N",
                self.segmentation.display(),
                self.world.display(),
                cells.levels,
                cells.levels - 1
            )));
        }
        let grid = read::map(&self.world, level, cells.levels)?;
        let truth = read::truth(&self.world, level, &cells, &grid)?;
        let pred = read::prediction(&self.segmentation, grid.width, grid.height)?;
        let n = CLASSES.len();
        let mut confusion = vec![vec![0u64; n]; n];
        for k in (0..pred.len()).filter(|&k| grid.free[k]) {
            confusion[truth[k] as usize][pred[k] as usize] += 1;
        }
        let total: u64 = confusion.iter().flatten().sum();
        let right: u64 = (0..n).map(|c| confusion[c][c]).sum();
        let mut doc = Map::new();
        let mut classes = Vec::new();
        let mut ious = Vec::new();
        for (c, name) in CLASSES.iter().enumerate().skip(1) {
            let tp = confusion[c][c];
            let t: u64 = confusion[c].iter().sum();
            let p: u64 = confusion.iter().map(|row| row[c]).sum();
            let iou = ratio(tp, t + p - tp);
            let (precision, recall) = (ratio(tp, p), ratio(tp, t));
            ious.extend(iou);
            doc.insert(format!("iou.{name}"), json!(iou));
            doc.insert(format!("precision.{name}"), json!(precision));
            doc.insert(format!("recall.{name}"), json!(recall));
            doc.insert(format!("pixels_truth.{name}"), json!(t));
            doc.insert(format!("pixels_predicted.{name}"), json!(p));
            classes.push((iou, precision, recall));
        }
        let iou_mean = (!ious.is_empty()).then(|| ious.iter().sum::<f64>() / ious.len() as f64);
        let radius = self.node_radius.unwrap_or(0.5 * cells.pitch);
        let graph: Vec<(usize, [f64; 2])> = crate::score::world::nodes(&self.world)?
            .into_iter()
            .filter(|n| {
                n.level == level
                    && matches!(
                        read::class_of_kind(n.kind),
                        JUNCTION | INTERSECTION | DEAD_END
                    )
            })
            .map(|n| (n.id, n.xy))
            .collect();
        let found = detected(&pred, &grid);
        let positions: Vec<[f64; 2]> = graph.iter().map(|g| g.1).collect();
        let budget = crate::memory::budget(None)?;
        let matched = matching::matches(&found, &positions, radius, budget.bytes)?;
        let node_error_mean_m = (!matched.is_empty())
            .then(|| matched.iter().map(|m| m.2).sum::<f64>() / matched.len() as f64);
        let command = format!(
            "subtgraph score {} --segmentation {} --level {level} --node-radius {radius} --out {}",
            self.world.display(),
            self.segmentation.display(),
            self.out.display()
        );
        for (k, v) in [
            ("format", json!("subtgraph-segmentation-score/1")),
            ("command", json!(command)),
            ("world", json!(self.world.display().to_string())),
            (
                "segmentation",
                json!(self.segmentation.display().to_string()),
            ),
            (
                "options",
                json!({
                    "level": level,
                    "width": grid.width,
                    "height": grid.height,
                    "resolution_m": grid.resolution,
                    "node_radius_m": radius,
                }),
            ),
            ("pixels_graded", json!(total)),
            ("pixel_accuracy", json!(ratio(right, total))),
            ("iou_mean", json!(iou_mean)),
            ("nodes_detected", json!(found.len())),
            ("nodes_truth", json!(graph.len())),
            ("nodes_matched", json!(matched.len())),
            (
                "node_precision",
                json!(ratio(matched.len() as u64, found.len() as u64)),
            ),
            (
                "node_recall",
                json!(ratio(matched.len() as u64, graph.len() as u64)),
            ),
            ("node_error_mean_m", json!(node_error_mean_m)),
            ("classes", json!(CLASSES)),
            ("confusion", json!(confusion)),
            (
                "matches",
                Value::Array(
                    matched
                        .iter()
                        .map(|&(i, j, d)| {
                            json!({"node": graph[j].0, "node_xy": graph[j].1, "detected_xy": found[i], "error_m": d})
                        })
                        .collect(),
                ),
            ),
        ] {
            doc.insert(k.to_owned(), v);
        }
        let mut json_bytes = serde_json::to_vec_pretty(&Value::Object(doc))
            .map_err(|e| Error::Input(format!("writing segmentation.json: {e}")))?;
        json_bytes.push(b'\n');
        let mut csv = String::from("truth\\predicted");
        for name in CLASSES {
            csv.push(',');
            csv.push_str(name);
        }
        csv.push('\n');
        for (c, row) in confusion.iter().enumerate() {
            csv.push_str(CLASSES[c]);
            for v in row {
                csv.push_str(&format!(",{v}"));
            }
            csv.push('\n');
        }
        let files = [
            ("segmentation.json", json_bytes),
            ("confusion.csv", csv.into_bytes()),
        ];
        crate::folder::write_atomically(&out, |w| {
            for (name, bytes) in &files {
                std::fs::write(w.root().join(name), bytes)
                    .map_err(Error::io(format!("writing {name}")))?;
            }
            Ok::<(), Error>(())
        })?;
        Ok(SegmentationScore {
            level,
            iou_mean,
            classes,
            nodes: [found.len(), graph.len(), matched.len()],
            node_error_mean_m,
            out: self.out.clone(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_level_is_read_from_the_file_name() {
        assert_eq!(level_in_name(Path::new("out/level-3.png")), Some(3));
        assert_eq!(level_in_name(Path::new("run2-level-12.npy")), Some(12));
        assert_eq!(level_in_name(Path::new("level-.png")), None);
        assert_eq!(level_in_name(Path::new("map.png")), None);
    }

    #[test]
    fn nodes_match_closest_pair_first_each_once_within_the_radius() {
        let found = [[0.0, 0.0], [1.0, 0.0], [50.0, 0.0]];
        let truth = [[0.9, 0.0], [3.0, 0.0]];
        // (1, 0) is closest (0.1 m); detection 0 then takes node 1 at 3 m; 50 m is too far.
        let m = matching::matches(&found, &truth, 8.0, u64::MAX).unwrap();
        let pairs: Vec<(usize, usize)> = m.iter().map(|x| (x.0, x.1)).collect();
        assert_eq!(pairs, vec![(1, 0), (0, 1)]);
        assert!((m[0].2 - 0.1).abs() < 1e-12 && (m[1].2 - 3.0).abs() < 1e-12);
        assert_eq!(
            matching::matches(&found, &truth, 1.0, u64::MAX)
                .unwrap()
                .len(),
            1
        );
    }

    #[test]
    fn each_connected_region_of_one_node_class_is_one_detection() {
        let grid = read::MapGrid {
            width: 4,
            height: 2,
            resolution: 1.0,
            origin: [0.0, 0.0],
            free: vec![true; 8],
        };
        // Row 0 (north): two junction pixels, then a dead end touching them; row 1: one
        // junction pixel under the first.
        let pred = [2, 2, 4, 0, 2, 0, 0, 0];
        let found = detected(&pred, &grid);
        assert_eq!(found.len(), 2);
        assert!((found[0][0] - (0.5 + 1.5 + 0.5) / 3.0).abs() < 1e-12);
        assert!((found[0][1] - (1.5 + 1.5 + 0.5) / 3.0).abs() < 1e-12);
        assert_eq!(found[1], [2.5, 1.5]);
    }
}
