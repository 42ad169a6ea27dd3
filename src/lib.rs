//! # subtgraph
//!
//! Procedural subterranean worlds (operational mines, natural caves, lava tubes) with
//! controlled topology, for validating robot autonomy in simulation. This crate is the command
//! line and the facade: it re-exports the libraries, fills the registry with every built-in,
//! knows the presets, and writes world folders atomically.
//!
//! ```
//! let registry = subtgraph::registry();
//! let pipeline = subtgraph::presets::load("cave").unwrap();
//! let world = subtgraph::core::generate(&pipeline, &registry).unwrap();
//! assert_eq!(world.reachable_from_start(), world.occupancy.occupied_count());
//! ```

pub use subtgraph_core as core;
pub use subtgraph_descriptors as descriptors;
pub use subtgraph_exporters as exporters;
pub use subtgraph_survey as survey;
pub use subtgraph_tilesets as tilesets;

pub mod dataset;
pub mod folder;
pub mod make;
pub mod memory;
pub mod presets;
pub mod preview;
pub mod score;
pub mod stats;

use subtgraph_core::Registry;

/// A registry holding every built-in component.
pub fn registry() -> Registry {
    let mut r = Registry::with_core_shapes();
    subtgraph_descriptors::register(&mut r).expect("built-in names are distinct");
    subtgraph_tilesets::register(&mut r).expect("built-in names are distinct");
    subtgraph_exporters::register(&mut r).expect("built-in names are distinct");
    r
}
