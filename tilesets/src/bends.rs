//! The centrelines a tile's passage follows in the plane: how a procedural tile set turns the
//! grid's cells into passages that do not show the grid.
//!
//! With [`Bends::Square`] (mines: drifts are driven straight and meet at right angles) every
//! cell joins its centre to the middle of each opening's face, so a corner is a 90-degree kink
//! at the cell centre. With [`Bends::Round`] (caves, lava tubes) a corner cell's passage is a
//! quarter circle of radius half a pitch centred on the cell corner the two openings share: it
//! leaves each face square to it, exactly as the neighbour's passage arrives, so a staircase of
//! cells becomes a smooth S-meander, and the arc keeps to its own cell (its outer wall passes
//! near the cell centre, far from the other cells). A straight cell gets a gentle seeded
//! sideways meander `amp * sin^2(pi t)`, zero with zero slope at both faces. Junctions and
//! dead ends keep the half-corridors: the grid says where they are.
//!
//! Everything here is a function of the cell and the world seed only, so every tile that
//! evaluates a neighbour's passage gets the same curve, and the world stays seamless.

use subtgraph_core::rng::WorldRng;

/// How a procedural passage turns at a corner cell.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Bends {
    /// Quarter-circle corners and meandering straights (caves and lava tubes).
    #[default]
    Round,
    /// Straight half-corridors meeting at the cell centre (mine drifts).
    Square,
}

/// One piece of a passage's centreline in the plane (world metres).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Centreline {
    /// A straight segment from `a` to `b` (a point when they coincide: a dead end's far end).
    Segment {
        /// Start.
        a: [f64; 2],
        /// End.
        b: [f64; 2],
    },
    /// A quarter circle of radius `r` about `c` from `e[0]` to `e[1]`.
    Arc {
        /// Centre (a corner of the cell).
        c: [f64; 2],
        /// Radius.
        r: f64,
        /// Ends, each `r` from `c` along perpendicular axes.
        e: [[f64; 2]; 2],
    },
    /// From `a` to `b`, displaced sideways (to the left of `a -> b`) by `amp * sin^2(pi t)`.
    Meander {
        /// Start.
        a: [f64; 2],
        /// End.
        b: [f64; 2],
        /// Greatest sideways displacement in metres (signed).
        amp: f64,
    },
}

fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

fn norm(a: [f64; 2]) -> f64 {
    dot(a, a).sqrt()
}

impl Centreline {
    /// Horizontal distance from `p` to the centreline (for the meander, to first order in its
    /// slope: exact on its axis and at its faces, where it meets the neighbours).
    pub fn distance(&self, p: [f64; 2]) -> f64 {
        match *self {
            Centreline::Segment { a, b } => {
                subtgraph_core::vec3::segment_distance_squared(p, a, b).sqrt()
            }
            Centreline::Arc { c, r, e } => {
                let w = sub(p, c);
                if dot(w, sub(e[0], c)) >= 0.0 && dot(w, sub(e[1], c)) >= 0.0 {
                    (norm(w) - r).abs()
                } else {
                    norm(sub(p, e[0])).min(norm(sub(p, e[1])))
                }
            }
            Centreline::Meander { a, b, amp } => {
                let d = sub(b, a);
                let len = norm(d);
                let q = sub(p, a);
                let t = dot(q, d) / (len * len);
                if !(0.0..=1.0).contains(&t) {
                    return norm(q).min(norm(sub(p, b)));
                }
                let lateral = (d[0] * q[1] - d[1] * q[0]) / len;
                let s = (std::f64::consts::PI * t).sin();
                let slope =
                    amp * std::f64::consts::PI * (2.0 * std::f64::consts::PI * t).sin() / len;
                (lateral - amp * s * s).abs() / (1.0 + slope * slope).sqrt()
            }
        }
    }

    /// The point at parameter `t` in `[0, 1]` and the unit direction of travel there.
    pub fn at(&self, t: f64) -> ([f64; 2], [f64; 2]) {
        match *self {
            Centreline::Segment { a, b } => {
                let d = sub(b, a);
                let len = norm(d).max(1e-9);
                ([a[0] + t * d[0], a[1] + t * d[1]], [d[0] / len, d[1] / len])
            }
            Centreline::Arc { c, r, e } => {
                let (u0, u1) = (sub(e[0], c), sub(e[1], c));
                let th = t * std::f64::consts::FRAC_PI_2;
                let (s, k) = th.sin_cos();
                (
                    [c[0] + k * u0[0] + s * u1[0], c[1] + k * u0[1] + s * u1[1]],
                    [(-s * u0[0] + k * u1[0]) / r, (-s * u0[1] + k * u1[1]) / r],
                )
            }
            Centreline::Meander { a, b, amp } => {
                let d = sub(b, a);
                let len = norm(d);
                let n = [-d[1] / len, d[0] / len];
                let s = (std::f64::consts::PI * t).sin();
                let off = amp * s * s;
                let slope = amp * std::f64::consts::PI * (2.0 * std::f64::consts::PI * t).sin();
                let dir = [d[0] + n[0] * slope, d[1] + n[1] * slope];
                let l = norm(dir);
                (
                    [a[0] + t * d[0] + n[0] * off, a[1] + t * d[1] + n[1] * off],
                    [dir[0] / l, dir[1] / l],
                )
            }
        }
    }

