//! Making a world folder, step by step, as `generate` and `dataset` both do it: the registry
//! with the pipeline's plugins, its components (route, shapes, tile set, exporters: built once
//! and checked before anything is generated, so a bad `[[export]]` costs nothing), the world
//! made with them, and the atomic folder.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, anyhow, bail};

use subtgraph_core::config::Provenance;
use subtgraph_core::params::ComponentSpec;
use subtgraph_core::{Budget, Components, Pipeline, Registry, World};

use crate::presets;

/// The registry with every built-in and the plugins of the pipeline and the command line.
pub fn registry_with(p: &Pipeline, extra: &[PathBuf]) -> Result<Registry> {
    let mut registry = crate::registry();
    let paths = p
        .plugins
        .paths
        .iter()
        .map(PathBuf::from)
        .chain(extra.iter().cloned());
    for path in paths {
        subtgraph_plugins::load(&path, &mut registry)?;
    }
    Ok(registry)
}

/// Adds the exporters named in a `--format` list (`mjcf,sdf,usd`) to the pipeline, each
/// once: a format the pipeline already exports is not added again. The pipeline then records
/// them, so its `world.toml` regenerates the same files.
pub fn add_formats(p: &mut Pipeline, formats: &[String]) -> Result<()> {
    for name in formats.iter().flat_map(|f| f.split(',')).map(str::trim) {
        if name.is_empty() {
            bail!("--format takes format names separated by commas, like --format mjcf,sdf,usd");
        }
        if !p.export.iter().any(|e| e.type_name == name) {
            p.export.push(ComponentSpec::named(name));
        }
    }
    Ok(())
}

pub use subtgraph_core::components::NamedExporter;

/// Builds the pipeline's components, each once ([`Pipeline::build`]), and checks its
/// exporters: one that needs geometry in a pipeline without a `[tileset]` is an error saying
/// to add one, or, with `no_mesh` (the user asked for no geometry), left out with a note on
/// standard error.
pub fn build(p: &Pipeline, registry: &Registry, no_mesh: bool) -> Result<Components> {
    let (components, skipped) = build_and_skipped(p, registry, no_mesh)?;
    note_skipped(&skipped);
    Ok(components)
}

/// [`build`], returning the names of the exporters left out under `no_mesh` instead of
/// noting them: `dataset` builds the components of every source and says each once.
pub fn build_and_skipped(
    p: &Pipeline,
    registry: &Registry,
    no_mesh: bool,
) -> Result<(Components, Vec<String>)> {
    let mut components = p.build(registry)?;
    let mut skipped = Vec::new();
    let mut kept = Vec::new();
    for e in std::mem::take(&mut components.exporters) {
        if e.exporter.needs_geometry() && components.tileset.is_none() {
            if no_mesh {
                skipped.push(e.name);
                continue;
            }
            bail!(
                "exporter '{}' writes geometry, but the pipeline has no [tileset]: add one (e.g. [tileset] type = \"cave\") or pass --tileset NAME",
                e.name
            );
        }
        kept.push(e);
    }
    components.exporters = kept;
    Ok((components, skipped))
}

