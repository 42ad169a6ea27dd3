//! The T-junction: a centre with arms up, down and right (paper eq. 1, `Upsilon^J`), in any of
//! four rotations.

use crate::grid::Direction;
use crate::shape::{Arm, ConstraintShape, Heading, Offset};

/// A three-way junction.
#[derive(Clone, Copy, Debug, Default)]
pub struct TJunction;

impl ConstraintShape for TJunction {
    fn footprint(&self) -> Vec<Offset> {
        vec![(0, 0), (-1, 0), (1, 0), (0, 1)]
    }

    fn arms(&self) -> Vec<Arm> {
        [Direction::North, Direction::South, Direction::East]
            .into_iter()
            .map(|d| Arm {
                from: d.step(),
                heading: Heading::Axis(d),
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arms_leave_from_the_footprint_outward() {
        let cells = TJunction.footprint();
        for arm in TJunction.arms() {
            assert!(cells.contains(&arm.from));
            let Heading::Axis(d) = arm.heading else {
                panic!("T-junction arms are axial")
            };
            assert_eq!(arm.from, d.step());
        }
        assert_eq!(TJunction.rotations(), 4);
    }
}
