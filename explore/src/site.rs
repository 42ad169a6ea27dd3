//! What the closed loop needs of a world, taken once from its survey and then owned: the
//! surfaces rays and bodies meet, where the base station and the robots start, and where the
//! artifacts are.
//!
//! Two ray casters, both the survey's (built once per world, shared through an `Arc`, so the
//! world itself can be dropped): the **collision surface** ([`WorldSurvey::rays`]), what a
//! robot's body, its floor and the radio's lines of sight meet, and the **scanned surface**
//! ([`WorldSurvey::scan_rays`]), what the LiDAR sees (the rock, and in a mine its services).
//!
//! The base station stands at the start tile's node (a dead end of level 0: the entrance),
//! its antenna [`ANTENNA`] above the floor, as the SubT competitions put theirs at the
//! entrance. Robots spawn along the start's passage, ahead of the base station, every
//! [`SPAWN_SPACING`] metres, facing along the passage, each where its body has the
//! platform's clearance.

use std::sync::Arc;

use subtgraph_core::artifacts::ArtifactClass;
use subtgraph_core::raycast::RayCaster;
use subtgraph_core::survey::Survey;
use subtgraph_survey::WorldSurvey;

use crate::body::Body;
use crate::error::ExploreError;

/// Height of every radio antenna above its floor, metres (the comms table's default).
pub const ANTENNA: f64 = 1.0;
/// Distance between neighbouring spawn spots along the start's passage, metres.
pub const SPAWN_SPACING: f64 = 2.5;
/// How far along the start's passage spawn spots are looked for, metres.
const SPAWN_REACH: f64 = 60.0;
/// The first spawn spot's distance from the base station, metres.
pub const SPAWN_FIRST: f64 = 3.0;

/// An artifact as the loop sees it.
#[derive(Clone, Debug, PartialEq)]
pub struct Artifact {
    /// Its id in `ground_truth/artifacts.json`.
    pub id: usize,
    /// Its class.
    pub class: ArtifactClass,
    /// The centre of its box, world frame (what a detection reports).
    pub centre: [f64; 3],
}

/// A pose on the plane with a height: where a robot stands and which way it faces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spawn {
    /// The body's reference point (on the floor for a ground robot, the body's centre for
    /// an aerial one), metres.
    pub position: [f64; 3],
    /// Heading, radians counter-clockwise from east.
    pub yaw: f64,
}

/// A world made ready for the loop.
#[derive(Clone)]
pub struct Site {
    /// The collision surface's hierarchy.
    pub collision: Arc<RayCaster>,
    /// What the LiDAR sees.
    pub scanned: Arc<RayCaster>,
    /// The artifacts (empty for a world without `[artifacts]`).
    pub artifacts: Vec<Artifact>,
    /// The start tile's node, on its floor.
    pub start: [f64; 3],
    /// The direction along the start's passage, away from its dead end, radians.
    pub heading: f64,
    /// The start's passage, from the start node on, points on its floor.
    pub passage: Vec<[f64; 3]>,
    /// The base station's antenna.
    pub base: [f64; 3],
    /// The collision surface's bounds, low and high corners.
    pub bounds: [[f64; 3]; 2],
    /// The world's seed.
    pub seed: u64,
    /// Levels.
    pub levels: usize,
    /// Metres between levels.
    pub level_height: f64,
}

