//! What the procedural tile sets share: resolving their knobs against the world, checking the
//! passages fit the tiles, and meshing a tile's block of the world field (visual at the full
//! resolution; its collision copy simplified from it within `collision_tolerance`).

use serde::Deserialize;
use subtgraph_core::Layout;
use subtgraph_core::budget::TileTriangles;
use subtgraph_core::config::Connections;
use subtgraph_core::error::{ConfigError, number};
use subtgraph_core::grid::Shaft;
use subtgraph_core::mesh::{ImageFile, Material};
use subtgraph_core::params::Params;
use subtgraph_core::tile::TileKind;
use subtgraph_core::tileset::{
    CrossSection, Seams, TileContext, TileGeometry, TileSet, TileSetError,
};

use crate::chambers::{ChamberSettings, SqueezeSettings, least_factors};
use crate::field::{Column, LocalField};
use crate::finish::Finish;
use crate::marching::{Block, polygonise_columns};
use crate::owner::Owners;
use crate::passage::{Levels, Passage, Profile, material};
use crate::ramp::{self, Helix, Sizing, Unfit};
use crate::services::{ServiceSettings, Services};
use crate::slope::Slope;
use crate::textures::Textures;
use crate::textures::rock::Look;

/// Triangles per lattice cell of surface that marching tetrahedra make on these fields
/// (measured on the presets; see the test `estimates_follow_the_meshes`).
const TRIANGLES_PER_CELL: f64 = 6.0;

/// The collision copy's triangles per visual triangle at the default tolerance (measured on
/// the presets, seed 1: cave 0.15, mine 0.12, lava tube 0.11), rounded up.
const COLLISION_SHARE: f64 = 0.16;

/// Metres per texture repeat: the box-projected texture coordinates' scale and the size of
/// one tile of the procedural textures.
pub const TEXTURE_REPEAT: f32 = 3.0;

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
    /// Wall relief amplitude of the style's plain relief (given alone, it means
    /// `finish = "none"` in a tile set with finishes).
    pub roughness: Option<f64>,
    /// How walls and back are finished, in tile sets that have finishes (mine): `"blasted"`
    /// (the mine's default), `"shotcrete"` or `"none"` (see [`crate::finish`]).
    pub finish: Option<String>,
    /// Relief RMS of the finish, centimetres (blasted 15, shotcrete 4).
    pub relief: Option<f64>,
    /// Length of a blast round along the drift, metres (3.5).
    pub round_length: Option<f64>,
    /// Metres of straight drift per refuge bay on average, in tile sets with bays (mine:
    /// 150; 0 for none).
    pub refuge_spacing: Option<f64>,
    /// Metres above the floor from which welded mesh panels cover the walls and back, in tile
    /// sets with finishes (mine: 2; 0 for none). Painted in the textures, not modelled.
    pub mesh_from: Option<f64>,
    /// Rocks per tile (0 for none).
    pub rocks: Option<f64>,
    /// `false`: no services (bolts, duct, pipes, cable, lights), in tile sets with them (mine;
    /// see [`crate::services`]).
    pub services: Option<bool>,
    /// Metres between rock bolts, along the drift and around the back (mine: 1.2; 0: none).
    pub bolt_spacing: Option<f64>,
    /// The ventilation duct's diameter, metres (mine: 1.0; 0: none).
    pub duct_diameter: Option<f64>,
    /// Pipes along one wall (mine: 2).
    pub pipes: Option<u32>,
    /// A cable run along the pipes' wall (mine: true).
    pub cable_run: Option<bool>,
    /// Metres between lights on the back (mine: 20; 0: none).
    pub light_spacing: Option<f64>,
    /// Lattice cells per tile pitch for the visual mesh: the detail level (multiple of 4).
    pub resolution: Option<u32>,
    /// Lattice cells per tile pitch of the coarse lattice (multiple of 2, divides
    /// `resolution`): the smallest rubble rock, the rock about a ramp and a squeeze's slack
    /// follow it (the collision mesh was marched on it before `collision_tolerance`).
    pub collision_resolution: Option<u32>,
    /// `[floors, the rest]`, metres: how far the visual surface may lie from the collision
    /// surface (see [`crate::collision`]; default `[0.02, 0.10]`, `[0, 0]` for a copy of the
    /// visual surface).
    pub collision_tolerance: Option<[f64; 2]>,
    /// Which surface materials to paint; others fall back to the wall material.
    pub materials: Option<Vec<String>>,
    /// Rooms at junctions and dead ends (see [`crate::chambers`]).
    pub chambers: Option<ChamberSettings>,
    /// Narrow or low places along corridors.
    pub squeezes: Option<SqueezeSettings>,
    /// `[width, height]`, metres: the least room a squeeze leaves (a robot's size).
    pub min_clearance: Option<[f64; 2]>,
    /// `[low, high]` degrees: the steepest grade of the floors, drawn per world from this range
    /// (`[0, 0]` for flat floors).
    pub grade: Option<[f64; 2]>,
    /// `"procedural"` (the default), `"none"`, or the user's images by material (read by
    /// [`crate::textures::Textures::from_params`]).
    pub textures: Option<toml::Value>,
    /// Pixels per texture repeat (see [`crate::textures`]).
    pub texture_size: Option<i64>,
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
    enabled: [bool; 5],
    textures: Textures,
    services: Services,
}

