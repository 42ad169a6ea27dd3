//! The search's queue of places to visit, nearest first: a ring of buckets, one per path
//! length (Dial, "Shortest-path forest with topological ordering", CACM 1969), since a move
//! costs a small whole number of tenths of a voxel, at most [`MAX_STEP`].
//!
//! Places of one length leave in the order of their keys, as they left the binary heap this
//! replaced (ordered by length, then key), so a search visits places in the same order and
//! the plans are the same to the bit; a push and a pop cost a few instructions instead of a
//! heap's logarithm of the queue (a late search holds tens of thousands).

/// The most a move may cost, tenths of a voxel (a diagonal step up beside rock: 14 + 4 + 20).
pub const MAX_STEP: u32 = 38;
/// Buckets in the ring: more than [`MAX_STEP`], so a bucket holds one length at a time.
const RING: usize = 64;

/// The queue.
#[derive(Clone, Debug)]
pub struct Queue {
    ring: Vec<Vec<u64>>,
    /// The length whose bucket is being emptied.
    at: u32,
    /// Whether that bucket is sorted (largest key first, popped from the end).
    sorted: bool,
    /// Entries held.
    len: usize,
}

impl Default for Queue {
    fn default() -> Self {
        Queue {
            ring: vec![Vec::new(); RING],
            at: 0,
            sorted: false,
            len: 0,
        }
    }
}

impl Queue {
    /// Empties it, keeping its memory, to start again from length 0.
    pub fn clear(&mut self) {
        for b in &mut self.ring {
            b.clear();
        }
        self.at = 0;
        self.sorted = false;
        self.len = 0;
    }

    /// Adds key `k` at length `c`, which is no shorter than the last popped and at most
    /// [`MAX_STEP`] longer.
    pub fn push(&mut self, c: u32, k: u64) {
        debug_assert!(
            c >= self.at && c - self.at <= MAX_STEP,
            "{c} from {}",
            self.at
        );
        if c == self.at {
            // (Only the first push, from length 0: moves cost at least one step.)
            self.sorted = false;
        }
        self.ring[c as usize % RING].push(k);
        self.len += 1;
    }

    /// The shortest length's smallest key, with its length.
    pub fn pop(&mut self) -> Option<(u32, u64)> {
        if self.len == 0 {
            return None;
        }
        loop {
            let bucket = &mut self.ring[self.at as usize % RING];
            if !bucket.is_empty() {
                if !self.sorted {
                    bucket.sort_unstable_by(|a, b| b.cmp(a));
                    self.sorted = true;
                }
                self.len -= 1;
                return bucket.pop().map(|k| (self.at, k));
            }
            self.at += 1;
            self.sorted = false;
        }
    }
}

#[cfg(test)]
mod tests {
    use std::cmp::Reverse;
    use std::collections::BinaryHeap;

    use super::*;

    #[test]
    fn the_dearest_move_fits_the_ring() {
        use crate::planner::space::move_cost;
        let dearest = [false, true]
            .into_iter()
            .flat_map(|diagonal| [-1, 0, 1].map(|rise| (diagonal, rise)))
            .flat_map(|(diagonal, rise)| [false, true].map(|rock| (diagonal, rise, rock)))
            .map(|(diagonal, rise, rock)| move_cost(false, diagonal, rise, rock))
            .chain([move_cost(true, false, 0, false)])
            .max();
        assert_eq!(dearest, Some(MAX_STEP));
        assert!(RING as u32 > MAX_STEP);
    }

    #[test]
    fn places_leave_as_they_leave_a_binary_heap() {
        // A search's pattern: pop one, push a few a step or more further on.
        let mut q = Queue::default();
        let mut heap = BinaryHeap::new();
        let mut state = 12345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            state >> 33
        };
        q.push(0, 7);
        heap.push(Reverse((0u32, 7u64)));
        let mut popped = 0;
        while let Some(Reverse(expected)) = heap.pop() {
            assert_eq!(q.pop(), Some(expected));
            popped += 1;
            if popped < 5000 {
                for _ in 0..(1 + next() % 3) {
                    let c = expected.0 + 10 + (next() % (u64::from(MAX_STEP) - 9)) as u32;
                    // Keys repeat across lengths, and several share a length.
                    let k = next() % 300;
                    q.push(c, k);
                    heap.push(Reverse((c, k)));
                }
            }
        }
        assert_eq!(q.pop(), None);
        assert!(popped > 1000, "{popped}");
    }
}
