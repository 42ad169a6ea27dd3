//! `mine`: an operational mine drift: flat floor, straight walls, arched back; regular in size,
//! with blasted (or shotcreted) walls (`crate::finish`), refuge bays (`crate::refuge`) and few
//! rocks.

use subtgraph_core::error::ConfigError;
use subtgraph_core::mesh::Material;
use subtgraph_core::params::Params;

use crate::bends::Bends;
use crate::finish::Finish;
use crate::passage::Rooms;
use crate::passage::{Passage, Profile};
use crate::procedural::{Procedural, Style};
use crate::services::Services;
use crate::slope::Slope;

/// Default metres of straight drift per refuge bay (`[tileset] refuge_spacing`).
pub const REFUGE_SPACING: f64 = 150.0;

/// Default metres above the floor from which mesh panels cover the walls and back
/// (`[tileset] mesh_from`): a common rule meshes a development drift down to within 2 m of
/// the floor.
pub const MESH_FROM: f64 = 2.0;

/// A drift profile: walls up to 60 % of the height, then an elliptical arch.
#[derive(Clone, Copy, Debug, Default)]
pub struct Drift;

impl Profile for Drift {
    fn section(&self, u: f64, v: f64, width: f64, height: f64) -> f64 {
        drift_walls(u, v, width, height).max(-v)
    }

    fn walls(&self, u: f64, v: f64, width: f64, height: f64) -> Option<f64> {
        Some(drift_walls(u, v, width, height))
    }
}

/// The drift's walls and arch, without its floor.
fn drift_walls(u: f64, v: f64, width: f64, height: f64) -> f64 {
    let a = 0.5 * width;
    let wall = 0.6 * height;
    let b = height - wall;
    let s = a.min(b);
    if v <= wall {
        (u - a) * s / a
    } else {
        (((u / a).powi(2) + ((v - wall) / b).powi(2)).sqrt() - 1.0) * s
    }
}

/// The `mine` tile set.
pub fn from_params(p: &Params) -> Result<Procedural, ConfigError> {
    Procedural::from_params(
        Style {
            name: "mine",
            profile: Box::new(Drift),
            width: 0.32,
            height: 0.28,
            shape: Passage {
                width: 0.0,
                height: 0.0,
                width_variation: 0.02,
                height_variation: 0.02,
                variation_scale: 3.0,
                roughness: 0.015,
                // Drill-and-blast walls by default (`[tileset] finish`, `crate::finish`); the
                // relief moves walls and back only, so floors and ramps keep their grade.
                finish: Finish::Blasted {
                    rms: crate::finish::BLASTED_RMS,
                    round: crate::finish::ROUND,
                },
                // A refuge bay every 150 m of straight drift on average (`crate::refuge`).
                refuge_spacing: REFUGE_SPACING,
                // Rock bolts, a ventilation duct, pipes, a cable run and lights
                // (`crate::services`).
                services: Services::MINE,
                // Welded mesh over the back and the walls from 2 m up (painted: `crate::finish`).
                mesh_from: MESH_FROM,
                roughness_scale: 0.25,
                floor_roughness: 0.0,
                rocks: 0.0,
                rock_size: 0.08,
                shaft_radius: 0.3,
                striations: false,
                // Drifts are driven to a size: no squeezes and, unless asked for
                // (`chambers = { rate = ... }`), no rooms; asked for, a room is rectangular
                // (a stope or a pump station cut at a junction or the end of a drift).
                rooms: Rooms {
                    chamber_round: false,
                    chamber_size: [2.0, 2.5],
                    ..Rooms::default()
                },
                // Drifts are driven straight and meet at right angles.
                bends: Bends::Square,
                meander: 0.0,
                grade: [1.0, 3.0],
                slope: Slope::flat(),
                hazard_lattice: 0.0,
            },
            materials: vec![
                Material::coloured("mine-wall", [0.42, 0.40, 0.37]),
                Material::coloured("mine-floor", [0.30, 0.28, 0.26]),
                Material::coloured("rock-pile", [0.50, 0.46, 0.40]),
                Material::coloured("striated-rock", [0.55, 0.50, 0.44]),
            ],
            rocks: 0.15,
        },
        p,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_drift_has_a_flat_floor_straight_walls_and_an_arch() {
        let (w, h) = (6.0, 5.0);
        assert!(Drift.section(0.0, 2.0, w, h) < 0.0, "inside");
        assert!(Drift.section(0.0, -0.1, w, h) > 0.0, "below the floor");
        assert!(Drift.section(2.9, 0.5, w, h) < 0.0 && Drift.section(3.1, 0.5, w, h) > 0.0);
        assert!(Drift.section(0.0, 4.9, w, h) < 0.0 && Drift.section(0.0, 5.1, w, h) > 0.0);
        // The arch narrows: near the crown the passage is narrower than at the walls.
        assert!(Drift.section(2.5, 4.5, w, h) > 0.0);
    }
}
