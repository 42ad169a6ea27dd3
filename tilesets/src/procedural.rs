//! What the procedural tile sets share: resolving their knobs against the world, checking the
//! passages fit the tiles, and meshing a tile's block of the world field (visual at the full
//! resolution, collision at a coarser one).

use serde::Deserialize;
use subtgraph_core::Layout;
use subtgraph_core::budget::TileTriangles;
use subtgraph_core::error::ConfigError;
use subtgraph_core::mesh::Material;
use subtgraph_core::params::Params;
use subtgraph_core::tile::TileKind;
use subtgraph_core::tileset::{
    CrossSection, Seams, TileContext, TileGeometry, TileSet, TileSetError,
};

use crate::field::{Column, Levels, LocalField, Passage, Profile, material};
use crate::marching::{Block, polygonise_columns};

/// Triangles per lattice cell of surface that marching tetrahedra make on these fields
/// (measured on the presets; see the test `estimates_follow_the_meshes`).
const TRIANGLES_PER_CELL: f64 = 6.0;

/// Most rocks per tile: a rock pile's rocks are a tenth of the passage wide, so a few dozen
/// cover a tile's floor; more is not a cave, only work.
pub const MAX_ROCKS: f64 = 50.0;

/// The `[tileset]` keys every procedural tile set takes. Lengths in metres; when absent they
/// follow the world's pitch and `world.max_width`.
#[derive(Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Settings {
    /// Passage width (default: the style's share of the pitch, at most `world.max_width`).
    pub width: Option<f64>,
    /// Passage height.
    pub height: Option<f64>,
    /// Wall relief amplitude.
    pub roughness: Option<f64>,
    /// Rocks per tile (0 for none).
    pub rocks: Option<f64>,
    /// Lattice cells per tile pitch for the visual mesh: the detail level (multiple of 4).
    pub resolution: Option<u32>,
    /// Lattice cells per tile pitch for the collision mesh (multiple of 2, divides
    /// `resolution`).
    pub collision_resolution: Option<u32>,
    /// Which surface materials to paint; others fall back to the wall material.
    pub materials: Option<Vec<String>>,
}

/// A style: the look of one cave type, relative to the tile pitch.
pub struct Style {
    /// The tile set's `type` name.
    pub name: &'static str,
    /// Cross-section.
    pub profile: Box<dyn Profile>,
    /// Width as a fraction of the pitch.
    pub width: f64,
    /// Height as a fraction of the pitch.
    pub height: f64,
    /// Knobs as fractions of the width (roughness, rock size) or as they are.
    pub shape: Passage,
    /// Materials, indexed by [`material`].
    pub materials: Vec<Material>,
    /// Default rocks per tile.
    pub rocks: f64,
}

/// A procedural tile set: a style and the user's settings.
pub struct Procedural {
    style: Style,
    settings: Settings,
    enabled: [bool; 4],
}

impl Procedural {
    /// Builds a tile set from a style and the `[tileset]` table.
    pub fn from_params(style: Style, params: &Params) -> Result<Self, ConfigError> {
        let settings: Settings = params.deserialize()?;
        for (key, v) in [("width", settings.width), ("height", settings.height)] {
            if v.is_some_and(|v| !(v.is_finite() && v > 0.0)) {
                return Err(params.error(key, "must be a positive number of metres"));
            }
        }
        if settings
            .roughness
            .is_some_and(|v| !(v.is_finite() && v >= 0.0))
        {
            return Err(params.error("roughness", "must be a number >= 0"));
        }
        if let Some(r) = settings.rocks.filter(|r| !(0.0..=MAX_ROCKS).contains(r)) {
            return Err(params.error(
                "rocks",
                format!(
                    "rocks = {r} per tile: must be from 0 to {MAX_ROCKS} (a pile's rocks are a \
                     tenth of the passage wide; {MAX_ROCKS} cover a tile's floor)"
                ),
            ));
        }
        if let Some(r) = settings.resolution {
            if !(8..=256).contains(&r) || r % 4 != 0 {
                return Err(params.error(
                    "resolution",
                    "must be a multiple of 4 from 8 to 256 (lattice cells per tile pitch)",
                ));
            }
        }
        let res = settings.resolution.unwrap_or(24);
        if let Some(c) = settings.collision_resolution {
            if c < 4 || c % 2 != 0 || res % c != 0 {
                return Err(params.error(
                    "collision_resolution",
                    format!("must be even, at least 4, and divide resolution ({res})"),
                ));
            }
        }
        let mut enabled = [true; 4];
        if let Some(list) = &settings.materials {
            let names: Vec<&str> = style.materials.iter().map(|m| m.name.as_str()).collect();
            enabled = [false; 4];
            enabled[usize::from(material::WALL)] = true;
            for m in list {
                match names.iter().position(|n| n == m) {
                    Some(i) => enabled[i] = true,
                    None => {
                        return Err(params.error(
                            "materials",
                            format!(
                                "unknown material '{m}'; this tile set has: {}",
                                names.join(", ")
                            ),
                        ));
                    }
                }
            }
        }
        Ok(Self {
            style,
            settings,
            enabled,
        })
    }

