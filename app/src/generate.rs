//! `generate`: one world from a pipeline file, a preset or the defaults (or from an occupancy
//! grid, `--occupancy`), into memory (Python's `generate`) or into a world folder written
//! atomically (the command line).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use subtgraph_core::{Budget, Components, Layout, Pipeline, Registry, World, import, npy};

use crate::folder::{Kind, Out};
use crate::pipeline::{self, Adjustments, NamedExporter, PipelineSource};
use crate::{Error, Frontend, memory};

/// What `generate` is asked to make.
#[derive(Clone, Debug, Default)]
pub struct GenerateRequest {
    /// The pipeline.
    pub source: PipelineSource,
    /// Overrides the pipeline's `world.seed` (0 to 2^63 - 1).
    pub seed: Option<u64>,
    /// `--tileset`, `--no-mesh`, `--format`.
    pub adjust: Adjustments,
    /// Plugin libraries besides the pipeline's `[plugins] paths`.
    pub plugins: Vec<PathBuf>,
    /// Import this occupancy grid (`.npy`) instead of generating a layout.
    pub occupancy: Option<PathBuf>,
    /// `--max-memory` (default: 3/4 of physical memory).
    pub max_memory: Option<String>,
    /// Who asks (how options are named in messages).
    pub frontend: Frontend,
}

/// A request's pipeline, registry and components, built once, before anything is generated.
pub struct Prepared {
    /// The pipeline, adjusted and seeded as asked.
    pub pipeline: Pipeline,
    /// Where it came from, as `world.toml` records it.
    pub description: String,
    /// The memory budget.
    pub budget: Budget,
    /// The registry its components came from.
    pub registry: Registry,
    /// Its components.
    pub components: Components,
    /// Exporters left out because they write geometry and no mesh was asked for.
    pub skipped: Vec<String>,
}

/// A world made in memory.
pub struct Generated {
    /// The world.
    pub world: World,
    /// The pipeline's exporters, built before the world was made.
    pub exporters: Vec<NamedExporter>,
    /// Exporters left out because they write geometry and no mesh was asked for.
    pub skipped: Vec<String>,
    /// How an imported grid was read (`--occupancy`), if one was.
    pub imported: Option<(String, import::Encoding)>,
    /// Time to make the world (layout and mesh).
    pub took: Duration,
}

/// A world made and written.
pub struct Written {
    /// What was made.
    pub generated: Generated,
    /// Time to write the folder, every exporter included.
    pub took: Duration,
    /// Unfinished folders of killed runs removed beside the new one: where, and how many.
    pub swept: Option<(PathBuf, usize)>,
}

impl GenerateRequest {
    /// The pipeline as asked: loaded, with `--tileset`, `--no-mesh`, the seed and `--format`
    /// applied, and where it came from.
    pub fn pipeline(&self) -> Result<(Pipeline, String), Error> {
        let (mut p, description) = self.source.load()?;
        self.adjust.apply_tileset(&mut p);
        if let Some(seed) = self.seed {
            p.world.seed = pipeline::check_seed(seed, self.frontend)?;
        }
        pipeline::add_formats(&mut p, &self.adjust.formats)?;
        Ok((p, description))
    }

    /// The pipeline, the registry (built-ins, plugins, and what `extend` adds: the Python
    /// package's components) and the components, each built once.
    pub fn prepare(
        &self,
        extend: &mut dyn FnMut(&mut Registry) -> Result<(), Error>,
    ) -> Result<Prepared, Error> {
        let budget = self.check_arguments()?;
        let (pipeline, description) = self.pipeline()?;
        let mut registry = crate::registry_with(&pipeline, &self.plugins)?;
        extend(&mut registry)?;
        let (components, skipped) = pipeline::build(&pipeline, &registry, self.adjust.no_mesh)?;
        Ok(Prepared {
            pipeline,
            description,
            budget,
            registry,
            components,
            skipped,
        })
    }

