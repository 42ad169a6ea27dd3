//! `subtgraph validate`.

use std::path::PathBuf;

use subtgraph::app::{Error, ValidateRequest};

/// `validate`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    /// The pipeline TOML file.
    pipeline: PathBuf,
    /// A plugin library to load (repeatable), besides the pipeline's `[plugins] paths`.
    #[arg(long = "plugin", value_name = "PATH")]
    plugins: Vec<PathBuf>,
}

/// Checks the pipeline and prints what its seed lays out.
pub fn run(a: Args) -> Result<(), Error> {
    let v = ValidateRequest {
        pipeline: a.pipeline.clone(),
        plugins: a.plugins,
    }
    .run()?;
    let w = &v.layout;
    super::print(&format!(
        "{}: valid; seed {} makes {} level(s) of {} x {} cells, {} occupied\n",
        a.pipeline.display(),
        w.resolved.seed,
        w.resolved.levels,
        w.resolved.rows,
        w.resolved.cols,
        w.occupancy.occupied_count()
    ));
    Ok(())
}
