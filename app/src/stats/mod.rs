//! `subtgraph stats`: the variability of worlds, as the paper's "Topological Analysis"
//! measures it (pairwise IoU, mirror asymmetry, tile appearance), plus environment sizes,
//! constraint satisfaction and graph statistics, per input folder (group) and overall.
//!
//! Writes into the report folder: `stats.json` (everything), `groups.csv` (the headline
//! numbers, one row per group and `all`), `worlds.csv` (one row per world),
//! `pairwise-iou.csv` and `pairwise-iou-eq19-as-printed.csv` (matrices over all worlds, in
//! group order), and each plot as SVG and PNG (`charts.rs`, drawn by [`subtgraph_plot`]).
//!
//! Pairwise IoU compares level 0 of two worlds (as the original's numbers do); mirror
//! asymmetry is per level, averaged over every level of every world of the group.

mod charts;
mod load;
pub mod metrics;
mod report;
mod tables;

use std::path::PathBuf;

use crate::Error;
use crate::folder::{Kind, Out};

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
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s {
            "common" => Ok(Crop::Common),
            "pad" => Ok(Crop::Pad),
            _ => Err(Error::Usage(format!(
                "--crop '{s}': write --crop common (crop to the shared rows and columns) or --crop pad (pad with empty cells)"
            ))),
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

/// What `stats` is asked.
#[derive(Clone, Debug)]
pub struct StatsRequest {
    /// World folders, dataset folders, or folders of the original's `.npy` grids: each one
    /// group of the report.
    pub inputs: Vec<PathBuf>,
    /// The report folder.
    pub out: PathBuf,
    /// How pairwise IoU treats grids of different sizes.
    pub crop: Crop,
}

/// A written report.
#[derive(Clone, Debug)]
pub struct Report {
    /// Groups in the report (inputs holding worlds).
    pub groups: usize,
    /// Worlds measured.
    pub worlds: usize,
    /// The headline numbers per group, as the command line prints them.
    pub summary: String,
}

impl StatsRequest {
    /// Loads the inputs, computes the statistics and writes the report folder.
    pub fn run(&self) -> Result<Report, Error> {
        let (inputs, out) = (&self.inputs, &self.out);
        let reading: Vec<&std::path::Path> = inputs.iter().map(PathBuf::as_path).collect();
        // A report replaces only an earlier report (stats needs no --force for that), never a
        // world, another command's folder or anything it reads.
        let destination = Out {
            path: out,
            kind: Kind::Stats,
            force: true,
            reading: &reading,
        };
        destination.check()?;
        let groups = load(inputs)?;
        let total: usize = groups.iter().map(|g| g.samples.len()).sum();
        if total == 0 {
            return Err(Error::Input(format!(
                "no worlds found in {}: give world folders (with occupancy.npy), dataset folders holding them, or folders of the original tool's .npy grids",
                inputs
                    .iter()
                    .map(|p| p.display().to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
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
        let stats = report::compute(&groups, self.crop);
        // Written atomically like a world folder: an earlier report is replaced, a folder
        // holding anything else is refused, and nothing is half-written.
        crate::folder::write_atomically(&destination, |w| {
            tables::write(&stats, &groups, w.root())?;
            charts::write_all(&stats, &groups, w.root())
        })?;
        Ok(Report {
            groups: groups.len(),
            worlds: total,
            summary: tables::summary(&stats, out),
        })
    }
}