    /// The passage knobs in metres for a world.
    pub fn passage(&self, world: &Layout) -> Passage {
        let pitch = world.resolved.tile_pitch;
        let s = &self.settings;
        let width = s
            .width
            .unwrap_or(self.style.width * pitch)
            .min(world.resolved.max_width);
        let base = &self.style.shape;
        Passage {
            width,
            height: s.height.unwrap_or(self.style.height * pitch),
            roughness: s.roughness.unwrap_or(base.roughness * width),
            roughness_scale: base.roughness_scale * width,
            floor_roughness: base.floor_roughness * width,
            rocks: s.rocks.unwrap_or(self.style.rocks),
            rock_size: base.rock_size * width,
            variation_scale: base.variation_scale * pitch,
            ..base.clone()
        }
    }

    fn resolution(&self) -> (u32, u32) {
        let r = self.settings.resolution.unwrap_or(24);
        (r, self.settings.collision_resolution.unwrap_or(r / 2))
    }

    fn levels(&self, world: &Layout) -> Levels {
        let h = world.resolved.tile_pitch / f64::from(self.resolution().0);
        Levels {
            height: world.resolved.level_height,
            below_floor: (0.12 * world.resolved.level_height).max(2.0 * h),
        }
    }

    fn block(world: &Layout, cell: subtgraph_core::grid::Cell, n: u32, levels: Levels) -> Block {
        let n = i64::from(n);
        let h = world.resolved.tile_pitch / n as f64;
        let off = world.level_offsets[cell.level];
        let col = cell.col as i64 + off[1];
        let row_up = world.occupancy.rows() as i64 - 1 - (cell.row as i64 + off[0]);
        let z = |l: usize| {
            let (lo, _) = levels.block_z(l);
            (lo / h).floor() as i64
        };
        let (z0, z1) = (z(cell.level), z(cell.level + 1));
        Block {
            origin: [col * n - n / 2, row_up * n - n / 2, z0],
            cubes: [n as usize, n as usize, (z1 - z0) as usize],
            h,
        }
    }
}

impl TileSet for Procedural {
    fn tile(&self, ctx: &TileContext<'_>) -> Result<TileGeometry, TileSetError> {
        let world = ctx.layout;
        let passage = self.passage(world);
        let levels = self.levels(world);
        let (visual_n, collision_n) = self.resolution();
        let fine = world.resolved.tile_pitch / f64::from(visual_n);
        let field = LocalField::around(
            world,
            ctx.cell,
            &passage,
            self.style.profile.as_ref(),
            levels,
            fine,
        );
        let enabled = self.enabled;
        let paint = |p: [f64; 3], col: &Column| {
            let (v, m) = field.at_column(p, col);
            (
                v,
                if enabled[usize::from(m)] {
                    m
                } else {
                    material::WALL
                },
            )
        };
        let column = |x: f64, y: f64| field.column(x, y);
        let block = |n| Self::block(world, ctx.cell, n, levels);
        let (visual, visual_seam) =
            polygonise_columns(block(visual_n), material::ROCK, column, paint);
        let (mut collision, collision_seam) =
            polygonise_columns(block(collision_n), material::ROCK, column, paint);
        collision.materials.clear();
        Ok(TileGeometry {
            visual,
            collision,
            seams: Seams::Listed {
                visual: visual_seam,
                collision: collision_seam,
            },
        })
    }

