//! Cameras: lamp-lit images of a world with exact depth, semantic labels and instance ids,
//! rendered along the same route, clocks and frames as the LiDAR.
//!
//! A camera model ([`CameraModel`]) is a rig of one to four cameras sharing a clock and an
//! exposure: `mono`, `stereo`, `fisheye-stereo` and `d435i` ([`presets`]), or a camera table
//! (a TOML file, [`table`]). Each camera has a lens ([`lens`]: pinhole with radial-tangential
//! distortion, or equidistant fisheye), a position on the rig, and the rig a sensor chip
//! ([`Sensor`]: pixel size, full well, read noise) behind which auto-exposure, shot and read
//! noise and vignetting turn light into 8-bit values ([`sensor`]).
//!
//! What the camera sees ([`scene`]) is the world's visual surface (`mesh/world.obj`), its
//! services (`mesh/services.obj`) and its artifacts, each triangle knowing its material, its
//! texture coordinates, its semantic class and its instance; rays are cast into one
//! hierarchy over all of it (the core's [`subtgraph_core::raycast`]). Underground there is no
//! light but the robot's: the platform's lamps ([`light`]) light each point with an
//! inverse-square falloff within their cones, shadowed by what stands between ([`render`]
//! casts the shadow rays from beside the lens), and the surface answers by its albedo,
//! normal and roughness maps ([`shade`], [`texture`]).
//!
//! Per frame and camera: RGB (or grey, for a monochrome chip), depth in metres along the
//! optical axis (float32), a semantic class and an instance id per pixel, and the frame's
//! difficulty ([`difficulty`]: the share of lit pixels, the mean brightness, the FAST corners
//! found, the motion blur). [`crate::camera_stream`] fits the frames into a sequence's timeline.

pub mod difficulty;
pub mod haze;
pub mod lens;
pub mod light;
pub mod presets;
pub mod raster;
pub mod render;
pub mod scene;
pub mod sensor;
pub mod shade;
pub mod still;
pub mod table;
pub mod texture;

use serde::Serialize;

use crate::error::SenseError;
use lens::Intrinsics;

/// One camera of a rig.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Camera {
    /// Its name in files and topics (`cam0`, `cam1`).
    pub name: String,
    /// Its image and lens.
    pub intrinsics: Intrinsics,
    /// Where its optical centre is in the first camera's optical frame (x right, y down, z
    /// forward), metres: a stereo pair's right camera is at `[baseline, 0, 0]`. The cameras
    /// of a rig look the same way.
    pub offset_m: [f64; 3],
}

/// How the rows of an image are exposed.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Shutter {
    /// Every row at once.
    Global,
    /// Row by row, top to bottom, the last row `readout_s` after the first.
    Rolling {
        /// Seconds from the first row's exposure to the last's.
        readout_s: f64,
    },
}

/// The image sensor behind the lenses: what turns light into numbers.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Sensor {
    /// The chip (`Sony IMX287`).
    pub chip: String,
    /// Pixel pitch, micrometres.
    pub pixel_um: f64,
    /// Electrons a pixel holds before it saturates.
    pub full_well_e: f64,
    /// Read noise, electrons (one standard deviation).
    pub read_noise_e: f64,
    /// Share of photons that become electrons.
    pub quantum_efficiency: f64,
    /// Colour (a Bayer chip: RGB images) or monochrome (grey images).
    pub colour: bool,
    /// The lens's f-number.
    pub f_number: f64,
    /// Shortest and longest exposure auto-exposure may choose, seconds.
    pub exposure_s: [f64; 2],
    /// Most analogue gain auto-exposure may add, decibels.
    pub max_gain_db: f64,
}

/// A camera rig: its cameras, their clock, their sensor.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CameraModel {
    /// Its name (`stereo`, or a table's `name`).
    pub name: String,
    /// The cameras; the first is the rig's reference.
    pub cameras: Vec<Camera>,
    /// Frames a second.
    pub rate_hz: f64,
    /// Global (the default) or rolling.
    pub shutter: Shutter,
    /// A rolling shutter's readout, seconds (used when the shutter is rolling).
    pub readout_s: f64,
    /// The sensor chip, the same behind every camera.
    pub sensor: Sensor,
    /// An RGB-D camera: the first camera also publishes a depth image (in the bag and the
    /// TUM RGB-D folder), zero outside this range of metres. `None` for plain cameras.
    pub depth_range_m: Option<[f64; 2]>,
    /// Where the numbers come from.
    pub source: String,
}

/// The built-in names `--camera` takes.
pub const NAMES: [&str; 4] = ["mono", "stereo", "fisheye-stereo", "d435i"];

impl CameraModel {
    /// A built-in model, or a camera table read from the file `name` names (its text in
    /// `read`).
    pub fn named(
        name: &str,
        read: impl FnOnce(&str) -> Option<String>,
    ) -> Result<CameraModel, SenseError> {
        let model = match name {
            "mono" => presets::mono(),
            "stereo" => presets::stereo(),
            "fisheye-stereo" => presets::fisheye_stereo(),
            "d435i" => presets::d435i(),
            other if other.ends_with(".toml") => {
                let text = read(other).ok_or_else(|| SenseError::BadCameraTable {
                    path: other.to_owned(),
                    why: "cannot be read".into(),
                })?;
                table::parse(&text, other)?
            }
            other => {
                return Err(SenseError::Unknown {
                    what: "camera model",
                    name: other.to_owned(),
                    known: format!("{}, none, or a camera table FILE.toml", NAMES.join(", ")),
                });
            }
        };
        model.check()?;
        Ok(model)
    }

