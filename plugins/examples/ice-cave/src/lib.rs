//! A tile set plugin for a new cave type: an ice cave, a tall keyhole section with smooth,
//! pale blue walls. It reuses the procedural machinery of `subtgraph-tilesets`, so it is closed
//! and seamless like the built-ins: a new look is a profile and a handful of numbers.
//!
//! ```toml
//! [tileset]
//! type = "ice-cave"
//! ```

use subtgraph_core::mesh::Material;
use subtgraph_tilesets::passage::{Passage, Profile};
use subtgraph_tilesets::procedural::{Procedural, Style};

/// A keyhole: a narrow slot below, a round chamber above.
struct Keyhole;

impl Profile for Keyhole {
    fn section(&self, u: f64, v: f64, width: f64, height: f64) -> f64 {
        let r = 0.5 * width;
        let centre = height - r;
        let round = ((u * u + (v - centre) * (v - centre)).sqrt() - r).max(-v);
        let slot = (u - 0.3 * width).max(-v).max(v - centre);
        round.min(slot)
    }
}

fn register(r: &mut subtgraph_plugins::Registrar<'_>) {
    r.tileset(
        "ice-cave",
        "tall keyhole passages with smooth pale blue ice",
        |p| {
            Ok(Box::new(Procedural::from_params(
                Style {
                    name: "ice-cave",
                    profile: Box::new(Keyhole),
                    width: 0.3,
                    height: 0.34,
                    // Only what differs from the default (the cave's) passage.
                    shape: Passage {
                        width_variation: 0.1,
                        height_variation: 0.08,
                        variation_scale: 1.5,
                        roughness: 0.02,
                        roughness_scale: 0.8,
                        floor_roughness: 0.0,
                        rock_size: 0.1,
                        ..Passage::default()
                    },
                    materials: vec![
                        Material::coloured("ice-wall", [0.70, 0.85, 0.95]),
                        Material::coloured("ice-floor", [0.80, 0.88, 0.92]),
                        Material::coloured("rock-pile", [0.40, 0.42, 0.45]),
                        Material::coloured("blue-ice", [0.45, 0.70, 0.92]),
                    ],
                    rocks: 0.1,
                },
                p,
            )?))
        },
    );
}

subtgraph_plugins::declare_plugin!("ice-cave", register);
