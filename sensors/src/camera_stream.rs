//! The cameras' frames in a sequence: rendered at the camera's rate along the route, each
//! written as soon as the sequence's clock passes it, the next rendered while this one is
//! encoded and written, so the two cores share both.
//!
//! Files of a frame stamped `t` (nanoseconds `ns`), camera `camN`:
//!
//! | file | contents |
//! |---|---|
//! | `camera/camN/rgb/<ns>.png` | 8-bit RGB (grey for a monochrome chip) |
//! | `camera/camN/depth/<ns>.tiff` | float32 metres along the optical axis, 0 where nothing is seen |
//! | `camera/camN/labels/<ns>.png` | 16-bit semantic class ids (`sequence.json`'s `camera.legend`) |
//! | `camera/camN/instances/<ns>.tiff` | 32-bit instance ids (`camera.instances`) |
//! | `camera/camN/ground_truth.tum` | the camera's optical frame in the world at each stamp (a rolling shutter's first row) |
//! | `camera/camchain.yaml`, `camera/imu.yaml` | Kalibr's calibration files, the true values |
//!
//! and the same images in the bag, the EuRoC folder and the TUM RGB-D folder when asked for.
//! Memory stays two frames' buffers whatever the length; each frame's difficulty label goes
//! to a file beside (`camera/.frames.jsonl`) that `sequence.json` takes in at the end.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use rayon::prelude::*;
use serde::Serialize;

use crate::camera::CameraModel;
use crate::camera::difficulty::{self, Difficulty};
use crate::camera::light::Rig;
use crate::camera::render::{Renderer, Shot};
use crate::camera::scene::CameraScene;
use crate::camera::sensor::{AutoExposure, Exposure, expose};
use crate::frames::Pose;
use crate::imu::ImuModel;
use crate::route::{Phase, Route};
use crate::write::bag::{Bag, ns};
use crate::write::euroc::{self, Euroc};
use crate::write::image;
use crate::write::tum_rgbd::TumRgbd;
use crate::write::{camera_msgs, kitti::Tum};

/// What to make of the cameras.
#[derive(Clone, Debug, PartialEq)]
pub struct CameraOptions {
    /// The camera model.
    pub model: CameraModel,
    /// Average five instants over each exposure.
    pub motion_blur: bool,
    /// Each lamp's lumens instead of the platform's (0: lamps off).
    pub lamp_lumens: Option<f64>,
    /// Light from everywhere, lux.
    pub ambient_lux: f64,
    /// No shot or read noise.
    pub noiseless: bool,
}

/// Which camera outputs besides the camera folder.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Outputs {
    /// Images and calibrations in the bag.
    pub bag: bool,
    /// `euroc/`.
    pub euroc: bool,
    /// `tum/` (an RGB-D camera).
    pub tum: bool,
}

/// A frame's label in `sequence.json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FrameLabel {
    /// Its index.
    pub frame: u64,
    /// Its stamp, seconds.
    pub time: f64,
    /// The graph edge it was taken on.
    pub edge: Option<usize>,
    /// The graph node it was taken at.
    pub node: Option<usize>,
    /// What the platform was doing.
    pub phase: Phase,
    /// The exposure time, seconds.
    pub exposure_s: f64,
    /// The gain, decibels.
    pub gain_db: f64,
    /// Each camera's difficulty.
    pub cameras: Vec<Difficulty>,
}

/// One camera's frame, encoded.
struct Encoded {
    image: Vec<u8>,
    rgb: Vec<u8>,
    depth: Vec<u8>,
    labels: Vec<u8>,
    instances: Vec<u8>,
    difficulty: Difficulty,
}

/// What encoding a frame needs, apart from the buffers.
struct Context<'a> {
    renderer: Renderer<'a>,
    options: &'a CameraOptions,
    seed: u64,
}

/// The frames of a sequence, being written.
pub struct Frames<'a> {
    ctx: Context<'a>,
    options: &'a CameraOptions,
    route: &'a Route,
    outputs: Outputs,
    /// Frames in all.
    pub count: u64,
    next: u64,
    ae: AutoExposure,
    exposure: Exposure,
    current: Vec<Shot>,
    spare: Vec<Shot>,
    rendered: bool,
    dir: PathBuf,
    euroc: Option<Euroc>,
    tum: Option<TumRgbd>,
    truth: Vec<Tum>,
    labels: BufWriter<File>,
    imu_offset_s: f64,
    /// Bytes written so far.
    pub bytes: u64,
}

/// Where the frame labels wait for `sequence.json`, in the sequence folder.
pub const LABELS_FILE: &str = "camera/.frames.jsonl";

