//! # subtgraph-app
//!
//! The commands of subtgraph, as typed requests with typed results and one error type
//! ([`Error`]): what the command line (`src/main.rs`, argument parsing and printing only) and
//! the Python package (`python/src`) both call, so a command behaves and fails the same from
//! either front end.
//!
//! | request | command | result |
//! |---|---|---|
//! | [`GenerateRequest`] | `generate` | a world, written atomically into a world folder |
//! | [`DatasetRequest`] | `dataset` | many worlds per source, in parallel, resumable, sharded |
//! | [`ValidateRequest`] | `validate` | the layout of a pipeline, checked by its tile set, no mesh |
//! | [`ScoreRequest`] | `score` | a robot's reports and map graded against a world's ground truth |
//! | [`StatsRequest`] | `stats` | the variability statistics of worlds, with plots |
//! | [`PreviewRequest`] | `preview` | a shaded picture of a world's mesh |
//! | [`PluginsRequest`] | `plugins list` | what plugin libraries register |
//! | [`SenseRequest`] | `sense` | a sensor sequence (LiDAR, IMU, poses) along a route through a world, by [`sense::run`] |
//! | [`ExploreRequest`] | `explore` | robots exploring a world in a closed loop, a run folder `score --run` grades |
//!
//! Every folder a request writes is written atomically and records which command wrote it
//! ([`folder`]); `--force` replaces only a folder the same command wrote, never one being read,
//! and `--out` is checked before any work ([`folder::out`]).
//!
//! ```no_run
//! use subtgraph_app::{GenerateRequest, PipelineSource};
//! let request = GenerateRequest {
//!     source: PipelineSource::Preset("cave".into()),
//!     seed: Some(7),
//!     ..GenerateRequest::default()
//! };
//! let written = request.write("worlds/cave-7".as_ref(), false).unwrap();
//! println!("{} cells", written.generated.world.occupancy.occupied_count());
//! ```

pub mod dataset;
mod error;
pub mod explore;
pub mod folder;
pub mod frontend;
pub mod generate;
pub mod input;
pub mod memory;
pub mod pipeline;
pub mod plugins;
pub mod presets;
pub mod preview;
pub mod rebuild;
pub mod report;
pub mod score;
pub mod sense;
pub mod sense_options;
pub mod stats;
pub mod validate;

pub use dataset::DatasetRequest;
pub use error::{Error, message};
pub use explore::ExploreRequest;
pub use frontend::Frontend;
pub use generate::{GenerateRequest, Generated};
pub use pipeline::PipelineSource;
pub use plugins::{PluginsRequest, registry, registry_with};
pub use preview::PreviewRequest;
pub use report::ReportRequest;
pub use score::ScoreRequest;
pub use score::segmentation::SegmentationRequest;
pub use score::trajectory::{Align, Associate, TrajectoryRequest};
pub use sense::{CameraRequest, SenseRequest};
pub use stats::StatsRequest;
pub use validate::ValidateRequest;
