//! Lenses: where a point in front of a camera lands in its image, and which ray a pixel sees.
//!
//! Two models, the two that Kalibr, OpenVINS, VINS-Fusion and ORB-SLAM3 calibrate and that
//! OpenCV implements:
//! - **pinhole with radial-tangential distortion** (Kalibr's `pinhole` + `radtan`, OpenCV's
//!   and ROS's `plumb_bob` with `k3 = 0`): `x = X/Z`, `y = Y/Z`, then
//!   `x' = x (1 + k1 r^2 + k2 r^4) + 2 p1 x y + p2 (r^2 + 2 x^2)` and likewise `y'`;
//! - **equidistant fisheye** (Kannala and Brandt, PAMI 2006, as Kalibr's `pinhole` +
//!   `equidistant` and OpenCV's `cv::fisheye`): the angle `theta` from the optical axis maps to
//!   the radius `theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8)`.
//!
//! Then `u = fx x' + cx`, `v = fy y' + cy` in pixels, OpenCV's and Kalibr's convention: the
//! centre of the top-left pixel is `(0, 0)`, so pixel `(i, j)` sees the ray
//! [`Intrinsics::ray`] gives for `(i, j)`.
//!
//! The camera's optical frame is OpenCV's and ROS's (REP 103 `_optical`): x right, y down,
//! z forward. A lens whose distortion folds the image (two rays landing on one pixel, or the
//! image's corners beyond what the polynomial reaches) is refused by [`Intrinsics::check`]
//! before anything is rendered: its pixels could not be turned back into rays.

use serde::Serialize;
use subtgraph_core::vec3::V3;

/// How a lens bends rays away from the pinhole's straight lines.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "model", rename_all = "kebab-case")]
pub enum Distortion {
    /// Radial-tangential (`radtan`, `plumb_bob` with `k3 = 0`): `[k1, k2, p1, p2]`.
    RadTan {
        /// `[k1, k2, p1, p2]`.
        coefficients: [f64; 4],
    },
    /// Equidistant fisheye (Kannala-Brandt): `[k1, k2, k3, k4]`.
    Equidistant {
        /// `[k1, k2, k3, k4]`.
        coefficients: [f64; 4],
    },
}

impl Distortion {
    /// Kalibr's name of the distortion model (`radtan`, `equidistant`).
    pub fn kalibr_name(&self) -> &'static str {
        match self {
            Distortion::RadTan { .. } => "radtan",
            Distortion::Equidistant { .. } => "equidistant",
        }
    }

    /// The ROS `CameraInfo` `distortion_model` (`plumb_bob`, `equidistant`).
    pub fn ros_name(&self) -> &'static str {
        match self {
            Distortion::RadTan { .. } => "plumb_bob",
            Distortion::Equidistant { .. } => "equidistant",
        }
    }

    /// The coefficients, in the order the model's name lists them.
    pub fn coefficients(&self) -> [f64; 4] {
        match *self {
            Distortion::RadTan { coefficients } | Distortion::Equidistant { coefficients } => {
                coefficients
            }
        }
    }
}

/// A camera's image and lens: size, focal lengths, principal point and distortion.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Intrinsics {
    /// Pixels across.
    pub width: u32,
    /// Pixels down.
    pub height: u32,
    /// Focal length in pixels, `[fx, fy]`.
    pub focal: [f64; 2],
    /// Principal point in pixels, `[cx, cy]` (the top-left pixel's centre is `(0, 0)`).
    pub centre: [f64; 2],
    /// The lens's distortion.
    pub distortion: Distortion,
    /// A fisheye's image circle, the full angle it sees, degrees (the T265's 163): pixels
    /// beyond it, the image's corners, see nothing (black, no depth). `None`: the whole
    /// image sees.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub circle_deg: Option<f64>,
}

/// Why a lens cannot be used, for [`Intrinsics::check`]'s caller to put in an error.
#[derive(Clone, Debug, PartialEq)]
pub struct LensProblem {
    /// The setting at fault.
    pub what: &'static str,
    /// Its value.
    pub value: String,
    /// What it must be.
    pub bounds: String,
}