impl<'a> Frames<'a> {
    /// Starts the camera folder (and the EuRoC and TUM folders `outputs` asks for) in `dir`:
    /// `count` frames of `options`' model on `rig`, through `scene` along `route`; `imu` and
    /// `imu_mount` for the calibration files, `seed` for the noise.
    #[allow(clippy::too_many_arguments)]
    pub fn create(
        dir: &Path,
        scene: &'a CameraScene,
        route: &'a Route,
        rig: &'a Rig,
        options: &'a CameraOptions,
        outputs: Outputs,
        count: u64,
        imu: (&ImuModel, &Pose),
        seed: u64,
    ) -> std::io::Result<Frames<'a>> {
        let model = &options.model;
        let root = dir.join("camera");
        std::fs::create_dir_all(&root)?;
        for c in &model.cameras {
            for sub in ["rgb", "depth", "labels", "instances"] {
                std::fs::create_dir_all(root.join(&c.name).join(sub))?;
            }
        }
        std::fs::write(
            root.join("camchain.yaml"),
            euroc::camchain(model, &rig.cameras, imu.1, imu.0.time_offset_s),
        )?;
        std::fs::write(root.join("imu.yaml"), euroc::imu_yaml(imu.0))?;
        let truth = model
            .cameras
            .iter()
            .map(|c| Tum::create(&root.join(&c.name).join("ground_truth.tum")))
            .collect::<std::io::Result<Vec<_>>>()?;
        let euroc = if outputs.euroc {
            Some(Euroc::create(
                &dir.join("euroc"),
                model,
                &rig.cameras,
                imu.1,
                imu.0,
            )?)
        } else {
            None
        };
        let tum = if outputs.tum {
            Some(TumRgbd::create(&dir.join("tum"))?)
        } else {
            None
        };
        let labels = BufWriter::new(File::create(dir.join(LABELS_FILE))?);
        let renderer = Renderer::new(scene, &route.trajectory, rig, model, options.motion_blur);
        let ae = AutoExposure::new(model);
        let longest = model.sensor.exposure_s[1];
        Ok(Frames {
            ctx: Context {
                renderer,
                options,
                seed: crate::noise::hash(seed, 0xca3e7a),
            },
            options,
            route,
            outputs,
            count,
            next: 0,
            ae,
            exposure: Exposure {
                time_s: longest,
                gain: 1.0,
            },
            current: vec![Shot::default(); model.cameras.len()],
            spare: vec![Shot::default(); model.cameras.len()],
            rendered: false,
            dir: dir.to_owned(),
            euroc,
            tum,
            truth,
            labels,
            imu_offset_s: imu.0.time_offset_s,
            bytes: 0,
        })
    }

    /// These frames seen through the dust, fog or mist of `air` (see
    /// [`crate::camera::haze`]; none: clear air).
    pub fn with_air(mut self, air: Option<&'a crate::conditions::Active<'a>>) -> Frames<'a> {
        self.ctx.renderer.air = air;
        self
    }

    /// Frame `j`'s stamp, seconds (a whole number of nanoseconds).
    pub fn stamp(&self, j: u64) -> f64 {
        stamp(&self.options.model, j)
    }

    /// The bag topics the cameras publish on (name, type).
    pub fn topics(model: &CameraModel) -> Vec<(String, &'static str)> {
        let mut t = Vec::new();
        for c in &model.cameras {
            t.push((format!("/{}/image_raw", c.name), "sensor_msgs/msg/Image"));
            t.push((
                format!("/{}/camera_info", c.name),
                "sensor_msgs/msg/CameraInfo",
            ));
        }
        if model.depth_range_m.is_some() {
            t.push((
                format!("/{}/depth/image_raw", model.cameras[0].name),
                "sensor_msgs/msg/Image",
            ));
        }
        t
    }

    /// The static transforms from `base_link` to each camera's optical frame.
    pub fn transforms(model: &CameraModel, rig: &Rig) -> Vec<(String, Pose)> {
        model
            .cameras
            .iter()
            .zip(&rig.cameras)
            .map(|(c, p)| (format!("{}_optical_frame", c.name), *p))
            .collect()
    }

    /// Renders, encodes and writes every frame stamped before `until` seconds.
    pub fn write_until(&mut self, until: f64, bag: &mut Option<Bag>) -> std::io::Result<()> {
        while self.next < self.count && self.stamp(self.next) < until {
            let j = self.next;
            if !self.rendered {
                self.render_into(j, true);
                self.exposure = self.ae.meter(&self.current[0].signal);
                self.rendered = true;
            }
            let this = self.exposure;
            // The next frame's exposure, from this one's metering, one frame behind as a
            // camera's loop is.
            let next = self.ae.meter(&self.current[0].signal);
            let more = j + 1 < self.count;
            let stamp_next = self.stamp(j + 1);
            let (ctx, spare, current) = (&self.ctx, &mut self.spare, &self.current);
            let ((), encoded) = rayon::join(
                || {
                    if more {
                        for (c, shot) in spare.iter_mut().enumerate() {
                            ctx.renderer.render(c, stamp_next, next.time_s, shot);
                        }
                    }
                },
                || ctx.encode(j, this, current),
            );
            self.write(j, this, encoded, bag)?;
            std::mem::swap(&mut self.current, &mut self.spare);
            self.exposure = next;
            self.next += 1;
        }
        Ok(())
    }

    /// Renders frame `j` into the current buffers (the first frame, before any metering).
    fn render_into(&mut self, j: u64, _first: bool) {
        let stamp = self.stamp(j);
        let t = self.exposure.time_s;
        for (c, shot) in self.current.iter_mut().enumerate() {
            self.ctx.renderer.render(c, stamp, t, shot);
        }
    }

    /// Writes frame `j`'s files, messages and label.
    fn write(
        &mut self,
        j: u64,
        exposure: Exposure,
        encoded: Vec<Encoded>,
        bag: &mut Option<Bag>,
    ) -> std::io::Result<()> {
        let model = &self.options.model;
        let stamp = self.stamp(j);
        let stamp_ns = ns(stamp);
        let root = self.dir.join("camera");
        for (c, (cam, e)) in model.cameras.iter().zip(&encoded).enumerate() {
            let base = root.join(&cam.name);
            let rgb = base.join(format!("rgb/{stamp_ns}.png"));
            for (path, bytes) in [
                (&rgb, &e.rgb),
                (&base.join(format!("depth/{stamp_ns}.tiff")), &e.depth),
                (&base.join(format!("labels/{stamp_ns}.png")), &e.labels),
                (
                    &base.join(format!("instances/{stamp_ns}.tiff")),
                    &e.instances,
                ),
            ] {
                std::fs::write(path, bytes)?;
                self.bytes += bytes.len() as u64;
            }
            let pose = self.ctx.renderer.camera_pose(c, stamp);
            self.truth[c].pose(stamp, &pose)?;
            if let Some(eu) = &mut self.euroc {
                self.bytes += eu.image(c, &cam.name, stamp_ns, &rgb)?;
            }
            if c == 0
                && let (Some(tum), Some(range)) = (&mut self.tum, model.depth_range_m)
            {
                let l = &cam.intrinsics;
                self.bytes += tum.frame(
                    stamp,
                    &rgb,
                    &self.current[0].depth,
                    l.width as usize,
                    range,
                    &pose,
                )?;
            }
            if let Some(b) = bag.as_mut().filter(|_| self.outputs.bag) {
                let l = &cam.intrinsics;
                let frame = format!("{}_optical_frame", cam.name);
                let channels = if model.sensor.colour { 3 } else { 1 };
                let encoding = if channels == 3 { "rgb8" } else { "mono8" };
                b.publish(&format!("/{}/image_raw", cam.name), stamp_ns, |buf| {
                    camera_msgs::image(
                        buf,
                        stamp_ns,
                        &frame,
                        l.width,
                        l.height,
                        encoding,
                        l.width * channels as u32,
                        |b| b.extend_from_slice(&e.image),
                    )
                })?;
                let tx = -l.focal[0] * (cam.offset_m[0] - model.cameras[0].offset_m[0]);
                b.publish(&format!("/{}/camera_info", cam.name), stamp_ns, |buf| {
                    camera_msgs::camera_info(buf, stamp_ns, &frame, cam, tx)
                })?;
                if c == 0
                    && let Some(range) = model.depth_range_m
                {
                    let depth = &self.current[0].depth;
                    b.publish(&format!("/{}/depth/image_raw", cam.name), stamp_ns, |buf| {
                        camera_msgs::image(
                            buf,
                            stamp_ns,
                            &frame,
                            l.width,
                            l.height,
                            "16UC1",
                            l.width * 2,
                            |b| {
                                for &d in depth {
                                    let d = f64::from(d);
                                    let mm = if d >= range[0] && d <= range[1] {
                                        (d * 1000.0).round().min(65535.0) as u16
                                    } else {
                                        0
                                    };
                                    b.extend_from_slice(&mm.to_le_bytes());
                                }
                            },
                        )
                    })?;
                }
            }
        }
        let mark = self.route.mark(stamp);
        let label = FrameLabel {
            frame: j,
            time: stamp,
            edge: mark.leg.map(|l| self.route.legs[l as usize].edge),
            node: mark.node.map(|n| n as usize),
            phase: mark.phase,
            exposure_s: round(exposure.time_s, 1e7),
            gain_db: round(exposure.gain_db(), 1e3),
            cameras: encoded.into_iter().map(|e| e.difficulty).collect(),
        };
        let line = serde_json::to_string(&label).expect("plain data");
        writeln!(self.labels, "{line}")?;
        Ok(())
    }

    /// Finishes the files; returns the bytes written and the labels' file.
    pub fn finish(self) -> std::io::Result<(u64, PathBuf)> {
        let mut bytes = self.bytes;
        for t in self.truth {
            bytes += t.finish()?;
        }
        if let Some(e) = self.euroc {
            bytes += e.finish()?;
        }
        if let Some(t) = self.tum {
            bytes += t.finish()?;
        }
        let mut labels = self.labels;
        labels.flush()?;
        Ok((bytes, self.dir.join(LABELS_FILE)))
    }

    /// The sequence's IMU sample for the EuRoC folder's IMU and ground truth (`mount`: the
    /// IMU in `base_link`).
    pub fn imu(&mut self, s: &crate::imu::ImuSample, mount: &Pose) -> std::io::Result<()> {
        if let Some(e) = &mut self.euroc {
            let t = s.stamp - self.imu_offset_s;
            let state = self.route.trajectory.state(t);
            e.imu(s, &state, mount, ns(t))?;
        }
        Ok(())
    }
}

