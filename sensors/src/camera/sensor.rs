//! From light to numbers: the lens's light gathering and vignetting, auto-exposure, shot and
//! read noise, gain, and the 8-bit values written.
//!
//! A surface of luminance `L` (candela per square metre) puts `E = L pi T / (4 N^2)` lux on the
//! sensor behind a lens of f-number `N` and transmittance `T = 0.9`, less towards the image's
//! edges (vignetting: the cos^4 law for the pinhole lenses; `cos(theta) sin(theta) / theta` for
//! an equidistant fisheye, its projection's own area ratio times the pupil's foreshortening).
//! A lux of white light is about 10^16 photons a second on a square metre, so a pixel of pitch
//! `p` and quantum efficiency `q` collects `10^16 p^2 q E` electrons a second.
//!
//! **Auto-exposure** meters each frame of the rig's first camera and sets the next frame's
//! exposure (a real camera's loop, one frame behind): the exposure-gain product that brings the
//! mean signal to 18 % of the full well, but no more than puts the brightest 3 % of pixels at
//! 90 %, changed by at most a factor of 2 a frame; the exposure time takes it up to its longest,
//! the gain the rest up to its most. Frames past both are dark, as a real camera's are. The
//! whole rig shares one exposure, as synchronised stereo pairs and the RealSense cameras do.
//!
//! **Noise**: a pixel collecting `e` electrons reads `e + sqrt(e + r^2) z` (Poisson's shot noise
//! and the read noise `r`, one Gaussian `z` per pixel and channel drawn by hashing the seed,
//! frame, camera and pixel), times the gain, over the full well, clipped, then encoded with
//! a 2.2 gamma to 8 bits. A monochrome chip reads the light's luminance.

use super::CameraModel;
use super::lens::Distortion;
use crate::noise;

/// The lens's transmittance.
const TRANSMITTANCE: f64 = 0.9;
/// Photons a second on a square metre per lux of white light.
const PHOTONS_PER_LUX_SECOND: f64 = 1e16;
/// The mean signal auto-exposure aims for, as a share of the full well.
const TARGET_MEAN: f64 = 0.18;
/// The most the brightest 3 % may reach.
const TARGET_HIGH: f64 = 0.9;

/// Electrons a second per candela per square metre of scene luminance at the image's centre.
pub fn electrons_per_nit_second(model: &CameraModel) -> f64 {
    let s = &model.sensor;
    let pixel = s.pixel_um * 1e-6;
    std::f64::consts::PI * TRANSMITTANCE / (4.0 * s.f_number * s.f_number)
        * PHOTONS_PER_LUX_SECOND
        * pixel
        * pixel
        * s.quantum_efficiency
}

/// The relative illumination at a ray `theta` radians off the optical axis.
pub fn vignetting(distortion: &Distortion, theta: f64) -> f64 {
    match distortion {
        Distortion::RadTan { .. } => theta.cos().powi(4),
        Distortion::Equidistant { .. } => {
            if theta < 1e-9 {
                1.0
            } else {
                theta.cos() * theta.sin() / theta
            }
        }
    }
}

/// An exposure: how long, and how much gain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Exposure {
    /// Seconds.
    pub time_s: f64,
    /// Linear gain (1 is none).
    pub gain: f64,
}

impl Exposure {
    /// The gain in decibels (20 log10).
    pub fn gain_db(&self) -> f64 {
        20.0 * self.gain.log10()
    }

    /// Exposure time times gain.
    pub fn product(&self) -> f64 {
        self.time_s * self.gain
    }
}

/// The auto-exposure loop's state: the exposure-gain product chosen last.
#[derive(Clone, Debug)]
pub struct AutoExposure {
    product: Option<f64>,
    limits: ([f64; 2], f64),
    full_well: f64,
}

impl AutoExposure {
    /// A loop for `model`'s sensor, not yet metered.
    pub fn new(model: &CameraModel) -> AutoExposure {
        let s = &model.sensor;
        AutoExposure {
            product: None,
            limits: (s.exposure_s, 10f64.powf(s.max_gain_db / 20.0)),
            full_well: s.full_well_e,
        }
    }

    /// The exposure of the next frame, after metering `signal` (electrons a second per pixel
    /// and channel, the rig's first camera; pixels outside a fisheye's circle are negative and
    /// left out). The first frame is exposed by its own metering.
    pub fn meter(&mut self, signal: &[[f32; 3]]) -> Exposure {
        let ideal = ideal_product(signal, self.full_well);
        let ([lo, hi], max_gain) = self.limits;
        let most = hi * max_gain;
        let ideal = ideal.clamp(lo, most);
        let product = match self.product {
            None => ideal,
            Some(last) => (ideal / last).clamp(0.5, 2.0) * last,
        };
        self.product = Some(product);
        let time_s = product.clamp(lo, hi);
        Exposure {
            time_s,
            gain: (product / time_s).clamp(1.0, max_gain),
        }
    }

    /// The exposure chosen last, if any.
    pub fn current(&self) -> Option<Exposure> {
        let ([lo, hi], max_gain) = self.limits;
        self.product.map(|p| {
            let time_s = p.clamp(lo, hi);
            Exposure {
                time_s,
                gain: (p / time_s).clamp(1.0, max_gain),
            }
        })
    }
}

