//! The route's geometry: the graph's polylines joined leg by leg, lifted to the platform's
//! height, shafts replaced by their axis, smoothed, and checked against the rock.
//!
//! The graph's polylines follow the middle of each passage on a raster of about 0.4 m, so
//! they zigzag; a platform driven along them would jerk at every step. The path is resampled
//! every [`STEP`] metres and smoothed with a Gaussian of [`SMOOTH`] metres (ends held, so a
//! stop stays where it is). Smoothing cuts corners, so every sample is checked for the
//! platform's clearance with the ray caster's nearest-point query; where a sample is too close
//! to the rock, the smoothing is taken back there (blended towards the graph's own line, which
//! keeps to the middle of the passage), and where even the graph's line is too close, the
//! route does not fit and says where.

use subtgraph_core::vec3::V3;

use super::Leg;
use crate::error::SenseError;
use crate::frames::norm;
use crate::graph::{EdgeKind, RouteGraph};
use crate::platform::{Kind, Platform};
use crate::scene::Scene;

/// Metres between path samples.
pub(super) const STEP: f64 = 0.2;
/// The smoothing's standard deviation, metres.
const SMOOTH: f64 = 1.5;

/// A point of the path and which leg it is on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Sample {
    /// The platform's reference point (a ground robot's on the floor, an aerial one's centre).
    pub p: V3,
    /// Index into the route's legs.
    pub leg: usize,
}

/// A stretch driven without stopping: from a stop to the next (the start, a turn-around, the
/// end).
pub(super) type Stretch = Vec<Sample>;

/// The stretches of a route, smoothed and checked.
pub(super) fn stretches(
    g: &RouteGraph,
    scene: &Scene,
    platform: &Platform,
    legs: &[Leg],
) -> Result<Vec<Stretch>, SenseError> {
    let mut out = Vec::new();
    let mut raw: Vec<Sample> = Vec::new();
    for (i, leg) in legs.iter().enumerate() {
        let line = leg_line(g, scene, platform, leg)?;
        let skip = usize::from(!raw.is_empty());
        raw.extend(line.into_iter().skip(skip).map(|p| Sample { p, leg: i }));
        let turns = legs
            .get(i + 1)
            .is_some_and(|next| next.edge == leg.edge && next.reversed != leg.reversed);
        if turns || i + 1 == legs.len() {
            out.push(finish(std::mem::take(&mut raw), scene, platform, g, legs)?);
        }
    }
    Ok(out)
}

/// A leg's line at the platform's height, from where it starts to where it ends.
fn leg_line(
    g: &RouteGraph,
    scene: &Scene,
    platform: &Platform,
    leg: &Leg,
) -> Result<Vec<V3>, SenseError> {
    let e = &g.edges[leg.edge];
    let mut line: Vec<V3> = if platform.kind == Kind::Aerial && e.kind == EdgeKind::Shaft {
        shaft_line(scene, platform, &e.polyline)
    } else if platform.kind == Kind::Aerial {
        e.polyline
            .iter()
            .map(|&p| [p[0], p[1], p[2] + flying_height(scene, platform, p)])
            .collect()
    } else {
        e.polyline.clone()
    };
    if leg.reversed {
        line.reverse();
    }
    Ok(line)
}

/// How high above the floor point `p` to fly: the platform's altitude, or half the free
/// height where the passage is lower than twice that.
fn flying_height(scene: &Scene, platform: &Platform, p: V3) -> f64 {
    let from = [p[0], p[1], p[2] + 0.1];
    let up = scene
        .caster
        .cast(from, [0.0, 0.0, 1.0], 4.0 * platform.altitude)
        .map_or(f64::INFINITY, |h| h.t + 0.1);
    platform.altitude.min(0.5 * up)
}

/// A shaft climbed along its axis: from the foot at flying height, up the axis measured on
/// the rock, to the landing at flying height.
fn shaft_line(scene: &Scene, platform: &Platform, polyline: &[V3]) -> Vec<V3> {
    let (foot, landing) = (polyline[0], polyline[polyline.len() - 1]);
    let lift = |p: V3| [p[0], p[1], p[2] + flying_height(scene, platform, p)];
    let (bottom, top) = (lift(foot), lift(landing));
    let mut line = vec![bottom];
    let rise = top[2] - bottom[2];
    let steps = (rise.abs() / 1.0).ceil().max(1.0) as usize;
    for k in 0..=steps {
        let f = k as f64 / steps as f64;
        let guess = [
            bottom[0] + f * (top[0] - bottom[0]),
            bottom[1] + f * (top[1] - bottom[1]),
            bottom[2] + f * rise,
        ];
        line.push(axis_at(scene, guess));
    }
    line.push(top);
    line
}

