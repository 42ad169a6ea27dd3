//! The world of a world folder, made again for `sense` from its `world.toml`, with three
//! guarantees (issue 37, items 1, 13 and 18):
//!
//! - **A world folder never runs code.** A folder may come from anyone, and a plugin is a
//!   shared library whose code runs the moment it is loaded, before it could be refused. So
//!   the plugins its `world.toml` names are never loaded because it names them: only the
//!   libraries the user names (`sense --plugin PATH`, or a dataset's own pipelines and
//!   `--plugin`) are. A `world.toml` that names one the user did not is refused, saying which
//!   and how to allow it.
//! - **The folder is the world its files describe.** Its `.subtgraph-files` list records a
//!   digest of each file the world was written with ([`crate::folder::digest`]); a
//!   `world.toml` or ground truth changed since is refused before anything is made, as it
//!   would rebuild another world than the folder's meshes and graph.
//! - **An imported world comes back from its own grid.** `generate --occupancy` records the
//!   pipeline it scaled the grid with, and the grid is the folder's `occupancy.npy` (the same
//!   cells and shafts, in the spatial codes every world folder has): importing that again with
//!   the recorded pipeline makes the same world; the digests say the grid is the one written.

use std::path::{Path, PathBuf};

use subtgraph_core::{Pipeline, World};

use crate::Error;
use crate::generate::GenerateRequest;
use crate::pipeline::PipelineSource;

/// The world a world folder was made from, rebuilt with the built-ins and `plugins` (the
/// libraries the user named) only.
pub fn world_of(folder: &Path, plugins: &[PathBuf]) -> Result<World, Error> {
    let toml = folder.join("world.toml");
    let (mut p, _) = PipelineSource::File(toml.clone()).load()?;
    not_named_by_the_user(&toml, &p, plugins)?;
    unchanged(folder)?;
    p.export.clear();
    // Loaded from `plugins`, each once.
    p.plugins.paths.clear();
    let occupancy = imported(&p).then(|| folder.join("occupancy.npy"));
    let request = GenerateRequest {
        source: PipelineSource::Given {
            pipeline: Box::new(p),
            description: folder.display().to_string(),
        },
        plugins: plugins.to_vec(),
        occupancy,
        ..GenerateRequest::default()
    };
    Ok(request.generate()?.world)
}

/// Whether a pipeline records a world imported from an occupancy grid (`generate
/// --occupancy`), whose layout its pipeline alone does not make.
fn imported(p: &Pipeline) -> bool {
    p.generated
        .as_ref()
        .and_then(|g| g.source.as_deref())
        .is_some_and(|s| s.starts_with("import "))
}

/// Refuses a `world.toml` naming a plugin that is not among `plugins` (compared as files, so
/// `./lib.so` and its full path are one).
fn not_named_by_the_user(toml: &Path, p: &Pipeline, plugins: &[PathBuf]) -> Result<(), Error> {
    let same = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    };
    for named in &p.plugins.paths {
        let named = Path::new(named);
        if !plugins.iter().any(|mine| same(mine, named)) {
            return Err(Error::Usage(format!(
                "{} names the plugin {} ([plugins] paths); a world folder never loads code by itself, as it may come from anyone: if you trust that library, name it yourself with --plugin {}",
                toml.display(),
                named.display(),
                named.display()
            )));
        }
    }
    Ok(())
}

/// Whether a world folder's file is one the world is rebuilt or its route planned from:
/// `world.toml`, the imported grid and the ground truth. Meshes and scene files are not read
/// (the world is made again), so a folder whose meshes were removed to save room still senses.
fn read_by_rebuild(path: &str) -> bool {
    path == "world.toml"
        || path == "occupancy.npy"
        || path == "topology.json"
        || path.starts_with("ground_truth/")
}

/// Refuses a folder whose recorded files that the rebuild reads changed since the world was
/// written.
fn unchanged(folder: &Path) -> Result<(), Error> {
    let Some(changed) = crate::folder::digest::changed(folder, read_by_rebuild) else {
        // Written before digests: the graph's counts are still compared after the rebuild.
        return Ok(());
    };
    if changed.is_empty() {
        return Ok(());
    }
    let shown: Vec<&str> = changed.iter().take(4).map(String::as_str).collect();
    let more = match changed.len() {
        n if n > 4 => format!(" and {} more", n - 4),
        _ => String::new(),
    };
    Err(Error::Input(format!(
        "{}: {}{more} changed after the world was made (not the bytes its {} records): the world is made again from world.toml, and a changed world.toml or ground truth would not be the world of this folder's meshes and graph; make the world again with `subtgraph generate {} --out NEW` and sense NEW, or put the original files back",
        folder.display(),
        shown.join(", "),
        crate::folder::manifest::FILE,
        folder.join("world.toml").display()
    )))
}
