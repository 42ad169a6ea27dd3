//! Particles in the air (dust, fog, mist) as a LiDAR sees them, after Hahner et al.'s fog
//! model ("Fog Simulation on Real LiDAR Point Clouds for 3D Object Detection in Adverse
//! Weather", ICCV 2021, and its published code), with the speckle of a random cloud added so
//! that particle returns come as a share rather than all or nothing.
//!
//! **Hahner's model.** A pulse of half-power width `tau_h` crosses a medium of extinction
//! coefficient `alpha` (1/m) and backscatter coefficient `beta` (1/(m sr)). The rock (a *hard
//! target* of Lambertian reflectance `rho` at range `R0`, whose backscatter is `beta0 = rho /
//! pi`) returns
//!
//! ```text
//! P_hard = C (beta0 xi(R0) / R0^2) exp(-2 alpha R0)
//! ```
//!
//! (the clear-air return attenuated both ways), and the particles (a *soft target*, spread
//! along the beam) return, at the receiver's range `R`,
//!
//! ```text
//! P_soft(R) = C beta  integral over t in [0, 2 tau_h] of
//!             sin^2(pi t / (2 tau_h)) exp(-2 alpha r) xi(r) / r^2 dt,   r = R - c t / 2,
//! ```
//!
//! where `xi(r)` is the overlap of the transmitter's beam with the receiver's field of view
//! (0 before `R1`, rising linearly to 1 at `R2`). The sensor reports the strongest echo: where
//! the soft target's peak beats the attenuated hard return, the point is replaced by one at
//! the soft target's peak range. For a pulse shorter than the distances over which
//! `exp(-2 alpha r) xi(r) / r^2` changes, the integral is `tau_h` times the integrand at the
//! pulse's centre, so a range bin of length `l = c tau_h / 2` holds
//!
//! ```text
//! m(r) = beta l xi(r) exp(-2 tau(r)) / r^2        (tau(r): the optical depth to r)
//! ```
//!
//! against the hard target's `h = (rho / pi) xi(R0) exp(-2 tau(R0)) / R0^2`, both in units of
//! the emitted power times the receiver's constant. Unlike a fog bank, which Hahner treats as
//! homogeneous, a cloud here may fill only part of a ray (a bank over a junction, the dust
//! behind the platform): `tau` is integrated along the ray through whatever media it crosses.
//!
//! **Speckle.** A bin's echo is the sum of many particles' echoes with random phases, so its
//! power is exponentially distributed about `m(r)` (fully developed speckle, Goodman,
//! "Speckle Phenomena in Optics", 2007, ch. 3): each bin draws `E m(r)`, `E ~ Exp(1)`, from the
//! ray's hash. The strongest echo wins if it reaches the detection floor `s_min`. So a ray
//! whose rock returns `h` gives a particle return with probability
//! `1 - prod_k (1 - exp(-max(h, s_min) / m_k))`, over the bins `k` between the sensor and the
//! rock: more often in denser air, from darker or farther rock.
//!
//! **Detection floor.** `s_min` is the signal of a 10 % Lambertian target at 40 % of the
//! model's farthest range (48 m for an OS1's 120 m, the datasheet's range at 10 %
//! reflectivity being about that): returns weaker than it are lost. Only rays that a condition
//! touches are held to it; in clear air the model stays what it is (every surface in range
//! returns), so `--conditions none` changes nothing.

use crate::noise;

/// Speed of light, m/s.
pub const LIGHT: f64 = 299_792_458.0;
/// The pulse's half-power width, seconds: Hahner's 20 ns.
pub const TAU_H: f64 = 20e-9;
/// The range bin of one pulse, metres: `c tau_h / 2`, 3 m.
pub const BIN: f64 = LIGHT * TAU_H / 2.0;
/// How far beyond the nearest range the receiver's view covers the beam fully, metres.
pub const OVERLAP: f64 = 1.0;
/// The largest speckle factor a hash draws (`-ln` of the smallest uniform), so a bin whose
/// mean times this cannot beat the best echo so far need not be drawn.
const SPECKLE_MAX: f64 = 37.5;

