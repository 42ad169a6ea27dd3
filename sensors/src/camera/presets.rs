//! The built-in cameras, named after the real ones they copy, with the numbers of their
//! datasheets; what a datasheet does not give (a chip's full well and read noise, a lens's
//! distortion) is typical of that chip or lens, and said so in the model's `source`.
//!
//! - `stereo`: a pair of FLIR Blackfly S BFS-U3-04S2C (Sony IMX287, colour, global shutter,
//!   720 x 540 pixels of 6.9 um) read as a 640 x 480 region, behind 3.5 mm f/2 lenses, 12 cm
//!   apart, 10 frames a second: the machine-vision cameras SubT teams carried (CERBERUS's
//!   robots carried Blackfly S cameras), at the LiDAR's rate.
//! - `mono`: the left camera of `stereo`.
//! - `fisheye-stereo`: an Intel RealSense T265's pair (OmniVision OV9282, monochrome, global
//!   shutter, 848 x 800 pixels of 3 um, 163 degrees, 6.4 cm apart, 30 frames a second), its
//!   lenses in the Kannala-Brandt model Intel calibrates them with.
//! - `d435i`: an Intel RealSense D435i's colour camera (OmniVision OV2740, 1.4 um pixels) in
//!   its 640 x 480 mode, 30 frames a second, with depth aligned to it (the D435i's
//!   `aligned_depth_to_color`), 0.3 to 10 m; its colour camera has a rolling shutter
//!   (`--rolling-shutter` renders it), global by default as the other presets.

use super::lens::{Distortion, Intrinsics};
use super::{Camera, CameraModel, Sensor, Shutter};

fn pinhole(width: u32, height: u32, f: f64, k: [f64; 4]) -> Intrinsics {
    Intrinsics {
        width,
        height,
        focal: [f, f],
        centre: [0.5 * f64::from(width) - 0.5, 0.5 * f64::from(height) - 0.5],
        distortion: Distortion::RadTan { coefficients: k },
        circle_deg: None,
    }
}

fn camera(name: &str, intrinsics: Intrinsics, offset_m: [f64; 3]) -> Camera {
    Camera {
        name: name.to_owned(),
        intrinsics,
        offset_m,
    }
}

/// The Blackfly S BFS-U3-04S2C behind a 3.5 mm f/2 lens, as `stereo` and `mono` use it.
fn blackfly() -> (Intrinsics, Sensor) {
    // 3.5 mm over 6.9 um pixels: 507 pixels; about 64 by 51 degrees over 640 x 480.
    let lens = pinhole(640, 480, 3.5e-3 / 6.9e-6, [-0.12, 0.03, 0.0, 0.0]);
    let sensor = Sensor {
        chip: "Sony IMX287 (colour)".into(),
        pixel_um: 6.9,
        full_well_e: 22_000.0,
        read_noise_e: 7.0,
        quantum_efficiency: 0.55,
        colour: true,
        f_number: 2.0,
        exposure_s: [2e-5, 0.02],
        max_gain_db: 24.0,
    };
    (lens, sensor)
}

/// `stereo`: two Blackfly S, 12 cm apart.
pub fn stereo() -> CameraModel {
    let (lens, sensor) = blackfly();
    CameraModel {
        name: "stereo".into(),
        cameras: vec![
            camera("cam0", lens, [0.0; 3]),
            camera("cam1", lens, [0.12, 0.0, 0.0]),
        ],
        rate_hz: 10.0,
        shutter: Shutter::Global,
        readout_s: 0.0,
        sensor,
        depth_range_m: None,
        source: "FLIR Blackfly S BFS-U3-04S2C datasheet: Sony IMX287 colour, global shutter, 720 x 540 of 6.9 um (read as a 640 x 480 region); a 3.5 mm f/2 lens (507 px, about 64 x 51 deg) with a typical mild barrel distortion; full well and read noise typical of the IMX287 (about 22 ke-, 7 e-); exposure capped at 20 ms and gain at 24 dB by the auto-exposure; 12 cm baseline; 10 Hz, the LiDAR's rate".into(),
    }
}

