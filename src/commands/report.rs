//! `subtgraph report`.

use std::path::PathBuf;

use subtgraph::app::{Error, ReportRequest};

/// `report`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    /// Runs as METHOD=FOLDER: FOLDER is a score folder written by `subtgraph score`, or a
    /// folder whose subfolders all are (one per world). Repeat for each method.
    #[arg(value_name = "METHOD=FOLDER")]
    runs: Vec<String>,
    /// A CSV naming the runs instead (or as well): header `world,method,score_folder`, paths
    /// relative to the CSV's folder; an empty world is taken from the score folder.
    #[arg(long = "runs", value_name = "CSV")]
    runs_csv: Option<PathBuf>,
    /// The report folder (created; an earlier report there is replaced with --force,
    /// anything else is refused).
    #[arg(long)]
    out: PathBuf,
    /// Replace a report folder `subtgraph report` wrote.
    #[arg(long)]
    force: bool,
    /// The bootstrap's seed: the same seed gives the same intervals.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Bootstrap resamples per interval.
    #[arg(long, default_value_t = subtgraph::app::report::sample::RESAMPLES)]
    resamples: usize,
}

/// Writes the report and prints its headline numbers.
pub fn run(a: Args) -> Result<(), Error> {
    let done = ReportRequest {
        runs: a.runs,
        runs_csv: a.runs_csv,
        out: a.out,
        force: a.force,
        seed: a.seed,
        resamples: a.resamples,
    }
    .run()?;
    super::print(&format!("{done}\n"));
    Ok(())
}
