//! The steps of making a world folder, as `generate` and `dataset` both take them: the
//! pipeline (a file, a preset or given), its components built once with the registry of
//! built-ins and plugins (route, shapes, tile set, exporters: checked before anything is
//! generated, so a bad `[[export]]` costs nothing), the world made with them within the memory
//! budget, and the atomic folder.

use std::path::Path;

use subtgraph_core::config::Provenance;
use subtgraph_core::export::WorldWriter;
use subtgraph_core::params::ComponentSpec;
use subtgraph_core::{Budget, Components, Pipeline, Registry, World};

use crate::folder::{self, FolderError, Out};
use crate::{Error, Frontend, presets};

pub use subtgraph_core::components::NamedExporter;

pub use subtgraph_core::config::MAX_SEED;
use subtgraph_core::config::MAX_SEED_SPELLED;

/// Refuses a seed above [`MAX_SEED`], naming the option as `frontend` spells it (`--seed`,
/// `seed`): the one check of every seed a user gives.
pub fn check_seed(seed: u64, frontend: Frontend) -> Result<u64, Error> {
    if seed > MAX_SEED {
        return Err(Error::Usage(format!(
            "{} must be at most {MAX_SEED_SPELLED}",
            frontend.option("seed")
        )));
    }
    Ok(seed)
}

/// Adds the exporters named in a `--format` list (`mjcf,sdf,usd`) to the pipeline, each
/// once: a format the pipeline already exports is not added again. The pipeline then records
/// them, so its `world.toml` regenerates the same files.
pub fn add_formats(p: &mut Pipeline, formats: &[String]) -> Result<(), Error> {
    for name in formats.iter().flat_map(|f| f.split(',')).map(str::trim) {
        if name.is_empty() {
            return Err(Error::Usage(
                "--format takes format names separated by commas, like --format mjcf,sdf,usd"
                    .into(),
            ));
        }
        if !p.export.iter().any(|e| e.type_name == name) {
            p.export.push(ComponentSpec::named(name));
        }
    }
    Ok(())
}

/// Builds the pipeline's components, each once ([`Pipeline::build`]), and checks its
/// exporters: one that needs geometry in a pipeline without a `[tileset]` is an error saying
/// to add one, or, with `no_mesh` (the user asked for no geometry), left out: its name is
/// returned, for the front end to say so.
pub fn build(
    p: &Pipeline,
    registry: &Registry,
    no_mesh: bool,
) -> Result<(Components, Vec<String>), Error> {
    let mut components = p.build(registry)?;
    let mut skipped = Vec::new();
    let mut kept = Vec::new();
    for e in std::mem::take(&mut components.exporters) {
        if e.exporter.needs_geometry() && components.tileset.is_none() {
            if no_mesh {
                skipped.push(e.name);
                continue;
            }
            return Err(Error::NoTileset { exporter: e.name });
        }
        kept.push(e);
    }
    components.exporters = kept;
    Ok((components, skipped))
}

fn provenance(source: &str) -> Provenance {
    Provenance {
        tool: "subtgraph".into(),
        version: env!("CARGO_PKG_VERSION").into(),
        source: Some(source.to_owned()),
    }
}

/// The `world.toml` that [`generate`] with these arguments writes, computed without generating
/// (resolving a pipeline only draws its ranges).
pub fn expected_world_toml(p: &Pipeline, source: &str) -> Result<String, Error> {
    let (mut resolved, _) = p.resolve()?;
    resolved.generated = Some(provenance(source));
    Ok(subtgraph_exporters::world_toml_text(&resolved))
}

/// Refuses the run when a plugin failed while it ran.
pub fn check_plugins() -> Result<(), Error> {
    subtgraph_plugins::check_failures().map_err(|e| Error::PluginFailed(e.to_string()))
}

/// Generates a world with the pipeline's components (built by [`build`]) within a memory
/// budget. The pipeline records where it came from before generating (the provenance enters
/// the world with it, and is not patched in afterwards).
pub fn generate(
    p: &Pipeline,
    components: &Components,
    source: &str,
    budget: &Budget,
) -> Result<World, Error> {
    let mut p = p.clone();
    p.generated = Some(provenance(source));
    let world = subtgraph_core::generate_with(&p, components, budget)?;
    check_plugins()?;
    Ok(world)
}

/// Writes the world folder at `out`, atomically (see [`crate::folder`]). The mesh is written
/// as OBJ (`mesh/world.obj`, `collision.obj`) unless an exporter writes geometry: then only
/// what was asked is written (`obj` among the formats writes the OBJ). world.toml records the
/// exporters, so it makes the same files again.
pub fn write_folder(
    world: &World,
    exporters: &[NamedExporter],
    out: &Out<'_>,
) -> Result<(), FolderError> {
    write_folder_recording(world, exporters, out, None)
}

