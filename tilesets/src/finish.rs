//! How a driven passage's walls and back are finished: blasted rock or sprayed shotcrete
//! (`[tileset] finish`, mine tile set), as relief added to the field in world coordinates.
//!
//! **Why.** A drift cut by drill and blast is not a prism: each blast round (3-4 m of advance)
//! leaves the rock broken back beyond the design profile (overbreak), most at the round's
//! face end where the perimeter holes are angled out ("lookouts"), so the walls step back in
//! where the next round starts; between the steps the rock breaks along its joints, decimetres
//! deep. A LiDAR in such a drift sees those steps and that relief along the drift, which is
//! what lets scan registration hold its position; in a smooth prism it slides (47 % of the
//! mine's scans were degenerate with relief of 1.5 cm). Shotcrete (sprayed concrete) covers
//! the rock with a smooth, lumpy skin: low relief, no steps.
//!
//! The relief is a function of world position and of the drift's direction alone, so two
//! tiles evaluating a point on their shared face compute the same number (seamless joins).
//! The floor is left as it is: the field scales relief by the height above the floor, as for
//! every tile set, and adds it to the walls and back of a passage's section only, never to its
//! floor (`crate::field`'s `Relieved`, [`Profile::walls`](crate::passage::Profile::walls)), so
//! the lattice's interpolation between a floor point and one above it cannot carry the relief
//! into the floor, and a robot drives on what it always did.
//!
//! Half-barrel marks (the 45 mm drill-hole remnants) and welded mesh panels (5.6 mm wire on a
//! 100 mm grid) are narrower than the lattice of any practical `[tileset] resolution` (at the
//! default 24 cells per 20 m pitch a cell is 0.83 m), so marching tetrahedra cannot hold them,
//! and a LiDAR sees the rock through the mesh. They are painted: rock from
//! [`Passage::mesh_from`](crate::passage::Passage::mesh_from) above the floor up takes the
//! `meshed-wall` material, whose texture shows the wire grid, and the blasted wall below it
//! shows the marks (`crate::textures::rock`, `Look::Mesh` and `Look::Blasted`).

use crate::noise::Noise;

/// The finish of a passage's walls and back.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Finish {
    /// The style's own wall relief (`roughness`, `roughness_scale`): today's walls.
    #[default]
    Plain,
    /// Drill-and-blast rock: joint relief and overbreak steps round by round.
    Blasted {
        /// Relief RMS, metres.
        rms: f64,
        /// Length of one blast round along the drift, metres.
        round: f64,
    },
    /// Sprayed concrete: smooth, lumpy, low relief.
    Shotcrete {
        /// Relief RMS, metres.
        rms: f64,
    },
}

/// Default relief RMS of blasted walls, metres (`[tileset] relief`, given in cm).
pub const BLASTED_RMS: f64 = 0.15;
/// Default relief RMS of shotcrete, metres.
pub const SHOTCRETE_RMS: f64 = 0.04;
/// Default length of a blast round, metres: a 3.5 m round of a jumbo's 4 m holes.
pub const ROUND: f64 = 3.5;

/// Greatest relief as a multiple of its RMS: relief is clamped there, and the field and the
/// fit checks take it as the wall relief's amplitude (`Passage::roughness`).
pub const PEAK: f64 = 2.5;

/// The noises the finishes draw from, seeded per world.
pub struct FinishNoise {
    joints: Noise,
    rounds: Noise,
}

/// RMS of [`Noise::fbm`] with 3 octaves over many points (measured by the test
/// `blasted_relief_has_the_rms_asked_for`), to scale it to unit RMS.
const FBM3_RMS: f64 = 0.22;
/// RMS of [`Noise::fbm`] with 2 octaves.
const FBM2_RMS: f64 = 0.24;

impl FinishNoise {
    /// The noises of the world with `seed`.
    pub fn new(seed: u64) -> Self {
        FinishNoise {
            joints: Noise::new(seed, "finish-joints"),
            rounds: Noise::new(seed, "finish-rounds"),
        }
    }
}

impl Finish {
    /// Whether the finish replaces the style's relief.
    pub fn is_plain(&self) -> bool {
        matches!(self, Finish::Plain)
    }

    /// The greatest relief, metres (`None` for [`Finish::Plain`]: the style's roughness).
    pub fn peak(&self) -> Option<f64> {
        match *self {
            Finish::Plain => None,
            Finish::Blasted { rms, .. } | Finish::Shotcrete { rms } => Some(PEAK * rms),
        }
    }

