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

pub use super::bits::Bits;
use super::cloud::{Grid, Points};
use super::world::Cells;

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
