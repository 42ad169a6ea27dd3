//! Dripping water: drops falling from the roof in sparse lines, each a point a beam can hit.
//!
//! Water seeps through a roof at fixed places, so drips fall along the same vertical lines
//! again and again. A wet place gets `lines_per_10m` drip lines per 10 m of its passages'
//! centrelines (default 3), each offset up to 1 m to either side, from the roof (found by a
//! ray cast up) to the floor, releasing a drop every `interval_s` seconds on average (default
//! 0.5 s; each line's own interval is 0.5 to 1.5 times that, its phase drawn from the seed).
//! A drop falls freely, so it is in the air for `sqrt(2 H / g)` (0.9 s from a 4 m roof).
//!
//! A beam is not a line: it is `W0` wide at the sensor and widens by its divergence `DIV`
//! (an OS1's 0.18 degrees). A drop of radius `A` within the beam returns the share
//! `(A / w)^2` of it that it covers, as a target of reflectance `RHO` (a water sphere sends
//! much of the light back the way it came), so drops return points only close to the sensor
//! (within about 10 m) and beat the rock behind them closer still.

use subtgraph_core::rng::WorldRng;
use subtgraph_core::vec3::{V3, dot, sub};

use super::medium::Receiver;
use crate::graph::{EdgeKind, RouteGraph};
use crate::route::GRAVITY;
use crate::scene::Scene;

/// A drop's radius, metres.
pub const A: f64 = 0.002;
/// The beam's radius at the sensor, metres.
pub const W0: f64 = 0.005;
/// The beam's full divergence, radians (0.18 degrees).
pub const DIV: f64 = 0.0031;
/// A drop's reflectance as a target.
pub const RHO: f64 = 0.5;
/// Default drip lines per 10 m of passage.
pub const LINES_PER_10M: f64 = 3.0;
/// Default seconds between a line's drops.
pub const INTERVAL_S: f64 = 0.5;
/// Drops farther than this from the sensor are not looked at, metres (none returns from
/// there: see [`reach`]).
pub const REACH: f64 = 20.0;

/// One line drops fall along.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    /// Where, in the plane.
    pub xy: [f64; 2],
    /// The roof's height there.
    pub top: f64,
    /// The floor's.
    pub bottom: f64,
    /// Seconds between drops.
    pub interval: f64,
    /// When the first drop left, seconds.
    pub phase: f64,
}

impl Line {
    /// Seconds a drop takes to fall.
    pub fn fall(&self) -> f64 {
        (2.0 * (self.top - self.bottom).max(0.0) / GRAVITY).sqrt()
    }

    /// The drops in the air at time `t`.
    pub fn drops(&self, t: f64, out: &mut Vec<V3>) {
        let fall = self.fall();
        let first = ((t - fall - self.phase) / self.interval).ceil().max(0.0) as i64;
        let last = ((t - self.phase) / self.interval).floor() as i64;
        for m in first..=last {
            let age = t - (self.phase + m as f64 * self.interval);
            if (0.0..=fall).contains(&age) {
                out.push([self.xy[0], self.xy[1], self.top - 0.5 * GRAVITY * age * age]);
            }
        }
    }
}

/// The drip lines along `edges`: `per_10m` lines per 10 m, kept only where `keep` says.
pub fn lines(
    graph: &RouteGraph,
    scene: &Scene,
    edges: &[usize],
    per_10m: f64,
    interval: f64,
    keep: &dyn Fn(V3) -> bool,
    rng: &mut WorldRng,
) -> Vec<Line> {
    let spacing = 10.0 / per_10m;
    let mut out = Vec::new();
    for &e in edges {
        let edge = &graph.edges[e];
        if edge.kind == EdgeKind::Shaft {
            continue;
        }
        let mut carried = rng.float_in(0.0, spacing);
        for w in edge.polyline.windows(2) {
            let (a, b) = (w[0], w[1]);
            let seg = sub(b, a);
            let len = crate::frames::norm(seg);
            let mut s = carried;
            while s < len {
                let f = s / len;
                let p = [a[0] + f * seg[0], a[1] + f * seg[1], a[2] + f * seg[2]];
                let side = rng.float_in(-1.0, 1.0);
                let h = (seg[0] * seg[0] + seg[1] * seg[1]).sqrt().max(1e-9);
                let q = [
                    p[0] - side * seg[1] / h,
                    p[1] + side * seg[0] / h,
                    p[2] + 0.3,
                ];
                let my_interval = interval * rng.float_in(0.5, 1.5);
                let phase = rng.float_in(0.0, my_interval);
                let roof = scene.caster.cast(q, [0.0, 0.0, 1.0], 40.0);
                if let Some(roof) = roof
                    && keep(p)
                {
                    out.push(Line {
                        xy: [q[0], q[1]],
                        top: q[2] + roof.t - 0.05,
                        bottom: p[2],
                        interval: my_interval,
                        phase,
                    });
                }
                s += spacing;
            }
            carried = s - len;
        }
    }
    out
}

/// The distance within which a drop can return at all, for a receiver's floor.
pub fn reach(rx: &Receiver) -> f64 {
    // RHO (A / (r DIV / 2))^2 / (pi r^2) >= s_min, the beam's own width left out.
    (RHO * A * A * 4.0 / (DIV * DIV * std::f64::consts::PI * rx.s_min))
        .powf(0.25)
        .min(REACH)
}

/// The strongest drop echo on the ray `o + t d` (unit `d`) before `end`, among `drops`: its
/// range and signal.
pub fn echo(drops: &[V3], o: V3, d: V3, end: f64, rx: &Receiver) -> Option<(f64, f64)> {
    let mut best: Option<(f64, f64)> = None;
    for &p in drops {
        let op = sub(p, o);
        let t = dot(op, d);
        if t < rx.r1 || t >= end {
            continue;
        }
        let w = W0 + 0.5 * DIV * t;
        let miss2 = dot(op, op) - t * t;
        if miss2 > (w + A) * (w + A) {
            continue;
        }
        let share = (A / w).powi(2).min(1.0);
        let signal = RHO * share * rx.xi(t) / (std::f64::consts::PI * t * t);
        if best.is_none_or(|(_, s)| signal > s) {
            best = Some((t, signal));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_drop_falls_and_a_beam_through_it_returns_its_range() {
        let line = Line {
            xy: [3.0, 0.0],
            top: 4.0,
            bottom: 0.0,
            interval: 10.0,
            phase: 0.0,
        };
        let mut drops = Vec::new();
        line.drops(0.5, &mut drops);
        assert_eq!(drops.len(), 1);
        let z = drops[0][2];
        assert!((z - (4.0 - 0.5 * GRAVITY * 0.25)).abs() < 1e-12);
        drops.clear();
        line.drops(2.0, &mut drops);
        assert!(drops.is_empty(), "it has landed");
        line.drops(0.5, &mut drops);
        let rx = Receiver::of_range(0.8, 120.0);
        let (t, s) = echo(&drops, [0.0, 0.0, z], [1.0, 0.0, 0.0], 10.0, &rx).unwrap();
        assert!((t - 3.0).abs() < 1e-12 && s > rx.s_min);
        // A beam passing 5 cm away misses it.
        assert!(echo(&drops, [0.0, 0.05, z], [1.0, 0.0, 0.0], 10.0, &rx).is_none());
        assert!(reach(&rx) > 5.0 && reach(&rx) <= REACH);
    }
}
