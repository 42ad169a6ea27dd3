//! Velodyne VLP-16 (Puck): 16 beams two degrees apart from -15 to +15 degrees, 1,800 columns a
//! turn at 10 Hz (0.2 degree azimuth resolution at 600 rpm).
//!
//! Numbers from Velodyne's VLP-16 datasheet: 30 degrees vertical field of view (+15 to -15),
//! 2 degrees vertical resolution, up to 100 m, range accuracy up to 3 cm (typical; taken here
//! as 1.5 cm one standard deviation). The driver's `ring` numbers the beams from the lowest
//! (ring 0, -15 degrees) up; its `time` is seconds from the scan's start.

use super::{Driver, LidarModel, Pattern};

/// The VLP-16.
pub fn vlp16() -> LidarModel {
    LidarModel {
        name: "vlp-16".into(),
        driver: Driver::Velodyne,
        pattern: Pattern::Spinning {
            elevations_deg: (0..16).map(|r| -15.0 + 2.0 * r as f64).collect(),
            azimuth_offsets_deg: vec![0.0; 16],
            columns: 1800,
        },
        rate_hz: 10.0,
        range_m: [0.5, 100.0],
        range_noise_m: 0.015,
        grazing_deg: 85.0,
        source: "Velodyne VLP-16 datasheet: +/-15 deg in 2 deg steps, up to 100 m, +/-3 cm typical accuracy, 0.2 deg at 10 Hz".into(),
    }
}
