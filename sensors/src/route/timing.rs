//! When the platform is where: speeds along each stretch within the platform's limits, turns
//! in place between stretches, and the control points of the trajectory's splines.
//!
//! Along a stretch, the speed at each sample is capped by the platform's cruising speed (its
//! climbing speed up a shaft), by its sideways acceleration in bends (`v^2 kappa`) and by its
//! turn rate (`v dpsi/ds`), then by its acceleration from the stop before and to the stop
//! after (a forward and a backward pass). Control points are placed every [`DT`] seconds
//! along that timing, so the trajectory's B-splines follow it; the splines smooth what the
//! passes leave with corners (an acceleration that switches on at once), so the limits are
//! planned at 95 % of the platform's.

use std::f64::consts::PI;

use subtgraph_core::rng::WorldRng;
use subtgraph_core::vec3::V3;

use super::path::{STEP, Stretch};
use super::{Mark, Phase};
use crate::frames::norm;
use crate::platform::{Kind, Platform};
use crate::trajectory::Control;

/// Seconds between control points.
pub(super) const DT: f64 = 0.1;
/// Gravity, m/s^2 (standard).
pub const GRAVITY: f64 = 9.80665;
/// The share of each limit planned for.
const MARGIN: f64 = 0.95;

/// Control points and what each is doing, for a whole route.
pub(super) struct Timed {
    pub control: Vec<Control>,
    pub marks: Vec<Mark>,
}

/// The heading of a direction in the plane, or `None` for a (nearly) vertical one.
fn heading(d: V3) -> Option<f64> {
    let h = (d[0] * d[0] + d[1] * d[1]).sqrt();
    (h > 0.3 * norm(d).max(1e-9)).then(|| d[1].atan2(d[0]))
}

/// `a` moved by a multiple of 2 pi to within pi of `reference`.
fn unwrap_near(a: f64, reference: f64) -> f64 {
    a - ((a - reference) / (2.0 * PI)).round() * 2.0 * PI
}

/// The timed control points of every stretch, joined by turns in place, with a still start
/// and end.
pub(super) fn control_points(
    stretches: &[Stretch],
    platform: &Platform,
    rng: &mut WorldRng,
) -> Timed {
    let mut t = Timed {
        control: Vec::new(),
        marks: Vec::new(),
    };
    let mut yaw = None::<f64>;
    for (k, stretch) in stretches.iter().enumerate() {
        let (positions, yaws) = along(stretch, yaw);
        let first_yaw = yaws[0];
        match yaw {
            None => {
                // The still start, facing the way the route begins.
                let c = control(positions[0], first_yaw, 0.0, 0.0);
                still(&mut t, c, platform.still[0], Mark::still(stretch[0].leg));
            }
            Some(y) => {
                // Turn in place from the last heading to this stretch's first: the shorter
                // way, or for a turn-around (half a turn) the side the seed picks.
                let mut target = unwrap_near(first_yaw, y);
                if ((target - y).abs() - PI).abs() < 0.2 && rng.coin() {
                    target += if target > y { -2.0 * PI } else { 2.0 * PI };
                }
                turn(&mut t, positions[0], y, target, platform, stretch[0].leg);
            }
        }
        let offset = t.control.last().map_or(0.0, |c| c[3] - yaws[0]);
        let offset = (offset / (2.0 * PI)).round() * 2.0 * PI;
        let yaws: Vec<f64> = yaws.iter().map(|y| y + offset).collect();
        drive(&mut t, stretch, &positions, &yaws, platform);
        yaw = t.control.last().map(|c| c[3]);
        if k + 1 == stretches.len() {
            let last = *t.control.last().expect("driven");
            still(
                &mut t,
                last,
                platform.still[1],
                Mark::still(stretch[stretch.len() - 1].leg),
            );
        }
    }
    attitude(&mut t.control, platform);
    t
}

/// A control point at rest: position and yaw, level.
fn control(p: V3, yaw: f64, pitch: f64, roll: f64) -> Control {
    [p[0], p[1], p[2], yaw, pitch, roll]
}

