//! Which edges a route takes, in which order: searches over the graph, before any geometry.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use subtgraph_core::rng::WorldRng;

use super::{Leg, RouteKind, allowed, back};
use crate::error::SenseError;
use crate::graph::RouteGraph;
use crate::platform::{Kind, Platform};

/// Shortest distances (metres) from `from` over the edges the platform takes, and the edge each
/// node was reached by. Ties go to the lower node id, so the result is the same every run.
pub(super) fn dijkstra(
    g: &RouteGraph,
    p: &Platform,
    from: usize,
) -> (Vec<f64>, Vec<Option<usize>>) {
    let n = g.nodes.len();
    let mut dist = vec![f64::INFINITY; n];
    let mut via = vec![None; n];
    let mut heap = BinaryHeap::new();
    dist[from] = 0.0;
    // Distances in millimetres as integers: a total order with no float ties.
    heap.push(Reverse((0u64, from)));
    while let Some(Reverse((d, u))) = heap.pop() {
        if d > (dist[u] * 1000.0).round() as u64 {
            continue;
        }
        for (e, v) in g.neighbours(u) {
            if !allowed(p, g.edges[e].kind) {
                continue;
            }
            let nd = dist[u] + g.edges[e].length.max(0.001);
            if nd < dist[v] {
                dist[v] = nd;
                via[v] = Some(e);
                heap.push(Reverse(((nd * 1000.0).round() as u64, v)));
            }
        }
    }
    (dist, via)
}

/// The legs from `from` to `to` along the tree `via` grew from `from`.
fn path(g: &RouteGraph, via: &[Option<usize>], from: usize, to: usize) -> Vec<Leg> {
    let mut legs = Vec::new();
    let mut at = to;
    while at != from {
        let e = via[at].expect("reachable");
        let edge = &g.edges[e];
        let (prev, reversed) = if edge.to == at {
            (edge.from, false)
        } else {
            (edge.to, true)
        };
        legs.push(Leg { edge: e, reversed });
        at = prev;
    }
    legs.reverse();
    legs
}

/// The legs of a route of `kind` from the graph's start.
pub(super) fn legs(
    g: &RouteGraph,
    p: &Platform,
    kind: RouteKind,
    rng: &mut WorldRng,
) -> Result<Vec<Leg>, SenseError> {
    let start = g.start;
    let (dist, via) = dijkstra(g, p, start);
    let no_route = |why: &str, fix: &str| SenseError::NoRoute {
        route: kind.name().to_owned(),
        why: why.to_owned(),
        fix: fix.to_owned(),
    };
    let farthest = |pick: &dyn Fn(usize) -> bool| {
        (0..g.nodes.len())
            .filter(|&i| i != start && dist[i].is_finite() && pick(i))
            .max_by(|&a, &b| dist[a].total_cmp(&dist[b]).then(b.cmp(&a)))
    };
    match kind {
        RouteKind::OutAndBack => {
            let target = farthest(&|i| g.nodes[i].kind == "dead-end")
                .or_else(|| farthest(&|_| true))
                .ok_or_else(|| {
                    no_route(
                        "the start is the only place this platform can reach",
                        "choose a world with passages from its start",
                    )
                })?;
            let out = path(g, &via, start, target);
            let mut all = out.clone();
            all.extend(back(&out));
            Ok(all)
        }
        RouteKind::Levels => {
            let level = g.nodes[start].level;
            let spread = |i: usize| g.nodes[i].level.abs_diff(level);
            let best = (0..g.nodes.len())
                .filter(|&i| dist[i].is_finite())
                .map(spread)
                .max()
                .unwrap_or(0);
            if best == 0 {
                let (why, fix) = if g.nodes.iter().all(|n| n.level == level) {
                    (
                        "the world has one level",
                        "generate it with world.levels = 2 or more",
                    )
                } else if p.kind == Kind::Ground {
                    (
                        "its levels are joined by shafts, which a ground robot cannot drive",
                        "use --platform aerial, or a world with world.connections = \"ramp\"",
                    )
                } else {
                    (
                        "no other level is reachable from the start",
                        "choose another world",
                    )
                };
                return Err(no_route(why, fix));
            }
            let target = farthest(&|i| spread(i) == best).expect("a node on that level");
            let out = path(g, &via, start, target);
            let mut all = out.clone();
            all.extend(back(&out));
            Ok(all)
        }
        RouteKind::Loop => {
            let cycle = cycle(g, p, start).ok_or_else(|| {
                no_route(
                    "the part of the world this platform can reach has no loop",
                    "use --route out-and-back or coverage, or generate the world with topology.loops of 1 or more",
                )
            })?;
            let mut cycle = cycle;
            if rng.coin() {
                // The other way round.
                cycle = back(&cycle);
                // Entered at the same node: rotate so it starts there again.
                let entry = leg_start(g, &cycle[cycle.len() - 1]);
                let first = cycle
                    .iter()
                    .position(|l| leg_start(g, l) == entry)
                    .unwrap_or(0);
                cycle.rotate_left(first);
            }
            let entry = leg_start(g, &cycle[0]);
            let out = path(g, &via, start, entry);
            let mut all = out.clone();
            all.extend(cycle);
            all.extend(back(&out));
            Ok(all)
        }
        RouteKind::Shaft | RouteKind::Edge(_) | RouteKind::Node(_) => {
            super::target::legs(g, p, kind, &dist)
        }
        RouteKind::Coverage => {
            let mut done = vec![false; g.edges.len()];
            let mut legs = Vec::new();
            cover(g, p, start, &mut done, &mut legs, rng);
            if legs.is_empty() {
                return Err(no_route(
                    "the start is the only place this platform can reach",
                    "choose a world with passages from its start",
                ));
            }
            Ok(legs)
        }
    }
}