impl Site {
    /// The site of a surveyed world with geometry.
    pub fn of(survey: &WorldSurvey<'_>) -> Result<Site, ExploreError> {
        let world = survey.world();
        let mesh = world.mesh().ok_or(ExploreError::NoMesh)?;
        let collision = Arc::clone(survey.rays().ok_or(ExploreError::NoMesh)?);
        let (scanned, _) = survey.scan_rays().ok_or(ExploreError::NoMesh)?;
        let scanned = Arc::clone(scanned);
        let start_cell = world.start.ok_or(ExploreError::NoStart)?;
        let start = survey.position(start_cell);
        // The start's passage: the centreline of the edge leaving the start node, oriented
        // away from it.
        let node = world.graph.nodes.iter().find(|n| n.cell == start_cell);
        let passage = node
            .and_then(|n| {
                world
                    .graph
                    .edges
                    .iter()
                    .zip(survey.edges())
                    .find(|(e, _)| e.from == n.id || e.to == n.id)
                    .map(|(e, line)| {
                        let mut points = line.points.clone();
                        if e.to == n.id {
                            points.reverse();
                        }
                        points
                    })
            })
            .unwrap_or_else(|| vec![start]);
        let ahead = passage
            .iter()
            .find(|p| (p[0] - start[0]).hypot(p[1] - start[1]) > 2.0)
            .copied()
            .unwrap_or([start[0] + 1.0, start[1], start[2]]);
        let heading = (ahead[1] - start[1]).atan2(ahead[0] - start[0]);
        let artifacts = survey
            .artifacts()
            .map(|placed| {
                placed
                    .artifacts
                    .iter()
                    .map(|a| Artifact {
                        id: a.id,
                        class: a.class,
                        centre: a.centre(),
                    })
                    .collect()
            })
            .unwrap_or_default();
        let (lo, hi) = mesh.collision.bounds().ok_or(ExploreError::NoMesh)?;
        Ok(Site {
            collision,
            scanned,
            artifacts,
            start,
            heading,
            passage,
            base: [start[0], start[1], start[2] + ANTENNA],
            bounds: [lo.map(f64::from), hi.map(f64::from)],
            seed: world.resolved.seed,
            levels: world.resolved.levels,
            level_height: world.resolved.level_height,
        })
    }

    /// Where `count` robots of `body` start: along the start's passage from
    /// [`SPAWN_FIRST`] metres, [`SPAWN_SPACING`] apart, each on its floor (an aerial robot at
    /// its altitude) with the body's clearance, facing along the passage.
    pub fn spawns(&self, body: &Body, count: usize) -> Result<Vec<Spawn>, ExploreError> {
        let mut out: Vec<Spawn> = Vec::with_capacity(count);
        let mut along = SPAWN_FIRST;
        while out.len() < count {
            if along > SPAWN_REACH {
                return Err(ExploreError::NoSpawn {
                    robot: out.len(),
                    searched_m: SPAWN_REACH,
                    platform: body.name,
                    clearance_m: body.clearance,
                });
            }
            let Some((p, yaw)) = point_along(&self.passage, along, self.heading) else {
                along += SPAWN_SPACING;
                continue;
            };
            along += SPAWN_SPACING;
            if let Some(position) = body.settle(&self.collision, p) {
                out.push(Spawn { position, yaw });
            }
        }
        Ok(out)
    }
}

/// The point `d` metres along a polyline and the heading of the piece it lies on (`heading`
/// for a polyline of one point); `None` past its end.
fn point_along(line: &[[f64; 3]], d: f64, heading: f64) -> Option<([f64; 3], f64)> {
    if line.len() < 2 {
        return (d == 0.0).then(|| (line[0], heading));
    }
    let mut left = d;
    for w in line.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2) + (b[2] - a[2]).powi(2)).sqrt();
        if len <= 0.0 {
            continue;
        }
        if left <= len {
            let t = left / len;
            let p = [
                a[0] + t * (b[0] - a[0]),
                a[1] + t * (b[1] - a[1]),
                a[2] + t * (b[2] - a[2]),
            ];
            return Some((p, (b[1] - a[1]).atan2(b[0] - a[0])));
        }
        left -= len;
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_along_a_polyline() {
        let line = [[0.0, 0.0, 0.0], [10.0, 0.0, 0.0], [10.0, 10.0, 0.0]];
        let (p, yaw) = point_along(&line, 15.0, 0.0).unwrap();
        assert!((p[0] - 10.0).abs() < 1e-12 && (p[1] - 5.0).abs() < 1e-12);
        assert!((yaw - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        assert!(point_along(&line, 20.5, 0.0).is_none());
    }
}
