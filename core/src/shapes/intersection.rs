//! The intersection: a centre with four arms (paper eq. 1, `Upsilon^I`). Symmetric, so it has
//! one rotation (paper eq. 3).

use crate::grid::Direction;
use crate::shape::{Arm, ConstraintShape, Heading, Offset};

/// A four-way crossing.
#[derive(Clone, Copy, Debug, Default)]
pub struct Intersection;

impl ConstraintShape for Intersection {
    fn footprint(&self) -> Vec<Offset> {
        let mut cells = vec![(0, 0)];
        cells.extend(Direction::ALL.map(Direction::step));
        cells
    }

    fn arms(&self) -> Vec<Arm> {
        Direction::ALL
            .into_iter()
            .map(|d| Arm {
                from: d.step(),
                heading: Heading::Axis(d),
            })
            .collect()
    }

    fn rotations(&self) -> u8 {
        1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_arms_one_per_direction() {
        let arms = Intersection.arms();
        assert_eq!(arms.len(), 4);
        assert_eq!(Intersection.footprint().len(), 5);
        assert_eq!(Intersection.rotations(), 1);
    }
}