/// The node a leg starts at.
pub(super) fn leg_start(g: &RouteGraph, l: &Leg) -> usize {
    let e = &g.edges[l.edge];
    if l.reversed { e.to } else { e.from }
}

/// Every edge reachable from `at`, depth first: each one driven out and back (a closed walk
/// that returns to `at`). Neighbours are taken in a seeded order.
fn cover(
    g: &RouteGraph,
    p: &Platform,
    at: usize,
    done: &mut [bool],
    legs: &mut Vec<Leg>,
    rng: &mut WorldRng,
) {
    let mut next: Vec<(usize, usize)> = g
        .neighbours(at)
        .filter(|&(e, _)| allowed(p, g.edges[e].kind))
        .collect();
    rng.shuffle(&mut next);
    for (e, v) in next {
        if done[e] {
            continue;
        }
        done[e] = true;
        let reversed = g.edges[e].to == at && g.edges[e].from != at;
        legs.push(Leg { edge: e, reversed });
        // A node already visited is not explored again from here: drive back at once.
        let visited = legs[..legs.len() - 1].iter().any(|l| leg_start(g, l) == v);
        if !visited && v != at {
            cover(g, p, v, done, legs, rng);
        }
        legs.push(Leg {
            edge: e,
            reversed: !reversed,
        });
    }
}

/// A cycle of the graph the platform can drive (as legs from and back to one node), the one
/// nearest the start found by a depth-first search from it.
fn cycle(g: &RouteGraph, p: &Platform, start: usize) -> Option<Vec<Leg>> {
    let n = g.nodes.len();
    let mut parent: Vec<Option<(usize, usize)>> = vec![None; n];
    let mut seen = vec![false; n];
    // Iterative DFS from the start; the first edge to a node already seen closes a cycle.
    let mut stack = vec![(start, None)];
    while let Some((u, from)) = stack.pop() {
        if seen[u] {
            continue;
        }
        seen[u] = true;
        parent[u] = from;
        let via = from.map_or(usize::MAX, |(_, e)| e);
        for (e, v) in g.neighbours(u) {
            if e == via || !allowed(p, g.edges[e].kind) {
                continue;
            }
            if seen[v] {
                // u .. v along the tree, then the edge back: find their common ancestor.
                let ancestors = |mut x: usize| {
                    let mut list = vec![x];
                    while let Some((px, _)) = parent[x] {
                        x = px;
                        list.push(x);
                    }
                    list
                };
                let (au, av) = (ancestors(u), ancestors(v));
                let common = *au.iter().find(|x| av.contains(x))?;
                // common -> ... -> u, the edge u -> v, v -> ... -> common.
                let mut down: Vec<Leg> = Vec::new();
                let mut x = u;
                while x != common {
                    let (px, pe) = parent[x]?;
                    down.push(Leg {
                        edge: pe,
                        reversed: g.edges[pe].to != x,
                    });
                    x = px;
                }
                down.reverse();
                down.push(Leg {
                    edge: e,
                    reversed: g.edges[e].from != u,
                });
                let mut x = v;
                while x != common {
                    let (px, pe) = parent[x]?;
                    down.push(Leg {
                        edge: pe,
                        reversed: g.edges[pe].from != x,
                    });
                    x = px;
                }
                return Some(down);
            }
            stack.push((v, Some((u, e))));
        }
    }
    None
}
