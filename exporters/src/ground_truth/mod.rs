//! Ground truth for scoring autonomy stacks: what a topometric segmentation, an exploration
//! coverage count, a multi-robot planner or a SLAM system should find, written under
//! `ground_truth/` in formats their users already read.
//!
//! | `type` | files | for |
//! |---|---|---|
//! | `graph` | `graph.json`, `graph.graphml` | topological maps, route planning (networkx) |
//! | `ros-map` | `maps/level-N.pgm` + `.yaml` | ROS map_server / nav2 occupancy maps, 2D SLAM |
//! | `free-space` | `free_space.npy` + `.json` | 3D exploration coverage, volumetric mapping |
//! | `semantic-labels` | `semantic_labels.json`, `.csv` | place categorisation (junction, dead end, ...) |
//! | `spawn-poses` | `spawn_poses.json` | multi-robot start and goal poses |
//! | `collision-budget` | `collision_budget.json` | how far the visual surface lies from the collision surface, per class (with a mesh) |
//! | `ground-truth` | all of the above | |
//! | `comms` | `comms.csv`, `comms.json` | radio line of sight between tiles (not in `ground-truth`) |
//!
//! None needs geometry: with the world's collision mesh they use its exact surface (the
//! survey's passages, `survey/src/passages.rs`), without one (`--no-mesh`, no `[tileset]`) the
//! grid's cells, and every file's
//! metadata says which (`source`). Every file records the seed and the frame where its format
//! allows: metres, x east (+column), y north (−row), z up (+level), origin at the centre of
//! cell (row `rows − 1`, column 0) of level 0, on its floor.

use serde::Deserialize;
use subtgraph_core::World;
use subtgraph_core::error::ConfigError;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter};
use subtgraph_core::params::Params;
use subtgraph_core::survey::Survey;

pub(crate) mod artifacts;
mod collision_budget;
mod comms;
mod free_space;
mod graph;
pub(crate) mod hazards;
pub(crate) mod ros_map;
mod semantic_labels;
mod spawn_poses;

pub use collision_budget::CollisionBudget;
pub use comms::Comms;
pub use free_space::FreeSpace;
pub use graph::GraphFiles;
pub use ros_map::RosMap;
pub use semantic_labels::SemanticLabels;
pub use spawn_poses::SpawnPoses;

/// The world frame, as written in the files' metadata.
pub(crate) const FRAME: &str = "metres; x east (+column), y north (-row), z up (+level); origin at the centre of cell (row rows-1, column 0) of level 0, on its floor";

/// The keys of every ground-truth exporter; each takes its own, `ground-truth` takes them all.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    /// `ros-map`: metres per pixel.
    pub resolution: Option<f64>,
    /// `ros-map`: metres above each level's floor at which the map is sliced.
    pub height: Option<f64>,
    /// `free-space`: voxel edge, metres.
    pub voxel: Option<f64>,
    /// `spawn-poses`: how many robots.
    pub robots: Option<u32>,
    /// `spawn-poses`: free radius around each robot, metres.
    pub clearance: Option<f64>,
    /// `spawn-poses`: least distance between robots, metres.
    pub spacing: Option<f64>,
}

impl Settings {
    /// Every key.
    pub const KEYS: [&str; 6] = [
        "resolution",
        "height",
        "voxel",
        "robots",
        "clearance",
        "spacing",
    ];

    /// Reads an `[[export]]` table that may hold only `keys`, checking each value.
    pub fn from_params(params: &Params, keys: &[&str]) -> Result<Settings, ConfigError> {
        if keys.is_empty() {
            params.expect_none()?;
        }
        params.expect_known(keys)?;
        let s: Settings = params.deserialize()?;
        let metres = [
            (
                "resolution",
                s.resolution,
                "metres per pixel, e.g. resolution = 0.25",
            ),
            (
                "height",
                s.height,
                "metres above the floor, e.g. height = 1.0",
            ),
            ("voxel", s.voxel, "metres, e.g. voxel = 0.5"),
            ("clearance", s.clearance, "metres, e.g. clearance = 1.0"),
            ("spacing", s.spacing, "metres, e.g. spacing = 2.0"),
        ];
        for (key, v, example) in metres {
            if v.is_some_and(|v| !(v.is_finite() && v > 0.0)) {
                return Err(params.error(key, format!("must be a positive number of {example}")));
            }
        }
        if s.robots.is_some_and(|n| !(1..=256).contains(&n)) {
            return Err(params.error("robots", "must be from 1 to 256, e.g. robots = 4"));
        }
        Ok(s)
    }
}

/// The world's box in the plane, `[x0, y0, x1, y1]`: every level's grid, whole cells.
pub(crate) fn extent(world: &World) -> [f64; 4] {
    let pitch = world.resolved.tile_pitch;
    let (rows, cols) = (world.occupancy.rows() as f64, world.occupancy.cols() as f64);
    let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
    for off in &world.level_offsets {
        let (r, c) = (off[0] as f64, off[1] as f64);
        b[0] = b[0].min((c - 0.5) * pitch);
        b[2] = b[2].max((c + cols - 0.5) * pitch);
        b[1] = b[1].min((-r - 0.5) * pitch);
        b[3] = b[3].max((rows - r - 0.5) * pitch);
    }
    b
}

/// Writes every ground-truth file with its defaults (`type = "ground-truth"`).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GroundTruth {
    /// The keys given, passed on to the exporter each belongs to.
    pub settings: Settings,
}

impl GroundTruth {
    /// From an `[[export]] type = "ground-truth"` table: any key of the five exporters.
    pub fn from_params(params: &Params) -> Result<GroundTruth, ConfigError> {
        Ok(GroundTruth {
            settings: Settings::from_params(params, &Settings::KEYS)?,
        })
    }
}

impl Exporter for GroundTruth {
    fn export(
        &self,
        world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        // One survey for all of them: the passages and the tiles' axes are found once.
        let s = &self.settings;
        GraphFiles.export(world, survey, out)?;
        SemanticLabels.export(world, survey, out)?;
        RosMap::from_settings(s).export(world, survey, out)?;
        FreeSpace::from_settings(s).export(world, survey, out)?;
        SpawnPoses::from_settings(s).export(world, survey, out)?;
        // Only a world with a mesh has two surfaces to compare.
        if world.mesh().is_some_and(collision_budget::has_surfaces) {
            CollisionBudget.export(world, survey, out)?;
        }
        Ok(())
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use subtgraph_core::World;

    /// The crate's two-level test world with a cave collision surface fine enough to keep its
    /// 7 m passages open (a 3 m lattice).
    pub(crate) fn world_with_mesh() -> World {
        let layout = crate::test_world_from("level_height = 40.0").into_parts().0;
        let spec = subtgraph_core::params::ComponentSpec {
            type_name: "cave".into(),
            params: subtgraph_core::params::Params::from_table(
                "tileset",
                toml::from_str("resolution = 16\ncollision_resolution = 8\nwidth = 7.0\nheight = 6.0\nrocks = 0")
                    .unwrap(),
            ),
        };
        let mut registry = subtgraph_core::Registry::empty();
        subtgraph_tilesets::register(&mut registry).unwrap();
        let tileset = registry.tilesets.build(&spec).unwrap();
        let mesh = subtgraph_core::assembly::assemble(&layout, tileset.as_ref()).unwrap();
        World::new(layout, Some(mesh))
    }
}
