//! One frame from a pose of one's own, for pipelines that choose their views (the Python
//! `World.render`): the camera stands still where it is put, lit by the platform's lamps
//! beside it, exposed by its own metering.

use super::CameraModel;
use super::light::Rig;
use super::render::{Renderer, Shot};
use super::scene::CameraScene;
use super::sensor::{AutoExposure, expose};
use crate::frames::Pose;
use crate::platform::Platform;
use crate::trajectory::Trajectory;

/// A rendered frame of one camera.
pub struct Still {
    /// Pixels across.
    pub width: usize,
    /// Pixels down.
    pub height: usize,
    /// 3 (RGB) or 1 (grey) bytes a pixel.
    pub channels: usize,
    /// The 8-bit image, rows from the top.
    pub image: Vec<u8>,
    /// Depth along the optical axis, metres (0: nothing seen).
    pub depth: Vec<f32>,
    /// Semantic class ids.
    pub labels: Vec<u16>,
    /// Instance ids.
    pub instances: Vec<u32>,
}

/// Renders camera `c` of `model` with its optical frame at `camera` (world frame: x right,
/// y down, z forward), the rig's other cameras and `platform`'s lamps (each of
/// `lamp_lumens` when given) placed around it as on the platform, `ambient_lux` of light from
/// everywhere; noise drawn from `seed` unless `noiseless`.
#[allow(clippy::too_many_arguments)]
pub fn render(
    scene: &CameraScene,
    model: &CameraModel,
    platform: &Platform,
    c: usize,
    camera: Pose,
    lamp_lumens: Option<f64>,
    ambient_lux: f64,
    noiseless: bool,
    seed: u64,
) -> Still {
    let rig = Rig::on(platform, model, lamp_lumens, ambient_lux);
    let c = c.min(model.cameras.len() - 1);
    // The body where it must be for camera `c` to be at `camera`, standing still.
    let body = camera.then(&rig.cameras[c].inverse());
    let r = body.rotation;
    let yaw = r[1][0].atan2(r[0][0]);
    let pitch = (-r[2][0]).clamp(-1.0, 1.0).asin();
    let roll = r[2][1].atan2(r[2][2]);
    let t = body.translation;
    let trajectory = Trajectory::new(1.0, vec![[t[0], t[1], t[2], yaw, pitch, roll]; 6]);
    let renderer = Renderer::new(scene, &trajectory, &rig, model, false);
    let mut shot = Shot::default();
    renderer.render(c, 0.0, model.sensor.exposure_s[1], &mut shot);
    let exposure = AutoExposure::new(model).meter(&shot.signal);
    let mut image = Vec::new();
    expose(model, &shot.signal, exposure, seed, noiseless, &mut image);
    let lens = &model.cameras[c].intrinsics;
    Still {
        width: lens.width as usize,
        height: lens.height as usize,
        channels: if model.sensor.colour { 3 } else { 1 },
        image,
        depth: shot.depth,
        labels: shot.class,
        instances: shot.instance,
    }
}
