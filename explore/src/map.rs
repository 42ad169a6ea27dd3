//! The map a robot builds from its scans: voxels that are unknown, free (a ray passed through)
//! or occupied (a ray ended there), over the world's box.
//!
//! Voxels live in chunks of 8 x 8 x 8, two bits each (free, occupied) in 16 words, allocated
//! only where a ray goes, and found through a two-level table: a dense grid of blocks of
//! 16 x 16 x 16 chunks over the world's box (a few thousand entries), each block's table of
//! chunk indices allocated when a ray first enters it. A map holds the passages seen and their
//! walls, not the world's box (a 1.1 km cave's box at 0.5 m is 1.2 billion voxels; the passages
//! a robot sees in 30 minutes are a few hundred thousand chunks at most), and finding a voxel
//! is two array reads (a hash of the chunk's coordinates cost a third of a scan's carving).
//! Its size is bounded: a chunk is 128 bytes and a block's table 16 KiB, and there are no
//! more of either than the box holds, which [`VoxelMap::new`] checks against a limit.
//!
//! A scan is carved in by walking returned rays through the voxels they cross (the algorithm
//! of Amanatides and Woo, 1987): the voxels before a ray's end are free, the one it ends in is
//! occupied. Every ray's end is taken, but free space only from every second ray, in a
//! checkerboard over the ranges image: at 2 degrees between rays and 0.5 m voxels,
//! neighbouring rays cross the same voxels up to 14 m out, and walking half of them halves
//! the carving (a third of a step's time) for a map that differs only at the far ends of long
//! rays, which the next scans fill. Occupied wins: a voxel a ray ended in stays occupied when another
//! ray grazes it (walls are thin in voxels; a graze must not open them).
//!
//! Maps merge (a robot meeting another over the radio takes the other's voxels): free and
//! occupied bits are ORed, occupied winning, so merging is the same in any order. Each chunk
//! carries the clock of its last change, so a robot sends another only the chunks changed
//! since it last sent to it ([`VoxelMap::patch_since`]), not its whole map every second.

use crate::error::ExploreError;
use crate::lidar::Scan;

/// Voxels along each side of a chunk.
const SIDE: i32 = 8;
/// Chunks along each side of a block.
const BLOCK: i32 = 16;
/// Bytes a chunk takes, with its coordinates and its voxels' heights.
pub const CHUNK_BYTES: u64 = 140 + 512;
/// Bytes a block's table takes.
pub const BLOCK_BYTES: u64 = 4 * 16 * 16 * 16;
/// No chunk (or no block) here.
const NONE: u32 = u32::MAX;

/// What a voxel is known to be.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Voxel {
    /// Never seen.
    Unknown,
    /// A ray passed through.
    Free,
    /// A ray ended there.
    Occupied,
}

/// A regular grid: voxel `[i, j, k]` spans `origin + [i, j, k] * voxel` to one voxel more.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grid {
    /// The low corner, metres.
    pub origin: [f64; 3],
    /// Voxel edge, metres.
    pub voxel: f64,
    /// Voxels along x, y, z.
    pub n: [usize; 3],
}

impl Grid {
    /// A grid over `bounds` (low and high corners) grown by `margin` metres on every side.
    pub fn covering(bounds: [[f64; 3]; 2], voxel: f64, margin: f64) -> Grid {
        let origin = bounds[0].map(|v| v - margin);
        let n = [0, 1, 2]
            .map(|k| (((bounds[1][k] + margin - origin[k]) / voxel).ceil()).max(1.0) as usize);
        Grid { origin, voxel, n }
    }

    /// The voxel holding `p`, if inside.
    pub fn voxel_of(&self, p: [f64; 3]) -> Option<[i32; 3]> {
        let mut out = [0i32; 3];
        for k in 0..3 {
            let t = ((p[k] - self.origin[k]) / self.voxel).floor();
            if !(t >= 0.0 && t < self.n[k] as f64) {
                return None;
            }
            out[k] = t as i32;
        }
        Some(out)
    }

