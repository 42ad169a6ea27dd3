//! Where a robot can be on its map, and where the map ends: the places and frontiers the
//! planner searches (see the planner's doc for the rules).
//!
//! A ground robot's LiDAR sees its floor in rings (a VLP-16 at 0.6 m meets a flat floor 2.2,
//! 2.6, 3.1, 3.8, 4.9, 6.9, 11 and 34 m away), so between the rings a floor voxel may be
//! unknown while its neighbours are not: a free voxel whose own floor is unknown counts as a
//! place when the floor is known under at least [`FLOOR_NEIGHBOURS`] of its eight neighbouring
//! columns at the same height.

use crate::body::Body;
use crate::map::{Grid, Voxel, VoxelMap};

/// Known floors around an unknown one that make it a floor too.
pub const FLOOR_NEIGHBOURS: usize = 3;
/// Extra cost of a step onto a place beside rock, in tenths of a voxel.
const BESIDE_ROCK: u32 = 20;

const ORTHOGONAL: [[i32; 2]; 4] = [[1, 0], [-1, 0], [0, 1], [0, -1]];
const AROUND: [[i32; 2]; 8] = [
    [1, 0],
    [-1, 0],
    [0, 1],
    [0, -1],
    [1, 1],
    [1, -1],
    [-1, 1],
    [-1, -1],
];
const FACES: [[i32; 3]; 6] = [
    [1, 0, 0],
    [-1, 0, 0],
    [0, 1, 0],
    [0, -1, 0],
    [0, 0, 1],
    [0, 0, -1],
];

/// A voxel a robot can be in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Place(pub [i32; 3]);

impl Place {
    /// A key for hash maps (coordinates below 2^21).
    pub fn key(self) -> u64 {
        let [x, y, z] = self.0;
        (x as u64 & 0x1f_ffff) | ((y as u64 & 0x1f_ffff) << 21) | ((z as u64 & 0x1f_ffff) << 42)
    }

    /// The place of a key.
    pub fn from_key(k: u64) -> Place {
        Place([
            (k & 0x1f_ffff) as i32,
            ((k >> 21) & 0x1f_ffff) as i32,
            ((k >> 42) & 0x1f_ffff) as i32,
        ])
    }

    fn at(self, d: [i32; 3]) -> Place {
        Place([self.0[0] + d[0], self.0[1] + d[1], self.0[2] + d[2]])
    }
}

/// A robot's map as places.
pub struct Space<'a> {
    map: &'a VoxelMap,
    flies: bool,
    /// The robot's voxel and how many voxels around it (in the plane, one up or down) an
    /// unknown floor is taken as known: a ground robot's LiDAR meets its floor no nearer
    /// than its lowest ring ([`BLIND_M`]).
    near: Option<([i32; 3], i32)>,
    /// Places the robot found it could not drive into.
    blocked: Option<&'a rustc_hash::FxHashSet<u64>>,
    /// The steepest rise a ground robot drives, per metre (a little under its limit).
    grade: f64,
    /// Places already asked about during this plan (a search asks of each voxel several
    /// times, once from each neighbour).
    memo: std::cell::RefCell<rustc_hash::FxHashMap<u64, bool>>,
}

/// Share of a ground robot's grade limit a move between two known floors may use: the
/// floors' tops are returns, a few centimetres off the surface between them.
const GRADE_MARGIN: f64 = 0.85;

/// How far from a ground robot its floor is taken as known where unseen, metres (a VLP-16
/// 0.6 m up meets a flat floor 2.2 m out).
pub const BLIND_M: f64 = 2.5;

impl<'a> Space<'a> {
    /// The places of `body` on `map`.
    pub fn new(map: &'a VoxelMap, body: &Body) -> Space<'a> {
        Space {
            map,
            flies: body.flies(),
            near: None,
            blocked: None,
            grade: (GRADE_MARGIN * body.max_grade_deg.to_radians()).tan(),
            memo: Default::default(),
        }
    }

    /// The same, with the floor around a ground robot at `position` (its reference point)
    /// taken as known within [`BLIND_M`].
    pub fn around(
        map: &'a VoxelMap,
        body: &Body,
        position: [f64; 3],
        blocked: &'a rustc_hash::FxHashSet<u64>,
    ) -> Space<'a> {
        let g = map.grid;
        let lift = 0.5 * g.voxel;
        let near = (!body.flies())
            .then(|| g.voxel_of([position[0], position[1], position[2] + lift]))
            .flatten()
            .map(|v| (v, (BLIND_M / g.voxel).round() as i32));
        Space {
            map,
            flies: body.flies(),
            near,
            blocked: Some(blocked),
            grade: (GRADE_MARGIN * body.max_grade_deg.to_radians()).tan(),
            memo: Default::default(),
        }
    }

    /// Whether `p` is within the blind zone around the robot.
    fn blind(&self, p: Place) -> bool {
        self.near.is_some_and(|(c, r)| {
            let d = [p.0[0] - c[0], p.0[1] - c[1]];
            d[0] * d[0] + d[1] * d[1] <= r * r && (p.0[2] - c[2]).abs() <= 1
        })
    }

    /// Voxel edge, metres.
    pub fn voxel(&self) -> f64 {
        self.map.grid.voxel
    }

    /// The grid.
    pub fn grid(&self) -> &Grid {
        &self.map.grid
    }

    /// A place's centre, world frame.
    pub fn centre(&self, p: Place) -> [f64; 3] {
        self.map.grid.centre(p.0)
    }

    fn get(&self, p: Place) -> Voxel {
        self.map.get(p.0)
    }

    fn occupied(&self, p: Place) -> bool {
        self.get(p) == Voxel::Occupied
    }

