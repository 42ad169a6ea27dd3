//! The trajectory: where the platform is at every instant, with exact derivatives.
//!
//! Position and ZYX Euler angles are six uniform quintic B-splines over time, sharing their
//! knots. A quintic B-spline has continuous derivatives up to the fourth, so velocity,
//! acceleration and jerk are continuous: an IMU sampled from it (accelerometer from the second
//! derivative, gyroscope from the first derivative of the angles) sees a physically possible
//! motion, with no steps a real platform could not make. Repeating a control point six times
//! makes the platform stand exactly still (a static start for IMU initialisation), and the
//! route's planner ([`crate::route`]) places control points at a fixed time step along a
//! time-parametrised path, so speeds and turn rates follow its limits.

use subtgraph_core::vec3::V3;

use crate::frames::{Pose, rotation_zyx};

/// The uniform quintic B-spline basis: `p(u) = [1 u u^2 u^3 u^4 u^5] M [P0 .. P5]`, times
/// 1/120.
const BASIS: [[f64; 6]; 6] = [
    [1.0, 26.0, 66.0, 26.0, 1.0, 0.0],
    [-5.0, -50.0, 0.0, 50.0, 5.0, 0.0],
    [10.0, 20.0, -60.0, 20.0, 10.0, 0.0],
    [-10.0, 20.0, 0.0, -20.0, 10.0, 0.0],
    [5.0, -20.0, 30.0, -20.0, 5.0, 0.0],
    [-1.0, 5.0, -10.0, 10.0, -5.0, 1.0],
];

/// One control point: position (metres) and `[yaw, pitch, roll]` (radians, unwrapped: yaw
/// runs on past pi rather than jumping).
pub type Control = [f64; 6];

/// A platform's motion: six quintic B-splines over time.
#[derive(Clone, Debug, PartialEq)]
pub struct Trajectory {
    dt: f64,
    control: Vec<Control>,
}

/// Everything about the platform at one instant, from the splines' exact derivatives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct State {
    /// Where the body frame is, and how it is turned.
    pub pose: Pose,
    /// World-frame velocity, m/s.
    pub velocity: V3,
    /// World-frame acceleration, m/s^2.
    pub acceleration: V3,
    /// Angular velocity in the body frame, rad/s.
    pub angular_velocity: V3,
    /// Angular acceleration in the body frame, rad/s^2.
    pub angular_acceleration: V3,
    /// `[yaw, pitch, roll]`, radians.
    pub euler: [f64; 3],
}

impl Trajectory {
    /// A trajectory through `control` points placed `dt` seconds apart (at least six).
    pub fn new(dt: f64, control: Vec<Control>) -> Trajectory {
        assert!(
            control.len() >= 6 && dt > 0.0,
            "a quintic spline needs six points"
        );
        Trajectory { dt, control }
    }

    /// How long it lasts, seconds (from 0).
    pub fn duration(&self) -> f64 {
        (self.control.len() - 5) as f64 * self.dt
    }

    /// The control points' spacing in time, seconds.
    pub fn step(&self) -> f64 {
        self.dt
    }

    /// The control points.
    pub fn control(&self) -> &[Control] {
        &self.control
    }

    /// Value and first and second time derivatives of every channel at `t` (clamped to the
    /// trajectory).
    fn channels(&self, t: f64) -> [[f64; 6]; 3] {
        let (i, u) = self.segment(t);
        // Powers of u and their first and second derivatives.
        let p = [1.0, u, u * u, u * u * u, u * u * u * u, u * u * u * u * u];
        let dp = [0.0, 1.0, 2.0 * u, 3.0 * p[2], 4.0 * p[3], 5.0 * p[4]];
        let ddp = [0.0, 0.0, 2.0, 6.0 * u, 12.0 * p[2], 20.0 * p[3]];
        let mut w = [[0.0; 6]; 3];
        for j in 0..6 {
            for k in 0..6 {
                w[0][j] += p[k] * BASIS[k][j];
                w[1][j] += dp[k] * BASIS[k][j];
                w[2][j] += ddp[k] * BASIS[k][j];
            }
        }
        let scale = [
            1.0 / 120.0,
            1.0 / (120.0 * self.dt),
            1.0 / (120.0 * self.dt * self.dt),
        ];
        let mut out = [[0.0; 6]; 3];
        for d in 0..3 {
            for (j, c) in self.control[i..i + 6].iter().enumerate() {
                for ch in 0..6 {
                    out[d][ch] += w[d][j] * c[ch];
                }
            }
            for v in &mut out[d] {
                *v *= scale[d];
            }
        }
        out
    }

    /// The body pose at `t` (position and orientation only: cheaper than [`state`](Self::state)).
    pub fn pose(&self, t: f64) -> Pose {
        let (i, u) = self.segment(t);
        let p = [1.0, u, u * u, u * u * u, u * u * u * u, u * u * u * u * u];
        let mut v = [0.0; 6];
        for (j, c) in self.control[i..i + 6].iter().enumerate() {
            let w: f64 = (0..6).map(|k| p[k] * BASIS[k][j]).sum::<f64>() / 120.0;
            for ch in 0..6 {
                v[ch] += w * c[ch];
            }
        }
        Pose::from_euler([v[0], v[1], v[2]], [v[3], v[4], v[5]])
    }

