//! `cave`: a natural cave: irregular cross-section, rough walls, rubble and rock piles on the
//! floor, width and height changing along the passage; walls with striated bands.

use subtgraph_core::error::ConfigError;
use subtgraph_core::mesh::Material;
use subtgraph_core::params::Params;

use crate::passage::Rooms;
use crate::passage::{Passage, Profile};
use crate::procedural::{Procedural, Style};

/// A rounded, slightly flattened section with a floor.
#[derive(Clone, Copy, Debug, Default)]
pub struct Gallery;

impl Profile for Gallery {
    fn section(&self, u: f64, v: f64, width: f64, height: f64) -> f64 {
        let a = 0.5 * width;
        let b = 0.6 * height;
        let centre = height - b;
        ((((u / a).powi(2) + ((v - centre) / b).powi(2)).sqrt() - 1.0) * a.min(b)).max(-v)
    }
}

/// The `cave` tile set.
pub fn from_params(p: &Params) -> Result<Procedural, ConfigError> {
    Procedural::from_params(
        Style {
            name: "cave",
            profile: Box::new(Gallery),
            width: 0.34,
            height: 0.30,
            // The default passage is the cave's, with rooms at some junctions and dead ends and
            // squeezes, narrow or low, along some corridors.
            shape: Passage {
                rooms: Rooms {
                    chamber_rate: 0.3,
                    chamber_size: [2.0, 3.0],
                    squeeze_rate: 0.15,
                    ..Rooms::default()
                },
                ..Passage::default()
            },
            materials: vec![
                Material::coloured("cave-wall", [0.46, 0.40, 0.33]),
                Material::coloured("cave-floor", [0.36, 0.31, 0.26]),
                Material::coloured("rock-pile", [0.55, 0.52, 0.48]),
                Material::coloured("striated-rock", [0.62, 0.52, 0.40]),
            ],
            rocks: 0.6,
        },
        p,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_gallery_is_round_above_a_floor() {
        let (w, h) = (8.0, 6.0);
        assert!(Gallery.section(0.0, 3.0, w, h) < 0.0);
        assert!(Gallery.section(0.0, -0.2, w, h) > 0.0);
        assert!(Gallery.section(0.0, 6.2, w, h) > 0.0);
        assert!(Gallery.section(4.2, 2.4, w, h) > 0.0);
    }
}
