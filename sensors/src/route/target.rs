//! Routes that go straight to what a study measures, starting there instead of at the
//! world's start: a dataset of shaft climbs or dusty junctions then costs seconds of sensor
//! time, not the minutes of corridor a route from the start drives first.
//!
//! - `shaft`: from the foot of the shaft nearest the world's start (by the graph, for a
//!   platform that flies), up to its landing, and back down: a still start at the foot for
//!   the IMU, then the climb at once.
//! - `edge:N`: from the end of edge N nearer the world's start, along it, and back.
//! - `node:N`: from the far end of node N's shortest edge, across N to the way straightest
//!   ahead, and back (into N and back out if it is a dead end).
//!
//! Each is refused, saying why and what to pass instead, where the platform cannot take it.

use super::{Leg, RouteKind, allowed, back};
use crate::error::SenseError;
use crate::graph::{EdgeKind, RouteGraph};
use crate::platform::{Kind, Platform};

/// The legs of a `shaft`, `edge:N` or `node:N` route; `dist` holds the shortest distances
/// from the world's start.
pub(super) fn legs(
    g: &RouteGraph,
    p: &Platform,
    kind: RouteKind,
    dist: &[f64],
) -> Result<Vec<Leg>, SenseError> {
    let no_route = |why: String, fix: &str| SenseError::NoRoute {
        route: kind.name(),
        why,
        fix: fix.to_owned(),
    };
    let out = match kind {
        RouteKind::Shaft => {
            if p.kind != Kind::Aerial {
                return Err(no_route(
                    "a ground robot cannot climb a shaft".into(),
                    "use --platform aerial",
                ));
            }
            // Each shaft by its foot (its lower end), the nearest foot first.
            let foot = |e: usize| {
                let edge = &g.edges[e];
                let low = g.nodes[edge.from].position[2] <= g.nodes[edge.to].position[2];
                if low { edge.from } else { edge.to }
            };
            let best = g
                .edges
                .iter()
                .filter(|e| e.kind == EdgeKind::Shaft && dist[foot(e.id)].is_finite())
                .min_by(|a, b| {
                    dist[foot(a.id)]
                        .total_cmp(&dist[foot(b.id)])
                        .then(a.id.cmp(&b.id))
                })
                .ok_or_else(|| {
                    no_route(
                        "the world has no shaft the platform can reach".into(),
                        "generate it with world.levels = 2 or more and world.connections = \"shaft\"",
                    )
                })?;
            vec![Leg {
                edge: best.id,
                reversed: foot(best.id) != best.from,
            }]
        }
        RouteKind::Edge(e) => {
            let edge = g.edges.get(e).ok_or_else(|| {
                no_route(
                    format!(
                        "edge {e} does not exist (the graph's edges are 0 to {})",
                        g.edges.len().saturating_sub(1)
                    ),
                    "pass an id from ground_truth/graph.json",
                )
            })?;
            if !allowed(p, edge.kind) {
                return Err(no_route(
                    format!("edge {e} is a shaft, which a ground robot cannot climb"),
                    "use --platform aerial, or another edge",
                ));
            }
            let reversed = dist[edge.to] < dist[edge.from];
            vec![Leg { edge: e, reversed }]
        }
        RouteKind::Node(n) => {
            if n >= g.nodes.len() {
                return Err(no_route(
                    format!(
                        "node {n} does not exist (the graph's nodes are 0 to {})",
                        g.nodes.len().saturating_sub(1)
                    ),
                    "pass an id from ground_truth/graph.json",
                ));
            }
            node_legs(g, p, n).ok_or_else(|| {
                no_route(
                    format!("node {n} has no passage this platform can take"),
                    "choose another node, or --platform aerial",
                )
            })?
        }
        _ => unreachable!("only target routes come here"),
    };
    let mut all = out.clone();
    all.extend(back(&out));
    Ok(all)
}

/// Into node `n` by its shortest edge (the platform is there soonest), and out by the edge
/// straightest ahead.
fn node_legs(g: &RouteGraph, p: &Platform, n: usize) -> Option<Vec<Leg>> {
    let edges: Vec<(usize, usize)> = g
        .neighbours(n)
        .filter(|&(e, _)| allowed(p, g.edges[e].kind))
        .collect();
    let into = edges.iter().map(|&(e, _)| e).min_by(|&a, &b| {
        g.edges[a]
            .length
            .total_cmp(&g.edges[b].length)
            .then(a.cmp(&b))
    })?;
    let edge = &g.edges[into];
    let leg_in = Leg {
        edge: into,
        reversed: edge.to != n,
    };
    // The heading the platform arrives with, and each way out's first heading.
    let line = &edge.polyline;
    let (a, b) = if leg_in.reversed {
        (line[1], line[0])
    } else {
        (line[line.len() - 2], line[line.len() - 1])
    };
    let arrive = [b[0] - a[0], b[1] - a[1]];
    let ahead = edges
        .iter()
        .filter(|&&(e, _)| e != into)
        .map(|&(e, _)| {
            let l = &g.edges[e].polyline;
            let reversed = g.edges[e].from != n;
            let (c, d) = if reversed {
                (l[l.len() - 1], l[l.len() - 2])
            } else {
                (l[0], l[1])
            };
            let leave = [d[0] - c[0], d[1] - c[1]];
            let cos = (arrive[0] * leave[0] + arrive[1] * leave[1])
                / ((arrive[0].hypot(arrive[1]) * leave[0].hypot(leave[1])).max(1e-12));
            (e, reversed, cos)
        })
        .max_by(|x, y| x.2.total_cmp(&y.2).then(y.0.cmp(&x.0)));
    let mut legs = vec![leg_in];
    if let Some((e, reversed, _)) = ahead {
        legs.push(Leg { edge: e, reversed });
    }
    Some(legs)
}
