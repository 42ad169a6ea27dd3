//! The occupancy grid: levels x rows x cols cells, and the compass directions between them.
//!
//! Rows grow southward and columns eastward, as in a picture of the level seen from above.
//! The world frame (see [`crate::layout::Layout::cell_position`]) puts x east, y north and z up.

use serde::{Deserialize, Serialize};

/// One of the four horizontal directions, in counter-clockwise order starting east, so that a
/// quarter turn counter-clockwise is `+1` (mod 4).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Direction {
    /// +column.
    East = 0,
    /// -row.
    North = 1,
    /// -column.
    West = 2,
    /// +row.
    South = 3,
}

impl Direction {
    /// All four, counter-clockwise from east.
    pub const ALL: [Direction; 4] = [
        Direction::East,
        Direction::North,
        Direction::West,
        Direction::South,
    ];

    /// `(d_row, d_col)` of one step in this direction.
    pub const fn step(self) -> (i32, i32) {
        match self {
            Direction::East => (0, 1),
            Direction::North => (-1, 0),
            Direction::West => (0, -1),
            Direction::South => (1, 0),
        }
    }

    /// The direction turned by `quarter_turns` counter-clockwise.
    pub const fn rotated(self, quarter_turns: u8) -> Direction {
        Direction::ALL[(self as usize + quarter_turns as usize) % 4]
    }

    /// The opposite direction.
    pub const fn opposite(self) -> Direction {
        self.rotated(2)
    }

    /// This direction's bit in an [`Openings`] mask.
    pub const fn bit(self) -> u8 {
        1 << self as u8
    }
}

/// A set of directions as a 4-bit mask (bit `d as u8` set when direction `d` is open).
pub type Openings = u8;

/// Rotates an openings mask by `quarter_turns` counter-clockwise.
pub const fn rotate_openings(mask: Openings, quarter_turns: u8) -> Openings {
    let q = quarter_turns % 4;
    ((mask << q) | (mask >> (4 - q))) & 0b1111
}

/// A vertical shaft from a dead end of one level to a dead end of the level above.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shaft {
    /// The dead end at the foot of the shaft, on level `k`.
    pub up: Cell,
    /// The dead end where it arrives, on level `k + 1`.
    pub landing: Cell,
    /// A ramp's spiral block (`world.connections = "ramp"`): the spiral turns in the 2 x 2
    /// block of cells made of the foot, the cells `dr` rows and `dc` columns from it, and the
    /// diagonal one (and the same around the landing on the level above), `[dr, dc]`, each
    /// `+1` or `-1`. Those three cells are empty on both levels, so the spiral is twice as wide
    /// as a cell and a decline at a drivable grade fits. `None` for a shaft, or a ramp that
    /// turns inside its own cell (an imported grid with no free block beside the foot).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub block: Option<[i8; 2]>,
}

impl Shaft {
    /// The three cells a spiral block adds beside `end` (the foot or the landing), when
    /// `block` is `[dr, dc]`: `(dr, 0)`, `(0, dc)` and `(dr, dc)` from it, or `None` where one
    /// falls off a grid of `rows` x `cols`.
    pub fn block_cells(
        end: Cell,
        [dr, dc]: [i8; 2],
        rows: usize,
        cols: usize,
    ) -> Option<[Cell; 3]> {
        let at = |a: i8, b: i8| {
            let r = end.row.checked_add_signed(isize::from(a))?;
            let c = end.col.checked_add_signed(isize::from(b))?;
            (r < rows && c < cols).then_some(Cell::new(end.level, r, c))
        };
        Some([at(dr, 0)?, at(0, dc)?, at(dr, dc)?])
    }

    /// The four spiral blocks a ramp end may take, in the order they are tried.
    pub const BLOCKS: [[i8; 2]; 4] = [[-1, -1], [-1, 1], [1, -1], [1, 1]];
}

/// A cell of the world: level, row, column.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct Cell {
    /// Level index, 0 at the bottom (the start level).
    pub level: usize,
    /// Row, growing southward.
    pub row: usize,
    /// Column, growing eastward.
    pub col: usize,
}

impl Cell {
    /// A cell from its three indices.
    pub const fn new(level: usize, row: usize, col: usize) -> Self {
        Self { level, row, col }
    }
}

/// A dense `levels x rows x cols` array, stored level-major then row-major, like the `.npy`
/// files the tool writes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Grid3<T> {
    levels: usize,
    rows: usize,
    cols: usize,
    data: Vec<T>,
}

