//! A sequence: a route planned through a scene, the sensors sampled along it, every file
//! streamed to disk scan by scan (frame by frame, with cameras and no LiDAR).
//!
//! Memory does not grow with the route's length beyond its trajectory (a few hundred bytes per
//! second of driving): scans are cast into two reused buffers, the next cast while the last is
//! written (so the two cores share ray casting, compression and writing), the bag's chunks are
//! written as they fill, and `sequence.json`'s labels are written one per line as each scan is
//! done. Before anything is cast, [`Sequence::estimate`] says how many bytes the folder will
//! take, so a run that cannot fit is refused first ([`Sequence::check_disk`]).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;

use serde::Serialize;
use subtgraph_core::vec3::V3;

use crate::camera::light::Rig;
use crate::camera::scene::CameraScene;
use crate::camera_stream::{CameraOptions, Frames, Outputs, frame_bytes};
use crate::conditions::{Active, Conditions};
use crate::error::SenseError;
use crate::frames::{Pose, mul_t};
use crate::graph::RouteGraph;
use crate::imu::{ImuModel, ImuStream};
use crate::labels;
use crate::lidar::LidarModel;
use crate::lidar::scan::{Scan, Scanner};
use crate::platform::{Kind, Platform};
use crate::route::{Route, RouteKind};
use crate::scene::Scene;
use crate::write::Formats;
use crate::write::bag::{self, Bag};
use crate::write::kitti::{Kitti, Tum};

/// Ground-truth odometry messages a second.
const ODOMETRY_HZ: f64 = 100.0;
/// Wheel odometry messages a second.
const WHEEL_HZ: f64 = 50.0;
/// The receiver range the conditions are placed with when a sequence has cameras and no LiDAR,
/// metres (the cameras' air does not use it; drips reach this far about the platform).
const CAMERA_RANGE_M: [f64; 2] = [0.3, 100.0];

/// What to make.
#[derive(Clone, Debug)]
pub struct Options {
    /// The platform.
    pub platform: Platform,
    /// The route.
    pub route: RouteKind,
    /// The LiDAR (`None`: `--lidar none`).
    pub lidar: Option<LidarModel>,
    /// The cameras (`None`: no camera).
    pub camera: Option<CameraOptions>,
    /// The IMU.
    pub imu: ImuModel,
    /// Which outputs.
    pub formats: Formats,
    /// Also publish wheel odometry (ground platforms).
    pub wheel_odometry: bool,
    /// The seed of the route's choices and the sensors' noise.
    pub seed: u64,
    /// Stop after this many seconds (the whole route without).
    pub duration: Option<f64>,
    /// Start this many seconds into the route (a window; the start without).
    pub start: Option<f64>,
    /// Dust, fog, wet rock, drips (`None`: clear air).
    pub conditions: Option<Conditions>,
}

/// A planned sequence, ready to write.
pub struct Sequence<'a> {
    /// The world.
    pub scene: &'a Scene,
    /// Its graph.
    pub graph: &'a RouteGraph,
    /// What to make.
    pub options: Options,
    /// The route.
    pub route: Route,
    /// Scans it will have (0 without a LiDAR).
    pub scans: u64,
    /// Camera frames it will have (0 without a camera).
    pub frames: u64,
    /// What the cameras see ([`Sequence::with_camera_scene`]).
    pub camera_scene: Option<&'a CameraScene>,
    /// Seconds it lasts.
    pub duration: f64,
    /// The route's time of its first scan, seconds (0 unless a window starts later).
    pub t0: f64,
}

/// Bytes a sequence will take.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Estimate {
    /// In all, at most.
    pub bytes: u64,
    /// Per scan (both formats), at most.
    pub per_scan: u64,
    /// Per camera frame (every camera and output), at most.
    pub per_frame: u64,
}

