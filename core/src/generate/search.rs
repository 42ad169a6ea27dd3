//! Guided shortest paths on a level (paper eqs. 14-15), on the implicit 4-connected grid.
//!
//! The original builds a dense `n^2 x n^2` matrix per path and runs scipy's Dijkstra on it.
//! Here the graph is implicit: a cell's neighbours are computed on the fly, and A* with the
//! Manhattan distance (admissible, since no step costs less than 1) returns the same optimal
//! cost as Dijkstra while expanding a fraction of the cells. Buffers are reused between
//! searches through generation stamps, so a search allocates nothing.
//!
//! Costs: a cell on the route descriptor's guide costs 1, any other allowed cell
//! [`DETOUR_COST`]. The original makes off-guide cells impassable, so a blocked guide silently
//! drops the route; a finite detour cost keeps the route on its guide wherever it can be and
//! still reaches the objective where it cannot.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::topology;

/// Cost of stepping onto a cell off the guide.
pub const DETOUR_COST: u32 = 6;

/// Reusable search buffers for one level size.
#[derive(Debug)]
pub struct Search {
    stamp: u32,
    seen: Vec<u32>,
    guide: Vec<u32>,
    dist: Vec<u32>,
    parent: Vec<u32>,
    heap: BinaryHeap<(Reverse<u32>, Reverse<u32>)>,
}

impl Search {
    /// Buffers for a level of `cells` cells.
    pub fn new(cells: usize) -> Self {
        Self {
            stamp: 0,
            seen: vec![0; cells],
            guide: vec![0; cells],
            dist: vec![0; cells],
            parent: vec![0; cells],
            heap: BinaryHeap::new(),
        }
    }

    /// The cheapest path from `s` to `g` on a `rows x cols` grid (row-major indices) whose
    /// inner cells all satisfy `may_use`. Returns the inner cells (neither `s` nor `g`), in
    /// order, or `None` when `g` cannot be reached.
    pub fn route(
        &mut self,
        [rows, cols]: [usize; 2],
        s: usize,
        g: usize,
        guide: &[[i32; 2]],
        may_use: impl Fn(usize) -> bool,
    ) -> Option<Vec<usize>> {
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.seen.fill(0);
            self.guide.fill(0);
            self.stamp = 1;
        }
        let stamp = self.stamp;
        for &[r, c] in guide {
            if let Some(i) = topology::index(rows, cols, r, c) {
                self.guide[i] = stamp;
            }
        }
        let (gr, gc) = ((g / cols) as i32, (g % cols) as i32);
        let h = |i: usize| {
            let (r, c) = ((i / cols) as i32, (i % cols) as i32);
            ((r - gr).abs() + (c - gc).abs()) as u32
        };
        self.heap.clear();
        self.seen[s] = stamp;
        self.dist[s] = 0;
        self.parent[s] = s as u32;
        self.heap.push((Reverse(h(s)), Reverse(s as u32)));
        while let Some((Reverse(f), Reverse(u))) = self.heap.pop() {
            let u = u as usize;
            if f != self.dist[u] + h(u) {
                continue; // stale entry
            }
            if u == g {
                let mut path = Vec::new();
                let mut v = self.parent[g] as usize;
                while v != s {
                    path.push(v);
                    v = self.parent[v] as usize;
                }
                path.reverse();
                return Some(path);
            }
            let (ur, uc) = ((u / cols) as i32, (u % cols) as i32);
            for (dr, dc) in [(0, 1), (-1, 0), (0, -1), (1, 0)] {
                let Some(v) = topology::index(rows, cols, ur + dr, uc + dc) else {
                    continue;
                };
                if v != g && !may_use(v) {
                    continue;
                }
                let step = if self.guide[v] == stamp {
                    1
                } else {
                    DETOUR_COST
                };
                let d = self.dist[u] + step;
                if self.seen[v] != stamp || d < self.dist[v] {
                    self.seen[v] = stamp;
                    self.dist[v] = d;
                    self.parent[v] = u as u32;
                    self.heap.push((Reverse(d + h(v)), Reverse(v as u32)));
                }
            }
        }
        None
    }
}
