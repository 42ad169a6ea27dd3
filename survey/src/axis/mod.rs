//! The passage axis of every tile, taken from the free space of the collision surface: where a
//! robot drives through a tile, as opposed to where the grid puts the tile's centre.
//!
//! A tile's passage need not pass through its centre: a DARPA cave tile's corner arcs away from
//! it and its straight tiles wind (on `examples/darpa-cave.toml`, 54 % of the corner tiles and
//! 38 % of the dead ends have no surface at all on the vertical line through their centre). So
//! every tile is looked at on a grid of vertical lines (at least `PIXELS` x `PIXELS`, at
//! most `SPACING` apart, so a ridge of rock a ball cannot cross lies on a line): a line is
//! drivable where one of its free stretches starts within the level (its floor) and is at least
//! `BODY` high. Over the drivable lines, a clearance-weighted shortest path (steps away from
//! the walls and from ledges are cheaper, so paths keep to the middle of the passage; no
//! diagonal step passes between two lines it could not step to) joins each opening of the
//! tile (the widest drivable line of the seam, nearest the seam's middle) to the tile's
//! *anchor*: for a tile with two or more openings the point nearest all of them along the
//! passage (the middle of a corridor tile, the meeting point of a junction), for a dead end
//! the middle of its passage (from the opening to the far end that still has clearance), and
//! for a shaft foot or landing the drivable line nearest the shaft's axis. Paths climb at most
//! 0.6 of the line spacing per line (31 degrees) and pay for every metre up or down.
//!
//! The paths' points are kept every `KEEP_M` and wherever the straight line between kept
//! points would stray more than `CHORD` from the path (a body is driven point to point).
//! The graph's node positions, its corridor polylines (anchor, path to the opening, the next
//! tile's path from its opening, its anchor, ...), the tiles' positions in the semantic labels and the spawn
//! and goal poses all use these, with the floor's own height. A tile where nothing is drivable
//! or an opening is not reached keeps its grid centre (`Axes::fallback` counts them). Without a
//! mesh the passages are the grid's, and the axis is the line through the cell centres.
//!
//! Deterministic: lines come from the exact raster of [`crate::passages`], paths from a
//! Dijkstra with integer costs and ties broken by index. Each tile's axis is found once, when
//! first asked for (`AxisCache`): artifact placement asks for a few tiles, the ground truth
//! for all of them (in parallel); a tile's axis depends on nothing else, so the order does
//! not matter.

pub(crate) mod tile;

use std::sync::OnceLock;

use rayon::prelude::*;
use subtgraph_core::World;
use subtgraph_core::config::Connections;
use subtgraph_core::grid::{Cell, Direction};

use crate::passages::Passages;
#[cfg(test)]
use tile::BODY;

/// Least horizontal run over which [`Axes::grade`] measures a rise, metres.
pub(crate) const GRADE_RUN: f64 = 4.0;

/// One tile's axis.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct TileAxis {
    /// Where the tile's node stands, on its floor.
    pub anchor: [f64; 3],
    /// Per direction (`Direction as usize`): the path from the anchor (excluded) to the
    /// opening's entry line next to the seam (included), on the floor. The neighbour's path
    /// starts on the line across the seam: the seam itself is not a point (the DARPA tiles'
    /// collision leaves a sliver open along some seams).
    pub exits: [Vec<[f64; 3]>; 4],
    /// The anchor's room: metres to the nearest line a body cannot stand on.
    pub anchor_room: f64,
    /// Per direction, every line of the path `exits` keeps points of (from the anchor,
    /// excluded, to the entry line, included), with its room: what a smoothed centreline may
    /// move within ([`crate::centrelines`]).
    pub lines: [Vec<Line>; 4],
}

/// A raster line on a tile's path, on its floor, and how far a body on it may move sideways
/// and still stand on drivable floor: metres to the nearest undrivable line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Line {
    pub point: [f64; 3],
    pub room: f64,
}

/// Each tile's axis, found when first asked for (`None`: the tile keeps its grid centre), in
/// a slot per cell of the grid.
#[derive(Debug)]
pub(crate) struct AxisCache {
    slots: Vec<OnceLock<Option<TileAxis>>>,
    rows: usize,
    cols: usize,
}

impl AxisCache {
    /// Empty slots for every cell of `world`'s grid.
    pub fn new(world: &World) -> AxisCache {
        let occ = &world.occupancy;
        AxisCache {
            slots: (0..occ.levels() * occ.rows() * occ.cols())
                .map(|_| OnceLock::new())
                .collect(),
            rows: occ.rows(),
            cols: occ.cols(),
        }
    }

    fn slot(&self, c: Cell) -> &OnceLock<Option<TileAxis>> {
        &self.slots[(c.level * self.rows + c.row) * self.cols + c.col]
    }
}

/// The axes of a world's tiles: its passages and the cache of what was found in them.
#[derive(Clone, Copy)]
pub(crate) struct Axes<'a> {
    world: &'a World,
    passages: &'a Passages<'a>,
    cache: &'a AxisCache,
}

