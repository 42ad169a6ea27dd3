//! Fog and mist banks: water droplets in the air, the physics of [`super::medium`] (Hahner et
//! al., ICCV 2021) with the droplets' sizes.
//!
//! Hahner's fog has `beta = 0.046 / MOR` against `alpha = ln 20 / MOR`, a lidar ratio of
//! 65 sr, which both fog and mist take here. They differ in their droplets: fog's are 10 um in
//! radius (radiation and advection fog, 5 to 15 um), mist's 3 um, so the same water in the air
//! dims a beam three times as much as mist. 100 mg of fog droplets a cubic metre (a liquid
//! water content of 0.1 g/m^3, moderate fog) gives 0.015 /m, 200 m of visibility; a thick bank
//! in a wet mine's ventilation holds ten times that.

/// Fog droplets' radius, micrometres.
pub const FOG_RADIUS_UM: f64 = 10.0;
/// Mist droplets' radius, micrometres.
pub const MIST_RADIUS_UM: f64 = 3.0;
/// Water, g/cm^3.
pub const G_CM3: f64 = 1.0;
/// Hahner's lidar ratio: `ln 20 / 0.046`, sr.
pub fn lidar_ratio_sr() -> f64 {
    20f64.ln() / 0.046
}
