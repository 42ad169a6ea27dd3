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
    /// Per (cell, heading) state, for [`Search::route_turning`]; grown on first use.
    turn_seen: Vec<u32>,
    turn_dist: Vec<u32>,
    turn_parent: Vec<u32>,
}

/// The four steps, in the order the searches try them; a heading is an index into this.
const STEPS: [(i32, i32); 4] = [(0, 1), (-1, 0), (0, -1), (1, 0)];
/// `turn_parent` of a state entered straight from the start cell.
const FROM_START: u32 = u32::MAX;

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
            turn_seen: Vec::new(),
            turn_dist: Vec::new(),
            turn_parent: Vec::new(),
        }
    }

    /// The cheapest path from `s` to `g` on a `rows x cols` grid (row-major indices) whose
    /// inner cells all satisfy `may_use`. Returns the inner cells (neither `s` nor `g`), in
    /// order, or `None` when `g` cannot be reached.
    ///
    /// Every change of direction costs `turn_cost` more (the route descriptor's
    /// [`turn_cost`](crate::route::RouteDescriptor::turn_cost)). With a
    /// positive cost the search runs on (cell, heading) states, so among paths of equal length
    /// the one with the fewest turns wins: a detour around an obstacle is one straight run
    /// and a turn, not a staircase. `0` is the plain search.
    pub fn route(
        &mut self,
        [rows, cols]: [usize; 2],
        s: usize,
        g: usize,
        guide: &[[i32; 2]],
        turn_cost: u32,
        may_use: impl Fn(usize) -> bool,
    ) -> Option<Vec<usize>> {
        self.stamp = self.stamp.wrapping_add(1);
        if self.stamp == 0 {
            self.seen.fill(0);
            self.guide.fill(0);
            self.turn_seen.fill(0);
            self.stamp = 1;
        }
        if turn_cost > 0 {
            return self.turning([rows, cols], s, g, guide, turn_cost, may_use);
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
            for (dr, dc) in STEPS {
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

    /// A* over (cell, heading) states: a step costs as in the plain search plus `turn_cost`
    /// when its heading differs from the previous step's. The first step from `s` is free to
    /// take any heading; no step turns back. The guide is stamped already.
    fn turning(
        &mut self,
        [rows, cols]: [usize; 2],
        s: usize,
        g: usize,
        guide: &[[i32; 2]],
        turn_cost: u32,
        may_use: impl Fn(usize) -> bool,
    ) -> Option<Vec<usize>> {
        let stamp = self.stamp;
        for &[r, c] in guide {
            if let Some(i) = topology::index(rows, cols, r, c) {
                self.guide[i] = stamp;
            }
        }
        let states = 4 * rows * cols;
        if self.turn_seen.len() < states {
            self.turn_seen.resize(states, 0);
            self.turn_dist.resize(states, 0);
            self.turn_parent.resize(states, 0);
        }
        let (gr, gc) = ((g / cols) as i32, (g % cols) as i32);
        let h = |i: usize| {
            let (r, c) = ((i / cols) as i32, (i % cols) as i32);
            ((r - gr).abs() + (c - gc).abs()) as u32
        };
        let step_cost = |guide: &[u32], v: usize| {
            if guide[v] == stamp { 1 } else { DETOUR_COST }
        };
        self.heap.clear();
        let (sr, sc) = ((s / cols) as i32, (s % cols) as i32);
        for (d, (dr, dc)) in STEPS.iter().enumerate() {
            let Some(v) = topology::index(rows, cols, sr + dr, sc + dc) else {
                continue;
            };
            if v == g {
                return Some(Vec::new());
            }
            if !may_use(v) {
                continue;
            }
            let state = 4 * v + d;
            let dist = step_cost(&self.guide, v);
            self.turn_seen[state] = stamp;
            self.turn_dist[state] = dist;
            self.turn_parent[state] = FROM_START;
            self.heap
                .push((Reverse(dist + h(v)), Reverse(state as u32)));
        }
        while let Some((Reverse(f), Reverse(u))) = self.heap.pop() {
            let u = u as usize;
            let (cell, heading) = (u / 4, u % 4);
            if f != self.turn_dist[u] + h(cell) {
                continue; // stale entry
            }
            if cell == g {
                let mut path = Vec::new();
                let mut v = self.turn_parent[u];
                while v != FROM_START {
                    path.push(v as usize / 4);
                    v = self.turn_parent[v as usize];
                }
                path.reverse();
                return Some(path);
            }
            let (ur, uc) = ((cell / cols) as i32, (cell % cols) as i32);
            for (d, (dr, dc)) in STEPS.iter().enumerate() {
                if d == (heading + 2) % 4 {
                    continue; // no turning back
                }
                let Some(v) = topology::index(rows, cols, ur + dr, uc + dc) else {
                    continue;
                };
                if v != g && !may_use(v) {
                    continue;
                }
                let turn = if d == heading { 0 } else { turn_cost };
                let dist = self.turn_dist[u] + step_cost(&self.guide, v) + turn;
                let state = 4 * v + d;
                if self.turn_seen[state] != stamp || dist < self.turn_dist[state] {
                    self.turn_seen[state] = stamp;
                    self.turn_dist[state] = dist;
                    self.turn_parent[state] = u as u32;
                    self.heap
                        .push((Reverse(dist + h(v)), Reverse(state as u32)));
                }
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn turns(path: &[usize], s: usize, g: usize, cols: usize) -> usize {
        let mut cells = vec![s];
        cells.extend_from_slice(path);
        cells.push(g);
        let step = |a: usize, b: usize| {
            (
                b as i64 / cols as i64 - a as i64 / cols as i64,
                b as i64 % cols as i64 - a as i64 % cols as i64,
            )
        };
        cells
            .windows(3)
            .filter(|w| step(w[0], w[1]) != step(w[1], w[2]))
            .count()
    }

    #[test]
    fn a_turn_cost_makes_routes_run_straight() {
        let (rows, cols) = (20, 20);
        let mut search = Search::new(rows * cols);
        let (s, g) = (2 * cols + 2, 14 * cols + 15);
        // No guide: every shortest path costs the same, so only the turn cost tells them apart.
        let path = search.route([rows, cols], s, g, &[], 40, |_| true).unwrap();
        assert_eq!(path.len(), 12 + 13 - 1, "still a shortest path");
        assert_eq!(turns(&path, s, g, cols), 1, "one right-angle turn");
        // A wall across the way: round it with as few turns as it allows.
        let wall = |v: usize| !(v / cols == 8 && v % cols < 17);
        let path = search.route([rows, cols], s, g, &[], 40, wall).unwrap();
        assert!(path.iter().all(|&v| wall(v)));
        assert!(turns(&path, s, g, cols) <= 3);
        // Without a turn cost the search is the plain one, and finds as short a path.
        let plain = search.route([rows, cols], s, g, &[], 0, |_| true).unwrap();
        assert_eq!(plain.len(), 24);
    }
}
