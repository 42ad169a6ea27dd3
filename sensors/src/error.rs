//! What can go wrong making a sequence, each variant saying what to change.

use std::path::PathBuf;

/// An error of the application hosting the sensors ([`crate::Host`]), kept with its type so
/// that the application can tell its own errors apart when they come back.
pub type HostError = Box<dyn std::error::Error + Send + Sync + 'static>;

/// Why a sequence could not be made. Nothing is written when one is returned.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SenseError {
    /// The world folder is missing or is not one.
    #[error("{path}: {why}; pass a world folder made by `subtgraph generate`")]
    NoWorld {
        /// The folder given.
        path: PathBuf,
        /// What is wrong.
        why: String,
    },
    /// The world folder has no ground-truth graph to plan routes on.
    #[error(
        "{path} has no ground truth (ground_truth/graph.json), which routes are planned on: generate the world with --format ground-truth (or add [[export]] type = \"ground-truth\" to its pipeline)"
    )]
    NoGroundTruth {
        /// The world folder.
        path: PathBuf,
    },
    /// The world was made without geometry, so there is nothing to scan.
    #[error(
        "the world has no mesh (made by generate --no-mesh, or without a [tileset]); generate it again with a tile set"
    )]
    NoMesh,
    /// The graph file is damaged.
    #[error("{path}: {why}; generate the world again")]
    BadGraph {
        /// The file.
        path: String,
        /// What is wrong.
        why: String,
    },
    /// An unknown name (LiDAR model, platform, route, output format).
    #[error("unknown {what} '{name}'; the {what}s are: {known}")]
    Unknown {
        /// What kind of name.
        what: &'static str,
        /// The name given.
        name: String,
        /// The names there are.
        known: String,
    },
    /// A number outside what the sensor or platform can physically do.
    #[error("{what} {value} is out of bounds: it must be {bounds}")]
    OutOfBounds {
        /// The setting (`--imu-rate`, `range_m` in a LiDAR table, ...).
        what: String,
        /// The value given.
        value: String,
        /// What it must be.
        bounds: String,
    },
    /// A LiDAR table (a custom model) could not be used.
    #[error("LiDAR table {path}: {why}")]
    BadLidarTable {
        /// The file.
        path: String,
        /// What is wrong, and what to write instead.
        why: String,
    },
    /// A conditions file (`--conditions`) could not be used.
    #[error("conditions {path}: {why}")]
    BadConditions {
        /// The file.
        path: String,
        /// What is wrong, and what to write instead.
        why: String,
    },
    /// A camera table (a custom camera) could not be used.
    #[error("camera table {path}: {why}")]
    BadCameraTable {
        /// The file.
        path: String,
        /// What is wrong, and what to write instead.
        why: String,
    },
    /// A sequence with cameras would take more disk than allowed.
    #[error(
        "this sequence would write about {} ({frames} camera frames of {} each, the scans and the IMU); --max-disk allows {}: pass a larger --max-disk, a shorter --duration, a lower --camera-rate, fewer --format outputs, or a camera with fewer pixels",
        bytes(*.estimate), bytes(*.per_frame), bytes(*.limit)
    )]
    TooLargeWithCameras {
        /// Bytes estimated.
        estimate: u64,
        /// Bytes per frame (every camera of the rig).
        per_frame: u64,
        /// Frames.
        frames: u64,
        /// The limit.
        limit: u64,
    },
    /// The route cannot be made in this world with this platform.
    #[error("route '{route}': {why}; {fix}")]
    NoRoute {
        /// The route asked for.
        route: String,
        /// Why not.
        why: String,
        /// What to do.
        fix: String,
    },
    /// The platform does not fit through the world somewhere on the route.
    #[error(
        "the {platform} platform does not fit at ({:.1}, {:.1}, {:.1}){}: {free:.2} m of free space around it where it needs {needed:.2} m; choose another --route or --platform, or a world with wider passages",
        at[0], at[1], at[2],
        edge.map(|e| format!(" on edge {e}")).unwrap_or_default()
    )]
    DoesNotFit {
        /// The platform.
        platform: &'static str,
        /// Where, world frame.
        at: [f64; 3],
        /// The graph edge there, if on one.
        edge: Option<usize>,
        /// The free radius there, metres.
        free: f64,
        /// The radius it needs, metres.
        needed: f64,
    },
    /// The sequence would take more disk than allowed.
    #[error(
        "this sequence would write about {} ({scans} scans of {} each and the IMU); --max-disk allows {}: pass a larger --max-disk, a shorter --duration, fewer --format outputs, or a LiDAR with fewer beams",
        bytes(*.estimate), bytes(*.per_scan), bytes(*.limit)
    )]
    TooLarge {
        /// Bytes estimated.
        estimate: u64,
        /// Bytes per scan.
        per_scan: u64,
        /// Scans.
        scans: u64,
        /// The limit.
        limit: u64,
    },
    /// Reading the world folder or writing the sequence failed.
    #[error("{what} {path}: {source}")]
    Io {
        /// What was being done.
        what: &'static str,
        /// On what.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// The application could not rebuild the world of a folder (the cause is its error).
    #[error("rebuilding the world of {folder}: {source}")]
    Rebuild {
        /// The world folder.
        folder: PathBuf,
        /// Why, as the application says it.
        source: HostError,
    },
    /// The rebuilt world's survey failed (its artifacts found no room: the message says
    /// which key to change).
    #[error("surveying the world: {0}")]
    Survey(#[from] subtgraph_survey::SurveyError),
    /// The application could not place the folder (the cause is its error).
    #[error("{0}")]
    Host(#[source] HostError),
}

/// A byte count as people read it.
pub fn bytes(n: u64) -> String {
    let n = n as f64;
    if n >= 1e9 {
        format!("{:.1} GB", n / 1e9)
    } else if n >= 1e6 {
        format!("{:.1} MB", n / 1e6)
    } else {
        format!("{:.0} kB", (n / 1e3).ceil())
    }
}
