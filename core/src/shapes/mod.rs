//! The built-in constraint shapes of the paper (eq. 1), one file each.

mod intersection;
mod loop_shape;
mod t_junction;

pub use intersection::Intersection;
pub use loop_shape::Loop;
pub use t_junction::TJunction;