    /// The centre of voxel `v`.
    pub fn centre(&self, v: [i32; 3]) -> [f64; 3] {
        [0, 1, 2].map(|k| self.origin[k] + (f64::from(v[k]) + 0.5) * self.voxel)
    }

    /// Whether `v` is inside.
    pub fn contains(&self, v: [i32; 3]) -> bool {
        (0..3).all(|k| v[k] >= 0 && (v[k] as usize) < self.n[k])
    }

    /// Chunks the box holds.
    pub fn chunks(&self) -> u64 {
        self.n
            .iter()
            .map(|&n| n.div_ceil(SIDE as usize) as u64)
            .product()
    }
}

#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Chunk {
    /// One word per layer (z within the chunk), bit `y * 8 + x`.
    free: [u64; 8],
    occupied: [u64; 8],
}

/// What a scan added to the map.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Added {
    /// Voxels newly known free.
    pub free: u64,
    /// Voxels newly known occupied.
    pub occupied: u64,
}

/// A robot's voxel map.
#[derive(Clone, Debug)]
pub struct VoxelMap {
    /// The grid.
    pub grid: Grid,
    /// Blocks along x, y, z.
    blocks: [usize; 3],
    /// Per block (x fastest), its table's index in `tables`, or [`NONE`].
    top: Vec<u32>,
    /// Per allocated block, its chunks' indices (x fastest), or [`NONE`].
    tables: Vec<Box<[u32; 4096]>>,
    chunks: Vec<Chunk>,
    /// Each chunk's coordinates, in chunks.
    coords: Vec<[i32; 3]>,
    /// Per chunk, each occupied voxel's highest return, in 255ths of the voxel above its
    /// bottom, plus one (0: none recorded): a floor's height within its voxel, which slopes
    /// a voxel cannot show are told by.
    tops: Vec<[u8; 512]>,
    /// Per chunk, the clock when it last changed (or was entered by a ray).
    stamps: Vec<u64>,
    /// Advanced by [`VoxelMap::mark`]: what changed after a mark has a later stamp.
    clock: u64,
    /// Per chunk, [`VoxelMap::edits`] when its voxels or heights last changed (entering
    /// alone does not count): what a planner kept of a chunk stands while this is no later.
    edited: Vec<u64>,
    /// Changes made so far, counted one by one.
    edits: u64,
    /// Voxels known free.
    pub free: u64,
    /// Voxels known occupied.
    pub occupied: u64,
}

fn split(v: [i32; 3]) -> ([i32; 3], usize, u64) {
    let c = [v[0] >> 3, v[1] >> 3, v[2] >> 3];
    let bit = 1u64 << (((v[1] & 7) << 3) | (v[0] & 7));
    (c, (v[2] & 7) as usize, bit)
}

impl VoxelMap {
    /// An empty map over `grid`, refused when its box could need more than `limit` bytes.
    pub fn new(grid: Grid, limit: u64) -> Result<VoxelMap, ExploreError> {
        let span = (SIDE * BLOCK) as usize;
        let blocks = grid.n.map(|n| n.div_ceil(span));
        let block_count = blocks.iter().map(|&b| b as u64).product::<u64>();
        let worst = grid
            .chunks()
            .saturating_mul(CHUNK_BYTES)
            .saturating_add(block_count.saturating_mul(BLOCK_BYTES + 4));
        if grid.n.iter().any(|&n| n >= 1 << 21) || worst > limit {
            return Err(ExploreError::MapTooLarge {
                voxel_m: grid.voxel,
                needed_mib: worst >> 20,
                limit_mib: limit >> 20,
            });
        }
        Ok(VoxelMap {
            grid,
            blocks,
            top: vec![NONE; block_count as usize],
            tables: Vec::new(),
            chunks: Vec::new(),
            coords: Vec::new(),
            tops: Vec::new(),
            stamps: Vec::new(),
            clock: 0,
            edited: Vec::new(),
            edits: 0,
            free: 0,
            occupied: 0,
        })
    }