    /// The unit direction of a straight segment (`None` for a point, an arc or a meander).
    pub fn direction(&self) -> Option<[f64; 2]> {
        match *self {
            Centreline::Segment { a, b } => {
                let d = sub(b, a);
                let len = norm(d);
                (len > 0.0).then(|| [d[0] / len, d[1] / len])
            }
            _ => None,
        }
    }

    /// How far from the middle of its cell the centreline point nearest `p` lies, metres
    /// along the passage as if it ran straight: 0 at the cell's middle, half a pitch at a face.
    /// A squeeze (`tilesets/src/chambers.rs`) is laid out along it, so it returns to the full
    /// passage before the faces whichever way the centreline bends. A half-corridor starts at
    /// the middle; an arc or meander is measured by its angle or parameter, scaled to half a
    /// pitch.
    pub fn from_middle(&self, p: [f64; 2]) -> f64 {
        match *self {
            Centreline::Segment { a, b } => {
                let d = sub(b, a);
                let len = norm(d);
                if len > 0.0 {
                    (dot(sub(p, a), d) / len).clamp(0.0, len)
                } else {
                    0.0
                }
            }
            Centreline::Arc { c, r, e } => {
                let w = sub(p, c);
                let (u0, u1) = (sub(e[0], c), sub(e[1], c));
                let th = dot(w, u1)
                    .atan2(dot(w, u0))
                    .clamp(0.0, std::f64::consts::FRAC_PI_2);
                (th - std::f64::consts::FRAC_PI_4).abs() / std::f64::consts::FRAC_PI_4 * r
            }
            Centreline::Meander { a, b, .. } => {
                let d = sub(b, a);
                let len = norm(d);
                let t = (dot(sub(p, a), d) / (len * len)).clamp(0.0, 1.0);
                (t - 0.5).abs() * len
            }
        }
    }

    /// The box `(lo, hi)` holding the centreline.
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        let pts: Vec<[f64; 2]> = match *self {
            Centreline::Segment { a, b } => vec![a, b],
            Centreline::Arc { c, e, .. } => {
                vec![c, [e[0][0] + e[1][0] - c[0], e[0][1] + e[1][1] - c[1]]]
            }
            Centreline::Meander { a, b, amp } => {
                let d = sub(b, a);
                let len = norm(d);
                let n = [-d[1] / len * amp, d[0] / len * amp];
                vec![a, b, [a[0] + n[0], a[1] + n[1]], [b[0] + n[0], b[1] + n[1]]]
            }
        };
        let lo = [0, 1].map(|k| pts.iter().map(|p| p[k]).fold(f64::MAX, f64::min));
        let hi = [0, 1].map(|k| pts.iter().map(|p| p[k]).fold(f64::MIN, f64::max));
        (lo, hi)
    }
}

/// The centrelines of a cell centred at `centre` whose openings' face midpoints are `ends`
/// (opposite faces are `2 * half` apart): for round bends a corner is one arc and a straight
/// one meander of amplitude `meander` (signed metres); anything else, and every cell with
/// square bends, is half-corridors from the centre (a dead end one rounded at the centre).
pub fn centrelines(
    centre: [f64; 2],
    ends: &[[f64; 2]],
    bends: Bends,
    meander: f64,
) -> Vec<Centreline> {
    if bends == Bends::Round && ends.len() == 2 {
        let (a, b) = (ends[0], ends[1]);
        let mid = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
        if norm(sub(mid, centre)) < 1e-9 * (1.0 + norm(sub(a, b))) {
            return vec![Centreline::Meander { a, b, amp: meander }];
        }
        let c = [a[0] + b[0] - centre[0], a[1] + b[1] - centre[1]];
        return vec![Centreline::Arc {
            c,
            r: norm(sub(a, c)),
            e: [a, b],
        }];
    }
    if ends.is_empty() {
        return vec![Centreline::Segment {
            a: centre,
            b: centre,
        }];
    }
    ends.iter()
        .map(|&b| Centreline::Segment { a: centre, b })
        .collect()
}

/// The seeded sideways meander of the straight cell `key`: up to `amplitude` metres either way.
pub fn meander(seed: u64, key: u64, amplitude: f64) -> f64 {
    if amplitude <= 0.0 {
        return 0.0;
    }
    WorldRng::new(seed, "meander", key).float_in(-amplitude, amplitude)
}

