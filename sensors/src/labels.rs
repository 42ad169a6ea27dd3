//! A label for every scan: where on the route it was taken, what the platform was doing, how
//! near the rock was, and how well the scan's geometry pins down the sensor's pose.
//!
//! **Degeneracy.** Scan-to-map registration (ICP, the LIO methods' updates) minimises the
//! point-to-plane residuals `n . (R p + t - q)`; near the solution each return adds the row
//! `J = [p x n, n]` to the Gauss-Newton Hessian `H = sum J^T J`. Its eigenvalues say how
//! strongly the scan constrains each direction of motion (three rotations, three
//! translations), its eigenvectors which directions those are: a long straight tunnel's
//! returns all have normals across the tunnel, so `H` has an eigenvalue near zero for
//! translation along it, and registration slides (Zhang, Kaess and Singh, "On degeneracy of
//! optimization-based state estimation problems", ICRA 2016). The label reports `H` divided by
//! the number of returns, its rotation rows scaled by the returns' RMS range so both halves are
//! unitless and comparable, its six eigenvalues and the weakest eigenvector, the same for the
//! translation block alone, and a score: the smallest translation eigenvalue over the largest
//! (1 for returns facing every way, 0 when a direction of travel is unconstrained). A scan is
//! `degenerate` when its score is below [`DEGENERATE`].

use serde::Serialize;

use crate::lidar::scan::Scan;
use crate::route::{Mark, Phase, Route};

/// `along_travel` below this predicts that LiDAR-only odometry slides: the threshold with the
/// best F1 for "KISS-ICP estimates under 90 % of the distance driven in 5 s" on the odd seeds
/// of `scripts/study-conditions`, held out on the even ones (docs/src/conditions.md).
pub const SLIDES_BELOW: f64 = 0.086;

/// Scores below this are degenerate: the weakest direction of translation is held by less
/// than a fiftieth of what holds the strongest. Measured on the presets' default routes (60 s,
/// OS1-32): the cave's scans score 0.021 to 0.28 (median 0.15), the mine's 0.002 to 0.26
/// (median 0.008, along its straight drifts), a uniform tube's 0.
pub const DEGENERATE: f64 = 0.02;

/// How well a scan constrains the sensor's pose.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Degeneracy {
    /// The smallest translation eigenvalue over the largest, `0..=1`.
    pub score: f64,
    /// Whether the score is below [`DEGENERATE`].
    pub degenerate: bool,
    /// Eigenvalues of the normalised Hessian, ascending.
    pub eigenvalues: [f64; 6],
    /// The eigenvector of the smallest: `[rx, ry, rz, tx, ty, tz]`, world axes.
    pub weakest: [f64; 6],
    /// Eigenvalues of the translation block, ascending.
    pub translation_eigenvalues: [f64; 3],
    /// The direction of translation least constrained, world axes (a unit vector).
    pub weakest_translation: [f64; 3],
    /// How strongly the scan holds the platform's motion along the way it is going: the
    /// translation block's curvature along the direction of travel over its largest
    /// eigenvalue, `0..=1` (`null` when the platform moves slower than 0.2 m/s).
    pub along_travel: Option<f64>,
    /// Whether LiDAR-only odometry is expected to slide here (lose a tenth or more of the
    /// distance driven): `along_travel` below [`SLIDES_BELOW`], as calibrated against
    /// KISS-ICP on the presets (docs/src/conditions.md).
    pub slides: bool,
}

/// Everything `sequence.json` says about one scan.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Label {
    /// The scan's index (its KITTI file number).
    pub scan: u64,
    /// When it starts, seconds from the sequence's start.
    pub time: f64,
    /// The graph edge it was taken on (`null` while still at the start or end).
    pub edge: Option<usize>,
    /// The graph node it was taken at, within a quarter of a tile pitch.
    pub node: Option<usize>,
    /// What the platform was doing.
    pub phase: Phase,
    /// The LiDAR's distance to the nearest rock, metres.
    pub wall_distance_m: f64,
    /// Returns in the scan.
    pub returns: usize,
    /// How well its geometry constrains the pose (`null` under 100 returns).
    pub degeneracy: Option<Degeneracy>,
    /// What the conditions did to it (only with `--conditions`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub conditions: Option<crate::conditions::ScanConditions>,
}

