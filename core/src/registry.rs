//! One registry for every component, looked up by the `type` name used in the pipeline file.
//!
//! Built-ins and plugins register the same way: a name, where it comes from, a one-line
//! summary, and a factory that builds the component from its TOML table. The registry is plain
//! data owned by the host, not a compile-time inventory, so components from a shared library
//! loaded at run time are found exactly like built-in ones.

use std::collections::BTreeMap;
use std::fmt;
use std::sync::Arc;

use crate::error::ConfigError;
use crate::export::Exporter;
use crate::params::{ComponentSpec, Params};
use crate::route::RouteDescriptor;
use crate::shape::ConstraintShape;
use crate::tileset::TileSet;

/// Builds a component from its parameters.
pub type Factory<T> = Arc<dyn Fn(&Params) -> Result<Box<T>, ConfigError> + Send + Sync>;

/// A registered component.
pub struct Entry<T: ?Sized> {
    /// Where it comes from: `built-in` or a plugin's path.
    pub origin: String,
    /// One line saying what it is.
    pub summary: String,
    /// Builds it.
    pub factory: Factory<T>,
}

/// The components of one kind, by name.
pub struct Catalogue<T: ?Sized> {
    kind: &'static str,
    entries: BTreeMap<String, Entry<T>>,
}

/// A second registration under a taken name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "{kind} '{name}' from {origin} is already registered by {existing}; rename one of them \
     (two components cannot share a `type` name)"
)]
pub struct DuplicateName {
    /// Component kind.
    pub kind: &'static str,
    /// The name.
    pub name: String,
    /// Who tried to register it.
    pub origin: String,
    /// Who has it.
    pub existing: String,
}

impl<T: ?Sized> Catalogue<T> {
    fn new(kind: &'static str) -> Self {
        Self {
            kind,
            entries: BTreeMap::new(),
        }
    }

    /// What kind of component this catalogue holds, for messages.
    pub fn kind(&self) -> &'static str {
        self.kind
    }

    /// Adds a component. A taken name is an error, never a silent override.
    pub fn register(
        &mut self,
        name: &str,
        origin: &str,
        summary: &str,
        factory: Factory<T>,
    ) -> Result<(), DuplicateName> {
        if let Some(e) = self.entries.get(name) {
            return Err(DuplicateName {
                kind: self.kind,
                name: name.to_owned(),
                origin: origin.to_owned(),
                existing: e.origin.clone(),
            });
        }
        self.entries.insert(
            name.to_owned(),
            Entry {
                origin: origin.to_owned(),
                summary: summary.to_owned(),
                factory,
            },
        );
        Ok(())
    }

    /// Adds a built-in component (origin `built-in`): how the workspace's own crates register
    /// theirs, without wrapping each factory by hand. A taken name is an error.
    pub fn add(
        &mut self,
        name: &str,
        summary: &str,
        factory: impl Fn(&Params) -> Result<Box<T>, ConfigError> + Send + Sync + 'static,
    ) -> Result<(), DuplicateName> {
        self.register(name, "built-in", summary, Arc::new(factory))
    }

    /// The registered names, sorted.
    pub fn names(&self) -> Vec<&str> {
        self.entries.keys().map(String::as_str).collect()
    }

    /// All entries, sorted by name.
    pub fn entries(&self) -> impl Iterator<Item = (&str, &Entry<T>)> {
        self.entries.iter().map(|(k, v)| (k.as_str(), v))
    }

    /// Whether a name is registered.
    pub fn contains(&self, name: &str) -> bool {
        self.entries.contains_key(name)
    }

    /// The entry registered under `name`, or an [`UnknownName`] listing the known ones.
    pub fn get(&self, name: &str) -> Result<&Entry<T>, UnknownName> {
        self.entries.get(name).ok_or_else(|| UnknownName {
            kind: self.kind,
            name: name.to_owned(),
            known: self.entries.keys().cloned().collect(),
        })
    }

    /// Builds the component a spec names. An unknown name lists the known ones.
    pub fn build(&self, spec: &ComponentSpec) -> Result<Box<T>, ConfigError> {
        match self.get(&spec.type_name) {
            Ok(e) => (e.factory)(&spec.params),
            Err(unknown) => Err(unknown.at(&spec.params)),
        }
    }
}

/// A `type` name no component of its kind is registered under.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error(
    "unknown {kind} '{name}' ({}); check the spelling, or load the plugin that provides it",
    known_list(.known)
)]
pub struct UnknownName {
    /// Component kind.
    pub kind: &'static str,
    /// The name asked for.
    pub name: String,
    /// The registered names, sorted.
    pub known: Vec<String>,
}

fn known_list(known: &[String]) -> String {
    if known.is_empty() {
        "none are registered yet".to_owned()
    } else {
        format!("known: {}", known.join(", "))
    }
}

impl UnknownName {
    /// The error at the `type` key of the table that named it.
    pub fn at(&self, params: &Params) -> ConfigError {
        params.error("type", self.to_string())
    }
}

