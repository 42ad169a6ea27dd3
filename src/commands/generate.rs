//! `subtgraph generate`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Duration;

use subtgraph::app::pipeline::{Adjustments, PipelineSource};
use subtgraph::app::{Error, GenerateRequest};
use subtgraph::core::World;

/// `generate`'s arguments.
#[derive(clap::Args)]
pub struct Args {
    /// A pipeline TOML file (see examples/). Without it and without --preset, the built-in
    /// defaults are used: the cave preset.
    pipeline: Option<PathBuf>,
    /// A built-in preset: mine, cave or lava-tube.
    #[arg(long, conflicts_with = "pipeline")]
    preset: Option<String>,
    /// Seed, overriding the pipeline's `world.seed` (0 to 2^63 - 1).
    #[arg(long)]
    seed: Option<u64>,
    /// The world folder to write.
    #[arg(long)]
    out: PathBuf,
    /// Replace --out if it is an existing world folder.
    #[arg(long)]
    force: bool,
    /// The tile set giving the world its geometry (mine, cave, lava-tube), overriding the
    /// pipeline's `[tileset]`.
    #[arg(long, value_name = "NAME")]
    tileset: Option<String>,
    /// Grids, graph and maps only: no geometry even if the pipeline has a `[tileset]`
    /// (exporters that write geometry are skipped, with a note).
    #[arg(long, conflicts_with = "tileset")]
    no_mesh: bool,
    /// Formats to export besides the pipeline's `[[export]]`s, separated by commas:
    /// obj, gltf, sdf, urdf, mjcf, usd, and the ground-truth files (see `plugins list`).
    #[arg(long, value_name = "LIST")]
    format: Vec<String>,
    /// A plugin library to load (repeatable), besides the pipeline's `[plugins] paths`.
    #[arg(long = "plugin", value_name = "PATH")]
    plugins: Vec<PathBuf>,
    /// Instead of generating, import an occupancy grid (.npy; the original's spatial,
    /// topological or structural encodings, or plain 0/1). The pipeline or preset still
    /// sets the scale (tile pitch, level height).
    #[arg(long, value_name = "FILE.npy")]
    occupancy: Option<PathBuf>,
    /// Memory the run may use, like 16G or 512M (default: 3/4 of physical memory). A world
    /// whose grid or meshes would need more is refused before it is made, with its estimate.
    #[arg(long, value_name = "SIZE")]
    max_memory: Option<String>,
}

/// Makes the world, writes its folder and prints what was made.
pub fn run(a: Args) -> Result<(), Error> {
    let request = GenerateRequest {
        source: match (a.pipeline, a.preset) {
            (Some(file), _) => PipelineSource::File(file),
            (None, Some(name)) => PipelineSource::Preset(name),
            (None, None) => PipelineSource::Defaults,
        },
        seed: a.seed,
        adjust: Adjustments {
            tileset: a.tileset,
            no_mesh: a.no_mesh,
            formats: a.format,
        },
        plugins: a.plugins,
        occupancy: a.occupancy,
        max_memory: a.max_memory,
        ..GenerateRequest::default()
    };
    let written = request.write(&a.out, a.force)?;
    let g = &written.generated;
    super::note_skipped(&g.skipped);
    if let Some((name, encoding)) = &g.imported {
        eprintln!("imported {name}: {encoding:?} encoding");
    }
    if let Some((parent, n)) = &written.swept {
        eprintln!(
            "note: removed {n} unfinished folder(s) in {} left by runs that were killed",
            parent.display()
        );
    }
    super::print(&summary(&g.world, &a.out, g.took));
    super::print(&files_written(&a.out, written.took));
    Ok(())
}

/// How many files and bytes the world folder holds and how long writing them (every exporter
/// included) took: what `scripts/bench-exports` reads.
fn files_written(out: &Path, took: Duration) -> String {
    let (mut files, mut bytes) = (0u64, 0u64);
    let mut stack = vec![out.to_owned()];
    while let Some(dir) = stack.pop() {
        for e in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            match e.metadata() {
                Ok(m) if m.is_dir() => stack.push(e.path()),
                Ok(m) => {
                    files += 1;
                    bytes += m.len();
                }
                Err(_) => {}
            }
        }
    }
    format!(
        "  wrote {files} files, {:.1} MB, in {:.1} ms\n",
        bytes as f64 / 1e6,
        took.as_secs_f64() * 1e3
    )
}

/// What was made: the grid, each level's structures, the mesh, unreachable cells.
fn summary(world: &World, out: &Path, took: Duration) -> String {
    let mut f = String::new();
    let r = &world.resolved;
    let _ = writeln!(
        f,
        "wrote {} (seed {}, {} level(s) of {} x {} cells, pitch {} m, made in {:.1} ms)",
        out.display(),
        r.seed,
        r.levels,
        r.rows,
        r.cols,
        r.tile_pitch,
        took.as_secs_f64() * 1e3
    );
    for l in &world.levels {
        let a = &l.achieved;
        let requested: Vec<String> = l
            .requested
            .iter()
            .map(|(k, v)| format!("{v} {k}"))
            .collect();
        let _ = writeln!(
            f,
            "  level {}: {} cells, {} T-junctions, {} intersections, {} loops, {} dead ends{}",
            l.level,
            l.cells,
            a.t_junctions,
            a.intersections,
            a.loops,
            a.dead_ends,
            if requested.is_empty() {
                String::new()
            } else {
                format!(" (asked: {})", requested.join(", "))
            }
        );
    }
    if let Some(m) = world.mesh() {
        let _ = writeln!(
            f,
            "  mesh: {} tiles, {} visual triangles, {} collision triangles",
            m.tiles.len(),
            m.visual.triangle_count(),
            m.collision.triangle_count()
        );
    }
    let reachable = world.reachable_from_start();
    let occupied = world.occupancy.occupied_count();
    if reachable != occupied {
        let _ = writeln!(
            f,
            "  note: {} of {occupied} cells are not reachable from the start",
            occupied - reachable
        );
    }
    f
}