impl Context<'_> {
    /// Frame `j`'s stamp, seconds.
    fn stamp(&self, j: u64) -> f64 {
        stamp(&self.options.model, j)
    }

    /// Every camera's frame `j` exposed, measured and encoded (in parallel).
    fn encode(&self, j: u64, exposure: Exposure, shots: &[Shot]) -> Vec<Encoded> {
        let model = &self.options.model;
        let channels = if model.sensor.colour { 3 } else { 1 };
        shots
            .par_iter()
            .enumerate()
            .map(|(c, shot)| {
                let l = &model.cameras[c].intrinsics;
                let (w, h) = (l.width as usize, l.height as usize);
                let mut img = Vec::new();
                let key = crate::noise::hash(self.seed, (j << 3) | c as u64);
                expose(
                    model,
                    &shot.signal,
                    exposure,
                    key,
                    self.options.noiseless,
                    &mut img,
                );
                let ((rgb, (depth, (labels, instances))), difficulty) = rayon::join(
                    || {
                        rayon::join(
                            || image::png8(w, h, channels, &img),
                            || {
                                rayon::join(
                                    || image::tiff_f32(w, h, &shot.depth),
                                    || {
                                        (
                                            image::png16(w, h, &shot.class),
                                            image::tiff_i32(w, h, &shot.instance),
                                        )
                                    },
                                )
                            },
                        )
                    },
                    || self.difficulty(c, j, exposure, shot, &img, channels),
                );
                Encoded {
                    image: img,
                    rgb,
                    depth,
                    labels,
                    instances,
                    difficulty,
                }
            })
            .collect()
    }

    /// One camera's difficulty in frame `j`.
    fn difficulty(
        &self,
        c: usize,
        j: u64,
        exposure: Exposure,
        shot: &Shot,
        img: &[u8],
        channels: usize,
    ) -> Difficulty {
        let model = &self.options.model;
        let l = &model.cameras[c].intrinsics;
        let (w, h) = (l.width as usize, l.height as usize);
        let mut grey = Vec::new();
        difficulty::to_grey(img, channels, &mut grey);
        Difficulty {
            lit_share: round(
                difficulty::lit_share(shot, exposure.time_s, model.sensor.read_noise_e),
                1e4,
            ),
            mean_brightness: round(difficulty::mean_brightness(&grey, shot), 1e3),
            keypoints: difficulty::fast9(&grey, w, h, 20),
            motion_blur_px: round(self.blur(c, j, exposure.time_s, shot), 1e3),
        }
    }

    /// How far the points a grid of camera `c`'s pixels sees move across its image during
    /// frame `j`'s exposure, mean pixels.
    fn blur(&self, c: usize, j: u64, exposure_s: f64, shot: &Shot) -> f64 {
        let r = &self.renderer;
        let px = &r.pixels[c];
        let lens = &self.options.model.cameras[c].intrinsics;
        let stamp = self.stamp(j);
        let (mut sum, mut n) = (0.0, 0u32);
        for gy in 0..12 {
            let y = (gy * 2 + 1) * px.height / 24;
            let t = r.row_time(c, stamp, y);
            let mid = r.camera_pose(c, t);
            let ends = [
                r.camera_pose(c, t - 0.5 * exposure_s).inverse(),
                r.camera_pose(c, t + 0.5 * exposure_s).inverse(),
            ];
            for gx in 0..16 {
                let x = (gx * 2 + 1) * px.width / 32;
                let k = y * px.width + x;
                let d = f64::from(shot.depth[k]);
                let ray = px.rays[k].map(f64::from);
                if d <= 0.0 || ray[2] <= 0.0 {
                    continue;
                }
                let p = mid.apply(ray.map(|v| v * d / ray[2]));
                let seen = ends.map(|e| lens.project(e.apply(p)));
                if let [Some(a), Some(b)] = seen {
                    sum += (a[0] - b[0]).hypot(a[1] - b[1]);
                    n += 1;
                }
            }
        }
        if n == 0 { 0.0 } else { sum / f64::from(n) }
    }
}

