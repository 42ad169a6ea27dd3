//! Where a condition is: the whole route, a level, a graph edge or node, or (dust) the cloud
//! the platform raises, as a volume a ray can be clipped against.
//!
//! An edge's volume is the union of capsules around its polyline (lifted to mid-height, 1.5 m
//! above the floor) of the condition's radius; a node's a sphere about it; a level's the slab
//! from 2 m under its lowest node to half way to the next level up (or 15 m over its highest
//! node); the route's everything. A ray's stretch inside is found in closed form (ray against
//! sphere, capsule, slab), not by stepping.

use serde::Serialize;
use subtgraph_core::vec3::{V3, dot, sub};

use crate::graph::RouteGraph;

/// A place as a `[[conditions]]` table's `at` names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Place {
    /// Everywhere the route goes.
    Route,
    /// About the platform, moving with it (dust it raises).
    Platform,
    /// Along a graph edge.
    Edge(usize),
    /// About a graph node.
    Node(usize),
    /// A level of the world.
    Level(usize),
}

impl Place {
    /// Reads `route`, `platform`, `edge N`, `node N` or `level N`.
    pub fn parse(text: &str) -> Result<Place, String> {
        let words: Vec<&str> = text.split_whitespace().collect();
        let number = |w: &str| {
            w.parse::<usize>()
                .map_err(|_| format!("'{w}' in at = \"{text}\" is not a whole number"))
        };
        match words.as_slice() {
            ["route"] => Ok(Place::Route),
            ["platform"] => Ok(Place::Platform),
            ["edge", n] => Ok(Place::Edge(number(n)?)),
            ["node", n] => Ok(Place::Node(number(n)?)),
            ["level", n] => Ok(Place::Level(number(n)?)),
            _ => Err(format!(
                "at = \"{text}\" is not a place: write \"route\", \"platform\", \"edge N\", \"node N\" or \"level N\" (N a graph id or level number)"
            )),
        }
    }

    /// Refuses a place the graph does not have.
    pub fn check(&self, graph: &RouteGraph) -> Result<(), String> {
        match *self {
            Place::Edge(e) if e >= graph.edges.len() => Err(format!(
                "edge {e} does not exist: the world's graph has edges 0 to {} (ground_truth/graph.json)",
                graph.edges.len().saturating_sub(1)
            )),
            Place::Node(n) if n >= graph.nodes.len() => Err(format!(
                "node {n} does not exist: the world's graph has nodes 0 to {} (ground_truth/graph.json)",
                graph.nodes.len().saturating_sub(1)
            )),
            Place::Level(l) if !graph.nodes.iter().any(|n| n.level == l) => {
                let top = graph.nodes.iter().map(|n| n.level).max().unwrap_or(0);
                Err(format!(
                    "level {l} does not exist: the world's levels are 0 to {top}"
                ))
            }
            _ => Ok(()),
        }
    }

    /// The place's name as written.
    pub fn name(&self) -> String {
        match self {
            Place::Route => "route".into(),
            Place::Platform => "platform".into(),
            Place::Edge(e) => format!("edge {e}"),
            Place::Node(n) => format!("node {n}"),
            Place::Level(l) => format!("level {l}"),
        }
    }
}

/// A place's volume in the world (the platform's cloud is not one: it moves; see
/// [`super::dust`]).
#[derive(Clone, Debug, PartialEq)]
pub enum Volume {
    /// All space.
    Everywhere,
    /// Between two heights.
    Slab {
        /// Bottom, metres.
        z0: f64,
        /// Top, metres.
        z1: f64,
    },
    /// A ball.
    Sphere {
        /// Centre.
        c: V3,
        /// Radius, metres.
        r: f64,
    },
    /// Capsules along a polyline.
    Tube {
        /// The segments' ends.
        segments: Vec<(V3, V3)>,
        /// Radius, metres.
        r: f64,
        /// Its bounding box, `[min, max]`.
        bounds: [V3; 2],
    },
}

/// Height of an edge's line and a node's centre above the floor, metres.
const MID_HEIGHT: f64 = 1.5;
/// The longest segment of an edge's tube, metres (its polyline, sampled every 0.4 m, is
/// thinned to segments about this long).
const SEGMENT: f64 = 2.0;

