//! Time association and alignment, as evo does them, so the numbers agree with `evo_ape` and
//! `evo_rpe` on the same files and options.
//!
//! - Association (evo's `sync.associate_trajectories`, nearest in time): the trajectory with
//!   fewer poses (the estimate when both have as many) is walked, and each of its poses is
//!   paired with the nearest pose of the other within `max_diff` seconds (the earlier on a tie);
//!   a pose with none is left out.
//! - Or interpolated (`--associate interpolate`, which evo does not do): the reference is
//!   interpolated at each estimate pose's time (linearly in position, by slerp in
//!   orientation) between the two reference poses around it, when they are at most
//!   `max_gap` seconds apart; estimate poses outside the reference's span or across a longer
//!   gap (the ground truth dropped out) are left out. For estimates at a rate of their own
//!   against a denser ground truth, every estimate pose is scored, none shifted in time.
//! - Alignment of the estimate onto the reference: Umeyama's least-squares rigid (SE(3)) or
//!   similarity (Sim(3)) transform of the paired positions (evo's `-a` and `-as`), solved with
//!   Horn's quaternion method, which gives the same transform without an SVD; or origin
//!   alignment (evo's `--align_origin`): the rigid transform that puts the estimate's first
//!   paired pose on the reference's, as LiDAR odometry is judged (it starts where the robot
//!   starts, and drift is all it has).

use super::pose::{Pose, Quat, Vec3, add, dot, mul, norm, rotate, scale, sub};

/// Pairs `(reference index, estimate index)` in time order.
pub fn associate(reference: &[f64], estimate: &[f64], max_diff: f64) -> Vec<(usize, usize)> {
    let est_longer = estimate.len() > reference.len();
    let (short, long) = if est_longer {
        (reference, estimate)
    } else {
        (estimate, reference)
    };
    let (first, last) = (long[0], long[long.len() - 1]);
    let mut out = Vec::new();
    for (i, &s) in short.iter().enumerate() {
        if s < first - max_diff || s > last + max_diff {
            continue;
        }
        let j = long.partition_point(|&x| x <= s).min(long.len() - 1);
        let up = long[j] - s;
        let low = if j > 0 {
            s - long[j - 1]
        } else {
            f64::INFINITY
        };
        let best = if up <= max_diff && up < low {
            j
        } else if low <= max_diff && low <= up {
            j - 1
        } else {
            continue;
        };
        out.push(if est_longer { (i, best) } else { (best, i) });
    }
    out
}

/// The reference interpolated at the estimate's times: `(estimate index, time, pose)` for
/// each estimate pose within the reference's span whose neighbouring reference poses are at
/// most `max_gap` seconds apart (a pose at a reference time takes that pose as it is).
pub fn interpolate(
    reference_times: &[f64],
    reference: &[Pose],
    estimate_times: &[f64],
    max_gap: f64,
) -> Vec<(usize, f64, Pose)> {
    let mut out = Vec::new();
    for (i, &t) in estimate_times.iter().enumerate() {
        let j = reference_times.partition_point(|&x| x < t);
        if j == reference_times.len() {
            continue;
        }
        if reference_times[j] == t {
            out.push((i, t, reference[j]));
            continue;
        }
        if j == 0 || reference_times[j] - reference_times[j - 1] > max_gap {
            continue;
        }
        let (t0, t1) = (reference_times[j - 1], reference_times[j]);
        let a = (t - t0) / (t1 - t0);
        let (p, q) = (&reference[j - 1], &reference[j]);
        out.push((
            i,
            t,
            Pose {
                q: slerp(p.q, q.q, a),
                t: add(p.t, scale(a, sub(q.t, p.t))),
            },
        ));
    }
    out
}

/// The rotation a share `a` of the way from `p` to `q`, along the shorter arc.
fn slerp(p: Quat, q: Quat, a: f64) -> Quat {
    let d: f64 = (0..4).map(|k| p[k] * q[k]).sum();
    let (q, d) = if d < 0.0 { (q.map(|x| -x), -d) } else { (q, d) };
    let (wp, wq) = if d > 1.0 - 1e-12 {
        (1.0 - a, a)
    } else {
        let theta = d.min(1.0).acos();
        let s = theta.sin();
        (((1.0 - a) * theta).sin() / s, (a * theta).sin() / s)
    };
    let r: Quat = std::array::from_fn(|k| wp * p[k] + wq * q[k]);
    let n = (0..4).map(|k| r[k] * r[k]).sum::<f64>().sqrt();
    r.map(|x| x / n)
}

/// A similarity transform `x ↦ s R x + t` applied to the estimate.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Alignment {
    /// `R`, a unit quaternion `[w, x, y, z]`.
    pub rotation: Quat,
    /// `t`, metres.
    pub translation: Vec3,
    /// `s` (1 unless Sim(3)).
    pub scale: f64,
}

impl Alignment {
    /// The pose moved by this transform: position `s R p + t`, orientation `R q` (evo scales
    /// the positions, then applies the rigid part).
    pub fn apply(&self, p: &Pose) -> Pose {
        Pose {
            q: mul(self.rotation, p.q),
            t: add(
                rotate(self.rotation, scale(self.scale, p.t)),
                self.translation,
            ),
        }
    }
}

/// The rigid transform putting `est0` on `ref0`: `ref0 ∘ est0⁻¹`.
pub fn origin(est0: &Pose, ref0: &Pose) -> Alignment {
    let t = ref0.compose(&est0.inverse());
    Alignment {
        rotation: t.q,
        translation: t.t,
        scale: 1.0,
    }
}

/// Why a least-squares alignment is undetermined.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Undetermined {
    /// Every associated position of the estimate is the same point: no rotation fits.
    #[error("the estimate's associated positions are all the same point")]
    OnePoint,
    /// The best scale is zero, negative or not a number.
    #[error("the best scale is {0}, not a positive number")]
    Scale(f64),
}