    /// Makes the world of a prepared request: its layout generated (or the grid imported)
    /// and meshed, within the budget.
    pub fn make(&self, prepared: Prepared) -> Result<Generated, Error> {
        let started = Instant::now();
        let Prepared {
            pipeline: p,
            description,
            budget,
            components,
            skipped,
            ..
        } = prepared;
        let (world, imported) = match &self.occupancy {
            Some(path) => {
                let (layout, encoding) = import_world(path, &p, &budget)?;
                let mesh = match &components.tileset {
                    Some(t) => Some(
                        subtgraph_core::assembly::assemble_within(
                            &layout,
                            t.tileset.as_ref(),
                            &budget,
                        )
                        .map_err(|e| Error::TileSet {
                            name: t.name.clone(),
                            source: e.into(),
                        })?,
                    ),
                    None => None,
                };
                (World::new(layout, mesh), Some(encoding))
            }
            None => (
                pipeline::generate(&p, &components, &description, &budget)?,
                None,
            ),
        };
        let took = started.elapsed();
        pipeline::check_plugins()?;
        Ok(Generated {
            world,
            exporters: components.exporters,
            skipped,
            imported,
            took,
        })
    }

    /// Makes the world in memory.
    pub fn generate(&self) -> Result<Generated, Error> {
        self.make(self.prepare(&mut |_| Ok(()))?)
    }

    /// Everything this request reads: the pipeline file, the occupancy grid, the plugins.
    pub fn reading(&self) -> Vec<&Path> {
        let mut r: Vec<&Path> = self.source.file().into_iter().collect();
        r.extend(self.occupancy.as_deref());
        r.extend(self.plugins.iter().map(PathBuf::as_path));
        r
    }

    /// Checks the arguments' values (the memory size, the seed), which need nothing read.
    pub fn check_arguments(&self) -> Result<Budget, Error> {
        let budget = memory::budget(self.max_memory.as_deref())?;
        if let Some(seed) = self.seed {
            pipeline::check_seed(seed, self.frontend)?;
        }
        Ok(budget)
    }

    /// Makes the world and writes its folder at `out` (replacing a world folder there only
    /// with `force`), atomically. The arguments, then `--out`, are checked before anything is
    /// read or made.
    pub fn write(&self, out: &Path, force: bool) -> Result<Written, Error> {
        self.check_arguments()?;
        let reading = self.reading();
        let out = Out {
            path: out,
            kind: Kind::World,
            force,
            reading: &reading,
        };
        out.check()?;
        let generated = self.generate()?;
        let writing = Instant::now();
        let swept = crate::folder::sweep_stale_beside(out.path);
        pipeline::write_folder(&generated.world, &generated.exporters, &out)?;
        Ok(Written {
            generated,
            took: writing.elapsed(),
            swept,
        })
    }
}

/// Reads an occupancy grid into a layout, sized from its header against the budget before any
/// value is decoded.
fn import_world(
    path: &Path,
    p: &Pipeline,
    budget: &Budget,
) -> Result<(Layout, (String, import::Encoding)), Error> {
    use subtgraph_core::budget;
    let bytes = crate::input::read(path)?;
    let name = path.display().to_string();
    let npy_error = |source| Error::Npy {
        file: name.clone(),
        source,
    };
    // The values as f64, the codes, and the world's grids.
    let shape = npy::shape(&bytes).map_err(npy_error)?;
    let cells: usize = shape.iter().product();
    let (levels, per_level) = match shape[..] {
        [l, r, c] => (l, r * c),
        _ => (1, cells),
    };
    let needed = budget::layout_bytes(levels, 1, per_level)
        .saturating_add((cells as u64).saturating_mul(budget::BYTES_PER_IMPORTED_CELL))
        .saturating_add(bytes.len() as u64);
    budget
        .check(
            needed,
            &format!("importing {name} ({cells} cells, shape {shape:?})"),
            "import a smaller grid (crop or split it with numpy)",
        )
        .map_err(|e| Error::TooLarge(e.to_string()))?;
    let array = npy::decode(&bytes).map_err(npy_error)?;
    let (layout, encoding) = import::import_occupancy(&array, &name, p, env!("CARGO_PKG_VERSION"))?;
    Ok((layout, (name, encoding)))
}
