//! # subtgraph-core
//!
//! The world model, the extension traits and the generation pipeline of subtgraph, a
//! procedural generator of subterranean worlds (mines, caves, lava tubes) with controlled
//! topology, after *SubTGraph* (the paper's Methodology).
//!
//! A world is an occupancy grid of `levels x rows x cols` cells. Structures
//! ([`shape::ConstraintShape`]: T-junctions, intersections, loops) are placed on each level,
//! their arms bent by a [`route::RouteDescriptor`] and laid by guided shortest paths, levels are
//! joined by shafts, and every occupied cell is classified into a [`tile::Tile`]. The result, a
//! [`layout::Layout`], also carries its topological [`graph::TopologyGraph`] and a report of the
//! requested against the achieved topology per level; it is made once and only read after.
//! A [`tileset::TileSet`] turns a layout into geometry ([`assembly`]), and a [`world::World`]
//! is a layout plus, optionally, that geometry. The survey (crate `subtgraph-survey`, through
//! [`survey::Survey`]) finds what exporters need in a finished world; exporters write it.
//!
//! Components are found by the `type` names of the pipeline file through one
//! [`registry::Registry`], which built-ins and dynamically loaded plugins fill alike.
//!
//! This crate does no file I/O: callers pass text and bytes in, and exporters write through a
//! [`export::WorldWriter`]. That keeps the core usable from tests, services and batch jobs, and
//! lets the command line make world folders atomic.

pub mod artifacts;
pub mod assembly;
pub mod budget;
pub mod components;
pub mod config;
pub mod direct_file;
pub mod error;
pub mod export;
pub mod generate;
pub mod graph;
pub mod grid;
pub mod hazards;
pub mod import;
pub mod layout;
pub mod mesh;
pub mod nesting;
pub mod npy;
pub mod params;
pub mod range;
pub mod raycast;
pub mod registry;
pub mod rng;
pub mod route;
pub mod shape;
pub mod shapes;
pub mod survey;
pub mod tile;
pub mod tileset;
pub mod topology;
pub mod vec3;
pub mod world;

pub use budget::Budget;
pub use components::Components;
pub use config::Pipeline;
pub use error::{ConfigError, Error};
pub use generate::{generate, generate_with, generate_within, layout, layout_with, layout_within};
pub use layout::Layout;
pub use registry::Registry;
pub use world::World;
