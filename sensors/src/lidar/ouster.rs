//! Ouster OS1-32, OS1-64 and OS1-128: beams evenly spread over a 45 degree vertical field of
//! view (the "uniform" beam configuration), 1,024 columns at 10 Hz, every beam of a column fired
//! together.
//!
//! Numbers from Ouster's OS1 datasheet: 45 degrees vertical field of view (+22.5 to -22.5),
//! range 0.8 to 120 m on an 80 % reflective target, range repeatability 1.5 cm one standard
//! deviation at high signal, 1,024 x 10 Hz mode. Channel 0 is the highest beam, as the driver
//! numbers them (`ring`).

use super::{Driver, LidarModel, Pattern};

/// An OS1 with `beams` beams.
pub fn os1(beams: usize) -> LidarModel {
    let elevations_deg = (0..beams)
        .map(|b| 22.5 - 45.0 * b as f64 / (beams - 1) as f64)
        .collect();
    LidarModel {
        name: format!("os1-{beams}"),
        driver: Driver::Ouster,
        pattern: Pattern::Spinning {
            elevations_deg,
            azimuth_offsets_deg: vec![0.0; beams],
            columns: 1024,
        },
        rate_hz: 10.0,
        range_m: [0.8, 120.0],
        range_noise_m: 0.015,
        grazing_deg: 85.0,
        source: "Ouster OS1 datasheet: 45 deg vertical field of view, 0.8 to 120 m, 1.5 cm (1 sigma) repeatability, 1024 x 10 Hz".into(),
    }
}
