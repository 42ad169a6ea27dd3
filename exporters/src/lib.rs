//! # subtgraph-exporters
//!
//! Writers for a world's files. The world folder's own files are always written:
//!
//! | file | what |
//! |---|---|
//! | `world.toml` | the resolved pipeline (seed, every drawn value, tool version): regenerates the world |
//! | `occupancy.npy` | `uint8 [levels, rows, cols]` with the original's spatial codes |
//! | `topology.json` | the graph, and requested against achieved counts per level |
//! | `maps/level-N.png` | a top-down picture per level, tile kinds in distinct colours |
//! | `mesh/world.obj`, `mesh/world.mtl`, `mesh/collision.obj` | the geometry, when the pipeline has a `[tileset]` |
//! | `mesh/textures/*.png` | the materials' albedo, normal and roughness maps, when the tile set makes them (`[tileset] textures`); written once, by the first format that names them |
//! | `ground_truth/artifacts.json`, `.csv` | the artifacts' classes and poses, when the pipeline has `[artifacts]` |
//! | `ground_truth/hazards.json` | the floor patches and hazard regions, when the pipeline has `[hazards]` |
//!
//! The `[[export]]` exporters (one file each) register in [`register`]. Those that write
//! geometry for simulators cut large worlds into [`parts`] and share per-part meshes.
//!
//! Exporters format; they find nothing themselves. What a format needs beyond the layout and
//! the meshes (the passages, node positions and centrelines, artifact poses, floor patches,
//! MuJoCo's height fields) comes from the world's survey (`subtgraph-survey`), made once per
//! world and handed to every exporter as a [`Survey`].

use subtgraph_core::World;
use subtgraph_core::artifacts::Artifact;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter};
use subtgraph_core::registry::{DuplicateName, Registry};
use subtgraph_core::survey::Survey;

mod fixtures;
mod gltf;
pub mod ground_truth;
pub mod hazards;
mod instances;
mod level_maps;
mod mjcf;
mod obj;
mod occupancy_npy;
pub mod parts;
mod sdf;
mod services;
mod tasks;
mod text;
mod topology_json;
mod urdf;
mod usd;
mod world_toml;

pub use gltf::Gltf;

pub use ground_truth::{
    CollisionBudget, Comms, FreeSpace, GraphFiles, GroundTruth, RosMap, SemanticLabels,
    Settings as GroundTruthSettings, SpawnPoses,
};
pub use level_maps::{LevelMaps, kind_colour};
pub use mjcf::Mjcf;
pub use obj::Obj;
pub use occupancy_npy::OccupancyNpy;
pub use sdf::{Lights, Sdf};
pub use tasks::Tasks;
pub use topology_json::TopologyJson;
pub use urdf::Urdf;
pub use usd::Usd;
pub use world_toml::{WorldToml, world_toml_text};

