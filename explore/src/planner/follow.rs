//! Following a path: pure pursuit of the first path point at least [`LOOKAHEAD`] metres ahead,
//! turning in place when it lies more than [`TURN_IN_PLACE`] off the heading, slowing in
//! turns, and for an aerial robot climbing toward the point's height.

use crate::body::{Body, Command, State, wrap};

/// How far ahead on the path the robot aims, metres.
pub const LOOKAHEAD: f64 = 1.5;
/// Heading error beyond which the robot stops and turns, radians (50 degrees).
pub const TURN_IN_PLACE: f64 = 0.873;
/// Turn-rate gain, 1/s.
const TURN_GAIN: f64 = 2.0;
/// Climb gain, 1/s.
const CLIMB_GAIN: f64 = 1.0;

/// The command that follows `path` from `state` (standing still at its end or without one).
pub fn command(body: &Body, state: &State, path: &[[f64; 3]]) -> Command {
    let p = state.position;
    let Some(last) = path.last() else {
        return Command::default();
    };
    let flat = |q: &[f64; 3]| (q[0] - p[0]).hypot(q[1] - p[1]);
    // The nearest path point, then the first at least LOOKAHEAD beyond it.
    let nearest = path
        .iter()
        .enumerate()
        .min_by(|a, b| flat(a.1).total_cmp(&flat(b.1)))
        .map_or(0, |(i, _)| i);
    let aim = path[nearest..]
        .iter()
        .find(|q| flat(q) >= LOOKAHEAD)
        .unwrap_or(last);
    let distance = flat(aim);
    let climb = if body.flies() {
        CLIMB_GAIN * (aim[2] - p[2])
    } else {
        0.0
    };
    if distance < 0.3 {
        return Command {
            climb,
            ..Command::default()
        };
    }
    let error = wrap((aim[1] - p[1]).atan2(aim[0] - p[0]) - state.yaw);
    let yaw_rate = (TURN_GAIN * error).clamp(-body.max_yaw_rate, body.max_yaw_rate);
    let speed = if error.abs() > TURN_IN_PLACE {
        0.0
    } else {
        // Full speed straight ahead, slower in turns and near the end.
        let turn = error.cos().max(0.0).powi(2);
        let near_end = (flat(last) / 2.0).clamp(0.3, 1.0);
        body.max_speed * turn * near_end
    };
    Command {
        speed,
        yaw_rate,
        climb,
    }
}

/// The command that backs along `trail` (positions, newest last): reversing toward the
/// newest one at least [`LOOKAHEAD`] away, nose away from it.
pub fn back(body: &Body, state: &State, trail: &[[f64; 3]]) -> Command {
    let p = state.position;
    let flat = |q: &[f64; 3]| (q[0] - p[0]).hypot(q[1] - p[1]);
    let Some(aim) = trail
        .iter()
        .rev()
        .find(|q| flat(q) >= LOOKAHEAD)
        .or(trail.first())
    else {
        return Command::default();
    };
    if flat(aim) < 0.2 {
        return Command::default();
    }
    // The heading that points the tail at the aim.
    let error = wrap((p[1] - aim[1]).atan2(p[0] - aim[0]) - state.yaw);
    let yaw_rate = (TURN_GAIN * error).clamp(-body.max_yaw_rate, body.max_yaw_rate);
    let speed = if error.abs() > TURN_IN_PLACE {
        0.0
    } else {
        -body.max_reverse * error.cos().max(0.0).powi(2)
    };
    Command {
        speed,
        yaw_rate,
        climb: 0.0,
    }
}
