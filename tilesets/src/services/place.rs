//! Where the services go: bolt rings and lights where a tile's passage axis crosses a
//! multiple of their spacing in world x or y, the duct, pipes and cable as runs along the
//! axis (see the module above).

use subtgraph_core::grid::Cell;
use subtgraph_core::mesh::{Mesh, Placement, quaternion};
use subtgraph_core::raycast::RayCaster;
use subtgraph_core::tileset::PassageAxis;
use subtgraph_core::vec3::{cross, dot, sub, unit};

use super::{Kit, Services};

/// The lowest a part is mounted above the floor, metres: above a ground robot.
pub const MOUNT: f64 = 1.7;

/// Pipes' and cable's radii, metres.
const PIPE_RADIUS: f64 = 0.075;
const CABLE_RADIUS: f64 = 0.05;
/// Metres between a part and the rock it hangs from (the duct's hangers, the pipes'
/// brackets).
const STAND_OFF: f64 = 0.1;
/// Cosine of the largest turn between two segments of a run still made one cylinder
/// (0.25 degrees: 4 mm over a 1 m segment).
const STRAIGHT: f64 = 0.999_990_5;
/// Metres between the duct's couplings.
const COUPLING_SPACING: f64 = 3.0;
/// Metres a dead end's duct, pipes and cable stop short of its far end.
const DEAD_END_TRIM: f64 = 1.5;

pub(crate) struct Placer<'a> {
    pub services: &'a Services,
    pub drift: super::Drift,
    pub visual: &'a Mesh,
    pub rays: Option<&'a RayCaster>,
    pub seed: u64,
}

/// A horizontal unit direction turned so its larger component is positive, so both tiles
/// at a join, whichever way their axes run, agree on which wall is "the" wall.
fn canonical(d: [f64; 3]) -> Option<[f64; 3]> {
    let h = unit([d[0], d[1], 0.0])?;
    let k = usize::from(h[1].abs() > h[0].abs());
    Some(if h[k] < 0.0 { h.map(|v| -v) } else { h })
}

/// The wall side of a canonical direction: to its right, horizontal.
fn side(d: [f64; 3]) -> [f64; 3] {
    [d[1], -d[0], 0.0]
}

fn lerp(a: [f64; 3], b: [f64; 3], t: f64) -> [f64; 3] {
    [0, 1, 2].map(|k| a[k] + t * (b[k] - a[k]))
}

fn add(a: [f64; 3], b: [f64; 3], s: f64) -> [f64; 3] {
    [0, 1, 2].map(|k| a[k] + s * b[k])
}

