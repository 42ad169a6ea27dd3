//! The loop: a ring of eight cells around an empty centre (paper eq. 1, `Upsilon^L`: the four
//! neighbours and the four diagonals), with an arm from each diagonal corner into that corner's
//! quadrant, as in the original. Each arm meets the ring at a T-junction, so a loop brings one
//! independent cycle and four T-junctions of its own.

use crate::grid::Direction::{East, North, South, West};
use crate::shape::{Arm, ConstraintShape, Heading, Offset};

/// A small closed circuit with four arms.
#[derive(Clone, Copy, Debug, Default)]
pub struct Loop;

impl ConstraintShape for Loop {
    fn footprint(&self) -> Vec<Offset> {
        vec![
            (-1, -1),
            (-1, 0),
            (-1, 1),
            (0, 1),
            (1, 1),
            (1, 0),
            (1, -1),
            (0, -1),
        ]
    }

    fn arms(&self) -> Vec<Arm> {
        vec![
            Arm {
                from: (-1, 1),
                heading: Heading::Quadrant(North, East),
            },
            Arm {
                from: (-1, -1),
                heading: Heading::Quadrant(North, West),
            },
            Arm {
                from: (1, -1),
                heading: Heading::Quadrant(South, West),
            },
            Arm {
                from: (1, 1),
                heading: Heading::Quadrant(South, East),
            },
        ]
    }

    fn rotations(&self) -> u8 {
        1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_ring_leaves_its_centre_empty_and_arms_start_at_corners() {
        let ring = Loop.footprint();
        assert_eq!(ring.len(), 8);
        assert!(!ring.contains(&(0, 0)));
        for arm in Loop.arms() {
            assert!(ring.contains(&arm.from));
            assert!(
                arm.from.0 != 0 && arm.from.1 != 0,
                "arms leave from corners"
            );
        }
    }
}
