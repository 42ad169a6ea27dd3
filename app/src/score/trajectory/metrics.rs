//! The scores of an aligned, associated trajectory. Every definition here is the one
//! `docs/src/scoring.md` (Trajectories) gives, and each is checked against evo.
//!
//! - APE: the distance between each estimated position (aligned) and its reference position
//!   (evo's `evo_ape ... --pose_relation trans_part`).
//! - RPE: for pose pairs `(i, j)`, the relative motion error `E = (Qᵢ⁻¹Qⱼ)⁻¹ (Pᵢ⁻¹Pⱼ)` (Q the
//!   reference, P the estimate); its translation's length and its rotation's angle. Pairs as
//!   evo makes them without `--all_pairs`: `(0, d), (d, 2d), ...` for `d` frames, and for `d`
//!   metres the poses where the reference's travelled path since the last chosen pose first
//!   reaches `d`, starting from pose 0 (`--delta_unit m --pairs_from_reference`).
//! - Final drift: the last associated pose's APE as a percentage of the reference's path
//!   length over the associated poses.
//! - Points (HILTI SLAM challenge style): each associated pose earns 10 points if its APE is
//!   at most 5 cm, 6 if at most 30 cm, 3 if at most 50 cm, 1 if at most 1 m, else 0.
//! - Failure: an APE above the limit (divergence), or a step between consecutive associated
//!   poses longer than the reference's step by more than the jump limit (a jump).

use serde::Serialize;

use super::pose::{Pose, angle, norm, sub};

/// Summary statistics of a list of errors, as evo's `stats.json` has them.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Stats {
    /// How many values.
    pub count: usize,
    /// Root mean square.
    pub rmse: f64,
    /// Mean.
    pub mean: f64,
    /// Median (the mean of the middle two for an even count).
    pub median: f64,
    /// Population standard deviation (divided by the count, as numpy's `std`).
    pub std: f64,
    /// Smallest.
    pub min: f64,
    /// Largest.
    pub max: f64,
    /// Sum of squares.
    pub sse: f64,
}

impl Stats {
    /// The statistics of `v` (not empty).
    pub fn of(v: &[f64]) -> Stats {
        let n = v.len() as f64;
        let sse: f64 = v.iter().map(|x| x * x).sum();
        let mean = v.iter().sum::<f64>() / n;
        let var = v.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n;
        let mut sorted = v.to_vec();
        sorted.sort_by(f64::total_cmp);
        let m = sorted.len() / 2;
        let median = if sorted.len() % 2 == 1 {
            sorted[m]
        } else {
            0.5 * (sorted[m - 1] + sorted[m])
        };
        Stats {
            count: v.len(),
            rmse: (sse / n).sqrt(),
            mean,
            median,
            std: var.sqrt(),
            min: sorted[0],
            max: sorted[sorted.len() - 1],
            sse,
        }
    }
}

/// APE of each pose: `|p̂ᵢ - qᵢ|`.
pub fn ape(reference: &[Pose], estimate: &[Pose]) -> Vec<f64> {
    reference
        .iter()
        .zip(estimate)
        .map(|(r, e)| norm(sub(e.t, r.t)))
        .collect()
}

/// Pairs `(0, d), (d, 2d), ...` below `n`.
pub fn pairs_by_frames(n: usize, d: usize) -> Vec<(usize, usize)> {
    let ids: Vec<usize> = (0..n).step_by(d.max(1)).collect();
    ids.windows(2).map(|w| (w[0], w[1])).collect()
}

/// Pairs of consecutive poses each at least `d` metres of the reference's path after the one
/// before, from pose 0.
pub fn pairs_by_path(reference: &[Pose], d: f64) -> Vec<(usize, usize)> {
    let mut ids = vec![0];
    let mut path = 0.0;
    for k in 1..reference.len() {
        path += norm(sub(reference[k].t, reference[k - 1].t));
        if path >= d {
            ids.push(k);
            path = 0.0;
        }
    }
    ids.windows(2).map(|w| (w[0], w[1])).collect()
}

/// The RPE of each pair: `(translation error m, rotation error degrees)`.
pub fn rpe(reference: &[Pose], estimate: &[Pose], pairs: &[(usize, usize)]) -> Vec<(f64, f64)> {
    pairs
        .iter()
        .map(|&(i, j)| {
            let q = reference[i].relative(&reference[j]);
            let p = estimate[i].relative(&estimate[j]);
            let e = q.relative(&p);
            (norm(e.t), angle(e.q).to_degrees())
        })
        .collect()
}

/// The reference's path length, metres.
pub fn path_length(poses: &[Pose]) -> f64 {
    poses.windows(2).map(|w| norm(sub(w[1].t, w[0].t))).sum()
}

/// The error thresholds of the points and their points: `(APE at most, metres; points)`.
pub const POINTS: [(f64, u32); 4] = [(0.05, 10), (0.30, 6), (0.50, 3), (1.0, 1)];

/// The points one pose's APE earns.
pub fn points(ape: f64) -> u32 {
    POINTS
        .iter()
        .find(|(limit, _)| ape <= *limit)
        .map_or(0, |&(_, p)| p)
}

/// Why a run failed, the first time it did.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Failure {
    /// `"divergence"` or `"jump"`.
    pub kind: &'static str,
    /// The associated pose (0-based) where it happened.
    pub pose: usize,
    /// The reference time there, seconds.
    pub time: f64,
    /// What was measured: the APE (divergence) or the excess of the step over the
    /// reference's (jump), metres.
    pub value_m: f64,
}

/// The first divergence (APE above `max_ape`) or jump (a step longer than the reference's by
/// more than `max_jump`), whichever comes first.
pub fn failure(
    times: &[f64],
    reference: &[Pose],
    estimate: &[Pose],
    ape: &[f64],
    max_ape: f64,
    max_jump: f64,
) -> Option<Failure> {
    for k in 0..ape.len() {
        if ape[k] > max_ape {
            return Some(Failure {
                kind: "divergence",
                pose: k,
                time: times[k],
                value_m: ape[k],
            });
        }
        if k > 0 {
            let step = norm(sub(estimate[k].t, estimate[k - 1].t));
            let truth = norm(sub(reference[k].t, reference[k - 1].t));
            if step - truth > max_jump {
                return Some(Failure {
                    kind: "jump",
                    pose: k,
                    time: times[k],
                    value_m: step - truth,
                });
            }
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stats_of_known_values() {
        let s = Stats::of(&[3.0, 1.0, 4.0, 2.0]);
        assert_eq!((s.min, s.max, s.median, s.mean), (1.0, 4.0, 2.5, 2.5));
        assert!((s.rmse - 7.5f64.sqrt()).abs() < 1e-15);
        assert!((s.std - 1.25f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn points_by_threshold() {
        assert_eq!(
            [0.0, 0.05, 0.051, 0.3, 0.5, 1.0, 1.01].map(points),
            [10, 10, 6, 6, 3, 1, 0]
        );
    }

    #[test]
    fn frame_pairs_do_not_overlap() {
        assert_eq!(pairs_by_frames(7, 3), vec![(0, 3), (3, 6)]);
        assert_eq!(pairs_by_frames(3, 1), vec![(0, 1), (1, 2)]);
    }
}
