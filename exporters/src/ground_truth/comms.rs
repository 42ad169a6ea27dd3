//! `comms`: which tiles see each other, the ground truth of a subterranean radio link
//! (`ground_truth/comms.csv` + `comms.json`): in the DARPA Subterranean Challenge the robots'
//! mesh radios carried data only along lines of sight and a little round corners, so which
//! places see which is what a comms-aware explorer (dropping radio nodes, planning returns to
//! a link) is scored against.
//!
//! Each passage tile has an antenna `antenna` metres (1.0) above the floor at its node's
//! position (the survey's [`Survey::position`]: on the floor of its own passage). Every pair of
//! tiles whose antennas are at most `range` metres (100) apart gets a row: their cells, the
//! distance, and whether the straight line between the antennas is clear of the collision
//! surface (one ray cast against the surface, the same ray caster the sensor sequences use);
//! a blocked line gives the distance along it to the first rock. Without a mesh (`--no-mesh`)
//! the grid answers: the line, sampled every eighth of a tile, is clear while every sample is
//! in a passage tile of the level at its height (`source` says which). Pairs farther apart than the
//! range are left out: no subterranean radio link reaches there through rock anyway.
//! Rows are in raster order of the first tile, then the second: the same bytes on every run
//! and thread count.

use rayon::prelude::*;
use subtgraph_core::World;
use subtgraph_core::error::ConfigError;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter, write_file};
use subtgraph_core::grid::Cell;
use subtgraph_core::params::Params;
use subtgraph_core::raycast::RayCaster;
use subtgraph_core::survey::Survey;

use super::FRAME;
use crate::mjcf::metres;

/// Writes `ground_truth/comms.csv` and `comms.json`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Comms {
    /// Pairs farther apart than this are not listed, metres.
    pub range: f64,
    /// The antenna's height above the floor, metres.
    pub antenna: f64,
}

impl Default for Comms {
    fn default() -> Self {
        Comms {
            range: 100.0,
            antenna: 1.0,
        }
    }
}

impl Comms {
    /// The keys it takes.
    pub const KEYS: [&str; 2] = ["range", "antenna"];

    /// From an `[[export]] type = "comms"` table.
    pub fn from_params(params: &Params) -> Result<Comms, ConfigError> {
        params.expect_known(&Comms::KEYS)?;
        let d = Comms::default();
        Ok(Comms {
            range: metres(params, "range", d.range, (0.0, 10_000.0), "100")?,
            antenna: metres(params, "antenna", d.antenna, (0.0, 100.0), "1.0")?,
        })
    }
}

/// One listed pair.
struct Link {
    a: usize,
    b: usize,
    distance: f64,
    /// Distance along the line to the first rock, if blocked.
    blocked_at: Option<f64>,
}

#[derive(serde::Serialize)]
struct Summary {
    format: &'static str,
    seed: u64,
    frame: &'static str,
    source: &'static str,
    range_m: f64,
    antenna_m: f64,
    tiles: usize,
    pairs: usize,
    in_sight: usize,
    columns: &'static str,
}

impl Exporter for Comms {
    fn export(
        &self,
        world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let cells: Vec<Cell> = world
            .occupancy
            .cells()
            .filter(|&c| world.tiles.get(c).is_some())
            .collect();
        let antennas: Vec<[f64; 3]> = cells
            .iter()
            .map(|&c| {
                let p = survey.position(c);
                [p[0], p[1], p[2] + self.antenna]
            })
            .collect();
        // The survey's own hierarchy when it holds one (built once per world, shared with the
        // widths and the sensors); else one of our own.
        let own = match survey.ray_caster() {
            Some(_) => None,
            None => world.mesh().map(|m| RayCaster::new(&m.collision)),
        };
        let caster = survey.ray_caster().or(own.as_ref());
        let range = self.range;
        let grid = |p: [f64; 3], dir: [f64; 3], distance: f64| grid_cast(world, p, dir, distance);
        let links: Vec<Link> = (0..antennas.len())
            .into_par_iter()
            .flat_map_iter(|a| {
                let antennas = &antennas;
                let grid = &grid;
                (a + 1..antennas.len()).filter_map(move |b| {
                    let (p, q) = (antennas[a], antennas[b]);
                    let d = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
                    let distance = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                    if distance > range || distance == 0.0 {
                        return None;
                    }
                    let dir = d.map(|x| x / distance);
                    let blocked_at = match caster {
                        Some(c) => c.cast(p, dir, distance).map(|h| h.t),
                        None => grid(p, dir, distance),
                    };
                    Some(Link {
                        a,
                        b,
                        distance,
                        blocked_at,
                    })
                })
            })
            .collect();
        let mut csv = String::from(
            "level_a,row_a,col_a,level_b,row_b,col_b,distance_m,line_of_sight,blocked_at_m\n",
        );
        use std::fmt::Write as _;
        for l in &links {
            let (a, b) = (cells[l.a], cells[l.b]);
            let _ = writeln!(
                csv,
                "{},{},{},{},{},{},{:.3},{},{}",
                a.level,
                a.row,
                a.col,
                b.level,
                b.row,
                b.col,
                l.distance,
                u8::from(l.blocked_at.is_none()),
                l.blocked_at.map_or(String::new(), |t| format!("{t:.3}"))
            );
        }
        write_file(out, "ground_truth/comms.csv", csv.as_bytes())?;
        let summary = Summary {
            format: "subtgraph-comms/1",
            seed: world.resolved.seed,
            frame: FRAME,
            source: if world.mesh().is_some() {
                "collision-mesh"
            } else {
                "grid"
            },
            range_m: self.range,
            antenna_m: self.antenna,
            tiles: cells.len(),
            pairs: links.len(),
            in_sight: links.iter().filter(|l| l.blocked_at.is_none()).count(),
            columns: "each pair of passage tiles whose antennas (antenna_m above the tile's node on its floor) are at most range_m apart: the two cells, the distance between the antennas, line_of_sight 1 when the straight line between them misses the collision surface, else 0 and blocked_at_m, the distance along it to the first rock",
        };
        crate::write_json(out, "ground_truth/comms.json", &summary)
    }
}

/// Without a mesh: the distance along the line to its first sample outside a passage tile.
fn grid_cast(world: &World, p: [f64; 3], dir: [f64; 3], distance: f64) -> Option<f64> {
    let pitch = world.resolved.tile_pitch;
    let height = world.resolved.level_height;
    let (rows, cols) = (world.occupancy.rows() as i64, world.occupancy.cols() as i64);
    let steps = (distance / (pitch / 8.0)).ceil().max(1.0) as usize;
    (0..=steps).find_map(|k| {
        let t = distance * k as f64 / steps as f64;
        let q = [p[0] + t * dir[0], p[1] + t * dir[1], p[2] + t * dir[2]];
        let level = (q[2] / height + 0.25).floor();
        let free = level >= 0.0 && (level as usize) < world.occupancy.levels() && {
            let l = level as usize;
            let off = world.level_offsets[l];
            let col = (q[0] / pitch + 0.5).floor() as i64 - off[1];
            let row = rows - 1 - (q[1] / pitch + 0.5).floor() as i64 - off[0];
            (0..rows).contains(&row)
                && (0..cols).contains(&col)
                && world
                    .tiles
                    .get(Cell {
                        level: l,
                        row: row as usize,
                        col: col as usize,
                    })
                    .is_some()
        };
        (!free).then_some(t)
    })
}
