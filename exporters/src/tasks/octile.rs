//! An octile grid as MovingAI's benchmarks define it: eight moves, straight ones cost 1 and
//! diagonal ones √2, and no corner cutting (a diagonal move needs both cells it passes
//! between free). Its connected groups, and optimal lengths by A* with the octile distance
//! (consistent for these moves, so the first time the goal leaves the queue its cost is
//! optimal).

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::f64::consts::SQRT_2;

/// Free cells of one level's map, row 0 north, as the `.map` file writes them.
#[derive(Clone, Debug)]
pub struct Octile {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Row-major: `free[y * width + x]`.
    pub free: Vec<bool>,
}

/// Connected groups of free cells.
#[derive(Clone, Debug)]
pub struct Groups {
    /// The group of each cell (`u32::MAX` for rock).
    pub of: Vec<u32>,
    /// Each group's cells, row-major order.
    pub cells: Vec<Vec<u32>>,
}

const MOVES: [(i64, i64); 8] = [
    (1, 0),
    (-1, 0),
    (0, 1),
    (0, -1),
    (1, 1),
    (1, -1),
    (-1, 1),
    (-1, -1),
];

impl Octile {
    fn is_free(&self, x: i64, y: i64) -> bool {
        x >= 0
            && y >= 0
            && (x as usize) < self.width
            && (y as usize) < self.height
            && self.free[y as usize * self.width + x as usize]
    }

    /// The cells one move from `c` and each move's cost.
    fn moves(&self, c: u32) -> impl Iterator<Item = (u32, f64)> + '_ {
        let (x, y) = (
            (c as usize % self.width) as i64,
            (c as usize / self.width) as i64,
        );
        MOVES.iter().filter_map(move |&(dx, dy)| {
            let (nx, ny) = (x + dx, y + dy);
            let diagonal = dx != 0 && dy != 0;
            let ok = self.is_free(nx, ny)
                && (!diagonal || (self.is_free(x + dx, y) && self.is_free(x, y + dy)));
            ok.then(|| {
                let cost = if diagonal { SQRT_2 } else { 1.0 };
                ((ny as usize * self.width + nx as usize) as u32, cost)
            })
        })
    }

    /// The connected groups, numbered in row-major order of their first cell.
    pub fn groups(&self) -> Groups {
        let mut of = vec![u32::MAX; self.free.len()];
        let mut cells = Vec::new();
        for start in 0..self.free.len() {
            if !self.free[start] || of[start] != u32::MAX {
                continue;
            }
            let id = cells.len() as u32;
            let mut members = vec![start as u32];
            of[start] = id;
            let mut next = 0;
            while next < members.len() {
                let c = members[next];
                next += 1;
                for (n, _) in self.moves(c) {
                    if of[n as usize] == u32::MAX {
                        of[n as usize] = id;
                        members.push(n);
                    }
                }
            }
            members.sort_unstable();
            cells.push(members);
        }
        Groups { of, cells }
    }

    /// `(x, y)` of cell index `c`.
    pub fn xy(&self, c: u32) -> (usize, usize) {
        (c as usize % self.width, c as usize / self.width)
    }
}

/// A* over one map, its scratch arrays kept between searches.
pub struct Search<'a> {
    map: &'a Octile,
    cost: Vec<f64>,
    stamp: Vec<u32>,
    round: u32,
}

/// The octile distance: a lower bound of the length between two cells.
fn octile(map: &Octile, a: u32, b: u32) -> f64 {
    let ((ax, ay), (bx, by)) = (map.xy(a), map.xy(b));
    let (dx, dy) = (ax.abs_diff(bx) as f64, ay.abs_diff(by) as f64);
    dx.max(dy) + (SQRT_2 - 1.0) * dx.min(dy)
}

impl<'a> Search<'a> {
    /// Scratch for `map`.
    pub fn new(map: &'a Octile) -> Self {
        Self {
            map,
            cost: vec![0.0; map.free.len()],
            stamp: vec![0; map.free.len()],
            round: 0,
        }
    }

    /// The optimal length from `start` to `goal`, `None` when no path joins them.
    pub fn length(&mut self, start: u32, goal: u32) -> Option<f64> {
        self.round += 1;
        let round = self.round;
        let map = self.map;
        // Costs are non-negative, so their bit patterns order as the numbers do. Among equal
        // estimates the cell farther along is taken first (fewer cells opened on open floors).
        let mut open = BinaryHeap::new();
        self.stamp[start as usize] = round;
        self.cost[start as usize] = 0.0;
        open.push(Reverse((
            octile(map, start, goal).to_bits(),
            Reverse(0u64),
            start,
        )));
        while let Some(Reverse((_, Reverse(g_bits), c))) = open.pop() {
            let g = self.cost[c as usize];
            if g.to_bits() != g_bits {
                continue; // Reached more cheaply since it was queued.
            }
            if c == goal {
                return Some(g);
            }
            for (n, step) in map.moves(c) {
                let ng = g + step;
                let seen = self.stamp[n as usize] == round;
                if !seen || ng < self.cost[n as usize] {
                    self.stamp[n as usize] = round;
                    self.cost[n as usize] = ng;
                    let f = ng + octile(map, n, goal);
                    open.push(Reverse((f.to_bits(), Reverse(ng.to_bits()), n)));
                }
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(rows: &[&str]) -> Octile {
        Octile {
            width: rows[0].len(),
            height: rows.len(),
            free: rows
                .iter()
                .flat_map(|r| r.bytes().map(|b| b == b'.'))
                .collect(),
        }
    }

    #[test]
    fn diagonals_cost_root_two_and_never_cut_corners() {
        let m = map(&["...", "...", "..."]);
        let mut s = Search::new(&m);
        assert!((s.length(0, 8).unwrap() - 2.0 * SQRT_2).abs() < 1e-12);
        // A rock beside the diagonal forces the way round it.
        let m = map(&[".@", ".."]);
        let mut s = Search::new(&m);
        assert_eq!(s.length(0, 3), Some(2.0));
        let m = map(&[".@", "@."]);
        assert_eq!(m.groups().cells.len(), 2);
        assert_eq!(Search::new(&m).length(0, 3), None);
    }

    #[test]
    fn a_wall_makes_the_path_go_round() {
        let m = map(&[".....", ".@@@.", "....."]);
        // (0,1) to (4,1): over the wall; no diagonal may clip its corners, so 1 + 4 + 1.
        assert_eq!(Search::new(&m).length(5, 9), Some(6.0));
        assert_eq!(m.groups().cells.len(), 1);
    }
}