    /// Bytes the map holds now.
    pub fn bytes(&self) -> u64 {
        self.chunks.len() as u64 * CHUNK_BYTES
            + self.tables.len() as u64 * BLOCK_BYTES
            + self.top.len() as u64 * 4
    }

    /// Where chunk `c`'s index lives: its block's number and its slot in the block's table.
    fn slot(&self, c: [i32; 3]) -> (usize, usize) {
        let b = [c[0] >> 4, c[1] >> 4, c[2] >> 4].map(|v| v as usize);
        let block = b[0] + self.blocks[0] * (b[1] + self.blocks[1] * b[2]);
        let l = [c[0] & 15, c[1] & 15, c[2] & 15].map(|v| v as usize);
        (block, l[0] + 16 * (l[1] + 16 * l[2]))
    }

    /// Chunk `c`'s index, if allocated (`c` within the grid).
    fn find(&self, c: [i32; 3]) -> Option<u32> {
        let (block, slot) = self.slot(c);
        let t = self.top[block];
        if t == NONE {
            return None;
        }
        let i = self.tables[t as usize][slot];
        (i != NONE).then_some(i)
    }

    /// Chunk `c`'s index, allocated when missing (`c` within the grid).
    fn find_or_add(&mut self, c: [i32; 3]) -> u32 {
        let (block, slot) = self.slot(c);
        let mut t = self.top[block];
        if t == NONE {
            t = self.tables.len() as u32;
            self.tables.push(Box::new([NONE; 4096]));
            self.top[block] = t;
        }
        let entry = &mut self.tables[t as usize][slot];
        if *entry == NONE {
            *entry = self.chunks.len() as u32;
            self.chunks.push(Chunk::default());
            self.coords.push(c);
            self.tops.push([0; 512]);
            self.stamps.push(0);
            self.edited.push(0);
        }
        let i = *entry;
        self.stamps[i as usize] = self.clock;
        i
    }

    /// Counts a change to chunk `i`'s voxels or heights.
    fn edit(&mut self, i: usize) {
        self.edits += 1;
        self.edited[i] = self.edits;
    }

    /// Changes to voxels and heights made so far (each counted; see [`VoxelMap::edited_near`]).
    pub fn edits(&self) -> u64 {
        self.edits
    }

