//! `ros-map`: a 2D occupancy map per level in the ROS map_server format (ROS 1 `map_server`,
//! ROS 2 `nav2_map_server`): `ground_truth/maps/level-N.pgm` (binary P5) and `level-N.yaml`.
//!
//! Each map is a slice of the passages `height` metres (default 1.0: a ground robot's lidar)
//! above the floor under each pixel (the level's nominal floor, or the floor the pixel's free
//! stretch starts on where floors slope up from it, `[tileset] grade`; on a rock, its top): 254 where the slice is inside a passage
//! (free), 0 in rock (occupied). A closed collision surface (the procedural tile sets') leaves
//! no pixel unknown; where a vertical line crosses an open one an odd number of times (mesh
//! tiles whose collision meshes do not close) the pixel is 205, unknown, on every level. With
//! `negate: 0` map_server reads a pixel as occupancy `(255 − v) / 255`: 0 → 1.0 > 0.65
//! (occupied), 254 → 0.004 < 0.196 (free), the thresholds `map_saver` writes. Pixels are
//! sampled at their centres; row 0 of the image is the north edge, and `origin` is the world
//! pose of the lower-left (south-west) corner of the lower-left pixel. All levels share one
//! extent, so the maps stack.
//!
//! `resolution` defaults to 0.25 m per pixel (a 5 m passage is 20 pixels across), doubled until
//! a level has at most 25 million pixels: a 44 × 44-cell cave (1.1 km) stays at 0.25 m, a
//! 70 × 70 lava tube (1.75 km, 7000 pixels across at 0.25 m) gets 0.5 m.

use subtgraph_core::World;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter, write_file};
use subtgraph_core::survey::{Columns, Raster, Survey};

use super::{FRAME, Settings, extent};
use crate::text::push_uint;

/// The most pixels a level's map may have at the default resolution.
const DEFAULT_PIXELS: f64 = 25e6;
/// The most pixels a level's map may have at all.
const MAX_PIXELS: f64 = 400e6;

/// Writes `ground_truth/maps/level-N.{pgm,yaml}`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RosMap {
    /// Metres per pixel; `None` picks one from the world's size.
    pub resolution: Option<f64>,
    /// Metres above each level's floor where the map is sliced.
    pub height: f64,
}

impl Default for RosMap {
    fn default() -> Self {
        Self {
            resolution: None,
            height: 1.0,
        }
    }
}

impl RosMap {
    /// The keys it takes.
    pub const KEYS: [&str; 2] = ["resolution", "height"];

    /// From checked settings.
    pub fn from_settings(s: &Settings) -> RosMap {
        RosMap {
            resolution: s.resolution,
            height: s.height.unwrap_or(1.0),
        }
    }

    /// The pixel grid of a world's maps.
    fn pixels(&self, world: &World) -> Result<Columns, ExportError> {
        grid(
            world,
            self.resolution,
            0.25,
            DEFAULT_PIXELS,
            MAX_PIXELS,
            "ros-map",
        )
    }

    /// Each level's slice on the grid `px`: `rows[j][level][i]` is [`FREE`], [`OCCUPIED`] or
    /// [`UNKNOWN`] for line `i` of row `j` (rows south to north). The `tasks` exporter's
    /// MovingAI maps are these slices on their own grid.
    pub(crate) fn slices(
        &self,
        world: &World,
        survey: &dyn Survey,
        px: &Columns,
    ) -> Raster<Vec<Vec<u8>>> {
        let levels = world.occupancy.levels();
        let lh = world.resolved.level_height;
        let height = self.height;
        // One raster gives every level's row: the lines are the same, only the height differs.
        // A hill's tiles (`floor_lift`) have their floor higher up: the level's band reaches
        // that much higher over them.
        let hills = world
            .mesh()
            .is_some_and(|m| m.tiles.iter().any(|t| t.floor_lift[1] > 0.0));
        let raised = |l: usize, i: u32, j: usize| {
            if !hills {
                return 0.0;
            }
            world
                .cell_at(l, px.x(i as usize), px.y(j))
                .map_or(0.0, |c| world.floor_lift(c)[1])
        };
        survey.raster(px, |j, spans, open| {
            let mut rows = vec![vec![OCCUPIED; px.nx]; levels];
            for s in spans {
                for (l, row) in rows.iter_mut().enumerate() {
                    // The floor under the pixel: where the free stretch starts if that is on
                    // this level (sloping floors, `[tileset] grade`, rise above the nominal
                    // one), the nominal floor if it starts below (a shaft from the level
                    // below).
                    let nominal = l as f64 * lh;
                    if s.z0 >= nominal + raised(l, s.i, j) + 0.75 * lh {
                        continue;
                    }
                    let z = s.z0.max(nominal) + height;
                    if s.z0 < z && z < s.z1 {
                        row[s.i as usize] = FREE;
                    }
                }
            }
            for &i in open {
                for row in rows.iter_mut() {
                    row[i as usize] = UNKNOWN;
                }
            }
            rows
        })
    }
}