/// The particles of one kind in the air: how they dim and scatter light.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Particles {
    /// Extinction coefficient, 1/m.
    pub alpha: f64,
    /// Backscatter coefficient, 1/(m sr).
    pub beta: f64,
}

impl Particles {
    /// The particles of mass concentration `mg_m3` (mg per cubic metre) of spheres of radius
    /// `radius_um` (micrometres) and material density `g_cm3`, with lidar ratio
    /// (extinction over backscatter) `lidar_ratio_sr`. Particles much larger than the
    /// wavelength (865 nm) have an extinction efficiency of 2, so `alpha = 3 Q C / (4 rho_p
    /// r)`.
    pub fn of_mass(mg_m3: f64, radius_um: f64, g_cm3: f64, lidar_ratio_sr: f64) -> Particles {
        let c = mg_m3 * 1e-6; // kg/m^3
        let rho = g_cm3 * 1e3; // kg/m^3
        let r = radius_um * 1e-6; // m
        let alpha = 3.0 * 2.0 * c / (4.0 * rho * r);
        Particles {
            alpha,
            beta: alpha / lidar_ratio_sr,
        }
    }

    /// The meteorological optical range, metres: where a beam keeps 5 % (`ln 20 / alpha`).
    pub fn visibility_m(&self) -> f64 {
        20f64.ln() / self.alpha
    }
}

/// The sensor's side of the model.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Receiver {
    /// Where the receiver starts to see the beam (the model's nearest range), metres.
    pub r1: f64,
    /// Where it sees all of it, metres.
    pub r2: f64,
    /// The range bin, metres.
    pub bin_m: f64,
    /// The detection floor, in units of `rho / (pi r^2)`.
    pub s_min: f64,
}

impl Receiver {
    /// The receiver of a LiDAR whose returns span `near` to `far` metres.
    pub fn of_range(near: f64, far: f64) -> Receiver {
        let r10 = 0.4 * far;
        Receiver {
            r1: near,
            r2: near + OVERLAP,
            bin_m: BIN,
            s_min: 0.1 / (std::f64::consts::PI * r10 * r10),
        }
    }

    /// The beam's overlap with the receiver's view at range `r`.
    pub fn xi(&self, r: f64) -> f64 {
        ((r - self.r1) / (self.r2 - self.r1)).clamp(0.0, 1.0)
    }

    /// A hard target's signal: reflectance `rho` (times the incidence cosine) at range `r`
    /// behind optical depth `tau`.
    pub fn hard(&self, rho: f64, r: f64, tau: f64) -> f64 {
        rho / std::f64::consts::PI * self.xi(r) * (-2.0 * tau).exp() / (r * r).max(1e-9)
    }
}

/// A stretch of a ray inside media: from `a` to `b` metres, with the media's coefficients
/// summed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    /// Where it starts along the ray, metres.
    pub a: f64,
    /// Where it ends.
    pub b: f64,
    /// Extinction there, 1/m.
    pub alpha: f64,
    /// Backscatter there, 1/(m sr).
    pub beta: f64,
    /// Which return kind its echoes are labelled (the densest medium's).
    pub kind: u8,
}

/// The optical depth from the sensor to `r` through `spans` (sorted, not overlapping).
pub fn depth(spans: &[Span], r: f64) -> f64 {
    spans
        .iter()
        .take_while(|s| s.a < r)
        .map(|s| s.alpha * (s.b.min(r) - s.a))
        .sum()
}

