//! Small separate pieces of the lattice's signs, removed before marching (issue 21 item 15).
//!
//! Marching tetrahedra joins two lattice points of the same sign only along the edges of the
//! Kuhn triangulation: the axes and the diagonals whose steps all point the same way
//! ([`NEIGHBOURS`]). Where the surface runs almost along a lattice plane (a lava tube's flat
//! bench top, a wall at a tangent), the field is within a few millimetres of zero on a whole
//! patch of points and their signs follow the noise, so a single point can end up solid with
//! all fourteen of its neighbours void (its solid neighbour across the other diagonal, which
//! the triangulation does not join), or void amid solid. Marching then closes a surface of
//! 24 triangles round that one point: a pebble floating in the passage, or a bubble sealed
//! in the rock, 0.7 m across on the lava-tube preset (seed 11 had one; 11 of 30 seeds had one
//! or two, every one a single point). A world is one surface: such a piece is no passage and
//! no rock a robot can meet.
//!
//! So before marching, every small component of one sign (at most [`MOST_POINTS`] points,
//! within [`MOST_EXTENT`] steps along each axis) is given the other sign: first the solid
//! ones (pebbles), then, on the signs that leaves, the void ones (bubbles), so a pebble and
//! the bubble round it both go. Flipping a point whose field is a few millimetres from zero
//! moves no other point of the surface; a real feature is never that small (a rock, a pillar
//! or a passage is part of a component of thousands of points). Nothing changes where there
//! is no such piece.
//!
//! A component may straddle a block's face. Points outside the block are read through
//! `outside`, which must give the value the block that owns the point computes (the
//! procedural tile sets evaluate the owning tile's own field), so a tile and its neighbour
//! find the same component and flip the same points on the face they share.

use std::cell::RefCell;
use std::collections::HashMap;

use crate::marching::Block;

/// Most lattice points of a component that is removed.
pub const MOST_POINTS: usize = 8;
/// Most lattice steps a removed component spans along any axis.
pub const MOST_EXTENT: i64 = 2;

/// The lattice steps that are edges of the Kuhn triangulation (see [`crate::marching`]).
pub const NEIGHBOURS: [[i64; 3]; 14] = [
    [1, 0, 0],
    [0, 1, 0],
    [0, 0, 1],
    [1, 1, 0],
    [1, 0, 1],
    [0, 1, 1],
    [1, 1, 1],
    [-1, 0, 0],
    [0, -1, 0],
    [0, 0, -1],
    [-1, -1, 0],
    [-1, 0, -1],
    [0, -1, -1],
    [-1, -1, -1],
];

/// The block's points and the signs around them, as the passes see them.
struct Signs<'a, F> {
    block: Block,
    dims: [usize; 3],
    values: &'a [f64],
    outside: F,
    /// Field values read outside the block (kept across the passes).
    read: &'a RefCell<HashMap<[i64; 3], f64>>,
    /// Outside points found in a small solid component (pass one's flips there).
    pebble: RefCell<HashMap<[i64; 3], bool>>,
}

impl<F: Fn([i64; 3]) -> f64> Signs<'_, F> {
    /// The index in `values` of global lattice point `p`, if it is in the block.
    fn local(&self, p: [i64; 3]) -> Option<usize> {
        let mut at = [0usize; 3];
        for d in 0..3 {
            let i = p[d] - self.block.origin[d];
            if i < 0 || i as usize >= self.dims[d] {
                return None;
            }
            at[d] = i as usize;
        }
        Some((at[2] * self.dims[1] + at[1]) * self.dims[0] + at[0])
    }

    /// Whether `p` is void in the field as evaluated (before any pass).
    fn void0(&self, p: [i64; 3]) -> bool {
        match self.local(p) {
            Some(i) => self.values[i] < 0.0,
            None => {
                let v = *self
                    .read
                    .borrow_mut()
                    .entry(p)
                    .or_insert_with(|| (self.outside)(p));
                v < 0.0
            }
        }
    }

    /// Whether `p` is void after pass one (small solid components made void). Inside the
    /// block pass one has written its flips into `values`; outside, they are found here.
    fn void1(&self, p: [i64; 3]) -> bool {
        if self.local(p).is_some() {
            return self.void0(p);
        }
        if self.void0(p) {
            return true;
        }
        if let Some(&small) = self.pebble.borrow().get(&p) {
            return small;
        }
        let small = component(p, |q| !self.void0(q)).is_some();
        self.pebble.borrow_mut().insert(p, small);
        small
    }
}

/// The component of the points `same` says are alike, from `start`, if it is small: at most
/// [`MOST_POINTS`] points within [`MOST_EXTENT`] steps along each axis. `None` as soon as it
/// is not.
fn component(start: [i64; 3], same: impl Fn([i64; 3]) -> bool) -> Option<Vec<[i64; 3]>> {
    let mut found = vec![start];
    let (mut lo, mut hi) = (start, start);
    let mut next = 0;
    while next < found.len() {
        let p = found[next];
        next += 1;
        for s in NEIGHBOURS {
            let q = [p[0] + s[0], p[1] + s[1], p[2] + s[2]];
            if found.contains(&q) || !same(q) {
                continue;
            }
            for d in 0..3 {
                lo[d] = lo[d].min(q[d]);
                hi[d] = hi[d].max(q[d]);
                if hi[d] - lo[d] > MOST_EXTENT {
                    return None;
                }
            }
            found.push(q);
            if found.len() > MOST_POINTS {
                return None;
            }
        }
    }
    Some(found)
}

