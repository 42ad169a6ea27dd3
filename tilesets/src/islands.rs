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

use crate::lattice::Block;

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
        let small = component(p, |q| {
            if self.void0(q) {
                Seen::Other
            } else {
                Seen::Alike
            }
        })
        .is_ok();
        self.pebble.borrow_mut().insert(p, small);
        small
    }
}

/// What a component search learns of a point.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Seen {
    /// Of the sign searched.
    Alike,
    /// Of the other sign.
    Other,
    /// Of the sign searched and in a component already found large.
    Large,
}

/// The component of the points `seen` says are alike, from `start`, if it is small: at most
/// [`MOST_POINTS`] points within [`MOST_EXTENT`] steps along each axis. `Err` with the points
/// found as soon as it is not (or meets a point known to be in a large one).
fn component(
    start: [i64; 3],
    seen: impl Fn([i64; 3]) -> Seen,
) -> Result<Vec<[i64; 3]>, Vec<[i64; 3]>> {
    let mut found = vec![start];
    let (mut lo, mut hi) = (start, start);
    let mut next = 0;
    while next < found.len() {
        let p = found[next];
        next += 1;
        for s in NEIGHBOURS {
            let q = [p[0] + s[0], p[1] + s[1], p[2] + s[2]];
            if found.contains(&q) {
                continue;
            }
            match seen(q) {
                Seen::Other => continue,
                Seen::Large => return Err(found),
                Seen::Alike => {}
            }
            for d in 0..3 {
                lo[d] = lo[d].min(q[d]);
                hi[d] = hi[d].max(q[d]);
            }
            found.push(q);
            if found.len() > MOST_POINTS || (0..3).any(|d| hi[d] - lo[d] > MOST_EXTENT) {
                return Err(found);
            }
        }
    }
    Ok(found)
}

/// How many of each point's neighbours inside the block have its sign (`void`: 1 void, 0
/// solid; x fastest, then y, then z), in the same order. The signs are first copied into an
/// array with a margin of one point all round that matches neither sign, so that each of the
/// fourteen steps is one pass over a flat array, with no test for the block's faces (which
/// lets the compiler run it on vectors: a few instructions a point in all).
fn alike_counts(void: &[u8], dims: [usize; 3]) -> Vec<u8> {
    let [nx, ny, nz] = dims;
    let (px, py) = (nx + 2, ny + 2);
    let padded_at = |i: usize, j: usize, k: usize| ((k + 1) * py + j + 1) * px + i + 1;
    let mut padded = vec![2u8; px * py * (nz + 2)];
    for k in 0..nz {
        for j in 0..ny {
            let row = (k * ny + j) * nx;
            let at = padded_at(0, j, k);
            padded[at..at + nx].copy_from_slice(&void[row..row + nx]);
        }
    }
    let mut count = vec![0u8; padded.len()];
    for s in NEIGHBOURS {
        let d = s[0] as isize + s[1] as isize * px as isize + s[2] as isize * (px * py) as isize;
        let (lo, hi) = (d.min(0).unsigned_abs(), padded.len() - d.max(0) as usize);
        let here = &padded[lo..hi];
        let there = &padded[lo.wrapping_add_signed(d)..hi.wrapping_add_signed(d)];
        let counted = &mut count[lo..hi];
        // Wrapping (a count is at most 14): the loop then runs on vectors.
        for x in 0..here.len() {
            counted[x] = counted[x].wrapping_add(u8::from(here[x] == there[x]));
        }
    }
    let mut out = vec![0u8; void.len()];
    for k in 0..nz {
        for j in 0..ny {
            let row = (k * ny + j) * nx;
            let at = padded_at(0, j, k);
            out[row..row + nx].copy_from_slice(&count[at..at + nx]);
        }
    }
    out
}

/// Gives every small component of one sign in `values` (the block's points, x fastest, then
/// y, then z) the other sign: solid ones first, then void ones on the signs that leaves.
/// `outside` gives the field at a global lattice point outside the block. Returns how many
/// points were flipped.
///
/// Cost: the neighbours alike of every point are counted over slices (`alike_counts`); a
/// point with eight or more is in no small component (it would have at least nine points),
/// nor is one next to a point found in a large component. From the few others a search of
/// at most nine points runs, reading points beyond a face only then.
pub fn remove(values: &mut [f64], block: Block, outside: impl Fn([i64; 3]) -> f64) -> usize {
    let dims = block.cubes.map(|c| c + 1);
    let read = RefCell::new(HashMap::new());
    let mut flipped = 0;
    let mut void: Vec<u8> = values.iter().map(|&v| u8::from(v < 0.0)).collect();
    let mut alike = alike_counts(&void, dims);
    for void_pass in [false, true] {
        let want = u8::from(void_pass);
        // Points decided: with eight or more alike neighbours, found in a large component, or
        // in a small one already flipped (which no other search can reach: a point of its sign
        // next to it would be in it).
        let mut large: Vec<bool> = alike
            .iter()
            .map(|&n| usize::from(n) >= MOST_POINTS)
            .collect();
        let candidates: Vec<usize> = (0..values.len())
            .filter(|&i| void[i] == want && !large[i])
            .collect();
        let signs = Signs {
            block,
            dims,
            values,
            outside: &outside,
            read: &read,
            pebble: RefCell::new(HashMap::new()),
        };
        // Outside the block pass two sees pass one's flips (`Signs::void1`); inside, `void`
        // already holds them.
        let void_at = |p: [i64; 3]| match signs.local(p) {
            Some(i) => void[i] == 1,
            None if void_pass => signs.void1(p),
            None => signs.void0(p),
        };
        let mut flips = Vec::new();
        for at in candidates {
            if large[at] {
                continue;
            }
            let (i, j, k) = (
                at % dims[0],
                (at / dims[0]) % dims[1],
                at / (dims[0] * dims[1]),
            );
            let p = [
                block.origin[0] + i as i64,
                block.origin[1] + j as i64,
                block.origin[2] + k as i64,
            ];
            // Next to a point of a large component, it is in that component.
            let joined = NEIGHBOURS.iter().any(|s| {
                signs
                    .local([p[0] + s[0], p[1] + s[1], p[2] + s[2]])
                    .is_some_and(|q| void[q] == want && large[q])
            });
            if joined {
                large[at] = true;
                continue;
            }
            let seen = |q: [i64; 3]| {
                if void_at(q) != void_pass {
                    Seen::Other
                } else if signs.local(q).is_some_and(|i| large[i]) {
                    Seen::Large
                } else {
                    Seen::Alike
                }
            };
            match component(p, seen) {
                Ok(piece) => {
                    for q in piece {
                        if let Some(i) = signs.local(q) {
                            if !large[i] {
                                large[i] = true;
                                flips.push(i);
                            }
                        }
                    }
                }
                Err(met) => {
                    for q in met {
                        if let Some(i) = signs.local(q) {
                            large[i] = true;
                        }
                    }
                }
            }
        }
        drop(signs);
        flipped += flips.len();
        if !flips.is_empty() {
            for i in flips {
                values[i] = -values[i];
                void[i] = 1 - void[i];
            }
            alike = alike_counts(&void, dims);
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
