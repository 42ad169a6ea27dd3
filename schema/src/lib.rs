//! # subtgraph-schema
//!
//! The JSON files of a world folder, one type each, defined once: the exporters build these
//! values and write them (`subtgraph-exporters`), and every reader (`score`, `stats`,
//! `preview`, the dataset index, the Python package) reads them back through the same types,
//! so a file's format cannot drift between its writer and its readers.
//!
//! | file | type |
//! |---|---|
//! | `topology.json` | [`Topology`] |
//! | `ground_truth/graph.json` | [`Graph`] |
//! | `ground_truth/artifacts.json` | [`Artifacts`] |
//! | `ground_truth/collision_budget.json` | [`CollisionBudget`] |
//! | `ground_truth/hazards.json` | [`Hazards`] |
//! | `ground_truth/semantic_labels.json` | [`SemanticLabels`] |
//! | `ground_truth/spawn_poses.json` | [`SpawnPoses`] |
//! | `ground_truth/free_space.json` | [`FreeSpace`] |
//! | `tasks/tasks.json` | [`Tasks`] |
//!
//! (`world.toml` is the core's [`subtgraph_core::Pipeline`], `occupancy.npy` and
//! `free_space.npy` are numpy arrays read by [`subtgraph_core::npy`].)
//!
//! Writing borrows: a document's lists are [`Cow`](std::borrow::Cow)s, so an exporter lends
//! the world's own nodes and edges and nothing is copied; reading owns (`Document<'static>`).
//!
//! A file read back is input like any other: it may have been edited, cut short or made by
//! something else. [`read`] parses it and checks its `format`; each document's `check` then
//! validates what its readers index by (ids in range, sizes that agree, finite numbers), so a
//! reader never panics or allocates on a number it has not checked.

use serde::de::DeserializeOwned;

mod artifacts;
mod collision_budget;
mod free_space;
mod graph;
mod hazards;
mod semantic_labels;
mod spawn_poses;
mod tasks;
mod topology;

pub use artifacts::{ArtifactEntry, Artifacts, GraphPlace, Hidden};
pub use collision_budget::{Classes, CollisionBudget, Distances};
pub use free_space::FreeSpace;
pub use graph::{Graph, GraphEdge, GraphNode};
pub use hazards::{HazardPatch, Hazards};
pub use semantic_labels::{SemanticLabels, TileLabel};
pub use spawn_poses::{Goal, Pose, Robot, SpawnPoses};
pub use tasks::{TaskLevel, Tasks};
pub use topology::{StructureCounts, Topology, structure_counts};

/// A document of a world folder: its path inside the folder and the `format` it carries.
pub trait Document: DeserializeOwned {
    /// Where the file is inside a world folder (`topology.json`).
    const PATH: &'static str;
    /// Its `format` value (`subtgraph-topology/1`): a reader refuses another.
    const FORMAT: &'static str;
    /// The `format` the file says it has.
    fn format(&self) -> &str;
    /// Checks what readers rely on (ids, sizes, finite numbers); the default checks nothing.
    fn check(&self) -> Result<(), SchemaError> {
        Ok(())
    }
}

/// What is wrong with a file read back from a world folder. Each message names the file and
/// says what to do: a world folder's files are written by `subtgraph generate`, so the fix is
/// almost always to make the world again.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SchemaError {
    /// The file is not the JSON its type describes (a missing key, a wrong type).
    #[error(
        "{file} is not a {format} file ({source}); was it edited? make the world again with `subtgraph generate`"
    )]
    Json {
        /// The file, inside the world folder.
        file: &'static str,
        /// The format expected.
        format: &'static str,
        /// serde's message, with the line and column.
        source: serde_json::Error,
    },
    /// The file says it has another format (or version).
    #[error(
        "{file} has format '{found}', not {format}: it was written by another program or version; make the world again with this version's `subtgraph generate`"
    )]
    Format {
        /// The file.
        file: &'static str,
        /// The format expected.
        format: &'static str,
        /// The format found (cut to a readable length).
        found: String,
    },
    /// A value is out of range or disagrees with another (an id past the end, a size of 0).
    #[error("{file}: {what}; was it edited? make the world again with `subtgraph generate`")]
    Invalid {
        /// The file.
        file: &'static str,
        /// What is wrong, naming the entry.
        what: String,
    },
}

impl SchemaError {
    /// An [`Invalid`](SchemaError::Invalid) error of `D`'s file.
    pub fn invalid<D: Document>(what: impl Into<String>) -> SchemaError {
        SchemaError::Invalid {
            file: D::PATH,
            what: what.into(),
        }
    }
}

/// Parses a document from a file's bytes, refusing another format, and checks it
/// ([`Document::check`]).
pub fn read<D: Document>(bytes: &[u8]) -> Result<D, SchemaError> {
    let doc: D = serde_json::from_slice(bytes).map_err(|source| SchemaError::Json {
        file: D::PATH,
        format: D::FORMAT,
        source,
    })?;
    if doc.format() != D::FORMAT {
        return Err(SchemaError::Format {
            file: D::PATH,
            format: D::FORMAT,
            found: subtgraph_core::error::excerpt(doc.format()).into_owned(),
        });
    }
    doc.check()?;
    Ok(doc)
}

/// Refuses a value that is not finite, naming it.
/// The `i`th node or edge (`what`) of a graph file carries the id `i`: ids count from 0 in
/// file order, which is how `graph.json` and `topology.json` both index their edges' ends.
pub(crate) fn id_in_order<D: Document>(what: &str, i: usize, id: usize) -> Result<(), SchemaError> {
    if id == i {
        Ok(())
    } else {
        Err(SchemaError::invalid::<D>(format!(
            "{what} {i} has id {id}: ids must count from 0"
        )))
    }
}

/// Edge `i` joins nodes `from` and `to`, both among the file's `nodes` nodes.
pub(crate) fn ends_exist<D: Document>(
    i: usize,
    [from, to]: [usize; 2],
    nodes: usize,
) -> Result<(), SchemaError> {
    if from < nodes && to < nodes {
        Ok(())
    } else {
        Err(SchemaError::invalid::<D>(format!(
            "edge {i} joins nodes {from} and {to}, but there are {nodes} nodes"
        )))
    }
}

pub(crate) fn finite<D: Document>(
    what: impl FnOnce() -> String,
    v: &[f64],
) -> Result<(), SchemaError> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(SchemaError::invalid::<D>(format!(
            "{} is not a finite number",
            what()
        )))
    }
}
