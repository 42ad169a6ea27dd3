//! Map coverage and map error on the world's free-space voxels
//! (`ground_truth/free_space.npy`, decided exactly by ray parity against the collision surface
//! when the world was made).
//!
//! - A free voxel is **covered** when a mapped point lies within `radius` of it: in a voxel at
//!   most `round(radius / voxel)` voxels away along each axis (a cube, at voxel resolution;
//!   `radius = 0` counts the voxels holding a point). Coverage is the share of free voxels
//!   covered, per level, per graph edge (the voxels over its corridor cells between its two
//!   nodes) and per node (its cell).
//! - A point is a **map error** when it is farther than `tolerance` from the collision
//!   surface, at voxel resolution: its voxel is not within `ceil(tolerance / voxel) + 1`
//!   voxels (along each axis) of both a free and a rock voxel (the one more because a point on
//!   the surface can be a voxel from the centres on either side), or it lies outside the grid.
//!
//! The voxels are bits in 64-bit words, one run of words per `(z, y)` row, so growing a set by
//! a radius is a few shifts and ORs per word, and a 10 M-point map of the lava-tube preset
//! scores in about a second.

use crate::Error;

use super::cloud::{Grid, Points};
use super::world::Cells;

/// Voxels as bits, one row of `words` 64-bit words per `(z, y)`; bit `i % 64` of word `i / 64`
/// is voxel `i` along x.
#[derive(Clone, Debug, PartialEq)]
pub struct Bits {
    /// Voxels along x, y, z.
    pub n: [usize; 3],
    /// Words per row.
    pub words: usize,
    /// Rows of words, z-major.
    pub data: Vec<u64>,
}

impl Bits {
    /// All clear.
    pub fn empty(n: [usize; 3]) -> Bits {
        let words = n[0].div_ceil(64);
        Bits {
            n,
            words,
            data: vec![0; words * n[1] * n[2]],
        }
    }

    /// From `free_space.npy`'s packed bytes (`np.packbits` along x: the first voxel is the
    /// high bit of its byte).
    pub fn from_packed(n: [usize; 3], packed: &[u8]) -> Bits {
        let mut b = Bits::empty(n);
        let row_bytes = n[0].div_ceil(8);
        for r in 0..n[1] * n[2] {
            let src = &packed[r * row_bytes..(r + 1) * row_bytes];
            let dst = &mut b.data[r * b.words..(r + 1) * b.words];
            for (m, &byte) in src.iter().enumerate() {
                dst[m / 8] |= u64::from(byte.reverse_bits()) << (8 * (m % 8));
            }
        }
        b.mask();
        b
    }

    fn mask(&mut self) {
        let tail = self.n[0] % 64;
        if tail != 0 {
            let keep = (1u64 << tail) - 1;
            for r in 0..self.n[1] * self.n[2] {
                self.data[r * self.words + self.words - 1] &= keep;
            }
        }
    }

    /// Sets voxel `[x, y, z]`; returns whether it was clear.
    pub fn set(&mut self, v: [usize; 3]) -> bool {
        let w = &mut self.data[(v[2] * self.n[1] + v[1]) * self.words + v[0] / 64];
        let bit = 1u64 << (v[0] % 64);
        let was = *w & bit == 0;
        *w |= bit;
        was
    }

    /// Whether voxel `[x, y, z]` is set.
    pub fn get(&self, v: [usize; 3]) -> bool {
        self.data[(v[2] * self.n[1] + v[1]) * self.words + v[0] / 64] >> (v[0] % 64) & 1 == 1
    }

    /// Every voxel not set (within the grid).
    pub fn not(&self) -> Bits {
        let mut b = self.clone();
        for w in &mut b.data {
            *w = !*w;
        }
        b.mask();
        b
    }

    /// Grown by `r` voxels along each axis (a cube). A set grown by `d` and then by `s` (at most
    /// `2d + 1`) is grown by `d + s`, so the growth is passes of 1, 2, 4, ... voxels (about
    /// log2 r of them, each a shift and an OR per word or row) instead of `r` passes of one;
    /// and a set grown by its axis's length covers that axis wherever it has a voxel, so `r`
    /// is cut to it. A radius of 1e300 metres costs what one of the world's size does.
    pub fn dilate(&self, r: usize) -> Bits {
        let [nx, ny, nz] = self.n;
        let mut out = self.grown_along_x(r.min(nx));
        for (stride, len) in [(1, ny), (ny, nz)] {
            let r = r.min(len);
            out = if r <= WINDOW {
                out.grown_within_rows(r, stride, len)
            } else {
                steps(r)
                    .into_iter()
                    .fold(out, |b, s| b.grown_along_rows(s, stride, len))
            };
        }
        out
    }

