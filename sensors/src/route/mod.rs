//! Routes over the ground-truth graph: which edges, in what order ([`plan`]), the path along
//! them (`path`), and when the platform is where (`timing`), as a [`Trajectory`] with a
//! label for every moment.
//!
//! The routes, as `--route` names them:
//! - `out-and-back` (the default): from the start to the farthest dead end the platform can
//!   reach, a turn in place, and back the same way (a turn-around, then the way out seen
//!   backwards: what broke FAST-LIO in the paper's backtracking case);
//! - `loop`: to the nearest loop, once around it (a loop closure), and back;
//! - `levels`: to the farthest node of the level farthest from the start's, by ramps for a
//!   ground robot or up shafts along their axis for an aerial one, and back;
//! - `coverage`: every edge the platform can take, depth first, each driven out and back;
//! - `shaft`, `edge:N`, `node:N`: straight to what a study measures, starting there rather
//!   than at the world's start (see `target`): the shaft nearest the start, climbed and
//!   flown back down; edge N driven end to end and back; node N crossed from its shortest
//!   edge and back.
//!
//! The seed picks what is left to chance: the way round a loop, the side a turn-around turns
//! to, the order coverage takes a junction's edges in.

mod path;
mod plan;
mod target;
mod timing;

use serde::Serialize;
use subtgraph_core::rng::WorldRng;

use crate::error::SenseError;
use crate::graph::{EdgeKind, RouteGraph};
use crate::platform::{Kind, Platform};
use crate::scene::Scene;
use crate::trajectory::Trajectory;

pub use timing::GRAVITY;

/// A route's kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RouteKind {
    /// To the farthest dead end and back.
    OutAndBack,
    /// Around a loop.
    Loop,
    /// Across levels.
    Levels,
    /// Every edge.
    Coverage,
    /// Up the shaft nearest the start and back down (aerial).
    Shaft,
    /// Along one edge and back.
    Edge(usize),
    /// Across one node and back.
    Node(usize),
}

/// The names `--route` takes, in [`RouteKind`] order (`edge:N` and `node:N` with a graph id).
pub const NAMES: [&str; 7] = [
    "out-and-back",
    "loop",
    "levels",
    "coverage",
    "shaft",
    "edge:N",
    "node:N",
];

impl RouteKind {
    /// A route kind by its name.
    pub fn named(name: &str) -> Result<RouteKind, SenseError> {
        match name {
            "out-and-back" => Ok(RouteKind::OutAndBack),
            "loop" => Ok(RouteKind::Loop),
            "levels" => Ok(RouteKind::Levels),
            "coverage" => Ok(RouteKind::Coverage),
            "shaft" => Ok(RouteKind::Shaft),
            other if other.starts_with("edge:") || other.starts_with("node:") => {
                let id = other[5..]
                    .parse::<usize>()
                    .map_err(|_| SenseError::Unknown {
                        what: "route",
                        name: other.to_owned(),
                        known: format!("{} (N a graph id, like edge:12)", NAMES.join(", ")),
                    })?;
                Ok(if other.starts_with("edge:") {
                    RouteKind::Edge(id)
                } else {
                    RouteKind::Node(id)
                })
            }
            other => Err(SenseError::Unknown {
                what: "route",
                name: other.to_owned(),
                known: NAMES.join(", "),
            }),
        }
    }

    /// Its name.
    pub fn name(self) -> String {
        match self {
            RouteKind::OutAndBack => NAMES[0].into(),
            RouteKind::Loop => NAMES[1].into(),
            RouteKind::Levels => NAMES[2].into(),
            RouteKind::Coverage => NAMES[3].into(),
            RouteKind::Shaft => NAMES[4].into(),
            RouteKind::Edge(e) => format!("edge:{e}"),
            RouteKind::Node(n) => format!("node:{n}"),
        }
    }
}

/// One edge driven in one direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Leg {
    /// The edge's id.
    pub edge: usize,
    /// Driven from its `to` node to its `from` node.
    pub reversed: bool,
}

/// Whether the platform can take an edge.
fn allowed(platform: &Platform, kind: EdgeKind) -> bool {
    kind != EdgeKind::Shaft || platform.kind == Kind::Aerial
}

/// The same legs driven back.
fn back(legs: &[Leg]) -> Vec<Leg> {
    legs.iter()
        .rev()
        .map(|l| Leg {
            edge: l.edge,
            reversed: !l.reversed,
        })
        .collect()
}