/// The widest angle from the optical axis a pixel may see, radians: just short of 90
/// degrees, so depth along the axis (what the depth images hold) stays positive.
const MAX_THETA: f64 = 89.0 * std::f64::consts::PI / 180.0;

impl Intrinsics {
    /// The normalised image point (`x'`, `y'` before the focal lengths) of a direction in
    /// the optical frame, or `None` behind the camera or past the lens's reach.
    pub fn distort(&self, p: V3) -> Option<[f64; 2]> {
        match self.distortion {
            Distortion::RadTan {
                coefficients: [k1, k2, p1, p2],
            } => {
                if p[2] <= 0.0 {
                    return None;
                }
                let (x, y) = (p[0] / p[2], p[1] / p[2]);
                let r2 = x * x + y * y;
                let radial = 1.0 + r2 * (k1 + k2 * r2);
                Some([
                    x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x),
                    y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y,
                ])
            }
            Distortion::Equidistant { coefficients: k } => {
                let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
                let theta = r.atan2(p[2]);
                if theta > MAX_THETA {
                    return None;
                }
                let d = theta_d(k, theta);
                if r < 1e-300 {
                    return Some([0.0, 0.0]);
                }
                Some([d * p[0] / r, d * p[1] / r])
            }
        }
    }

    /// The pixel `[u, v]` a direction in the optical frame lands on (it may be outside the
    /// image), or `None` behind the camera.
    pub fn project(&self, p: V3) -> Option<[f64; 2]> {
        let [x, y] = self.distort(p)?;
        Some([
            self.focal[0] * x + self.centre[0],
            self.focal[1] * y + self.centre[1],
        ])
    }

    /// The direction (`z = 1`) pixel `[u, v]` sees, the inverse of [`project`](Self::project)
    /// by Newton's method (to 1e-12 of a normalised unit), or `None` where the lens cannot
    /// be inverted there.
    pub fn ray(&self, u: f64, v: f64) -> Option<V3> {
        let xd = (u - self.centre[0]) / self.focal[0];
        let yd = (v - self.centre[1]) / self.focal[1];
        match self.distortion {
            Distortion::RadTan { coefficients } => undistort_radtan(coefficients, xd, yd),
            Distortion::Equidistant { coefficients: k } => {
                let rd = (xd * xd + yd * yd).sqrt();
                if rd < 1e-300 {
                    return Some([0.0, 0.0, 1.0]);
                }
                let theta = invert_theta(k, rd)?;
                if theta > self.max_theta() {
                    return None;
                }
                let s = theta.tan() / rd;
                Some([xd * s, yd * s, 1.0])
            }
        }
    }

    /// The widest angle from the optical axis a pixel sees, radians.
    fn max_theta(&self) -> f64 {
        self.circle_deg
            .map_or(MAX_THETA, |c| (0.5 * c).to_radians().min(MAX_THETA))
    }

    /// Whether pixel `[u, v]` lies inside the lens's image circle (always, without one).
    pub fn in_circle(&self, u: f64, v: f64) -> bool {
        let Distortion::Equidistant { coefficients: k } = self.distortion else {
            return true;
        };
        if self.circle_deg.is_none() {
            return true;
        }
        let xd = (u - self.centre[0]) / self.focal[0];
        let yd = (v - self.centre[1]) / self.focal[1];
        (xd * xd + yd * yd).sqrt() <= theta_d(k, self.max_theta())
    }

    /// Refuses a lens no camera has: a size, focal length or principal point out of bounds,
    /// or a distortion that folds the image (the radius stops growing before the image's
    /// corners, so two rays would meet at one pixel) or that cannot be inverted at every
    /// pixel to within a thousandth of a pixel.
    pub fn check(&self) -> Result<(), LensProblem> {
        let problem = |what, value: String, bounds: &str| {
            Err(LensProblem {
                what,
                value,
                bounds: bounds.to_owned(),
            })
        };
        let (w, h) = (self.width, self.height);
        if !(16..=4096).contains(&w) || !(16..=4096).contains(&h) {
            return problem(
                "resolution",
                format!("{w} x {h}"),
                "16 to 4096 pixels each way",
            );
        }
        let [fx, fy] = self.focal;
        if !(fx.is_finite() && fy.is_finite() && fx >= 1.0 && fy >= 1.0)
            || fx > 100.0 * f64::from(w)
            || fy > 100.0 * f64::from(h)
            || fx / fy > 4.0
            || fy / fx > 4.0
        {
            return problem(
                "focal length",
                format!("[{fx}, {fy}] pixels"),
                "positive, at least 1 pixel, at most 100 image widths, fx and fy within 4 times each other",
            );
        }
        let [cx, cy] = self.centre;
        if !(cx.is_finite() && cy.is_finite())
            || cx < 0.0
            || cy < 0.0
            || cx > f64::from(w - 1)
            || cy > f64::from(h - 1)
        {
            return problem(
                "principal point",
                format!("[{cx}, {cy}]"),
                &format!("inside the image, 0 to {} and 0 to {}", w - 1, h - 1),
            );
        }
        if let Some(c) = self.circle_deg {
            let fisheye = matches!(self.distortion, Distortion::Equidistant { .. });
            if !(c.is_finite() && c > 10.0 && c <= 178.0 && fisheye) {
                return problem(
                    "field_of_view_deg",
                    format!("{c}"),
                    "an equidistant (fisheye) lens's image circle, 10 to 178 degrees across",
                );
            }
        }
        let k = self.distortion.coefficients();
        if k.iter().any(|c| !c.is_finite() || c.abs() > 10.0) {
            return problem(
                "distortion coefficients",
                format!("{k:?}"),
                "finite, each within -10 to 10",
            );
        }
        // The farthest normalised radius a pixel of the image reaches.
        let corners = [
            [0.0, 0.0],
            [f64::from(w - 1), 0.0],
            [0.0, f64::from(h - 1)],
            [f64::from(w - 1), f64::from(h - 1)],
        ];
        let reach = corners
            .iter()
            .map(|[u, v]| {
                let x = (u - cx) / fx;
                let y = (v - cy) / fy;
                (x * x + y * y).sqrt()
            })
            .fold(0.0, f64::max);
        if let Some(why) = self.folds(reach) {
            return problem(
                "distortion coefficients",
                format!("{} {k:?}", self.distortion.kalibr_name()),
                &format!(
                    "a distortion that does not fold the image: {why}; check their signs and sizes (a calibration's coefficients, in Kalibr's order)"
                ),
            );
        }
        // Every pixel's ray goes back to the same pixel (a grid, corners and edges included).
        for j in 0..=16 {
            for i in 0..=16 {
                let u = f64::from(w - 1) * f64::from(i) / 16.0;
                let v = f64::from(h - 1) * f64::from(j) / 16.0;
                if !self.in_circle(u, v) {
                    continue;
                }
                let back = self.ray(u, v).and_then(|r| self.project(r));
                let off = back.map_or(f64::INFINITY, |[bu, bv]| (bu - u).hypot(bv - v));
                if off.is_nan() || off > 1e-3 {
                    return problem(
                        "distortion coefficients",
                        format!("{} {k:?}", self.distortion.kalibr_name()),
                        &format!(
                            "a distortion every pixel can be turned back into a ray: pixel ({u:.0}, {v:.0}) cannot (the lens folds or reaches past 89 degrees from its axis there)"
                        ),
                    );
                }
            }
        }
        Ok(())
    }

    /// Why the radial part folds before the normalised radius `reach`, if it does.
    fn folds(&self, reach: f64) -> Option<String> {
        match self.distortion {
            Distortion::RadTan {
                coefficients: [k1, k2, ..],
            } => {
                // r_d(r) = r (1 + k1 r^2 + k2 r^4) must grow until it passes `reach`.
                let mut r = 0.0;
                let step = 1e-3;
                loop {
                    let slope = 1.0 + 3.0 * k1 * r * r + 5.0 * k2 * r.powi(4);
                    if slope <= 0.0 {
                        return Some(format!(
                            "the distorted radius stops growing at {r:.3} (normalised), short of the image's corners at {reach:.3}"
                        ));
                    }
                    let rd = r * (1.0 + r * r * (k1 + k2 * r * r));
                    if rd > reach {
                        return None;
                    }
                    if r > 20.0 {
                        return Some(format!(
                            "the image's corners at {reach:.3} (normalised) lie past what the lens reaches"
                        ));
                    }
                    r += step;
                }
            }
            Distortion::Equidistant { coefficients: k } => {
                let mut theta: f64 = 0.0;
                let circle = self.circle_deg.map(|c| (0.5 * c).to_radians());
                loop {
                    if theta_d_slope(k, theta) <= 0.0 {
                        return Some(format!(
                            "the distorted angle stops growing at {:.1} degrees from the axis",
                            theta.to_degrees()
                        ));
                    }
                    if theta_d(k, theta) > reach || circle.is_some_and(|c| theta >= c) {
                        return None;
                    }
                    if theta > MAX_THETA {
                        return Some(
                            "the image's corners lie more than 89 degrees from the optical axis (a field of view of 178 degrees or more); use a longer focal length or a smaller image".to_owned(),
                        );
                    }
                    theta += 1e-3;
                }
            }
        }
    }

    /// The field of view across and down through the principal point, degrees (a
    /// fisheye's image circle where it is narrower than the image).
    pub fn field_of_view_deg(&self) -> [f64; 2] {
        let angle = |u: f64, v: f64| {
            self.ray(u, v).map_or(self.max_theta(), |r| {
                let n = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
                (r[2] / n).acos()
            })
        };
        let (w, h) = (f64::from(self.width - 1), f64::from(self.height - 1));
        let [cx, cy] = self.centre;
        [
            (angle(0.0, cy) + angle(w, cy)).to_degrees(),
            (angle(cx, 0.0) + angle(cx, h)).to_degrees(),
        ]
    }
}