    /// The segment `t` falls in and where in it (`0..=1`), `t` clamped to the trajectory.
    fn segment(&self, t: f64) -> (usize, f64) {
        let last = self.control.len() - 6;
        let x = (t / self.dt).clamp(0.0, (last + 1) as f64);
        let i = (x.floor() as usize).min(last);
        (i, x - i as f64)
    }

    /// The full state at `t`.
    pub fn state(&self, t: f64) -> State {
        let [v, d, dd] = self.channels(t);
        let euler = [v[3], v[4], v[5]];
        let (yaw_d, pitch_d, roll_d) = (d[3], d[4], d[5]);
        let (yaw_dd, pitch_dd, roll_dd) = (dd[3], dd[4], dd[5]);
        let (sp, cp) = v[4].sin_cos();
        let (sr, cr) = v[5].sin_cos();
        // Body rates of ZYX Euler angles, and their derivative.
        let angular_velocity = [
            roll_d - yaw_d * sp,
            pitch_d * cr + yaw_d * sr * cp,
            -pitch_d * sr + yaw_d * cr * cp,
        ];
        let angular_acceleration = [
            roll_dd - yaw_dd * sp - yaw_d * pitch_d * cp,
            pitch_dd * cr - pitch_d * roll_d * sr + yaw_dd * sr * cp + yaw_d * roll_d * cr * cp
                - yaw_d * pitch_d * sr * sp,
            -pitch_dd * sr - pitch_d * roll_d * cr + yaw_dd * cr * cp
                - yaw_d * roll_d * sr * cp
                - yaw_d * pitch_d * cr * sp,
        ];
        State {
            pose: Pose {
                translation: [v[0], v[1], v[2]],
                rotation: rotation_zyx(euler),
            },
            velocity: [d[0], d[1], d[2]],
            acceleration: [dd[0], dd[1], dd[2]],
            angular_velocity,
            angular_acceleration,
            euler,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wavy() -> Trajectory {
        let control = (0..40)
            .map(|i| {
                let x = i as f64;
                [
                    x,
                    (0.3 * x).sin() * 4.0,
                    0.1 * x,
                    0.2 * x,
                    0.1 * (0.5 * x).cos(),
                    0.05 * (0.7 * x).sin(),
                ]
            })
            .collect();
        Trajectory::new(0.25, control)
    }

    #[test]
    fn the_basis_sums_to_one_and_joins_segments_smoothly() {
        for u in [0.0, 0.3, 0.77, 1.0] {
            let p = [1.0, u, u * u, u * u * u, u * u * u * u, u * u * u * u * u];
            let sum: f64 = (0..6)
                .map(|j| (0..6).map(|k| p[k] * BASIS[k][j]).sum::<f64>())
                .sum();
            assert!((sum - 120.0).abs() < 1e-9);
        }
        // Across a knot, value and derivatives agree from both sides.
        let tr = wavy();
        let knot = 10.0 * tr.step();
        let (a, b) = (tr.channels(knot - 1e-9), tr.channels(knot + 1e-9));
        for d in 0..3 {
            for ch in 0..6 {
                assert!((a[d][ch] - b[d][ch]).abs() < 1e-5, "{d} {ch}");
            }
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let tr = wavy();
        let h = 1e-5;
        for t in [1.3, 2.0, 4.71, 7.9] {
            let s = tr.state(t);
            let (a, b) = (tr.state(t - h), tr.state(t + h));
            for k in 0..3 {
                let v = (b.pose.translation[k] - a.pose.translation[k]) / (2.0 * h);
                assert!((v - s.velocity[k]).abs() < 1e-6);
                let acc = (b.velocity[k] - a.velocity[k]) / (2.0 * h);
                assert!((acc - s.acceleration[k]).abs() < 1e-5);
                let alpha = (b.angular_velocity[k] - a.angular_velocity[k]) / (2.0 * h);
                assert!((alpha - s.angular_acceleration[k]).abs() < 1e-5);
            }
            // Body angular velocity from the rotation's derivative: skew(w) = R^T dR/dt.
            let (ra, rb, r) = (a.pose.rotation, b.pose.rotation, s.pose.rotation);
            let mut rtdr = [[0.0; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    rtdr[i][j] = (0..3)
                        .map(|k| r[k][i] * (rb[k][j] - ra[k][j]) / (2.0 * h))
                        .sum();
                }
            }
            let w = [rtdr[2][1], rtdr[0][2], rtdr[1][0]];
            for k in 0..3 {
                assert!(
                    (w[k] - s.angular_velocity[k]).abs() < 1e-6,
                    "{w:?} {:?}",
                    s.angular_velocity
                );
            }
        }
    }

    #[test]
    fn six_equal_points_stand_still() {
        let mut control = vec![[3.0, 4.0, 5.0, 1.0, 0.0, 0.0]; 6];
        control.extend((1..8).map(|i| [3.0 + i as f64, 4.0, 5.0, 1.0, 0.0, 0.0]));
        let tr = Trajectory::new(0.1, control);
        let s = tr.state(0.05);
        assert_eq!(s.pose.translation, [3.0, 4.0, 5.0]);
        assert_eq!(s.velocity, [0.0; 3]);
        assert_eq!(s.acceleration, [0.0; 3]);
        assert!(tr.state(0.5).velocity[0] > 0.0);
    }
}
