//! `spawn-poses`: where several robots start and where each should go,
//! `ground_truth/spawn_poses.json`, for multi-robot exploration and planning benchmarks.
//!
//! Spawns are near the start tile (a dead end of level 0) and along the first tiles of its
//! corridor, nearest the tile centre first, all facing into the passage (along the start
//! tile's opening). Each stands on the floor, found by a downward cast from 1 m above the
//! level's nominal floor through the exact passages (the collision surface, or the grid's
//! floor without one), and keeps `clearance` metres (default 1.0) of free space around it: every
//! line within that radius (sampled every quarter of the clearance, at most 0.25 m) is free
//! from 0.3 m to 1.0 m above the robot's floor, the body of a ground robot. Robots are at
//! least `spacing` metres apart (default 2.0).
//!
//! Goals are the graph's nodes farthest from the start by path length over the graph
//! (corridors and shafts, metres), one per robot and distinct while there are enough nodes;
//! shaft ends are left out (they are passages between levels, not places). Each goal's yaw
//! is the heading in which the shortest path arrives.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use subtgraph_core::World;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter};
use subtgraph_core::grid::{Cell, Direction};
use subtgraph_core::survey::{Columns, Span, Survey};
use subtgraph_core::tile::TileKind;

use super::{FRAME, Settings};

/// The cast starts this far above the nominal floor.
const PROBE: f64 = 1.0;
/// The robot's body, metres above its floor, that must be free within the clearance.
const BODY: [f64; 2] = [0.3, 1.0];
/// Tiles of the start's corridor where robots may spawn.
const SPAWN_TILES: usize = 4;

/// Writes `ground_truth/spawn_poses.json`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpawnPoses {
    /// How many robots.
    pub robots: u32,
    /// Free radius around each robot, metres.
    pub clearance: f64,
    /// Least distance between two robots, metres.
    pub spacing: f64,
}

impl Default for SpawnPoses {
    fn default() -> Self {
        Self {
            robots: 4,
            clearance: 1.0,
            spacing: 2.0,
        }
    }
}

use subtgraph_schema::Pose;
type Goal = subtgraph_schema::Goal<&'static str>;
type Robot = subtgraph_schema::Robot<&'static str>;
type Document = subtgraph_schema::SpawnPoses<&'static str>;

fn yaw_of(d: Direction) -> f64 {
    use std::f64::consts::{FRAC_PI_2, PI};
    match d {
        Direction::East => 0.0,
        Direction::North => FRAC_PI_2,
        Direction::West => PI,
        Direction::South => -FRAC_PI_2,
    }
}

impl SpawnPoses {
    /// The keys it takes.
    pub const KEYS: [&str; 3] = ["robots", "clearance", "spacing"];

    /// From checked settings.
    pub fn from_settings(s: &Settings) -> SpawnPoses {
        let d = SpawnPoses::default();
        SpawnPoses {
            robots: s.robots.unwrap_or(d.robots),
            clearance: s.clearance.unwrap_or(d.clearance),
            spacing: s.spacing.unwrap_or(d.spacing),
        }
    }