/// The equidistant model's distorted angle.
fn theta_d(k: [f64; 4], theta: f64) -> f64 {
    let t2 = theta * theta;
    theta * (1.0 + t2 * (k[0] + t2 * (k[1] + t2 * (k[2] + t2 * k[3]))))
}

/// Its derivative in `theta`.
fn theta_d_slope(k: [f64; 4], theta: f64) -> f64 {
    let t2 = theta * theta;
    1.0 + t2 * (3.0 * k[0] + t2 * (5.0 * k[1] + t2 * (7.0 * k[2] + t2 * 9.0 * k[3])))
}

/// The angle whose distorted angle is `rd`, by Newton's method from `rd` itself.
fn invert_theta(k: [f64; 4], rd: f64) -> Option<f64> {
    let mut theta = rd.min(MAX_THETA);
    for _ in 0..50 {
        let f = theta_d(k, theta) - rd;
        let slope = theta_d_slope(k, theta);
        if slope <= 1e-9 {
            return None;
        }
        let next = (theta - f / slope).clamp(0.0, MAX_THETA + 0.01);
        if (next - theta).abs() < 1e-14 {
            theta = next;
            break;
        }
        theta = next;
    }
    (theta <= MAX_THETA && (theta_d(k, theta) - rd).abs() < 1e-9).then_some(theta)
}