/// A grid of square cells over the world's extent ([`extent`]) for `exporter`: `resolution`
/// metres per cell if given (refused above `max` cells per level, naming the key), else
/// `default` doubled until a level has at most `default_max` cells.
pub(crate) fn grid(
    world: &World,
    resolution: Option<f64>,
    default: f64,
    default_max: f64,
    max: f64,
    exporter: &str,
) -> Result<Columns, ExportError> {
    let [x0, y0, x1, y1] = extent(world);
    let count = |r: f64| ((x1 - x0) / r).ceil() * ((y1 - y0) / r).ceil();
    let step = match resolution {
        Some(r) => {
            if count(r) > max {
                return Err(ExportError::Unsupported(format!(
                    "{exporter}: resolution = {r} makes maps of {:.1} million cells per level (at most {:.0} million); use a larger resolution",
                    count(r) / 1e6,
                    max / 1e6
                )));
            }
            r
        }
        None => {
            let mut r = default;
            while count(r) > default_max {
                r *= 2.0;
            }
            r
        }
    };
    Ok(Columns {
        x0,
        y0,
        step,
        nx: ((x1 - x0) / step).ceil() as usize,
        ny: ((y1 - y0) / step).ceil() as usize,
    })
}

/// Free and occupied pixel values (map_server's trinary convention with `negate: 0`).
pub(crate) const FREE: u8 = 254;
const OCCUPIED: u8 = 0;
/// Where the vertical line crossed an open surface (a tile set whose collision meshes do not
/// close), so inside and outside cannot be told.
const UNKNOWN: u8 = 205;

impl Exporter for RosMap {
    fn export(
        &self,
        world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let px = self.pixels(world)?;
        let levels = world.occupancy.levels();
        let lh = world.resolved.level_height;
        let raster = self.slices(world, survey, &px);
        for level in 0..levels {
            let mut pgm = format!(
                "P5\n# subtgraph ground truth: level {level}, seed {}, {} m per pixel, sliced {} m above the floor; row 0 is north\n{} {}\n255\n",
                world.resolved.seed, px.step, self.height, px.nx, px.ny
            )
            .into_bytes();
            pgm.reserve(px.nx * px.ny);
            for rows in raster.rows.iter().rev() {
                pgm.extend_from_slice(&rows[level]);
            }
            let base = format!("ground_truth/maps/level-{level}");
            write_file(out, &format!("{base}.pgm"), &pgm)?;
            let mut yaml = format!(
                "# subtgraph ground truth, seed {seed}: level {level} sliced {h} m above its floor (z = {z} m over its nominal floor)\n\
                 # frame: {FRAME}\n\
                 # computed from: {source}{open}\n\
                 image: level-{level}.pgm\n\
                 mode: trinary\n\
                 resolution: {r}\n\
                 origin: [{x0}, {y0}, 0.0]\n\
                 negate: 0\n\
                 occupied_thresh: 0.65\n\
                 free_thresh: 0.196\n",
                seed = world.resolved.seed,
                h = self.height,
                z = level as f64 * lh + self.height,
                source = survey.source().name(),
                open = if raster.open_lines > 0 {
                    format!(" ({} lines crossed an open surface)", raster.open_lines)
                } else {
                    String::new()
                },
                r = px.step,
                x0 = px.x0,
                y0 = px.y0,
            )
            .into_bytes();
            yaml.extend_from_slice(b"# pixels: ");
            push_uint(&mut yaml, px.nx as u64);
            yaml.extend_from_slice(b" x ");
            push_uint(&mut yaml, px.ny as u64);
            yaml.push(b'\n');
            write_file(out, &format!("{base}.yaml"), &yaml)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::export::MemoryWriter;

    #[test]
    fn grid_maps_are_free_exactly_over_occupied_cells() {
        let world = crate::test_world();
        let map = RosMap {
            resolution: Some(2.0),
            height: 1.0,
        };
        let mut out = MemoryWriter::default();
        map.export(&world, &crate::survey_of(&world), &mut out)
            .unwrap();
        let pgm = out.get("ground_truth/maps/level-1.pgm").unwrap();
        let px = map.pixels(&world).unwrap();
        let header_end = pgm.len() - px.nx * px.ny;
        assert!(pgm[..header_end].ends_with(b"\n255\n"));
        let img = &pgm[header_end..];
        for (k, &v) in img.iter().enumerate() {
            let (r, i) = (k / px.nx, k % px.nx);
            let (x, y) = (px.x(i), px.y(px.ny - 1 - r));
            let cell = world.cell_at(1, x, y).unwrap();
            let occupied = *world.occupancy.get(cell);
            assert_eq!(v == FREE, occupied, "pixel ({r}, {i})");
        }
        let yaml =
            String::from_utf8(out.get("ground_truth/maps/level-1.yaml").unwrap().to_vec()).unwrap();
        assert!(
            yaml.contains("image: level-1.pgm\n") && yaml.contains("resolution: 2\n"),
            "{yaml}"
        );
    }

    #[test]
    fn the_default_resolution_keeps_maps_small() {
        let world = crate::test_world();
        let px = RosMap::default().pixels(&world).unwrap();
        assert_eq!(px.step, 0.25);
        let big = RosMap {
            resolution: Some(0.001),
            height: 1.0,
        };
        assert!(big.pixels(&world).is_err());
    }
}