impl<'a> Axes<'a> {
    /// The axes of `world`'s tiles in `passages` (the collision surface, or the grid: then no
    /// tile has one), kept in `cache`.
    pub fn new(world: &'a World, passages: &'a Passages<'a>, cache: &'a AxisCache) -> Self {
        Axes {
            world,
            passages,
            cache,
        }
    }

    /// The axis of the tile at `c`, found now if it was not yet.
    pub(crate) fn get(&self, c: Cell) -> Option<&'a TileAxis> {
        if matches!(self.passages, Passages::Grid(_)) || !*self.world.occupancy.get(c) {
            return None;
        }
        self.cache
            .slot(c)
            .get_or_init(|| tile::tile_axis(self.world, self.passages, c))
            .as_ref()
    }

    /// Finds the axes of `cells` (in parallel) that are not found yet.
    pub fn find(&self, cells: &[Cell]) {
        cells.par_iter().for_each(|&c| {
            self.get(c);
        });
    }

    /// Finds every tile's axis (in parallel).
    pub fn find_all(&self) {
        let cells: Vec<Cell> = self
            .world
            .occupancy
            .cells()
            .filter(|&c| *self.world.occupancy.get(c))
            .collect();
        self.find(&cells);
    }

    /// Tiles that keep their grid centre, among those found.
    #[cfg(test)]
    pub fn fallback(&self) -> usize {
        self.cache
            .slots
            .iter()
            .filter(|s| matches!(s.get(), Some(None)))
            .count()
    }

    /// Whether no tile found has an axis of its own (a world without a mesh).
    pub fn is_empty(&self) -> bool {
        !self
            .cache
            .slots
            .iter()
            .any(|s| matches!(s.get(), Some(Some(_))))
    }

    /// Every point of a tile's axis: its anchor and its paths to the openings (the grid
    /// centre alone for a tile without an axis).
    pub fn tile_points(&self, c: Cell) -> Vec<[f64; 3]> {
        match self.get(c) {
            Some(a) => std::iter::once(a.anchor)
                .chain(a.exits.iter().flatten().copied())
                .collect(),
            None => vec![self.world.cell_position(c)],
        }
    }

    /// A robot's way through a tile it enters from `from`: that opening's path to the anchor,
    /// the anchor, then the paths to the other openings (east, north, west, south); `None`
    /// for a tile without an axis or without that opening.
    pub fn walk_from(&self, c: Cell, from: Direction) -> Option<Vec<[f64; 3]>> {
        let a = self.get(c)?;
        let entry = &a.exits[from as usize];
        if entry.is_empty() {
            return None;
        }
        let mut walk: Vec<[f64; 3]> = entry.iter().rev().copied().collect();
        walk.push(a.anchor);
        for d in Direction::ALL.into_iter().filter(|&d| d != from) {
            walk.extend(a.exits[d as usize].iter().copied());
        }
        Some(walk)
    }

    /// Where a tile's node stands: its anchor, or the grid centre; a shaft's landing stands
    /// over the shaft's axis ([`Axes::collar`]).
    pub fn position(&self, c: Cell) -> [f64; 3] {
        self.collar(c).unwrap_or_else(|| self.anchor(c))
    }

    /// The tile's anchor (the drivable point its lines meet at), or the grid centre.
    pub fn anchor(&self, c: Cell) -> [f64; 3] {
        self.get(c)
            .map_or_else(|| self.world.cell_position(c), |a| a.anchor)
    }

    /// For the landing of a vertical shaft whose tile set lays its own axis (the procedural
    /// ones: the shaft is sunk round its foot cell's centre), the point over the shaft's axis
    /// at the landing's floor height (its anchor's): the shaft's collar. A robot coming up the
    /// shaft arrives there, and the straight line from the foot's node to it runs up the
    /// middle of the shaft, not across its wall (the drivable anchor nearest the axis is
    /// beside the hole, the radius and more away). `None` for anything else, and for tiles
    /// from mesh files (where the shaft's axis is the files').
    pub fn collar(&self, c: Cell) -> Option<[f64; 3]> {
        let world = self.world;
        if world.resolved.connections != Connections::Shaft {
            return None;
        }
        let shaft = world.shafts.iter().find(|s| s.landing == c)?;
        world.mesh()?.tile(c)?.axis.as_ref()?;
        let anchor = self.get(c)?.anchor;
        let [x, y, _] = world.cell_position(shaft.up);
        Some([x, y, anchor[2]])
    }

    /// The steepest grade of a tile's floor along its axis, degrees: rise over run from the
    /// anchor along each exit, between points at least [`GRADE_RUN`] metres apart horizontally
    /// (nearer points are merged, so rubble is not a grade). `None` without an axis.
    pub fn grade(&self, c: Cell) -> Option<f64> {
        let a = self.get(c)?;
        let mut worst: f64 = 0.0;
        for exit in &a.exits {
            let mut last = a.anchor;
            for &p in exit {
                let run = (p[0] - last[0]).hypot(p[1] - last[1]);
                if run >= GRADE_RUN {
                    worst = worst.max((p[2] - last[2]).abs().atan2(run).to_degrees());
                    last = p;
                }
            }
        }
        Some(worst)
    }

    /// The centreline through `cells` (consecutive cells of one corridor, or a shaft's two
    /// ends): anchors joined by each tile's path to the opening they share.
    pub fn polyline(&self, cells: &[Cell]) -> Vec<[f64; 3]> {
        let mut out: Vec<[f64; 3]> = Vec::new();
        let push = |p: [f64; 3], out: &mut Vec<[f64; 3]>| {
            if out.last() != Some(&p) {
                out.push(p);
            }
        };
        for (k, &c) in cells.iter().enumerate() {
            if k > 0 {
                let prev = cells[k - 1];
                if let (Some(d), Some(a)) = (towards(c, prev), self.get(c)) {
                    for &p in a.exits[d as usize].iter().rev() {
                        push(p, &mut out);
                    }
                }
            }
            push(self.position(c), &mut out);
            if let Some(&next) = cells.get(k + 1) {
                if let (Some(d), Some(a)) = (towards(c, next), self.get(c)) {
                    for &p in &a.exits[d as usize] {
                        push(p, &mut out);
                    }
                }
            }
        }
        out
    }
}