impl<T: ?Sized> Catalogue<T> {
    /// The first name `other` has that `self` has too.
    fn clash(&self, other: &Catalogue<T>) -> Option<DuplicateName> {
        other.entries.iter().find_map(|(name, e)| {
            self.entries.get(name).map(|existing| DuplicateName {
                kind: self.kind,
                name: name.clone(),
                origin: e.origin.clone(),
                existing: existing.origin.clone(),
            })
        })
    }
}

impl<T: ?Sized> fmt::Debug for Catalogue<T> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Catalogue")
            .field("kind", &self.kind)
            .field("names", &self.names())
            .finish()
    }
}

/// Every component the pipeline can name.
#[derive(Debug)]
pub struct Registry {
    /// `[route] type = ...`
    pub route_descriptors: Catalogue<dyn RouteDescriptor>,
    /// `[topology]` counts and `[[topology.structure]] type = ...`
    pub constraint_shapes: Catalogue<dyn ConstraintShape>,
    /// `[tileset] type = ...`
    pub tilesets: Catalogue<dyn TileSet>,
    /// `[[export]] type = ...`
    pub exporters: Catalogue<dyn Exporter>,
}

impl Default for Registry {
    fn default() -> Self {
        Self::empty()
    }
}

impl Registry {
    /// A registry with nothing in it.
    pub fn empty() -> Self {
        Self {
            route_descriptors: Catalogue::new("route descriptor"),
            constraint_shapes: Catalogue::new("constraint shape"),
            tilesets: Catalogue::new("tile set"),
            exporters: Catalogue::new("exporter"),
        }
    }

    /// Moves every component of `other` into this registry, or none if any name is taken.
    pub fn merge(&mut self, other: Registry) -> Result<(), DuplicateName> {
        if let Some(d) = self
            .route_descriptors
            .clash(&other.route_descriptors)
            .or_else(|| self.constraint_shapes.clash(&other.constraint_shapes))
            .or_else(|| self.tilesets.clash(&other.tilesets))
            .or_else(|| self.exporters.clash(&other.exporters))
        {
            return Err(d);
        }
        self.route_descriptors
            .entries
            .extend(other.route_descriptors.entries);
        self.constraint_shapes
            .entries
            .extend(other.constraint_shapes.entries);
        self.tilesets.entries.extend(other.tilesets.entries);
        self.exporters.entries.extend(other.exporters.entries);
        Ok(())
    }

    /// A registry with the core's built-in constraint shapes (loop, T-junction,
    /// intersection, room-and-pillar). Route descriptors, tile sets and exporters come from their crates.
    pub fn with_core_shapes() -> Self {
        use crate::shapes::{Intersection, Loop, RoomAndPillar, TJunction};
        let mut r = Self::empty();
        let shapes: [(&str, &str, Factory<dyn ConstraintShape>); 4] = [
            (
                "loop",
                "a ring of eight cells around an empty centre, with an arm from each corner",
                Arc::new(|p: &Params| {
                    p.expect_none()?;
                    Ok(Box::new(Loop) as Box<dyn ConstraintShape>)
                }),
            ),
            (
                "t-junction",
                "a centre with three arms, in any of four rotations",
                Arc::new(|p: &Params| {
                    p.expect_none()?;
                    Ok(Box::new(TJunction) as Box<dyn ConstraintShape>)
                }),
            ),
            (
                "intersection",
                "a centre with four arms",
                Arc::new(|p: &Params| {
                    p.expect_none()?;
                    Ok(Box::new(Intersection) as Box<dyn ConstraintShape>)
                }),
            ),
            (
                "room-and-pillar",
                "a mine panel: drifts and crosscuts crossing round a grid of pillars (pillars = [rows, cols])",
                Arc::new(|p: &Params| {
                    Ok(Box::new(RoomAndPillar::from_params(p)?) as Box<dyn ConstraintShape>)
                }),
            ),
        ];
        for (name, summary, f) in shapes {
            r.constraint_shapes
                .register(name, "built-in", summary, f)
                .expect("built-in names are distinct");
        }
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unknown_names_list_the_known_ones() {
        let r = Registry::with_core_shapes();
        let err = match r.constraint_shapes.build(&ComponentSpec::named("y-fork")) {
            Err(e) => e,
            Ok(_) => panic!("y-fork is not built in"),
        };
        assert!(
            err.message
                .contains("known: intersection, loop, room-and-pillar, t-junction"),
            "{err}"
        );
    }

    #[test]
    fn a_taken_name_is_refused() {
        let mut r = Registry::with_core_shapes();
        let e = r
            .constraint_shapes
            .register(
                "loop",
                "libmine.so",
                "",
                Arc::new(
                    |_: &Params| Ok(Box::new(crate::shapes::Loop) as Box<dyn ConstraintShape>),
                ),
            )
            .unwrap_err();
        assert_eq!(e.existing, "built-in");
        assert!(e.to_string().contains("rename one"));
    }
}
