//! Generation per the paper's Methodology: structures placed on each level, objective nodes,
//! route-descriptor guide points, guided shortest paths, union into the level, shafts joining
//! level `k` to level `k + 1`, and tile classification.
//!
//! What the original lacks and this adds:
//! - every level is checked against the request (one network, requested junctions,
//!   intersections and loops, no corridors fused side by side) and rebuilt with a derived seed
//!   when it falls short, up to `world.attempts` times, then a clear error;
//! - shafts are stacked: the landing on level `k + 1` sits exactly above the shaft's foot on
//!   level `k`, so the world frame is shared by every level;
//! - every random choice comes from a stream derived from the seed, so the same pipeline and
//!   seed give the same world on any machine and thread count.

pub(crate) mod level;
mod search;

use crate::budget::Budget;
use crate::components::Components;
use crate::config::Pipeline;
use crate::error::Error;
use crate::grid::{Cell, Grid3};
use crate::layout::{Counts, Layout, Shaft};
use crate::registry::Registry;
use crate::rng::WorldRng;
use crate::shape::ConstraintShape;
use crate::world::World;

pub use level::structure_counts;
pub use search::DETOUR_COST;

/// Generates the world a pipeline describes: its layout and, when the pipeline has a
/// `[tileset]`, its geometry. Builds the pipeline's components ([`Pipeline::build`]), then
/// runs [`generate_with`]. No memory budget: see [`generate_within`].
pub fn generate(pipeline: &Pipeline, registry: &Registry) -> Result<World, Error> {
    generate_within(pipeline, registry, &Budget::unlimited())
}

/// [`generate`], refusing a world that would need more memory than `budget` before making
/// it: its grid before the layout, its meshes before the first tile.
pub fn generate_within(
    pipeline: &Pipeline,
    registry: &Registry,
    budget: &Budget,
) -> Result<World, Error> {
    generate_with(pipeline, &pipeline.build(registry)?, budget)
}

/// The run step of [`generate_within`]: the layout, then the geometry of `components`' tile
/// set when it has one, with components built once by [`Pipeline::build`] (for this pipeline,
/// or another with the same components: a dataset's worlds differ only in their seed).
pub fn generate_with(
    pipeline: &Pipeline,
    components: &Components,
    budget: &Budget,
) -> Result<World, Error> {
    let layout = layout_with(pipeline, components, budget)?;
    let mesh = match &components.tileset {
        Some(t) => Some(mesh_with(&layout, t, budget)?),
        None => None,
    };
    Ok(World::new(layout, mesh))
}

/// The geometry of a layout by a built tile set, within `budget`: what [`generate_with`] runs
/// after the layout, and what meshes an imported grid. A tile set's error is an
/// [`Error::Component`] naming it.
pub fn mesh_with(
    layout: &Layout,
    tileset: &crate::components::NamedTileSet,
    budget: &Budget,
) -> Result<crate::assembly::WorldMesh, Error> {
    crate::assembly::assemble_within(layout, tileset.tileset.as_ref(), budget).map_err(|e| {
        Error::Component {
            component: "tile set",
            name: tileset.name.clone(),
            message: e.to_string(),
        }
    })
}

/// The most empty cells a shape may keep around its footprint ([`ConstraintShape::clearance`]):
/// placing a structure checks a square of `2 c + 1` cells on each side around every footprint
/// cell, so a plugin's clearance of a million cells would never finish.
pub const MAX_CLEARANCE: i32 = 16;

/// Refuses a shape whose rotations or clearance the generator cannot use as given: distinct
/// quarter turns are 1, 2 or 4 (3 would draw three of the four turns, favouring some
/// headings), and a clearance is from 1 to [`MAX_CLEARANCE`] cells. Built-in and Python
/// shapes are checked where they are made; this catches a plugin's.
fn check_shape(name: &str, shape: &dyn ConstraintShape) -> Result<(), Error> {
    let fail = |message: String| Error::Component {
        component: "constraint shape",
        name: name.to_owned(),
        message,
    };
    let r = shape.rotations();
    if !matches!(r, 1 | 2 | 4) {
        return Err(fail(format!(
            "rotations() is {r}; it must be 1, 2 or 4 (the distinct quarter turns of the \
             footprint: 1 for a shape that looks the same turned by 90 degrees, 2 for one that \
             looks the same turned by 180, else 4)"
        )));
    }
    let c = shape.clearance();
    if !(1..=MAX_CLEARANCE).contains(&c) {
        return Err(fail(format!(
            "clearance() is {c}; it must be a whole number of cells from 1 to {MAX_CLEARANCE}"
        )));
    }
    Ok(())
}