/// The middle of a shaft's section through `guess`: the mean of where 32 horizontal rays from
/// it meet the rock, twice over (the second from the first's middle).
fn axis_at(scene: &Scene, guess: V3) -> V3 {
    let mut c = guess;
    for _ in 0..2 {
        let (mut sx, mut sy, mut n) = (0.0, 0.0, 0.0);
        for k in 0..32 {
            let a = k as f64 / 32.0 * std::f64::consts::TAU;
            let d = [a.cos(), a.sin(), 0.0];
            if let Some(h) = scene.caster.cast(c, d, 30.0) {
                sx += c[0] + h.t * d[0];
                sy += c[1] + h.t * d[1];
                n += 1.0;
            }
        }
        if n < 24.0 {
            // Open to one side (the shaft meets a passage): keep the guess.
            return c;
        }
        c = [sx / n, sy / n, c[2]];
    }
    c
}

/// Resamples a stretch, smooths it and makes it fit.
fn finish(
    raw: Vec<Sample>,
    scene: &Scene,
    platform: &Platform,
    g: &RouteGraph,
    legs: &[Leg],
) -> Result<Stretch, SenseError> {
    let line = resample(&raw);
    let smooth = gaussian(&line);
    // Where the smoothed line is too close to the rock, blend back towards the raw one.
    let mut weight = vec![1.0f64; line.len()];
    let window = (SMOOTH / STEP).ceil() as usize * 2;
    for _ in 0..6 {
        let blended: Vec<V3> = (0..line.len())
            .map(|i| lerp(line[i].p, smooth[i], weight[i]))
            .collect();
        let bad: Vec<usize> = (0..line.len())
            .filter(|&i| tight(scene, platform, blended[i]).is_some())
            .collect();
        if bad.is_empty() {
            return Ok(blended
                .into_iter()
                .zip(&line)
                .map(|(p, s)| Sample { p, leg: s.leg })
                .collect());
        }
        for &i in &bad {
            for w in &mut weight[i.saturating_sub(window)..(i + window + 1).min(line.len())] {
                *w *= 0.3;
            }
        }
    }
    // Even nearly the graph's own line is too close: say where.
    let worst = (0..line.len())
        .filter_map(|i| tight(scene, platform, line[i].p).map(|free| (i, free)))
        .min_by(|a, b| a.1.total_cmp(&b.1));
    let (i, free) = worst.unwrap_or((0, 0.0));
    Err(SenseError::DoesNotFit {
        platform: platform.name,
        at: line[i].p,
        edge: Some(legs[line[i].leg].edge).filter(|&e| e < g.edges.len()),
        free,
        needed: platform.clearance,
    })
}

/// The free radius about the platform's clearance point at `p`, when it is less than the
/// platform needs.
pub(super) fn tight(scene: &Scene, platform: &Platform, p: V3) -> Option<f64> {
    let c = [p[0], p[1], p[2] + platform.clearance_height];
    scene
        .caster
        .nearest(c, platform.clearance)
        .map(|n| n.distance)
}

fn lerp(a: V3, b: V3, w: f64) -> V3 {
    [
        a[0] + w * (b[0] - a[0]),
        a[1] + w * (b[1] - a[1]),
        a[2] + w * (b[2] - a[2]),
    ]
}

/// Samples every [`STEP`] metres along the polyline (the last point kept).
fn resample(raw: &[Sample]) -> Vec<Sample> {
    let mut out = vec![raw[0]];
    let mut carried = 0.0;
    for w in raw.windows(2) {
        let (a, b) = (w[0].p, w[1].p);
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let len = norm(d);
        let mut s = STEP - carried;
        while s < len {
            out.push(Sample {
                p: lerp(a, b, s / len),
                leg: w[1].leg,
            });
            s += STEP;
        }
        carried = len - (s - STEP);
    }
    let last = raw[raw.len() - 1];
    if norm([
        last.p[0] - out[out.len() - 1].p[0],
        last.p[1] - out[out.len() - 1].p[1],
        last.p[2] - out[out.len() - 1].p[2],
    ]) > 1e-6
    {
        out.push(last);
    }
    out
}

/// A Gaussian smoothing of the samples, the ends held: the line is extended past each end by
/// its point reflection there, which keeps the end point and its direction.
fn gaussian(line: &[Sample]) -> Vec<V3> {
    let n = line.len();
    let sigma = SMOOTH / STEP;
    let half = (3.0 * sigma).ceil() as isize;
    let kernel: Vec<f64> = (-half..=half)
        .map(|k| (-(k * k) as f64 / (2.0 * sigma * sigma)).exp())
        .collect();
    let total: f64 = kernel.iter().sum();
    let at = |i: isize| -> V3 {
        let last = n as isize - 1;
        if i < 0 {
            let (e, m) = (line[0].p, line[(-i).min(last) as usize].p);
            [2.0 * e[0] - m[0], 2.0 * e[1] - m[1], 2.0 * e[2] - m[2]]
        } else if i > last {
            let (e, m) = (
                line[last as usize].p,
                line[(2 * last - i).max(0) as usize].p,
            );
            [2.0 * e[0] - m[0], 2.0 * e[1] - m[1], 2.0 * e[2] - m[2]]
        } else {
            line[i as usize].p
        }
    };
    (0..n as isize)
        .map(|i| {
            let mut acc = [0.0; 3];
            for (j, w) in kernel.iter().enumerate() {
                let p = at(i + j as isize - half);
                for k in 0..3 {
                    acc[k] += w * p[k];
                }
            }
            acc.map(|x| x / total)
        })
        .collect()
}