    /// Whether the floor under `p` (the voxel below) is known, or known around it.
    fn floored(&self, p: Place) -> bool {
        let below = p.at([0, 0, -1]);
        match self.get(below) {
            Voxel::Occupied => true,
            Voxel::Free => false,
            Voxel::Unknown => {
                AROUND
                    .iter()
                    .filter(|d| self.occupied(below.at([d[0], d[1], 0])))
                    .count()
                    >= FLOOR_NEIGHBOURS
            }
        }
    }

    /// Whether a robot can be at `p`.
    pub fn is_place(&self, p: Place) -> bool {
        let key = p.key();
        if let Some(&known) = self.memo.borrow().get(&key) {
            return known;
        }
        let answer = self.place_now(p);
        self.memo.borrow_mut().insert(key, answer);
        answer
    }

    fn place_now(&self, p: Place) -> bool {
        if self.blocked.is_some_and(|b| b.contains(&p.key())) {
            return false;
        }
        let here = self.get(p);
        if self.flies {
            return here == Voxel::Free && FACES.iter().all(|d| !self.occupied(p.at(*d)));
        }
        if here == Voxel::Occupied || self.occupied(p.at([0, 0, 1])) {
            return false;
        }
        if here == Voxel::Free && self.floored(p) {
            return true;
        }
        // Around the robot, where its LiDAR does not see the floor: a place unless the voxel
        // below is known free (a drop) or the voxel itself stands on another place.
        self.blind(p)
            && self.get(p.at([0, 0, -1])) != Voxel::Free
            && !(here == Voxel::Unknown && self.occupied(p.at([0, 0, -2])))
    }

    /// Whether the place `p` borders the unknown.
    pub fn is_frontier(&self, p: Place) -> bool {
        if self.flies {
            return FACES.iter().any(|d| self.get(p.at(*d)) == Voxel::Unknown);
        }
        if self.blind(p) {
            return false;
        }
        ORTHOGONAL.iter().any(|d| {
            // The neighbouring column from two voxels below to one above: no floor or wall
            // known there, and something unknown below the body.
            let c = p.at([d[0], d[1], 0]);
            let column = [c.at([0, 0, -2]), c.at([0, 0, -1]), c, c.at([0, 0, 1])];
            column.iter().all(|&v| !self.occupied(v))
                && column[..3].iter().any(|&v| self.get(v) == Voxel::Unknown)
                && !column[1..].iter().any(|&v| self.is_place(v))
        })
    }

    /// The places one move from `p`, with the move's cost in tenths of a voxel.
    pub fn neighbours(&self, p: Place, out: &mut Vec<(Place, u32)>) {
        out.clear();
        if self.flies {
            for d in FACES {
                let q = p.at(d);
                if self.is_place(q) {
                    out.push((q, 10));
                }
            }
            return;
        }
        for d in AROUND {
            let diagonal = d[0] != 0 && d[1] != 0;
            if diagonal {
                // No cutting a corner of rock.
                let (a, b) = (p.at([d[0], 0, 0]), p.at([0, d[1], 0]));
                if self.occupied(a) || self.occupied(b) {
                    continue;
                }
            }
            for dz in [0, 1, -1] {
                let q = p.at([d[0], d[1], dz]);
                if dz == 1 && self.occupied(p.at([0, 0, 1])) {
                    continue;
                }
                if !self.is_place(q) {
                    continue;
                }
                // The floors' tops (the highest returns in the voxels under the two places)
                // tell a slope the voxels cannot: no move steeper than the robot drives.
                let run = if diagonal {
                    std::f64::consts::SQRT_2
                } else {
                    1.0
                } * self.voxel();
                if let (Some(a), Some(b)) = (
                    self.map.top(p.at([0, 0, -1]).0),
                    self.map.top(q.at([0, 0, -1]).0),
                ) {
                    if (b - a).abs() > self.grade * run {
                        break;
                    }
                } else if dz != 0 {
                    // A voxel up or down with a floor unseen at either end: not taken.
                    break;
                }
                let mut cost = if diagonal { 14 } else { 10 } + if dz != 0 { 4 } else { 0 };
                if self.beside_rock(q) {
                    cost += BESIDE_ROCK;
                }
                out.push((q, cost));
                break;
            }
        }
    }

    /// Whether rock stands beside `p` at its height or above, or the floor beside it is a
    /// voxel lower (rough ground: the foot of a pile, the edge of a dip).
    fn beside_rock(&self, p: Place) -> bool {
        ORTHOGONAL.iter().any(|d| {
            let c = p.at([d[0], d[1], 0]);
            self.occupied(c)
                || self.occupied(c.at([0, 0, 1]))
                || self.get(c.at([0, 0, -1])) == Voxel::Free
        })
    }

    /// Where a search starts for a robot at `position` (its reference point: the floor for a
    /// ground robot): the place nearest it within a voxel or two, or its own voxel when the
    /// map has none there yet (a robot sees no floor within 2 m of itself until it moves).
    pub fn place_near(&self, position: [f64; 3]) -> Option<Place> {
        let lift = if self.flies { 0.0 } else { 0.5 * self.voxel() };
        let own = self
            .map
            .grid
            .voxel_of([position[0], position[1], position[2] + lift])
            .map(Place)?;
        let mut best: Option<(i32, Place)> = None;
        for dz in -1..=1 {
            for dy in -2..=2 {
                for dx in -2..=2 {
                    let q = own.at([dx, dy, dz]);
                    if self.is_place(q) {
                        let d = dx * dx + dy * dy + dz * dz;
                        if best.is_none_or(|(b, _)| d < b) {
                            best = Some((d, q));
                        }
                    }
                }
            }
        }
        Some(best.map_or(own, |(_, q)| q))
    }
}
