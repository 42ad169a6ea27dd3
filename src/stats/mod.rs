//! `subtgraph stats`: the variability of worlds, as the paper's "Topological Analysis"
//! measures it (pairwise IoU, mirror asymmetry, tile appearance), plus environment sizes,
//! constraint satisfaction and graph statistics, per input folder (group) and overall.
//!
//! Writes into the report folder: `stats.json` (everything), `groups.csv` (the headline
//! numbers, one row per group and `all`), `worlds.csv` (one row per world),
//! `pairwise-iou.csv` and `pairwise-iou-eq19-as-printed.csv` (matrices over all worlds, in
//! group order), and each plot as SVG and PNG (`charts.rs`, drawn by [`plot`]).
//!
//! Pairwise IoU compares level 0 of two worlds (as the original's numbers do); mirror
//! asymmetry is per level, averaged over every level of every world of the group.

mod charts;
mod load;
pub mod metrics;
mod report;
mod tables;

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};

pub use load::{Group, Sample, load, sample_of};

/// How pairwise IoU treats two grids of different sizes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Crop {
    /// Both cropped to the rows and columns they share (the top-left corner), as the
    /// original's published numbers are.
    Common,
    /// The smaller padded with empty cells: the union counts both worlds whole.
    Pad,
}

impl std::str::FromStr for Crop {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "common" => Ok(Crop::Common),
            "pad" => Ok(Crop::Pad),
            _ => Err(format!(
                "--crop '{s}': write --crop common (crop to the shared rows and columns) or --crop pad (pad with empty cells)"
            )),
        }
    }
}

impl Crop {
    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Crop::Common => "common",
            Crop::Pad => "pad",
        }
    }
}

/// Loads the inputs, computes the statistics and writes the report folder. Returns a short
/// text summary (the headline numbers per group).
pub fn run(inputs: &[PathBuf], out: &Path, crop: Crop) -> Result<String> {
    let groups = load(inputs)?;
    let total: usize = groups.iter().map(|g| g.samples.len()).sum();
    if total == 0 {
        bail!(
            "no worlds found in {}: give world folders (with occupancy.npy), dataset folders holding them, or folders of the original tool's .npy grids",
            inputs
                .iter()
                .map(|p| p.display().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    for g in &groups {
        if g.samples.is_empty() {
            eprintln!(
                "warning: {} holds no world; it is left out",
                g.path.display()
            );
        }
    }
    let groups: Vec<Group> = groups
        .into_iter()
        .filter(|g| !g.samples.is_empty())
        .collect();
    let stats = report::compute(&groups, crop);
    // Written atomically like a world folder: an earlier report is replaced, a folder holding
    // anything else is refused, and nothing is half-written.
    crate::folder::write_atomically(out, true, |w| {
        tables::write(&stats, &groups, w.root())?;
        charts::write_all(&stats, &groups, w.root())
    })?;
    Ok(tables::summary(&stats, out))
}
