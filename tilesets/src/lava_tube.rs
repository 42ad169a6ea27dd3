//! `lava-tube`: a wide, smooth, elliptical tube with a flat lava floor and a bench along each
//! wall (the shelves a lava flow leaves as it drains).

use subtgraph_core::error::ConfigError;
use subtgraph_core::mesh::Material;
use subtgraph_core::params::Params;

use crate::bends::Bends;
use crate::passage::Rooms;
use crate::passage::{Passage, Profile};
use crate::procedural::{Procedural, Style};
use crate::slope::Slope;

/// An ellipse cut by a flat floor, with side benches.
#[derive(Clone, Copy, Debug, Default)]
pub struct Tube;

impl Profile for Tube {
    fn section(&self, u: f64, v: f64, width: f64, height: f64) -> f64 {
        let a = 0.5 * width;
        let b = 0.7 * height;
        let centre = height - b;
        let tube =
            ((((u / a).powi(2) + ((v - centre) / b).powi(2)).sqrt() - 1.0) * a.min(b)).max(-v);
        // Benches: solid where near a wall and low.
        let bench = (u - 0.72 * a).min(0.14 * height - v);
        tube.max(bench)
    }
}

/// The `lava-tube` tile set.
pub fn from_params(p: &Params) -> Result<Procedural, ConfigError> {
    Procedural::from_params(
        Style {
            name: "lava-tube",
            profile: Box::new(Tube),
            width: 0.38,
            height: 0.3,
            shape: Passage {
                width: 0.0,
                height: 0.0,
                width_variation: 0.12,
                height_variation: 0.1,
                variation_scale: 1.2,
                roughness: 0.025,
                finish: crate::finish::Finish::Plain,
                refuge_spacing: 0.0,
                services: crate::services::Services::NONE,
                mesh_from: 0.0,
                roughness_scale: 0.6,
                floor_roughness: 0.0,
                rocks: 0.0,
                rock_size: 0.08,
                shaft_radius: 0.28,
                striations: false,
                // Lava tubes widen into rooms where flows met or ponded, and close down to
                // low crawls where the roof sagged or the floor rose: squeezes are mostly low.
                rooms: Rooms {
                    chamber_rate: 0.3,
                    chamber_size: [1.8, 2.6],
                    squeeze_rate: 0.12,
                    squeeze_factor: [0.45, 0.7],
                    low_share: 0.8,
                    ..Rooms::default()
                },
                bends: Bends::Round,
                meander: 0.06,
                grade: [3.0, 6.0],
                slope: Slope::flat(),
                hazard_lattice: 0.0,
            },
            materials: vec![
                Material::coloured("lava-tube-wall", [0.25, 0.22, 0.21]),
                Material::coloured("lava-floor", [0.16, 0.15, 0.15]),
                Material::coloured("rock-pile", [0.40, 0.34, 0.30]),
                Material::coloured("striated-rock", [0.35, 0.28, 0.25]),
            ],
            rocks: 0.2,
        },
        p,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_tube_has_a_flat_floor_and_benches() {
        let (w, h) = (10.0, 7.0);
        assert!(Tube.section(0.0, 0.5, w, h) < 0.0, "open above the floor");
        assert!(Tube.section(0.0, -0.1, w, h) > 0.0, "flat floor");
        assert!(Tube.section(4.0, 0.5, w, h) > 0.0, "bench near the wall");
        assert!(Tube.section(4.0, 2.5, w, h) < 0.0, "open above the bench");
    }
}