/// The label of a scan.
pub fn label(scan: &Scan, route: &Route, wall_distance_m: f64) -> Label {
    let mid = scan.start;
    let mark: Mark = route.mark(mid);
    Label {
        scan: scan.index,
        time: scan.start,
        edge: mark.leg.map(|l| route.legs[l as usize].edge),
        node: mark.node.map(|n| n as usize),
        phase: mark.phase,
        wall_distance_m: (wall_distance_m * 1000.0).round() / 1000.0,
        returns: scan.returns,
        degeneracy: (scan.returns >= 100).then(|| {
            let v = route.trajectory.state(scan.start).velocity;
            with_travel(degeneracy(scan), scan, v)
        }),
        conditions: None,
    }
}

/// `d` with its constraint along the velocity `v` (world frame) filled in.
pub fn with_travel(mut d: Degeneracy, scan: &Scan, v: [f64; 3]) -> Degeneracy {
    let speed = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if speed < 0.2 {
        return d;
    }
    let u = v.map(|x| x / speed);
    let t = translation_block(scan);
    let mut along = 0.0;
    for (a, row) in t.iter().enumerate() {
        for (b, x) in row.iter().enumerate() {
            along += u[a] * x * u[b];
        }
    }
    let top = d.translation_eigenvalues[2];
    let value = if top > 0.0 {
        (along / top).clamp(0.0, 1.0)
    } else {
        0.0
    };
    d.along_travel = Some((value * 1e6).round() / 1e6);
    d.slides = value < SLIDES_BELOW;
    d
}

/// The translation block of a scan's Hessian over its returns.
// Indices, as the matrix algebra is written.
#[allow(clippy::needless_range_loop)]
fn translation_block(scan: &Scan) -> [[f64; 3]; 3] {
    let n = scan.returns.max(1) as f64;
    let mut h = [[0.0; 6]; 6];
    let mut k = 0;
    for a in 0..6 {
        for b in a..6 {
            h[a][b] = scan.hessian[k] / n;
            h[b][a] = h[a][b];
            k += 1;
        }
    }
    std::array::from_fn(|a| std::array::from_fn(|b| h[3 + a][3 + b]))
}

/// The degeneracy of a scan's Hessian.
// Indices, as the matrix algebra is written.
#[allow(clippy::needless_range_loop)]
pub fn degeneracy(scan: &Scan) -> Degeneracy {
    let n = scan.returns.max(1) as f64;
    let length = (scan.range2 / n).sqrt().max(1e-6);
    let mut h = [[0.0; 6]; 6];
    let mut k = 0;
    for a in 0..6 {
        for b in a..6 {
            // Rotation rows and columns (0..3) in units of the RMS range.
            let s = if a < 3 { 1.0 / length } else { 1.0 } * if b < 3 { 1.0 / length } else { 1.0 };
            h[a][b] = scan.hessian[k] * s / n;
            h[b][a] = h[a][b];
            k += 1;
        }
    }
    let (values, vectors) = jacobi(h);
    let mut t = [[0.0; 3]; 3];
    for a in 0..3 {
        for b in 0..3 {
            t[a][b] = h[3 + a][3 + b];
        }
    }
    let (tv, tvec) = jacobi(t);
    let round = |x: f64| (x * 1e6).round() / 1e6;
    let score = if tv[2] > 0.0 {
        tv[0].max(0.0) / tv[2]
    } else {
        0.0
    };
    Degeneracy {
        score: round(score),
        degenerate: score < DEGENERATE,
        eigenvalues: values.map(round),
        weakest: canonical(vectors[0]).map(round),
        translation_eigenvalues: tv.map(round),
        weakest_translation: canonical(tvec[0]).map(round),
        along_travel: None,
        slides: false,
    }
}

/// A unit vector's sign fixed (its largest component positive), so a label does not flip
/// between runs of the eigen-solver.
fn canonical<const N: usize>(v: [f64; N]) -> [f64; N] {
    let big = v
        .iter()
        .copied()
        .max_by(|a, b| a.abs().total_cmp(&b.abs()))
        .unwrap_or(1.0);
    if big < 0.0 { v.map(|x| -x) } else { v }
}

