//! # subtgraph
//!
//! Procedural subterranean worlds (operational mines, natural caves, lava tubes) with
//! controlled topology, for validating robot autonomy in simulation. This crate is the command
//! line (`src/main.rs`: argument parsing and printing) and the facade: it re-exports the
//! libraries under one name.
//!
//! | module | crate | what |
//! |---|---|---|
//! | [`core`] | `subtgraph-core` | the model, the extension traits, the registry, the pipeline |
//! | [`descriptors`] | `subtgraph-descriptors` | route descriptors |
//! | [`tilesets`] | `subtgraph-tilesets` | tile sets |
//! | [`exporters`] | `subtgraph-exporters` | the world folder's files and simulator formats |
//! | [`schema`] | `subtgraph-schema` | one type per world-folder file, for writers and readers |
//! | [`app`] | `subtgraph-app` | the commands as typed requests (generate, dataset, score, ...) |
//!
//! ```
//! let registry = subtgraph::registry();
//! let pipeline = subtgraph::presets::load("cave").unwrap();
//! let world = subtgraph::core::generate(&pipeline, &registry).unwrap();
//! assert_eq!(world.reachable_from_start(), world.occupancy.occupied_count());
//! ```

pub use subtgraph_app as app;
pub use subtgraph_core as core;
pub use subtgraph_descriptors as descriptors;
pub use subtgraph_exporters as exporters;
pub use subtgraph_schema as schema;
pub use subtgraph_survey as survey;
pub use subtgraph_tilesets as tilesets;

pub use subtgraph_app::{folder, presets, registry};
