//! `[hazards]`: floor patches with another friction, the first hazard of a world (where they
//! go is computed by the exporters: `exporters/src/hazards.rs`).
//!
//! ```toml
//! [hazards]
//! friction = { mud = 0.05, ice = 0.02 }   # share of the floor (whole tiles) per material
//! ```
//!
//! Optional: a pipeline without it makes the files it always made. Rubble fields and
//! negative obstacles are not made yet.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::rng::WorldRng;

/// A floor material with its own friction.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FloorMaterial {
    /// Wet clay: sticky for feet, slippery for wheels.
    Mud,
    /// Frozen seepage.
    Ice,
    /// Loose sand.
    Sand,
    /// Rock under running water.
    WetRock,
}

impl FloorMaterial {
    /// Every material.
    pub const ALL: [FloorMaterial; 4] = [
        FloorMaterial::Mud,
        FloorMaterial::Ice,
        FloorMaterial::Sand,
        FloorMaterial::WetRock,
    ];

    /// The name in pipeline files and ground truth.
    pub const fn name(self) -> &'static str {
        match self {
            FloorMaterial::Mud => "mud",
            FloorMaterial::Ice => "ice",
            FloorMaterial::Sand => "sand",
            FloorMaterial::WetRock => "wet-rock",
        }
    }

    /// Coulomb friction coefficient (sliding), against rock's 0.8 in USD and 1.0 in MuJoCo.
    pub const fn friction(self) -> f64 {
        match self {
            FloorMaterial::Mud => 0.3,
            FloorMaterial::Ice => 0.05,
            FloorMaterial::Sand => 0.5,
            FloorMaterial::WetRock => 0.4,
        }
    }
}

/// `[hazards]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HazardsSection {
    /// Share of the floor per material, whole tiles.
    #[serde(default)]
    pub friction: BTreeMap<FloorMaterial, f64>,
}

impl HazardsSection {
    /// What is wrong with the section, as `(key, message)`.
    pub fn problem(&self) -> Option<(&'static str, String)> {
        if self
            .friction
            .values()
            .any(|s| !(s.is_finite() && (0.0..=1.0).contains(s)))
        {
            return Some((
                "hazards.friction",
                "each share is a number from 0 to 1, e.g. friction = { mud = 0.05 }".into(),
            ));
        }
        if self.friction.values().sum::<f64>() > 1.0 {
            return Some((
                "hazards.friction",
                "the shares add up to more than the whole floor (1); lower them".into(),
            ));
        }
        None
    }

    /// Which tiles get which material: `tiles` (the candidates, in a fixed order) shuffled by
    /// the world's `"hazards"` stream, then `round(share x count)` for each material in name
    /// order.
    pub fn assign<T: Copy>(&self, seed: u64, tiles: &[T]) -> Vec<(T, FloorMaterial)> {
        let mut order: Vec<T> = tiles.to_vec();
        WorldRng::new(seed, "hazards", 0).shuffle(&mut order);
        let mut out = Vec::new();
        let mut next = 0;
        for (&m, &share) in &self.friction {
            let n = (share * tiles.len() as f64).round() as usize;
            let n = n.min(order.len() - next);
            out.extend(order[next..next + n].iter().map(|&t| (t, m)));
            next += n;
        }
        out
    }
}
