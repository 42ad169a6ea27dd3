//! Livox Mid-360: a non-repeating scan pattern over 360 degrees of azimuth and -7 to +52
//! degrees of elevation, 200,000 points a second from four lasers, 10 frames a second.
//!
//! Numbers from Livox's Mid-360 datasheet: field of view 360 x 59 degrees (-7 to 52), point
//! rate 200,000 a second, range 0.1 to 40 m at 10 % reflectivity (70 m at 80 %), range
//! precision 2 cm (one standard deviation at 10 m). The pattern itself is Livox's own and not
//! published: here each laser sweeps the elevation range up and down 700 times a second while
//! the head turns once a frame, with a phase that moves by the golden ratio every frame, so
//! frames never repeat and a second's frames fill the field of view, as the real one's do.

use super::{Driver, LidarModel, Pattern};

/// The Mid-360.
pub fn mid360() -> LidarModel {
    LidarModel {
        name: "mid-360".into(),
        driver: Driver::Livox,
        pattern: Pattern::NonRepeating {
            lines: 4,
            points_per_second: 200_000.0,
            elevation_deg: [-7.0, 52.0],
            sweeps_per_second: 701.3,
        },
        rate_hz: 10.0,
        range_m: [0.1, 70.0],
        range_noise_m: 0.02,
        grazing_deg: 85.0,
        source: "Livox Mid-360 datasheet: 360 x 59 deg (-7 to 52), 200,000 points/s, 0.1 to 70 m, 2 cm (1 sigma) precision; the pattern is a model".into(),
    }
}
