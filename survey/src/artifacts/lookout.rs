//! Where the lines of sight to artifacts in a tile start (`crate::sight`), and whether each
//! placed artifact is seen from there: the ground truth's `visible_from_axis` and
//! `sight_from`.

use std::collections::HashMap;

use subtgraph_core::World;
use subtgraph_core::grid::{Cell, Direction};

use crate::axis::Axes;
use crate::passages::Passages;
use crate::sight;

/// Where the lines of sight to artifacts in one tile start (`sight.rs`).
pub(crate) struct Lookout {
    /// The tile's axis points (anchor first).
    points: Vec<[f64; 3]>,
    /// With `[artifacts] hidden`, the robot's way through the tile from the opening nearest
    /// the start; `None` without the key, or for a tile entered from no known opening.
    walk: Option<Vec<[f64; 3]>>,
}

impl Lookout {
    /// The lookout of `cell`, from its axis; `approach` with `[artifacts] hidden`, when
    /// `distances` (from the start along the graph, per cell) say which opening a robot
    /// comes in by.
    pub(crate) fn of(
        world: &World,
        axes: &Axes,
        distances: &HashMap<Cell, f64>,
        cell: Cell,
        approach: bool,
    ) -> Lookout {
        let walk = approach
            .then(|| {
                Direction::ALL
                    .into_iter()
                    .filter_map(|d| {
                        let n = world.occupancy.neighbour(cell, d)?;
                        let dist = *distances.get(&n)?;
                        let walk = axes.walk_from(cell, d)?;
                        dist.is_finite().then_some((dist, walk))
                    })
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .map(|(_, walk)| walk)
            })
            .flatten();
        Lookout {
            points: axes.tile_points(cell),
            walk,
        }
    }

    /// The eye looking at `target`.
    pub(crate) fn eye(&self, target: [f64; 3]) -> [f64; 3] {
        match &self.walk {
            Some(walk) => sight::approach_eye(walk, target),
            None => sight::eye(&self.points, target),
        }
    }
}

/// Whether the artifact centred at each of `targets` (in the tile of its cell) is seen from
/// its tile's passage axis, and the eye it is looked at from (`sight.rs`). With `approach`
/// (`[artifacts] hidden`), from where a robot first comes near. Without a mesh every artifact
/// is seen, from its tile's centre.
pub(crate) fn look(
    world: &World,
    passages: &Passages,
    axes: &Axes,
    targets: &[(Cell, [f64; 3])],
    approach: bool,
) -> Vec<(bool, [f64; 3])> {
    if matches!(passages, Passages::Grid(_)) {
        return targets
            .iter()
            .map(|&(c, _)| (true, world.cell_position(c)))
            .collect();
    }
    let mut cells: Vec<Cell> = targets.iter().map(|t| t.0).collect();
    cells.sort();
    cells.dedup();
    axes.find(&cells);
    let distances = if approach {
        super::distances(world)
    } else {
        HashMap::new()
    };
    let lookouts: HashMap<Cell, Lookout> = cells
        .iter()
        .map(|&c| (c, Lookout::of(world, axes, &distances, c, approach)))
        .collect();
    targets
        .iter()
        .map(|&(c, target)| {
            let eye = lookouts[&c].eye(target);
            (sight::clear(passages, eye, target), eye)
        })
        .collect()
}
