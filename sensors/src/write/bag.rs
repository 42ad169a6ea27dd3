//! The ROS 2 bag: `bag/bag_0.mcap` and `bag/metadata.yaml`, topics as a robot records them.
//!
//! | topic | type | frame |
//! |---|---|---|
//! | `/points` | `sensor_msgs/msg/PointCloud2`, the driver's fields | the LiDAR's (`os_sensor`, `velodyne`, `livox_frame`) |
//! | `/imu` | `sensor_msgs/msg/Imu` | `imu_link` |
//! | `/ground_truth/odom` | `nav_msgs/msg/Odometry`, `map` to `base_link` | `map` |
//! | `/wheel/odom` (with wheel odometry) | `nav_msgs/msg/Odometry`, `odom` to `base_link` | `odom` |
//! | `/tf_static` | `tf2_msgs/msg/TFMessage`: `base_link` to the LiDAR and the IMU (and the cameras) | |
//!
//! With cameras, their images and calibrations too ([`super::camera_msgs`]); without a LiDAR
//! (`--lidar none`), no `/points`.
//!
//! Frames follow REP 103 and REP 105: `map` is the world folder's frame (x east, y north,
//! z up), `base_link` the platform's. A point cloud is stamped with its scan's start (the
//! time of its first column, as ouster-ros and the Velodyne driver stamp theirs) and logged at
//! that stamp too: readers that take a bag's log times for the scans' (KISS-ICP does) then
//! agree with the ground truth, which is at the scans' starts.

use std::io;
use std::path::{Path, PathBuf};

use super::camera_msgs;
use super::cdr::{self, FLOAT32, FLOAT64, Field, UINT8, UINT16, UINT32};
use super::mcap::Mcap;
use crate::frames::Pose;
use crate::lidar::scan::Scan;
use crate::lidar::{Driver, LidarModel};
use subtgraph_core::direct_file::{DirectFile, Spool};

/// Frame names.
pub const MAP: &str = "map";
/// The platform's body.
pub const BASE: &str = "base_link";
/// The IMU.
pub const IMU: &str = "imu_link";
/// Wheel odometry's fixed frame.
pub const ODOM: &str = "odom";

/// Reliable, volatile (what the drivers offer), in rosbag2's QoS text (version 5).
const QOS: &str = "- history: 3\n  depth: 0\n  reliability: 1\n  durability: 2\n  deadline:\n    sec: 9223372036\n    nsec: 854775807\n  lifespan:\n    sec: 9223372036\n    nsec: 854775807\n  liveliness: 1\n  liveliness_lease_duration:\n    sec: 9223372036\n    nsec: 854775807\n  avoid_ros_namespace_conventions: false";

/// Reliable, transient local: late subscribers still get `/tf_static`, as tf2 publishes it.
fn qos_latched() -> String {
    QOS.replace("durability: 2", "durability: 1")
}

/// A topic of the bag.
struct Topic {
    name: String,
    type_name: &'static str,
    channel: u16,
    qos: String,
}

/// The bag being written.
pub struct Bag {
    mcap: Mcap<DirectFile>,
    dir: PathBuf,
    topics: Vec<Topic>,
    model: Option<LidarModel>,
    /// Scratch for reordering an organized cloud.
    order: Vec<usize>,
    /// Whether an Ouster cloud carries the `return_kind` debug field (under conditions).
    kinds: bool,
}

/// Nanoseconds from seconds.
pub fn ns(t: f64) -> u64 {
    (t.max(0.0) * 1e9).round() as u64
}