    /// The spawn positions, nearest the start tile's centre first.
    fn spawns(
        &self,
        world: &World,
        survey: &dyn Survey,
        start: Cell,
    ) -> Result<Vec<[f64; 3]>, ExportError> {
        let pitch = world.resolved.tile_pitch;
        // The start tile and the next tiles of its corridor.
        let mut cells = world
            .graph
            .edges
            .iter()
            .find_map(|e| {
                if e.cells.first() == Some(&start) {
                    Some(e.cells.clone())
                } else if e.cells.last() == Some(&start) {
                    Some(e.cells.iter().rev().copied().collect())
                } else {
                    None
                }
            })
            .unwrap_or_else(|| vec![start]);
        cells.retain(|c| c.level == start.level);
        cells.truncate(SPAWN_TILES);
        let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
        for c in &cells {
            let p = world.cell_position(*c);
            b = [
                b[0].min(p[0] - 0.5 * pitch),
                b[1].min(p[1] - 0.5 * pitch),
                b[2].max(p[0] + 0.5 * pitch),
                b[3].max(p[1] + 0.5 * pitch),
            ];
        }
        let step = (0.25 * self.clearance).min(0.25);
        let cols = Columns {
            x0: b[0],
            y0: b[1],
            step,
            nx: ((b[2] - b[0]) / step).ceil() as usize,
            ny: ((b[3] - b[1]) / step).ceil() as usize,
        };
        let rows = survey
            .raster_within(&cols, b, |_, spans, open| {
                // A line through an open surface is never free.
                spans
                    .iter()
                    .filter(|s| open.binary_search(&s.i).is_err())
                    .copied()
                    .collect::<Vec<_>>()
            })
            .rows;
        let line = |i: usize, j: usize| -> &[Span] {
            let row = &rows[j];
            let a = row.partition_point(|s| (s.i as usize) < i);
            let n = row[a..].partition_point(|s| s.i as usize == i);
            &row[a..a + n]
        };
        // The cast starts above the floor of the start's own passage (its axis), which may lie
        // above or below the level's nominal floor.
        let nominal = survey.position(start)[2];
        let floor = |i: usize, j: usize| {
            let z = nominal + PROBE;
            line(i, j)
                .iter()
                .find(|s| s.z0 <= z && z <= s.z1)
                .map(|s| s.z0)
        };
        let body_free = |i: usize, j: usize, f: f64| {
            line(i, j)
                .iter()
                .any(|s| s.z0 <= f + BODY[0] && s.z1 >= f + BODY[1])
        };
        let reach = (self.clearance / step).ceil() as i64;
        let disc: Vec<(i64, i64)> = (-reach..=reach)
            .flat_map(|dj| (-reach..=reach).map(move |di| (di, dj)))
            .filter(|&(di, dj)| ((di * di + dj * dj) as f64).sqrt() * step <= self.clearance)
            .collect();
        let centre = survey.position(start);
        let mut candidates: Vec<(f64, usize, usize)> = (0..cols.ny)
            .flat_map(|j| (0..cols.nx).map(move |i| (i, j)))
            .filter(|&(i, j)| {
                world
                    .cell_at(start.level, cols.x(i), cols.y(j))
                    .is_some_and(|c| cells.contains(&c))
            })
            .map(|(i, j)| {
                let d = (cols.x(i) - centre[0]).powi(2) + (cols.y(j) - centre[1]).powi(2);
                (d, j, i)
            })
            .collect();
        candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then((a.1, a.2).cmp(&(b.1, b.2))));
        let mut placed: Vec<[f64; 3]> = Vec::new();
        for (_, j, i) in candidates {
            if placed.len() == self.robots as usize {
                break;
            }
            let (x, y) = (cols.x(i), cols.y(j));
            if placed
                .iter()
                .any(|p| (p[0] - x).hypot(p[1] - y) < self.spacing)
            {
                continue;
            }
            let Some(f) = floor(i, j) else { continue };
            let clear = disc.iter().all(|&(di, dj)| {
                let (ii, jj) = (i as i64 + di, j as i64 + dj);
                ii >= 0
                    && jj >= 0
                    && (ii as usize) < cols.nx
                    && (jj as usize) < cols.ny
                    && body_free(ii as usize, jj as usize, f)
            });
            if clear {
                placed.push([x, y, f]);
            }
        }
        if placed.len() < self.robots as usize {
            return Err(ExportError::Unsupported(format!(
                "spawn-poses: only {} of {} robots fit on the first {} tiles of the start's corridor with clearance = {} m and spacing = {} m; lower robots, clearance or spacing",
                placed.len(),
                self.robots,
                cells.len(),
                self.clearance,
                self.spacing
            )));
        }
        Ok(placed)
    }

    /// The goals: nodes by decreasing path length from the start node.
    fn goals(&self, world: &World, survey: &dyn Survey, start: Cell) -> Vec<Goal> {
        let g = &world.graph;
        let Some(source) = g.nodes.iter().position(|n| n.cell == start) else {
            return Vec::new();
        };
        let mut adjacent = vec![Vec::new(); g.nodes.len()];
        for e in &g.edges {
            adjacent[e.from].push((e.to, e.id));
            adjacent[e.to].push((e.from, e.id));
        }
        // A ramp is as long as its spiral (graph.json's length), not the level height.
        let lengths: Vec<f64> = survey.edges().iter().map(|e| e.length_m).collect();
        let mut dist = vec![f64::INFINITY; g.nodes.len()];
        let mut via = vec![usize::MAX; g.nodes.len()];
        dist[source] = 0.0;
        // Non-negative f64 order as their bits do; ties go to the smaller node id.
        let mut heap = BinaryHeap::from([Reverse((0u64, source))]);
        while let Some(Reverse((d, n))) = heap.pop() {
            let d = f64::from_bits(d);
            if d > dist[n] {
                continue;
            }
            for &(m, e) in &adjacent[n] {
                let nd = d + lengths[e];
                if nd < dist[m] {
                    dist[m] = nd;
                    via[m] = e;
                    heap.push(Reverse((nd.to_bits(), m)));
                }
            }
        }
        let mut order: Vec<usize> = (0..g.nodes.len())
            .filter(|&n| {
                n != source
                    && dist[n].is_finite()
                    && !matches!(g.nodes[n].kind, TileKind::ShaftUp | TileKind::ShaftLanding)
            })
            .collect();
        order.sort_by(|&a, &b| dist[b].total_cmp(&dist[a]).then(a.cmp(&b)));
        order.truncate(self.robots as usize);
        order
            .into_iter()
            .map(|n| {
                let node = &g.nodes[n];
                let [x, y, nominal] = survey.position(node.cell);
                let z = survey.floor(x, y, nominal, PROBE).unwrap_or(nominal);
                let e = &g.edges[via[n]];
                let (a, b) = if e.to == n {
                    (e.cells[e.cells.len() - 2], e.cells[e.cells.len() - 1])
                } else {
                    (e.cells[1], e.cells[0])
                };
                let (pa, pb) = (world.cell_position(a), world.cell_position(b));
                let (dx, dy) = (pb[0] - pa[0], pb[1] - pa[1]);
                let yaw = if dx == 0.0 && dy == 0.0 {
                    0.0
                } else {
                    dy.atan2(dx)
                };
                Goal {
                    node: n,
                    kind: node.kind.name(),
                    cell: node.cell,
                    path_length_m: dist[n],
                    pose: Pose::new([x, y, z], yaw),
                }
            })
            .collect()
    }
}