    /// Grown by `r` along x: directly for a few voxels, by doubling passes beyond.
    fn grown_along_x(&self, r: usize) -> Bits {
        if r <= WINDOW {
            return self.grown_within_x(r);
        }
        steps(r)
            .into_iter()
            .fold(self.clone(), |b, s| b.grown_by_pass_x(s))
    }

    /// Grown by `r` (at most [`WINDOW`]) along x: `r` steps of one voxel over each row, in
    /// place, carrying across words.
    fn grown_within_x(&self, r: usize) -> Bits {
        let words = self.words;
        let mut out = self.clone();
        for row in out.data.chunks_exact_mut(words) {
            for _ in 0..r {
                // Bit 63 of the word before, as it was before this step.
                let mut carry = 0u64;
                for k in 0..words {
                    let v = row[k];
                    let next_low = if k + 1 < words { row[k + 1] & 1 } else { 0 };
                    row[k] = v | (v << 1) | carry | (v >> 1) | (next_low << 63);
                    carry = v >> 63;
                }
            }
        }
        out.mask();
        out
    }

    /// Each row grown by `r` (at most [`WINDOW`]) along the axis whose index steps by `stride`
    /// rows and runs to `len`: the OR of the rows within `r`, in one pass.
    fn grown_within_rows(&self, r: usize, stride: usize, len: usize) -> Bits {
        if r == 0 {
            return self.clone();
        }
        let w = self.words;
        let mut out = Bits::empty(self.n);
        let rows = self.n[1] * self.n[2];
        for block in (0..rows).step_by(stride * len) {
            for idx in 0..len {
                for off in 0..stride {
                    let r0 = block + idx * stride + off;
                    let dst = &mut out.data[r0 * w..(r0 + 1) * w];
                    for t in idx.saturating_sub(r)..=(idx + r).min(len - 1) {
                        let src = block + t * stride + off;
                        or_into(dst, &self.data[src * w..(src + 1) * w]);
                    }
                }
            }
        }
        out
    }

    /// Each voxel ORed with those `s` away along x (one doubling pass).
    fn grown_by_pass_x(&self, s: usize) -> Bits {
        let words = self.words;
        let (q, b) = (s / 64, (s % 64) as u32);
        let mut out = self.clone();
        for (dst, src) in out
            .data
            .chunks_exact_mut(words)
            .zip(self.data.chunks_exact(words))
        {
            if q == 0 {
                // Within a word and into its neighbours: the common case, a few voxels.
                let mut lower = 0u64;
                for (k, (d, &w)) in dst.iter_mut().zip(src).enumerate() {
                    let higher = src.get(k + 1).copied().unwrap_or(0);
                    *d |= (w << b) | (lower >> (64 - b)) | (w >> b) | (higher << (64 - b));
                    lower = w;
                }
                continue;
            }
            let at = |k: usize| src.get(k).copied().unwrap_or(0);
            for (k, w) in dst.iter_mut().enumerate() {
                // From `s` below (k - q words, b bits) and from `s` above.
                let below = k.checked_sub(q).map_or(0, |j| {
                    let lower = j.checked_sub(1).map_or(0, at);
                    (at(j) << b) | if b == 0 { 0 } else { lower >> (64 - b) }
                });
                let j = k + q;
                let above = (at(j) >> b) | if b == 0 { 0 } else { at(j + 1) << (64 - b) };
                *w |= below | above;
            }
        }
        out.mask();
        out
    }

