//! Constraint shapes: the structures placed on a level before routing (paper eqs. 1-4).
//!
//! A shape is a small set of cells around a centre (its footprint) plus the arms that leave it.
//! The generator places the footprint, routes each arm to an objective node drawn by
//! [`ConstraintShape::objective`] (paper eqs. 5-6), and later links free arm ends of different
//! structures so the level is one connected network.

use crate::error::ConfigError;
use crate::grid::Direction;
use crate::rng::WorldRng;

/// A cell offset `(d_row, d_col)` from a structure's centre.
pub type Offset = (i32, i32);

/// Where an arm heads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Heading {
    /// Along one axis, like the arms of a T-junction or an intersection.
    Axis(Direction),
    /// Into the quadrant between two perpendicular directions, like a loop's corner arms.
    Quadrant(Direction, Direction),
}

impl Heading {
    /// The heading turned by `quarter_turns` counter-clockwise.
    pub fn rotated(self, quarter_turns: u8) -> Heading {
        match self {
            Heading::Axis(d) => Heading::Axis(d.rotated(quarter_turns)),
            Heading::Quadrant(a, b) => {
                Heading::Quadrant(a.rotated(quarter_turns), b.rotated(quarter_turns))
            }
        }
    }
}

/// An arm: a corridor that leaves the structure from one of its cells.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Arm {
    /// The footprint cell the arm leaves from.
    pub from: Offset,
    /// Where its objective node lies.
    pub heading: Heading,
}

/// Turns an offset by `quarter_turns` counter-clockwise (rows grow southward).
pub fn rotate_offset((dr, dc): Offset, quarter_turns: u8) -> Offset {
    (0..quarter_turns % 4).fold((dr, dc), |(r, c), _| (-c, r))
}

/// A structural constraint: T-junction, intersection, loop, or one of a plugin's.
///
/// Only the footprint and the arms are required. The defaults place it in any of four
/// rotations and draw objective nodes as the paper does.
///
/// # Example
///
/// An "L-bend" structure: a corner with two arms.
///
/// ```
/// use subtgraph_core::grid::Direction;
/// use subtgraph_core::shape::{Arm, ConstraintShape, Heading, Offset};
///
/// struct LBend;
///
/// impl ConstraintShape for LBend {
///     fn footprint(&self) -> Vec<Offset> {
///         vec![(0, 0), (0, 1), (1, 0)]
///     }
///     fn arms(&self) -> Vec<Arm> {
///         vec![
///             Arm { from: (0, 1), heading: Heading::Axis(Direction::East) },
///             Arm { from: (1, 0), heading: Heading::Axis(Direction::South) },
///         ]
///     }
/// }
/// assert_eq!(LBend.rotations(), 4);
/// ```
pub trait ConstraintShape: Send + Sync {
    /// The occupied cells in the base orientation, relative to the centre. Must be 4-connected.
    fn footprint(&self) -> Vec<Offset>;

    /// The arms in the base orientation. Each must leave from a footprint cell.
    fn arms(&self) -> Vec<Arm>;

    /// How many quarter-turn rotations are distinct (paper eq. 3: 4 for a T-junction, 1 for
    /// symmetric shapes). The generator draws one of `0..rotations()`.
    fn rotations(&self) -> u8 {
        4
    }

    /// Empty cells kept around the footprint when placing structures, so that two structures
    /// never touch.
    fn clearance(&self) -> i32 {
        2
    }

    /// Whether the shape can be placed on a level of `rows x cols` cells at all. Checked for
    /// every requested shape before a level is built, so a shape too large for the grid is a
    /// configuration error naming its key (a room-and-pillar block's `pillars`) instead of
    /// attempts that cannot succeed. The default accepts every level.
    fn fits(&self, rows: usize, cols: usize) -> Result<(), ConfigError> {
        let _ = (rows, cols);
        Ok(())
    }

    /// The shape to place for one structure on a level of `rows x cols`, for a shape whose
    /// size is drawn per level (a room-and-pillar block's pillars): the drawn shape, whose
    /// footprint and arms are placed and whose junctions and loops are expected. `None` (the
    /// default, which draws nothing) places `self`.
    fn drawn(
        &self,
        rows: usize,
        cols: usize,
        rng: &mut WorldRng,
    ) -> Option<Box<dyn ConstraintShape>> {
        let _ = (rows, cols, rng);
        None
    }

    /// The objective node of an arm leaving from cell `from` (absolute `[row, col]`), on a level
    /// of `rows x cols` (paper eqs. 5-6): `t` cells along the heading, `t` in `[2, n]`, with a
    /// sideways jitter in `[-2, 2]`. The generator clamps it to the level.
    fn objective(
        &self,
        from: [i32; 2],
        heading: Heading,
        rows: usize,
        cols: usize,
        rng: &mut WorldRng,
    ) -> [i32; 2] {
        let reach = |d: Direction, rng: &mut WorldRng| {
            let n = if d.step().0 != 0 { rows } else { cols } as i64;
            rng.int_in(2, n.max(2)) as i32
        };
        match heading {
            Heading::Axis(d) => {
                let t = reach(d, rng);
                let mu = rng.int_in(-2, 2) as i32;
                let (sr, sc) = d.step();
                let (pr, pc) = d.rotated(1).step();
                [from[0] + sr * t + pr * mu, from[1] + sc * t + pc * mu]
            }
            Heading::Quadrant(a, b) => {
                let (ta, tb) = (reach(a, rng), reach(b, rng));
                let (ar, ac) = a.step();
                let (br, bc) = b.step();
                [from[0] + ar * ta + br * tb, from[1] + ac * ta + bc * tb]
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotating_an_offset_matches_rotating_a_direction() {
        for d in Direction::ALL {
            for q in 0..4 {
                assert_eq!(rotate_offset(d.step(), q), d.rotated(q).step());
            }
        }
    }

    #[test]
    fn axis_objectives_lie_ahead_with_small_jitter() {
        struct Dot;
        impl ConstraintShape for Dot {
            fn footprint(&self) -> Vec<Offset> {
                vec![(0, 0)]
            }
            fn arms(&self) -> Vec<Arm> {
                vec![]
            }
        }
        let mut rng = WorldRng::new(3, "t", 0);
        for _ in 0..200 {
            let o = Dot.objective([10, 10], Heading::Axis(Direction::East), 40, 40, &mut rng);
            assert!((12..=50).contains(&o[1]), "{o:?}");
            assert!((8..=12).contains(&o[0]), "{o:?}");
        }
    }
}
