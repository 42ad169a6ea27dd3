//! Sloping floors: a world-wide smooth lift of each level's floor, so passages rise and fall
//! within a level (issue 15 item 3) and stay seamless (the lift is a function of the level and
//! the horizontal world position only, the same in every tile).
//!
//! The lift of level `l` at `(x, y)` is `amp * (1/2 + (sin(k1 . p + f1) + sin(k2 . p + f2)) / 4)`:
//! two plane waves of one wavelength in seeded directions at least 60 degrees apart, with seeded
//! phases per level. It lies in `[0, amp]` (floors only rise above the level's nominal floor, so
//! nothing below it changes) and its gradient is at most `amp * pi / wavelength`, so choosing
//! `amp = tan(grade) * wavelength / pi` bounds the grade in every direction, along every passage.
//! The world's steepest grade is drawn (seeded) from `[tileset] grade = [low, high]`.

use std::f64::consts::PI;

use subtgraph_core::rng::WorldRng;

/// The floor lift of a world.
#[derive(Clone, Debug, PartialEq)]
pub struct Slope {
    /// Greatest lift, metres.
    pub amp: f64,
    /// Wave number, radians per metre.
    k: f64,
    seed: u64,
}

/// One level's waves: unit directions times `k`, and phases.
#[derive(Clone, Copy, Debug)]
pub struct Waves {
    amp: f64,
    k: [[f64; 2]; 2],
    phase: [f64; 2],
}

impl Slope {
    /// Floors whose steepest grade is `grade` degrees, undulating over `wavelength` metres.
    pub fn new(seed: u64, grade: f64, wavelength: f64) -> Self {
        Slope {
            amp: grade.to_radians().tan() * wavelength / PI,
            k: 2.0 * PI / wavelength,
            seed,
        }
    }

    /// Flat floors.
    pub fn flat() -> Self {
        Slope {
            amp: 0.0,
            k: 0.0,
            seed: 0,
        }
    }

    /// The waves of level `level`.
    pub fn level(&self, level: usize) -> Waves {
        let mut rng = WorldRng::new(self.seed, "slope", level as u64);
        let a = rng.float_in(0.0, 2.0 * PI);
        let b = a + rng.float_in(PI / 3.0, 2.0 * PI / 3.0);
        let phase = [rng.float_in(0.0, 2.0 * PI), rng.float_in(0.0, 2.0 * PI)];
        Waves {
            amp: self.amp,
            k: [a, b].map(|t| [self.k * t.cos(), self.k * t.sin()]),
            phase,
        }
    }
}

impl Waves {
    /// Flat: no lift.
    pub const FLAT: Waves = Waves {
        amp: 0.0,
        k: [[0.0; 2]; 2],
        phase: [0.0; 2],
    };

    /// The lift in metres at `(x, y)`, in `[0, amp]`.
    pub fn lift(&self, x: f64, y: f64) -> f64 {
        if self.amp == 0.0 {
            return 0.0;
        }
        let s = |i: usize| (self.k[i][0] * x + self.k[i][1] * y + self.phase[i]).sin();
        self.amp * (0.5 + 0.25 * (s(0) + s(1)))
    }
}

/// The world's steepest grade in degrees, drawn from `[low, high]`.
pub fn draw_grade(seed: u64, [low, high]: [f64; 2]) -> f64 {
    if high <= low {
        return low;
    }
    WorldRng::new(seed, "grade", 0).float_in(low, high)
}

/// Why a `grade = [low, high]` is refused, if it is.
pub fn invalid(grade: [f64; 2]) -> Option<String> {
    let [low, high] = grade;
    if !(low.is_finite() && high.is_finite()) {
        return Some(format!(
            "grade = [{low}, {high}]: both must be numbers of degrees, e.g. grade = [0, 12]"
        ));
    }
    if low < 0.0 {
        return Some(format!(
            "grade = [{low}, {high}]: a grade is an angle from 0 degrees (flat) up; \
             use low >= 0 (floors rise and fall, so a negative grade is a positive one the other way)"
        ));
    }
    if high >= 45.0 {
        return Some(format!(
            "grade = [{low}, {high}]: floors must be under 45 degrees (steeper is a wall, not a \
             floor; a wheeled robot drives about 15); use high < 45"
        ));
    }
    if low > high {
        return Some(format!(
            "grade = [{low}, {high}]: low is above high; write the smaller angle first"
        ));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lift_stays_in_range_and_its_grade_under_the_bound() {
        let s = Slope::new(7, 12.0, 60.0);
        let bound = 12f64.to_radians().tan();
        let mut steepest: f64 = 0.0;
        for level in 0..3 {
            let w = s.level(level);
            for i in 0..200 {
                for j in 0..200 {
                    let (x, y) = (i as f64 * 1.7, j as f64 * 1.3);
                    let h = w.lift(x, y);
                    assert!((0.0..=s.amp).contains(&h));
                    let e = 1e-4;
                    let gx = (w.lift(x + e, y) - w.lift(x - e, y)) / (2.0 * e);
                    let gy = (w.lift(x, y + e) - w.lift(x, y - e)) / (2.0 * e);
                    steepest = steepest.max((gx * gx + gy * gy).sqrt());
                }
            }
        }
        assert!(steepest <= bound * 1.0001, "{steepest} > {bound}");
        assert!(
            steepest > 0.7 * bound,
            "the grade is used: {steepest} of {bound}"
        );
        assert_eq!(Waves::FLAT.lift(3.0, 4.0), 0.0);
    }

    #[test]
    fn bad_grades_are_refused_saying_what_to_change() {
        assert!(invalid([0.0, 12.0]).is_none() && invalid([3.0, 3.0]).is_none());
        assert!(invalid([-1.0, 5.0]).unwrap().contains("low >= 0"));
        assert!(invalid([1.0, 45.0]).unwrap().contains("high < 45"));
        assert!(invalid([6.0, 2.0]).unwrap().contains("smaller angle first"));
        assert!(
            invalid([f64::NAN, 2.0])
                .unwrap()
                .contains("numbers of degrees")
        );
        let g = draw_grade(5, [2.0, 6.0]);
        assert!((2.0..=6.0).contains(&g) && g == draw_grade(5, [2.0, 6.0]));
    }
}
