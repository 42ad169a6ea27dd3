//! `subtgraph report METHOD=FOLDER... [--runs runs.csv] --out DIR`: the statistics of whole
//! datasets, from the score folders `subtgraph score` wrote for many worlds and one or more
//! methods (the paper's evaluations over hundreds of worlds).
//!
//! - Runs (`runs.rs`): which score folder is which method on which world, and every number
//!   of each folder's summary JSON, read generically (a new kind of score needs no code).
//! - The world's parameters (`world.rs`): loops, junctions, levels, length, ... from the world
//!   folder's files.
//! - Statistics (`sample.rs`, `wilcoxon.rs`): per method and preset the mean, median and a
//!   seeded bootstrap interval of every metric and the success rate with a Wilson interval;
//!   per pair of methods the paired differences with Wilcoxon's signed-rank test; per metric
//!   and parameter a least-squares line, and failure rates per bin.
//! - Output (`files.rs`, `plots.rs`): `report.json`, CSV tables, PNG plots and an
//!   `index.html` that opens offline, in a folder written atomically (`Kind::Report`).
//!
//! Single-threaded and ordered by name throughout: the same runs give the same bytes.

pub mod analysis;
pub mod bounds;
pub mod csv;
mod files;
mod plots;
pub mod runs;
pub mod sample;
pub mod wilcoxon;
pub mod world;

use std::fmt;
use std::path::{Path, PathBuf};

use crate::Error;
use crate::folder::{Kind, Out};

pub use analysis::Report;

/// What `report` is asked.
#[derive(Clone, Debug)]
pub struct ReportRequest {
    /// `METHOD=FOLDER` arguments: a score folder or a folder of score folders.
    pub runs: Vec<String>,
    /// A `world,method,score_folder` CSV.
    pub runs_csv: Option<PathBuf>,
    /// The report folder.
    pub out: PathBuf,
    /// Replace a report folder the tool wrote.
    pub force: bool,
    /// The bootstrap's seed.
    pub seed: u64,
    /// Bootstrap resamples per interval.
    pub resamples: usize,
}

/// What the report found, as the command line prints it.
#[derive(Clone, Debug)]
pub struct Reported {
    /// Methods, worlds, runs and metrics counted.
    pub counts: [usize; 4],
    /// `(a, b, metric, p)` of the smallest Wilcoxon p-values, one per pair of methods.
    pub headline: Vec<String>,
    /// The folder written.
    pub out: PathBuf,
}

impl fmt::Display for Reported {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [m, w, r, k] = self.counts;
        writeln!(
            f,
            "report: {m} method(s), {w} world(s), {r} run(s), {k} metric(s)"
        )?;
        for h in &self.headline {
            writeln!(f, "{h}")?;
        }
        write!(f, "wrote {}", self.out.display())
    }
}

impl ReportRequest {
    fn reading(&self) -> Vec<&Path> {
        let mut r: Vec<&Path> = self
            .runs
            .iter()
            .filter_map(|a| a.split_once('=').map(|(_, f)| Path::new(f)))
            .collect();
        r.extend(self.runs_csv.as_deref());
        r
    }

    /// Reads the runs, computes and writes the report folder (`--out` checked first).
    pub fn run(&self) -> Result<Reported, Error> {
        if self.runs.is_empty() && self.runs_csv.is_none() {
            return Err(Error::Usage(
                "name the runs: METHOD=FOLDER arguments (a score folder, or a folder of them) or --runs runs.csv (world,method,score_folder)".into(),
            ));
        }
        bounds::resamples(self.resamples)?;
        let reading = self.reading();
        let out = Out {
            path: &self.out,
            kind: Kind::Report,
            force: self.force,
            reading: &reading,
        };
        out.check()?;
        let mut all = Vec::new();
        for (k, a) in self.runs.iter().enumerate() {
            all.extend(runs::from_argument(k + 1, a)?);
        }
        if let Some(csv) = &self.runs_csv {
            all.extend(runs::from_csv(csv)?);
        }
        let list = runs::merge(all)?;
        let report = analysis::analyse(&list, self.seed, self.resamples)?;
        let files = files::files(&report, &absolute(&self.out));
        crate::folder::write_atomically(&out, |w| {
            for (name, bytes) in &files {
                let path = w.root().join(name);
                if let Some(dir) = path.parent() {
                    std::fs::create_dir_all(dir).map_err(Error::io(format!("creating {name}")))?;
                }
                std::fs::write(&path, bytes).map_err(Error::io(format!("writing {name}")))?;
            }
            Ok::<(), Error>(())
        })?;
        Ok(Reported {
            counts: [
                report.methods.len(),
                report.worlds.len(),
                report.runs.len(),
                report.metrics.len(),
            ],
            headline: report.headline(),
            out: self.out.clone(),
        })
    }
}

/// `p` made absolute and its existing part canonical (the folder itself does not exist yet).
fn absolute(p: &Path) -> PathBuf {
    let p = if p.is_absolute() {
        p.to_owned()
    } else {
        std::env::current_dir().unwrap_or_default().join(p)
    };
    match (
        p.parent().and_then(|d| d.canonicalize().ok()),
        p.file_name(),
    ) {
        (Some(d), Some(n)) => d.join(n),
        _ => p,
    }
}