    /// Each row (of `words` words) ORed with the rows `s` away along the axis whose index
    /// steps by `stride` rows and runs to `len`: y (`stride` 1, `len` ny) or z (`stride` ny,
    /// `len` nz).
    fn grown_along_rows(&self, s: usize, stride: usize, len: usize) -> Bits {
        let w = self.words;
        let mut out = self.clone();
        let rows = self.n[1] * self.n[2];
        let row = |r: usize| &self.data[r * w..(r + 1) * w];
        for block in (0..rows).step_by(stride * len) {
            for idx in 0..len {
                for off in 0..stride {
                    let r0 = block + idx * stride + off;
                    let dst = &mut out.data[r0 * w..(r0 + 1) * w];
                    if idx >= s {
                        or_into(dst, row(r0 - s * stride));
                    }
                    if idx + s < len {
                        or_into(dst, row(r0 + s * stride));
                    }
                }
            }
        }
        out
    }
}

/// `dst |= src`, word by word.
fn or_into(dst: &mut [u64], src: &[u64]) {
    for (d, s) in dst.iter_mut().zip(src) {
        *d |= *s;
    }
}

/// Up to this radius a set grows along an axis in one pass over the rows within it (at most
/// `2 WINDOW + 1` of them); beyond, by doubling passes.
const WINDOW: usize = 8;

/// The passes that grow a set by `r`: 1, 2, 4, ... and what remains, each at most one more
/// than twice the growth so far, so no voxel in between is skipped.
fn steps(r: usize) -> Vec<usize> {
    let (mut out, mut done, mut next) = (Vec::new(), 0usize, 1usize);
    while done < r {
        let s = next.min(r - done);
        out.push(s);
        done += s;
        next = next.saturating_mul(2);
    }
    out
}

/// Coverage of one region (a level, an edge or a node).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Share {
    /// Free voxels.
    pub free: u64,
    /// Of which covered.
    pub covered: u64,
}

impl Share {
    /// `covered / free`, 0 for a region without free voxels.
    pub fn share(&self) -> f64 {
        if self.free == 0 {
            0.0
        } else {
            self.covered as f64 / self.free as f64
        }
    }
}

/// What a map gives.
#[derive(Clone, Debug, PartialEq)]
pub struct Coverage {
    /// Per level.
    pub levels: Vec<Share>,
    /// Per edge (by id).
    pub edges: Vec<Share>,
    /// Per node (by id).
    pub nodes: Vec<Share>,
    /// The whole world.
    pub total: Share,
    /// Points read.
    pub points: usize,
    /// Points outside the free-space grid.
    pub outside: usize,
    /// Points farther than the tolerance from the surface (the outside ones included).
    pub errors: usize,
}

/// Refuses a map in another frame or unit: a point more than `margin` metres outside the grid.
pub fn check_bounds(points: &Points, grid: &Grid, margin: f64, file: &str) -> Result<(), Error> {
    let lo = grid.origin;
    let hi = [0, 1, 2].map(|k| grid.origin[k] + grid.n[k] as f64 * grid.voxel);
    for (i, p) in points.iter().enumerate() {
        let out = (0..3).any(|k| {
            let v = f64::from(p[k]);
            v < lo[k] - margin || v > hi[k] + margin
        });
        if out {
            return Err(Error::Input(format!(
                "{file}: point {i} ({}, {}, {}) is more than {margin:.0} m outside the world (x {:.1} to {:.1}, y {:.1} to {:.1}, z {:.1} to {:.1} m): the map must be in the world frame in metres (x east, y north, z up, as topology.json), not in millimetres or the robot's odometry frame",
                p[0], p[1], p[2], lo[0], hi[0], lo[1], hi[1], lo[2], hi[2]
            )));
        }
    }
    Ok(())
}

