//! A mine drift's services: rock bolts with plates on a pattern over the back and upper
//! walls, a ventilation duct hung from the back, pipes and a cable run along one wall, and
//! lights on the back (`[tileset] services`, `bolt_spacing`, `duct_diameter`, `pipes`,
//! `cable_run`, `light_spacing`; the mine tile set's default is all of them).
//!
//! They are what a LiDAR mostly sees in a real drift, and they break the symmetry of a
//! straight drift along its axis. Each is a small closed part (a prototype) placed many times
//! ([`subtgraph_core::mesh::Fixtures`]) once every tile is made and welded: the placement
//! walks each tile's passage axis in world coordinates (a bolt ring or a light wherever the
//! axis crosses a multiple of the spacing in x or y, the duct, pipes and cable as segments of
//! the axis), so the services run on across tile joins with no seam and do not depend on how
//! the world is cut into tiles. Bolt plates and lights are put where rays from the drift's
//! axis meet the welded rock ([`subtgraph_core::raycast`]), so they sit on the rock whatever
//! its relief; the duct, pipes and cable keep a fixed height and stand-off from the nominal
//! section, clear of the relief.
//!
//! Everything is mounted at least 1.7 m above the floor (bolts and lights on the back and the
//! walls above the spring of the arch, pipes and cable at half the drift's height, the duct
//! under the crown): above a ground robot, so the parts are in the visual mesh and the
//! survey's rays (LiDAR), not in the collision surface. The jitter of each bolt is drawn from
//! the world seed and the bolt's place in the world.

mod parts;
mod place;

use subtgraph_core::error::ConfigError;
use subtgraph_core::mesh::{Fixtures, Material, Mesh, Prototype};
use subtgraph_core::params::Params;
use subtgraph_core::raycast::RayCaster;
use subtgraph_core::tileset::PassageAxis;

/// The services' materials, in the order their prototypes name them (after the tile set's
/// own materials).
pub const MATERIALS: [(&str, [f32; 3]); 5] = [
    ("mine-bolt", [0.55, 0.52, 0.48]),
    ("mine-duct", [0.75, 0.62, 0.12]),
    ("mine-pipe", [0.20, 0.28, 0.45]),
    ("mine-cable", [0.06, 0.06, 0.06]),
    ("mine-light", [0.92, 0.92, 0.85]),
];

/// Which services a drift carries and their sizes, metres (0: none of that kind).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Services {
    /// Rock bolts: metres between bolts, along the drift and around the back (a square
    /// pattern, every other ring staggered).
    pub bolt_spacing: f64,
    /// The ventilation duct's diameter.
    pub duct_diameter: f64,
    /// Pipes along one wall (0 to 4), 0.15 m across.
    pub pipes: u32,
    /// A cable run along the same wall, above the pipes.
    pub cable_run: bool,
    /// Metres between lights on the back.
    pub light_spacing: f64,
}

impl Services {
    /// No services (the cave and the lava tube).
    pub const NONE: Services = Services {
        bolt_spacing: 0.0,
        duct_diameter: 0.0,
        pipes: 0,
        cable_run: false,
        light_spacing: 0.0,
    };

    /// A mine drift's: bolts on a 1.2 m pattern, a 1 m duct, two pipes, a cable run, a light
    /// every 20 m.
    pub const MINE: Services = Services {
        bolt_spacing: 1.2,
        duct_diameter: 1.0,
        pipes: 2,
        cable_run: true,
        light_spacing: 20.0,
    };

    /// Whether there is any.
    pub fn any(&self) -> bool {
        *self != Self::NONE
    }

    /// The style's services changed by the `[tileset]` keys (`services = false` turns them
    /// all off, then each key given turns its own back on), refused in a tile set without
    /// services.
    pub fn from_params(
        style: Services,
        s: &ServiceSettings,
        params: &Params,
        tileset: &str,
    ) -> Result<Services, ConfigError> {
        let keys = [
            ("services", s.services.is_some()),
            ("bolt_spacing", s.bolt_spacing.is_some()),
            ("duct_diameter", s.duct_diameter.is_some()),
            ("pipes", s.pipes.is_some()),
            ("cable_run", s.cable_run.is_some()),
            ("light_spacing", s.light_spacing.is_some()),
        ];
        if !style.any() {
            if let Some((key, _)) = keys.iter().find(|k| k.1) {
                return Err(params.error(
                    key,
                    format!(
                        "the {tileset} tile set has no services (bolts, duct, pipes, cable, \
                         lights: only the mine has them); remove {key}"
                    ),
                ));
            }
            return Ok(style);
        }
        let spacing = |key: &str, v: Option<f64>, low: f64, high: f64, example: &str| match v {
            Some(v) if !(v == 0.0 || (v.is_finite() && (low..=high).contains(&v))) => Err(params
                .error(
                    key,
                    format!(
                        "must be 0 (none) or from {low} to {high} metres, e.g. {key} = \
                             {example}"
                    ),
                )),
            _ => Ok(v),
        };
        let mut out = if s.services == Some(false) {
            Services::NONE
        } else {
            style
        };
        if let Some(v) = spacing("bolt_spacing", s.bolt_spacing, 0.5, 5.0, "1.2")? {
            out.bolt_spacing = v;
        }
        if let Some(v) = spacing("duct_diameter", s.duct_diameter, 0.3, 1.5, "1.0")? {
            out.duct_diameter = v;
        }
        if let Some(v) = spacing("light_spacing", s.light_spacing, 5.0, 500.0, "20")? {
            out.light_spacing = v;
        }
        if let Some(n) = s.pipes {
            if n > 4 {
                return Err(params.error("pipes", "must be from 0 to 4 pipes, e.g. pipes = 2"));
            }
            out.pipes = n;
        }
        if let Some(c) = s.cable_run {
            out.cable_run = c;
        }
        Ok(out)
    }

