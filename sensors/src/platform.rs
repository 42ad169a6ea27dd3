//! Platforms: what carries the sensors, with its limits (speed, acceleration, turn rate), the
//! room it needs (clearance) and where its sensors are mounted.
//!
//! Two built-ins, named as the command line takes them: `ground`, a wheeled robot the size of
//! a Clearpath Jackal with its LiDAR on a short mast (it drives corridors and ramps, never
//! shafts), and `aerial`, a small quadrotor that flies along passages at a fixed height above
//! their floor and climbs shafts along their axis.

use serde::Serialize;
use subtgraph_core::vec3::V3;

use crate::error::SenseError;
use crate::frames::Pose;

/// Ground or aerial.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Kind {
    /// Drives on the floor: corridors and ramps.
    Ground,
    /// Flies: corridors, ramps and shafts.
    Aerial,
}

/// A platform's limits and mounts.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Platform {
    /// `ground` or `aerial`.
    pub name: &'static str,
    /// Ground or aerial.
    pub kind: Kind,
    /// Cruising speed, m/s (the speed on straight, level passages).
    pub max_speed: f64,
    /// Speed up or down a shaft, m/s.
    pub max_climb: f64,
    /// Acceleration and braking, m/s^2.
    pub max_acceleration: f64,
    /// Sideways acceleration in bends, m/s^2 (limits the speed through them).
    pub max_lateral_acceleration: f64,
    /// Turn rate, rad/s.
    pub max_yaw_rate: f64,
    /// Radius of the sphere about the clearance point that must be free of rock, metres.
    pub clearance: f64,
    /// Height of the clearance point above the platform's reference (the floor for a ground
    /// robot, the body's centre for an aerial one), metres.
    pub clearance_height: f64,
    /// Flying height above the floor, metres (aerial; lower in passages under twice its
    /// height).
    pub altitude: f64,
    /// Seconds standing still before moving (IMU initialisation) and after stopping.
    pub still: [f64; 2],
    /// The LiDAR in `base_link`.
    #[serde(skip)]
    pub lidar: Pose,
    /// The IMU in `base_link`.
    #[serde(skip)]
    pub imu: Pose,
}

/// The names the command line takes.
pub const NAMES: [&str; 2] = ["ground", "aerial"];

/// The IMU's offset from the LiDAR's origin: an Ouster OS1's internal IMU (its documented
/// `imu_to_sensor_transform`, millimetres converted to metres).
const IMU_IN_LIDAR: V3 = [0.006253, -0.011775, 0.007645];

impl Platform {
    /// A built-in platform by name.
    pub fn named(name: &str) -> Result<Platform, SenseError> {
        let mast = |h: f64| Pose::translated([0.0, 0.0, h]);
        let imu =
            |h: f64| Pose::translated([IMU_IN_LIDAR[0], IMU_IN_LIDAR[1], h + IMU_IN_LIDAR[2]]);
        match name {
            "ground" => Ok(Platform {
                name: "ground",
                kind: Kind::Ground,
                max_speed: 2.0,
                max_climb: 0.0,
                max_acceleration: 1.0,
                max_lateral_acceleration: 1.0,
                max_yaw_rate: 1.0,
                clearance: 0.3,
                clearance_height: 0.55,
                altitude: 0.0,
                still: [2.0, 1.0],
                lidar: mast(0.6),
                imu: imu(0.6),
            }),
            "aerial" => Ok(Platform {
                name: "aerial",
                kind: Kind::Aerial,
                max_speed: 2.0,
                max_climb: 1.0,
                max_acceleration: 1.5,
                max_lateral_acceleration: 1.5,
                max_yaw_rate: 1.0,
                clearance: 0.5,
                clearance_height: 0.0,
                altitude: 1.5,
                still: [2.0, 1.0],
                lidar: mast(0.15),
                imu: imu(0.15),
            }),
            other => Err(SenseError::Unknown {
                what: "platform",
                name: other.to_owned(),
                known: NAMES.join(", "),
            }),
        }
    }
}