/// Coverage and map error of `points` on the free voxels `free`.
pub fn measure(
    points: &Points,
    grid: &Grid,
    free: &Bits,
    cells: &Cells,
    radius: f64,
    tolerance: f64,
) -> Coverage {
    let v = grid.voxel;
    let voxel_of = |p: &[f32; 3]| -> Option<[usize; 3]> {
        let mut out = [0usize; 3];
        for k in 0..3 {
            let t = ((f64::from(p[k]) - grid.origin[k]) / v).floor();
            if t < 0.0 || t >= grid.n[k] as f64 {
                return None;
            }
            out[k] = t as usize;
        }
        Some(out)
    };
    let mut hits = Bits::empty(grid.n);
    let mut outside = 0;
    for p in points {
        match voxel_of(p) {
            Some(x) => {
                hits.set(x);
            }
            None => outside += 1,
        }
    }
    // One voxel more than the tolerance: a surface point and the centres of the voxels on
    // either side of it can be a voxel apart.
    // Growing by more than the grid's longest axis changes nothing: a tolerance of 1e300 m
    // is one of the world's size (a cast of a huge float saturates, and is cut here).
    let longest = grid.n.iter().copied().max().unwrap_or(0);
    let reach = ((tolerance / v).ceil() as usize).min(longest) + 1;
    let near_free = free.dilate(reach);
    let near_rock = free.not().dilate(reach);
    let errors = outside
        + points
            .iter()
            .filter_map(voxel_of)
            .filter(|&x| {
                // Beyond the grid is rock.
                let edge = (0..3).any(|k| x[k] < reach || x[k] + reach >= grid.n[k]);
                !(near_free.get(x) && (edge || near_rock.get(x)))
            })
            .count();
    let mut covered = hits.dilate(((radius / v).round() as usize).min(longest));
    for (c, f) in covered.data.iter_mut().zip(&free.data) {
        *c &= *f;
    }
    let mut levels = vec![Share::default(); cells.levels];
    let mut edges = vec![Share::default(); cells.edge_count];
    let mut nodes = vec![Share::default(); cells.node_count];
    let mut total = Share::default();
    let [nx, ny, nz] = grid.n;
    let xs: Vec<f64> = (0..nx)
        .map(|i| grid.origin[0] + (i as f64 + 0.5) * v)
        .collect();
    for k in 0..nz {
        let z = grid.origin[2] + (k as f64 + 0.5) * v;
        for j in 0..ny {
            let y = grid.origin[1] + (j as f64 + 0.5) * v;
            let row = (k * ny + j) * free.words;
            for w in 0..free.words {
                let (mut f, c) = (free.data[row + w], covered.data[row + w]);
                while f != 0 {
                    let b = f.trailing_zeros() as usize;
                    f &= f - 1;
                    let hit = c >> b & 1;
                    total.free += 1;
                    total.covered += hit;
                    let i = w * 64 + b;
                    if let Some((level, region)) = cells.region(xs[i], y, z) {
                        levels[level].free += 1;
                        levels[level].covered += hit;
                        let s = match region {
                            super::world::Region::Node(n) => &mut nodes[n],
                            super::world::Region::Edge(e) => &mut edges[e],
                        };
                        s.free += 1;
                        s.covered += hit;
                    }
                }
            }
        }
    }
    Coverage {
        levels,
        edges,
        nodes,
        total,
        points: points.len(),
        outside,
        errors,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dilation_grows_a_voxel_into_a_cube_across_word_boundaries() {
        let mut b = Bits::empty([130, 5, 4]);
        b.set([64, 2, 1]);
        let d = b.dilate(1);
        let mut count = 0;
        for z in 0..4 {
            for y in 0..5 {
                for x in 0..130 {
                    if d.get([x, y, z]) {
                        count += 1;
                        assert!((63..=65).contains(&x) && (1..=3).contains(&y) && z <= 2);
                    }
                }
            }
        }
        assert_eq!(count, 27);
        // Growing by passes of 1, 2, 4, ... is growing voxel by voxel: compared with the cube
        // counted directly, for radii across a word boundary and beyond the grid.
        let mut one = Bits::empty([200, 7, 6]);
        one.set([70, 3, 2]);
        one.set([3, 0, 5]);
        for r in [2, 3, 5, 6, 7, 9, 63, 64, 65, 130, 1000, usize::MAX] {
            let d = one.dilate(r);
            for z in 0..6usize {
                for y in 0..7usize {
                    for x in 0..200usize {
                        let near = |c: [usize; 3]| {
                            x.abs_diff(c[0]) <= r && y.abs_diff(c[1]) <= r && z.abs_diff(c[2]) <= r
                        };
                        assert_eq!(
                            d.get([x, y, z]),
                            near([70, 3, 2]) || near([3, 0, 5]),
                            "r {r} at {x}, {y}, {z}"
                        );
                    }
                }
            }
        }
        assert_eq!(b.not().not(), b);
        let packed = [0b1000_0001u8, 0b0100_0000];
        let f = Bits::from_packed([10, 1, 1], &packed);
        let set: Vec<usize> = (0..10).filter(|&x| f.get([x, 0, 0])).collect();
        assert_eq!(set, [0, 7, 9]);
    }
}
