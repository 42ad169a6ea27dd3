//! What dust and fog do to a camera's pixel: the light of the scene dimmed on its way, and the
//! robot's own lamp scattered back into the lens (the haze that grows with the lamp's power,
//! why a robot in dust sees less with its lights up).
//!
//! For a pixel's ray through media `spans` (as [`super::Active::spans`] gives them) to the
//! surface it sees at `hit` metres, with a lamp of radiant intensity `I` (W/sr) beside the
//! camera, single scattering gives:
//!
//! ```text
//! transmittance       T = exp(-tau(hit))                 (the scene's light, one way)
//! lamp_transmittance  T_L = exp(-2 tau(hit))             (the lamp's light, there and back)
//! backscatter         L_b = I integral from r0 to hit of beta(r) exp(-2 tau(r)) / r^2 dr
//! ```
//!
//! with `beta` the medium's backscatter coefficient (1/(m sr), the same the LiDAR's particles
//! have) and `r0` where the lamp's beam enters the camera's view ([`OVERLAP_M`]). A pixel
//! then reads `T_L * (lamp-lit surface radiance) + T * (otherwise lit) + L_b`. `L_b` grows in
//! proportion to the lamp's power: doubling the light doubles the haze while the surface's
//! share stays the same.
//!
//! The camera renderer of `sense` calls this per pixel; until it lands, this function is
//! what it will call, tested on its own.

use super::medium::{Span, depth};

/// Where a lamp beside the camera starts to light what the camera sees, metres.
pub const OVERLAP_M: f64 = 0.3;

/// A lamp beside the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Lamp {
    /// Radiant intensity along the camera's view, W/sr.
    pub intensity_w_sr: f64,
}

/// What the media do to one pixel's ray.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Seen {
    /// The scene's light reaching the camera from the surface, `0..=1`.
    pub transmittance: f64,
    /// The lamp's light reaching the surface and coming back, `0..=1`.
    pub lamp_transmittance: f64,
    /// Lamp light scattered back into the pixel, W/(m^2 sr).
    pub backscatter: f64,
}

/// A camera ray through `spans` (sorted, not overlapping) to a surface at `hit` metres, lit
/// by `lamp`.
pub fn camera_ray(spans: &[Span], hit: f64, lamp: &Lamp) -> Seen {
    let tau = depth(spans, hit);
    let mut integral = 0.0;
    for s in spans {
        let (a, b) = (s.a.max(OVERLAP_M), s.b.min(hit));
        if b <= a || s.beta <= 0.0 {
            continue;
        }
        // With u = 1/r the 1/r^2 goes into du and the integrand is smooth: Simpson's rule.
        let (u0, u1) = (1.0 / b, 1.0 / a);
        let n = 64;
        let h = (u1 - u0) / n as f64;
        let f = |u: f64| {
            let r = 1.0 / u;
            s.beta * (-2.0 * depth(spans, r)).exp()
        };
        let mut sum = f(u0) + f(u1);
        for k in 1..n {
            sum += f(u0 + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        integral += sum * h / 3.0;
    }
    Seen {
        transmittance: (-tau).exp(),
        lamp_transmittance: (-2.0 * tau).exp(),
        backscatter: lamp.intensity_w_sr * integral,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn uniform(alpha: f64, beta: f64, to: f64) -> Vec<Span> {
        vec![Span {
            a: 0.0,
            b: to,
            alpha,
            beta,
            kind: 1,
        }]
    }

    #[test]
    fn clear_air_adds_no_haze_and_dims_nothing() {
        let s = camera_ray(
            &[],
            12.0,
            &Lamp {
                intensity_w_sr: 5.0,
            },
        );
        assert_eq!(
            (s.transmittance, s.lamp_transmittance, s.backscatter),
            (1.0, 1.0, 0.0)
        );
    }

    #[test]
    fn haze_matches_the_closed_forms_and_grows_with_the_lamp() {
        // No extinction: L_b = I beta (1/r0 - 1/R).
        let lamp = Lamp {
            intensity_w_sr: 2.0,
        };
        let s = camera_ray(&uniform(0.0, 0.01, 20.0), 8.0, &lamp);
        let exact = 2.0 * 0.01 * (1.0 / OVERLAP_M - 1.0 / 8.0);
        assert!((s.backscatter - exact).abs() < 1e-9 * exact, "{s:?}");
        // With extinction, against a fine trapezoidal sum in r.
        let spans = uniform(0.2, 0.005, 30.0);
        let s = camera_ray(&spans, 10.0, &lamp);
        let n = 2_000_000;
        let dr = (10.0 - OVERLAP_M) / n as f64;
        let sum: f64 = (0..n)
            .map(|k| {
                let r = OVERLAP_M + (k as f64 + 0.5) * dr;
                0.005 * (-0.4 * r).exp() / (r * r) * dr
            })
            .sum();
        assert!(
            (s.backscatter - 2.0 * sum).abs() < 1e-4 * s.backscatter,
            "{s:?} {sum}"
        );
        assert!((s.transmittance - (-2.0f64).exp()).abs() < 1e-12);
        assert!((s.lamp_transmittance - (-4.0f64).exp()).abs() < 1e-12);
        let brighter = camera_ray(
            &spans,
            10.0,
            &Lamp {
                intensity_w_sr: 4.0,
            },
        );
        assert!((brighter.backscatter - 2.0 * s.backscatter).abs() < 1e-12);
    }
}