    /// The latest of [`VoxelMap::edits`] at which chunk `c` (chunk coordinates: a voxel's over
    /// eight) or one of the 26 around it changed; 0 when none has since the map began. What was
    /// worked out from the voxels within three of a chunk when the count was `n` stands while
    /// this is at most `n`.
    pub fn edited_near(&self, c: [i32; 3]) -> u64 {
        let span = self.grid.n.map(|n| n.div_ceil(SIDE as usize) as i32);
        let mut latest = 0;
        for dz in -1..=1 {
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let d = [c[0] + dx, c[1] + dy, c[2] + dz];
                    if (0..3).any(|a| d[a] < 0 || d[a] >= span[a]) {
                        continue;
                    }
                    if let Some(i) = self.find(d) {
                        latest = latest.max(self.edited[i as usize]);
                    }
                }
            }
        }
        latest
    }

    /// Chunks allocated.
    pub fn chunk_count(&self) -> usize {
        self.chunks.len()
    }

    /// What voxel `v` is known to be (outside the grid: unknown).
    pub fn get(&self, v: [i32; 3]) -> Voxel {
        if !self.grid.contains(v) {
            return Voxel::Unknown;
        }
        let (c, layer, bit) = split(v);
        match self.find(c) {
            None => Voxel::Unknown,
            Some(i) => {
                let ch = &self.chunks[i as usize];
                if ch.occupied[layer] & bit != 0 {
                    Voxel::Occupied
                } else if ch.free[layer] & bit != 0 {
                    Voxel::Free
                } else {
                    Voxel::Unknown
                }
            }
        }
    }

    /// Whether `v` is occupied.
    pub fn is_occupied(&self, v: [i32; 3]) -> bool {
        self.get(v) == Voxel::Occupied
    }

    /// Whether `v` is free.
    pub fn is_free(&self, v: [i32; 3]) -> bool {
        self.get(v) == Voxel::Free
    }

    /// Marks `v` free (unless occupied); returns whether it was unknown.
    pub fn set_free(&mut self, v: [i32; 3]) -> bool {
        let (c, layer, bit) = split(v);
        let i = self.find_or_add(c) as usize;
        let ch = &mut self.chunks[i];
        let new = (ch.free[layer] | ch.occupied[layer]) & bit == 0;
        if new {
            // An occupied voxel stays occupied (and out of the free list).
            ch.free[layer] |= bit;
            self.free += 1;
            self.edit(i);
        }
        new
    }

    /// Marks `v` occupied; returns whether it was not.
    pub fn set_occupied(&mut self, v: [i32; 3]) -> bool {
        let (c, layer, bit) = split(v);
        let i = self.find_or_add(c) as usize;
        let ch = &mut self.chunks[i];
        let was_free = ch.free[layer] & bit != 0;
        let new = ch.occupied[layer] & bit == 0;
        ch.occupied[layer] |= bit;
        ch.free[layer] &= !bit;
        if new {
            self.occupied += 1;
            if was_free {
                self.free -= 1;
            }
            self.edit(i);
        }
        new
    }

    /// Marks `v` occupied with a return at height `z` (kept when the highest in it).
    pub fn set_occupied_at(&mut self, v: [i32; 3], z: f64) -> bool {
        let bottom = self.grid.origin[2] + f64::from(v[2]) * self.grid.voxel;
        let q = (((z - bottom) / self.grid.voxel).clamp(0.0, 1.0) * 254.0).round() as u8 + 1;
        let (c, layer, bit) = split(v);
        let i = self.find_or_add(c) as usize;
        let slot = (v[0] & 7) as usize | (((v[1] & 7) as usize) << 3) | (layer << 6);
        let t = &mut self.tops[i][slot];
        let higher = q > *t;
        *t = (*t).max(q);
        let ch = &mut self.chunks[i];
        let was_free = ch.free[layer] & bit != 0;
        let new = ch.occupied[layer] & bit == 0;
        ch.occupied[layer] |= bit;
        ch.free[layer] &= !bit;
        if new {
            self.occupied += 1;
            if was_free {
                self.free -= 1;
            }
        }
        if new || higher {
            self.edit(i);
        }
        new
    }

    /// The highest return recorded in occupied voxel `v`, metres (a floor's top).
    pub fn top(&self, v: [i32; 3]) -> Option<f64> {
        if !self.grid.contains(v) {
            return None;
        }
        let (c, _, _) = split(v);
        let i = self.find(c)? as usize;
        let slot =
            (v[0] & 7) as usize | (((v[1] & 7) as usize) << 3) | (((v[2] & 7) as usize) << 6);
        let q = self.tops[i][slot];
        (q > 0).then(|| {
            self.grid.origin[2] + (f64::from(v[2]) + f64::from(q - 1) / 254.0) * self.grid.voxel
        })
    }

    /// Carves a scan in: each returned ray's voxels free up to its end, its end occupied.
    pub fn insert(&mut self, scan: &Scan) -> Added {
        let (free0, occ0) = (self.free, self.occupied);
        let mut walker = Walker::default();
        let rings = scan.dirs.len() / scan.columns.len().max(1);
        for (k, d) in scan.dirs.iter().enumerate() {
            let r = f64::from(scan.ranges[k]);
            if r <= 0.0 {
                continue;
            }
            // Free space from every second ray, in a checkerboard over the ranges image.
            let column = scan.columns.get(k / rings.max(1)).copied().unwrap_or(0);
            if (column as usize + k % rings.max(1)) % 2 == 0 {
                self.ray(&mut walker, scan.origin, *d, r);
            } else {
                let end = [0, 1, 2].map(|a| scan.origin[a] + r * d[a]);
                if let Some(v) = self.grid.voxel_of(end) {
                    self.set_occupied_at(v, end[2]);
                }
            }
        }
        Added {
            free: self.free.saturating_sub(free0),
            occupied: self.occupied.saturating_sub(occ0),
        }
    }

    /// One ray from `o` along unit `d`, ending `r` metres on.
    fn ray(&mut self, walker: &mut Walker, o: [f64; 3], d: [f64; 3], r: f64) {
        let g = self.grid;
        let end = [o[0] + r * d[0], o[1] + r * d[1], o[2] + r * d[2]];
        let Some(mut v) = g.voxel_of(o) else {
            return;
        };
        let last = g.voxel_of(end);
        let mut step = [0i32; 3];
        let mut t_max = [f64::INFINITY; 3];
        let mut t_delta = [f64::INFINITY; 3];
        for k in 0..3 {
            if d[k] > 0.0 {
                step[k] = 1;
                let edge = g.origin[k] + (f64::from(v[k]) + 1.0) * g.voxel;
                t_max[k] = (edge - o[k]) / d[k];
                t_delta[k] = g.voxel / d[k];
            } else if d[k] < 0.0 {
                step[k] = -1;
                let edge = g.origin[k] + f64::from(v[k]) * g.voxel;
                t_max[k] = (edge - o[k]) / d[k];
                t_delta[k] = -g.voxel / d[k];
            }
        }
        // Free voxels are set through the chunk in hand, looked up again only when the walk
        // leaves it.
        walker.chunk = None;
        loop {
            if Some(v) == last {
                break;
            }
            let t_next = t_max[0].min(t_max[1]).min(t_max[2]);
            if t_next >= r {
                break;
            }
            self.free_cached(walker, v);
            let k = if t_max[0] <= t_max[1] && t_max[0] <= t_max[2] {
                0
            } else if t_max[1] <= t_max[2] {
                1
            } else {
                2
            };
            v[k] += step[k];
            t_max[k] += t_delta[k];
            if !g.contains(v) {
                return;
            }
        }
        if let Some(l) = last {
            self.set_occupied_at(l, end[2]);
        }
    }

    fn free_cached(&mut self, walker: &mut Walker, v: [i32; 3]) {
        let (c, layer, bit) = split(v);
        let i = match walker.chunk {
            Some((cc, i)) if cc == c => i,
            _ => {
                // (Stamped by `find_or_add`.)
                let i = self.find_or_add(c);
                walker.chunk = Some((c, i));
                i
            }
        };
        let ch = &mut self.chunks[i as usize];
        if (ch.free[layer] | ch.occupied[layer]) & bit == 0 {
            ch.free[layer] |= bit;
            self.free += 1;
            self.edit(i as usize);
        }
    }

    /// Takes every voxel `other` knows (same grid): free and occupied ORed, occupied winning.
    pub fn merge(&mut self, other: &VoxelMap) {
        self.apply(&other.patch_since(None));
    }

    /// Ends a round of changes: returns the clock before, which every change so far is
    /// stamped at or below and every later one above.
    pub fn mark(&mut self) -> u64 {
        self.clock += 1;
        self.clock - 1
    }

    /// The chunks changed after the mark `since` (all with `None`), to send to another map.
    pub fn patch_since(&self, since: Option<u64>) -> Patch {
        let mut p = Patch::default();
        for (j, &stamp) in self.stamps.iter().enumerate() {
            if since.is_none_or(|s| stamp > s) {
                p.coords.push(self.coords[j]);
                p.chunks.push(self.chunks[j]);
                p.tops.push(self.tops[j]);
            }
        }
        p
    }

    /// Takes a patch's voxels: free and occupied ORed, occupied winning, the highest tops.
    /// Only the chunks this changes are stamped (so what comes back unchanged is not sent on
    /// again).
    pub fn apply(&mut self, patch: &Patch) {
        for (k, &c) in patch.coords.iter().enumerate() {
            let theirs = patch.chunks[k];
            let (i, new) = match self.find(c) {
                Some(i) => (i as usize, false),
                None => (self.find_or_add(c) as usize, true),
            };
            let mut changed = new;
            for (a, b) in self.tops[i].iter_mut().zip(patch.tops[k].iter()) {
                if *b > *a {
                    *a = *b;
                    changed = true;
                }
            }
            let ch = &mut self.chunks[i];
            for l in 0..8 {
                let (f0, o0) = (ch.free[l], ch.occupied[l]);
                ch.occupied[l] |= theirs.occupied[l];
                ch.free[l] = (ch.free[l] | theirs.free[l]) & !ch.occupied[l];
                if (f0, o0) != (ch.free[l], ch.occupied[l]) {
                    changed = true;
                    self.free =
                        self.free + u64::from(ch.free[l].count_ones()) - u64::from(f0.count_ones());
                    self.occupied = self.occupied + u64::from(ch.occupied[l].count_ones())
                        - u64::from(o0.count_ones());
                }
            }
            if changed {
                self.stamps[i] = self.clock;
                self.edit(i);
            }
        }
    }

    /// Every voxel in `state`, in a fixed order (chunks by their coordinates, then voxels).
    pub fn voxels(&self, state: Voxel) -> Vec<[i32; 3]> {
        let mut order: Vec<([i32; 3], usize)> = self
            .coords
            .iter()
            .enumerate()
            .map(|(i, c)| ([c[2], c[1], c[0]], i))
            .collect();
        order.sort_unstable();
        let mut out = Vec::new();
        for (_, i) in order {
            let c = self.coords[i];
            let ch = &self.chunks[i];
            for layer in 0..8 {
                let mut bits = match state {
                    Voxel::Free => ch.free[layer],
                    Voxel::Occupied => ch.occupied[layer],
                    Voxel::Unknown => !(ch.free[layer] | ch.occupied[layer]),
                };
                while bits != 0 {
                    let b = bits.trailing_zeros() as i32;
                    bits &= bits - 1;
                    let v = [
                        c[0] * SIDE + (b & 7),
                        c[1] * SIDE + (b >> 3),
                        c[2] * SIDE + layer as i32,
                    ];
                    if self.grid.contains(v) {
                        out.push(v);
                    }
                }
            }
        }
        out
    }
}

