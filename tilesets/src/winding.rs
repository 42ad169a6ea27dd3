//! How a ramp's decline winds away from an exact helix: its radius and its grade vary along
//! it, seeded per ramp, as a real decline's do (it is driven round the ore body, steeper here,
//! flatter there), so a LiDAR's view changes at every step and a scan matcher cannot slide
//! along an exact helix where every view is the same.
//!
//! The planned helix ([`crate::ramp::Helix::plan`]) stays the skeleton: its circle of radius
//! `R`, its climb from floor to floor and the flats and blends at its ends. A [`Winding`]
//! draws the passage in from that circle (never out: the spiral keeps within its block) by up
//! to `inset` metres, in two waves, one of them not a whole number of times a turn (so no two
//! turns are alike), and adds a wave to the floor's height whose slope swings the grade by
//! `swing` of the planned grade either way. The floor's wave repeats once a turn, so the
//! height between one turn and the next is the planned one: the rock between turns is kept.
//! Both fade in after the foot's blend and out before the top's over half a turn (the
//! *taper*), so the leads meet the spiral tangentially on their floors as before.
//!
//! The amplitudes are drawn, then halved until the steepest grade on the drawn line is within
//! `world.ramp_grade` and the turns keep their rock (the plan's own check); the
//! phases are drawn from the world's seed and the ramp's foot cell alone.

use std::f64::consts::{PI, TAU};

use subtgraph_core::rng::WorldRng;

/// How far a ramp winds from its helix (all zero: the exact helix).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Winding {
    /// How far the passage's axis comes in from the planned circle at most, metres.
    pub inset: f64,
    /// Phases of the radius' waves (once a turn and [`SLOW`] times a turn), radians.
    pub radius_phase: [f64; 2],
    /// How far the grade swings either way, as a share of the planned grade.
    pub swing: f64,
    /// Phases of the floor's waves (once and twice a turn), radians.
    pub grade_phase: [f64; 2],
}

/// The radius's second wave, in waves per turn: not a whole number, so that no two turns of a
/// ramp have the same radii.
pub const SLOW: f64 = 0.61;

/// Where a winding acts along a helix: its radius `R` and the stretch `[a, b]` of the climb
/// (metres along) between the blends, with the taper's length.
#[derive(Clone, Copy, Debug)]
pub struct Span {
    /// The planned circle's radius, metres.
    pub radius: f64,
    /// Where the climb's steady part starts and ends, metres along the helix.
    pub climb: [f64; 2],
    /// The planned grade's slope (rise over run).
    pub slope: f64,
}

impl Span {
    /// The taper's length: half a turn, or a third of the steady climb when shorter.
    fn taper_length(&self) -> f64 {
        (PI * self.radius).min((self.climb[1] - self.climb[0]) / 3.0)
    }

    /// The taper at `s`: 0 outside the steady climb, rising smoothly to 1 over half a turn
    /// at both its ends.
    fn taper(&self, s: f64) -> f64 {
        let t = self.taper_length();
        if t <= 0.0 {
            return 0.0;
        }
        let smooth = |x: f64| {
            let x = x.clamp(0.0, 1.0);
            x * x * (3.0 - 2.0 * x)
        };
        smooth((s - self.climb[0]) / t) * smooth((self.climb[1] - s) / t)
    }
}

impl Winding {
    /// The exact helix.
    pub const NONE: Winding = Winding {
        inset: 0.0,
        radius_phase: [0.0; 2],
        swing: 0.0,
        grade_phase: [0.0; 2],
    };

    /// The winding of the ramp whose foot has key `key` in a world seeded `seed`, at its full
    /// drawn amplitude: an inset of 5 to 9 % of the radius, but leaving `pillar` metres of
    /// the circle's radius free, and a swing of 20 to 40 % of the grade.
    pub fn draw(seed: u64, key: u64, radius: f64, pillar: f64) -> Winding {
        let mut rng = WorldRng::new(seed, "ramp-winding", key);
        let inset = (rng.float_in(0.05, 0.09) * radius).min((radius - pillar).max(0.0));
        Winding {
            inset,
            radius_phase: [rng.float_in(0.0, TAU), rng.float_in(0.0, TAU)],
            swing: rng.float_in(0.2, 0.4),
            grade_phase: [rng.float_in(0.0, TAU), rng.float_in(0.0, TAU)],
        }
    }

