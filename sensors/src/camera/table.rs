//! A camera table: a camera rig described in a TOML file, for a model that is not built in.
//!
//! ```toml
//! name = "my-stereo"                # what sequence.json calls it
//! rate_hz = 20                      # frames a second
//! readout_ms = 15                   # optional: a rolling shutter's readout (--rolling-shutter)
//! depth_range_m = [0.3, 10.0]       # optional: an RGB-D camera (depth aligned to the first)
//!
//! [sensor]
//! chip = "Sony IMX273"              # optional, for sequence.json
//! pixel_um = 3.45
//! full_well_e = 10000
//! read_noise_e = 2.5
//! quantum_efficiency = 0.6
//! colour = true                     # RGB images (false: grey)
//! f_number = 2.0
//! exposure_ms = [0.02, 20.0]        # shortest and longest exposure auto-exposure may choose
//! max_gain_db = 24
//!
//! [[camera]]                        # one to four, the first the rig's reference
//! width = 752
//! height = 480
//! focal = [458.654, 457.296]        # fx, fy, pixels
//! centre = [367.215, 248.375]       # cx, cy, pixels (the top-left pixel's centre is 0, 0)
//! distortion = "radtan"             # or "equidistant" (Kannala-Brandt fisheye)
//! coefficients = [-0.2834, 0.0740, 0.0002, 0.0000]  # k1 k2 p1 p2, or k1 k2 k3 k4
//! field_of_view_deg = 163           # optional, equidistant only: the lens's image circle
//!
//! [[camera]]
//! offset_m = [0.11, 0.0, 0.0]       # in the first camera's frame (x right, y down, z forward)
//! # ... and the same keys as above
//! ```
//!
//! Unknown keys are errors, so a misspelt one is not silently ignored.

use serde::Deserialize;