/// Adds the built-in `[[export]]` exporters to a registry.
pub fn register(registry: &mut Registry) -> Result<(), DuplicateName> {
    let e = &mut registry.exporters;
    e.add(
        "obj",
        "Wavefront OBJ + MTL, visual and collision; `split` adds one OBJ pair per part",
        |p| Ok(Box::new(Obj::from_params(p)?) as Box<dyn Exporter>),
    )?;
    e.add(
        "graph",
        "ground truth: the topology graph as ground_truth/graph.json and graph.graphml (networkx)",
        |p| {
            GroundTruthSettings::from_params(p, &[])?;
            Ok(Box::new(GraphFiles) as Box<dyn Exporter>)
        },
    )?;
    e.add(
        "ros-map",
        "ground truth: a ROS map_server occupancy map per level (ground_truth/maps/level-N.pgm + .yaml); `resolution`, `height`",
        |p| {
            let s = GroundTruthSettings::from_params(p, &RosMap::KEYS)?;
            Ok(Box::new(RosMap::from_settings(&s)) as Box<dyn Exporter>)
        },
    )?;
    e.add(
        "free-space",
        "ground truth: the 3D free space as a bit-packed voxel grid (ground_truth/free_space.npy + .json); `voxel`",
        |p| {
            let s = GroundTruthSettings::from_params(p, &FreeSpace::KEYS)?;
            Ok(Box::new(FreeSpace::from_settings(&s)) as Box<dyn Exporter>)
        },
    )?;
    e.add(
        "semantic-labels",
        "ground truth: every tile's kind, rotation, openings and position (ground_truth/semantic_labels.json + .csv)",
        |p| {
            GroundTruthSettings::from_params(p, &[])?;
            Ok(Box::new(SemanticLabels) as Box<dyn Exporter>)
        },
    )?;
    e.add(
        "spawn-poses",
        "ground truth: spawn and goal poses for several robots (ground_truth/spawn_poses.json); `robots`, `clearance`, `spacing`",
        |p| {
            let s = GroundTruthSettings::from_params(p, &SpawnPoses::KEYS)?;
            Ok(Box::new(SpawnPoses::from_settings(&s)) as Box<dyn Exporter>)
        },
    )?;
    e.add(
        "collision-budget",
        "ground truth: how far the visual surface lies from the collision surface, per class (ground_truth/collision_budget.json)",
        |p| {
            GroundTruthSettings::from_params(p, &[])?;
            Ok(Box::new(CollisionBudget) as Box<dyn Exporter>)
        },
    )?;
    e.add(
        "ground-truth",
        "ground truth: graph, ros-map, free-space, semantic-labels, spawn-poses and collision-budget with their keys",
        |p| Ok(Box::new(GroundTruth::from_params(p)?) as Box<dyn Exporter>),
    )?;
    e.add(
        "comms",
        "ground truth: line of sight between every two passage tiles within `range` (ground_truth/comms.csv + .json), the DARPA comms question; `range`, `antenna`",
        |p| Ok(Box::new(Comms::from_params(p)?) as Box<dyn Exporter>),
    )?;
    e.add(
        "tasks",
        "planning benchmarks: MovingAI octile maps and scenarios per level, single- and multi-agent (tasks/level-N.map, .scen, level-N-random-K.scen, tasks.json); `resolution`, `problems`, `agents`, `instances`",
        |p| Ok(Box::new(Tasks::from_params(p)?) as Box<dyn Exporter>),
    )?;
    e.add(
        "mjcf",
        "MuJoCo MJCF: mujoco/world.xml including a file per part; collision as convex slabs in the rock (`tolerance`, `thickness`)",
        |p| Ok(Box::new(Mjcf::from_params(p)?) as Box<dyn Exporter>),
    )?;
    e.add(
        "urdf",
        "URDF for PyBullet: urdf/world.urdf, one static link, concave collision meshes per part",
        |p| Ok(Box::new(Urdf::from_params(p)?) as Box<dyn Exporter>),
    )?;
    e.add(
        "sdf",
        "Gazebo SDFormat 1.9 world (gz-sim): a static model per part, visual and collision meshes, cave lighting",
        |p| Ok(Box::new(Sdf::from_params(p)?) as Box<dyn Exporter>),
    )?;
    e.add(
        "usd",
        "USD (Isaac Sim, Omniverse): usd/world.usda with a layer per part, UsdPhysics triangle-mesh colliders, repeated tiles instanced",
        |p| Ok(Box::new(Usd::from_params(p)?) as Box<dyn Exporter>),
    )?;
    e.add(
        "gltf",
        "binary glTF 2.0 (Blender, Unity, web viewers): mesh/world.glb, a node per part, Y up",
        |p| Ok(Box::new(Gltf::from_params(p)?) as Box<dyn Exporter>),
    )?;
    Ok(())
}

/// Writes `doc` as pretty-printed JSON ending in a newline: every JSON file of a world folder.
pub(crate) fn write_json<T: serde::Serialize + ?Sized>(
    out: &mut dyn WorldWriter,
    path: &str,
    doc: &T,
) -> Result<(), ExportError> {
    let mut text = serde_json::to_string_pretty(doc).expect("plain data serializes");
    text.push('\n');
    subtgraph_core::export::write_file(out, path, text.as_bytes())
}