fn length(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// Whether a segment climbs too steeply to carry services (a shaft).
fn steep(a: [f64; 3], b: [f64; 3]) -> bool {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    d[2].abs() > 0.5 * length(d) || d[0].hypot(d[1]) < 1e-9
}

/// A number in `[-1, 1)` from the world seed and a bolt's place (splitmix64).
fn jitter(seed: u64, keys: [i64; 5]) -> f64 {
    let mut z = seed;
    for k in keys {
        z = z.wrapping_add(0x9e37_79b9_7f4a_7c15).wrapping_add(k as u64);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
    }
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// Where the segment `a -> b` crosses a multiple of `spacing` in x or y (the larger of its
/// moves): `(multiple, axis, t)`, with `t` in the half-open range that puts a point shared by
/// two segments (or two tiles) in exactly one of them.
fn crossings(a: [f64; 3], b: [f64; 3], spacing: f64) -> Vec<(i64, usize, f64)> {
    let k = usize::from((b[1] - a[1]).abs() > (b[0] - a[0]).abs());
    let d = b[k] - a[k];
    if d.abs() < 1e-12 {
        return Vec::new();
    }
    let (lo, hi) = (a[k].min(b[k]), a[k].max(b[k]));
    let mut out = Vec::new();
    let mut m = (lo / spacing).ceil() as i64;
    while (m as f64) * spacing < hi {
        out.push((m, k, ((m as f64) * spacing - a[k]) / d));
        m += 1;
    }
    out
}

/// The polyline from `line[0]` with its first `trim` metres cut off.
fn trimmed(line: &[[f64; 3]], trim: f64) -> Vec<[f64; 3]> {
    let mut left = trim;
    for (i, w) in line.windows(2).enumerate() {
        let l = length([w[1][0] - w[0][0], w[1][1] - w[0][1], w[1][2] - w[0][2]]);
        if l > left {
            let mut out = vec![lerp(w[0], w[1], left / l)];
            out.extend_from_slice(&line[i + 1..]);
            return out;
        }
        left -= l;
    }
    Vec::new()
}

impl Placer<'_> {
    /// Every placement, tile by tile (raster order), exit by exit.
    pub fn run(&self, axes: &[(Cell, &PassageAxis)]) -> Vec<Placement> {
        let mut out = Vec::new();
        let clear = 0.5 * self.drift.size[0] + 0.3;
        for &(cell, axis) in axes {
            let open: Vec<usize> = (0..4).filter(|&d| !axis.exits[d].is_empty()).collect();
            let through = open.len() == 2 && open[1] == open[0] + 2;
            let dead_end = open.len() == 1;
            for &d in &open {
                let mut line = vec![axis.node];
                line.extend_from_slice(&axis.exits[d]);
                // Junctions and corners: no rings near the node, where drifts cross; the
                // pipes and cable stop there, the duct meets the others' at the node.
                let near_node = if through || dead_end { 0.0 } else { clear };
                self.rings(cell, &line, axis.node, near_node, &mut out);
                let (duct_trim, wall_trim) = if dead_end {
                    (DEAD_END_TRIM, DEAD_END_TRIM)
                } else {
                    (0.0, near_node)
                };
                self.runs(cell, &line, duct_trim, wall_trim, &mut out);
            }
        }
        out
    }

    /// Bolt rings and lights along one exit's line.
    fn rings(
        &self,
        cell: Cell,
        line: &[[f64; 3]],
        node: [f64; 3],
        near_node: f64,
        out: &mut Vec<Placement>,
    ) {
        let Some(rays) = self.rays else { return };
        for (spacing, bolts) in [
            (self.services.bolt_spacing, true),
            (self.services.light_spacing, false),
        ] {
            if spacing <= 0.0 {
                continue;
            }
            for w in line.windows(2) {
                if steep(w[0], w[1]) {
                    continue;
                }
                let Some(d) = canonical([w[1][0] - w[0][0], w[1][1] - w[0][1], 0.0]) else {
                    continue;
                };
                for (m, k, t) in crossings(w[0], w[1], spacing) {
                    let p = lerp(w[0], w[1], t);
                    if (p[0] - node[0]).hypot(p[1] - node[1]) < near_node {
                        continue;
                    }
                    if bolts {
                        self.ring(rays, cell, p, d, [m, k as i64], out);
                    } else {
                        self.light(rays, cell, p, d, out);
                    }
                }
            }
        }
    }

    /// Whether a ray's hit is on the rock of the walls or back.
    fn on_rock(&self, triangle: u32) -> bool {
        let m = self
            .visual
            .materials
            .get(triangle as usize)
            .copied()
            .unwrap_or(self.drift.rock[0]);
        self.drift.rock.contains(&m)
    }

    /// One ring of bolts around the back and upper walls at `p` (on the floor at the axis),
    /// the drift running along `d`.
    fn ring(
        &self,
        rays: &RayCaster,
        cell: Cell,
        p: [f64; 3],
        d: [f64; 3],
        key: [i64; 2],
        out: &mut Vec<Placement>,
    ) {
        let [w, h] = self.drift.size;
        let spacing = self.services.bolt_spacing;
        let s = side(d);
        let radius = (0.5 * w).max(0.4 * h);
        let step = spacing / radius;
        let half = std::f64::consts::FRAC_PI_2;
        let stagger = if key[0].rem_euclid(2) == 1 { 0.5 } else { 0.0 };
        let n = (half / step).floor() as i64 + 1;
        // The other horizontal coordinate, coarsely, tells parallel drifts apart.
        let across = (p[1 - key[1] as usize] / 0.5).round() as i64;
        let level = (p[2] / 1.0).round() as i64;
        for j in -n..=n {
            let phi0 = (j as f64 + stagger) * step;
            if phi0.abs() > half {
                continue;
            }
            let keys = |c: i64| [key[0], key[1], across, level, 8 * j + c];
            let phi = phi0 + 0.03 / radius * jitter(self.seed, keys(0));
            let along = 0.04 * jitter(self.seed, keys(1));
            let dir = add([0.0, 0.0, phi.cos()], s, phi.sin());
            let origin = add(add(p, [0.0, 0.0, 1.0], 0.6 * h), d, along);
            let Some(hit) = rays.cast(origin, dir, 2.0 * radius) else {
                continue;
            };
            let n_rock = hit.normal.map(f64::from);
            if -dot(n_rock, dir) < 0.4 || !self.on_rock(hit.triangle) {
                continue;
            }
            let at = add(origin, dir, hit.t);
            if at[2] - p[2] < MOUNT {
                continue;
            }
            let Some(x) = unit(add(d, n_rock, -dot(d, n_rock))) else {
                continue;
            };
            out.push(Placement {
                prototype: Kit::BOLT,
                cell,
                translation: at,
                rotation: quaternion(x, cross(n_rock, x)),
                scale: [1.0; 3],
            });
        }
    }

    /// A light on the back beside the duct at `p`.
    fn light(
        &self,
        rays: &RayCaster,
        cell: Cell,
        p: [f64; 3],
        d: [f64; 3],
        out: &mut Vec<Placement>,
    ) {
        let [w, h] = self.drift.size;
        let origin = add(add(p, side(d), -0.25 * w), [0.0, 0.0, 1.0], 1.0);
        let Some(hit) = rays.cast(origin, [0.0, 0.0, 1.0], 2.0 * h) else {
            return;
        };
        let at = add(origin, [0.0, 0.0, 1.0], hit.t);
        if !self.on_rock(hit.triangle) || at[2] - 0.14 - p[2] < MOUNT {
            return;
        }
        out.push(Placement {
            prototype: Kit::LIGHT,
            cell,
            translation: at,
            rotation: quaternion(d, cross([0.0, 0.0, 1.0], d)),
            scale: [1.0; 3],
        });
    }

    /// The duct, pipes and cable along one exit's line: the duct with its first
    /// `duct_trim` metres cut off, the wall's runs `wall_trim`.
    fn runs(
        &self,
        cell: Cell,
        line: &[[f64; 3]],
        duct_trim: f64,
        wall_trim: f64,
        out: &mut Vec<Placement>,
    ) {
        let sv = &self.services;
        let (back, wall, height) = (self.drift.back, self.drift.wall, self.drift.size[1]);
        if sv.duct_diameter > 0.0 {
            let r = 0.5 * sv.duct_diameter;
            let v = back - STAND_OFF - r;
            if v - r >= MOUNT {
                self.cylinders(cell, line, duct_trim, Kit::DUCT, 0.0, v, r, out);
            }
        }
        let u = wall - STAND_OFF - PIPE_RADIUS;
        for i in 0..sv.pipes {
            let v = 0.55 * height - 0.25 * f64::from(i);
            if v - PIPE_RADIUS >= MOUNT {
                self.cylinders(cell, line, wall_trim, Kit::PIPE, u, v, PIPE_RADIUS, out);
            }
        }
        if sv.cable_run {
            let v = 0.55 * height + 0.2;
            let u = wall - STAND_OFF - CABLE_RADIUS;
            if v - CABLE_RADIUS >= MOUNT {
                self.cylinders(cell, line, wall_trim, Kit::CABLE, u, v, CABLE_RADIUS, out);
            }
        }
    }

    /// One run of cylinders of radius `r` along `line` (less its first `trim` metres), `u`
    /// metres toward the wall side and `v` above the floor.
    #[allow(clippy::too_many_arguments)]
    fn cylinders(
        &self,
        cell: Cell,
        line: &[[f64; 3]],
        trim: f64,
        prototype: u32,
        u: f64,
        v: f64,
        r: f64,
        out: &mut Vec<Placement>,
    ) {
        let line = if trim > 0.0 {
            trimmed(line, trim)
        } else {
            line.to_vec()
        };
        if line.len() < 2 {
            return;
        }
        // Each vertex's wall side, from the mean of its segments' directions, so segments
        // meet end to end; a side that turns over (the wall taken changes) breaks the run.
        let n = line.len();
        let sides: Vec<Option<[f64; 3]>> = (0..n)
            .map(|i| {
                let a = line[i.saturating_sub(1)];
                let b = line[(i + 1).min(n - 1)];
                canonical([b[0] - a[0], b[1] - a[1], 0.0]).map(side)
            })
            .collect();
        // The offset line, broken where a segment is steep or the wall side turns over.
        let mut pieces: Vec<Vec<[f64; 3]>> = vec![Vec::new()];
        for i in 0..n - 1 {
            let (a, b) = (line[i], line[i + 1]);
            let (Some(sa), Some(sb)) = (sides[i], sides[i + 1]) else {
                pieces.push(Vec::new());
                continue;
            };
            if steep(a, b) || dot(sa, sb) < 0.5 {
                pieces.push(Vec::new());
                continue;
            }
            let a = add(add(a, sa, u), [0.0, 0.0, 1.0], v);
            let b = add(add(b, sb, u), [0.0, 0.0, 1.0], v);
            let piece = pieces.last_mut().expect("one at least");
            if piece.is_empty() {
                piece.push(a);
            }
            // Straight on: the segment lengthens the last one (one cylinder per straight).
            if piece.len() >= 2 {
                let [p, q] = [piece[piece.len() - 2], piece[piece.len() - 1]];
                let (d0, d1) = (unit(sub(q, p)), unit(sub(b, q)));
                if let (Some(d0), Some(d1)) = (d0, d1) {
                    if dot(d0, d1) > STRAIGHT {
                        *piece.last_mut().expect("two") = b;
                        continue;
                    }
                }
            }
            piece.push(b);
        }
        // The duct's couplings: a short wider ring wherever the duct crosses a multiple of
        // their spacing in x or y (world coordinates, as the bolts), its faces across it.
        if prototype == Kit::DUCT {
            for w in pieces.iter().flat_map(|p| p.windows(2)) {
                let Some(x) = unit(sub(w[1], w[0])) else {
                    continue;
                };
                let Some(y) = unit(cross([0.0, 0.0, 1.0], x)) else {
                    continue;
                };
                for (_, _, t) in crossings(w[0], w[1], COUPLING_SPACING) {
                    out.push(Placement {
                        prototype,
                        cell,
                        translation: add(lerp(w[0], w[1], t), x, -0.04),
                        rotation: quaternion(x, y),
                        scale: [0.08, 1.12 * r, 1.12 * r],
                    });
                }
            }
        }
        // Overlap at each end hides the wedge a bend opens between two segments.
        let extend = 0.5 * r;
        for w in pieces.iter().flat_map(|p| p.windows(2)) {
            let (a, b) = (w[0], w[1]);
            let delta = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let len = length(delta);
            let (Some(x), Some(y)) = (unit(delta), unit(cross([0.0, 0.0, 1.0], delta))) else {
                continue;
            };
            out.push(Placement {
                prototype,
                cell,
                translation: add(a, x, -extend),
                rotation: quaternion(x, y),
                scale: [len + 2.0 * extend, r, r],
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_crossing_shared_by_two_segments_is_in_one() {
        let (a, b, c) = ([0.0, 0.0, 0.0], [1.2, 0.1, 0.0], [2.0, 0.2, 0.0]);
        let one: Vec<_> = crossings(a, b, 1.2).into_iter().map(|x| x.0).collect();
        let two: Vec<_> = crossings(b, c, 1.2).into_iter().map(|x| x.0).collect();
        assert_eq!((one, two), (vec![0], vec![1]));
        // Run backwards, the same multiples fall to the other segments.
        let back: Vec<_> = crossings(c, b, 1.2).into_iter().map(|x| x.0).collect();
        assert_eq!(back, vec![1]);
        assert!(crossings(b, a, 1.2).iter().all(|x| x.0 == 0 && x.2 > 0.99));
    }

    #[test]
    fn both_ways_along_a_drift_take_the_same_wall() {
        let e = canonical([1.0, 0.1, 0.0]).unwrap();
        let w = canonical([-1.0, -0.1, 0.0]).unwrap();
        assert_eq!(side(e), side(w));
    }

    #[test]
    fn jitter_is_in_range_and_depends_on_every_key() {
        let a = jitter(7, [1, 0, 3, 0, 5]);
        assert!((-1.0..1.0).contains(&a));
        assert_ne!(a, jitter(7, [1, 0, 3, 0, 6]));
        assert_ne!(a, jitter(8, [1, 0, 3, 0, 5]));
    }
}