/// Gives every small component of one sign in `values` (the block's points, x fastest, then
/// y, then z) the other sign: solid ones first, then void ones on the signs that leaves.
/// `outside` gives the field at a global lattice point outside the block. Returns how many
/// points were flipped.
pub fn remove(values: &mut [f64], block: Block, outside: impl Fn([i64; 3]) -> f64) -> usize {
    let dims = block.cubes.map(|c| c + 1);
    let read = RefCell::new(HashMap::new());
    let mut flipped = 0;
    for void_pass in [false, true] {
        let flips: Vec<usize> = {
            let signs = Signs {
                block,
                dims,
                values,
                outside: &outside,
                read: &read,
                pebble: RefCell::new(HashMap::new()),
            };
            // In pass one `void1` is `void0` inside the block; outside it differs only in
            // pass two, where pass one's flips are taken into account.
            let void = |p: [i64; 3]| {
                if void_pass {
                    signs.void1(p)
                } else {
                    signs.void0(p)
                }
            };
            let mut decided = vec![false; values.len()];
            let mut flips = Vec::new();
            for k in 0..dims[2] {
                for j in 0..dims[1] {
                    for i in 0..dims[0] {
                        let at = (k * dims[1] + j) * dims[0] + i;
                        if decided[at] || (values[at] < 0.0) != void_pass {
                            continue;
                        }
                        let p = [
                            block.origin[0] + i as i64,
                            block.origin[1] + j as i64,
                            block.origin[2] + k as i64,
                        ];
                        // Only points on the surface start a search: every small component
                        // has one.
                        let surface = NEIGHBOURS
                            .iter()
                            .any(|s| void([p[0] + s[0], p[1] + s[1], p[2] + s[2]]) != void_pass);
                        if !surface {
                            continue;
                        }
                        match component(p, |q| void(q) == void_pass) {
                            Some(piece) => {
                                for q in piece {
                                    if let Some(i) = signs.local(q) {
                                        if !decided[i] {
                                            decided[i] = true;
                                            flips.push(i);
                                        }
                                    }
                                }
                            }
                            None => decided[at] = true,
                        }
                    }
                }
            }
            flips
        };
        flipped += flips.len();
        for i in flips {
            values[i] = -values[i];
        }
    }
    flipped
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A block of `n` cubes a side from the origin, with a field given per global point.
    fn run(n: usize, field: impl Fn([i64; 3]) -> f64) -> (Vec<f64>, usize) {
        let block = Block {
            origin: [0, 0, 0],
            cubes: [n, n, n],
            h: 1.0,
        };
        let m = n + 1;
        let mut values: Vec<f64> = (0..m * m * m)
            .map(|i| field([(i % m) as i64, ((i / m) % m) as i64, (i / (m * m)) as i64]))
            .collect();
        let flipped = remove(&mut values, block, field);
        (values, flipped)
    }

    fn at(n: usize, p: [usize; 3]) -> usize {
        let m = n + 1;
        (p[2] * m + p[1]) * m + p[0]
    }

    #[test]
    fn a_lone_point_of_either_sign_takes_its_neighbours_sign() {
        // Solid below z = 4, void above, with one solid point in the void at (4, 4, 6) and
        // its solid neighbour across the diagonal the triangulation does not join.
        let pebble = |p: [i64; 3]| match p {
            [4, 4, 6] => 0.01,
            [4, 5, 5] => 0.02,
            [_, _, z] if z < 4 => 1.0,
            _ => -1.0,
        };
        let (values, flipped) = run(8, pebble);
        assert_eq!(flipped, 2, "the point and its diagonal neighbour");
        assert!(values[at(8, [4, 4, 6])] < 0.0 && values[at(8, [4, 5, 5])] < 0.0);
        // A bubble in the rock.
        let bubble = |p: [i64; 3]| match p {
            [3, 3, 2] => -0.001,
            [_, _, z] if z < 4 => 1.0,
            _ => -1.0,
        };
        let (values, flipped) = run(8, bubble);
        assert_eq!(flipped, 1);
        assert!(values[at(8, [3, 3, 2])] > 0.0);
    }

    #[test]
    fn larger_pieces_and_the_surface_itself_are_kept() {
        // A slab of void three points thick through the block, and a solid bar five points
        // long floating in it: neither is small.
        let field = |p: [i64; 3]| match p {
            [2..=6, 4, 4] => 0.5,
            [_, _, 3..=5] => -1.0,
            _ => 1.0,
        };
        let (values, flipped) = run(8, field);
        assert_eq!(flipped, 0);
        assert!(values[at(8, [4, 4, 4])] > 0.0);
    }

    #[test]
    fn a_piece_across_the_face_is_found_from_both_sides() {
        // A pebble of two points, one on each side of x = 8, seen from the block [0, 8] and
        // from the block [8, 16]: both flip their point on the face and only theirs.
        let field = |p: [i64; 3]| match p {
            [8, 4, 5] | [9, 4, 5] => 0.3,
            [_, _, z] if z < 3 => 1.0,
            _ => -1.0,
        };
        let (left, n) = run(8, field);
        assert_eq!(n, 1);
        assert!(left[at(8, [8, 4, 5])] < 0.0);
        let block = Block {
            origin: [8, 0, 0],
            cubes: [8, 8, 8],
            h: 1.0,
        };
        let mut right: Vec<f64> = (0..9 * 9 * 9)
            .map(|i| field([8 + (i % 9) as i64, ((i / 9) % 9) as i64, (i / 81) as i64]))
            .collect();
        assert_eq!(remove(&mut right, block, field), 2);
        assert!(right[at(8, [0, 4, 5])] < 0.0 && right[at(8, [1, 4, 5])] < 0.0);
    }
}