/// Notes on standard error the exporters left out under `--no-mesh`, one line each.
pub fn note_skipped(names: &[String]) {
    for name in names {
        eprintln!(
            "note: skipping exporter '{name}': it writes geometry, and --no-mesh asked for none"
        );
    }
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
pub fn expected_world_toml(p: &Pipeline, source: &str) -> Result<String> {
    let (mut resolved, _) = p.resolve()?;
    resolved.generated = Some(provenance(source));
    Ok(subtgraph_exporters::world_toml_text(&resolved))
}

/// Generates a world with the pipeline's components (built by [`build`]) within a memory
/// budget. The pipeline records where it came from before generating (the provenance enters
/// the world with it, and is not patched in afterwards).
pub fn generate(
    p: &Pipeline,
    components: &Components,
    source: &str,
    budget: &Budget,
) -> Result<World> {
    let mut p = p.clone();
    p.generated = Some(provenance(source));
    let world = subtgraph_core::generate_with(&p, components, budget)?;
    subtgraph_plugins::check_failures().map_err(|e| anyhow!(e))?;
    Ok(world)
}

/// Writes the world folder (its own files, then every exporter's) at `out`, atomically, after
/// removing what killed runs left beside it.
pub fn write(world: &World, exporters: &[NamedExporter], out: &Path, force: bool) -> Result<()> {
    if let Some((parent, n)) = crate::folder::sweep_stale_beside(out) {
        eprintln!(
            "note: removed {n} unfinished folder(s) in {} left by runs that were killed",
            parent.display()
        );
    }
    write_folder(world, exporters, out, force)?;
    Ok(())
}

/// Writes the world folder at `out`, atomically (see [`crate::folder`]). The mesh is written
/// as OBJ (`mesh/world.obj`, `collision.obj`) unless an exporter writes geometry: then only
/// what was asked is written (`obj` among the formats writes the OBJ). world.toml records the
/// exporters, so it makes the same files again.
pub fn write_folder(
    world: &World,
    exporters: &[NamedExporter],
    out: &Path,
    force: bool,
) -> Result<(), crate::folder::FolderError> {
    let default_obj = !exporters.iter().any(|e| e.exporter.needs_geometry());
    crate::folder::write_atomically(out, force, |w| {
        // The world's survey, once for every exporter (and the artifacts placed by it).
        let survey = subtgraph_survey::WorldSurvey::new(world)?;
        subtgraph_exporters::write_world_files(world, &survey, w, default_obj)?;
        for e in exporters {
            e.exporter
                .export(world, &survey, w)
                .map_err(|err| anyhow!("exporter '{}': {err}", e.name))?;
        }
        subtgraph_plugins::check_failures().map_err(|e| anyhow!(e))?;
        Ok(())
    })
}

/// The pipeline to use and a description of where it came from.
pub fn load_pipeline(file: Option<&Path>, preset: Option<&str>) -> Result<(Pipeline, String)> {
    match (file, preset) {
        (Some(path), _) => {
            let text = std::fs::read_to_string(path)
                .with_context(|| format!("reading pipeline file {}", path.display()))?;
            let mut p = Pipeline::parse(&text, &path.display().to_string())?;
            p.anchor_paths(path.parent().unwrap_or(Path::new(".")));
            Ok((p, path.display().to_string()))
        }
        (None, preset) => {
            let name = preset.unwrap_or("cave");
            let mut p = presets::load(name).ok_or_else(|| {
                anyhow!(
                    "unknown preset '{name}'; the presets are: {}",
                    presets::names()
                )
            })?;
            p.anchor_paths(&Path::new(env!("CARGO_MANIFEST_DIR")).join("examples"));
            let source = match preset {
                Some(_) => format!("preset {name}"),
                None => "built-in defaults (the cave preset)".into(),
            };
            Ok((p, source))
        }
    }
}

/// How `dataset` turns each pipeline file or preset into a source: the command line's
/// `--tileset`, `--no-mesh`, `--format` and `--plugin`.
pub struct SourceOptions<'a> {
    /// Replaces the pipeline's `[tileset]`.
    pub tileset: Option<&'a str>,
    /// No geometry: the tile set and the exporters that need it are left out.
    pub no_mesh: bool,
    /// Exporters to add, as `--format` lists them.
    pub formats: &'a [String],
    /// Plugin libraries besides the pipeline's own.
    pub plugins: &'a [PathBuf],
}

/// A dataset source from a pipeline file or a preset (see [`load_pipeline`]), named by the
/// preset or the file's stem, with its registry (plus what `extend` adds: the Python
/// package's components) and components; and the exporters left out under `no_mesh`.
pub fn dataset_source(
    file: Option<&Path>,
    preset: Option<&str>,
    opts: &SourceOptions<'_>,
    extend: &mut dyn FnMut(&mut Registry) -> Result<()>,
) -> Result<(crate::dataset::Source, Vec<String>)> {
    let (mut p, description) = load_pipeline(file, preset)?;
    let name = match (file, preset) {
        (Some(f), _) => f
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "world".into()),
        (None, n) => n.unwrap_or("cave").to_owned(),
    };
    if let Some(t) = opts.tileset {
        p.tileset = Some(ComponentSpec::named(t));
    }
    if opts.no_mesh {
        p.tileset = None;
    }
    add_formats(&mut p, opts.formats)?;
    let mut registry = registry_with(&p, opts.plugins)?;
    extend(&mut registry)?;
    let (components, skipped) = build_and_skipped(&p, &registry, opts.no_mesh)?;
    let source = crate::dataset::Source {
        name,
        description,
        pipeline: p,
        components,
        registry,
    };
    Ok((source, skipped))
}

/// The error and its causes, each cause once: many errors already quote their cause in their
/// own message (`writing mesh/world.obj: File too large`), so a cause already said is skipped.
pub fn message(e: &anyhow::Error) -> String {
    let mut text = String::new();
    for cause in e.chain() {
        let part = cause.to_string();
        if text.is_empty() {
            text = part;
        } else if !text.contains(&part) {
            text.push_str(": ");
            text.push_str(&part);
        }
    }
    text
}