/// [`write_folder`], with `world_toml` written as `world.toml` instead of the world's own
/// pipeline: for a world made in memory and written with other exporters than it was made
/// with (Python's `World.export(formats=...)`), whose `world.toml` must name those.
pub fn write_folder_recording(
    world: &World,
    exporters: &[NamedExporter],
    out: &Out<'_>,
    world_toml: Option<&str>,
) -> Result<(), FolderError> {
    let default_obj = !exporters.iter().any(|e| e.exporter.needs_geometry());
    folder::write_atomically(out, |w| {
        let mut recording;
        let w: &mut dyn WorldWriter = match world_toml {
            Some(text) => {
                recording = WithWorldToml {
                    inner: w,
                    world_toml: text,
                };
                &mut recording
            }
            None => w,
        };
        // The world's survey, once for every exporter (and the artifacts placed by it).
        let survey = subtgraph_survey::WorldSurvey::new(world)?;
        subtgraph_exporters::write_world_files(world, &survey, w, default_obj)
            .map_err(Error::WorldFiles)?;
        for e in exporters {
            e.exporter
                .export(world, &survey, w)
                .map_err(|source| Error::Export {
                    exporter: e.name.clone(),
                    source,
                })?;
        }
        check_plugins()
    })
}

/// Writes into another writer, giving `world.toml` the text of a pipeline that records every
/// exporter written (so the folder's `world.toml` makes the same files again).
struct WithWorldToml<'a> {
    inner: &'a mut dyn WorldWriter,
    world_toml: &'a str,
}

impl WorldWriter for WithWorldToml<'_> {
    fn write(&mut self, path: &str, bytes: &[u8]) -> std::io::Result<()> {
        if path == "world.toml" {
            self.inner.write(path, self.world_toml.as_bytes())
        } else {
            self.inner.write(path, bytes)
        }
    }
    fn contains(&self, path: &str) -> bool {
        self.inner.contains(path)
    }
    fn stream(
        &mut self,
        path: &str,
        fill: &mut dyn FnMut(&mut dyn std::io::Write) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        if path == "world.toml" {
            self.inner.write(path, self.world_toml.as_bytes())
        } else {
            self.inner.stream(path, fill)
        }
    }
}

/// Where a pipeline comes from.
#[derive(Clone, Debug, Default)]
pub enum PipelineSource {
    /// A pipeline TOML file; paths in it are relative to its folder.
    File(std::path::PathBuf),
    /// A built-in preset by name.
    Preset(String),
    /// The built-in defaults: the cave preset.
    #[default]
    Defaults,
    /// A pipeline already parsed (the Python package's dict or TOML text), and how to name
    /// where it came from in `world.toml`.
    Given {
        /// The pipeline.
        pipeline: Box<Pipeline>,
        /// Where it came from (`a dict from Python`).
        description: String,
    },
}

impl PipelineSource {
    /// The pipeline and a description of where it came from (recorded in `world.toml`).
    pub fn load(&self) -> Result<(Pipeline, String), Error> {
        match self {
            PipelineSource::File(path) => {
                let text = String::from_utf8(crate::input::read(path).map_err(|e| match e {
                    Error::Io { source, .. } => Error::Io {
                        what: format!("reading pipeline file {}", path.display()),
                        source,
                    },
                    e => e,
                })?)
                .map_err(|_| {
                    Error::Input(format!(
                        "pipeline file {} is not UTF-8 text",
                        path.display()
                    ))
                })?;
                let mut p = Pipeline::parse(&text, &path.display().to_string())?;
                p.anchor_paths(path.parent().unwrap_or(Path::new(".")));
                Ok((p, path.display().to_string()))
            }
            PipelineSource::Preset(name) => Ok((preset(name)?, format!("preset {name}"))),
            PipelineSource::Defaults => Ok((
                preset("cave")?,
                "built-in defaults (the cave preset)".into(),
            )),
            PipelineSource::Given {
                pipeline,
                description,
            } => Ok(((**pipeline).clone(), description.clone())),
        }
    }

    /// The short name of a dataset source: a preset's name, a file's stem.
    pub fn name(&self) -> String {
        match self {
            PipelineSource::File(f) => f
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "world".into()),
            PipelineSource::Preset(n) => n.clone(),
            PipelineSource::Defaults => "cave".into(),
            PipelineSource::Given { .. } => "world".into(),
        }
    }

    /// The file the pipeline is read from, if any.
    pub fn file(&self) -> Option<&Path> {
        match self {
            PipelineSource::File(f) => Some(f),
            _ => None,
        }
    }
}

/// A preset's pipeline, its paths anchored at the examples folder it comes from.
fn preset(name: &str) -> Result<Pipeline, Error> {
    let mut p = presets::load(name).ok_or_else(|| Error::UnknownPreset {
        name: subtgraph_core::error::excerpt(name).into_owned(),
        known: presets::names(),
    })?;
    p.anchor_paths(&presets::examples_dir());
    Ok(p)
}

/// The command line's `--tileset`, `--no-mesh` and `--format`, applied to a pipeline.
#[derive(Clone, Debug, Default)]
pub struct Adjustments {
    /// Replaces the pipeline's `[tileset]`.
    pub tileset: Option<String>,
    /// No geometry: the tile set and the exporters that need it are left out.
    pub no_mesh: bool,
    /// Exporters to add, as `--format` lists them.
    pub formats: Vec<String>,
}

impl Adjustments {
    /// Applies `--tileset` and `--no-mesh` to `p`.
    pub fn apply_tileset(&self, p: &mut Pipeline) {
        if let Some(name) = &self.tileset {
            p.tileset = Some(ComponentSpec::named(name));
        }
        if self.no_mesh {
            p.tileset = None;
        }
    }

    /// Applies them all to `p`.
    pub fn apply(&self, p: &mut Pipeline) -> Result<(), Error> {
        self.apply_tileset(p);
        add_formats(p, &self.formats)
    }
}
