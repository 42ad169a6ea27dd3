//! Lines of sight through the collision surface's free space: whether an artifact is seen
//! from its tile's passage axis (`axis`). One computation for two users, so they cannot
//! disagree: placement (`artifacts`, which hides a share of the artifacts on purpose with
//! `[artifacts] hidden`) and the ground truth's `visible_from_axis` flag (the exporters'
//! `ground_truth/artifacts.rs`, from [`Artifact::visible_from_axis`]).
//!
//! [`Artifact::visible_from_axis`]: subtgraph_core::artifacts::Artifact::visible_from_axis
//!
//! The eye is [`EYE`] above the nearest point of the tile's axis (its anchor and its paths to
//! the openings, as a polyline per path) to the artifact's centre. The line from the eye to
//! the centre is clear when every [`SIGHT_STEP`] along it the point lies in a free stretch of
//! the collision surface's vertical line; the last [`SIGHT_END`] before the centre, where the
//! artifact touches a wall or the floor, is not looked at. An artifact around a bend, in a
//! pocket of the wall or behind a boulder is not seen. Without a mesh every artifact is seen
//! (from its tile's centre).
//!
//! The nearest point of the axis sees nearly everything in a tile (on the cave preset, seeds
//! 1 and 2, a search of every tile found 3 of the 6 hidden spots asked for, on the small
//! caves of the tests 5 of 16): a robot that has driven up to an artifact has found it. What hides an artifact is where the robot
//! is when it first comes near: with `[artifacts] hidden`, the eye is `approach_eye`, the
//! first point within [`NEAR`] of the artifact on the robot's way into the tile from the
//! opening nearest the start along the graph (then on to the anchor and the other
//! openings), so an artifact just past a bend, or in the far leg of a junction, is hidden.
//! Without the key the eye stays the nearest point, as in worlds made before it.

use crate::passages::Passages;

/// Height of the eye above the passage axis's floor, metres (a robot's sensor).
pub const EYE: f64 = 0.5;
/// Spacing of the points looked at along a line of sight, metres.
pub const SIGHT_STEP: f64 = 0.2;
/// How far from the artifact's centre the line of sight stops being looked at, metres.
pub const SIGHT_END: f64 = 0.3;

/// How near a robot on its way comes to an artifact before the artifact counts as in reach
/// of its sensors, metres: with `[artifacts] hidden`, the eye is the first point of the way
/// this near (`approach_eye`).
pub const NEAR: f64 = 10.0;

/// The eye looking at `target` as a robot comes to it: [`EYE`] above the first point of
/// `walk` (the robot's way through the tile, from the opening it enters by, see
/// `Axes::walk_from`) within [`NEAR`] of it; with no point that near, [`eye`] on the walk.
pub(crate) fn approach_eye(walk: &[[f64; 3]], target: [f64; 3]) -> [f64; 3] {
    match walk.iter().find(|p| dist2(**p, target) <= NEAR * NEAR) {
        Some(p) => [p[0], p[1], p[2] + EYE],
        None => eye(walk, target),
    }
}

/// The eye looking at `target` from a tile's axis `points` (anchor first, then each path to
/// an opening): [`EYE`] above the nearest point of the polyline through them.
pub(crate) fn eye(points: &[[f64; 3]], target: [f64; 3]) -> [f64; 3] {
    // The nearest point of the axis's polyline pieces (anchor to each path).
    let mut eye = points[0];
    let mut best = f64::MAX;
    for w in points.windows(2) {
        let q = nearest_on_segment(target, w[0], w[1]);
        let d = dist2(q, target);
        if d < best {
            (best, eye) = (d, q);
        }
    }
    if points.len() == 1 {
        eye = points[0];
    }
    [eye[0], eye[1], eye[2] + EYE]
}

/// The points looked at on the line from `eye` to `target`: every [`SIGHT_STEP`] from the
/// eye, stopping [`SIGHT_END`] short of the target.
pub(crate) fn samples(eye: [f64; 3], target: [f64; 3]) -> Vec<[f64; 3]> {
    let len = dist2(eye, target).sqrt();
    let n = ((len - SIGHT_END).max(0.0) / SIGHT_STEP).floor() as usize;
    (0..=n)
        .map(|k| {
            let t = (k as f64 * SIGHT_STEP / len.max(1e-9)).min(1.0);
            [
                eye[0] + (target[0] - eye[0]) * t,
                eye[1] + (target[1] - eye[1]) * t,
                eye[2] + (target[2] - eye[2]) * t,
            ]
        })
        .collect()
}

/// Whether the line from `eye` to `target` stays in free space (exact casts on the
/// passages).
pub(crate) fn clear(passages: &Passages, eye: [f64; 3], target: [f64; 3]) -> bool {
    !blocked(passages, eye, target).contains(&true)
}

/// Whether each point looked at on the line from `eye` to `target` ([`samples`]) is in rock.
pub(crate) fn blocked(passages: &Passages, eye: [f64; 3], target: [f64; 3]) -> Vec<bool> {
    let samples = samples(eye, target);
    let xy: Vec<[f64; 2]> = samples.iter().map(|p| [p[0], p[1]]).collect();
    let columns = passages.columns_at(&xy);
    samples
        .iter()
        .zip(&columns)
        .map(|(p, spans)| !spans.iter().any(|s| s[0] <= p[2] && p[2] <= s[1]))
        .collect()
}

/// Whether rock stands between the eye and the target beyond doubt: two points in a row
/// (a [`SIGHT_STEP`] of rock), the first at least two steps from the eye. What placement
/// asks of a hidden spot: a single point out of the free stretches may be a sliver where
/// two tiles meet, and a spot that is hidden only there is one no robot would miss.
pub(crate) fn walled(blocked: &[bool]) -> bool {
    blocked.windows(2).skip(2).any(|w| w[0] && w[1])
}

/// Whether a spot with `blocked` along its sight line is what placement aims for: `seen`, no
/// rock at all on the line; hidden, rock beyond doubt ([`walled`]).
pub(crate) fn as_aimed(seen: bool, blocked: &[bool]) -> bool {
    if seen {
        !blocked.contains(&true)
    } else {
        walled(blocked)
    }
}

pub(crate) fn dist2(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).powi(2)).sum()
}

fn nearest_on_segment(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    let ab = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let l2 = ab.iter().map(|v| v * v).sum::<f64>();
    let t = if l2 > 0.0 {
        (((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1] + (p[2] - a[2]) * ab[2]) / l2)
            .clamp(0.0, 1.0)
    } else {
        0.0
    };
    [a[0] + t * ab[0], a[1] + t * ab[1], a[2] + t * ab[2]]
}
