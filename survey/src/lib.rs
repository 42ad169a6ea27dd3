//! # subtgraph-survey
//!
//! The survey of a finished world: the stage between the tile sets and the exporters. It
//! runs once per world, after the mesh, and answers what every format would otherwise find
//! again for itself:
//!
//! | what | where | when |
//! |---|---|---|
//! | the passages: the free stretches of any vertical line, by exact ray parity on the collision surface (the grid's cells without a mesh) | [`passages`] | built when first asked for |
//! | each tile's passage axis: where its node stands, its paths to its openings, its grade | [`axis`] | per tile, when first asked for (artifact placement asks for a few, the ground truth for all, in parallel) |
//! | each edge's centreline and its length | [`centrelines`] | when first asked for |
//! | each edge's least width and height on the collision surface | [`sections`] | when first asked for |
//! | what a ray hits on the collision surface: one hierarchy, shared by the widths and heights, the comms and the collision budget | [`WorldSurvey::rays`] | built when first asked for |
//! | what a sensor's ray hits: the visual surface and the fixtures (a mine's services), for `subtgraph sense` and Python's `World.raycast` and `World.lidar_scan` | [`WorldSurvey::scan_rays`] | built when first asked for |
//! | the artifacts' poses and whether each is seen from its tile's passage | [`artifacts`], [`sight`] | when the survey is made (a pipeline with `[artifacts]` always writes them) |
//! | the floor patches of `[hazards] friction` | [`hazards`] | when the survey is made |
//! | MuJoCo's height fields and convex slabs | [`heightfields`], [`convex_pieces`] | when MuJoCo's writer asks, with its settings |
//!
//! So each format costs what it needs: a world exported as OBJ alone builds nothing here, one
//! with ground truth finds the passages once for its graph, maps, free space and spawn poses,
//! and its artifacts with them.
//!
//! Exporters see a [`WorldSurvey`] through the core's [`Survey`] trait (the core names it in
//! `Exporter::export`, so a plugin's exporter gets the same answers). Everything is a pure
//! function of the world: what is found first does not change what is found later, and no
//! result depends on the thread count.

pub mod artifacts;
pub mod axis;
pub mod centrelines;
pub mod convex_pieces;
pub mod hazards;
pub mod heightfields;
pub mod passages;
pub mod sections;
pub mod sight;

use std::sync::{Arc, OnceLock};

use subtgraph_core::World;
use subtgraph_core::artifacts::PlacedArtifacts;
use subtgraph_core::config::Pipeline;
use subtgraph_core::grid::Cell;
use subtgraph_core::hazards::Patch;
use subtgraph_core::mesh::Mesh;
use subtgraph_core::raycast::RayCaster;
use subtgraph_core::survey::{Columns, EdgeLine, RowVisitor, Source, Survey};

use crate::axis::{Axes, AxisCache};
use crate::passages::Passages;
use crate::sections::Sections;

/// Why a world cannot be surveyed. Each message says what to change in the pipeline.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SurveyError {
    /// Not every artifact of `[artifacts]` found a spot: lower `artifacts.count`,
    /// `artifacts.min_spacing` or `artifacts.min_distance_from_start`, or allow more
    /// placement rules.
    #[error(
        "artifacts: placed {placed} of {count}: no tile allowed by placement = {rules:?} at least {min_distance_from_start} m from the start along the passages has room for a {class} {min_spacing} m from the others; lower artifacts.count, artifacts.min_spacing or artifacts.min_distance_from_start, or allow more placement rules"
    )]
    ArtifactsDoNotFit {
        /// How many were placed before one found no spot.
        placed: usize,
        /// How many were asked for.
        count: usize,
        /// The placement rules, as named in the pipeline.
        rules: Vec<&'static str>,
        /// `artifacts.min_distance_from_start`, metres.
        min_distance_from_start: f64,
        /// The class of the artifact that found no spot.
        class: &'static str,
        /// `artifacts.min_spacing`, metres.
        min_spacing: f64,
    },
}

