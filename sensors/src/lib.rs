//! # subtgraph-sensors
//!
//! Sensor sequences without a simulator: a LiDAR, an IMU and ground-truth poses along a route
//! through a subtgraph world, written as a ROS 2 bag, a KITTI folder and a TUM trajectory that
//! SLAM and odometry methods read as they are, with a label per scan.
//!
//! The paper stress-tests LiDAR-inertial odometry in its worlds with Gazebo, ROS, a robot model
//! and an operator per world. None of that is needed to make what those methods read: the
//! world's visual surface and its ground-truth graph suffice. A route is planned on the
//! graph ([`route`]) and timed into a smooth trajectory ([`trajectory`]); a LiDAR model
//! ([`lidar`]) casts its rays into the surface with the core's ray caster
//! ([`subtgraph_core::raycast`]), the one the world's survey holds over the visual surface
//! and a mine's services ([`subtgraph_survey::WorldSurvey::scan_rays`]; what each triangle
//! is: [`surface`]), from the pose the sensor has at each ray's instant; an IMU
//! ([`imu`]) reads the trajectory's exact derivatives; and the writers ([`write`](mod@write)) stream it all
//! to disk. [`request::SenseRequest`] is the `subtgraph sense` command; a dataset worker that
//! already holds a world and its survey calls [`scene::Scene::of_survey`], [`sequence::Sequence::plan`] and
//! [`sequence::Sequence::write`] directly.
//!
//! Everything is deterministic: the same world, options and seed give byte-identical folders
//! on any number of threads.

pub mod camera;
pub mod camera_stream;
pub mod conditions;
pub mod error;
pub mod frames;
pub mod graph;
pub mod imu;
pub mod labels;
pub mod lidar;
pub mod noise;
pub mod platform;
pub mod request;
pub mod route;
pub mod scene;
pub mod sequence;
pub mod surface;
pub mod trajectory;
pub mod write;

pub use error::{HostError, SenseError};
pub use request::{CameraRequest, Host, SenseRequest};
pub use scene::Scene;
pub use sequence::{Options, Sequence, Summary};
