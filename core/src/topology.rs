//! Counting the topology of one level: junctions, intersections, dead ends, independent
//! cycles, 4-connected components and fused 2 x 2 blocks.
//!
//! The generator's acceptance test (did the level get the junctions and loops it asked for?)
//! and the report of what a world achieved must count the same way, or a world could be
//! accepted with one number and reported with another. Both therefore read a level through the
//! same borrowed [`GridView`] and the functions here; nothing else in the workspace counts.
//!
//! Counts use 4-adjacency inside the level: a cell's degree is its number of occupied
//! neighbours (north, south, east, west). Loops are the cycle rank `edges - cells +
//! components`, the number of independent cycles of the cell graph.
//!
//! ```
//! use subtgraph_core::topology::GridView;
//! // A ring of 8 cells around an empty centre: one loop, no junction, one component.
//! let cells = [true, true, true, true, false, true, true, true, true];
//! let view = GridView::new(3, 3, &cells);
//! let c = view.counts();
//! assert_eq!((c.loops, c.t_junctions, c.dead_ends), (1, 0, 0));
//! assert_eq!(view.component_count(), 1);
//! assert!(!view.has_fused_block());
//! ```

use serde::{Deserialize, Serialize};

use crate::grid::Occupancy;

/// Topology counts of one level.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Counts {
    /// Tiles with three openings.
    pub t_junctions: u32,
    /// Tiles with four openings.
    pub intersections: u32,
    /// Independent cycles (edges - cells + components, over 4-adjacency).
    pub loops: u32,
    /// Tiles with one opening (shaft feet and landings included).
    pub dead_ends: u32,
}

/// A borrowed `rows x cols` level, row-major, `true` where the cell is a passage.
#[derive(Clone, Copy, Debug)]
pub struct GridView<'a> {
    rows: usize,
    cols: usize,
    cells: &'a [bool],
}

/// The four steps of 4-adjacency, as `(row, column)` offsets: east, north, west, south.
pub const STEPS: [(i32, i32); 4] = [(0, 1), (-1, 0), (0, -1), (1, 0)];

impl<'a> GridView<'a> {
    /// A view of `cells`, which must hold `rows * cols` cells (panics otherwise: a caller's
    /// bug, never the user's input).
    pub fn new(rows: usize, cols: usize, cells: &'a [bool]) -> Self {
        assert_eq!(
            cells.len(),
            rows * cols,
            "a level view needs rows x cols cells"
        );
        Self { rows, cols, cells }
    }

    /// Rows.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Columns.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// Whether cell `i` (row-major index) is a passage.
    pub fn occupied(&self, i: usize) -> bool {
        self.cells[i]
    }

    /// The index of `(row, col)` if inside the level.
    pub fn index(&self, r: i32, c: i32) -> Option<usize> {
        index(self.rows, self.cols, r, c)
    }