    /// The same waves at `share` of their amplitudes.
    pub fn scaled(&self, share: f64) -> Winding {
        Winding {
            inset: self.inset * share,
            swing: self.swing * share,
            ..*self
        }
    }

    /// Whether the winding leaves the helix exact.
    pub fn is_none(&self) -> bool {
        self.inset == 0.0 && self.swing == 0.0
    }

    /// How far the passage's axis comes in from the planned circle `s` metres along, metres
    /// (0 up to `inset`).
    pub fn inset_at(&self, span: &Span, s: f64) -> f64 {
        if self.inset == 0.0 {
            return 0.0;
        }
        let a = s / span.radius;
        let [p, q] = self.radius_phase;
        let wave = 0.5 + 0.25 * (a + p).cos() + 0.25 * (SLOW * a + q).cos();
        self.inset * span.taper(s) * wave
    }

    /// What the winding adds to the planned floor's height `s` metres along, metres: a wave
    /// repeating once a turn (but in the tapers) whose slope is at most `swing` of the
    /// planned slope either way.
    pub fn rise_at(&self, span: &Span, s: f64) -> f64 {
        if self.swing == 0.0 {
            return 0.0;
        }
        let a = s / span.radius;
        let [p, q] = self.grade_phase;
        // The wave `w = sin(a + p) + sin(2a + q) / 2` is within [-1.5, 1.5] and its slope
        // within [-2, 2] per radian, and the smoothstep taper's slope at most 1.5 over its
        // length: the added slope `amplitude * (taper' w + taper w')` is at most `swing` of
        // the planned one (in the steady part, where the taper is 1, the swing is 0.74 of
        // that for half a turn's taper).
        let t = span.taper_length();
        let amplitude = self.swing * span.slope / (2.25 / t + 2.0 / span.radius);
        amplitude * span.taper(s) * ((a + p).sin() + 0.5 * (2.0 * a + q).sin())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn span() -> Span {
        Span {
            radius: 16.0,
            climb: [4.0, 400.0],
            slope: 0.1,
        }
    }

    #[test]
    fn the_winding_is_zero_at_both_ends_and_inward_only() {
        let w = Winding::draw(7, 3, 16.0, 5.0);
        assert!(w.inset > 0.7 && w.inset < 1.5, "{w:?}");
        let s = span();
        for end in [0.0, 2.0, 4.0, 400.0, 410.0] {
            assert_eq!(w.inset_at(&s, end), 0.0);
            assert_eq!(w.rise_at(&s, end), 0.0);
        }
        let insets: Vec<f64> = (0..1600)
            .map(|i| w.inset_at(&s, 0.1 * f64::from(i)))
            .collect();
        assert!(insets.iter().all(|&d| (0.0..=w.inset).contains(&d)));
        // It varies: the radius is not the same a turn later.
        let turn = TAU * 16.0;
        assert!((w.inset_at(&s, 40.0) - w.inset_at(&s, 40.0 + turn)).abs() > 1e-3);
    }

    #[test]
    fn the_floor_wave_repeats_each_turn_and_swings_the_grade_within_its_share() {
        let w = Winding::draw(11, 5, 16.0, 5.0);
        let s = span();
        let turn = TAU * 16.0;
        // In the steady climb (beyond the tapers) a turn adds nothing to the height.
        let t = PI * 16.0;
        for x in [4.0 + t, 200.0, 400.0 - t - turn] {
            assert!((w.rise_at(&s, x + turn) - w.rise_at(&s, x)).abs() < 1e-9);
        }
        let h = 0.01;
        let steepest = (0..10_000)
            .map(|i| 50.0 + 0.01 * f64::from(i))
            .map(|x| ((w.rise_at(&s, x + h) - w.rise_at(&s, x)) / h).abs())
            .fold(0.0, f64::max);
        assert!(steepest <= w.swing * s.slope * 1.0001, "{steepest}");
        assert!(steepest >= 0.4 * w.swing * s.slope, "{steepest}");
        // Also in the tapers.
        let all = (0..41_000)
            .map(|i| 0.01 * f64::from(i))
            .map(|x| ((w.rise_at(&s, x + h) - w.rise_at(&s, x)) / h).abs())
            .fold(0.0, f64::max);
        assert!(all <= w.swing * s.slope * 1.0001, "{all}");
    }
}
