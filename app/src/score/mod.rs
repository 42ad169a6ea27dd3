//! `subtgraph score WORLD --reports FILE [--map CLOUD] --out DIR`: grades a robot's run
//! against a world's ground truth, as the DARPA Subterranean Challenge graded teams.
//!
//! - Reports (`reports.rs`): matched to `ground_truth/artifacts.json` by the DARPA rule (same
//!   class within 5 m, each artifact once, in time order); duplicates, wrong classes and false
//!   reports counted.
//! - A map (`cloud.rs`, `coverage.rs`, voxel sets in `bits.rs`): coverage of the world's free
//!   space per level, graph edge and node, and map error, on `ground_truth/free_space.npy`.
//! - Output: `score.json`, `reports.csv`, `artifacts.csv`, `coverage.csv`, `level-N.png`
//!   (`picture.rs`) in a folder written atomically like every folder the tool writes (an
//!   existing one is replaced only with `--force` and only if the tool wrote all of it), and a
//!   summary on the terminal.
//!
//! Bad input is an error naming the file and the row or point: an unknown class, a NaN, an
//! empty file, or positions far outside the world (another frame or unit).

pub mod bits;
pub mod cloud;
pub mod coverage;
mod picture;
mod report;
pub mod reports;
pub mod run;
pub mod segmentation;
pub mod trajectory;
pub mod world;

use std::fmt;
use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::Error;
use crate::folder::{Kind, Out};

pub use reports::MATCH_RADIUS;

/// What `score` is asked.
#[derive(Clone, Debug)]
pub struct ScoreRequest {
    /// The world folder.
    pub world: PathBuf,
    /// The reports file (CSV or JSON).
    pub reports: PathBuf,
    /// A map (PLY, PCD, occupancy .npy), if any.
    pub map: Option<PathBuf>,
    /// A free voxel within this distance of a mapped point is covered, metres.
    pub radius: f64,
    /// A mapped point farther than this from the surface is an error, metres.
    pub tolerance: f64,
    /// The output folder.
    pub out: PathBuf,
    /// Replace a score folder the tool wrote.
    pub force: bool,
    /// A run folder (`--run`): its reports count only when they came over a link; its
    /// explored share and radio are scored too (`run.rs`).
    pub run: Option<PathBuf>,
}

/// How many reports had each outcome.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Counts {
    /// Found an artifact.
    pub scored: usize,
    /// Found one found before.
    pub duplicate: usize,
    /// Near artifacts of other classes only.
    pub wrong_class: usize,
    /// Near no artifact.
    pub false_reports: usize,
}

/// A map's coverage and error, as the summary gives them.
#[derive(Clone, Debug, PartialEq)]
pub struct MapScore {
    /// Points read.
    pub points: usize,
    /// Share of the free space covered, the whole world.
    pub coverage: f64,
    /// The same per level.
    pub levels: Vec<f64>,
    /// Points farther than the tolerance from the surface.
    pub errors: usize,
}

/// What a run scored; [`fmt::Display`] writes the summary the command line prints.
#[derive(Clone, Debug, PartialEq)]
pub struct Scored {
    /// Artifacts found.
    pub outcomes: Counts,
    /// Artifacts in the world.
    pub artifacts_total: usize,
    /// Reports read.
    pub reports_total: usize,
    /// Mean distance of the scoring reports from their artifacts, metres.
    pub mean_error_m: Option<f64>,
    /// The map's score, when one was given.
    pub map: Option<MapScore>,
    /// The radius and tolerance it was scored with, metres.
    pub radius: f64,
    /// See `radius`.
    pub tolerance: f64,
    /// The score folder written.
    pub out: PathBuf,
    /// What `--run` adds.
    pub run: Option<run::RunScore>,
}

impl fmt::Display for Scored {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let o = &self.outcomes;
        write!(
            f,
            "score {} of {} artifacts ({} reports: {} scored, {} duplicate, {} wrong class, {} false)",
            o.scored,
            self.artifacts_total,
            self.reports_total,
            o.scored,
            o.duplicate,
            o.wrong_class,
            o.false_reports
        )?;
        if let Some(e) = self.mean_error_m {
            write!(f, "; mean error of scored reports {e:.2} m")?;
        }
        if let Some(m) = &self.map {
            write!(
                f,
                "\nmap: {} points, coverage {:.1} % of the free space (radius {} m); per level:",
                m.points,
                100.0 * m.coverage,
                self.radius
            )?;
            for (l, x) in m.levels.iter().enumerate() {
                write!(f, " {l}: {:.1} %", 100.0 * x)?;
            }
            write!(
                f,
                "\nmap error: {} points ({:.2} %) farther than {} m from the surface",
                m.errors,
                100.0 * m.errors as f64 / m.points.max(1) as f64,
                self.tolerance
            )?;
        }
        if let Some(r) = &self.run {
            write!(f, "\n{}", run::summary(r))?;
        }
        write!(f, "\nwrote {}", self.out.display())
    }
}