use super::lens::{Distortion, Intrinsics};
use super::{Camera, CameraModel, Sensor, Shutter};
use crate::error::SenseError;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Table {
    name: String,
    rate_hz: f64,
    #[serde(default)]
    readout_ms: Option<f64>,
    #[serde(default)]
    depth_range_m: Option<[f64; 2]>,
    sensor: SensorTable,
    camera: Vec<CameraTable>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SensorTable {
    #[serde(default)]
    chip: Option<String>,
    pixel_um: f64,
    full_well_e: f64,
    read_noise_e: f64,
    quantum_efficiency: f64,
    colour: bool,
    f_number: f64,
    exposure_ms: [f64; 2],
    max_gain_db: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CameraTable {
    #[serde(default)]
    name: Option<String>,
    width: u32,
    height: u32,
    focal: [f64; 2],
    centre: [f64; 2],
    distortion: String,
    coefficients: [f64; 4],
    #[serde(default)]
    field_of_view_deg: Option<f64>,
    #[serde(default)]
    offset_m: Option<[f64; 3]>,
}

/// Reads a table (`path` names it in errors). Its numbers are checked by
/// [`CameraModel::check`].
pub fn parse(text: &str, path: &str) -> Result<CameraModel, SenseError> {
    let bad = |why: String| SenseError::BadCameraTable {
        path: path.to_owned(),
        why,
    };
    let t: Table = toml::from_str(text).map_err(|e| bad(e.message().to_owned()))?;
    let mut cameras = Vec::new();
    for (i, c) in t.camera.into_iter().enumerate() {
        let distortion = match c.distortion.as_str() {
            "radtan" => Distortion::RadTan {
                coefficients: c.coefficients,
            },
            "equidistant" => Distortion::Equidistant {
                coefficients: c.coefficients,
            },
            other => {
                return Err(bad(format!(
                    "camera {i}: distortion '{other}' is not one of radtan, equidistant"
                )));
            }
        };
        cameras.push(Camera {
            name: c.name.unwrap_or_else(|| format!("cam{i}")),
            intrinsics: Intrinsics {
                width: c.width,
                height: c.height,
                focal: c.focal,
                centre: c.centre,
                distortion,
                circle_deg: c.field_of_view_deg,
            },
            offset_m: c.offset_m.unwrap_or([0.0; 3]),
        });
    }
    let names: std::collections::BTreeSet<&str> = cameras.iter().map(|c| c.name.as_str()).collect();
    if names.len() != cameras.len() {
        return Err(bad("two cameras have the same name; name each once".into()));
    }
    if names
        .iter()
        .any(|n| n.is_empty() || !n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
    {
        return Err(bad(
            "a camera's name must be letters, digits and _ (it names folders and topics)".into(),
        ));
    }
    let s = t.sensor;
    let readout_s = t.readout_ms.map_or(0.0, |r| r * 1e-3);
    Ok(CameraModel {
        name: t.name,
        cameras,
        rate_hz: t.rate_hz,
        shutter: Shutter::Global,
        readout_s,
        sensor: Sensor {
            chip: s.chip.unwrap_or_else(|| "unnamed".into()),
            pixel_um: s.pixel_um,
            full_well_e: s.full_well_e,
            read_noise_e: s.read_noise_e,
            quantum_efficiency: s.quantum_efficiency,
            colour: s.colour,
            f_number: s.f_number,
            exposure_s: s.exposure_ms.map(|x| x * 1e-3),
            max_gain_db: s.max_gain_db,
        },
        depth_range_m: t.depth_range_m,
        source: format!("camera table {path}"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// EuRoC's cam0 (an MT9V034 behind a radial-tangential lens), as Kalibr calibrated it.
    pub(crate) const TABLE: &str = r#"
name = "euroc"
rate_hz = 20
[sensor]
pixel_um = 6.0
full_well_e = 10000
read_noise_e = 3
quantum_efficiency = 0.5
colour = false
f_number = 2.0
exposure_ms = [0.02, 20.0]
max_gain_db = 12
[[camera]]
width = 752
height = 480
focal = [458.654, 457.296]
centre = [367.215, 248.375]
distortion = "radtan"
coefficients = [-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]
[[camera]]
width = 752
height = 480
focal = [457.587, 456.134]
centre = [379.999, 255.238]
distortion = "radtan"
coefficients = [-0.28368365, 0.07451284, -0.00010473, -3.55590700e-05]
offset_m = [0.11, 0.0, 0.0]
"#;

    fn named(text: String) -> Result<CameraModel, SenseError> {
        CameraModel::named("t.toml", |_| Some(text))
    }

    #[test]
    fn a_table_reads_and_its_mistakes_are_named() {
        let m = named(TABLE.into()).unwrap();
        assert_eq!(m.cameras.len(), 2);
        assert_eq!(m.cameras[1].name, "cam1");
        let cases = [
            (TABLE.replace("focal", "focall"), "focall"),
            (TABLE.replace("458.654", "0.0"), "focal length of cam0"),
            (TABLE.replace("-0.28340811", "-3.0"), "fold"),
            (TABLE.replace("rate_hz = 20", "rate_hz = 4000"), "rate_hz"),
            (TABLE.replace("\"radtan\"", "\"mei\""), "'mei'"),
            (TABLE.replace("width = 752", "width = 100000"), "resolution"),
            (
                TABLE.replace("exposure_ms = [0.02, 20.0]", "exposure_ms = [0.02, 90.0]"),
                "frame period",
            ),
            (
                TABLE.replace("colour = false", "colour = false\nshiny = 1"),
                "shiny",
            ),
        ];
        for (text, says) in cases {
            let e = named(text).unwrap_err().to_string();
            assert!(e.contains(says), "{says}: {e}");
        }
        let e = CameraModel::named("zed2", |_| None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("stereo") && e.contains("zed2"), "{e}");
        let e = CameraModel::named("missing.toml", |_| None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing.toml"), "{e}");
    }
}
