//! Wet and dark rock, and puddles on its floors.
//!
//! A film of water darkens rock in the near infrared (light that enters the film is
//! reflected inside it and absorbed; wet basalt and shale lose half to three quarters of
//! their reflectance): a surface hit inside a wet place has its reflectivity multiplied by the
//! condition's `reflectance_factor` (default 0.3). Its signal then falls toward the detection
//! floor ([`super::medium::Receiver`]): below it the return is lost, and above it the range
//! noise grows as the signal falls, since a time-of-flight sensor's range precision goes as
//! one over the square root of its signal (shot noise): `sigma = sigma_0 sqrt(s_nominal / s)`,
//! never below the datasheet's `sigma_0`, which holds from `s_nominal` = 25 times the floor
//! up (a 10 % target at a fifth of its rated range).
//!
//! **Puddles.** Of the floor in a wet place (surfaces facing up, within 30 degrees of
//! vertical), the share `puddles` (default 0.25) is under water, in 0.5 m cells chosen by
//! the seed. Water is a mirror: the beam goes on, reflected, and what it meets there comes
//! back along the same path, so the sensor reports a point *under* the floor at the whole
//! path's length (the ghost of the walls and roof seen in a puddle). The mirror reflects what
//! Fresnel's equations give for water (Schlick's approximation, n = 1.33: 2 % head on, most
//! of the light at grazing angles, which is how a LiDAR sees a floor).

use subtgraph_core::vec3::V3;

use super::medium::Receiver;
use crate::noise;

/// Default reflectance factor of wet rock.
pub const FACTOR: f64 = 0.3;
/// Default share of a wet floor under water.
pub const PUDDLES: f64 = 0.25;
/// Puddle cells, metres.
const CELL: f64 = 0.5;

/// The range noise's factor for a return of signal `s` (at least 1).
pub fn noise_scale(rx: &Receiver, s: f64) -> f64 {
    (25.0 * rx.s_min / s.max(1e-30)).sqrt().max(1.0)
}

/// Whether a surface of unit normal `n` is floor.
pub fn is_floor(n: V3) -> bool {
    n[2] > 30f64.to_radians().cos()
}

/// Whether the floor at `p` is under water, for a share `share` of cells.
pub fn puddle_at(seed: u64, p: V3, share: f64) -> bool {
    let cx = (p[0] / CELL).floor() as i64 as u64;
    let cy = (p[1] / CELL).floor() as i64 as u64;
    let cz = (p[2] / 2.0).floor() as i64 as u64;
    let key = cx.wrapping_mul(0x9e37_79b9) ^ cy.wrapping_mul(0x85eb_ca6b) ^ cz << 48;
    noise::uniform(seed, key) < share
}

/// Water's reflectance at incidence cosine `cos` (Schlick, n = 1.33).
pub fn fresnel(cos: f64) -> f64 {
    let r0: f64 = ((1.33 - 1.0) / (1.33 + 1.0)) * ((1.33 - 1.0) / (1.33 + 1.0));
    r0 + (1.0 - r0) * (1.0 - cos.clamp(0.0, 1.0)).powi(5)
}

/// `d` mirrored in the plane of unit normal `n`.
pub fn mirror(d: V3, n: V3) -> V3 {
    let k = 2.0 * (d[0] * n[0] + d[1] * n[1] + d[2] * n[2]);
    [d[0] - k * n[0], d[1] - k * n[1], d[2] - k * n[2]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn water_mirrors_more_at_grazing_angles() {
        assert!((fresnel(1.0) - 0.02).abs() < 0.001);
        assert!(fresnel(0.2) > 0.3 && fresnel(0.05) > 0.75);
        let m = mirror([0.6, 0.0, -0.8], [0.0, 0.0, 1.0]);
        assert!((m[2] - 0.8).abs() < 1e-12 && (m[0] - 0.6).abs() < 1e-12);
    }

    #[test]
    fn puddles_cover_their_share_of_the_floor() {
        let n = 40_000;
        let wet = (0..n)
            .filter(|i| {
                puddle_at(
                    5,
                    [(i % 200) as f64 * 0.5, (i / 200) as f64 * 0.5, 0.0],
                    0.25,
                )
            })
            .count();
        assert!((wet as f64 / n as f64 - 0.25).abs() < 0.01, "{wet}");
    }

    #[test]
    fn noise_grows_as_the_signal_falls() {
        let rx = Receiver::of_range(0.8, 120.0);
        assert_eq!(noise_scale(&rx, 100.0 * rx.s_min), 1.0);
        assert!((noise_scale(&rx, rx.s_min) - 5.0).abs() < 1e-9);
    }
}