    /// The tile set's materials followed by the services' (only when there are services, so
    /// a world without them keeps its files).
    pub fn materials(&self, style: &[Material]) -> Vec<Material> {
        let mut out = style.to_vec();
        if self.any() {
            out.extend(MATERIALS.iter().map(|(n, c)| Material::coloured(n, *c)));
        }
        out
    }

    /// Places the services along the tiles' passage axes in the welded `visual` surface of
    /// `drift`s (`first_material`: index of `mine-bolt` among the world's materials).
    pub fn place(
        &self,
        drift: Drift,
        visual: &Mesh,
        axes: &[(subtgraph_core::grid::Cell, &PassageAxis)],
        seed: u64,
        first_material: u8,
    ) -> Fixtures {
        if !self.any() || axes.is_empty() {
            return Fixtures::default();
        }
        let rays = if self.bolt_spacing > 0.0 || self.light_spacing > 0.0 {
            Some(RayCaster::quick(visual))
        } else {
            None
        };
        let kit = Kit::new(first_material);
        let placer = place::Placer {
            services: self,
            drift,
            visual,
            rays: rays.as_ref(),
            seed,
        };
        let placements = placer.run(axes);
        let mut fixtures = Fixtures {
            prototypes: kit.prototypes,
            placements,
        };
        // Keep only the prototypes placed, numbered in order.
        let counts = fixtures.counts();
        let mut renumber = vec![u32::MAX; counts.len()];
        let mut kept = Vec::new();
        for (k, p) in std::mem::take(&mut fixtures.prototypes)
            .into_iter()
            .enumerate()
        {
            if counts[k] > 0 {
                renumber[k] = kept.len() as u32;
                kept.push(p);
            }
        }
        for p in &mut fixtures.placements {
            p.prototype = renumber[p.prototype as usize];
        }
        fixtures.prototypes = kept;
        fixtures
    }
}

/// What the placement needs of the passage (kept apart from the tile sets' `Passage`, which
/// carries the services' knobs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drift {
    /// Nominal width and height, metres.
    pub size: [f64; 2],
    /// The nearest the rock comes to the axis sideways: half the nominal width less its
    /// variation and relief, metres.
    pub wall: f64,
    /// The nearest the back comes to the floor: the nominal height less its variation and
    /// relief, metres.
    pub back: f64,
    /// The materials of rock walls and back (plain, striated and meshed).
    pub rock: [u8; 3],
}

/// The prototypes, in a fixed order ([`Kit::BOLT`] ...).
pub(crate) struct Kit {
    prototypes: Vec<Prototype>,
}

impl Kit {
    pub(crate) const BOLT: u32 = 0;
    pub(crate) const DUCT: u32 = 1;
    pub(crate) const PIPE: u32 = 2;
    pub(crate) const CABLE: u32 = 3;
    pub(crate) const LIGHT: u32 = 4;

    fn new(first: u8) -> Kit {
        let part = |name, mesh, k: u8| Prototype {
            name,
            mesh,
            material: first + k,
        };
        Kit {
            prototypes: vec![
                part("rock-bolt", parts::bolt(0.15, 0.04), 0),
                part("duct", parts::cylinder(16), 1),
                part("pipe", parts::cylinder(8), 2),
                part("cable", parts::cylinder(6), 3),
                part(
                    "light",
                    parts::cuboid([-0.25, -0.08, -0.14], [0.25, 0.08, 0.04]),
                    4,
                ),
            ],
        }
    }
}

/// The `[tileset]` keys of the services (in the procedural tile sets' settings).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ServiceSettings {
    /// `false`: none of the services (each key below then turns its own on again).
    pub services: Option<bool>,
    /// Metres between rock bolts (0: none).
    pub bolt_spacing: Option<f64>,
    /// The ventilation duct's diameter, metres (0: none).
    pub duct_diameter: Option<f64>,
    /// How many pipes along the wall.
    pub pipes: Option<u32>,
    /// Whether a cable run goes along the wall.
    pub cable_run: Option<bool>,
    /// Metres between lights (0: none).
    pub light_spacing: Option<f64>,
}
