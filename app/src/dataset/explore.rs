//! `dataset --explore`: the baseline (or another `--planner`) run in every world of the run's
//! share, each run written to `runs/NAME/` and scored into `scores/NAME/` inside the dataset
//! folder once the worlds are made, so that `subtgraph report frontier=OUT/scores` compares
//! it over the dataset with any other method.
//!
//! Why after the worlds and one world at a time: a mission steps its robots in parallel already,
//! and holds the world's ray casters and the robots' maps, so missions side by side would
//! multiply the memory without making the run faster. Like `--sense`, each folder is written
//! atomically, a complete run (and score) is kept when the same command runs again, a damaged
//! one of ours is made again, and anything else in its place is refused.

use std::path::{Path, PathBuf};

use crate::explore::ExploreRequest;
use crate::folder::manifest::{self, Kind, Manifest};
use crate::{Error, ScoreRequest};

/// The folder of the runs, inside the dataset folder.
pub const RUNS_DIR: &str = "runs";
/// The folder of the runs' scores, inside the dataset folder.
pub const SCORES_DIR: &str = "scores";

/// What the exploring of a dataset did.
#[derive(Debug, Default, Clone, PartialEq)]
pub struct Explored {
    /// Runs written by this run.
    pub made: usize,
    /// Complete runs found and kept.
    pub kept: usize,
    /// Simulated seconds of the runs made.
    pub simulated_s: f64,
    /// Wall seconds of the missions made.
    pub run_s: f64,
}

/// Checks `template`'s names and numbers before any world is made.
pub fn check(template: &ExploreRequest) -> Result<(), Error> {
    template.options(0)?;
    Ok(())
}

/// Whether `dir` holds a complete folder of `kind` (kept), needs making again (`Some(true)`:
/// ours but damaged), or is free or someone else's (`Some(false)`: the request refuses the
/// latter itself).
fn state(dir: &Path, kind: Kind) -> Option<bool> {
    match manifest::read(dir) {
        Some(Manifest::Complete(Some(k), files)) if k == kind => {
            let damage = manifest::damage(dir, &files);
            if damage.is_empty() {
                return None;
            }
            eprintln!(
                "note: {} is incomplete ({}); making it again",
                dir.display(),
                damage.join(", ")
            );
            Some(true)
        }
        _ => Some(false),
    }
}

/// Runs and scores `template` in each world `names` lists that is complete in the dataset
/// folder `out` (its `world`, `out` and `force` are set here).
pub fn explore_worlds(
    out: &Path,
    names: &[String],
    template: &ExploreRequest,
    progress: &dyn Fn(&str, f64, f64),
) -> Result<Explored, Error> {
    let (runs, scores) = (out.join(RUNS_DIR), out.join(SCORES_DIR));
    for dir in [&runs, &scores] {
        std::fs::create_dir_all(dir).map_err(Error::io(format!("creating {}", dir.display())))?;
    }
    let mut done = Explored::default();
    for name in names {
        let world = out.join(name);
        if !world.join("world.toml").is_file() {
            continue;
        }
        let run = runs.join(name);
        let wrap = |source| Error::Exploring {
            world: name.clone(),
            source: Box::new(source),
        };
        if let Some(force) = state(&run, Kind::Explore) {
            let request = ExploreRequest {
                world: world.clone(),
                out: run.clone(),
                force,
                ..template.clone()
            };
            let explored = request.run(&|t, of| progress(name, t, of)).map_err(wrap)?;
            done.made += 1;
            done.simulated_s += explored.simulated_s;
            done.run_s += explored.run_s;
        } else {
            done.kept += 1;
        }
        let score = scores.join(name);
        if let Some(force) = state(&score, Kind::Score) {
            score_run(&world, &run, score, force).map_err(wrap)?;
        }
    }
    Ok(done)
}

/// Scores a run folder as `subtgraph score WORLD --run RUN --out SCORE` does.
pub fn score_run(world: &Path, run: &Path, out: PathBuf, force: bool) -> Result<(), Error> {
    let files = crate::score::run::locate(run)?;
    ScoreRequest {
        world: world.to_owned(),
        reports: files.reports,
        map: files.map,
        radius: 1.0,
        tolerance: 0.5,
        out,
        force,
        run: Some(run.to_owned()),
    }
    .run()?;
    Ok(())
}
