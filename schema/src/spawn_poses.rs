//! `ground_truth/spawn_poses.json`: spawn and goal poses for several robots (written by the
//! exporters' `SpawnPoses`).
//!
//! `S` is the type of the fixed texts: `&'static str` where the writer fills them in,
//! `String` (the default) where a file is read.

use serde::{Deserialize, Serialize};
use subtgraph_core::grid::Cell;

use crate::Document;

/// `ground_truth/spawn_poses.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SpawnPoses<S = String> {
    /// [`SpawnPoses::FORMAT`](Document::FORMAT).
    pub format: S,
    /// The world's seed.
    pub seed: u64,
    /// The frame, in words.
    pub frame: S,
    /// Units, in words.
    pub units: S,
    /// Where the free space came from (`mesh` or `grid`).
    pub source: S,
    /// The start tile.
    pub start: Cell,
    /// Robots asked for.
    pub robots_requested: u32,
    /// Free radius around each robot, metres.
    pub clearance_m: f64,
    /// Least distance between two robots, metres.
    pub spacing_m: f64,
    /// The robot's body, metres above its floor, kept free.
    pub body_m: [f64; 2],
    /// Whether every robot has a goal of its own.
    pub goals_distinct: bool,
    /// The robots.
    pub robots: Vec<Robot<S>>,
}

/// A pose on a floor: position, yaw about z and the same as a quaternion.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Pose {
    /// Metres.
    pub position: [f64; 3],
    /// Radians counter-clockwise from east about z.
    pub yaw: f64,
    /// The yaw as a quaternion, `[x, y, z, w]`.
    pub quaternion_xyzw: [f64; 4],
}

impl Pose {
    /// The pose at `position` turned `yaw` about z.
    pub fn new(position: [f64; 3], yaw: f64) -> Pose {
        Pose {
            position,
            yaw,
            quaternion_xyzw: [0.0, 0.0, (0.5 * yaw).sin(), (0.5 * yaw).cos()],
        }
    }
}

/// Where a robot goes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Goal<S = String> {
    /// The goal's graph node.
    pub node: usize,
    /// Its tile's kind.
    pub kind: S,
    /// Its cell.
    pub cell: Cell,
    /// From the start along the graph, metres.
    pub path_length_m: f64,
    /// Where to stand.
    pub pose: Pose,
}

/// One robot: where it spawns and where it goes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Robot<S = String> {
    /// `robot_K`.
    pub name: String,
    /// Where it starts.
    pub spawn: Pose,
    /// Where it goes.
    pub goal: Goal<S>,
}

impl Document for SpawnPoses {
    const PATH: &'static str = "ground_truth/spawn_poses.json";
    const FORMAT: &'static str = "subtgraph-spawn-poses/1";

    fn format(&self) -> &str {
        &self.format
    }
}