/// Standing still for `seconds` (at least the six points that make the spline rest).
fn still(t: &mut Timed, c: Control, seconds: f64, mark: Mark) {
    let n = ((seconds / DT).ceil() as usize).max(6);
    for _ in 0..n {
        t.control.push(c);
        t.marks.push(mark);
    }
}

/// Turning in place from `from` to `to` (radians, unwrapped) at the platform's turn rate,
/// with a smooth start and stop.
fn turn(t: &mut Timed, p: V3, from: f64, to: f64, platform: &Platform, leg: usize) {
    let delta = to - from;
    // The quintic smoothstep's peak rate is 15/8 of its mean.
    let seconds = 1.875 * delta.abs() / (MARGIN * platform.max_yaw_rate);
    let n = (seconds / DT).ceil().max(1.0) as usize;
    let mark = Mark {
        leg: Some(leg as u32),
        node: None,
        phase: Phase::TurnAround,
    };
    for i in 0..=n {
        let x = i as f64 / n as f64;
        let s = x * x * x * (10.0 - 15.0 * x + 6.0 * x * x);
        t.control.push(control(p, from + s * delta, 0.0, 0.0));
        t.marks.push(mark);
    }
}

/// Positions and headings (unwrapped, starting near `before`) of a stretch's samples. A
/// vertical stretch of path (a shaft) keeps the heading it was entered with.
fn along(stretch: &Stretch, before: Option<f64>) -> (Vec<V3>, Vec<f64>) {
    let positions: Vec<V3> = stretch.iter().map(|s| s.p).collect();
    let n = positions.len();
    let dir = |i: usize| {
        let (a, b) = if i + 1 < n {
            (positions[i], positions[i + 1])
        } else {
            (positions[i.saturating_sub(1)], positions[i])
        };
        [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
    };
    let mut yaws = Vec::with_capacity(n);
    let first = (0..n)
        .find_map(|i| heading(dir(i)))
        .or(before)
        .unwrap_or(0.0);
    let mut last = before.map_or(first, |b| unwrap_near(first, b));
    for i in 0..n {
        if let Some(h) = heading(dir(i)) {
            last = unwrap_near(h, last);
        }
        yaws.push(last);
    }
    (positions, yaws)
}

/// Drives along a stretch: the speed profile, then control points every [`DT`].
fn drive(t: &mut Timed, stretch: &Stretch, positions: &[V3], yaws: &[f64], platform: &Platform) {
    let n = positions.len();
    if n < 2 {
        return;
    }
    // Speed caps per sample.
    let mut v = vec![0.0f64; n];
    for i in 0..n {
        let (a, b) = (
            positions[i.saturating_sub(1)],
            positions[(i + 1).min(n - 1)],
        );
        let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let len = norm(d).max(1e-9);
        let vertical = d[2].abs() / len > 0.7;
        let mut cap = if vertical && platform.kind == Kind::Aerial {
            platform.max_climb
        } else {
            platform.max_speed
        };
        // Curvature from the turn between the neighbouring steps.
        if i > 0 && i + 1 < n {
            let (p0, p1, p2) = (positions[i - 1], positions[i], positions[i + 1]);
            let u = [p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]];
            let w = [p2[0] - p1[0], p2[1] - p1[1], p2[2] - p1[2]];
            let (lu, lw) = (norm(u).max(1e-9), norm(w).max(1e-9));
            let cos = ((u[0] * w[0] + u[1] * w[1] + u[2] * w[2]) / (lu * lw)).clamp(-1.0, 1.0);
            let kappa = cos.acos() / (0.5 * (lu + lw));
            if kappa > 1e-9 {
                cap = cap.min((MARGIN * platform.max_lateral_acceleration / kappa).sqrt());
            }
            let dyaw = (yaws[i + 1] - yaws[i - 1]).abs() / (lu + lw);
            if dyaw > 1e-9 {
                cap = cap.min(MARGIN * platform.max_yaw_rate / dyaw);
            }
        }
        v[i] = cap * MARGIN;
    }
    v[0] = 0.0;
    v[n - 1] = 0.0;
    let accel = MARGIN * platform.max_acceleration;
    let ds = |i: usize| {
        let (a, b) = (positions[i], positions[i + 1]);
        norm([b[0] - a[0], b[1] - a[1], b[2] - a[2]])
    };
    for i in 1..n {
        v[i] = v[i].min((v[i - 1] * v[i - 1] + 2.0 * accel * ds(i - 1)).sqrt());
    }
    for i in (0..n - 1).rev() {
        v[i] = v[i].min((v[i + 1] * v[i + 1] + 2.0 * accel * ds(i)).sqrt());
    }
    // Time at each sample: constant acceleration between samples.
    let mut time = vec![0.0f64; n];
    for i in 1..n {
        let mean = 0.5 * (v[i - 1] + v[i]);
        time[i] = time[i - 1] + if mean > 1e-6 { ds(i - 1) / mean } else { STEP };
    }
    let total = time[n - 1];
    let steps = (total / DT).ceil().max(1.0) as usize;
    let mut j = 0;
    for k in 1..=steps {
        let tk = (k as f64 * DT).min(total);
        while j + 2 < n && time[j + 1] < tk {
            j += 1;
        }
        let span = (time[j + 1] - time[j]).max(1e-12);
        let f = ((tk - time[j]) / span).clamp(0.0, 1.0);
        let (a, b) = (positions[j], positions[j + 1]);
        let p = [
            a[0] + f * (b[0] - a[0]),
            a[1] + f * (b[1] - a[1]),
            a[2] + f * (b[2] - a[2]),
        ];
        let yaw = yaws[j] + f * (yaws[j + 1] - yaws[j]);
        t.control.push(control(p, yaw, 0.0, 0.0));
        t.marks.push(Mark {
            leg: Some(stretch[j].leg as u32),
            node: None,
            phase: Phase::Drive,
        });
    }
}

