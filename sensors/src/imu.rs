//! The IMU: specific force and angular rate from the trajectory's exact derivatives, with the
//! noise and bias drift of a named device.
//!
//! The accelerometer measures the IMU's acceleration minus gravity, in its own frame: at rest
//! and level it reads +9.81 m/s^2 up. Its acceleration is the platform's at the IMU's mount:
//! `a + alpha x r + omega x (omega x r)` for a mount `r` from `base_link`'s origin. The gyroscope
//! measures the body's angular velocity in the IMU's frame. Each axis gets white noise (the
//! device's noise density times the square root of the rate) and a bias that walks (its random
//! walk density times the square root of the step), the continuous-time model Kalibr and the
//! LIO methods assume.
//!
//! Defaults: the Analog Devices ADIS16448 as calibrated for the EuRoC MAV dataset (Burri et
//! al., IJRR 2016): gyroscope 1.6968e-4 rad/s/sqrt(Hz) and 1.9393e-5 rad/s^2/sqrt(Hz),
//! accelerometer 2.0e-3 m/s^2/sqrt(Hz) and 3.0e-3 m/s^3/sqrt(Hz); its datasheet gives noise
//! densities of 0.0066 deg/s/sqrt(Hz) and 0.23 mg/sqrt(Hz), of which these are the measured
//! counterparts.

use serde::Serialize;
use subtgraph_core::vec3::{V3, cross};

use crate::error::SenseError;
use crate::frames::{Pose, add, mul, mul_t};
use crate::noise;
use crate::route::GRAVITY;
use crate::trajectory::Trajectory;

/// An IMU's noise and rate.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ImuModel {
    /// The device the numbers come from.
    pub device: String,
    /// Samples per second.
    pub rate_hz: f64,
    /// Gyroscope white noise density, rad/s/sqrt(Hz).
    pub gyroscope_noise_density: f64,
    /// Gyroscope bias random walk, rad/s^2/sqrt(Hz).
    pub gyroscope_random_walk: f64,
    /// Accelerometer white noise density, m/s^2/sqrt(Hz).
    pub accelerometer_noise_density: f64,
    /// Accelerometer bias random walk, m/s^3/sqrt(Hz).
    pub accelerometer_random_walk: f64,
    /// Added to every IMU time stamp, seconds (a clock offset from the LiDAR's).
    pub time_offset_s: f64,
}

impl ImuModel {
    /// The ADIS16448 at `rate_hz`.
    pub fn adis16448(rate_hz: f64) -> ImuModel {
        ImuModel {
            device: "ADIS16448 (EuRoC calibration)".into(),
            rate_hz,
            gyroscope_noise_density: 1.6968e-4,
            gyroscope_random_walk: 1.9393e-5,
            accelerometer_noise_density: 2.0e-3,
            accelerometer_random_walk: 3.0e-3,
            time_offset_s: 0.0,
        }
    }

    /// The same device without noise or drift.
    pub fn noiseless(mut self) -> ImuModel {
        self.device.push_str(", noise off");
        self.gyroscope_noise_density = 0.0;
        self.gyroscope_random_walk = 0.0;
        self.accelerometer_noise_density = 0.0;
        self.accelerometer_random_walk = 0.0;
        self
    }

    /// Refuses rates and offsets no IMU has.
    pub fn check(&self) -> Result<(), SenseError> {
        if !(self.rate_hz >= 10.0 && self.rate_hz <= 4000.0) {
            return Err(SenseError::OutOfBounds {
                what: "--imu-rate".into(),
                value: format!("{} Hz", self.rate_hz),
                bounds: "10 to 4000 Hz".into(),
            });
        }
        if self.time_offset_s.is_nan() || self.time_offset_s.abs() > 1.0 {
            return Err(SenseError::OutOfBounds {
                what: "--imu-time-offset".into(),
                value: format!("{} s", self.time_offset_s),
                bounds: "within -1 to 1 seconds".into(),
            });
        }
        Ok(())
    }
}

/// One IMU sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuSample {
    /// Its time stamp, seconds (the true time plus the model's offset).
    pub stamp: f64,
    /// Angular rate, rad/s, IMU frame.
    pub gyroscope: V3,
    /// Specific force, m/s^2, IMU frame.
    pub accelerometer: V3,
    /// The biases in this reading, gyroscope (rad/s) and accelerometer (m/s^2): the ground
    /// truth EuRoC's `state_groundtruth_estimate0` gives.
    pub bias: [V3; 2],
}