    /// The in-level 4-neighbours of cell `i`, occupied or not.
    pub fn neighbours(&self, i: usize) -> impl Iterator<Item = usize> + use<'a> {
        neighbours(self.rows, self.cols, i)
    }

    /// Number of occupied 4-neighbours of cell `i`.
    pub fn degree(&self, i: usize) -> usize {
        self.neighbours(i).filter(|&n| self.cells[n]).count()
    }

    /// 4-connected components: a label per cell (`u32::MAX` for empty ones) and their number.
    pub fn components(&self) -> (Vec<u32>, u32) {
        let mut label = vec![u32::MAX; self.cells.len()];
        let mut n = 0;
        let mut stack = Vec::new();
        for i in 0..self.cells.len() {
            if !self.cells[i] || label[i] != u32::MAX {
                continue;
            }
            label[i] = n;
            stack.push(i);
            while let Some(u) = stack.pop() {
                for v in self.neighbours(u) {
                    if self.cells[v] && label[v] == u32::MAX {
                        label[v] = n;
                        stack.push(v);
                    }
                }
            }
            n += 1;
        }
        (label, n)
    }

    /// Number of 4-connected pieces of occupied cells.
    pub fn component_count(&self) -> u32 {
        self.components().1
    }

    /// Occupied cells.
    pub fn cell_count(&self) -> u32 {
        self.cells.iter().filter(|&&v| v).count() as u32
    }

    /// Junction, intersection, dead-end and cycle counts, every cell counted by its degree.
    pub fn counts(&self) -> Counts {
        let mut c = Counts::default();
        let (mut cells, mut edges) = (0u32, 0u32);
        for i in 0..self.cells.len() {
            if !self.cells[i] {
                continue;
            }
            cells += 1;
            let (r, col) = ((i / self.cols) as i32, (i % self.cols) as i32);
            // Each edge once: toward east and south.
            edges += u32::from(self.index(r, col + 1).is_some_and(|j| self.cells[j]));
            edges += u32::from(self.index(r + 1, col).is_some_and(|j| self.cells[j]));
            match self.degree(i) {
                1 => c.dead_ends += 1,
                3 => c.t_junctions += 1,
                4 => c.intersections += 1,
                _ => {}
            }
        }
        c.loops = (edges + self.component_count()).saturating_sub(cells);
        c
    }

    /// The top-left `(row, col)` of every fully occupied 2 x 2 block: corridors fused side by
    /// side into a ladder of junctions, which the generator never makes.
    pub fn fused_blocks(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        let cols = self.cols;
        (0..self.rows.saturating_sub(1)).flat_map(move |r| {
            (0..cols.saturating_sub(1)).filter_map(move |c| {
                let i = r * cols + c;
                (self.cells[i]
                    && self.cells[i + 1]
                    && self.cells[i + cols]
                    && self.cells[i + cols + 1])
                    .then_some((r, c))
            })
        })
    }

    /// Whether any 2 x 2 block is fully occupied.
    pub fn has_fused_block(&self) -> bool {
        self.fused_blocks().next().is_some()
    }
}

/// Level `level` of a world's occupancy as a view.
pub fn level(occ: &Occupancy, level: usize) -> GridView<'_> {
    let n = occ.rows() * occ.cols();
    GridView::new(
        occ.rows(),
        occ.cols(),
        &occ.as_slice()[level * n..(level + 1) * n],
    )
}

/// The row-major index of `(r, c)` in a `rows x cols` grid, if inside.
pub fn index(rows: usize, cols: usize, r: i32, c: i32) -> Option<usize> {
    (r >= 0 && c >= 0 && (r as usize) < rows && (c as usize) < cols)
        .then(|| r as usize * cols + c as usize)
}

/// The in-grid 4-neighbours of cell `i` of a `rows x cols` grid, in [`STEPS`] order.
pub fn neighbours(rows: usize, cols: usize, i: usize) -> impl Iterator<Item = usize> {
    let (r, c) = ((i / cols) as i32, (i % cols) as i32);
    STEPS
        .into_iter()
        .filter_map(move |(dr, dc)| index(rows, cols, r + dr, c + dc))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(rows: &[&str]) -> (usize, usize, Vec<bool>) {
        let cells = rows
            .iter()
            .flat_map(|r| r.bytes().map(|b| b == b'#'))
            .collect();
        (rows.len(), rows[0].len(), cells)
    }

    #[test]
    fn a_plus_has_one_intersection_and_four_dead_ends() {
        let (r, c, cells) = grid(&[".#.", "###", ".#."]);
        let v = GridView::new(r, c, &cells);
        let counts = v.counts();
        assert_eq!(counts.intersections, 1);
        assert_eq!(counts.dead_ends, 4);
        assert_eq!(counts.loops, 0);
        assert_eq!(v.cell_count(), 5);
    }

    #[test]
    fn two_pieces_and_a_fused_block() {
        let (r, c, cells) = grid(&["##..#", "##..#", "....#"]);
        let v = GridView::new(r, c, &cells);
        assert_eq!(v.component_count(), 2);
        assert_eq!(v.fused_blocks().collect::<Vec<_>>(), vec![(0, 0)]);
        // The 2 x 2 block is a 4-cycle: one loop; its cells have degree 2.
        assert_eq!(v.counts().loops, 1);
        assert_eq!(v.counts().t_junctions, 0);
    }
}
