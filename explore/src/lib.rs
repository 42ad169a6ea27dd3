//! # subtgraph-explore
//!
//! Closed-loop autonomy without a simulator. Everything `subtgraph sense` does is open loop:
//! the route is fixed before the first scan. Here robots choose where to go, scan by scan: a
//! policy (a learned one through the Gymnasium environment, or the frontier baseline) sends
//! velocity commands, the body moves within its limits through the world's collision surface
//! ([`body`]), the LiDAR casts into the world's surface ([`lidar`]), the scans build a voxel map
//! ([`map`]), artifacts in view are detected ([`detect`]) and reported to a base station over a
//! radio after the SubT virtual competition's ([`radio`]), with breadcrumb repeaters
//! ([`mission`]).
//!
//! No physics engine runs: a wheeled robot in a tunnel at 2 m/s is a kinematic body as far as
//! exploration is concerned, and what matters (it cannot pass through rock, climb a wall, or
//! drive off a ledge) is decided exactly against the collision surface with the core's ray
//! caster, the same hierarchy every ray question about the world asks. That is what lets one
//! core step an environment thousands of times a second and a 30-minute, three-robot mission
//! finish in well under a minute.
//!
//! - [`site`]: what the loop takes from a world (its ray casters, start, artifacts).
//! - [`body`], [`lidar`], [`map`], [`detect`]: one robot's body, sensor, map and detector;
//!   [`robot`] steps them together.
//! - [`radio`]: links, hops to the base station, breadcrumbs.
//! - [`planner`]: the frontier baseline; [`mission`]: several robots, the radio, the loop.
//! - [`run`]: the run folder `subtgraph score --run` reads.
//! - [`env`](mod@env): one robot stepped by an outside policy (the Python package's Gymnasium
//!   environment).
//!
//! Every run is deterministic: the same world, options and seed give the same bytes on any
//! number of threads.

pub mod body;
pub mod detect;
pub mod env;
pub mod error;
pub mod lidar;
pub mod map;
pub mod mission;
pub mod planner;
pub mod radio;
pub mod robot;
pub mod run;
pub mod site;

pub use error::ExploreError;
pub use mission::{Mission, Options, Policy};
pub use site::Site;