/// `sequence.json`'s `camera`: the model, where each camera and lamp is, the exposure and
/// light, the files, the legend of the label images and what the instance ids are.
pub fn head(
    options: &CameraOptions,
    rig: &Rig,
    scene: &CameraScene,
    frames: u64,
) -> serde_json::Value {
    let pose = |p: &Pose| {
        serde_json::json!({
            "translation": p.translation,
            "quaternion_xyzw": p.quaternion(),
        })
    };
    let m = &options.model;
    serde_json::json!({
        "model": m,
        "frames": m.cameras.iter().map(|c| format!("{}_optical_frame", c.name)).collect::<Vec<_>>(),
        "base_link_to_camera": rig.cameras.iter().map(pose).collect::<Vec<_>>(),
        "optical_frame": "x right, y down, z forward (REP 103 _optical, OpenCV's)",
        "lamps": &rig.lamps,
        "ambient_lux": rig.ambient_lux,
        "motion_blur": options.motion_blur,
        "noiseless": options.noiseless,
        "frame_count": frames,
        "frame_period_s": m.period(),
        "stamps": "the middle of each exposure (a rolling shutter's first row; row r of h at stamp + r readout / h)",
        "files": {
            "rgb": "camera/<cam>/rgb/<ns>.png: 8-bit RGB (grey for a monochrome chip)",
            "depth": "camera/<cam>/depth/<ns>.tiff: float32 metres along the optical axis, 0 where nothing is seen",
            "labels": "camera/<cam>/labels/<ns>.png: 16-bit class ids (legend)",
            "instances": "camera/<cam>/instances/<ns>.tiff: int32 instance ids (instances)",
            "ground_truth": "camera/<cam>/ground_truth.tum: the camera's optical frame at each stamp",
            "calibration": "camera/camchain.yaml, camera/imu.yaml (Kalibr)",
        },
        "legend": &scene.legend,
        "instances": &scene.instances,
        "surface_triangles": scene.mesh.triangles.len(),
    })
}