/// Umeyama's least-squares transform taking `est` onto `reference` (the same length), with
/// a scale when `with_scale`. `Err` says why it is undetermined.
pub fn umeyama(
    est: &[Vec3],
    reference: &[Vec3],
    with_scale: bool,
) -> Result<Alignment, Undetermined> {
    let n = est.len() as f64;
    let mean = |v: &[Vec3]| {
        let s = v.iter().fold([0.0; 3], |a, &p| add(a, p));
        scale(1.0 / n, s)
    };
    let (mx, my) = (mean(est), mean(reference));
    let mut c = [[0.0; 3]; 3]; // Σ (x - mx)(y - my)ᵀ
    let mut spread = 0.0;
    for (x, y) in est.iter().zip(reference) {
        let (dx, dy) = (sub(*x, mx), sub(*y, my));
        spread += dot(dx, dx);
        for a in 0..3 {
            for b in 0..3 {
                c[a][b] += dx[a] * dy[b];
            }
        }
    }
    if spread <= 0.0 {
        return Err(Undetermined::OnePoint);
    }
    let [[sxx, sxy, sxz], [syx, syy, syz], [szx, szy, szz]] = c;
    let k = [
        [sxx + syy + szz, syz - szy, szx - sxz, sxy - syx],
        [syz - szy, sxx - syy - szz, sxy + syx, szx + sxz],
        [szx - sxz, sxy + syx, -sxx + syy - szz, syz + szy],
        [sxy - syx, szx + sxz, syz + szy, -sxx - syy + szz],
    ];
    let q = largest_eigenvector(k);
    let s = if with_scale {
        let mut num = 0.0;
        for (x, y) in est.iter().zip(reference) {
            num += dot(sub(*y, my), rotate(q, sub(*x, mx)));
        }
        num / spread
    } else {
        1.0
    };
    if !(s.is_finite() && s > 0.0) {
        return Err(Undetermined::Scale(s));
    }
    Ok(Alignment {
        rotation: q,
        translation: sub(my, scale(s, rotate(q, mx))),
        scale: s,
    })
}

/// The unit eigenvector of the largest eigenvalue of a symmetric 4x4 matrix, by cyclic Jacobi
/// rotations (exact to rounding; a handful of sweeps).
fn largest_eigenvector(mut a: [[f64; 4]; 4]) -> Quat {
    let mut v = [[0.0; 4]; 4];
    for (i, row) in v.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for _ in 0..60 {
        let off: f64 = (0..4)
            .flat_map(|i| (0..4).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i][j] * a[i][j])
            .sum();
        let diag: f64 = (0..4).map(|i| a[i][i] * a[i][i]).sum();
        if off <= 1e-30 * diag || off == 0.0 {
            break;
        }
        for p in 0..4 {
            for q in p + 1..4 {
                if a[p][q] == 0.0 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for row in a.iter_mut() {
                    let (akp, akq) = (row[p], row[q]);
                    row[p] = c * akp - s * akq;
                    row[q] = s * akp + c * akq;
                }
                let (rp, rq) = (a[p], a[q]);
                for k in 0..4 {
                    a[p][k] = c * rp[k] - s * rq[k];
                    a[q][k] = s * rp[k] + c * rq[k];
                }
                for row in v.iter_mut() {
                    let (vp, vq) = (row[p], row[q]);
                    row[p] = c * vp - s * vq;
                    row[q] = s * vp + c * vq;
                }
            }
        }
    }
    let best = (0..4)
        .max_by(|&i, &j| a[i][i].total_cmp(&a[j][j]))
        .expect("four eigenvalues");
    let q = [v[0][best], v[1][best], v[2][best], v[3][best]];
    let n = norm([q[1], q[2], q[3]]).hypot(q[0]);
    q.map(|x| x / n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_within_the_tolerance_and_the_earlier_on_a_tie() {
        let r = [0.0, 1.0, 2.0, 3.0];
        let e = [0.004, 1.5, 2.009, 7.0];
        // 0.004 -> 0; 1.5 is 0.5 from both: none within 0.01; 2.009 -> 2; 7 -> none.
        assert_eq!(associate(&r, &e, 0.01), vec![(0, 0), (2, 2)]);
        assert_eq!(associate(&r, &e, 0.5), vec![(0, 0), (1, 1), (2, 2)]);
    }

    #[test]
    fn umeyama_recovers_a_known_similarity() {
        let h = (0.4f64).sin();
        let truth = Alignment {
            rotation: [(0.4f64).cos(), h * 0.36, h * 0.48, h * 0.8],
            translation: [3.0, -1.0, 2.0],
            scale: 1.7,
        };
        let est: Vec<Vec3> = (0..20)
            .map(|i| {
                let f = i as f64;
                [f.cos() * 5.0, f.sin() * 3.0, 0.1 * f * f]
            })
            .collect();
        let reference: Vec<Vec3> = est
            .iter()
            .map(|&p| {
                truth
                    .apply(&Pose {
                        q: [1.0, 0.0, 0.0, 0.0],
                        t: p,
                    })
                    .t
            })
            .collect();
        let a = umeyama(&est, &reference, true).unwrap();
        assert!((a.scale - 1.7).abs() < 1e-12, "{a:?}");
        let same = (0..4).all(|k| (a.rotation[k] - truth.rotation[k]).abs() < 1e-9)
            || (0..4).all(|k| (a.rotation[k] + truth.rotation[k]).abs() < 1e-9);
        assert!(same, "{a:?}");
        assert!(norm(sub(a.translation, truth.translation)) < 1e-9, "{a:?}");
    }
}