/// A world's survey: what it found when it was made (the artifacts, the floor patches) and
/// what it finds when first asked (the rest; see the crate's doc).
pub struct WorldSurvey<'w> {
    world: &'w World,
    passages: OnceLock<Passages<'w>>,
    axes: AxisCache,
    /// Set once every tile's axis is found (in parallel): what the ground truth reads.
    all_axes: OnceLock<()>,
    edges: OnceLock<Vec<EdgeLine>>,
    /// The one ray-cast structure over the collision surface (`core::raycast`'s hierarchy),
    /// built once, when first needed: by the edges' widths and heights ([`Sections`]), the
    /// comms or the collision budget. `None` without a mesh.
    rays: OnceLock<Option<Arc<RayCaster>>>,
    /// What a sensor's rays hit: the hierarchy over the visual surface, and with fixtures (a
    /// mine's services) the visual surface with the fixtures baked after it (`None`: the
    /// visual surface alone, not copied).
    scan: OnceLock<Option<(Arc<RayCaster>, Option<Mesh>)>>,
    sections: OnceLock<Vec<Option<(f64, f64)>>>,
    artifacts: Option<PlacedArtifacts>,
    patches: Option<Vec<Patch>>,
}

impl<'w> WorldSurvey<'w> {
    /// Surveys `world`: places its artifacts (`[artifacts]`: on the passages, which are then
    /// found now) and its floor patches (`[hazards]`); the rest waits until asked for.
    pub fn new(world: &'w World) -> Result<WorldSurvey<'w>, SurveyError> {
        let mut survey = WorldSurvey {
            world,
            passages: OnceLock::new(),
            axes: AxisCache::new(world),
            all_axes: OnceLock::new(),
            edges: OnceLock::new(),
            rays: OnceLock::new(),
            scan: OnceLock::new(),
            sections: OnceLock::new(),
            artifacts: None,
            patches: hazards::patches(world),
        };
        if world.pipeline.artifacts.is_some() {
            let placed = artifacts::place(world, survey.passages(), &survey.axes())?;
            survey.artifacts = placed;
        }
        Ok(survey)
    }

    /// The world surveyed.
    pub fn world(&self) -> &'w World {
        self.world
    }

    fn passages(&self) -> &Passages<'w> {
        self.passages.get_or_init(|| Passages::of(self.world))
    }

    /// The tiles' axes, each found when first asked for.
    fn axes(&self) -> Axes<'_> {
        Axes::new(self.world, self.passages(), &self.axes)
    }

    /// The tiles' axes, every one found (in parallel, once).
    fn all_axes(&self) -> Axes<'_> {
        let axes = self.axes();
        self.all_axes.get_or_init(|| axes.find_all());
        axes
    }

    /// What a ray hits on the collision surface (what a robot's body meets and the ground
    /// truth is made on): the hierarchy over it, built on the first call (a fraction of a
    /// second for the lava-tube preset's 0.55 M collision triangles, on two cores) and shared
    /// from then on; `None` for a world without a mesh. The edges' widths and heights, the
    /// comms and the collision budget ask this one; the sensors ask
    /// [`scan_rays`](Self::scan_rays).
    pub fn rays(&self) -> Option<&Arc<RayCaster>> {
        self.rays
            .get_or_init(|| {
                let mesh = self.world.mesh()?;
                Some(Arc::new(RayCaster::new(&mesh.collision)))
            })
            .as_ref()
    }

    /// What a sensor sees, and the surface its hits' triangle indices refer to: the world's
    /// finest surface, the one `mesh/world.obj` holds and cameras and other simulators' ray
    /// casters see (the visual surface), and in a world with fixtures (a mine's bolts, duct,
    /// pipes, cable and lights, `mesh/services.obj`) the fixtures baked after it, in one
    /// hierarchy built when first asked for. Its triangle indices are the visual mesh's, then
    /// the fixtures' (so a hit's material, texture coordinates and tile are looked up there).
    /// The ground truth keeps to the collision surface ([`rays`](Self::rays)), which the
    /// collision budget (`ground_truth/collision_budget.json`) says how far it lies from this.
    pub fn scan_rays(&self) -> Option<(&Arc<RayCaster>, &Mesh)> {
        let mesh = self.world.mesh()?;
        let (caster, all) = self
            .scan
            .get_or_init(|| {
                if mesh.fixtures.is_empty() {
                    return Some((Arc::new(RayCaster::new(&mesh.visual)), None));
                }
                let mut all = mesh.visual.clone();
                // Rays take their triangles' normals; the fixtures are baked without vertex
                // normals, so the rock's go too rather than cover only part of the surface.
                all.normals.clear();
                all.append(&mesh.fixtures.baked());
                Some((Arc::new(RayCaster::new(&all)), Some(all)))
            })
            .as_ref()?;
        Some((caster, all.as_ref().unwrap_or(&mesh.visual)))
    }

    /// The edges' widths and heights, measured by rays into [`rays`](Self::rays).
    fn sections_of(&self) -> Option<Sections<'_>> {
        let rays = self.rays()?;
        Sections::of(self.world, rays)
    }
}

