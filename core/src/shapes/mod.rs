//! The built-in constraint shapes, one file each: the paper's three (eq. 1) and the
//! room-and-pillar block of a mine panel.

mod intersection;
mod loop_shape;
mod room_and_pillar;
mod t_junction;

pub use intersection::Intersection;
pub use loop_shape::Loop;
pub use room_and_pillar::{DEFAULT_PILLARS, PillarBlock, RoomAndPillar, most_pillars};
pub use t_junction::TJunction;