    /// Refuses numbers no real camera has.
    pub fn check(&self) -> Result<(), SenseError> {
        let oob = |what: &str, value: String, bounds: &str| {
            Err(SenseError::OutOfBounds {
                what: format!("{what} of camera '{}'", self.name),
                value,
                bounds: bounds.to_owned(),
            })
        };
        if self.cameras.is_empty() || self.cameras.len() > 4 {
            return oob(
                "cameras",
                self.cameras.len().to_string(),
                "1 to 4 cameras a rig",
            );
        }
        for c in &self.cameras {
            c.intrinsics
                .check()
                .or_else(|p| oob(&format!("{} of {}", p.what, c.name), p.value, &p.bounds))?;
            if c.offset_m.iter().any(|x| !x.is_finite() || x.abs() > 2.0) {
                return oob(
                    &format!("offset_m of {}", c.name),
                    format!("{:?}", c.offset_m),
                    "within 2 metres of the first camera on each axis",
                );
            }
        }
        if !(self.rate_hz >= 0.5 && self.rate_hz <= 240.0) {
            return oob(
                "rate_hz",
                self.rate_hz.to_string(),
                "0.5 to 240 frames a second",
            );
        }
        // The fastest USB3 and GigE machine-vision cameras move about a gigapixel a second.
        let pixels: f64 = self
            .cameras
            .iter()
            .map(|c| f64::from(c.intrinsics.width) * f64::from(c.intrinsics.height))
            .sum();
        if pixels * self.rate_hz > 1e9 {
            return oob(
                "pixels a second (width x height x cameras x rate)",
                format!("{:.0}", pixels * self.rate_hz),
                "at most 1,000 million",
            );
        }
        let s = &self.sensor;
        let [lo, hi] = s.exposure_s;
        if !(lo >= 1e-6 && lo <= hi && hi <= 1.0 / self.rate_hz + 1e-12) {
            return oob(
                "exposure",
                format!("[{lo}, {hi}] s"),
                &format!(
                    "[shortest, longest] from 1 microsecond up to the frame period ({:.4} s at {} Hz)",
                    1.0 / self.rate_hz,
                    self.rate_hz
                ),
            );
        }
        for (what, v, lo, hi) in [
            ("pixel_um", s.pixel_um, 0.5, 50.0),
            ("full_well_e", s.full_well_e, 500.0, 1e6),
            ("read_noise_e", s.read_noise_e, 0.0, 100.0),
            ("quantum_efficiency", s.quantum_efficiency, 0.01, 1.0),
            ("f_number", s.f_number, 0.7, 32.0),
            ("max_gain_db", s.max_gain_db, 0.0, 48.0),
        ] {
            if !(v.is_finite() && v >= lo && v <= hi) {
                return oob(what, v.to_string(), &format!("{lo} to {hi}"));
            }
        }
        if !(self.readout_s >= 0.0 && self.readout_s <= 1.0 / self.rate_hz + 1e-12) {
            return oob(
                "readout_s",
                self.readout_s.to_string(),
                "0 up to the frame period (a rolling shutter reads its rows within a frame)",
            );
        }
        if let Shutter::Rolling { readout_s } = self.shutter
            && !(readout_s > 0.0 && readout_s <= 1.0 / self.rate_hz + 1e-12)
        {
            return oob(
                "readout_s",
                readout_s.to_string(),
                "above 0 and up to the frame period for a rolling shutter",
            );
        }
        if let Some([near, far]) = self.depth_range_m
            && !(near >= 0.0 && near < far && far <= 100.0)
        {
            return oob(
                "depth_range_m",
                format!("[{near}, {far}]"),
                "[nearest, farthest] with 0 <= nearest < farthest <= 100 metres",
            );
        }
        Ok(())
    }

    /// How long between frames, seconds.
    pub fn period(&self) -> f64 {
        1.0 / self.rate_hz
    }

    /// Pixels a frame of every camera holds.
    pub fn pixels_per_frame(&self) -> u64 {
        self.cameras
            .iter()
            .map(|c| u64::from(c.intrinsics.width) * u64::from(c.intrinsics.height))
            .sum()
    }
}

/// What a command line may change on a camera model.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Overrides {
    /// Frames a second.
    pub rate_hz: Option<f64>,
    /// Expose row by row, with the model's readout time.
    pub rolling_shutter: bool,
}

impl Overrides {
    /// Applies these to a model and checks it again.
    pub fn apply(&self, mut m: CameraModel) -> Result<CameraModel, SenseError> {
        if let Some(r) = self.rate_hz {
            m.rate_hz = r;
            // The longest exposure stays within the frame period.
            m.sensor.exposure_s[1] = m.sensor.exposure_s[1].min(1.0 / r.max(1e-9));
            m.sensor.exposure_s[0] = m.sensor.exposure_s[0].min(m.sensor.exposure_s[1]);
            m.readout_s = m.readout_s.min(1.0 / r.max(1e-9));
        }
        if self.rolling_shutter {
            m.shutter = Shutter::Rolling {
                readout_s: m.readout_s,
            };
        }
        m.check()?;
        Ok(m)
    }
}
