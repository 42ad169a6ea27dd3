//! The only light underground is the robot's: lamps on the body, each a point source whose
//! intensity falls off from its axis over its beam and with the square of the distance, and
//! where the cameras sit among them.
//!
//! Photometric units throughout: a lamp's output in lumens, its intensity in candela, the light
//! on a surface in lux, what a surface sends back in candela per square metre. A lamp's beam
//! is a smooth bell, `I(a) = I0 exp(-ln 2 (1 - cos a) / (1 - cos(beam / 2)))` for the angle `a`
//! off its axis (a von Mises-Fisher lobe: half the peak at half the beam angle, as a
//! datasheet's beam angle is, and one exponential to work out), nothing behind it; `I0` is set
//! so the beam carries the lamp's lumens.
//!
//! Where they are ([`Rig::on`]): the cameras face forward, centred across the platform's
//! front, and two lamps sit 15 cm to either side of them and 5 cm above, pointing where the
//! cameras look. That is close to the lens, as SubT robots carried them, so a lamp's shadows
//! fall just beside what casts them, thin slivers of black along every edge. A ground robot
//! carries two 1,500-lumen lamps of 60 degrees (LED work lamps), the cameras 0.45 m above the
//! floor and tilted 5 degrees down; an aerial robot two 1,000-lumen lamps of 90 degrees, the
//! cameras level at its centre's height.

use serde::Serialize;
use subtgraph_core::vec3::V3;

use super::CameraModel;
use crate::frames::{Pose, rotation_zyx};
use crate::platform::{Kind, Platform};

/// One lamp on the body.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Lamp {
    /// Where, in `base_link`, metres.
    pub position: V3,
    /// Where it points, a unit vector in `base_link`.
    pub axis: V3,
    /// Its output, lumens.
    pub lumens: f64,
    /// Full angle at half the peak intensity, degrees.
    pub beam_deg: f64,
    /// Peak intensity on the axis, candela (from the lumens and the beam).
    pub peak_cd: f64,
}

impl Lamp {
    /// A lamp of `lumens` with a beam of `beam_deg`.
    pub fn new(position: V3, axis: V3, lumens: f64, beam_deg: f64) -> Lamp {
        let mut lamp = Lamp {
            position,
            axis,
            lumens,
            beam_deg,
            peak_cd: 0.0,
        };
        // The beam's solid angle: 2 pi times the integral of the bell's profile sin(a) over
        // the front half (midpoint rule, 2,000 steps: well under 0.1 % of error).
        let steps = 2000;
        let da = std::f64::consts::FRAC_PI_2 / f64::from(steps);
        let solid: f64 = (0..steps)
            .map(|i| {
                let a = (f64::from(i) + 0.5) * da;
                lamp.profile(a.cos()) * a.sin() * da
            })
            .sum::<f64>()
            * std::f64::consts::TAU;
        lamp.peak_cd = if solid > 0.0 { lumens / solid } else { 0.0 };
        lamp
    }

    /// The share of the peak intensity at the angle whose cosine is `cos_a` off the axis.
    #[inline]
    pub fn profile(&self, cos_a: f64) -> f64 {
        if cos_a <= 0.0 {
            return 0.0;
        }
        let half = (0.5 * self.beam_deg).to_radians().cos();
        (-std::f64::consts::LN_2 * (1.0 - cos_a.min(1.0)) / (1.0 - half).max(1e-9)).exp()
    }

    /// This lamp placed in the world by the body's pose.
    pub fn placed(&self, body: &Pose) -> PlacedLamp {
        let r = &body.rotation;
        let cos_half = (0.5 * self.beam_deg).to_radians().cos();
        PlacedLamp {
            position: body.apply(self.position),
            axis: crate::frames::mul(r, self.axis),
            peak_cd: self.peak_cd,
            kappa: std::f64::consts::LN_2 / (1.0 - cos_half).max(1e-9),
        }
    }
}

/// A lamp where it is at one instant, world frame.
#[derive(Clone, Copy, Debug)]
pub struct PlacedLamp {
    /// Where.
    pub position: V3,
    /// Where it points.
    pub axis: V3,
    /// Peak intensity, candela.
    pub peak_cd: f64,
    /// The lobe's sharpness: `ln 2 / (1 - cos(beam / 2))`.
    kappa: f64,
}

impl PlacedLamp {
    /// The illuminance, lux, a surface facing the lamp squarely receives at `point`, and the
    /// unit vector from the point to the lamp and its distance: `I(a) / d^2` (the surface's
    /// own tilt is the shading's to apply).
    #[inline]
    pub fn at(&self, point: V3) -> (f64, V3, f64) {
        let d = [
            self.position[0] - point[0],
            self.position[1] - point[1],
            self.position[2] - point[2],
        ];
        let d2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
        let dist = d2.sqrt().max(1e-6);
        let to_lamp = [d[0] / dist, d[1] / dist, d[2] / dist];
        let cos_a =
            -(to_lamp[0] * self.axis[0] + to_lamp[1] * self.axis[1] + to_lamp[2] * self.axis[2]);
        let profile = if cos_a > 0.0 {
            (-self.kappa * (1.0 - cos_a.min(1.0))).exp()
        } else {
            0.0
        };
        let lux = self.peak_cd * profile / d2.max(1e-4);
        (lux, to_lamp, dist)
    }
}