/// The undistorted normalised point of a radial-tangential lens's distorted one, by Newton's
/// method on both coordinates.
fn undistort_radtan([k1, k2, p1, p2]: [f64; 4], xd: f64, yd: f64) -> Option<V3> {
    let (mut x, mut y) = (xd, yd);
    for _ in 0..60 {
        let r2 = x * x + y * y;
        let radial = 1.0 + r2 * (k1 + k2 * r2);
        let fx = x * radial + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x) - xd;
        let fy = y * radial + p1 * (r2 + 2.0 * y * y) + 2.0 * p2 * x * y - yd;
        // d radial / dx = (2 k1 + 4 k2 r2) x.
        let dr = 2.0 * k1 + 4.0 * k2 * r2;
        let j00 = radial + x * dr * x + 2.0 * p1 * y + 6.0 * p2 * x;
        let j01 = x * dr * y + 2.0 * p1 * x + 2.0 * p2 * y;
        let j10 = y * dr * x + 2.0 * p1 * x + 2.0 * p2 * y;
        let j11 = radial + y * dr * y + 6.0 * p1 * y + 2.0 * p2 * x;
        let det = j00 * j11 - j01 * j10;
        if det.abs() < 1e-12 || !det.is_finite() {
            return None;
        }
        let dx = (fx * j11 - fy * j01) / det;
        let dy = (fy * j00 - fx * j10) / det;
        x -= dx;
        y -= dy;
        if dx.abs() < 1e-14 && dy.abs() < 1e-14 {
            break;
        }
    }
    (x.is_finite() && y.is_finite()).then_some([x, y, 1.0])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pinhole(k: [f64; 4]) -> Intrinsics {
        Intrinsics {
            width: 640,
            height: 480,
            focal: [500.0, 500.0],
            centre: [319.5, 239.5],
            distortion: Distortion::RadTan { coefficients: k },
            circle_deg: None,
        }
    }

    #[test]
    fn rays_go_back_to_their_pixels() {
        let euroc = pinhole([-0.28340811, 0.07395907, 0.00019359, 1.76187114e-05]);
        let fisheye = Intrinsics {
            width: 848,
            height: 800,
            focal: [286.0, 286.0],
            centre: [424.0, 400.0],
            distortion: Distortion::Equidistant {
                coefficients: [-0.0087, 0.0405, -0.0383, 0.0068],
            },
            circle_deg: Some(163.0),
        };
        for lens in [euroc, fisheye, pinhole([0.0; 4])] {
            lens.check().unwrap();
            for (u, v) in [(0.0, 0.0), (100.3, 400.7), (319.5, 239.5), (639.0, 479.0)] {
                let Some(r) = lens.ray(u, v) else {
                    assert!(!lens.in_circle(u, v), "{lens:?} ({u}, {v})");
                    continue;
                };
                let [bu, bv] = lens.project(r).unwrap();
                assert!((bu - u).abs() < 1e-6 && (bv - v).abs() < 1e-6, "{lens:?}");
            }
        }
        // The fisheye sees 150 degrees or more across.
        assert!(
            fisheye.field_of_view_deg()[0] > 150.0,
            "{:?}",
            fisheye.field_of_view_deg()
        );
    }

    #[test]
    fn a_folding_or_impossible_lens_is_refused() {
        // A strong negative k1 turns the radius back before the corners.
        let e = pinhole([-1.5, 0.0, 0.0, 0.0]).check().unwrap_err();
        assert!(e.bounds.contains("fold"), "{e:?}");
        let mut zero = pinhole([0.0; 4]);
        zero.focal = [0.0, 500.0];
        assert_eq!(zero.check().unwrap_err().what, "focal length");
        let mut off = pinhole([0.0; 4]);
        off.centre = [900.0, 10.0];
        assert_eq!(off.check().unwrap_err().what, "principal point");
        // A fisheye whose corners lie past 89 degrees.
        let wide = Intrinsics {
            width: 1000,
            height: 1000,
            focal: [150.0, 150.0],
            centre: [500.0, 500.0],
            distortion: Distortion::Equidistant {
                coefficients: [0.0; 4],
            },
            circle_deg: None,
        };
        assert!(wide.check().is_err());
        // The same with an image circle of 160 degrees: its corners see nothing.
        let circled = Intrinsics {
            circle_deg: Some(160.0),
            ..wide
        };
        circled.check().unwrap();
        assert!(circled.ray(0.0, 0.0).is_none() && !circled.in_circle(0.0, 0.0));
        assert!(circled.ray(500.0, 500.0).is_some());
    }
}