impl Volume {
    /// The volume of `place` (not the platform's) in `graph`, of radius `radius` for an edge
    /// or node.
    pub fn of(place: Place, graph: &RouteGraph, radius: f64) -> Volume {
        match place {
            Place::Route | Place::Platform => Volume::Everywhere,
            Place::Node(n) => {
                let p = graph.nodes[n].position;
                Volume::Sphere {
                    c: [p[0], p[1], p[2] + MID_HEIGHT],
                    r: radius,
                }
            }
            Place::Edge(e) => {
                let line = &graph.edges[e].polyline;
                let mut kept = vec![line[0]];
                for &p in &line[1..] {
                    let last = kept[kept.len() - 1];
                    if crate::frames::norm(sub(p, last)) >= SEGMENT {
                        kept.push(p);
                    }
                }
                if kept.len() == 1 || kept[kept.len() - 1] != line[line.len() - 1] {
                    kept.push(line[line.len() - 1]);
                }
                let lift = |p: V3| [p[0], p[1], p[2] + MID_HEIGHT];
                let segments: Vec<(V3, V3)> =
                    kept.windows(2).map(|w| (lift(w[0]), lift(w[1]))).collect();
                let mut bounds = [[f64::INFINITY; 3], [f64::NEG_INFINITY; 3]];
                for &(a, b) in &segments {
                    for p in [a, b] {
                        for k in 0..3 {
                            bounds[0][k] = bounds[0][k].min(p[k] - radius);
                            bounds[1][k] = bounds[1][k].max(p[k] + radius);
                        }
                    }
                }
                Volume::Tube {
                    segments,
                    r: radius,
                    bounds,
                }
            }
            Place::Level(l) => {
                let zs = |f: &dyn Fn(usize) -> bool| -> Vec<f64> {
                    graph
                        .nodes
                        .iter()
                        .filter(|n| f(n.level))
                        .map(|n| n.position[2])
                        .collect()
                };
                let own = zs(&|x| x == l);
                let lo = own.iter().copied().fold(f64::INFINITY, f64::min);
                let hi = own.iter().copied().fold(f64::NEG_INFINITY, f64::max);
                let above = zs(&|x| x != l)
                    .into_iter()
                    .filter(|&z| z > hi + 1.0)
                    .fold(f64::INFINITY, f64::min);
                let top = if above.is_finite() {
                    0.5 * (hi + above)
                } else {
                    hi + 15.0
                };
                Volume::Slab {
                    z0: lo - 2.0,
                    z1: top,
                }
            }
        }
    }

    /// Whether a point is inside.
    pub fn contains(&self, p: V3) -> bool {
        match self {
            Volume::Everywhere => true,
            Volume::Slab { z0, z1 } => p[2] >= *z0 && p[2] <= *z1,
            Volume::Sphere { c, r } => {
                let d = sub(p, *c);
                dot(d, d) <= r * r
            }
            Volume::Tube { segments, r, .. } => segments
                .iter()
                .any(|&(a, b)| point_segment_distance2(p, a, b) <= r * r),
        }
    }

    /// The stretch `[a, b]` of the ray `o + t d` (`d` a unit vector), `t` in `[0, end]`,
    /// inside; pushed onto `out` (a tube may give several, unsorted and overlapping).
    pub fn clip(&self, o: V3, d: V3, end: f64, out: &mut Vec<(f64, f64)>) {
        let mut push = |a: f64, b: f64| {
            let (a, b) = (a.max(0.0), b.min(end));
            if b > a {
                out.push((a, b));
            }
        };
        match self {
            Volume::Everywhere => push(0.0, end),
            Volume::Slab { z0, z1 } => {
                if d[2].abs() < 1e-12 {
                    if o[2] >= *z0 && o[2] <= *z1 {
                        push(0.0, end);
                    }
                } else {
                    let (t0, t1) = ((z0 - o[2]) / d[2], (z1 - o[2]) / d[2]);
                    push(t0.min(t1), t0.max(t1));
                }
            }
            Volume::Sphere { c, r } => {
                if let Some((a, b)) = ray_sphere(o, d, *c, *r) {
                    push(a, b);
                }
            }
            Volume::Tube {
                segments,
                r,
                bounds,
            } => {
                if ray_box(o, d, bounds, end).is_none() {
                    return;
                }
                for &(a, b) in segments {
                    if let Some((t0, t1)) = ray_capsule(o, d, a, b, *r) {
                        push(t0, t1);
                    }
                }
            }
        }
    }
}