/// Chunks of a map, sent to another ([`VoxelMap::patch_since`], [`VoxelMap::apply`]).
#[derive(Clone, Debug, Default)]
pub struct Patch {
    coords: Vec<[i32; 3]>,
    chunks: Vec<Chunk>,
    tops: Vec<[u8; 512]>,
}

impl Patch {
    /// Chunks it holds.
    pub fn len(&self) -> usize {
        self.coords.len()
    }

    /// Whether it holds none.
    pub fn is_empty(&self) -> bool {
        self.coords.is_empty()
    }
}

/// The chunk a ray's walk is in.
#[derive(Default)]
struct Walker {
    chunk: Option<([i32; 3], u32)>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid() -> Grid {
        Grid {
            origin: [0.0; 3],
            voxel: 0.5,
            n: [40, 40, 20],
        }
    }

    #[test]
    fn a_ray_frees_what_it_crosses_and_occupies_where_it_ends() {
        let mut map = VoxelMap::new(grid(), 1 << 30).unwrap();
        let scan = Scan {
            origin: [1.25, 1.25, 1.25],
            dirs: vec![[1.0, 0.0, 0.0]],
            ranges: vec![5.0],
            columns: vec![0],
        };
        let added = map.insert(&scan);
        // From the voxel at 1.0-1.5 to the one at 6.0-6.5: 10 free, 1 occupied.
        assert_eq!(
            added,
            Added {
                free: 10,
                occupied: 1
            }
        );
        assert_eq!(map.get([2, 2, 2]), Voxel::Free);
        assert_eq!(map.get([11, 2, 2]), Voxel::Free);
        assert_eq!(map.get([12, 2, 2]), Voxel::Occupied);
        assert_eq!(map.get([13, 2, 2]), Voxel::Unknown);
        assert_eq!(map.get([2, 3, 2]), Voxel::Unknown);
        // Again: nothing new; a graze through the wall does not open it.
        assert_eq!(map.insert(&scan), Added::default());
        map.set_free([12, 2, 2]);
        assert_eq!(map.get([12, 2, 2]), Voxel::Occupied);
        assert_eq!(map.voxels(Voxel::Free).len() as u64, map.free);
        assert_eq!(map.voxels(Voxel::Occupied), vec![[12, 2, 2]]);
    }

