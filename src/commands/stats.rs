//! `subtgraph stats`.

use std::path::PathBuf;

use subtgraph::app::{Error, StatsRequest};

/// `stats`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    /// World folders, dataset folders (holding world folders), or folders of the original
    /// tool's .npy grids. Each argument is one group in the report.
    #[arg(required = true)]
    inputs: Vec<PathBuf>,
    /// The report folder (created; an earlier stats report there is replaced, anything else
    /// is refused).
    #[arg(long)]
    out: PathBuf,
    /// How pairwise IoU treats grids of different sizes: `common` crops both to the rows
    /// and columns they share (the top-left corner), `pad` pads the smaller with empty
    /// cells (the union counts everything).
    #[arg(long, default_value = "common", value_name = "common|pad")]
    crop: String,
}

/// Writes the report and prints its headline numbers.
pub fn run(a: Args) -> Result<(), Error> {
    let report = StatsRequest {
        inputs: a.inputs,
        out: a.out,
        crop: a.crop.parse()?,
    }
    .run()?;
    super::print(&format!("{}\n", report.summary));
    Ok(())
}