/// The squared distance from `p` to the segment `a b`.
pub fn point_segment_distance2(p: V3, a: V3, b: V3) -> f64 {
    let ab = sub(b, a);
    let len2 = dot(ab, ab);
    let f = if len2 > 0.0 {
        (dot(sub(p, a), ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = [a[0] + f * ab[0], a[1] + f * ab[1], a[2] + f * ab[2]];
    let d = sub(p, q);
    dot(d, d)
}

/// Where the ray `o + t d` (unit `d`) is inside the ball about `c` of radius `r`.
pub fn ray_sphere(o: V3, d: V3, c: V3, r: f64) -> Option<(f64, f64)> {
    let oc = sub(o, c);
    let b = dot(oc, d);
    let disc = b * b - (dot(oc, oc) - r * r);
    if disc <= 0.0 {
        return None;
    }
    let s = disc.sqrt();
    Some((-b - s, -b + s))
}

/// Where the ray enters and leaves a box, within `[0, end]`.
fn ray_box(o: V3, d: V3, b: &[V3; 2], end: f64) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (0.0f64, end);
    for k in 0..3 {
        if d[k].abs() < 1e-12 {
            if o[k] < b[0][k] || o[k] > b[1][k] {
                return None;
            }
            continue;
        }
        let (a, c) = ((b[0][k] - o[k]) / d[k], (b[1][k] - o[k]) / d[k]);
        t0 = t0.max(a.min(c));
        t1 = t1.min(a.max(c));
    }
    (t1 > t0).then_some((t0, t1))
}

/// Where the ray `o + t d` (unit `d`) is inside the capsule of radius `r` about the segment
/// `a b`: the union of its cylinder and its two end balls, one interval as a capsule is
/// convex.
pub fn ray_capsule(o: V3, d: V3, a: V3, b: V3, r: f64) -> Option<(f64, f64)> {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    let mut take = |t: Option<(f64, f64)>| {
        if let Some((x, y)) = t {
            lo = lo.min(x);
            hi = hi.max(y);
        }
    };
    take(ray_sphere(o, d, a, r));
    take(ray_sphere(o, d, b, r));
    let ba = sub(b, a);
    let oa = sub(o, a);
    let baba = dot(ba, ba);
    if baba > 0.0 {
        let bard = dot(ba, d);
        let baoa = dot(ba, oa);
        let k2 = baba - bard * bard;
        let k1 = baba * dot(oa, d) - baoa * bard;
        let k0 = baba * dot(oa, oa) - baoa * baoa - r * r * baba;
        if k2 > 1e-12 {
            let disc = k1 * k1 - k2 * k0;
            if disc > 0.0 {
                let s = disc.sqrt();
                let (mut t0, mut t1) = ((-k1 - s) / k2, (-k1 + s) / k2);
                // Clip to between the end planes: 0 <= baoa + t bard <= baba.
                if bard.abs() > 1e-12 {
                    let (p0, p1) = ((0.0 - baoa) / bard, (baba - baoa) / bard);
                    t0 = t0.max(p0.min(p1));
                    t1 = t1.min(p0.max(p1));
                } else if baoa < 0.0 || baoa > baba {
                    t1 = t0 - 1.0;
                }
                if t1 > t0 {
                    take(Some((t0, t1)));
                }
            }
        }
    }
    (hi > lo).then_some((lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn places_read_and_bad_ones_say_what_to_write() {
        assert_eq!(Place::parse("edge 12"), Ok(Place::Edge(12)));
        assert_eq!(Place::parse(" level  1 "), Ok(Place::Level(1)));
        assert_eq!(Place::parse("route"), Ok(Place::Route));
        assert!(
            Place::parse("edge -1")
                .unwrap_err()
                .contains("whole number")
        );
        assert!(Place::parse("cave").unwrap_err().contains("\"edge N\""));
    }

    #[test]
    fn a_capsule_clip_agrees_with_sampling_the_ray() {
        let (a, b, r) = ([0.0, 0.0, 0.0], [4.0, 1.0, 0.5], 1.2);
        let mut seed = 1u64;
        for _ in 0..500 {
            let mut next = || {
                seed = crate::noise::hash(seed, 3);
                (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
            };
            let o = [next() * 6.0, next() * 6.0, next() * 3.0];
            let d = crate::frames::scale([next(), next(), next()], 1.0);
            let Some(d) = subtgraph_core::vec3::unit(d) else {
                continue;
            };
            let got = ray_capsule(o, d, a, b, r);
            // Sample the ray every 1 mm from -20 to 20 m.
            let inside: Vec<f64> = (-20_000..20_000)
                .map(|i| i as f64 * 1e-3)
                .filter(|&t| {
                    let p = [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]];
                    point_segment_distance2(p, a, b) <= r * r
                })
                .collect();
            match got {
                None => assert!(inside.len() <= 2, "{o:?} {d:?}: {}", inside.len()),
                Some((t0, t1)) => {
                    let (s0, s1) = (inside[0], inside[inside.len() - 1]);
                    assert!(
                        (t0 - s0).abs() < 2e-3 && (t1 - s1).abs() < 2e-3,
                        "{t0} {t1} {s0} {s1}"
                    );
                }
            }
        }
    }
}
