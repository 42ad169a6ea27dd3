//! A constraint shape plugin: a Y-fork, a stem that splits into two branches heading off
//! diagonally.
//!
//! ```toml
//! [[topology.structure]]
//! type = "y-fork"
//! count = [1, 2]
//! ```

use subtgraph_core::grid::Direction::{East, North, South, West};
use subtgraph_core::shape::{Arm, ConstraintShape, Heading, Offset};

struct YFork;

impl ConstraintShape for YFork {
    fn footprint(&self) -> Vec<Offset> {
        vec![(0, 0), (1, 0), (0, -1), (0, 1)]
    }

    fn arms(&self) -> Vec<Arm> {
        vec![
            Arm {
                from: (1, 0),
                heading: Heading::Axis(South),
            },
            Arm {
                from: (0, -1),
                heading: Heading::Quadrant(North, West),
            },
            Arm {
                from: (0, 1),
                heading: Heading::Quadrant(North, East),
            },
        ]
    }
}

fn register(r: &mut subtgraph_plugins::Registrar<'_>) {
    r.constraint_shape(
        "y-fork",
        "a stem splitting into two diagonal branches",
        |p| {
            p.expect_none()?;
            Ok(Box::new(YFork))
        },
    );
}

subtgraph_plugins::declare_plugin!("y-fork", register);