/// What a written sequence holds.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// Scans.
    pub scans: u64,
    /// Rays cast.
    pub rays: u64,
    /// Returns.
    pub returns: u64,
    /// Seconds of sensor time.
    pub duration_s: f64,
    /// Metres of route driven (within the duration).
    pub route_length_m: f64,
    /// Bytes written.
    pub bytes: u64,
    /// Scans labelled degenerate.
    pub degenerate_scans: u64,
    /// What the cameras wrote, with cameras.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub camera: Option<CameraSummary>,
    /// Seconds spent before the first scan (rebuilding the world, building the ray caster,
    /// planning the route): for the benchmark, not written (it differs from run to run).
    #[serde(skip)]
    pub prepare_s: f64,
}

/// What a sequence's cameras wrote.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CameraSummary {
    /// Frames (each with an image of every camera).
    pub frames: u64,
    /// Images (frames times cameras).
    pub images: u64,
    /// Pixels rendered.
    pub pixels: u64,
}

impl<'a> Sequence<'a> {
    /// Plans the route and checks the options.
    pub fn plan(
        scene: &'a Scene,
        graph: &'a RouteGraph,
        options: Options,
    ) -> Result<Sequence<'a>, SenseError> {
        if let Some(l) = &options.lidar {
            l.check()?;
        }
        if let Some(c) = &options.camera {
            c.model.check()?;
        }
        if options.lidar.is_none() && options.camera.is_none() {
            return Err(SenseError::OutOfBounds {
                what: "--lidar".into(),
                value: "none".into(),
                bounds: "given a --camera (a sequence needs a LiDAR or a camera)".into(),
            });
        }
        options.imu.check()?;
        if let Some(d) = options.duration
            && !(d > 0.0 && d.is_finite())
        {
            return Err(SenseError::OutOfBounds {
                what: "--duration".into(),
                value: format!("{d} s"),
                bounds: "a positive number of seconds".into(),
            });
        }
        if options.wheel_odometry && options.platform.kind != Kind::Ground {
            return Err(SenseError::OutOfBounds {
                what: "--wheel-odometry".into(),
                value: format!("on the {} platform", options.platform.name),
                bounds: "used with --platform ground only (an aerial platform has no wheels)"
                    .into(),
            });
        }
        let route =
            crate::route::plan(graph, scene, &options.platform, options.route, options.seed)?;
        let full = route.trajectory.duration();
        let t0 = options.start.unwrap_or(0.0);
        if !(t0 >= 0.0 && t0 < full) {
            return Err(SenseError::OutOfBounds {
                what: "--start".into(),
                value: format!("{t0} s"),
                bounds: format!(
                    "0 or more and within the route's {full:.1} s (route '{}')",
                    route.kind.name()
                ),
            });
        }
        if t0 > 0.0 && options.camera.is_some() {
            return Err(SenseError::OutOfBounds {
                what: "--start".into(),
                value: format!("{t0} s"),
                bounds: "0 with --camera (cameras record from the route's start; a later window is for the LiDAR alone): drop --start, or --camera".into(),
            });
        }
        let duration = options.duration.map_or(full - t0, |d| d.min(full - t0));
        let count = |period: f64| ((duration / period).floor() as u64).max(1);
        let scans = options.lidar.as_ref().map_or(0, |l| count(l.period()));
        let frames = options
            .camera
            .as_ref()
            .map_or(0, |c| count(c.model.period()));
        Ok(Sequence {
            scene,
            graph,
            options,
            route,
            scans,
            frames,
            camera_scene: None,
            duration,
            t0,
        })
    }

    /// This sequence with what its cameras see (needed when it has cameras).
    pub fn with_camera_scene(mut self, scene: &'a CameraScene) -> Sequence<'a> {
        self.camera_scene = Some(scene);
        self
    }

    /// The bytes the folder will take, at most (the bag counted uncompressed).
    pub fn estimate(&self) -> Estimate {
        let o = &self.options;
        let mut per_scan = 600 + 110; // the label in sequence.json, the TUM line
        if let Some(lidar) = &o.lidar {
            let rays = lidar.rays_per_scan();
            if o.formats.bag {
                per_scan += bag::scan_bytes(lidar, rays);
            }
            if o.formats.kitti {
                per_scan += 16 * rays as u64 + 260;
            }
        }
        let per_frame = o
            .camera
            .as_ref()
            .map_or(0, |c| frame_bytes(&c.model, o.formats));
        let mut per_second = 0.0;
        if o.formats.bag {
            per_second += o.imu.rate_hz * 360.0 + ODOMETRY_HZ * 760.0;
            if o.wheel_odometry {
                per_second += WHEEL_HZ * 760.0;
            }
        }
        if o.formats.kitti {
            per_second += o.imu.rate_hz * 120.0;
        }
        if o.formats.euroc {
            per_second += o.imu.rate_hz * 400.0;
        }
        let bytes = self.scans * per_scan
            + self.frames * per_frame
            + (per_second * self.duration) as u64
            + 64 * 1024;
        Estimate {
            bytes,
            per_scan,
            per_frame,
        }
    }

    /// Refuses a sequence larger than `limit` bytes.
    pub fn check_disk(&self, limit: u64) -> Result<Estimate, SenseError> {
        let e = self.estimate();
        if e.bytes > limit && self.frames > 0 {
            return Err(SenseError::TooLargeWithCameras {
                estimate: e.bytes,
                per_frame: e.per_frame,
                frames: self.frames,
                limit,
            });
        }
        if e.bytes > limit {
            return Err(SenseError::TooLarge {
                estimate: e.bytes,
                per_scan: e.per_scan,
                scans: self.scans,
                limit,
            });
        }
        Ok(e)
    }

    fn scanner(&self) -> Option<Scanner<'_>> {
        self.options.lidar.as_ref().map(|lidar| {
            Scanner::new(
                lidar,
                self.scene,
                &self.route.trajectory,
                self.options.platform.lidar,
                crate::noise::hash(self.options.seed, 0x11da5),
            )
        })
    }

    /// Writes the sequence into `dir` (an empty folder): `world` describes the world in
    /// `sequence.json`. `progress` is told each scan's index as it is written.
    pub fn write(
        &self,
        dir: &Path,
        world: serde_json::Value,
        progress: &mut dyn FnMut(u64),
    ) -> Result<Summary, SenseError> {
        let io = |what: &'static str, path: &Path| {
            let path = path.to_owned();
            move |source| SenseError::Io { what, path, source }
        };
        let o = &self.options;
        // The conditions act on the LiDAR's rays and the cameras' pixels (without a LiDAR, the
        // receiver's range is the cameras' own, which the air does not use).
        let range_m = o.lidar.as_ref().map_or(CAMERA_RANGE_M, |l| l.range_m);
        let active = match &o.conditions {
            Some(c) if o.lidar.is_some() || o.camera.is_some() => Some(Active::new(
                c,
                self.graph,
                self.scene,
                &self.route,
                range_m,
                &o.platform,
                crate::noise::hash(o.seed, 0xc0d1),
            )),
            _ => None,
        };
        let debug = active.is_some() && o.lidar.is_some();
        let camera_topics = match (&o.camera, o.formats.bag) {
            (Some(c), true) => Frames::topics(&c.model),
            _ => Vec::new(),
        };
        let mut bag = if o.formats.bag {
            let d = dir.join("bag");
            std::fs::create_dir_all(&d).map_err(io("creating", &d))?;
            Some(
                Bag::create(
                    &d,
                    o.lidar.as_ref(),
                    o.wheel_odometry,
                    debug,
                    &camera_topics,
                )
                .map_err(io("writing", &d))?,
            )
        } else {
            None
        };
        let mut kitti = if o.formats.kitti {
            let d = dir.join("kitti");
            Some(Kitti::create(&d, debug).map_err(io("writing", &d))?)
        } else {
            None
        };
        let tum_path = dir.join("ground_truth.tum");
        let mut tum = Tum::create(&tum_path).map_err(io("writing", &tum_path))?;
        let json_path = dir.join("sequence.json");
        let mut json = BufWriter::new(File::create(&json_path).map_err(io("writing", &json_path))?);
        let platform = &o.platform;
        let rig = o
            .camera
            .as_ref()
            .map(|c| Rig::on(platform, &c.model, c.lamp_lumens, c.ambient_lux));
        let mut head = self.head(world, rig.as_ref());
        if let Some(a) = &active {
            head["conditions"] = a.describe();
        }
        let head = serde_json::to_string_pretty(&head).expect("plain data");
        // The head object, left open for the labels.
        let head = head.trim_end().trim_end_matches('}').trim_end();
        write!(json, "{head},\n  \"scans\": [\n").map_err(io("writing", &json_path))?;

        if let Some(b) = &mut bag {
            let mut frames: Vec<(String, Pose)> = Vec::new();
            if let Some(lidar) = &o.lidar {
                frames.push((lidar.driver.frame_id().into(), platform.lidar));
            }
            frames.push((bag::IMU.into(), platform.imu));
            if let (Some(c), Some(rig)) = (&o.camera, &rig) {
                frames.extend(Frames::transforms(&c.model, rig));
            }
            let tf: Vec<(&str, &str, Pose)> = frames
                .iter()
                .map(|(child, pose)| (bag::BASE, child.as_str(), *pose))
                .collect();
            b.tf_static(&tf).map_err(io("writing", dir))?;
        }
        let mut frames = match (&o.camera, &rig) {
            (Some(c), Some(rig)) => {
                let scene = self.camera_scene.ok_or(SenseError::NoMesh)?;
                let outputs = Outputs {
                    bag: o.formats.bag,
                    euroc: o.formats.euroc,
                    tum: o.formats.tum,
                };
                let imu = (&o.imu, &platform.imu);
                Some(
                    Frames::create(
                        dir,
                        scene,
                        &self.route,
                        rig,
                        c,
                        outputs,
                        self.frames,
                        imu,
                        o.seed,
                    )
                    .map_err(io("writing", dir))?
                    .with_air(active.as_ref()),
                )
            }
            _ => None,
        };
        let scanner = self.scanner().map(|s| s.with_conditions(active.as_ref()));
        let trajectory = &self.route.trajectory;
        let mut imu = ImuStream::new(&o.imu, trajectory, platform.imu, o.seed);
        let variances = [
            o.imu.gyroscope_noise_density.powi(2) * o.imu.rate_hz,
            o.imu.accelerometer_noise_density.powi(2) * o.imu.rate_hz,
        ];
        let t0 = self.t0;
        let mut odometry_next = (t0 * ODOMETRY_HZ).ceil() as u64;
        let mut wheel = Wheel::new(o.seed);
        // The sequence's ticks: its scans, or without a LiDAR its camera frames.
        let (ticks, period) = match (&o.lidar, &o.camera) {
            (Some(l), _) => (self.scans, l.period()),
            (None, Some(c)) => (self.frames, c.model.period()),
            (None, None) => (0, 1.0),
        };
        let mut summary = Summary {
            scans: self.scans,
            rays: 0,
            returns: 0,
            duration_s: self.duration,
            route_length_m: 0.0,
            bytes: 0,
            degenerate_scans: 0,
            camera: None,
            prepare_s: 0.0,
        };
        let mut buffers = [Scan::default(), Scan::default()];
        if let Some(s) = &scanner {
            s.scan(0, t0, &mut buffers[0]);
        }
        let mut last_position: Option<V3> = None;
        let mut first_label = true;
        for k in 0..ticks {
            let (current, next) = buffers.split_at_mut(1);
            let (current, next) = if k % 2 == 0 {
                (&mut current[0], &mut next[0])
            } else {
                (&mut next[0], &mut current[0])
            };
            let cast_next = || {
                if let Some(s) = &scanner
                    && k + 1 < ticks
                {
                    s.scan(k + 1, t0 + (k + 1) as f64 * period, next);
                }
            };
            let scan: Option<&Scan> = scanner.as_ref().map(|_| &*current);
            let write_this = || -> Result<(Option<labels::Label>, Pose), SenseError> {
                let start = t0 + k as f64 * period;
                let publish = start + period;
                // Everything logged before this scan's cloud arrives.
                log_imu(
                    &mut imu,
                    [t0, publish],
                    &mut bag,
                    &mut kitti,
                    &mut frames,
                    variances,
                    &platform.imu,
                )
                .map_err(io("writing", dir))?;
                while (odometry_next as f64) / ODOMETRY_HZ <= publish {
                    let t = odometry_next as f64 / ODOMETRY_HZ;
                    odometry_next += 1;
                    if let Some(b) = &mut bag {
                        let s = trajectory.state(t);
                        let v = mul_t(&s.pose.rotation, s.velocity);
                        b.odometry(
                            "/ground_truth/odom",
                            t,
                            bag::MAP,
                            &s.pose,
                            v,
                            s.angular_velocity,
                            0.0,
                        )
                        .map_err(io("writing", dir))?;
                    }
                }
                if o.wheel_odometry {
                    while wheel.next_time() <= publish {
                        let (t, pose, v, w) = wheel.step(trajectory);
                        if t < t0 {
                            continue;
                        }
                        if let Some(b) = &mut bag {
                            b.odometry("/wheel/odom", t, bag::ODOM, &pose, v, w, 1e-3)
                                .map_err(io("writing", dir))?;
                        }
                    }
                }
                let (label, pose) = match (scan, &scanner) {
                    (Some(scan), Some(scanner)) => {
                        if let Some(b) = &mut bag {
                            b.scan(scan).map_err(io("writing", dir))?;
                        }
                        let pose = scanner.pose(scan.start);
                        if let Some(kt) = &mut kitti {
                            kt.scan(scan, &pose).map_err(io("writing", dir))?;
                        }
                        let wall = self
                            .scene
                            .caster
                            .nearest(pose.translation, 100.0)
                            .map_or(100.0, |n| n.distance);
                        let mut label = labels::label(scan, &self.route, wall);
                        if let Some(a) = &active {
                            let rays = scan.points.len();
                            label.conditions =
                                Some(a.label(scan.start, pose.translation, &scan.kinds, rays));
                        }
                        (Some(label), pose)
                    }
                    // Without a LiDAR, the ground truth is the first camera's.
                    _ => (
                        None,
                        trajectory
                            .pose(start)
                            .then(&rig.as_ref().map_or(Pose::IDENTITY, |r| r.cameras[0])),
                    ),
                };
                tum.pose(start, &pose).map_err(io("writing", &tum_path))?;
                if let Some(f) = &mut frames {
                    f.write_until(publish, &mut bag)
                        .map_err(io("writing", dir))?;
                }
                Ok((label, pose))
            };
            let ((), written) = rayon::join(cast_next, write_this);
            let (label, pose) = written?;
            if let (Some(scan), Some(label)) = (scan, &label) {
                summary.rays += scan.points.len() as u64;
                summary.returns += scan.returns as u64;
                if label.degeneracy.as_ref().is_some_and(|d| d.degenerate) {
                    summary.degenerate_scans += 1;
                }
                let line = serde_json::to_string(label).expect("plain data");
                let sep = if first_label { "" } else { ",\n" };
                first_label = false;
                write!(json, "{sep}    {line}").map_err(io("writing", &json_path))?;
            }
            if let Some(p) = last_position {
                summary.route_length_m +=
                    crate::frames::norm(subtgraph_core::vec3::sub(pose.translation, p));
            }
            last_position = Some(pose.translation);
            progress(k);
        }
        if !first_label {
            writeln!(json).map_err(io("writing", &json_path))?;
        }
        // The IMU and odometry to the end of the last scan (and frame).
        let end = t0
            + (ticks as f64 * period).max(
                o.camera
                    .as_ref()
                    .map_or(0.0, |c| self.frames as f64 * c.model.period()),
            );
        log_imu(
            &mut imu,
            [t0, end],
            &mut bag,
            &mut kitti,
            &mut frames,
            variances,
            &platform.imu,
        )
        .map_err(io("writing", dir))?;
        if let Some(f) = &mut frames {
            f.write_until(f64::INFINITY, &mut bag)
                .map_err(io("writing", dir))?;
        }
        let labels_file = match frames {
            Some(f) => {
                let (bytes, labels) = f.finish().map_err(io("writing", dir))?;
                summary.bytes += bytes;
                let c = o.camera.as_ref().map(|c| &c.model);
                summary.camera = c.map(|m| CameraSummary {
                    frames: self.frames,
                    images: self.frames * m.cameras.len() as u64,
                    pixels: self.frames * m.pixels_per_frame(),
                });
                Some(labels)
            }
            None => None,
        };
        if let Some(b) = bag {
            summary.bytes += b.finish().map_err(io("writing", dir))?;
        }
        if let Some(kt) = kitti {
            summary.bytes += kt.finish().map_err(io("writing", dir))?;
        }
        summary.bytes += tum.finish().map_err(io("writing", &tum_path))?;
        summary.route_length_m = (summary.route_length_m * 1000.0).round() / 1000.0;
        write!(json, "  ]").map_err(io("writing", &json_path))?;
        if let Some(path) = labels_file {
            // The frames' labels, one a line, taken in from the file they waited in.
            let text = std::fs::read_to_string(&path).map_err(io("reading", &path))?;
            write!(json, ",\n  \"camera_frames\": [\n").map_err(io("writing", &json_path))?;
            for (i, line) in text.lines().enumerate() {
                let sep = if i == 0 { "" } else { ",\n" };
                write!(json, "{sep}    {line}").map_err(io("writing", &json_path))?;
            }
            write!(json, "\n  ]").map_err(io("writing", &json_path))?;
            std::fs::remove_file(&path).map_err(io("removing", &path))?;
        }
        let tail = serde_json::to_string_pretty(&serde_json::json!({ "summary": &summary }))
            .expect("plain data");
        let tail = tail.trim_start().trim_start_matches('{');
        writeln!(json, ",{tail}").map_err(io("writing", &json_path))?;
        json.flush().map_err(io("writing", &json_path))?;
        Ok(summary)
    }

    /// `sequence.json`'s head: everything but the labels and the summary.
    fn head(&self, world: serde_json::Value, rig: Option<&Rig>) -> serde_json::Value {
        let o = &self.options;
        let pose = |p: &Pose| {
            serde_json::json!({
                "translation": p.translation,
                "quaternion_xyzw": p.quaternion(),
            })
        };
        let mut head = serde_json::json!({
            "format": "subtgraph-sequence/1",
            "world": world,
            "seed": o.seed,
            "frames": {
                "world": bag::MAP,
                "base": bag::BASE,
                "lidar": o.lidar.as_ref().map(|l| l.driver.frame_id()),
                "imu": bag::IMU,
                "convention": "REP 103/105: metres, x east, y north, z up in map (the world folder's frame); x forward, y left, z up in base_link",
            },
            "platform": &o.platform,
            "extrinsics": {
                "base_link_to_lidar": pose(&o.platform.lidar),
                "base_link_to_imu": pose(&o.platform.imu),
            },
            "lidar": &o.lidar,
            "imu": &o.imu,
            "wheel_odometry": o.wheel_odometry,
            "outputs": {
                "bag": o.formats.bag,
                "kitti": o.formats.kitti,
                "ground_truth": "ground_truth.tum and kitti/poses.txt: the LiDAR's pose at each scan's start, world frame",
            },
            "route": {
                "kind": self.route.kind.name(),
                "nodes": &self.route.nodes,
                "legs": &self.route.legs,
                "length_m": (self.route.length * 1000.0).round() / 1000.0,
                "duration_s": self.route.trajectory.duration(),
                "control_step_s": self.route.trajectory.step(),
            },
            "scan_count": self.scans,
            "scan_period_s": o.lidar.as_ref().map(LidarModel::period),
            "degenerate_below": labels::DEGENERATE,
        });
        if self.t0 > 0.0 {
            head["window_start_s"] = self.t0.into();
        }
        if let (Some(c), Some(rig), Some(scene)) = (&o.camera, rig, self.camera_scene) {
            head["camera"] = crate::camera_stream::head(c, rig, scene, self.frames);
            head["outputs"]["euroc"] = o.formats.euroc.into();
            head["outputs"]["tum_rgbd"] = o.formats.tum.into();
            if o.lidar.is_none() {
                head["outputs"]["ground_truth"] = "ground_truth.tum: the first camera's optical frame at each frame's stamp, world frame".into();
            }
        }
        head
    }
}