    #[test]
    fn a_diagonal_ray_visits_connected_voxels_and_merging_is_symmetric() {
        let mut a = VoxelMap::new(grid(), 1 << 30).unwrap();
        let d = [0.6f64, 0.48, 0.64];
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let scan = Scan {
            origin: [0.3, 0.2, 0.1],
            dirs: vec![d.map(|x| x / n)],
            ranges: vec![7.0],
            columns: vec![0],
        };
        a.insert(&scan);
        let mut free = a.voxels(Voxel::Free);
        free.sort();
        // Each voxel after the first touches one before it through a face.
        for w in free.windows(2) {
            assert!(w.iter().all(|v| a.is_free(*v)));
        }
        let mut b = VoxelMap::new(grid(), 1 << 30).unwrap();
        b.set_occupied([0, 0, 0]);
        b.set_free([30, 30, 10]);
        let mut ab = a.clone();
        ab.merge(&b);
        let mut ba = b.clone();
        ba.merge(&a);
        for s in [Voxel::Free, Voxel::Occupied] {
            assert_eq!(ab.voxels(s), ba.voxels(s));
        }
        assert_eq!((ab.free, ab.occupied), (ba.free, ba.occupied));
        assert_eq!(ab.get([0, 0, 0]), Voxel::Occupied);
    }