/// The noise-free reading at time `t` of an IMU mounted at `mount` in `base_link`.
pub fn truth(trajectory: &Trajectory, mount: &Pose, t: f64) -> (V3, V3) {
    let s = trajectory.state(t);
    let (w, alpha, r) = (
        s.angular_velocity,
        s.angular_acceleration,
        mount.translation,
    );
    // The mount's acceleration in the body frame, then in the world.
    let lever = add(cross(alpha, r), cross(w, cross(w, r)));
    let a_world = add(s.acceleration, mul(&s.pose.rotation, lever));
    let f_body = mul_t(&s.pose.rotation, add(a_world, [0.0, 0.0, GRAVITY]));
    (mul_t(&mount.rotation, w), mul_t(&mount.rotation, f_body))
}

/// Samples an IMU along a trajectory, in order: its biases walk from one sample to the next.
pub struct ImuStream<'a> {
    model: &'a ImuModel,
    trajectory: &'a Trajectory,
    mount: Pose,
    seed: u64,
    next: u64,
    bias: [V3; 2],
}

impl<'a> ImuStream<'a> {
    /// A stream starting at time 0 with zero biases.
    pub fn new(model: &'a ImuModel, trajectory: &'a Trajectory, mount: Pose, seed: u64) -> Self {
        ImuStream {
            model,
            trajectory,
            mount,
            seed: noise::hash(seed, 0x1e0_u64),
            next: 0,
            bias: [[0.0; 3]; 2],
        }
    }

    /// The true time of the next sample.
    pub fn peek_time(&self) -> f64 {
        self.next as f64 / self.model.rate_hz
    }

    /// The next sample.
    pub fn sample(&mut self) -> ImuSample {
        let k = self.next;
        self.next += 1;
        let dt = 1.0 / self.model.rate_hz;
        let t = k as f64 * dt;
        let (gyro, accel) = truth(self.trajectory, &self.mount, t);
        let m = self.model;
        let white = [
            m.gyroscope_noise_density / dt.sqrt(),
            m.accelerometer_noise_density / dt.sqrt(),
        ];
        let walk = [
            m.gyroscope_random_walk * dt.sqrt(),
            m.accelerometer_random_walk * dt.sqrt(),
        ];
        let mut out = [gyro, accel];
        let bias = self.bias;
        for (s, reading) in out.iter_mut().enumerate() {
            for (axis, r) in reading.iter_mut().enumerate() {
                let key = k * 12 + (s * 6 + axis) as u64;
                *r += self.bias[s][axis] + white[s] * noise::normal(self.seed, key);
                self.bias[s][axis] += walk[s] * noise::normal(self.seed, key + 3);
            }
        }
        ImuSample {
            stamp: t + m.time_offset_s,
            gyroscope: out[0],
            accelerometer: out[1],
            bias,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn at_rest_the_accelerometer_reads_gravity_up_and_the_gyroscope_nothing() {
        let tr = Trajectory::new(0.1, vec![[1.0, 2.0, 3.0, 0.4, 0.0, 0.0]; 10]);
        let (g, a) = truth(&tr, &Pose::translated([0.1, 0.0, 0.5]), 0.2);
        assert!(g.iter().all(|x| x.abs() < 1e-12));
        assert!((a[2] - GRAVITY).abs() < 1e-12 && a[0].abs() < 1e-12);
    }

    #[test]
    fn turning_in_place_an_offset_imu_feels_the_centripetal_pull() {
        // Yaw at a constant 1 rad/s (control points on a line), the IMU 0.5 m ahead.
        let control = (0..40)
            .map(|i| [0.0, 0.0, 0.0, 0.1 * i as f64, 0.0, 0.0])
            .collect();
        let tr = Trajectory::new(0.1, control);
        let (g, a) = truth(&tr, &Pose::translated([0.5, 0.0, 0.0]), 2.0);
        assert!((g[2] - 1.0).abs() < 1e-9, "{g:?}");
        // omega^2 r towards the centre: -0.5 m/s^2 along the IMU's x.
        assert!((a[0] + 0.5).abs() < 1e-9, "{a:?}");
    }
}