/// Wheel odometry: the body's forward speed and yaw rate, with a scale error and noise,
/// integrated in the plane from where the robot started (the `odom` frame).
struct Wheel {
    seed: u64,
    next: u64,
    pose: [f64; 3],
    scale: f64,
}

impl Wheel {
    fn new(seed: u64) -> Wheel {
        let seed = crate::noise::hash(seed, 0x0e1);
        Wheel {
            seed,
            next: 0,
            pose: [0.0; 3],
            // A wheel's radius known to 1 %.
            scale: 1.0 + 0.01 * crate::noise::normal(seed, u64::MAX),
        }
    }

    fn next_time(&self) -> f64 {
        self.next as f64 / WHEEL_HZ
    }

    fn step(&mut self, trajectory: &crate::trajectory::Trajectory) -> (f64, Pose, V3, V3) {
        let t = self.next_time();
        let k = self.next;
        self.next += 1;
        let s = trajectory.state(t);
        let v = mul_t(&s.pose.rotation, s.velocity);
        let speed = self.scale * v[0] + 0.02 * crate::noise::normal(self.seed, 2 * k);
        let yaw_rate = s.angular_velocity[2] + 0.01 * crate::noise::normal(self.seed, 2 * k + 1);
        if k > 0 {
            let dt = 1.0 / WHEEL_HZ;
            self.pose[2] += yaw_rate * dt;
            self.pose[0] += speed * self.pose[2].cos() * dt;
            self.pose[1] += speed * self.pose[2].sin() * dt;
        }
        let pose = Pose::from_euler([self.pose[0], self.pose[1], 0.0], [self.pose[2], 0.0, 0.0]);
        (t, pose, [speed, 0.0, 0.0], [0.0, 0.0, yaw_rate])
    }
}

/// Writes every IMU sample of `imu` stamped up to `until` (seconds) to the outputs asked for
/// (the EuRoC folder of `frames`, with its ground truth, through the IMU's `mount`); samples
/// before the sequence's start `from` (the stream's warm-up, stamped below 0, and a window's
/// route before it) are dropped. `window` is `[from, until]`.
fn log_imu(
    imu: &mut ImuStream,
    window: [f64; 2],
    bag: &mut Option<Bag>,
    kitti: &mut Option<Kitti>,
    frames: &mut Option<Frames<'_>>,
    variances: [f64; 2],
    mount: &Pose,
) -> std::io::Result<()> {
    let [from, until] = window;
    while imu.peek_time() <= until {
        let s = imu.sample();
        if s.stamp < from {
            continue;
        }
        if let Some(b) = bag {
            b.imu(s.stamp, s.gyroscope, s.accelerometer, variances)?;
        }
        if let Some(kt) = kitti {
            kt.imu(s.stamp, s.gyroscope, s.accelerometer)?;
        }
        if let Some(f) = frames {
            f.imu(&s, mount)?;
        }
    }
    Ok(())
}
