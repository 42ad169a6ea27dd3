//! What a robot's planner keeps of its map between plans: for each chunk of the map (8 x 8 x 8
//! voxels), which voxels are places, which places are frontiers, and the moves out of each
//! place ([`super::space`] says what these are), worked out again only when the map changed
//! within a chunk of it, or the robot found a place it could not drive into.
//!
//! Why: every plan searches the places within reach of the robot, which late in a mission is
//! most of the passages it has seen (several hundred metres), and each answer reads a dozen
//! voxels around the place; worked out afresh for every plan (each robot every three seconds),
//! that was two thirds of a 30-minute mission's time, though far from the robot its map had not
//! changed. The map counts its changes and stamps each chunk with the count at its last one
//! ([`VoxelMap::edited_near`]), so what was worked out for a chunk stands while no chunk around
//! it changed after.
//!
//! **The same answers**: near the robot (within [`super::space::BLIND_M`] and two voxels, up
//! to two voxels up or down) a ground robot's answers depend on where it stands (its unseen
//! floor is taken as known), so there [`super::space::Space`] works them out for each plan as before; what is
//! kept was worked out as if the robot were far away, which is what the answers are everywhere
//! else. The moves are kept in the order they are worked out, so a search meets places in the
//! same order and the plans are the same to the bit.
//!
//! **Bounded**: a chunk keeps 64 bytes and 4 per place; only chunks a search reached are kept,
//! and when there are more than twice the map's chunks (and a few thousand) all are dropped.

use rustc_hash::FxHashMap;

use crate::map::VoxelMap;

/// A place's kept answers: bit 31 set for a place, bit 30 for a frontier, and three bits a
/// direction (the space's eight neighbouring columns, or six faces for a flying robot): the
/// move's rise (0: no move, 1: level, 2: a voxel up, 3: a voxel down) and, above it, whether
/// rock is beside where it leads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Kept(u32);

const PLACE: u32 = 1 << 31;
const FRONTIER: u32 = 1 << 30;

impl Kept {
    /// A place's answers: a frontier or not, and its moves as [`Kept::moves`] gives them.
    pub fn place(frontier: bool, moves: impl IntoIterator<Item = (usize, i32, bool)>) -> Kept {
        let mut k = PLACE;
        if frontier {
            k |= FRONTIER;
        }
        for (i, rise, rock) in moves {
            let code = match rise {
                0 => 1,
                1 => 2,
                _ => 3,
            } | if rock { 4 } else { 0 };
            k |= code << (3 * i);
        }
        Kept(k)
    }

    /// Whether a robot can be there.
    pub fn is_place(self) -> bool {
        self.0 & PLACE != 0
    }

    /// Whether the place borders the unknown.
    pub fn is_frontier(self) -> bool {
        self.0 & FRONTIER != 0
    }

    /// The moves out of the place, in order of the first `directions`: each direction's
    /// index, the rise and whether rock is beside where it leads.
    pub fn moves(self, directions: usize, mut f: impl FnMut(usize, i32, bool)) {
        for i in 0..directions {
            let code = (self.0 >> (3 * i)) & 7;
            let rise = match code & 3 {
                0 => continue,
                1 => 0,
                2 => 1,
                _ => -1,
            };
            f(i, rise, code & 4 != 0);
        }
    }
}

/// A chunk's answers as worked out: its places (a word per layer, bit `y * 8 + x`, as the
/// map's) and each place's answers in the order of those bits, layer by layer.
#[derive(Clone, Debug, Default)]
pub struct Worked {
    /// The places.
    pub places: [u64; 8],
    /// Their answers.
    pub kept: Vec<Kept>,
}

/// What one chunk keeps.
#[derive(Clone, Debug)]
struct Chunk {
    /// The map's count of changes when this was worked out.
    edits: u64,
    /// The plan it was last found current in.
    checked: u64,
    /// The answers.
    worked: Worked,
}

/// What a robot's planner keeps between plans (see the module's doc).
#[derive(Clone, Debug, Default)]
pub struct Places {
    chunks: FxHashMap<u64, Chunk>,
    /// Plans begun.
    plan: u64,
    /// The map's count of changes when this plan began.
    edits: u64,
    /// How many places the robot had found it could not drive into (they only grow).
    blocked: usize,
}

impl Places {
    /// Begins a plan on `map` with `blocked` places found undrivable.
    pub fn begin(&mut self, map: &VoxelMap, blocked: usize) {
        self.plan += 1;
        self.edits = map.edits();
        if blocked != self.blocked || self.chunks.len() > 2 * map.chunk_count() + 4096 {
            self.chunks.clear();
            self.blocked = blocked;
        }
    }

    /// Chunks kept.
    pub fn len(&self) -> usize {
        self.chunks.len()
    }

    /// Whether none is.
    pub fn is_empty(&self) -> bool {
        self.chunks.is_empty()
    }

    /// Voxel `v`'s answers (`v` within the map's grid), its chunk's worked out by
    /// `work_out` (given the chunk's coordinates: a voxel's over eight) when not kept or no
    /// longer current on `map`.
    pub fn get(
        &mut self,
        map: &VoxelMap,
        v: [i32; 3],
        work_out: impl FnOnce([i32; 3]) -> Worked,
    ) -> Kept {
        let c = [v[0] >> 3, v[1] >> 3, v[2] >> 3];
        let key = (c[0] as u64 & 0x1f_ffff)
            | ((c[1] as u64 & 0x1f_ffff) << 21)
            | ((c[2] as u64 & 0x1f_ffff) << 42);
        let (plan, edits) = (self.plan, self.edits);
        let chunk = match self.chunks.entry(key) {
            std::collections::hash_map::Entry::Occupied(e) => {
                let chunk = e.into_mut();
                if chunk.checked != plan {
                    if map.edited_near(c) > chunk.edits {
                        chunk.worked = work_out(c);
                        chunk.edits = edits;
                    }
                    chunk.checked = plan;
                }
                chunk
            }
            std::collections::hash_map::Entry::Vacant(e) => e.insert(Chunk {
                edits,
                checked: plan,
                worked: work_out(c),
            }),
        };
        let w = &chunk.worked;
        let (layer, bit) = ((v[2] & 7) as usize, ((v[1] & 7) << 3 | (v[0] & 7)) as u32);
        let word = w.places[layer];
        if word >> bit & 1 == 0 {
            return Kept(0);
        }
        let before: u32 = w.places[..layer].iter().map(|w| w.count_ones()).sum();
        let below = (word & ((1u64 << bit) - 1)).count_ones();
        w.kept[(before + below) as usize]
    }
}
