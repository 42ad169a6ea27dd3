//! Build, then run: the components a pipeline names (its route descriptor, one constraint
//! shape per structure name, its tile set and its exporters), each built exactly once by
//! [`Pipeline::build`] and then used by every run step ([`crate::generate::layout_with`],
//! [`crate::generate::generate_with`], the command line's exporters).
//!
//! Building is where a component's parameters are checked and where it does its expensive
//! setup: a mesh-files tile set reads every mesh file of its manifest when it is built. Building
//! once and handing the components to the steps that need them is what keeps a DARPA world
//! from reading its tiles twice, and a dataset from reading them once per world: the
//! components do not depend on the seed (a pipeline names the same structures whatever its
//! ranges draw), so one [`Components`] serves every world of a source.

use std::collections::BTreeMap;

use crate::config::Pipeline;
use crate::error::Error;
use crate::export::Exporter;
use crate::params::ComponentSpec;
use crate::registry::Registry;
use crate::route::RouteDescriptor;
use crate::shape::ConstraintShape;
use crate::tileset::TileSet;

/// An exporter ready to run, with its `type` name for messages.
pub struct NamedExporter {
    /// The `type` name.
    pub name: String,
    /// The exporter.
    pub exporter: Box<dyn Exporter>,
}

/// A pipeline's tile set, with its `type` name for messages.
pub struct NamedTileSet {
    /// The `type` name.
    pub name: String,
    /// The tile set.
    pub tileset: Box<dyn TileSet>,
}

/// Everything a pipeline names, built: what the run steps use instead of the registry.
pub struct Components {
    /// `[route]`.
    pub route: Box<dyn RouteDescriptor>,
    /// One shape per structure name the levels ask for (`[topology]` counts,
    /// `[[topology.structure]]`, `topology.per_level`).
    pub shapes: BTreeMap<String, Box<dyn ConstraintShape>>,
    /// `[tileset]`, when the pipeline makes geometry.
    pub tileset: Option<NamedTileSet>,
    /// `[[export]]`, in the pipeline's order.
    pub exporters: Vec<NamedExporter>,
}

impl Pipeline {
    /// Builds every component this pipeline names from `registry`, each once: the exporters
    /// first (a bad `[[export]]` is reported before anything costly is built), then the route
    /// descriptor, the tile set and the constraint shapes. An unknown name is an
    /// [`Error::Config`] at its `type` key listing the known ones.
    pub fn build(&self, registry: &Registry) -> Result<Components, Error> {
        let mut exporters = Vec::new();
        for spec in &self.export {
            let exporter = match registry.exporters.get(&spec.type_name) {
                Ok(entry) => (entry.factory)(&spec.params)?,
                Err(unknown) => {
                    return Err(Error::Config(spec.params.error(
                        "type",
                        format!("{unknown} (formats: {})", unknown.known.join(", ")),
                    )));
                }
            };
            exporters.push(NamedExporter {
                name: spec.type_name.clone(),
                exporter,
            });
        }
        let (_, resolved) = self.resolve()?;
        let route = registry.route_descriptors.build(&self.route)?;
        let tileset = match &self.tileset {
            Some(t) => Some(NamedTileSet {
                name: t.type_name.clone(),
                tileset: registry.tilesets.build(t)?,
            }),
            None => None,
        };
        // One shape object per structure name. The names come from the file (the built-in
        // counts, `[[topology.structure]]`, `topology.per_level`), not from the draws, so the
        // seed does not change this set.
        let mut shapes: BTreeMap<String, Box<dyn ConstraintShape>> = BTreeMap::new();
        for level in &resolved.per_level {
            for (name, _) in level {
                if shapes.contains_key(name) {
                    continue;
                }
                let spec = self
                    .topology
                    .structures
                    .iter()
                    .find(|s| &s.type_name == name)
                    .map(|s| {
                        let mut s = s.clone();
                        s.params.take("count");
                        s
                    })
                    .unwrap_or_else(|| ComponentSpec::named(name));
                shapes.insert(name.clone(), registry.constraint_shapes.build(&spec)?);
            }
        }
        Ok(Components {
            route,
            shapes,
            tileset,
            exporters,
        })
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;
    use std::sync::atomic::{AtomicUsize, Ordering::SeqCst};

    use super::*;
    use crate::budget::Budget;
    use crate::export::{ExportError, WorldWriter};
    use crate::route::Segment;
    use crate::world::World;

    struct Flat;
    impl RouteDescriptor for Flat {
        fn offset(&self, _t: f64, _s: &Segment) -> f64 {
            0.0
        }
    }

    struct Nothing;
    impl Exporter for Nothing {
        fn export(
            &self,
            _w: &World,
            _s: &dyn crate::survey::Survey,
            _o: &mut dyn WorldWriter,
        ) -> Result<(), ExportError> {
            Ok(())
        }
    }

    #[test]
    fn every_component_is_built_once_and_the_run_steps_build_none() {
        let built = Arc::new(AtomicUsize::new(0));
        let mut r = Registry::with_core_shapes();
        let b = built.clone();
        r.route_descriptors
            .add("flat", "test", move |_| {
                b.fetch_add(1, SeqCst);
                Ok(Box::new(Flat))
            })
            .unwrap();
        let b = built.clone();
        r.exporters
            .add("nothing", "test", move |_| {
                b.fetch_add(1, SeqCst);
                Ok(Box::new(Nothing))
            })
            .unwrap();
        let p = Pipeline::parse(
            "[route]\ntype = \"flat\"\n[[export]]\ntype = \"nothing\"\n",
            "t.toml",
        )
        .unwrap();
        let c = p.build(&r).unwrap();
        assert_eq!(
            built.load(SeqCst),
            2,
            "the route and the exporter, once each"
        );
        assert_eq!(c.exporters.len(), 1);
        assert_eq!(c.exporters[0].name, "nothing");
        assert!(c.tileset.is_none());
        let (_, resolved) = p.resolve().unwrap();
        let names: Vec<&String> = resolved.per_level[0].iter().map(|(n, _)| n).collect();
        assert_eq!(c.shapes.keys().collect::<Vec<_>>(), names);

        // The run steps use the components: several worlds (other seeds too), nothing rebuilt.
        let world = crate::generate::generate_with(&p, &c, &Budget::unlimited()).unwrap();
        let mut other = p.clone();
        other.world.seed += 1;
        crate::generate::layout_with(&other, &c, &Budget::unlimited()).unwrap();
        assert_eq!(built.load(SeqCst), 2);
        // And make the same world as the one-call `generate`, which builds its own.
        let again = crate::generate::generate(&p, &r).unwrap();
        assert_eq!(built.load(SeqCst), 4);
        assert_eq!(world.tiles, again.tiles);
    }
}