    fn materials(&self) -> Vec<Material> {
        self.style.materials.clone()
    }

    fn opening(&self, world: &Layout) -> Option<CrossSection> {
        let p = self.passage(world);
        Some(CrossSection {
            width: p.width,
            height: p.height,
        })
    }

    fn check(&self, world: &Layout) -> Result<(), TileSetError> {
        let p = self.passage(world);
        let pitch = world.resolved.tile_pitch;

        let levels = self.levels(world);
        let name = self.style.name;
        let half_width = 0.5 * p.width * (1.0 + p.width_variation) + p.roughness;
        let room = 0.5 * pitch - 2.0 * pitch / f64::from(self.resolution().0);
        if half_width > room {
            return Err(TileSetError::Unsuited {
                what: format!(
                    "{name}: passages up to {:.1} m wide (width {:.1} m with its variation and relief) \
                     do not fit tiles {pitch} m apart",
                    2.0 * half_width,
                    p.width
                ),
                fix: "use a smaller [tileset] width or roughness, or a larger world.tile_pitch"
                    .into(),
            });
        }
        if p.shaft_radius * p.width + p.roughness > room {
            return Err(TileSetError::Unsuited {
                what: format!("{name}: the shaft does not fit the tile"),
                fix: "use a smaller [tileset] width".into(),
            });
        }
        let top = p.height * (1.0 + p.height_variation) + p.roughness + p.floor_roughness;
        let head = world.resolved.level_height - 2.0 * levels.below_floor;
        if world.resolved.levels > 1 && top > head {
            return Err(TileSetError::Unsuited {
                what: format!(
                    "{name}: passages up to {top:.1} m high do not fit between levels {} m apart",
                    world.resolved.level_height
                ),
                fix: "raise world.level_height or lower [tileset] height".into(),
            });
        }
        Ok(())
    }

    fn texture_scale(&self) -> f32 {
        3.0
    }

    fn estimate(&self, world: &Layout, kind: TileKind) -> Option<TileTriangles> {
        // Marching tetrahedra make about TRIANGLES_PER_CELL triangles per lattice cell of
        // surface, and a tile's surface is its half-corridors' walls (the section's perimeter
        // along half a pitch each), its shaft's and its rocks'.
        let p = self.passage(world);
        let pitch = world.resolved.tile_pitch;
        let perimeter =
            2.0 * (p.width * (1.0 + p.width_variation) + p.height * (1.0 + p.height_variation));
        let arms = match kind {
            TileKind::DeadEnd | TileKind::ShaftUp | TileKind::ShaftLanding => 1.0,
            TileKind::Straight | TileKind::Corner => 2.0,
            TileKind::TJunction => 3.0,
            TileKind::Intersection => 4.0,
        };
        let shaft = if matches!(kind, TileKind::ShaftUp | TileKind::ShaftLanding) {
            std::f64::consts::TAU * p.shaft_radius * p.width * 0.5 * world.resolved.level_height
        } else {
            0.0
        };
        let rocks = p.rocks.ceil() * 2.0 * std::f64::consts::TAU * p.rock_size * p.rock_size;
        let area = arms * perimeter * 0.5 * pitch + shaft + rocks;
        let (visual, collision) = self.resolution();
        let triangles = |n: u32| {
            let h = pitch / f64::from(n);
            TRIANGLES_PER_CELL * area / (h * h)
        };
        Some(TileTriangles {
            visual: triangles(visual),
            collision: triangles(collision),
        })
    }

    fn detail_advice(&self) -> Option<String> {
        let (visual, collision) = self.resolution();
        Some(format!(
            "lower [tileset] resolution (now {visual}; triangles grow with its square) or \
             collision_resolution (now {collision})"
        ))
    }
}
