//! The cameras' ROS 2 messages in CDR, and their definitions: `sensor_msgs/msg/Image` and
//! `sensor_msgs/msg/CameraInfo`.
//!
//! | topic | type | contents |
//! |---|---|---|
//! | `/camN/image_raw` | `Image` | `rgb8` (a colour chip) or `mono8`, stamped at the middle of the exposure (a rolling shutter's first row) |
//! | `/camN/camera_info` | `CameraInfo` | the true intrinsics: `plumb_bob` (`k3 = 0`) or `equidistant`, `R` identity, `P = [K | -fx b]` with `b` the camera's offset from the first along x |
//! | `/cam0/depth/image_raw` (an RGB-D camera) | `Image` | `16UC1`, millimetres along the optical axis, aligned to cam0 (REP 118), 0 outside the depth range |
//!
//! Each camera's frame is its optical frame (`camN_optical_frame`: x right, y down, z
//! forward), placed on `base_link` by `/tf_static`.

use super::cdr::{Cdr, HEADER, TIME, definition};
use crate::camera::Camera;

/// A `sensor_msgs/Image` whose `height * step` bytes `fill` appends.
#[allow(clippy::too_many_arguments)]
pub fn image(
    buf: &mut Vec<u8>,
    stamp_ns: u64,
    frame: &str,
    width: u32,
    height: u32,
    encoding: &str,
    step: u32,
    fill: impl FnOnce(&mut Vec<u8>),
) {
    let mut c = Cdr::new(buf);
    c.header(stamp_ns, frame);
    c.u32(height);
    c.u32(width);
    c.string(encoding);
    c.u8(0);
    c.u32(step);
    c.bytes_with((height * step) as usize, fill);
}

/// A `sensor_msgs/CameraInfo` of `camera`, `tx` the projection's `-fx b` term.
pub fn camera_info(buf: &mut Vec<u8>, stamp_ns: u64, frame: &str, camera: &Camera, tx: f64) {
    let l = &camera.intrinsics;
    let [fx, fy] = l.focal;
    let [cx, cy] = l.centre;
    let mut c = Cdr::new(buf);
    c.header(stamp_ns, frame);
    c.u32(l.height);
    c.u32(l.width);
    c.string(l.distortion.ros_name());
    let d = l.distortion.coefficients();
    let d: Vec<f64> = match l.distortion {
        crate::camera::lens::Distortion::RadTan { .. } => vec![d[0], d[1], d[2], d[3], 0.0],
        crate::camera::lens::Distortion::Equidistant { .. } => d.to_vec(),
    };
    c.u32(d.len() as u32);
    c.f64s(&d);
    c.f64s(&[fx, 0.0, cx, 0.0, fy, cy, 0.0, 0.0, 1.0]);
    c.f64s(&[1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]);
    c.f64s(&[fx, 0.0, cx, tx, 0.0, fy, cy, 0.0, 0.0, 0.0, 1.0, 0.0]);
    c.u32(0);
    c.u32(0);
    // The region of interest: none (the whole image).
    c.u32(0);
    c.u32(0);
    c.u32(0);
    c.u32(0);
    c.u8(0);
}

/// The definitions of the cameras' message types (`None` for another type).
pub fn schema(type_name: &str) -> Option<String> {
    let definition = match type_name {
        "sensor_msgs/msg/Image" => definition(
            "std_msgs/Header header\nuint32 height\nuint32 width\nstring encoding\nuint8 is_bigendian\nuint32 step\nuint8[] data\n",
            &[HEADER, TIME],
        ),
        "sensor_msgs/msg/CameraInfo" => definition(
            "std_msgs/Header header\nuint32 height\nuint32 width\nstring distortion_model\nfloat64[] d\nfloat64[9] k\nfloat64[9] r\nfloat64[12] p\nuint32 binning_x\nuint32 binning_y\nsensor_msgs/RegionOfInterest roi\n",
            &[
                HEADER,
                TIME,
                "MSG: sensor_msgs/RegionOfInterest\nuint32 x_offset\nuint32 y_offset\nuint32 height\nuint32 width\nbool do_rectify\n",
            ],
        ),
        _ => return None,
    };
    Some(definition)
}