/// Eigenvalues (ascending) and unit eigenvectors of a symmetric matrix, by cyclic Jacobi
/// rotations.
// Indices, as the matrix algebra is written.
#[allow(clippy::needless_range_loop)]
pub fn jacobi<const N: usize>(mut a: [[f64; N]; N]) -> ([f64; N], [[f64; N]; N]) {
    let mut v = [[0.0; N]; N];
    for (i, row) in v.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    for _ in 0..64 {
        let off: f64 = (0..N)
            .flat_map(|i| (0..N).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i][j] * a[i][j])
            .sum();
        if off < 1e-24 {
            break;
        }
        for p in 0..N {
            for q in p + 1..N {
                if a[p][q].abs() < 1e-300 {
                    continue;
                }
                let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = theta.signum().max(0.0) * 2.0 - 1.0;
                let t = t / (theta.abs() + (theta * theta + 1.0).sqrt());
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                for k in 0..N {
                    let (akp, akq) = (a[k][p], a[k][q]);
                    a[k][p] = c * akp - s * akq;
                    a[k][q] = s * akp + c * akq;
                }
                for k in 0..N {
                    let (apk, aqk) = (a[p][k], a[q][k]);
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for row in v.iter_mut() {
                    let (vkp, vkq) = (row[p], row[q]);
                    row[p] = c * vkp - s * vkq;
                    row[q] = s * vkp + c * vkq;
                }
            }
        }
    }
    let mut order: [usize; N] = std::array::from_fn(|i| i);
    order.sort_by(|&i, &j| a[i][i].total_cmp(&a[j][j]));
    let values = order.map(|i| a[i][i]);
    let vectors = order.map(|i| std::array::from_fn(|k| v[k][i]));
    (values, vectors)
}

/// Whether the phase means the platform is standing still.
pub fn is_still(p: Phase) -> bool {
    p == Phase::Still
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn jacobi_finds_eigenpairs() {
        let m = [[4.0, 1.0, 0.5], [1.0, 3.0, 0.2], [0.5, 0.2, 1.0]];
        let (vals, vecs) = jacobi(m);
        assert!(vals[0] <= vals[1] && vals[1] <= vals[2]);
        for (l, v) in vals.iter().zip(&vecs) {
            for i in 0..3 {
                let mv: f64 = (0..3).map(|k| m[i][k] * v[k]).sum();
                assert!((mv - l * v[i]).abs() < 1e-9);
            }
        }
    }

    #[test]
    fn a_tube_is_degenerate_along_its_axis_and_a_box_room_is_not() {
        // Returns from the wall of a tube along x: normals in the y-z plane.
        let mut tube = Scan::default();
        let mut room = Scan::default();
        let add = |scan: &mut Scan, q: [f64; 3], n: [f64; 3]| {
            crate::lidar::scan::accumulate(&mut scan.hessian, q, n);
            scan.range2 += q.iter().map(|x| x * x).sum::<f64>();
            scan.returns += 1;
        };
        for i in 0..400 {
            let a = i as f64 * 0.1;
            let x = (i % 20) as f64 - 10.0;
            add(
                &mut tube,
                [x, 2.0 * a.cos(), 2.0 * a.sin()],
                [0.0, -a.cos(), -a.sin()],
            );
            let axis = i % 3;
            let mut n = [0.0; 3];
            n[axis] = if i % 2 == 0 { 1.0 } else { -1.0 };
            add(&mut room, [x, a.sin() * 3.0, a.cos() * 2.0], n);
        }
        let t = degeneracy(&tube);
        assert!(t.degenerate && t.score < 1e-6, "{t:?}");
        assert!(t.weakest_translation[0] > 0.999, "{t:?}");
        let r = degeneracy(&room);
        assert!(!r.degenerate && r.score > 0.5, "{r:?}");
        // Driving along the tube it slides; across it (were it possible) it would not.
        let along = with_travel(t.clone(), &tube, [2.0, 0.0, 0.0]);
        assert!(
            along.slides && along.along_travel.unwrap() < 1e-6,
            "{along:?}"
        );
        let across = with_travel(t, &tube, [0.0, 2.0, 0.0]);
        assert!(
            !across.slides && across.along_travel.unwrap() > 0.4,
            "{across:?}"
        );
        let still = with_travel(r, &room, [0.0, 0.0, 0.05]);
        assert!(still.along_travel.is_none() && !still.slides);
    }
}
