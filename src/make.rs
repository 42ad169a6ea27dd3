//! Making a world folder, step by step, as `generate` and `dataset` both do it: the registry
//! with the pipeline's plugins, the exporters (built and checked before anything is
//! generated, so a bad `[[export]]` costs nothing), the world, and the atomic folder.

use std::path::{Path, PathBuf};

use anyhow::{Result, anyhow, bail};

use subtgraph_core::config::Provenance;
use subtgraph_core::export::Exporter;
use subtgraph_core::params::ComponentSpec;
use subtgraph_core::{Budget, Pipeline, Registry, World};

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

/// An exporter ready to run, with its `type` name for messages.
pub struct NamedExporter {
    /// The `type` name.
    pub name: String,
    /// The exporter.
    pub exporter: Box<dyn Exporter>,
}

/// Builds the pipeline's exporters. One that needs geometry in a pipeline without a
/// `[tileset]` is an error saying to add one, or, with `no_mesh` (the user asked for no
/// geometry), left out with a note on standard error.
pub fn exporters(p: &Pipeline, registry: &Registry, no_mesh: bool) -> Result<Vec<NamedExporter>> {
    let mut out = Vec::new();
    for spec in &p.export {
        let exporter = registry.exporters.build(spec).map_err(|e| {
            let known = registry.exporters.names().join(", ");
            if e.message.contains("unknown exporter") {
                anyhow!("{e} (formats: {known})")
            } else {
                anyhow!(e)
            }
        })?;
        if exporter.needs_geometry() && p.tileset.is_none() {
            if no_mesh {
                eprintln!(
                    "note: skipping exporter '{}': it writes geometry, and --no-mesh asked for none",
                    spec.type_name
                );
                continue;
            }
            bail!(
                "exporter '{}' writes geometry, but the pipeline has no [tileset]: add one (e.g. [tileset] type = \"cave\") or pass --tileset NAME",
                spec.type_name
            );
        }
        out.push(NamedExporter {
            name: spec.type_name.clone(),
            exporter,
        });
    }
    Ok(out)
}

/// Generates a world within a memory budget and records where its pipeline came from.
pub fn generate(p: &Pipeline, registry: &Registry, source: &str, budget: &Budget) -> Result<World> {
    let mut world = subtgraph_core::generate_within(p, registry, budget)?;
    world.pipeline.generated = Some(Provenance {
        tool: "subtgraph".into(),
        version: env!("CARGO_PKG_VERSION").into(),
        source: Some(source.to_owned()),
    });
    subtgraph_plugins::check_failures().map_err(|e| anyhow!(e))?;
    Ok(world)
}

/// Writes the world folder (its own files, then every exporter's) at `out`, atomically.
pub fn write(world: &World, exporters: &[NamedExporter], out: &Path, force: bool) -> Result<()> {
    crate::folder::write_atomically(out, force, |w| {
        subtgraph_exporters::write_world_folder(world, w)?;
        for e in exporters {
            e.exporter
                .export(world, w)
                .map_err(|err| anyhow!("exporter '{}': {err}", e.name))?;
        }
        subtgraph_plugins::check_failures().map_err(|e| anyhow!(e))?;
        Ok(())
    })?;
    Ok(())
}
