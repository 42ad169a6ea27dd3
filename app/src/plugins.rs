//! The registry of components (route descriptors, constraint shapes, tile sets, exporters):
//! every built-in, plus plugin libraries; and `plugins list`, what a plugin library registers.

use std::path::PathBuf;

use subtgraph_core::{Pipeline, Registry};

use crate::Error;

/// A registry holding every built-in component.
pub fn registry() -> Registry {
    let mut r = Registry::with_core_shapes();
    subtgraph_descriptors::register(&mut r).expect("built-in names are distinct");
    subtgraph_tilesets::register(&mut r).expect("built-in names are distinct");
    subtgraph_exporters::register(&mut r).expect("built-in names are distinct");
    r
}

/// The registry with every built-in, the pipeline's plugins (`[plugins] paths`) and `extra`
/// (the command line's `--plugin`).
pub fn registry_with(p: &Pipeline, extra: &[PathBuf]) -> Result<Registry, Error> {
    let mut registry = registry();
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

/// One component of a registry: what `plugins list` and Python's `components()` show.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Listed {
    /// `route descriptor`, `constraint shape`, `tile set` or `exporter`.
    pub kind: String,
    /// Its `type` name.
    pub name: String,
    /// Who registered it (`built-in`, a plugin's path, `python`).
    pub origin: String,
    /// One line on what it is.
    pub summary: String,
}

/// Every component of `registry`, kind by kind, each kind in name order.
pub fn components(registry: &Registry) -> Vec<Listed> {
    fn rows<T: ?Sized>(c: &subtgraph_core::registry::Catalogue<T>, out: &mut Vec<Listed>) {
        for (name, e) in c.entries() {
            out.push(Listed {
                kind: c.kind().into(),
                name: name.into(),
                origin: e.origin.clone(),
                summary: e.summary.clone(),
            });
        }
    }
    let mut out = Vec::new();
    rows(&registry.route_descriptors, &mut out);
    rows(&registry.constraint_shapes, &mut out);
    rows(&registry.tilesets, &mut out);
    rows(&registry.exporters, &mut out);
    out
}

/// `plugins list [PATH...]`: the components each plugin library registers (with no path, the
/// built-ins).
#[derive(Clone, Debug, Default)]
pub struct PluginsRequest {
    /// Plugin libraries (`.so`, `.dylib`, `.dll`).
    pub paths: Vec<PathBuf>,
}

/// A plugin library and what it registers.
#[derive(Clone, Debug)]
pub struct PluginList {
    /// Its declared name.
    pub name: String,
    /// The file it was loaded from.
    pub path: String,
    /// `(kind, name, summary)` of each component it registers.
    pub components: Vec<(String, String, String)>,
}

/// What `plugins list` found.
#[derive(Clone, Debug)]
pub enum Plugins {
    /// No path given: the built-in components.
    BuiltIn(Vec<Listed>),
    /// Each library given, in order.
    Loaded(Vec<PluginList>),
}

impl PluginsRequest {
    /// Loads the libraries, each into a registry of the built-ins (so a name a plugin takes
    /// from a built-in is refused as in a run).
    pub fn run(&self) -> Result<Plugins, Error> {
        if self.paths.is_empty() {
            return Ok(Plugins::BuiltIn(components(&registry())));
        }
        let mut registry = registry();
        let mut out = Vec::new();
        for path in &self.paths {
            let plugin = subtgraph_plugins::load(path, &mut registry)?;
            out.push(PluginList {
                name: plugin.info.name.clone(),
                path: plugin.info.path.clone(),
                components: plugin
                    .components
                    .iter()
                    .map(|(k, n, s)| (k.to_string(), n.to_string(), s.to_string()))
                    .collect(),
            });
        }
        Ok(Plugins::Loaded(out))
    }
}