impl Bag {
    /// Starts a bag in `dir` (which must exist), with `/points` for a LiDAR `model`, and the
    /// `extra` topics (name, message type) after the others; `kinds` adds the `return_kind`
    /// debug field to an Ouster cloud (a byte of its record's padding: what made each return,
    /// or took it).
    pub fn create(
        dir: &Path,
        model: Option<&LidarModel>,
        wheel: bool,
        kinds: bool,
        extra: &[(String, &'static str)],
    ) -> io::Result<Bag> {
        let file = DirectFile::create(&dir.join("bag_0.mcap"), Spool::new()?)?;
        let mut mcap = Mcap::new(file)?;
        let mut topics = Vec::new();
        let mut list: Vec<(String, &'static str, String)> = Vec::new();
        if model.is_some() {
            list.push(("/points".into(), "sensor_msgs/msg/PointCloud2", QOS.into()));
        }
        list.extend([
            ("/imu".into(), "sensor_msgs/msg/Imu", QOS.into()),
            (
                "/ground_truth/odom".into(),
                "nav_msgs/msg/Odometry",
                QOS.into(),
            ),
            ("/tf_static".into(), "tf2_msgs/msg/TFMessage", qos_latched()),
        ]);
        if wheel {
            list.push(("/wheel/odom".into(), "nav_msgs/msg/Odometry", QOS.into()));
        }
        list.extend(extra.iter().map(|(n, t)| (n.clone(), *t, QOS.to_owned())));
        let mut schemas: Vec<(&str, u16)> = Vec::new();
        for (name, type_name, qos) in list {
            let schema = match schemas.iter().find(|(t, _)| *t == type_name) {
                Some(&(_, id)) => id,
                None => {
                    let definition = cdr::schema(type_name)
                        .or_else(|| camera_msgs::schema(type_name))
                        .unwrap_or_default();
                    let id = mcap.schema(type_name, &definition)?;
                    schemas.push((type_name, id));
                    id
                }
            };
            let channel = mcap.channel(schema, &name, &[("offered_qos_profiles", &qos)])?;
            topics.push(Topic {
                name,
                type_name,
                channel,
                qos,
            });
        }
        Ok(Bag {
            mcap,
            dir: dir.to_owned(),
            topics,
            model: model.cloned(),
            order: Vec::new(),
            kinds,
        })
    }

    /// A message on `topic` (one of the bag's), stamped and logged at `stamp_ns`, whose CDR
    /// `fill` writes.
    pub fn publish(
        &mut self,
        topic: &str,
        stamp_ns: u64,
        fill: impl FnOnce(&mut Vec<u8>),
    ) -> io::Result<()> {
        let c = self.channel(topic);
        self.mcap.message(c, stamp_ns, stamp_ns, fill)
    }

    fn channel(&self, name: &str) -> u16 {
        self.topics
            .iter()
            .find(|t| t.name == name)
            .map_or(0, |t| t.channel)
    }

    /// The static transforms, stamped at 0 as tf2's static broadcaster latches them.
    pub fn tf_static(&mut self, transforms: &[(&str, &str, Pose)]) -> io::Result<()> {
        let c = self.channel("/tf_static");
        self.mcap
            .message(c, 0, 0, |b| cdr::tf_message(b, 0, transforms))
    }

    /// A scan's point cloud, logged at its stamp.
    pub fn scan(&mut self, scan: &Scan) -> io::Result<()> {
        let log = scan.start;
        let c = self.channel("/points");
        let stamp = ns(scan.start);
        let Some(m) = &self.model else {
            return Ok(());
        };
        let frame = m.driver.frame_id();
        match m.driver {
            Driver::Ouster => {
                // Organized: a row per ring, columns in firing order; no return is zeros.
                let (columns, rings) = m.groups();
                self.order.clear();
                for ring in 0..rings {
                    self.order
                        .extend((0..columns).map(|col| col * rings + ring));
                }
                let all = [
                    f("x", 0, FLOAT32),
                    f("y", 4, FLOAT32),
                    f("z", 8, FLOAT32),
                    f("intensity", 12, FLOAT32),
                    f("t", 16, UINT32),
                    f("reflectivity", 20, UINT16),
                    f("ring", 22, UINT16),
                    f("ambient", 24, UINT16),
                    f("range", 28, UINT32),
                    f("return_kind", 26, UINT8),
                ];
                let kinds = self.kinds;
                let fields = if kinds { &all[..] } else { &all[..9] };
                let order = &self.order;
                self.mcap.message(c, ns(log), ns(log), |b| {
                    cdr::point_cloud2(
                        b,
                        stamp,
                        frame,
                        rings as u32,
                        columns as u32,
                        fields,
                        32,
                        true,
                        |b| {
                            b.reserve(order.len() * 32);
                            for &i in order {
                                let p = &scan.points[i];
                                let mut rec = [0u8; 32];
                                let t = round_u32(f64::from(p.time) * 1e9);
                                rec[16..20].copy_from_slice(&t.to_le_bytes());
                                rec[22..24].copy_from_slice(&p.ring.to_le_bytes());
                                if kinds {
                                    rec[26] = p.kind;
                                }
                                if p.valid {
                                    for k in 0..3 {
                                        rec[4 * k..4 * k + 4]
                                            .copy_from_slice(&p.xyz[k].to_le_bytes());
                                    }
                                    let signal = ouster_signal(p.reflectance, p.range);
                                    rec[12..16].copy_from_slice(&signal.to_le_bytes());
                                    let refl = round_u16(p.reflectance * 100.0);
                                    rec[20..22].copy_from_slice(&refl.to_le_bytes());
                                    let mm = round_u32(f64::from(p.range) * 1000.0);
                                    rec[28..32].copy_from_slice(&mm.to_le_bytes());
                                }
                                b.extend_from_slice(&rec);
                            }
                        },
                    )
                })
            }
            Driver::Velodyne => {
                let fields = [
                    f("x", 0, FLOAT32),
                    f("y", 4, FLOAT32),
                    f("z", 8, FLOAT32),
                    f("intensity", 12, FLOAT32),
                    f("ring", 16, UINT16),
                    f("time", 18, FLOAT32),
                ];
                let n = scan.returns as u32;
                self.mcap.message(c, ns(log), ns(log), |b| {
                    cdr::point_cloud2(b, stamp, frame, 1, n, &fields, 22, true, |b| {
                        for p in scan.points.iter().filter(|p| p.valid) {
                            for k in 0..3 {
                                b.extend_from_slice(&p.xyz[k].to_le_bytes());
                            }
                            b.extend_from_slice(&(p.reflectance * 100.0).to_le_bytes());
                            b.extend_from_slice(&p.ring.to_le_bytes());
                            b.extend_from_slice(&p.time.to_le_bytes());
                        }
                    })
                })
            }
            Driver::Livox => {
                let fields = [
                    f("x", 0, FLOAT32),
                    f("y", 4, FLOAT32),
                    f("z", 8, FLOAT32),
                    f("intensity", 12, FLOAT32),
                    f("tag", 16, UINT8),
                    f("line", 17, UINT8),
                    f("timestamp", 18, FLOAT64),
                ];
                let n = scan.returns as u32;
                self.mcap.message(c, ns(log), ns(log), |b| {
                    cdr::point_cloud2(b, stamp, frame, 1, n, &fields, 26, true, |b| {
                        for p in scan.points.iter().filter(|p| p.valid) {
                            for k in 0..3 {
                                b.extend_from_slice(&p.xyz[k].to_le_bytes());
                            }
                            b.extend_from_slice(&(p.reflectance * 150.0).to_le_bytes());
                            b.push(0);
                            b.push(p.ring as u8);
                            let abs = ns(scan.start + f64::from(p.time)) as f64;
                            b.extend_from_slice(&abs.to_le_bytes());
                        }
                    })
                })
            }
        }
    }

    /// An IMU sample (stamped and logged at `stamp` seconds).
    pub fn imu(
        &mut self,
        stamp: f64,
        gyroscope: [f64; 3],
        accelerometer: [f64; 3],
        variances: [f64; 2],
    ) -> io::Result<()> {
        let c = self.channel("/imu");
        self.mcap.message(c, ns(stamp), ns(stamp), |b| {
            cdr::imu(b, ns(stamp), IMU, gyroscope, accelerometer, variances)
        })
    }

    /// An odometry message on `topic` (`/ground_truth/odom` or `/wheel/odom`).
    #[allow(clippy::too_many_arguments)]
    pub fn odometry(
        &mut self,
        topic: &str,
        stamp: f64,
        frame: &str,
        pose: &Pose,
        linear: [f64; 3],
        angular: [f64; 3],
        variance: f64,
    ) -> io::Result<()> {
        let c = self.channel(topic);
        self.mcap.message(c, ns(stamp), ns(stamp), |b| {
            cdr::odometry(b, ns(stamp), frame, BASE, pose, linear, angular, variance)
        })
    }

    /// Finishes the MCAP file and writes `metadata.yaml`; returns the bytes written.
    pub fn finish(mut self) -> io::Result<u64> {
        let counts = self.mcap.counts();
        let (first, last) = self.mcap.span().unwrap_or((0, 0));
        let total: u64 = counts.iter().map(|c| c.1).sum();
        let mut topics = String::new();
        for t in &self.topics {
            let n = counts.iter().find(|c| c.0 == t.channel).map_or(0, |c| c.1);
            topics.push_str(&format!(
                "    - topic_metadata:\n        name: {}\n        type: {}\n        serialization_format: cdr\n        offered_qos_profiles: \"{}\"\n      message_count: {n}\n",
                t.name,
                t.type_name,
                t.qos.replace('\n', "\\n")
            ));
        }
        let duration = last - first;
        let yaml = format!(
            "rosbag2_bagfile_information:\n  version: 5\n  storage_identifier: mcap\n  duration:\n    nanoseconds: {duration}\n  starting_time:\n    nanoseconds_since_epoch: {first}\n  message_count: {total}\n  topics_with_message_count:\n{topics}  compression_format: \"\"\n  compression_mode: \"\"\n  relative_file_paths:\n    - bag_0.mcap\n  files:\n    - path: bag_0.mcap\n      starting_time:\n        nanoseconds_since_epoch: {first}\n      duration:\n        nanoseconds: {duration}\n      message_count: {total}\n"
        );
        self.mcap
            .metadata("rosbag2", &[("serialized_metadata", &yaml)])?;
        let (_, bytes) = self.mcap.finish()?;
        std::fs::write(self.dir.join("metadata.yaml"), &yaml)?;
        Ok(bytes + yaml.len() as u64)
    }
}

fn f(name: &'static str, offset: u32, datatype: u8) -> Field {
    Field {
        name,
        offset,
        datatype,
    }
}

/// `x.round() as u32`, inline: on x86-64's baseline (no SSE4.1) `round` is a library call,
/// three of them a point. The same integer for every input: halves away from zero, negatives
/// and NaN 0, beyond the range `u32::MAX` (`x - t` is exact: the fraction of a float is one).
fn round_u32(x: f64) -> u32 {
    let t = x as u32;
    if x - f64::from(t) >= 0.5 && t < u32::MAX {
        t + 1
    } else {
        t
    }
}

/// `x.round() as u16`, inline, as [`round_u32`].
fn round_u16(x: f32) -> u16 {
    let t = x as u16;
    if x - f32::from(t) >= 0.5 && t < u16::MAX {
        t + 1
    } else {
        t
    }
}

/// An Ouster `intensity` (signal photons) for a return: the surface's reflectance over the
/// squared range, scaled to the counts the OS1 reports from rock a few metres away.
pub fn ouster_signal(reflectance: f32, range: f32) -> f32 {
    (reflectance * 20_000.0 / range.max(1.0).powi(2)).min(65_535.0)
}

/// Bytes a scan's message takes, for estimates.
pub fn scan_bytes(model: &LidarModel, returns: usize) -> u64 {
    let header = 200u64;
    header
        + match model.driver {
            Driver::Ouster => 32 * model.rays_per_scan() as u64,
            Driver::Velodyne => 22 * returns as u64,
            Driver::Livox => 26 * returns as u64,
        }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inline_rounding_matches_the_library_round_everywhere() {
        let mut xs = vec![
            0.0,
            -0.0,
            0.49999999999999994,
            0.5,
            1.5,
            2.5,
            -0.3,
            -0.5,
            -7.5,
            4294967294.5,
            4294967295.4,
            4294967295.5,
            1e20,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
        ];
        // Times in nanoseconds and ranges in millimetres, as the records hold them, and every
        // neighbour of a half.
        let mut z = 0x9e37_79b9_7f4a_7c15u64;
        for _ in 0..200_000 {
            z = crate::noise::hash(z, 1);
            let x = (z >> 11) as f64 / (1u64 << 53) as f64 * 2e8;
            let half = x.floor() + 0.5;
            let bits = half.to_bits();
            xs.extend([x, half, f64::from_bits(bits - 1), f64::from_bits(bits + 1)]);
        }
        for x in xs {
            assert_eq!(round_u32(x), x.round() as u32, "{x:e}");
            let y = x as f32 * 1e-6;
            assert_eq!(round_u16(y), y.round() as u16, "{y:e}");
            let h = (x as f32).fract() + 7.0;
            assert_eq!(round_u16(h), h.round() as u16, "{h:e}");
        }
        for y in [0.5f32, 65534.5, 65535.4, 65535.5, 1e9, -0.5, f32::NAN] {
            assert_eq!(round_u16(y), y.round() as u16, "{y:e}");
        }
    }
}