/// The strongest particle echo of a ray, if one beats `floor` (the hard return's signal or
/// the detection floor, whichever is larger): its range (the bin's centre moved within the
/// bin), its signal and its kind. `end` is where the ray stops (its rock, or its farthest
/// range); `seed` and `key` make the draws the ray's own.
pub fn strongest_echo(
    spans: &[Span],
    rx: &Receiver,
    end: f64,
    floor: f64,
    seed: u64,
    key: u64,
) -> Option<(f64, f64, u8)> {
    let beta_max = spans.iter().map(|s| s.beta).fold(0.0, f64::max);
    if beta_max <= 0.0 {
        return None;
    }
    let mut best: Option<(f64, f64, u8)> = None;
    let mut best_signal = floor;
    let mut tau = 0.0;
    let mut si = 0;
    let mut k = 0u64;
    loop {
        let r = rx.r1 + (k as f64 + 0.5) * rx.bin_m;
        if r >= end {
            break;
        }
        // Beyond the overlap the bins' means only fall: stop once none could win.
        if r >= rx.r2 && SPECKLE_MAX * beta_max * rx.bin_m / (r * r) < best_signal {
            break;
        }
        while si < spans.len() && spans[si].b <= r {
            si += 1;
        }
        if si < spans.len() && spans[si].a <= r {
            let s = &spans[si];
            tau = depth(spans, r);
            let mean = s.beta * rx.bin_m * rx.xi(r) * (-2.0 * tau).exp() / (r * r);
            if SPECKLE_MAX * mean > best_signal {
                let e = -noise::uniform(seed, key ^ (k << 40) ^ 0x5eed).ln();
                let signal = e * mean;
                if signal > best_signal {
                    let u = noise::uniform(seed, key ^ (k << 40) ^ 0xb1);
                    let at = (r + (u - 0.5) * rx.bin_m).clamp(rx.r1, end);
                    best = Some((at, signal, s.kind));
                    best_signal = signal;
                }
            }
        } else if si >= spans.len() {
            break;
        }
        k += 1;
    }
    let _ = tau;
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hahners_fog_coefficients_give_his_lidar_ratio_and_visibility() {
        // Hahner: alpha = ln(20) / MOR, beta = 0.046 / MOR.
        let p = Particles::of_mass(100.0, 10.0, 1.0, 20f64.ln() / 0.046);
        assert!((p.beta * p.visibility_m() - 0.046).abs() < 1e-12);
        // 100 mg of 10 um droplets a cubic metre: alpha 0.015 / m, 200 m of visibility.
        assert!((p.alpha - 0.015).abs() < 1e-12, "{p:?}");
    }

    #[test]
    fn particle_echoes_come_as_often_as_the_speckle_model_says() {
        // A uniform medium from the sensor to a dark wall at 12 m.
        let rx = Receiver::of_range(0.8, 120.0);
        let p = Particles::of_mass(150.0, 5.0, 2.5, 40.0);
        let spans = [Span {
            a: 0.0,
            b: 12.0,
            alpha: p.alpha,
            beta: p.beta,
            kind: 1,
        }];
        let h = rx.hard(0.1, 12.0, depth(&spans, 12.0));
        let floor = h.max(rx.s_min);
        let mut expected_miss = 1.0;
        let mut k = 0;
        loop {
            let r = rx.r1 + (k as f64 + 0.5) * rx.bin_m;
            if r >= 12.0 {
                break;
            }
            let m = p.beta * rx.bin_m * rx.xi(r) * (-2.0 * depth(&spans, r)).exp() / (r * r);
            expected_miss *= 1.0 - (-floor / m).exp();
            k += 1;
        }
        let n = 20_000;
        let won = (0..n)
            .filter(|&i| strongest_echo(&spans, &rx, 12.0, floor, 7, i).is_some())
            .count();
        let share = won as f64 / n as f64;
        let expected = 1.0 - expected_miss;
        assert!(expected > 0.05 && expected < 0.95, "{expected}");
        assert!(
            (share - expected).abs() < 0.015,
            "{share} against {expected}"
        );
    }
}