impl Survey for WorldSurvey<'_> {
    fn record(&self) -> &Pipeline {
        &self.world.pipeline
    }

    fn source(&self) -> Source {
        self.passages().source()
    }

    fn visit_rows(&self, cols: &Columns, bounds: [f64; 4], row: &RowVisitor<'_>) -> usize {
        self.passages()
            .raster_within(cols, bounds, |j, spans, open| row(j, spans, open))
            .open_lines
    }

    fn column(&self, x: f64, y: f64) -> Vec<[f64; 2]> {
        self.passages().column(x, y)
    }

    fn position(&self, cell: Cell) -> [f64; 3] {
        self.all_axes().position(cell)
    }

    fn grade(&self, cell: Cell) -> Option<f64> {
        self.all_axes().grade(cell)
    }

    fn has_axes(&self) -> bool {
        !self.all_axes().is_empty()
    }

    fn edges(&self) -> &[EdgeLine] {
        self.edges
            .get_or_init(|| centrelines::edges(self.world, self.passages(), &self.all_axes()))
    }

    fn sections(&self) -> &[Option<(f64, f64)>] {
        self.sections.get_or_init(|| {
            let sections = self.sections_of();
            self.edges()
                .iter()
                .zip(&self.world.graph.edges)
                .map(|(line, e)| sections.as_ref().and_then(|s| s.edge(e.kind, &line.points)))
                .collect()
        })
    }

    fn artifacts(&self) -> Option<&PlacedArtifacts> {
        self.artifacts.as_ref()
    }

    fn patches(&self) -> Option<&[Patch]> {
        self.patches.as_deref()
    }

    fn ray_caster(&self) -> Option<&RayCaster> {
        self.rays().map(|r| &**r)
    }
}

/// Small worlds for the crate's tests.
#[cfg(test)]
pub(crate) mod tests {
    use subtgraph_core::World;
    use subtgraph_core::registry::Registry;

    /// A two-level 24 x 24 world without a mesh, corridors routed straight.
    pub(crate) fn world() -> World {
        world_from("")
    }

    /// [`world`] with extra `[world]` keys.
    fn world_from(world_keys: &str) -> World {
        let text = format!(
            "[world]\nseed = 3\nlevels = 2\nrows = 24\ncols = 24\n{world_keys}\n[topology]\nloops = 1\nt_junctions = 1\nintersections = 1\n"
        );
        let p = subtgraph_core::Pipeline::parse(&text, "test.toml").unwrap();
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

    struct Straight;

    impl subtgraph_core::route::RouteDescriptor for Straight {
        fn offset(&self, _t: f64, _s: &subtgraph_core::route::Segment) -> f64 {
            0.0
        }
    }

    /// [`world`] (levels 40 m apart) meshed by the cave tile set with `keys`.
    fn meshed(keys: &str) -> World {
        let layout = world_from("level_height = 40.0").into_parts().0;
        let spec = subtgraph_core::params::ComponentSpec {
            type_name: "cave".into(),
            params: subtgraph_core::params::Params::from_table(
                "tileset",
                toml::from_str(keys).unwrap(),
            ),
        };
        let mut registry = Registry::empty();
        subtgraph_tilesets::register(&mut registry).unwrap();
        let tileset = registry.tilesets.build(&spec).unwrap();
        let mesh = subtgraph_core::assembly::assemble(&layout, tileset.as_ref()).unwrap();
        World::new(layout, Some(mesh))
    }

    /// The two-level test world with a cave collision surface fine enough to keep its 7 m
    /// passages open (a 3 m lattice).
    pub(crate) fn world_with_mesh() -> World {
        meshed("resolution = 16\ncollision_resolution = 8\nwidth = 7.0\nheight = 6.0\nrocks = 0")
    }

    /// The two-level test world with a coarse cave mesh.
    pub(crate) fn coarse_world_with_mesh() -> World {
        meshed("resolution = 8\ncollision_resolution = 4\nwidth = 7.0\nheight = 6.0")
    }
}