/// Where the cameras and lamps are on a platform.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Rig {
    /// Each camera's optical frame (x right, y down, z forward) in `base_link`, in the
    /// model's order.
    #[serde(skip)]
    pub cameras: Vec<Pose>,
    /// The lamps.
    pub lamps: Vec<Lamp>,
    /// Light reaching everything from everywhere, lux (0 by default: there is none
    /// underground).
    pub ambient_lux: f64,
}

/// The optical frame's axes in a body frame that looks along its x: x right is the body's -y,
/// y down the body's -z, z forward the body's x (rows: body from optical).
const OPTICAL: [[f64; 3]; 3] = [[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]];

impl Rig {
    /// The cameras of `model` and the lamps of `platform`, lamps scaled to `lamp_lumens` each
    /// when given (0 turns them off), with `ambient_lux` of light from everywhere.
    pub fn on(
        platform: &Platform,
        model: &CameraModel,
        lamp_lumens: Option<f64>,
        ambient_lux: f64,
    ) -> Rig {
        let (mount, pitch_deg, lumens, beam) = match platform.kind {
            Kind::Ground => ([0.30, 0.0, 0.45], 5.0, 1500.0, 60.0),
            Kind::Aerial => ([0.15, 0.0, 0.0], 0.0, 1000.0, 90.0),
        };
        let lumens = lamp_lumens.unwrap_or(lumens);
        // The rig's frame: at the mount point, looking forward, tilted down.
        let tilt = rotation_zyx([0.0, f64::to_radians(pitch_deg), 0.0]);
        let look = Pose {
            translation: mount,
            rotation: crate::frames::matmul(&tilt, &OPTICAL),
        };
        // The cameras centred on the mount (a stereo pair's middle on the body's axis).
        let n = model.cameras.len() as f64;
        let mean = [0, 1, 2].map(|k| model.cameras.iter().map(|c| c.offset_m[k]).sum::<f64>() / n);
        let cameras = model
            .cameras
            .iter()
            .map(|c| {
                look.then(&Pose::translated([
                    c.offset_m[0] - mean[0],
                    c.offset_m[1] - mean[1],
                    c.offset_m[2] - mean[2],
                ]))
            })
            .collect();
        let axis = crate::frames::mul(&look.rotation, [0.0, 0.0, 1.0]);
        let lamps = if lumens > 0.0 {
            [-0.15, 0.15]
                .into_iter()
                .map(|side| {
                    // Beside the lens (optical x) and a little above it (optical -y).
                    Lamp::new(look.apply([side, -0.05, 0.0]), axis, lumens, beam)
                })
                .collect()
        } else {
            Vec::new()
        };
        Rig {
            cameras,
            lamps,
            ambient_lux,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lamp_carries_its_lumens_and_falls_off_with_the_square_of_distance() {
        let lamp = Lamp::new([0.0; 3], [1.0, 0.0, 0.0], 1500.0, 60.0);
        // Lumens back from the intensity over the sphere (a finer, independent sum).
        let n = 20_000;
        let total: f64 = (0..n)
            .map(|i| {
                let a = (f64::from(i) + 0.5) * std::f64::consts::PI / f64::from(n);
                lamp.peak_cd * lamp.profile(a.cos()) * a.sin() * std::f64::consts::PI / f64::from(n)
            })
            .sum::<f64>()
            * std::f64::consts::TAU;
        assert!((total - 1500.0).abs() < 1.5, "{total}");
        // Half the peak at half the beam angle.
        assert!((lamp.profile(30f64.to_radians().cos()) - 0.5).abs() < 1e-9);
        let placed = lamp.placed(&Pose::IDENTITY);
        let (near, ..) = placed.at([2.0, 0.0, 0.0]);
        let (far, to_lamp, d) = placed.at([4.0, 0.0, 0.0]);
        assert!((near / far - 4.0).abs() < 1e-9);
        assert!((d - 4.0).abs() < 1e-12 && (to_lamp[0] + 1.0).abs() < 1e-12);
        // Nothing behind it.
        assert_eq!(placed.at([-3.0, 0.0, 0.0]).0, 0.0);
    }

    #[test]
    fn cameras_look_forward_between_the_lamps() {
        let platform = Platform::named("ground").unwrap();
        let rig = Rig::on(&platform, &super::super::presets::stereo(), None, 0.0);
        let forward = crate::frames::mul(&rig.cameras[0].rotation, [0.0, 0.0, 1.0]);
        assert!(forward[0] > 0.99 && forward[2] < 0.0, "{forward:?}");
        // cam1 is to the right: the body's -y.
        assert!(rig.cameras[1].translation[1] < rig.cameras[0].translation[1]);
        let centre = 0.5 * (rig.cameras[0].translation[1] + rig.cameras[1].translation[1]);
        assert!(centre.abs() < 1e-12);
        assert_eq!(rig.lamps.len(), 2);
        assert!(rig.lamps[0].position[1] > 0.1 && rig.lamps[1].position[1] < -0.1);
        let dark = Rig::on(&platform, &super::super::presets::stereo(), Some(0.0), 0.0);
        assert!(dark.lamps.is_empty());
    }
}