/// The floor line of the ramp joining `cells` (a ramp's foot and landing), when the world's
/// mesh has one.
pub(crate) fn ramp_line<'a>(world: &'a World, cells: &[Cell]) -> Option<&'a [[f64; 3]]> {
    let i = world
        .shafts
        .iter()
        .position(|s| cells.first() == Some(&s.up) && cells.last() == Some(&s.landing))?;
    world.mesh()?.ramps.get(i).map(Vec::as_slice)
}

/// Where a ramp's floor line leaves the level of `c`, when `c` is a ramp's foot or landing.
pub(crate) fn ramp_end(world: &World, c: Cell) -> Option<[f64; 2]> {
    let ramps = &world.mesh()?.ramps;
    let (i, s) = world
        .shafts
        .iter()
        .enumerate()
        .find(|(_, s)| s.up == c || s.landing == c)?;
    let line = ramps.get(i)?;
    let p = if s.up == c { line.first() } else { line.last() }?;
    Some([p[0], p[1]])
}

/// The direction of a step from `a` to its neighbour `b` on the same level.
pub(crate) fn towards(a: Cell, b: Cell) -> Option<Direction> {
    if a.level != b.level {
        return None;
    }
    let step = (b.row as i64 - a.row as i64, b.col as i64 - a.col as i64);
    Direction::ALL.into_iter().find(|d| {
        let (dr, dc) = d.step();
        (i64::from(dr), i64::from(dc)) == step
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::graph::EdgeKind;

    #[test]
    fn nodes_and_centrelines_stand_on_the_floor_of_the_passages() {
        let world = crate::tests::world_with_mesh();
        let passages = Passages::of(&world);
        let cache = AxisCache::new(&world);
        let axes = Axes::new(&world, &passages, &cache);
        axes.find_all();
        assert_eq!(axes.fallback(), 0, "every tile has an axis");
        let on_floor = |p: [f64; 3]| {
            passages
                .column(p[0], p[1])
                .iter()
                .any(|s| (s[0] - p[2]).abs() < 1e-9 && s[1] - s[0] >= BODY)
        };
        for n in &world.graph.nodes {
            // A shaft's landing stands over the shaft (its collar), its anchor on the floor.
            let p = axes.anchor(n.cell);
            assert!(on_floor(p), "node {} at {p:?}", n.id);
        }
        for e in world
            .graph
            .edges
            .iter()
            .filter(|e| e.kind == EdgeKind::Corridor)
        {
            let line = axes.polyline(&e.cells);
            assert!(
                line.len() > e.cells.len(),
                "the path follows the passage between anchors"
            );
            // A shaft landing's node stands over the shaft's hole (its collar).
            let collars: Vec<[f64; 3]> = e.cells.iter().filter_map(|&c| axes.collar(c)).collect();
            for p in line.into_iter().filter(|p| !collars.contains(p)) {
                // Free half a metre above it, on a floor at most a metre below it (seam
                // points carry the floor of the line next to the seam).
                let free = passages
                    .column(p[0], p[1])
                    .iter()
                    .any(|s| s[0] <= p[2] + 0.5 && p[2] + 0.5 <= s[1] && p[2] - s[0] < 1.0);
                assert!(free, "edge {} point {p:?}", e.id);
            }
        }
        // Without a mesh the axis is the grid's: cell centres.
        let grid = crate::tests::world();
        let passages = Passages::of(&grid);
        let cache = AxisCache::new(&grid);
        let axes = Axes::new(&grid, &passages, &cache);
        axes.find_all();
        assert!(axes.is_empty());
        let c = grid.start.unwrap();
        assert_eq!(axes.position(c), grid.cell_position(c));
    }
}