#[cfg(test)]
mod tests {
    use super::*;

    const HALF: f64 = 12.5;

    fn heading_change(line: &Centreline, steps: usize) -> f64 {
        let mut worst: f64 = 0.0;
        for i in 0..steps {
            let (_, d0) = line.at(i as f64 / steps as f64);
            let (_, d1) = line.at((i + 1) as f64 / steps as f64);
            worst = worst.max(dot(d0, d1).clamp(-1.0, 1.0).acos());
        }
        worst
    }

    #[test]
    fn a_corner_is_a_quarter_circle_from_face_to_face_square_to_both() {
        // Openings east and north of a cell at the origin.
        let (e, n) = ([HALF, 0.0], [0.0, HALF]);
        let lines = centrelines([0.0, 0.0], &[e, n], Bends::Round, 0.0);
        let [line] = lines[..] else { panic!() };
        let (p0, d0) = line.at(0.0);
        let (p1, d1) = line.at(1.0);
        assert!(norm(sub(p0, e)) < 1e-9 && norm(sub(p1, n)) < 1e-9);
        // Leaves the east face heading west (into the cell), arrives at the north face heading
        // north: square to each face, as the neighbours' passages are.
        assert!(d0[0].abs() > 0.999 && d1[1] > 0.999, "{d0:?} {d1:?}");
        // Smooth: the heading turns by pi/2 over an arc of length pi/2 * HALF.
        assert!(heading_change(&line, 100) < 0.02);
        // The distance is zero on the arc, half a pitch at the corner, and stays in the cell.
        for t in [0.0, 0.3, 0.5, 1.0] {
            assert!(line.distance(line.at(t).0) < 1e-9);
        }
        assert!((line.distance([HALF, HALF]) - HALF).abs() < 1e-9);
        let (lo, hi) = line.bounds();
        assert!(lo[0] >= 0.0 && lo[1] >= 0.0 && hi[0] <= HALF && hi[1] <= HALF);
    }

    #[test]
    fn a_straight_meanders_and_meets_its_faces_square() {
        let (w, e) = ([-HALF, 3.0], [HALF, 3.0]);
        let lines = centrelines([0.0, 3.0], &[w, e], Bends::Round, 2.0);
        let [line] = lines[..] else { panic!() };
        for t in [0.0, 1.0] {
            let (p, d) = line.at(t);
            assert!(p[1] == 3.0 && d[1].abs() < 1e-9 && d[0] > 0.0);
        }
        let (mid, _) = line.at(0.5);
        assert!((mid[1] - 5.0).abs() < 1e-9);
        assert!(line.distance(mid) < 1e-9 && (line.distance([0.0, 3.0]) - 2.0).abs() < 1e-9);
        assert!(line.distance([-HALF - 1.0, 3.0]) == 1.0);
    }

    #[test]
    fn square_bends_and_junctions_keep_half_corridors() {
        let ends = [[HALF, 0.0], [0.0, HALF]];
        let lines = centrelines([0.0, 0.0], &ends, Bends::Square, 0.0);
        assert_eq!(lines.len(), 2);
        assert!(
            lines
                .iter()
                .all(|l| matches!(l, Centreline::Segment { .. }))
        );
        let t = centrelines(
            [0.0, 0.0],
            &[ends[0], ends[1], [-HALF, 0.0]],
            Bends::Round,
            1.0,
        );
        assert_eq!(t.len(), 3);
        let dead = centrelines([1.0, 2.0], &[], Bends::Round, 1.0);
        assert!(dead[0].distance([1.0, 5.0]) == 3.0);
    }

    #[test]
    fn from_middle_runs_from_the_cell_middle_to_half_a_pitch_at_each_face() {
        let half = 12.5;
        let centre = [0.0, 0.0];
        let (east, north) = ([half, 0.0], [0.0, half]);
        let west = [-half, 0.0];
        for line in [
            centrelines(centre, &[east, north], Bends::Round, 0.0)[0],
            centrelines(centre, &[west, east], Bends::Round, 2.0)[0],
            centrelines(centre, &[east, north], Bends::Square, 0.0)[0],
        ] {
            let (start, _) = line.at(0.0);
            let (end, _) = line.at(1.0);
            assert!((line.from_middle(end) - half).abs() < 1e-9, "{line:?}");
            if !matches!(line, Centreline::Segment { .. }) {
                let (mid, _) = line.at(0.5);
                assert!(line.from_middle(mid).abs() < 1e-9, "{line:?}");
                assert!((line.from_middle(start) - half).abs() < 1e-9, "{line:?}");
            } else {
                assert!(line.from_middle(start).abs() < 1e-9);
            }
        }
    }
}
