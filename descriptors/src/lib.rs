//! # subtgraph-descriptors
//!
//! The built-in route descriptors, one file each. All four are members of the paper's harmonic
//! family `A sin(h pi t)` (eq. 11): `linear` (h = 0, straight circuits), `parabolic` (h = 1,
//! wide curved circuits), `sine` (h = 2, wave-like circuits), and `harmonic`, which takes any
//! whole number of half-waves. The amplitude defaults to the original's `min(rows, cols) / 20`
//! cells and can be set with `amplitude` (in cells).

use subtgraph_core::registry::{DuplicateName, Registry};
use subtgraph_core::route::RouteDescriptor;

mod harmonic;
mod linear;
mod parabolic;
mod sine;

pub use harmonic::{FixedHarmonic, Harmonic};
pub use linear::Linear;
pub use parabolic::Parabolic;
pub use sine::Sine;

/// Adds the built-in route descriptors to a registry.
pub fn register(registry: &mut Registry) -> Result<(), DuplicateName> {
    let r = &mut registry.route_descriptors;
    r.add(
        "linear",
        "straight corridors (0 harmonics): operational mines",
        |p| Ok(Box::new(Linear::from_params(p)?) as Box<dyn RouteDescriptor>),
    )?;
    r.add(
        "parabolic",
        "one wide bend per corridor (1 harmonic): natural caves",
        |p| Ok(Box::new(Parabolic::from_params(p)?) as Box<dyn RouteDescriptor>),
    )?;
    r.add(
        "sine",
        "a full wave per corridor (2 harmonics): lava tubes",
        |p| Ok(Box::new(Sine::from_params(p)?) as Box<dyn RouteDescriptor>),
    )?;
    r.add(
        "harmonic",
        "`harmonics` half-waves of `amplitude` cells per corridor",
        |p| Ok(Box::new(Harmonic::from_params(p)?) as Box<dyn RouteDescriptor>),
    )?;
    Ok(())
}