/// Writes the files every world folder has, and the OBJ meshes when the world has geometry.
pub fn write_world_folder(
    world: &World,
    survey: &dyn Survey,
    out: &mut dyn WorldWriter,
) -> Result<(), ExportError> {
    write_world_files(world, survey, out, true)
}

/// Writes the files every world folder has; with `obj`, also the OBJ meshes (`mesh/world.obj`,
/// `.mtl`, `collision.obj`) when the world has geometry. The command line passes `obj` only
/// when no exporter writes geometry: a world asked for in USD alone gets USD alone (the OBJ of
/// a large world is gigabytes), and one asked for in no format keeps its mesh as OBJ. The
/// artifacts and hazards the `survey` found are always written with them.
pub fn write_world_files(
    world: &World,
    survey: &dyn Survey,
    out: &mut dyn WorldWriter,
    obj: bool,
) -> Result<(), ExportError> {
    let always: [&dyn Exporter; 4] = [&WorldToml, &OccupancyNpy, &TopologyJson, &LevelMaps];
    for e in always {
        e.export(world, survey, out)?;
    }
    if obj && world.mesh().is_some() {
        Obj::default().export(world, survey, out)?;
    }
    if let Some(placed) = survey.artifacts() {
        ground_truth::artifacts::write(world, placed, out)?;
    }
    if let Some(patches) = survey.patches() {
        ground_truth::hazards::write(world, patches, out)?;
    }
    Ok(())
}

/// The artifacts the survey placed (none without `[artifacts]`).
pub(crate) fn artifacts_of(survey: &dyn Survey) -> &[Artifact] {
    survey.artifacts().map_or(&[], |a| &a.artifacts)
}

/// The survey of a test world.
#[cfg(test)]
pub(crate) fn survey_of(world: &World) -> subtgraph_survey::WorldSurvey<'_> {
    subtgraph_survey::WorldSurvey::new(world).unwrap()
}

/// A small two-level world with a coarse cave mesh, for the exporters' tests.
#[cfg(test)]
pub(crate) fn test_world_with_mesh() -> World {
    let layout = test_world_from("level_height = 40.0").into_parts().0;
    let spec = subtgraph_core::params::ComponentSpec {
        type_name: "cave".into(),
        params: subtgraph_core::params::Params::from_table(
            "tileset",
            toml::from_str("resolution = 8\ncollision_resolution = 4\nwidth = 7.0\nheight = 6.0")
                .unwrap(),
        ),
    };
    let mut registry = Registry::empty();
    subtgraph_tilesets::register(&mut registry).unwrap();
    let tileset = registry.tilesets.build(&spec).unwrap();
    let mesh = subtgraph_core::assembly::assemble(&layout, tileset.as_ref()).unwrap();
    World::new(layout, Some(mesh))
}

/// A small two-level world for the exporters' tests.
#[cfg(test)]
fn test_world() -> World {
    test_world_from("")
}

/// [`test_world`] with extra `[world]` keys.
#[cfg(test)]
fn test_world_from(world_keys: &str) -> World {
    let text = format!(
        "[world]\nseed = 3\nlevels = 2\nrows = 24\ncols = 24\n{world_keys}\n[topology]\nloops = 1\nt_junctions = 1\nintersections = 1\n"
    );
    let text = text.as_str();
    let p = subtgraph_core::Pipeline::parse(text, "test.toml").unwrap();
    let mut registry = Registry::with_core_shapes();
    registry
        .route_descriptors
        .register(
            "parabolic",
            "test",
            "",
            std::sync::Arc::new(|_| {
                Ok(Box::new(Straight) as Box<dyn subtgraph_core::route::RouteDescriptor>)
            }),
        )
        .unwrap();
    World::new(subtgraph_core::layout(&p, &registry).unwrap(), None)
}

#[cfg(test)]
struct Straight;

#[cfg(test)]
impl subtgraph_core::route::RouteDescriptor for Straight {
    fn offset(&self, _t: f64, _s: &subtgraph_core::route::Segment) -> f64 {
        0.0
    }
}