/// Refuses reports far outside the world: another frame or unit.
fn check_reports(list: &[reports::Report], cells: &world::Cells, file: &Path) -> Result<(), Error> {
    let [x0, y0, x1, y1] = cells.extent();
    let margin = (2.0 * cells.pitch).max(20.0);
    let (z0, z1) = (
        -cells.level_height,
        cells.levels as f64 * cells.level_height,
    );
    for r in list {
        let [x, y, z] = r.position;
        if x < x0 - margin
            || x > x1 + margin
            || y < y0 - margin
            || y > y1 + margin
            || z < z0 - margin
            || z > z1 + margin
        {
            return Err(Error::Input(format!(
                "{}: row {}: ({x}, {y}, {z}) is more than {margin:.0} m outside the world (x {x0:.1} to {x1:.1}, y {y0:.1} to {y1:.1}, z {z0:.1} to {z1:.1} m): reports must be in the world frame in metres (x east, y north, z up, as ground_truth/artifacts.json)",
                file.display(),
                r.row
            )));
        }
    }
    Ok(())
}

impl ScoreRequest {
    /// Where the score folder goes: never over the world, the reports or the map.
    fn destination<'a>(&'a self, reading: &'a [&'a Path]) -> Out<'a> {
        Out {
            path: &self.out,
            kind: Kind::Score,
            force: self.force,
            reading,
        }
    }

    /// Scores the run and writes the score folder (`--out` checked before anything is read).
    pub fn run(&self) -> Result<Scored, Error> {
        for (what, v) in [("--radius", self.radius), ("--tolerance", self.tolerance)] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::Usage(format!(
                    "{what} must be a number of metres, 0 or more"
                )));
            }
        }
        let mut reading: Vec<&Path> = vec![&self.world, &self.reports];
        reading.extend(self.map.as_deref());
        reading.extend(self.run.as_deref());
        self.destination(&reading).check()?;
        let cells = world::cells(&self.world)?;
        let truth = world::artifacts(&self.world)?;
        if let Some(t) = truth.iter().find(|t| t.level >= cells.levels) {
            return Err(Error::Input(format!(
                "{}: ground_truth/artifacts.json puts artifact {} on level {}, but topology.json has {} level(s); were they edited? make the world again with `subtgraph generate`",
                self.world.display(),
                t.id,
                t.level,
                cells.levels
            )));
        }
        let list = reports::read(&self.reports)?;
        check_reports(&list, &cells, &self.reports)?;
        let run_files = self.run.as_deref().map(run::locate).transpose()?;
        let (list, without_link) = match &run_files {
            Some(files) => run::over_link(files, list)?,
            None => (list, 0),
        };
        let (verdicts, found) = reports::score(&list, &truth);
        let map = match &self.map {
            None => None,
            Some(path) => {
                let (grid, free) = world::free_space(&self.world)?;
                let points = cloud::read(path, Some(&grid))?;
                let margin = (2.0 * cells.pitch).max(20.0);
                coverage::check_bounds(&points, &grid, margin, &path.display().to_string())?;
                let c =
                    coverage::measure(&points, &grid, &free, &cells, self.radius, self.tolerance);
                Some((path.clone(), grid, c))
            }
        };
        let run_score = match &run_files {
            Some(files) => {
                // The explored share needs the free space; a world without it scores the rest.
                let free = world::free_space(&self.world).ok();
                Some(run::measure(
                    files,
                    without_link,
                    free.as_ref().map(|(g, f)| (g, f)),
                    &cells,
                )?)
            }
            None => None,
        };
        let count = |k: reports::Outcome| verdicts.iter().filter(|v| v.outcome == k).count();
        let errors: Vec<f64> = found
            .iter()
            .flatten()
            .filter_map(|&k| verdicts[k].distance_m)
            .collect();
        let scored = Scored {
            outcomes: Counts {
                scored: count(reports::Outcome::Scored),
                duplicate: count(reports::Outcome::Duplicate),
                wrong_class: count(reports::Outcome::WrongClass),
                false_reports: count(reports::Outcome::False),
            },
            artifacts_total: truth.len(),
            reports_total: list.len(),
            mean_error_m: (!errors.is_empty())
                .then(|| errors.iter().sum::<f64>() / errors.len() as f64),
            map: map.as_ref().map(|(_, _, c)| MapScore {
                points: c.points,
                coverage: c.total.share(),
                levels: c.levels.iter().map(|l| l.share()).collect(),
                errors: c.errors,
            }),
            radius: self.radius,
            tolerance: self.tolerance,
            out: self.out.clone(),
            run: run_score,
        };
        let mut files = report::files(
            self,
            &scored,
            &report::Inputs {
                cells: &cells,
                truth: &truth,
                verdicts: &verdicts,
                found: &found,
                map: map.as_ref().map(|(p, g, c)| (p.as_path(), g, c)),
            },
        );
        if let Some(r) = &scored.run {
            let text = serde_json::to_string_pretty(r).expect("plain data") + "\n";
            files.push(("run.json".into(), text.into_bytes()));
        }
        crate::folder::write_atomically(&self.destination(&reading), |w| {
            for (name, bytes) in &files {
                std::fs::write(w.root().join(name), bytes)
                    .map_err(Error::io(format!("writing {name}")))?;
            }
            Ok::<(), Error>(())
        })?;
        Ok(scored)
    }
}