/// The exposure-gain product that puts the mean signal at [`TARGET_MEAN`] of the full well
/// without the brightest 3 % past [`TARGET_HIGH`] (a histogram of the signal's logarithm, so
/// no sort); `f64::INFINITY` for a black frame.
fn ideal_product(signal: &[[f32; 3]], full_well: f64) -> f64 {
    const BINS: usize = 256;
    // log2 of electrons a second, from 2^-4 to 2^60.
    let bin = |x: f64| (((x.max(1e-30).log2() + 4.0) * 4.0).clamp(0.0, (BINS - 1) as f64)) as usize;
    let mut hist = [0u64; BINS];
    let (mut sum, mut n) = (0.0, 0u64);
    for p in signal {
        if p[0] < 0.0 {
            continue;
        }
        let y = f64::from(p[0].max(p[1]).max(p[2]));
        sum += f64::from(p[0] + p[1] + p[2]) / 3.0;
        n += 1;
        hist[bin(y)] += 1;
    }
    if n == 0 || sum <= 0.0 {
        return f64::INFINITY;
    }
    let mean = sum / n as f64;
    let mut above = 0u64;
    let mut high = 0.0;
    for (i, &h) in hist.iter().enumerate().rev() {
        above += h;
        if above as f64 >= 0.03 * n as f64 {
            high = 2f64.powf(i as f64 / 4.0 - 4.0 + 0.25);
            break;
        }
    }
    let by_mean = TARGET_MEAN * full_well / mean;
    if high > 0.0 {
        by_mean.min(TARGET_HIGH * full_well / high)
    } else {
        by_mean
    }
}

/// The 8-bit value of a linear value in `[0, 1]` (a 2.2 gamma), by a table of 4,096 steps.
#[inline]
pub fn encode(x: f64) -> u8 {
    static TABLE: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
    let t = TABLE.get_or_init(|| {
        (0..=4096)
            .map(|i| ((f64::from(i) / 4096.0).powf(1.0 / 2.2) * 255.0).round() as u8)
            .collect()
    });
    t[(x.clamp(0.0, 1.0) * 4096.0).round() as usize]
}

/// Turns one camera's signal into its 8-bit image (`channels` 3 or 1 a pixel, rows from the
/// top), exposed by `exposure`, its noise keyed by `key` (the seed, frame and camera) and the
/// pixel. Pixels with a negative signal (outside a fisheye's circle) are black.
pub fn expose(
    model: &CameraModel,
    signal: &[[f32; 3]],
    exposure: Exposure,
    key: u64,
    noiseless: bool,
    out: &mut Vec<u8>,
) {
    use rayon::prelude::*;
    let s = &model.sensor;
    let colour = s.colour;
    let channels = if colour { 3 } else { 1 };
    out.resize(signal.len() * channels, 0);
    let scale = exposure.gain / s.full_well_e;
    let read2 = s.read_noise_e * s.read_noise_e;
    let t = exposure.time_s;
    let value = |e: f64, k: u64| {
        let n = if noiseless {
            e
        } else {
            e + (e + read2).sqrt() * noise::normal(key, k)
        };
        encode(n * scale)
    };
    const CHUNK: usize = 4096;
    out.par_chunks_mut(CHUNK * channels)
        .zip(signal.par_chunks(CHUNK))
        .enumerate()
        .for_each(|(c, (out, signal))| {
            for (i, (o, p)) in out.chunks_exact_mut(channels).zip(signal).enumerate() {
                let pixel = (c * CHUNK + i) as u64;
                if p[0] < 0.0 {
                    o.fill(0);
                    continue;
                }
                if colour {
                    for (ch, v) in o.iter_mut().enumerate() {
                        *v = value(f64::from(p[ch]) * t, 3 * pixel + ch as u64);
                    }
                } else {
                    let y = 0.2126 * f64::from(p[0])
                        + 0.7152 * f64::from(p[1])
                        + 0.0722 * f64::from(p[2]);
                    o[0] = value(y * t, 3 * pixel);
                }
            }
        });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_exposure_brings_the_mean_to_its_target_and_moves_by_at_most_twice() {
        let model = super::super::presets::stereo();
        let mut ae = AutoExposure::new(&model);
        // A uniform frame: the product that makes it 18 % of the full well.
        let s = 1e6f32;
        let e = ae.meter(&vec![[s; 3]; 1000]);
        let mean = e.product() * f64::from(s) / model.sensor.full_well_e;
        assert!((mean - 0.18).abs() < 0.01, "{e:?} {mean}");
        // Ten times darker: the next exposure doubles, no more.
        let next = ae.meter(&vec![[s / 10.0; 3]; 1000]);
        assert!((next.product() / e.product() - 2.0).abs() < 1e-9);
        // Black: the longest exposure and the most gain.
        let mut dark = AutoExposure::new(&model);
        let black = dark.meter(&vec![[0.0; 3]; 100]);
        assert_eq!(black.time_s, 0.02);
        assert!((black.gain_db() - 24.0).abs() < 1e-9);
    }

    #[test]
    fn noise_grows_as_the_square_root_of_the_signal() {
        let model = super::super::presets::stereo();
        let exposure = Exposure {
            time_s: 1.0,
            gain: 1.0,
        };
        let n = 20_000;
        let mut out = Vec::new();
        // About 2,000 electrons: a mean of 9 % of the full well.
        let e = 2000.0f32;
        expose(&model, &vec![[e; 3]; n], exposure, 7, false, &mut out);
        let lin: Vec<f64> = out
            .iter()
            .map(|&b| (f64::from(b) / 255.0).powf(2.2) * model.sensor.full_well_e)
            .collect();
        let mean = lin.iter().sum::<f64>() / lin.len() as f64;
        let var = lin.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / lin.len() as f64;
        assert!((mean / 2000.0 - 1.0).abs() < 0.05, "{mean}");
        // Shot and read noise (45 e-), plus the 8-bit steps' own (about 30 e- here).
        assert!(var.sqrt() > 40.0 && var.sqrt() < 70.0, "{}", var.sqrt());
        let mut quiet = Vec::new();
        expose(&model, &vec![[e; 3]; 100], exposure, 7, true, &mut quiet);
        assert!(quiet.iter().all(|&b| b == quiet[0]));
    }
}