/// Pitch and roll at every control point: a ground robot's follow its path's slope (it rides
/// the floor), an aerial one's tilt its thrust along its acceleration plus gravity, as a
/// quadrotor must.
fn attitude(control: &mut [Control], platform: &Platform) {
    let n = control.len();
    let p = |i: usize| {
        let c = control[i.min(n - 1)];
        [c[0], c[1], c[2]]
    };
    let mut tilt = vec![[0.0f64; 2]; n];
    for i in 1..n.saturating_sub(1) {
        let (a, b, c) = (p(i - 1), p(i), p(i + 1));
        let yaw = control[i][3];
        match platform.kind {
            Kind::Ground => {
                let d = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
                let forward = d[0] * yaw.cos() + d[1] * yaw.sin();
                let horizontal = (d[0] * d[0] + d[1] * d[1]).sqrt();
                if horizontal > 1e-3 {
                    // Nose up (negative pitch) going up the way it faces.
                    let slope = d[2] / horizontal;
                    tilt[i][0] = -(slope * forward.signum()).atan();
                } else {
                    tilt[i][0] = tilt[i - 1][0];
                }
            }
            Kind::Aerial => {
                let acc = [
                    (a[0] - 2.0 * b[0] + c[0]) / (DT * DT),
                    (a[1] - 2.0 * b[1] + c[1]) / (DT * DT),
                    (a[2] - 2.0 * b[2] + c[2]) / (DT * DT) + GRAVITY,
                ];
                let (s, co) = yaw.sin_cos();
                let (tx, ty) = (co * acc[0] + s * acc[1], -s * acc[0] + co * acc[1]);
                tilt[i] = [
                    tx.atan2(acc[2]),
                    (-ty).atan2((tx * tx + acc[2] * acc[2]).sqrt()),
                ];
            }
        }
    }
    // A short moving average: second differences of control points are rough.
    for (i, c) in control.iter_mut().enumerate().take(n) {
        let lo = i.saturating_sub(2);
        let hi = (i + 3).min(n);
        let m = (hi - lo) as f64;
        c[4] = tilt[lo..hi].iter().map(|t| t[0]).sum::<f64>() / m;
        c[5] = tilt[lo..hi].iter().map(|t| t[1]).sum::<f64>() / m;
    }
}