impl Procedural {
    /// The rock surfaces' materials ([`surface_materials`]), before the services'.
    fn surfaces(&self) -> Vec<Material> {
        surface_materials(&self.style.materials, self.mesh_from())
    }

    /// Metres above the floor where mesh panels start (0: none), as asked or the style's.
    fn mesh_from(&self) -> f64 {
        self.settings
            .mesh_from
            .unwrap_or(self.style.shape.mesh_from)
    }

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
        if let Some(why) = settings.grade.and_then(crate::slope::invalid) {
            return Err(params.error("grade", why));
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
        if settings.collision_tolerance.is_some_and(|t| {
            t.iter()
                .any(|v| !(v.is_finite() && (0.0..=1.0).contains(v)))
        }) {
            return Err(params.error(
                "collision_tolerance",
                "must be [floors, the rest] in metres, each from 0 to 1 (how far the visual \
                 surface may lie from the collision surface), e.g. collision_tolerance = \
                 [0.02, 0.10]",
            ));
        }
        check_rooms(&settings, params)?;
        check_finish(&style, &settings, params)?;
        let surfaces = surface_materials(
            &style.materials,
            settings.mesh_from.unwrap_or(style.shape.mesh_from),
        );
        let mut enabled = [true; 5];
        if let Some(list) = &settings.materials {
            let names: Vec<&str> = surfaces.iter().map(|m| m.name.as_str()).collect();
            enabled = [false; 5];
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
        let services = Services::from_params(
            style.shape.services,
            &ServiceSettings {
                services: settings.services,
                bolt_spacing: settings.bolt_spacing,
                duct_diameter: settings.duct_diameter,
                pipes: settings.pipes,
                cable_run: settings.cable_run,
                light_spacing: settings.light_spacing,
            },
            params,
            style.name,
        )?;
        let textures = Textures::from_params(params, &services.materials(&surfaces))?;
        let mut tileset = Self {
            style,
            settings,
            enabled,
            textures,
            services,
        };
        // Half-barrel marks run along the drift, and the box projection lays them along it
        // on walls alone, so they are drawn where the back is under mesh (`crate::finish`;
        // not when `materials` leaves the mesh out and the wall material takes the back).
        if matches!(tileset.finish(), Finish::Blasted { .. })
            && tileset.mesh_from() > 0.0
            && tileset.enabled[usize::from(material::MESHED)]
        {
            let wall = &tileset.style.materials[usize::from(material::WALL)].name;
            tileset.textures = tileset.textures.clone().with_look(wall, Look::Blasted);
        }
        Ok(tileset)
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
        // A straight cell's meander keeps the widest passage inside its cell, two lattice
        // cells clear of its sides.
        let roughness = self.relief_amplitude(width);
        let half_width = 0.5 * width * (1.0 + base.width_variation) + roughness;
        let lattice = pitch / f64::from(self.resolution().0);
        let room = 0.5 * pitch - half_width - 2.0 * lattice;
        let mut passage = Passage {
            width,
            height: s.height.unwrap_or(self.style.height * pitch),
            roughness,
            finish: self.finish(),
            refuge_spacing: s.refuge_spacing.unwrap_or(base.refuge_spacing),
            roughness_scale: base.roughness_scale * width,
            floor_roughness: base.floor_roughness * width,
            rocks: s.rocks.unwrap_or(self.style.rocks),
            rock_size: base.rock_size * width,
            variation_scale: base.variation_scale * pitch,
            rooms: self.rooms(world, width),
            meander: (base.meander * pitch).min(room).max(0.0),
            hazard_lattice: pitch / f64::from(self.resolution().1),
            services: self.services,
            mesh_from: self.mesh_from(),
            ..base.clone()
        };
        passage.slope = self.slope(world, &passage);
        passage
    }

    /// The walls' finish: the style's default, or as `[tileset]` asks (`finish`, `relief`,
    /// `round_length`); `roughness` given alone keeps the plain relief it sets.
    fn finish(&self) -> Finish {
        let s = &self.settings;
        let kind = match (s.finish.as_deref(), self.style.shape.finish) {
            (Some(k), _) => k,
            (None, _) if s.roughness.is_some() => "none",
            (None, Finish::Blasted { .. }) => "blasted",
            (None, Finish::Shotcrete { .. }) => "shotcrete",
            (None, Finish::Plain) => "none",
        };
        let rms = |default: f64| s.relief.map_or(default, |cm| 0.01 * cm);
        match kind {
            "blasted" if rms(crate::finish::BLASTED_RMS) > 0.0 => Finish::Blasted {
                rms: rms(crate::finish::BLASTED_RMS),
                round: s.round_length.unwrap_or(crate::finish::ROUND),
            },
            "shotcrete" if rms(crate::finish::SHOTCRETE_RMS) > 0.0 => Finish::Shotcrete {
                rms: rms(crate::finish::SHOTCRETE_RMS),
            },
            _ => Finish::Plain,
        }
    }

    /// The wall relief's amplitude for passages `width` wide: the finish's peak, or the
    /// style's (or the user's) roughness.
    fn relief_amplitude(&self, width: f64) -> f64 {
        self.finish().peak().unwrap_or_else(|| {
            self.settings
                .roughness
                .unwrap_or(self.style.shape.roughness * width)
        })
    }

    /// The grade range, degrees: as asked for (refused by [`TileSet::check`] when its rise
    /// does not fit under the next level), or the style's default, lowered to what fits.
    fn grade(&self, world: &Layout, p: &Passage) -> [f64; 2] {
        if let Some(g) = self.settings.grade {
            return g;
        }
        let [low, high] = self.style.shape.grade;
        let room = self.lift_room(world, p).max(0.0);
        let fits = (room * std::f64::consts::PI / world.resolved.tile_pitch)
            .atan()
            .to_degrees();
        let high = high.min(0.999 * fits);
        [low.min(high), high]
    }

    /// Metres a floor may rise above its level's nominal floor: what the passage's highest
    /// ceiling leaves below the next level's block (on one level, the same margin below the top
    /// of its own block, so the ceiling stays a closed surface inside the tile).
    fn lift_room(&self, world: &Layout, p: &Passage) -> f64 {
        let top = p.height * (1.0 + p.height_variation) + p.roughness + p.floor_roughness;
        self.levels(world).head() - top
    }

    /// The floors' waves: as long as a few tiles (at least one pitch, at most three), shorter
    /// where a long wave's rise would not fit under the next level.
    fn slope(&self, world: &Layout, p: &Passage) -> Slope {
        let [_, high] = self.grade(world, p);
        if high <= 0.0 {
            return Slope::flat();
        }
        let pitch = world.resolved.tile_pitch;
        let room = self.lift_room(world, p).max(0.0);
        let wavelength =
            (room * std::f64::consts::PI / high.to_radians().tan()).clamp(pitch, 3.0 * pitch);
        let grade = crate::slope::draw_grade(world.resolved.seed, self.grade(world, p));
        Slope::new(world.resolved.seed, grade, wavelength)
    }

    /// Chambers and squeezes in metres: the style's defaults and the user's keys, with the
    /// least squeeze factors that keep `min_clearance` (and the wall relief, and half a
    /// collision lattice cell for the coarser collision surface) clear.
    fn rooms(&self, world: &Layout, width: f64) -> crate::passage::Rooms {
        let pitch = world.resolved.tile_pitch;
        let s = &self.settings;
        let base = &self.style.shape;
        let mut rooms = base.rooms.clone();
        rooms.squeeze_length = rooms.squeeze_length.map(|l| l * pitch);
        if let Some(c) = &s.chambers {
            rooms.chamber_rate = c.rate.unwrap_or(rooms.chamber_rate);
            rooms.chamber_size = c.size.unwrap_or(rooms.chamber_size);
        }
        if let Some(q) = &s.squeezes {
            rooms.squeeze_rate = q.rate.unwrap_or(rooms.squeeze_rate);
            rooms.squeeze_length = q.length.unwrap_or(rooms.squeeze_length);
            rooms.squeeze_factor = q.factor.unwrap_or(rooms.squeeze_factor);
        }
        rooms.min_clearance = s.min_clearance.unwrap_or(rooms.min_clearance);
        rooms.least_factor = self.least_factors(world, width, rooms.min_clearance);
        rooms
    }

    /// The least squeeze factors that keep a `clearance` box clear in passages `width` wide
    /// (more than 1 when even the unsqueezed passage cannot hold it).
    fn least_factors(&self, world: &Layout, width: f64, clearance: [f64; 2]) -> [f64; 2] {
        self.least_factors_within(world, width, clearance, true)
    }

    /// [`Self::least_factors`], with or without the `lattice` slack: half a collision lattice
    /// cell, which the coarser collision surface may take from the passage.
    fn least_factors_within(
        &self,
        world: &Layout,
        width: f64,
        clearance: [f64; 2],
        lattice: bool,
    ) -> [f64; 2] {
        let pitch = world.resolved.tile_pitch;
        let s = &self.settings;
        let base = &self.style.shape;
        let height = s.height.unwrap_or(self.style.height * pitch);
        let relief = self.relief_amplitude(width);
        // Half a collision lattice cell, and what a sloping floor (`tilesets/src/slope.rs`)
        // rises across the box: slopes run any way, so the floor tilts across passages too.
        let steepest = s.grade.map_or(base.grade[1], |g| g[1]).max(0.0);
        let cell = if lattice {
            0.5 * pitch / f64::from(self.resolution().1)
        } else {
            0.0
        };
        let slack = cell + steepest.to_radians().tan() * clearance[0];
        least_factors(
            self.style.profile.as_ref(),
            width * (1.0 - base.width_variation),
            height * (1.0 - base.height_variation),
            clearance,
            relief,
            slack,
        )
    }

    /// Why the robot's box `min_clearance` does not fit even the unsqueezed passage, with the
    /// largest box of the same proportions that does. The same for a written value and the
    /// default (a small ground robot): the same value gives the same answer.
    fn clearance_unfit(&self, world: &Layout, p: &Passage) -> TileSetError {
        let name = self.style.name;
        let [cw, ch] = p.rooms.min_clearance;
        let holds = |k: f64| {
            self.least_factors_within(world, p.width, [k * cw, k * ch], false)
                .iter()
                .all(|&f| f <= 1.0)
        };
        let (mut lo, mut hi) = (0.0, 1.0);
        for _ in 0..40 {
            let mid = 0.5 * (lo + hi);
            if holds(mid) {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        // Rounded down to 5 cm, so the value suggested fits as written.
        let down = |x: f64| number((x * 20.0).floor() / 20.0);
        let default = match self.settings.min_clearance {
            Some(_) => "",
            None => " (its default: a small ground robot)",
        };
        let smaller = if (lo * cw * 20.0).floor() > 0.0 && (lo * ch * 20.0).floor() > 0.0 {
            format!(
                "set [tileset] min_clearance = [{}, {}] or less (the largest robot of these \
                 proportions the passage holds), or widen the passage ([tileset] width, \
                 height)",
                down(lo * cw),
                down(lo * ch)
            )
        } else {
            "widen the passage ([tileset] width, height), or give a smaller [tileset] \
             min_clearance"
                .to_owned()
        };
        TileSetError::Unsuited {
            what: format!(
                "{name}: [tileset] min_clearance = [{}, {}]{default} does not fit even the \
                 unsqueezed passage ({:.1} m \
                 wide, {:.1} m high at its narrowest, less {:.2} m of wall relief)",
                number(cw),
                number(ch),
                p.width * (1.0 - p.width_variation),
                p.height * (1.0 - p.height_variation),
                p.roughness
            ),
            fix: smaller,
        }
    }

    /// `[floors, the rest]`, metres: as asked, or [`crate::collision::DEFAULT_TOLERANCE`].
    fn collision_tolerance(&self) -> [f64; 2] {
        self.settings
            .collision_tolerance
            .unwrap_or(crate::collision::DEFAULT_TOLERANCE)
    }

    fn resolution(&self) -> (u32, u32) {
        let r = self.settings.resolution.unwrap_or(24);
        (r, self.settings.collision_resolution.unwrap_or(r / 2))
    }

    fn levels(&self, world: &Layout) -> Levels {
        self.levels_apart(world, world.resolved.level_height)
    }

    /// The levels' vertical layout were they `height` metres apart.
    fn levels_apart(&self, world: &Layout, height: f64) -> Levels {
        let h = world.resolved.tile_pitch / f64::from(self.resolution().0);
        let rock = (0.12 * height).max(2.0 * h);
        let mut below_floor = rock;
        if crate::rubble::has_drops(world) {
            below_floor = below_floor.max(self.pit_depth(world) + 2.0 * h);
        }
        Levels {
            height,
            below_floor,
            above_ceiling: rock,
            coarse: world.resolved.tile_pitch / f64::from(self.resolution().1),
        }
    }

    /// How deep a drop's pit is. It comes from the nominal height alone: `passage()` needs
    /// the levels (through the slopes' room and the chambers' fit), so calling it here would
    /// recurse.
    fn pit_depth(&self, world: &Layout) -> f64 {
        let height = self
            .settings
            .height
            .unwrap_or(self.style.height * world.resolved.tile_pitch);
        crate::rubble::pit_depth(height)
    }

    /// Why passages up to `top` metres high do not fit between the levels: what the rock
    /// under the next level's floor (a drop's pit and the rock under it, in a world with
    /// drops) and above this level's ceiling leave, and the level spacing that would fit.
    fn levels_too_close(&self, world: &Layout, levels: &Levels, top: f64) -> TileSetError {
        let name = self.style.name;
        let apart = number(levels.height);
        // The spacing that fits, rounded up to the decimetre shown. The rock grows with the
        // spacing (an eighth of it), so the spacing is found as the fixed point of
        // `top + rock(spacing)`, which a few rounds reach (each step is at most a quarter of
        // the last).
        let mut need = levels.height;
        for _ in 0..64 {
            let l = self.levels_apart(world, need);
            need = top + l.below_floor + l.above_ceiling;
        }
        let need = (need * 10.0).ceil() / 10.0;
        let rock = levels.above_ceiling;
        let pit = self.pit_depth(world);
        if crate::rubble::has_drops(world) && levels.below_floor > rock {
            let under = levels.below_floor - pit;
            if top <= levels.height - 2.0 * rock {
                return TileSetError::Unsuited {
                    what: format!(
                        "{name}: hazards.drops: a drop's pit is {pit:.1} m deep with {under:.1} m \
                         of rock under it, so with passages up to {top:.1} m high and {rock:.1} m \
                         of rock above them levels must be at least {need:.1} m apart; they are \
                         {apart} m apart (without drops they would fit)"
                    ),
                    fix: format!(
                        "raise world.level_height to {need:.1} or more, lower [tileset] height \
                         (a pit is 0.3 of it deep), use a finer [tileset] resolution (the rock \
                         under a pit is two lattice cells), or leave out hazards.drops"
                    ),
                };
            }
        }
        let below = levels.below_floor;
        let pits = if levels.below_floor > rock {
            " (a drop's pit and the rock under it: hazards.drops)"
        } else {
            ""
        };
        TileSetError::Unsuited {
            what: format!(
                "{name}: passages up to {top:.1} m high, with {rock:.1} m of rock above their \
                 ceiling and {below:.1} m under the next level's floor{pits}, need levels at \
                 least {need:.1} m apart; they are {apart} m apart"
            ),
            fix: format!(
                "raise world.level_height to {need:.1} or more, or lower [tileset] height"
            ),
        }
    }

    /// The ramp of `shaft` when the world has ramps, or why it does not fit.
    fn ramp_plan(&self, world: &Layout, shaft: &Shaft) -> Result<Option<Helix>, TileSetError> {
        if world.resolved.connections != Connections::Ramp {
            return Ok(None);
        }
        let p = self.passage(world);
        let (visual, collision) = self.resolution();
        let pitch = world.resolved.tile_pitch;
        let sizing = Sizing::of(
            world,
            &p,
            pitch / f64::from(visual),
            pitch / f64::from(collision),
        );
        let name = self.style.name;
        ramp::plan(world, shaft, &sizing)
            .map(Some)
            .map_err(|e| {
                match e {
            Unfit::Narrow { width, room } => TileSetError::Unsuited {
                what: format!(
                    "{name}: a ramp of passages {width:.1} m wide leaves no rock pillar in tiles \
                     {} m apart (the spiral must stay within {room:.1} m of its centre)",
                    number(pitch)
                ),
                fix: "use a smaller [tileset] width, a larger world.tile_pitch, a finer [tileset] \
                      resolution or collision_resolution (the pillar must hold collision lattice \
                      cells), or world.connections = \"shaft\""
                    .into(),
            },
            Unfit::Steep { grade } => TileSetError::Unsuited {
                what: format!(
                    "{name}: the gentlest ramp between levels {} m apart in tiles {} m apart \
                     climbs at {grade:.1} degrees, steeper than world.ramp_grade = {} (each turn \
                     must hold the {:.1} m high spiral passage and rock above it)",
                    number(world.resolved.level_height),
                    number(pitch),
                    number(world.resolved.ramp_grade),
                    sizing.height
                ),
                fix: "raise world.ramp_grade, use a larger world.tile_pitch or a lower [tileset] \
                      height, or set world.connections = \"shaft\""
                    .into(),
            },
        }
            })
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
        // A ramp's end meshes its whole spiral block on its level: the block's other three
        // cells are empty on both levels, so no other tile covers them.
        let (mut origin, mut cubes) = ([col * n - n / 2, row_up * n - n / 2, z0], [n, n]);
        if let Some([dr, dc]) = crate::ramp::shaft_of(world, cell).and_then(|s| s.block) {
            cubes = [2 * n, 2 * n];
            if dc < 0 {
                origin[0] -= n;
            }
            if dr > 0 {
                origin[1] -= n;
            }
        }
        Block {
            origin,
            cubes: [cubes[0] as usize, cubes[1] as usize, (z1 - z0) as usize],
            h,
        }
    }
}

/// The materials of a tile set's rock surfaces: its style's, then the meshed walls' when
/// mesh panels are on (at [`material::MESHED`]).
fn surface_materials(style: &[Material], mesh_from: f64) -> Vec<Material> {
    debug_assert_eq!(style.len(), usize::from(material::MESHED));
    let mut out = style.to_vec();
    if mesh_from > 0.0 {
        // A little lighter than the rock: the galvanised wire, where no texture shows it.
        let c = style[usize::from(material::WALL)].colour;
        out.push(Material::coloured("meshed-wall", c.map(|c| c * 0.85 + 0.1)));
    }
    out
}

/// Checks the `finish`, `relief` and `round_length` keys: known values, in a tile set that has
/// finishes, not mixed with the plain relief's `roughness`.
fn check_finish(style: &Style, s: &Settings, params: &Params) -> Result<(), ConfigError> {
    let name = style.name;
    let asked = s.finish.is_some()
        || s.relief.is_some()
        || s.round_length.is_some()
        || s.refuge_spacing.is_some()
        || s.mesh_from.is_some();
    // A tile set with finishes is one whose style has a finish or refuge bays of its own (the
    // mine: blasted walls and refuge bays by default).
    let has_finishes = !style.shape.finish.is_plain() || style.shape.refuge_spacing > 0.0;
    if asked && !has_finishes {
        let key = if s.finish.is_some() {
            "finish"
        } else if s.relief.is_some() {
            "relief"
        } else if s.round_length.is_some() {
            "round_length"
        } else if s.refuge_spacing.is_some() {
            "refuge_spacing"
        } else {
            "mesh_from"
        };
        return Err(params.error(
            key,
            format!(
                "the {name} tile set has no wall finishes, refuge bays or mesh panels (only \
                 mine has them); remove {key} (its wall relief is set with roughness)"
            ),
        ));
    }
    if let Some(f) = s.finish.as_deref() {
        if !matches!(f, "blasted" | "shotcrete" | "none") {
            return Err(params.error(
                "finish",
                format!("unknown finish '{f}': use \"blasted\", \"shotcrete\" or \"none\""),
            ));
        }
        if f != "none" && s.roughness.is_some() {
            return Err(params.error(
                "roughness",
                format!(
                    "roughness sets the plain relief of finish = \"none\"; with finish = \"{f}\" \
                     set relief (centimetres RMS) instead, or drop roughness"
                ),
            ));
        }
    }
    if s.relief
        .is_some_and(|r| !(r.is_finite() && (0.0..=50.0).contains(&r)))
    {
        return Err(params.error(
            "relief",
            "must be from 0 to 50 (centimetres RMS of the walls' relief; blasted rock 10-20, \
             shotcrete 2-6)",
        ));
    }
    if s.round_length
        .is_some_and(|r| !(r.is_finite() && (0.5..=20.0).contains(&r)))
    {
        return Err(params.error(
            "round_length",
            "must be from 0.5 to 20 metres (the advance of one blast round; 3-4 typical)",
        ));
    }
    if s.refuge_spacing
        .is_some_and(|r| !(r.is_finite() && (r == 0.0 || r >= 20.0)))
    {
        return Err(params.error(
            "refuge_spacing",
            "must be 0 (no refuge bays) or at least 20 metres of straight drift per bay on \
             average, e.g. refuge_spacing = 150",
        ));
    }
    if s.mesh_from
        .is_some_and(|m| !(m.is_finite() && (m == 0.0 || (0.5..=20.0).contains(&m))))
    {
        return Err(params.error(
            "mesh_from",
            "must be 0 (no mesh panels) or from 0.5 to 20 metres above the floor, the height \
             where the mesh over the walls and back begins, e.g. mesh_from = 2",
        ));
    }
    Ok(())
}

/// Checks the `chambers`, `squeezes` and `min_clearance` keys' values.
fn check_rooms(s: &Settings, params: &Params) -> Result<(), ConfigError> {
    let share = |v: Option<f64>| v.is_some_and(|v| !(0.0..=1.0).contains(&v));
    let range = |r: Option<[f64; 2]>, lo: f64, hi: f64| {
        r.is_some_and(|[a, b]| !(a.is_finite() && b.is_finite() && lo <= a && a <= b && b <= hi))
    };
    if let Some(c) = &s.chambers {
        if share(c.rate) {
            return Err(params.error(
                "chambers.rate",
                "must be from 0 to 1 (the share of junction and dead-end tiles with a chamber)",
            ));
        }
        if range(c.size, 1.0, 10.0) {
            return Err(params.error(
                "chambers.size",
                "must be [low, high] passage widths with 1 <= low <= high <= 10, e.g. \
                 size = [2.0, 3.0] (a chamber is also clamped to fit its tile)",
            ));
        }
    }
    if let Some(q) = &s.squeezes {
        if share(q.rate) {
            return Err(params.error(
                "squeezes.rate",
                "must be from 0 to 1 (the share of straight and corner tiles with a squeeze)",
            ));
        }
        if range(q.length, 0.0, 1e4) {
            return Err(params.error(
                "squeezes.length",
                "must be [low, high] metres with 0 <= low <= high, e.g. length = [3.0, 8.0]",
            ));
        }
        if range(q.factor, 0.0, 1.0) || q.factor.is_some_and(|f| f[0] <= 0.0) {
            return Err(params.error(
                "squeezes.factor",
                "must be [low, high] with 0 < low <= high <= 1 (the passage's size at the \
                 squeeze as a share of its size), e.g. factor = [0.45, 0.7]",
            ));
        }
    }
    if s.min_clearance
        .is_some_and(|c| c.iter().any(|v| !(v.is_finite() && *v > 0.0)))
    {
        return Err(params.error(
            "min_clearance",
            "must be [width, height] in metres, both positive (a robot's size), e.g. \
             min_clearance = [1.0, 1.0]",
        ));
    }
    Ok(())
}

impl TileSet for Procedural {
    fn tile(&self, ctx: &TileContext<'_>) -> Result<TileGeometry, TileSetError> {
        let world = ctx.layout;
        let passage = self.passage(world);
        let levels = self.levels(world);
        let (visual_n, _) = self.resolution();
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
        // Points beyond the block, for a small piece across a face (`crate::islands`).
        let blocks_of = |n: u32| move |cell| Self::block(world, cell, n, levels);
        let visual_blocks = blocks_of(visual_n);
        let profile = self.style.profile.as_ref();
        let visual_owners = Owners::new(
            world,
            &passage,
            profile,
            levels,
            fine,
            &visual_blocks,
            &field,
        );
        let h = world.resolved.tile_pitch / f64::from(visual_n);
        let (visual, visual_seam) =
            polygonise_columns(block(visual_n), material::ROCK, column, paint, |p| {
                visual_owners.value(p, h)
            });
        let (collision, collision_seam) =
            crate::collision::collision_of(&visual, &visual_seam, self.collision_tolerance());
        let (chamber, squeeze) =
            crate::chambers::of_cell(world, ctx.cell, ctx.tile.kind, &passage, levels, fine);
        // No rubble or drop in a squeeze (`crate::rubble::tile_hazard` says none there).
        let hazards =
            crate::rubble::tile_hazard(world, ctx.cell, &passage, self.style.profile.as_ref())
                .map(|h| vec![h.region])
                .unwrap_or_default();
        let mut labels = crate::chambers::labels(&chamber, &squeeze);
        if visual.materials.contains(&material::MESHED) {
            labels.push("mesh-panels");
        }
        if crate::refuge::of_cell(
            world,
            ctx.cell,
            ctx.tile.kind,
            ctx.tile.openings,
            &passage,
            squeeze.is_some(),
        )
        .is_some()
        {
            labels.push("refuge-bay");
        }
        Ok(TileGeometry {
            labels,
            visual,
            collision,
            seams: Seams::Listed {
                visual: visual_seam,
                collision: collision_seam,
            },
            hazards,
            axis: crate::axis::passage_axis(world, ctx.cell, &passage, levels, fine),
        })
    }

    fn fixtures(
        &self,
        world: &Layout,
        visual: &subtgraph_core::mesh::Mesh,
        axes: &[(
            subtgraph_core::grid::Cell,
            &subtgraph_core::tileset::PassageAxis,
        )],
    ) -> Result<subtgraph_core::mesh::Fixtures, TileSetError> {
        let seed = subtgraph_core::rng::derive_seed(world.resolved.seed, "services", 0);
        let first = self.surfaces().len() as u8;
        let p = self.passage(world);
        // The nominal section less its variation and relief: the rock is never nearer.
        let drift = crate::services::Drift {
            size: [p.width, p.height],
            back: p.height * (1.0 - p.height_variation) - p.roughness,
            wall: 0.5 * p.width * (1.0 - p.width_variation) - p.roughness,
            rock: [material::WALL, material::STRIATED, material::MESHED],
        };
        Ok(self.services.place(drift, visual, axes, seed, first))
    }

    fn materials(&self) -> Vec<Material> {
        self.textures
            .apply(&self.services.materials(&self.surfaces()))
    }

    fn textures(&self, seed: u64) -> Result<Vec<ImageFile>, TileSetError> {
        Ok(self.textures.files(
            &self.services.materials(&self.surfaces()),
            seed,
            f64::from(TEXTURE_REPEAT),
        ))
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
                     do not fit tiles {} m apart",
                    2.0 * half_width,
                    p.width,
                    number(pitch)
                ),
                fix: "use a smaller [tileset] width or roughness, or a larger world.tile_pitch"
                    .into(),
            });
        }
        // Mesh that starts above the lowest back would leave bare back rock, on which the
        // half-barrel marks' texture cannot follow a drift's direction (`crate::finish`).
        let back = p.height * (1.0 - p.height_variation) - p.roughness;
        if p.mesh_from > 0.0 && p.mesh_from >= back {
            return Err(TileSetError::Unsuited {
                what: format!(
                    "{name}: mesh panels from {} m up would leave the back bare where it is \
                     lowest ({back:.1} m above the floor)",
                    number(p.mesh_from)
                ),
                fix: format!(
                    "set [tileset] mesh_from below {back:.1} m (the default is {}), or 0 for \
                     no mesh",
                    number(self.style.shape.mesh_from)
                ),
            });
        }
        if p.shaft_radius * p.width * (1.0 + crate::field::SHAFT_SWELL) + p.roughness > room {
            return Err(TileSetError::Unsuited {
                what: format!("{name}: the shaft does not fit the tile"),
                fix: "use a smaller [tileset] width".into(),
            });
        }
        // After the passage fits its tile (a passage too wide for the tile is told so, not
        // blamed on the robot): the robot's box must fit the unsqueezed passage, whether `min_clearance` was
        // written or left to its default (the same value gives the same answer). The
        // collision lattice's slack is left out here: it bounds how far a squeeze may close
        // (with it, no squeeze is made where the box would not stay clear), but a passage
        // that holds the box only without it is what any coarse lattice makes, default robot
        // or not, and is made.
        if self
            .least_factors_within(world, p.width, p.rooms.min_clearance, false)
            .iter()
            .any(|&f| f > 1.0)
        {
            return Err(self.clearance_unfit(world, &p));
        }
        for s in &world.shafts {
            self.ramp_plan(world, s)?;
        }
        let top = p.height * (1.0 + p.height_variation) + p.roughness + p.floor_roughness;
        let [low, high] = self.grade(world, &p);
        let room = self.lift_room(world, &p);
        if high > 0.0 {
            let most = high.to_radians().tan() * world.resolved.tile_pitch / std::f64::consts::PI;
            if most > room {
                return Err(TileSetError::Unsuited {
                    what: format!(
                        "{name}: [tileset] grade = [{}, {}] makes floors rise {most:.1} m \
                         within one tile pitch, but passages up to {top:.1} m high leave only \
                         {:.1} m below the next level (levels {} m apart)",
                        number(low),
                        number(high),
                        room.max(0.0),
                        number(world.resolved.level_height)
                    ),
                    fix: format!(
                        "lower the high end of [tileset] grade (now {} degrees), lower \
                         [tileset] height, or raise world.level_height",
                        number(high)
                    ),
                });
            }
        }
        if world.resolved.levels > 1 && top > levels.head() {
            return Err(self.levels_too_close(world, &levels, top));
        }
        Ok(())
    }

    fn texture_scale(&self) -> f32 {
        TEXTURE_REPEAT
    }

    fn makes_hazards(&self) -> bool {
        true
    }

    fn ramp(&self, world: &Layout, shaft: &Shaft) -> Option<Vec<[f64; 3]>> {
        let h = self.ramp_plan(world, shaft).ok()??;
        let p = self.passage(world);
        let field = LocalField::around(
            world,
            shaft.up,
            &p,
            self.style.profile.as_ref(),
            self.levels(world),
            1.0,
        );
        // The floors' slopes lift the spiral's ends as the field does (`LocalField::around`).
        let [(a0, _), (a1, _)] = h.leads();
        let lifts = [
            p.slope.level(shaft.up.level).lift(a0[0], a0[1]),
            p.slope.level(shaft.up.level + 1).lift(a1[0], a1[1]),
        ];
        Some(
            h.floor_line()
                .into_iter()
                .map(|[x, y, z]| [x, y, z + h.lift_at(lifts, z) + field.column(x, y).rubble()])
                .collect(),
        )
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
        let ends = matches!(kind, TileKind::ShaftUp | TileKind::ShaftLanding);
        // A ramp's two ends share its spiral's walls (the world's first ramp stands for all).
        let ramp = world
            .shafts
            .first()
            .filter(|_| ends)
            .and_then(|s| self.ramp_plan(world, s).ok().flatten());
        let shaft = match ramp {
            Some(h) => 0.5 * h.length * perimeter,
            None if ends => {
                std::f64::consts::TAU * p.shaft_radius * p.width * 0.5 * world.resolved.level_height
            }
            None => 0.0,
        };
        let rocks = p.rocks.ceil() * 2.0 * std::f64::consts::TAU * p.rock_size * p.rock_size;
        let area = arms * perimeter * 0.5 * pitch + shaft + rocks;
        let h = pitch / f64::from(self.resolution().0);
        let visual = TRIANGLES_PER_CELL * area / (h * h);
        // The collision copy is the visual surface simplified (`crate::collision`): all of it
        // at a tolerance of 0, a share at the others (assembly's check of the first tiles made
        // catches a tighter tolerance's larger share).
        let share = if self.collision_tolerance().iter().all(|&t| t <= 0.0) {
            1.0
        } else {
            COLLISION_SHARE
        };
        Some(TileTriangles {
            visual,
            collision: share * visual,
        })
    }

    fn detail_advice(&self) -> Option<String> {
        let (visual, _) = self.resolution();
        let [floors, rest] = self.collision_tolerance();
        Some(format!(
            "lower [tileset] resolution (now {visual}; triangles grow with its square) or \
             raise collision_tolerance (now [{}, {}] m)",
            number(floors),
            number(rest)
        ))
    }
}