impl Exporter for SpawnPoses {
    fn export(
        &self,
        world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let start = world.start.ok_or_else(|| {
            ExportError::Unsupported("spawn-poses: the world has no start tile".into())
        })?;
        let openings = world.tiles.get(start).map_or(0, |t| t.openings);
        let facing = Direction::ALL
            .into_iter()
            .find(|d| openings & d.bit() != 0)
            .unwrap_or(Direction::East);
        let spawns = self.spawns(world, survey, start)?;
        let goals = self.goals(world, survey, start);
        if goals.is_empty() {
            return Err(ExportError::Unsupported(
                "spawn-poses: the graph has no node to go to besides the start".into(),
            ));
        }
        let goals_distinct = goals.len() >= spawns.len();
        let robots = spawns
            .into_iter()
            .enumerate()
            .map(|(k, p)| {
                let g = &goals[k % goals.len()];
                Robot {
                    name: format!("robot_{k}"),
                    spawn: Pose::new(p, yaw_of(facing)),
                    goal: Goal {
                        node: g.node,
                        kind: g.kind,
                        cell: g.cell,
                        path_length_m: g.path_length_m,
                        pose: Pose::new(g.pose.position, g.pose.yaw),
                    },
                }
            })
            .collect();
        let doc = Document {
            format: "subtgraph-spawn-poses/1",
            seed: world.resolved.seed,
            frame: FRAME,
            units: "metres; yaw in radians counter-clockwise from east (x) about z; quaternions x, y, z, w",
            source: survey.source().name(),
            start,
            robots_requested: self.robots,
            clearance_m: self.clearance,
            spacing_m: self.spacing,
            body_m: BODY,
            goals_distinct,
            robots,
        };
        crate::write_json(out, "ground_truth/spawn_poses.json", &doc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn robots_spawn_apart_on_the_floor_and_go_far() {
        let world = super::super::tests::world_with_mesh();
        let survey = crate::survey_of(&world);
        let survey: &dyn Survey = &survey;
        let start = world.start.unwrap();
        let sp = SpawnPoses::default();
        let spawns = sp.spawns(&world, survey, start).unwrap();
        assert_eq!(spawns.len(), 4);
        for (k, a) in spawns.iter().enumerate() {
            for b in &spawns[k + 1..] {
                assert!((a[0] - b[0]).hypot(a[1] - b[1]) >= sp.spacing);
            }
            // On the floor: the cast at this exact point, from just above it (floors slope),
            // finds the same height.
            let f = survey.floor(a[0], a[1], a[2], PROBE).unwrap();
            assert!((f - a[2]).abs() < 1e-9, "{a:?} vs {f}");
        }
        let goals = sp.goals(&world, survey, start);
        assert_eq!(goals.len(), 4);
        assert!(
            goals
                .windows(2)
                .all(|w| w[0].path_length_m >= w[1].path_length_m)
        );
        let too_many = SpawnPoses { robots: 200, ..sp };
        assert!(too_many.spawns(&world, survey, start).is_err());
    }
}