    #[test]
    fn every_change_and_only_a_change_is_counted_where_it_was_made() {
        let mut map = VoxelMap::new(grid(), 1 << 30).unwrap();
        let far = [4, 4, 2];
        assert_eq!(map.edited_near(far), 0);
        // A ray's free voxels alone (its end already occupied, no higher).
        map.set_occupied_at([12, 2, 2], 1.3);
        let scan = Scan {
            origin: [1.25, 1.25, 1.25],
            dirs: vec![[1.0, 0.0, 0.0]],
            ranges: vec![5.0],
            columns: vec![0],
        };
        let before = map.edited_near([0, 0, 0]);
        map.insert(&scan);
        let after = map.edited_near([0, 0, 0]);
        assert!(after > before, "{before} {after}");
        // The same scan again changes nothing.
        map.insert(&scan);
        assert_eq!(map.edited_near([0, 0, 0]), after);
        // A higher return in an occupied voxel is a change; a lower one is not.
        map.set_occupied_at([12, 2, 2], 1.4);
        let higher = map.edited_near([1, 0, 0]);
        assert!(higher > after);
        map.set_occupied_at([12, 2, 2], 1.2);
        assert_eq!(map.edited_near([1, 0, 0]), higher);
        // A voxel freed alone, and a voxel taken from another map.
        map.set_free([3, 5, 2]);
        assert!(map.edited_near([0, 0, 0]) > higher);
        let mut other = VoxelMap::new(grid(), 1 << 30).unwrap();
        other.set_occupied([30, 30, 10]);
        let e = map.edits();
        map.merge(&other);
        assert!(map.edited_near(far) > e);
        // Chunks more than one away from a change see none.
        assert_eq!(map.edited_near([0, 4, 0]), 0);
        // Merging the same again changes nothing.
        let e = map.edits();
        map.merge(&other);
        assert_eq!(map.edits(), e);
    }

    #[test]
    fn a_map_too_large_is_refused() {
        let g = Grid {
            origin: [0.0; 3],
            voxel: 0.01,
            n: [100_000, 100_000, 1000],
        };
        let e = VoxelMap::new(g, 1 << 30).unwrap_err().to_string();
        assert!(e.contains("larger voxel"), "{e}");
    }
}