/// What the platform is doing.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Phase {
    /// Standing still (the start, for IMU initialisation, and the end).
    Still,
    /// Moving along a corridor.
    Drive,
    /// Turning in place (at a dead end, or to go back the way it came).
    TurnAround,
    /// At a junction (a T-junction or an intersection).
    Junction,
    /// In a shaft.
    Shaft,
    /// On a ramp.
    Ramp,
    /// Over a floor hazard (rubble, a drop's rim).
    Hazard,
}

/// Where on the route a moment is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Mark {
    /// Index into the route's legs.
    pub leg: Option<u32>,
    /// The graph node it is at, if any (within a quarter of a tile pitch of it).
    pub node: Option<u32>,
    /// What the platform is doing.
    pub phase: Phase,
}

impl Mark {
    fn still(leg: usize) -> Mark {
        Mark {
            leg: Some(leg as u32),
            node: None,
            phase: Phase::Still,
        }
    }
}

/// A planned route: its legs and the trajectory along them, with a mark per control point.
#[derive(Clone, Debug)]
pub struct Route {
    /// Which route.
    pub kind: RouteKind,
    /// The edges, in order.
    pub legs: Vec<Leg>,
    /// The graph nodes passed, in order (the start first).
    pub nodes: Vec<usize>,
    /// The platform's `base_link` over time.
    pub trajectory: Trajectory,
    /// What the platform does at each control point of the trajectory.
    pub marks: Vec<Mark>,
    /// Length driven, metres.
    pub length: f64,
}

impl Route {
    /// What the platform is doing at time `t`.
    pub fn mark(&self, t: f64) -> Mark {
        // Control point k shapes the spline most around time (k - 2.5) dt.
        let k = (t / self.trajectory.step() + 2.5).round() as usize;
        self.marks[k.min(self.marks.len() - 1)]
    }
}

/// Plans a route of `kind` for `platform` in a world.
pub fn plan(
    graph: &RouteGraph,
    scene: &Scene,
    platform: &Platform,
    kind: RouteKind,
    seed: u64,
) -> Result<Route, SenseError> {
    let mut rng = WorldRng::new(seed, "route", 0);
    let legs = plan::legs(graph, platform, kind, &mut rng)?;
    let stretches = path::stretches(graph, scene, platform, &legs)?;
    let timed = timing::control_points(&stretches, platform, &mut rng);
    let first = legs
        .first()
        .map_or(graph.start, |l| plan::leg_start(graph, l));
    let mut nodes = vec![first];
    for l in &legs {
        let e = &graph.edges[l.edge];
        nodes.push(if l.reversed { e.from } else { e.to });
    }
    let length: f64 = stretches
        .iter()
        .flat_map(|s| s.windows(2))
        .map(|w| crate::frames::norm(subtgraph_core::vec3::sub(w[1].p, w[0].p)))
        .sum();
    let mut marks = timed.marks;
    let radius = 0.25 * scene.tile_pitch;
    for (m, c) in marks.iter_mut().zip(&timed.control) {
        let p = [c[0], c[1], c[2]];
        let Some(leg) = m.leg else { continue };
        let leg = legs[leg as usize];
        let e = &graph.edges[leg.edge];
        // The nearer end node, if near enough.
        let near = [e.from, e.to]
            .into_iter()
            .map(|n| {
                let q = graph.nodes[n].position;
                let d = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt();
                (n, d, (p[2] - q[2]).abs())
            })
            .filter(|&(_, d, dz)| d <= radius && dz <= 3.0 + platform.altitude)
            .min_by(|a, b| a.1.total_cmp(&b.1));
        m.node = near.map(|(n, _, _)| n as u32);
        if m.phase != Phase::Drive {
            continue;
        }
        m.phase = match e.kind {
            EdgeKind::Shaft => Phase::Shaft,
            EdgeKind::Ramp => Phase::Ramp,
            EdgeKind::Corridor => {
                let junction = near.is_some_and(|(n, _, _)| {
                    matches!(
                        graph.nodes[n].kind.as_str(),
                        "t-junction" | "intersection" | "junction"
                    )
                });
                if junction {
                    Phase::Junction
                } else if scene.at_hazard(p) {
                    Phase::Hazard
                } else {
                    Phase::Drive
                }
            }
        };
    }
    Ok(Route {
        kind,
        legs,
        nodes,
        trajectory: Trajectory::new(timing::DT, timed.control),
        marks,
        length,
    })
}