impl<T: Clone> Grid3<T> {
    /// A grid filled with `value`.
    pub fn filled(levels: usize, rows: usize, cols: usize, value: T) -> Self {
        Self {
            levels,
            rows,
            cols,
            data: vec![value; levels * rows * cols],
        }
    }
}

impl<T> Grid3<T> {
    /// A grid from its values in level-major, row-major order. `None` when the length is not
    /// `levels * rows * cols`.
    pub fn from_vec(levels: usize, rows: usize, cols: usize, data: Vec<T>) -> Option<Self> {
        (data.len() == levels * rows * cols).then_some(Self {
            levels,
            rows,
            cols,
            data,
        })
    }

    /// Number of levels.
    pub fn levels(&self) -> usize {
        self.levels
    }
    /// Number of rows per level.
    pub fn rows(&self) -> usize {
        self.rows
    }
    /// Number of columns per level.
    pub fn cols(&self) -> usize {
        self.cols
    }
    /// `[levels, rows, cols]`.
    pub fn shape(&self) -> [usize; 3] {
        [self.levels, self.rows, self.cols]
    }
    /// All values, level-major then row-major.
    pub fn as_slice(&self) -> &[T] {
        &self.data
    }

    fn index(&self, c: Cell) -> usize {
        debug_assert!(c.level < self.levels && c.row < self.rows && c.col < self.cols);
        (c.level * self.rows + c.row) * self.cols + c.col
    }

    /// The value at a cell (panics outside the grid).
    pub fn get(&self, c: Cell) -> &T {
        &self.data[self.index(c)]
    }

    /// The value at a cell, mutably (panics outside the grid).
    pub fn get_mut(&mut self, c: Cell) -> &mut T {
        let i = self.index(c);
        &mut self.data[i]
    }

    /// The neighbour one step in `dir` on the same level, if inside the grid.
    pub fn neighbour(&self, c: Cell, dir: Direction) -> Option<Cell> {
        let (dr, dc) = dir.step();
        let r = c.row as i64 + i64::from(dr);
        let k = c.col as i64 + i64::from(dc);
        (r >= 0 && k >= 0 && (r as usize) < self.rows && (k as usize) < self.cols)
            .then(|| Cell::new(c.level, r as usize, k as usize))
    }

    /// Every cell in raster order (level, row, column).
    pub fn cells(&self) -> impl Iterator<Item = Cell> + '_ {
        let (rows, cols) = (self.rows, self.cols);
        (0..self.levels).flat_map(move |l| {
            (0..rows).flat_map(move |r| (0..cols).map(move |c| Cell::new(l, r, c)))
        })
    }

    /// The cells of one level in raster order.
    pub fn level_cells(&self, level: usize) -> impl Iterator<Item = Cell> + '_ {
        let cols = self.cols;
        (0..self.rows).flat_map(move |r| (0..cols).map(move |c| Cell::new(level, r, c)))
    }
}

/// Which cells hold a passage. `true` is occupied.
pub type Occupancy = Grid3<bool>;

impl Occupancy {
    /// The directions from `c` to occupied neighbours on the same level.
    pub fn openings(&self, c: Cell) -> Openings {
        let mut mask = 0;
        for d in Direction::ALL {
            if let Some(n) = self.neighbour(c, d) {
                if *self.get(n) {
                    mask |= d.bit();
                }
            }
        }
        mask
    }

    /// Number of occupied cells.
    pub fn occupied_count(&self) -> usize {
        self.data.iter().filter(|&&v| v).count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotating_openings_matches_rotating_directions() {
        for d in Direction::ALL {
            for q in 0..4 {
                assert_eq!(rotate_openings(d.bit(), q), d.rotated(q).bit());
            }
        }
        assert_eq!(Direction::East.opposite(), Direction::West);
        assert_eq!(Direction::North.rotated(1), Direction::West);
    }

    #[test]
    fn openings_see_only_the_same_level() {
        let mut g = Occupancy::filled(2, 3, 3, false);
        *g.get_mut(Cell::new(0, 1, 1)) = true;
        *g.get_mut(Cell::new(0, 1, 2)) = true;
        *g.get_mut(Cell::new(0, 0, 1)) = true;
        *g.get_mut(Cell::new(1, 2, 1)) = true;
        let m = g.openings(Cell::new(0, 1, 1));
        assert_eq!(m, Direction::East.bit() | Direction::North.bit());
        assert_eq!(g.neighbour(Cell::new(0, 0, 0), Direction::North), None);
        assert_eq!(g.occupied_count(), 4);
    }
}