    /// The part of the relief that does not depend on the drift's direction (joints, lumps),
    /// metres, positive into the passage (more rock).
    pub fn texture(&self, n: &FinishNoise, p: [f64; 3]) -> f64 {
        match *self {
            Finish::Plain => 0.0,
            // Joint-bounded blocks a metre or so across, with their smaller breaks; 60 % of
            // the variance (the rest is the rounds' overbreak).
            Finish::Blasted { rms, .. } => {
                let s = 1.0 / 1.1;
                rms * 0.77 * n.joints.fbm(p[0] * s, p[1] * s, p[2] * s, 3) / FBM3_RMS
            }
            // Lumps of sprayed concrete over the rock, a couple of metres across.
            Finish::Shotcrete { rms } => {
                let s = 1.0 / 2.2;
                rms * n.joints.fbm(p[0] * s, p[1] * s, p[2] * s, 2) / FBM2_RMS
            }
        }
    }

    /// The overbreak of the blast round at `p` in a drift running along `dir` (a unit
    /// vector in the plane), metres, positive into the passage: a sawtooth along the drift
    /// (the walls break back further toward each round's face and step in where the next
    /// round starts) plus a depth drawn per round. Zero for other finishes.
    pub fn overbreak(&self, n: &FinishNoise, p: [f64; 3], dir: [f64; 2]) -> f64 {
        let Finish::Blasted { rms, round } = *self else {
            return 0.0;
        };
        // Distance along the drift in world coordinates: the same for every tile along a
        // straight drift, whichever way its centreline was drawn.
        let (ax, ay) = (dir[0].abs(), dir[1].abs());
        let s = p[0] * ax + p[1] * ay;
        // Which of the two horizontal axes the drift follows, and where it lies across.
        let across = p[0] * ay - p[1] * ax;
        let t = s / round;
        let k = t.floor();
        let f = t - k;
        // The round's own depth of overbreak, one value per round and drift line.
        let depth = n.rounds.at(k + 0.5, across / 7.0 + 0.5, 0.5);
        // Sawtooth of zero mean and RMS 1/sqrt(12) * 2 = 0.577 over a round; the depth's
        // RMS is about 0.3. Together 40 % of the variance.
        let saw = 0.5 - f;
        rms * 0.63 * (saw * 2.0 + 1.2 * depth) / 0.68
    }

    /// The relief at `p`, clamped to the finish's peak: `texture` plus, where the drift's
    /// direction is known (a corridor), its `overbreak`.
    pub fn relief(&self, texture: f64, n: &FinishNoise, p: [f64; 3], dir: Option<[f64; 2]>) -> f64 {
        let Some(peak) = self.peak() else {
            return 0.0;
        };
        let o = dir.map_or(0.0, |d| self.overbreak(n, p, d));
        (texture + o).clamp(-peak, peak)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rms_of(f: impl Fn([f64; 3]) -> f64) -> f64 {
        let mut sum = 0.0;
        let n = 40_000;
        for i in 0..n {
            let i = i as f64;
            let p = [
                (i * 0.7548776662).fract() * 300.0,
                (i * 0.5698402910).fract() * 300.0,
                (i * 0.3819660113).fract() * 30.0,
            ];
            let v = f(p);
            sum += v * v;
        }
        (sum / n as f64).sqrt()
    }

    #[test]
    fn blasted_relief_has_the_rms_asked_for() {
        let n = FinishNoise::new(7);
        let b = Finish::Blasted {
            rms: 0.15,
            round: ROUND,
        };
        let rms = rms_of(|p| b.relief(b.texture(&n, p), &n, p, Some([1.0, 0.0])));
        assert!((rms - 0.15).abs() < 0.02, "blasted relief RMS {rms}");
        let texture = rms_of(|p| b.texture(&n, p));
        assert!(
            (0.09..0.13).contains(&texture),
            "joint relief RMS {texture}"
        );
        let s = Finish::Shotcrete { rms: 0.04 };
        let rms = rms_of(|p| s.relief(s.texture(&n, p), &n, p, Some([0.0, 1.0])));
        assert!((rms - 0.04).abs() < 0.008, "shotcrete RMS {rms}");
    }

    #[test]
    fn overbreak_steps_between_rounds_and_is_the_same_either_way_along_the_drift() {
        let n = FinishNoise::new(3);
        let b = Finish::Blasted {
            rms: 0.15,
            round: 3.5,
        };
        let at = |x: f64| b.overbreak(&n, [x, 12.0, 2.0], [1.0, 0.0]);
        // Across a round boundary the wall steps by most of the sawtooth.
        let step = at(7.0 + 1e-6) - at(7.0 - 1e-6);
        assert!(step > 0.1, "step {step}");
        // Within a round it changes smoothly.
        assert!((at(8.0) - at(8.01)).abs() < 0.01);
        // A centreline drawn the other way gives the same wall.
        assert_eq!(at(5.0), b.overbreak(&n, [5.0, 12.0, 2.0], [-1.0, 0.0]));
        assert_eq!(Finish::Plain.relief(0.3, &n, [0.0; 3], None), 0.0);
    }
}