/// The bytes a frame of every camera takes at most, with the outputs `formats` asks for: the
/// files uncompressed (an RGB image's noise leaves PNG little to save; depth, classes and
/// instances compress two to fifty times, so this is an upper bound).
pub fn frame_bytes(model: &CameraModel, formats: crate::write::Formats) -> u64 {
    let channels = if model.sensor.colour { 3 } else { 1 };
    let mut bytes = 400; // the label in sequence.json
    for c in &model.cameras {
        let px = u64::from(c.intrinsics.width) * u64::from(c.intrinsics.height);
        // RGB, depth, classes, instances; the files' heads and the TUM line.
        bytes += px * (channels + 4 + 2 + 4) + 4 * 1024 + 100;
        if formats.bag {
            bytes += px * channels + 1024;
        }
        if formats.euroc {
            bytes += 64;
        }
    }
    if let Some(c) = model
        .cameras
        .first()
        .filter(|_| model.depth_range_m.is_some())
    {
        let px = u64::from(c.intrinsics.width) * u64::from(c.intrinsics.height);
        if formats.tum {
            bytes += 2 * px + 300;
        }
        if formats.bag {
            bytes += 2 * px + 300;
        }
    }
    bytes
}

/// Frame `j`'s stamp of `model`, seconds: `j / rate` to the nanosecond.
pub fn stamp(model: &CameraModel, j: u64) -> f64 {
    (j as f64 * 1e9 / model.rate_hz).round() / 1e9
}

/// `x` rounded to `1 / scale`.
fn round(x: f64, scale: f64) -> f64 {
    (x * scale).round() / scale
}