/// Generates a world's layout only: occupancy, tiles, shafts, graph and report, without
/// geometry (what `--no-mesh` runs). No memory budget: see [`layout_within`].
pub fn layout(pipeline: &Pipeline, registry: &Registry) -> Result<Layout, Error> {
    layout_within(pipeline, registry, &Budget::unlimited())
}

/// [`layout`], refusing first a grid that would need more memory than `budget`.
pub fn layout_within(
    pipeline: &Pipeline,
    registry: &Registry,
    budget: &Budget,
) -> Result<Layout, Error> {
    layout_with(pipeline, &pipeline.build(registry)?, budget)
}

/// The run step of [`layout_within`], with components built once by [`Pipeline::build`]: the
/// route descriptor guides the arms of the constraint shapes; the tile set and exporters are
/// not used.
pub fn layout_with(
    pipeline: &Pipeline,
    components: &Components,
    budget: &Budget,
) -> Result<Layout, Error> {
    let (resolved_pipeline, resolved) = pipeline.resolve()?;
    budget
        .check(
            crate::budget::layout_bytes(resolved.levels, resolved.rows, resolved.cols),
            &format!(
                "a world of {} level(s) of {} x {} cells",
                resolved.levels, resolved.rows, resolved.cols
            ),
            "make it smaller (world.levels, world.min_length, or world.rows and world.cols)",
        )
        .map_err(Error::TooLarge)?;
    let descriptor = &components.route;
    let shapes = &components.shapes;

    let (rows, cols) = (resolved.rows, resolved.cols);
    // A shape that can never fit this grid is the pipeline's error, not a level's failure.
    for (name, shape) in shapes {
        if resolved
            .per_level
            .iter()
            .any(|l| l.iter().any(|(n, c)| n == name && *c > 0))
        {
            check_shape(name, shape.as_ref())?;
            shape.fits(rows, cols)?;
        }
    }
    let mut occupancy = Grid3::filled(resolved.levels, rows, cols, false);
    let mut shafts = Vec::new();
    let mut expected: Vec<Option<Counts>> = Vec::new();
    let mut attempts_used = Vec::new();
    let mut search = search::Search::new(rows * cols);
    let mut landing: Option<level::ShaftFoot> = None;
    for k in 0..resolved.levels {
        let structures: Vec<(&str, &dyn ConstraintShape)> = resolved.per_level[k]
            .iter()
            .flat_map(|(name, count)| {
                let shape: &dyn ConstraintShape = shapes[name].as_ref();
                std::iter::repeat_n((name.as_str(), shape), *count as usize)
            })
            .collect();
        let spec = level::LevelSpec {
            rows,
            cols,
            structures,
            landing: landing.map(|f| f.at),
            landing_block: landing.and_then(|f| f.block),
            ramp_blocks: resolved.connections == crate::config::Connections::Ramp,
            exact: resolved.exact,
            needs_shaft_up: k + 1 < resolved.levels,
        };
        let mut last_failure = None;
        let mut built = None;
        for attempt in 0..resolved.attempts {
            let mut rng = WorldRng::new(
                resolved.seed,
                "level",
                (k as u64) << 32 | u64::from(attempt),
            );
            match level::build_level(&spec, descriptor.as_ref(), &mut search, &mut rng) {
                Ok(b) => {
                    built = Some((b, attempt + 1));
                    break;
                }
                Err(why) => last_failure = Some(why),
            }
        }
        let Some((b, used)) = built else {
            let mut advice = "use a larger grid (raise world.min_length, or world.rows and \
                              world.cols), ask for fewer structures on this level, or set \
                              topology.exact = false"
                .to_owned();
            if spec.ramp_blocks && last_failure == Some(level::LevelFailure::NoShaftFoot) {
                advice.push_str(", or join the levels by shafts (world.connections = \"shaft\")");
            }
            return Err(Error::Unsatisfiable {
                level: k,
                what: last_failure.map(|w| w.to_string()).unwrap_or_default(),
                attempts: resolved.attempts,
                rows,
                cols,
                advice,
            });
        };
        for (i, &o) in b.occ.iter().enumerate() {
            if o {
                *occupancy.get_mut(Cell::new(k, i / cols, i % cols)) = true;
            }
        }
        if let Some(foot) = landing {
            let (r, c) = foot.at;
            shafts.push(Shaft {
                up: Cell::new(k - 1, r, c),
                landing: Cell::new(k, r, c),
                block: foot.block,
            });
        }
        landing = b.shaft_up;
        expected.push(Some(b.expected));
        attempts_used.push(used);
    }
    let requested = resolved
        .per_level
        .iter()
        .map(|l| l.iter().cloned().collect())
        .collect();
    Ok(Layout::new(
        resolved_pipeline,
        resolved,
        occupancy,
        shafts,
        requested,
        expected,
        attempts_used,
    ))
}
