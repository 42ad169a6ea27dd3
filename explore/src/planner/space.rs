//! Where a robot can be on its map, and where the map ends: the places and frontiers the
//! planner searches (see the planner's doc for the rules).
//!
//! A ground robot's LiDAR sees its floor in rings (a VLP-16 at 0.6 m meets a flat floor 2.2,
//! 2.6, 3.1, 3.8, 4.9, 6.9, 11 and 34 m away), so between the rings a floor voxel may be
//! unknown while its neighbours are not: a free voxel whose own floor is unknown counts as a
//! place when the floor is known under at least [`FLOOR_NEIGHBOURS`] of its eight neighbouring
//! columns at the same height.

use std::cell::RefCell;

use crate::body::Body;
use crate::map::{Grid, Voxel, VoxelMap};

use super::places::{Kept, Places, Worked};

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
    memo: RefCell<rustc_hash::FxHashMap<u64, bool>>,
    /// What the planner keeps between plans, with the same space without the blind zone
    /// that works it out ([`Space::keeping`]).
    kept: Option<(RefCell<&'a mut Places>, Box<Space<'a>>)>,
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
            kept: None,
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
            kept: None,
        }
    }

    /// The same, answering from what `places` kept of earlier plans where the map has not
    /// changed since and the answer does not depend on where the robot stands (see
    /// [`super::places`]): the same answers, worked out once.
    pub fn keeping(mut self, places: &'a mut Places) -> Space<'a> {
        places.begin(self.map, self.blocked.map_or(0, |b| b.len()));
        let far = Space {
            map: self.map,
            flies: self.flies,
            near: None,
            blocked: self.blocked,
            grade: self.grade,
            memo: Default::default(),
            kept: None,
        };
        self.kept = Some((RefCell::new(places), Box::new(far)));
        self
    }

    /// What was kept of place `p`, when the answer may come from there: `None` near the
    /// robot (its answers depend on the blind zone: the voxels they read are within one
    /// column and one voxel up or down of `p`) and outside the grid.
    fn kept(&self, p: Place) -> Option<Kept> {
        let (places, far) = self.kept.as_ref()?;
        if let Some((c, r)) = self.near {
            let d = [p.0[0] - c[0], p.0[1] - c[1], p.0[2] - c[2]];
            if d[2].abs() <= 2 && d[0] * d[0] + d[1] * d[1] <= (r + 2) * (r + 2) {
                return None;
            }
        }
        if !self.map.grid.contains(p.0) {
            return None;
        }
        Some(places.borrow_mut().get(self.map, p.0, |c| far.work_out(c)))
    }

    /// The answers of chunk `c` (chunk coordinates) for [`Places`].
    fn work_out(&self, c: [i32; 3]) -> Worked {
        let mut w = Worked::default();
        let mut moves = Vec::with_capacity(8);
        for (z, word) in w.places.iter_mut().enumerate() {
            for bit in 0..64 {
                let p = Place([
                    c[0] * 8 + (bit & 7),
                    c[1] * 8 + (bit >> 3),
                    c[2] * 8 + z as i32,
                ]);
                if !self.is_place(p) {
                    continue;
                }
                *word |= 1 << bit;
                moves.clear();
                self.moves_now(p, |i, _, rise, rock| moves.push((i, rise, rock)));
                w.kept
                    .push(Kept::place(self.is_frontier_now(p), moves.iter().copied()));
            }
        }
        w
    }

    /// The moves a kept place's answers give out of `p`, with their costs.
    fn kept_moves(&self, k: Kept, p: Place, out: &mut Vec<(Place, u32)>) {
        let directions = if self.flies {
            FACES.len()
        } else {
            AROUND.len()
        };
        k.moves(directions, |i, rise, rock| {
            if self.flies {
                out.push((p.at(FACES[i]), move_cost(true, false, 0, false)));
            } else {
                let d = AROUND[i];
                let diagonal = d[0] != 0 && d[1] != 0;
                out.push((
                    p.at([d[0], d[1], rise]),
                    move_cost(false, diagonal, rise, rock),
                ));
            }
        });
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
        if let Some(k) = self.kept(p) {
            return k.is_place();
        }
        self.is_place_now(p)
    }

    /// [`Space::is_place`] worked out here (once a plan).
    fn is_place_now(&self, p: Place) -> bool {
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
        if let Some(k) = self.kept(p).filter(|k| k.is_place()) {
            return k.is_frontier();
        }
        self.is_frontier_now(p)
    }

    /// [`Space::is_frontier`] worked out here.
    fn is_frontier_now(&self, p: Place) -> bool {
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

    /// What a search does at place `p`: whether it is a frontier (asked only when
    /// `frontier_ends`), and if not, the places one move away into `out` ([`Space::neighbours`]).
    pub fn visit(&self, p: Place, frontier_ends: bool, out: &mut Vec<(Place, u32)>) -> bool {
        out.clear();
        if let Some(k) = self.kept(p).filter(|k| k.is_place()) {
            if frontier_ends && k.is_frontier() {
                return true;
            }
            self.kept_moves(k, p, out);
            return false;
        }
        if frontier_ends && self.is_frontier_now(p) {
            return true;
        }
        self.neighbours(p, out);
        false
    }

    /// The places one move from `p`, with the move's cost in tenths of a voxel.
    pub fn neighbours(&self, p: Place, out: &mut Vec<(Place, u32)>) {
        out.clear();
        if let Some(k) = self.kept(p).filter(|k| k.is_place()) {
            self.kept_moves(k, p, out);
            return;
        }
        self.moves_now(p, |_, q, dz, rock| {
            out.push((
                q,
                move_cost(self.flies, q.0[0] != p.0[0] && q.0[1] != p.0[1], dz, rock),
            ))
        });
    }

    /// The moves out of `p` worked out here, in order: each direction's index (in [`AROUND`],
    /// or [`FACES`] for a flying robot), the place reached, its rise in voxels, and whether
    /// rock is beside it.
    fn moves_now(&self, p: Place, mut f: impl FnMut(usize, Place, i32, bool)) {
        if self.flies {
            for (i, d) in FACES.iter().enumerate() {
                let q = p.at(*d);
                if self.is_place(q) {
                    f(i, q, 0, false);
                }
            }
            return;
        }
        for (i, d) in AROUND.iter().enumerate() {
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
                f(i, q, dz, self.beside_rock(q));
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

/// A move's cost in tenths of a voxel: a step (diagonal: 14), four more a voxel up or down,
/// [`BESIDE_ROCK`] more onto a place beside rock; a flying robot's steps cost 10.
pub(super) fn move_cost(flies: bool, diagonal: bool, dz: i32, rock: bool) -> u32 {
    if flies {
        return 10;
    }
    let mut cost = if diagonal { 14 } else { 10 } + if dz != 0 { 4 } else { 0 };
    if rock {
        cost += BESIDE_ROCK;
    }
    cost
}

#[cfg(test)]
mod tests {
    use rustc_hash::FxHashSet;

    use super::*;
    use crate::body::Body;

    /// A number in [0, 1) from a voxel and a round (splitmix64).
    fn noise(v: [i32; 3], round: u64) -> f64 {
        let mut z = (v[0] as u64) ^ ((v[1] as u64) << 20) ^ ((v[2] as u64) << 40) ^ (round << 60);
        z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49eb_133d_1111);
        (z ^ (z >> 31)) as f64 / 2f64.powi(64)
    }

    /// Carves round `round` of a rough passage into columns `xs`: floors rising with x and
    /// stepping here and there, walls, a ceiling, a pillar, and columns left unseen.
    fn carve(map: &mut VoxelMap, xs: std::ops::Range<i32>, round: u64) {
        let g = map.grid;
        for x in xs {
            for y in 0..g.n[1] as i32 {
                let seen = noise([x, y, 0], round);
                if seen < 0.12 {
                    continue;
                }
                let floor = 2 + x / 10 + i32::from(noise([x, y, 1], round) < 0.2);
                let wall = !(4..g.n[1] as i32 - 4).contains(&y) || (x % 11 == 5 && y % 9 == 4);
                for z in floor..(floor + 6).min(g.n[2] as i32) {
                    let v = [x, y, z];
                    if z == floor || wall || z == floor + 5 {
                        let bottom = g.origin[2] + f64::from(z) * g.voxel;
                        map.set_occupied_at(v, bottom + noise(v, round) * g.voxel);
                    } else if noise(v, round + 7) > 0.05 {
                        map.set_free(v);
                    }
                }
            }
        }
    }

    /// Every voxel of the grid.
    fn all(g: &Grid) -> impl Iterator<Item = [i32; 3]> + use<> {
        let n = g.n.map(|n| n as i32);
        (0..n[2]).flat_map(move |z| (0..n[1]).flat_map(move |y| (0..n[0]).map(move |x| [x, y, z])))
    }

    /// A voxel's answers: a place, a frontier, the moves out.
    type Answers = (bool, bool, Vec<(Place, u32)>);

    /// Every voxel's answers from `space`.
    fn answers(space: &Space<'_>, g: &Grid) -> Vec<Answers> {
        let mut out = Vec::new();
        let mut near = Vec::new();
        for z in -1..=g.n[2] as i32 {
            for y in -1..=g.n[1] as i32 {
                for x in -1..=g.n[0] as i32 {
                    let p = Place([x, y, z]);
                    let place = space.is_place(p);
                    let frontier = place && space.is_frontier(p);
                    if place {
                        space.neighbours(p, &mut near);
                    } else {
                        near.clear();
                    }
                    out.push((place, frontier, near.clone()));
                }
            }
        }
        out
    }

    #[test]
    fn kept_answers_are_the_answers_worked_out_afresh_as_the_map_changes() {
        let g = Grid {
            origin: [0.0, 0.0, 0.0],
            voxel: 0.5,
            n: [56, 24, 14],
        };
        for body in ["ground", "aerial"] {
            let body = Body::named(body).unwrap();
            let mut map = VoxelMap::new(g, 1 << 30).unwrap();
            let mut blocked = FxHashSet::default();
            let mut places = Places::default();
            let mut kept_any = 0;
            for round in 0..7u64 {
                // More of the passage each round; in the last round's part the gaps seen
                // (free only), and in the part before it floors seen higher (heights only):
                // each kind of change must reach what was kept.
                let x0 = round as i32 * 8;
                carve(&mut map, x0..x0 + 8, 0);
                if round >= 2 {
                    let xs = x0 - 16..x0 - 8;
                    let mut gaps = 0;
                    for v in all(&g).filter(|v| xs.contains(&v[0])) {
                        let floored = map.is_occupied([v[0], v[1], v[2] - 1])
                            || map.is_free([v[0], v[1], v[2] - 1]);
                        if map.get(v) == crate::map::Voxel::Unknown && floored {
                            map.set_free(v);
                            gaps += 1;
                        }
                    }
                    assert!(gaps > 0);
                }
                if round >= 4 {
                    let xs = x0 - 32..x0 - 24;
                    for v in all(&g).filter(|v| xs.contains(&v[0]) && v[1] % 3 == 0) {
                        if map.is_occupied(v) {
                            let top = g.origin[2] + (f64::from(v[2]) + 0.99) * g.voxel;
                            map.set_occupied_at(v, top);
                        }
                    }
                }
                let at = [2.0 + 4.0 * round as f64, 6.0, 1.5 + 0.5 * round as f64];
                if round == 6 {
                    // A place far from the robot, kept, then found undrivable.
                    let fresh = Space::around(&map, &body, at, &blocked);
                    let p = all(&g)
                        .map(Place)
                        .find(|&p| p.0[0] < 8 && fresh.is_place(p))
                        .unwrap();
                    drop(fresh);
                    blocked.insert(p.key());
                }
                let fresh = Space::around(&map, &body, at, &blocked);
                let expected = answers(&fresh, &g);
                let kept = Space::around(&map, &body, at, &blocked).keeping(&mut places);
                let got = answers(&kept, &g);
                drop(kept);
                kept_any = kept_any.max(places.len());
                assert_eq!(expected.len(), got.len());
                for (i, (e, k)) in expected.iter().zip(&got).enumerate() {
                    assert_eq!(e, k, "voxel {i} in round {round} of a {:?}", body.flies());
                }
                assert!(
                    expected.iter().filter(|a| a.1).count() > 10,
                    "the test's map has frontiers"
                );
            }
            assert!(kept_any > 10, "chunks kept: {kept_any}");
        }
    }
}