/// `mono`: the left camera of [`stereo`].
pub fn mono() -> CameraModel {
    let mut m = stereo();
    m.name = "mono".into();
    m.cameras.truncate(1);
    m.source = format!("the left camera of stereo: {}", m.source);
    m
}

/// `fisheye-stereo`: an Intel RealSense T265's fisheye pair.
pub fn fisheye_stereo() -> CameraModel {
    let lens = Intrinsics {
        width: 848,
        height: 800,
        focal: [286.0, 286.0],
        centre: [423.5, 399.5],
        distortion: Distortion::Equidistant {
            coefficients: [-0.0087, 0.0405, -0.0383, 0.0068],
        },
        circle_deg: Some(163.0),
    };
    CameraModel {
        name: "fisheye-stereo".into(),
        cameras: vec![
            camera("cam0", lens, [0.0; 3]),
            camera("cam1", lens, [0.064, 0.0, 0.0]),
        ],
        rate_hz: 30.0,
        shutter: Shutter::Global,
        readout_s: 0.0,
        sensor: Sensor {
            chip: "OmniVision OV9282 (monochrome)".into(),
            pixel_um: 3.0,
            full_well_e: 8_000.0,
            read_noise_e: 4.0,
            quantum_efficiency: 0.6,
            colour: false,
            f_number: 2.0,
            exposure_s: [2e-5, 0.015],
            max_gain_db: 24.0,
        },
        depth_range_m: None,
        source: "Intel RealSense T265 datasheet: two OmniVision OV9282, monochrome, global shutter, 848 x 800, 163 +- 5 deg field of view, 64 mm baseline, 30 fps; the lenses as a T265's factory calibration gives them (Kannala-Brandt, fx = fy = 286); full well and read noise typical of a 3 um pixel; exposure capped at 15 ms".into(),
    }
}

/// `d435i`: an Intel RealSense D435i's colour camera with depth aligned to it.
pub fn d435i() -> CameraModel {
    CameraModel {
        name: "d435i".into(),
        // 615 px over 640 x 480: 55 by 43 degrees, the 4:3 crop of the 69 x 42 degree field
        // the datasheet gives for 16:9.
        cameras: vec![camera("cam0", pinhole(640, 480, 615.0, [0.0; 4]), [0.0; 3])],
        rate_hz: 30.0,
        shutter: Shutter::Global,
        readout_s: 0.02,
        sensor: Sensor {
            chip: "OmniVision OV2740 (colour)".into(),
            pixel_um: 1.4,
            full_well_e: 4_500.0,
            read_noise_e: 2.5,
            quantum_efficiency: 0.5,
            colour: true,
            f_number: 2.0,
            exposure_s: [1e-4, 1.0 / 30.0],
            max_gain_db: 18.0,
        },
        depth_range_m: Some([0.3, 10.0]),
        source: "Intel RealSense D435i datasheet: RGB OmniVision OV2740, 1.4 um pixels, 69 x 42 deg (16:9), rolling shutter (20 ms readout here); the 640 x 480 mode at 30 fps (fx = fy = 615, no distortion, as the D435i reports its colour intrinsics); depth aligned to colour, 0.3 to 10 m; full well and read noise typical of a 1.4 um pixel".into(),
    }
}

#[cfg(test)]
mod tests {
    use super::super::NAMES;
    use super::*;

    #[test]
    fn every_preset_checks_and_its_fields_of_view_are_the_datasheets() {
        for name in NAMES {
            let m = CameraModel::named(name, |_| None).unwrap();
            assert_eq!(m.name, name);
        }
        let fov = d435i().cameras[0].intrinsics.field_of_view_deg();
        assert!((fov[1] - 42.6).abs() < 0.5, "{fov:?}");
        let t265 = fisheye_stereo().cameras[0].intrinsics;
        // The image circle (163 degrees, 384 pixels across its radius) leaves the corners dark.
        assert!(t265.in_circle(423.5, 20.0) && !t265.in_circle(0.0, 0.0));
        let s = stereo().cameras[0].intrinsics.field_of_view_deg();
        assert!(s[0] > 60.0 && s[0] < 75.0, "{s:?}");
    }
}
