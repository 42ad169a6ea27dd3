//! Hills on straight runs, from a manifest's `elevation` tile (the DARPA SubT cave's
//! `cave_elevation`): a straight tile whose floor climbs `rise` metres between its two
//! opposite openings.
//!
//! The layout has no hills: a hill is how this tile set builds a run of straight tiles. A
//! *run* is a maximal row (or column) of two or more consecutive `straight` tiles of one level
//! that all open along it. A run chosen for a hill (each with probability `rate`, drawn from
//! the world's stream `"elevation"` keyed by the run's first cell, so every tile of the run
//! agrees on it whichever thread makes it) gets the elevation tile at its west (or north) end,
//! climbing into the run, the elevation tile turned half a turn at its other end, climbing
//! down out of it, and the straights between lifted by `rise`. The graph, the tile kinds and
//! every other tile stay as they are; the tiles' floor lifts
//! ([`subtgraph_core::tileset::TileSet::floor_lift`]) tell the ground truth where the floor
//! went.
//!
//! On a world of several levels a run gets a hill only where no occupied cell of the level
//! above stands over any of its cells or beside them (the 8 neighbours): the lifted rock would
//! reach that level's tiles (the DARPA levels are 64 m apart and the elevation tile's ceiling
//! stands 60 m over its low floor).
//!
//! Which way a file climbs is measured, not assumed: the floor near each of its two openings
//! is read off its free space (lines cast down through the mesh: a floor faces up with a
//! ceiling over it), and the lower opening is turned west, the base orientation.

use std::path::Path;
use std::sync::Arc;

use subtgraph_core::Layout;
use subtgraph_core::grid::{Cell, Direction, rotate_openings};
use subtgraph_core::mesh::Mesh;
use subtgraph_core::rng::WorldRng;
use subtgraph_core::tile::TileKind;

use super::manifest::{Manifest, ManifestError, ManifestTile};
use super::prepare::{describe, openings, turn};
use super::{Asset, ELEVATION, Entry, Hills};

/// What a hill makes of one tile.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Part {
    /// An end of the hill: the elevation tile turned this many quarter turns from its base
    /// orientation (low opening west, high east), its low opening outside the run.
    Climb(u8),
    /// A straight between the ends, lifted by the rise.
    Raised,
}

/// The part of a hill the tile at `cell` is, when the run it belongs to has one (`rate`: the
/// share of eligible runs that get a hill).
pub(super) fn part(layout: &Layout, cell: Cell, rate: f64) -> Option<Part> {
    if rate <= 0.0 {
        return None;
    }
    let straight = |c: Cell| {
        layout
            .tiles
            .get(c)
            .filter(|t| t.kind == TileKind::Straight)
            .map(|t| t.openings)
    };
    let open = straight(cell)?;
    // Runs go east (rows of cells) or south (columns), from their west or north end.
    let along = if open & Direction::East.bit() != 0 {
        Direction::East
    } else {
        Direction::South
    };
    let same = |c: &Cell| straight(*c) == Some(open);
    let end = |d: Direction| {
        let mut c = cell;
        while let Some(n) = layout.occupancy.neighbour(c, d).filter(same) {
            c = n;
        }
        c
    };
    let (first, last) = (end(along.opposite()), end(along));
    if first == last {
        return None;
    }
    let mut run = vec![first];
    while let Some(&c) = run.last().filter(|&&c| c != last) {
        run.push(layout.occupancy.neighbour(c, along)?);
    }
    if run.iter().any(|&c| crowded_above(layout, c)) {
        return None;
    }
    let key = ((first.level as u64) << 41)
        | ((first.row as u64) << 21)
        | ((first.col as u64) << 1)
        | u64::from(along == Direction::South);
    if WorldRng::new(layout.resolved.seed, "elevation", key).unit() >= rate {
        return None;
    }
    // The base orientation climbs east: the run's west end as it is, its east end half a
    // turn; a column's north end three quarter turns (low side north), its south end one.
    let turns = |at_first: bool| match (along, at_first) {
        (Direction::East, true) => 0,
        (Direction::East, false) => 2,
        (_, true) => 3,
        (_, false) => 1,
    };
    Some(if cell == first {
        Part::Climb(turns(true))
    } else if cell == last {
        Part::Climb(turns(false))
    } else {
        Part::Raised
    })
}

/// Whether an occupied cell of the level above stands over `c` or one of its 8 neighbours.
fn crowded_above(layout: &Layout, c: Cell) -> bool {
    let up = c.level + 1;
    if up >= layout.occupancy.levels() {
        return false;
    }
    let (here, there) = (layout.level_offsets[c.level], layout.level_offsets[up]);
    let (rows, cols) = (
        layout.occupancy.rows() as i64,
        layout.occupancy.cols() as i64,
    );
    (-1..=1).any(|dr| {
        (-1..=1).any(|dc| {
            let r = c.row as i64 + dr + here[0] - there[0];
            let k = c.col as i64 + dc + here[1] - there[1];
            (0..rows).contains(&r)
                && (0..cols).contains(&k)
                && *layout.occupancy.get(Cell::new(up, r as usize, k as usize))
        })
    })
}

/// The floor near the west and the east opening of a mesh in its base orientation (metres):
/// per side the median over lines a few metres in from the opening, each line's lowest floor
/// (a crossing facing up with one facing down above it). `None` where a side has no floor.
pub(super) fn end_floors(mesh: &Mesh, pitch: f64) -> Option<[f64; 2]> {
    let triangles: Vec<[[f64; 3]; 3]> = mesh
        .triangles
        .iter()
        .map(|t| t.map(|i| mesh.positions[i as usize].map(f64::from)))
        .filter(|p| super::collision::area(p) != 0.0)
        .collect();
    let side = |x: f64| {
        let mut found: Vec<f64> = [-0.1, -0.05, 0.0, 0.05, 0.1]
            .iter()
            .filter_map(|&f| lowest_floor(&triangles, [x, f * pitch]))
            .collect();
        found.sort_by(f64::total_cmp);
        found.get(found.len() / 2).copied()
    };
    Some([side(-0.47 * pitch)?, side(0.47 * pitch)?])
}

/// The lowest floor on the vertical line through `q`: a crossing of a triangle facing up (seen
/// from above, counter-clockwise) whose next crossing up faces down.
fn lowest_floor(triangles: &[[[f64; 3]; 3]], q: [f64; 2]) -> Option<f64> {
    let hits = super::collision::line_crossings(triangles, q);
    hits.windows(2).find(|w| w[0].1 && !w[1].1).map(|w| w[0].0)
}

/// The `elevation` tile: its files turned so the low opening faces west (the given `rotation`,
/// or the one the floors at its openings show), checked against `rise` and `rate`.
pub(super) fn elevation_tile(
    path: &Path,
    manifest: &Manifest,
    t: &ManifestTile,
    read: &dyn Fn(&str) -> Result<Arc<Mesh>, ManifestError>,
) -> Result<Hills, ManifestError> {
    let value = |problem: String| ManifestError::Value {
        path: path.to_owned(),
        problem,
    };
    let name = subtgraph_core::error::excerpt(&t.kind);
    if t.kind != ELEVATION {
        return Err(value(format!(
            "tile '{name}': `rise` and `rate` describe hills; give them on the kind = \
             \"elevation\" tile only"
        )));
    }
    if t.cap.is_some() || t.cap_faces.is_some() || t.top.is_some() || t.split.is_some() {
        return Err(value(
            "tile 'elevation': `cap`, `cap_faces`, `top` and `split` are not for the elevation \
             tile; remove them"
                .into(),
        ));
    }
    if t.files.is_empty() {
        return Err(value("tile 'elevation' lists no files".into()));
    }
    let Some(rise) = t.rise else {
        return Err(value(
            "tile 'elevation': give rise, how far its floor climbs from the low opening to the \
             high one (metres, file units times scale)"
                .into(),
        ));
    };
    if !(rise.is_finite() && rise > 0.0) {
        return Err(value(format!(
            "tile 'elevation': rise = {rise}: give the climb as a positive number of metres"
        )));
    }
    let Some(rate) = t.rate else {
        return Err(value(
            "tile 'elevation': give rate, the share of straight runs that get a hill (0 to 1)"
                .into(),
        ));
    };
    if !(0.0..=1.0).contains(&rate) {
        return Err(value(format!(
            "tile 'elevation': rate = {rate}: give the share of straight runs that get a hill, \
             from 0 to 1"
        )));
    }
    let pitch = manifest.pitch * manifest.scale;
    let rise = rise * manifest.scale;
    let mut assets = Vec::new();
    for f in &t.files {
        let mesh = read(f)?;
        let turned = |q: u8| {
            let mut m = (*mesh).clone();
            let back = (4 - q) % 4;
            for p in &mut m.positions {
                *p = turn(*p, back);
            }
            for n in &mut m.normals {
                *n = turn(*n, back);
            }
            m
        };
        // The openings say east-west or north-south; the floors say which end is low.
        let q0 = match t.rotation {
            Some(r) => r,
            None => {
                let found = openings(&mesh, pitch, TileKind::Straight);
                (0..2)
                    .find(|&q| rotate_openings(TileKind::Straight.base_openings(), q) == found)
                    .ok_or_else(|| ManifestError::Openings {
                        path: path.to_owned(),
                        file: f.clone(),
                        kind: t.kind.clone(),
                        found: describe(found),
                        half: pitch / 2.0,
                    })?
            }
        };
        let m = turned(q0);
        let Some([west, east]) = end_floors(&m, pitch) else {
            return Err(value(format!(
                "tile 'elevation': {f} has no floor near one of its openings (turned {q0} \
                 quarter turns); check `pitch`, `up` and `rotation`"
            )));
        };
        let (m, climb) = match t.rotation {
            _ if east > west => (m, east - west),
            None => (turned(q0 + 2), west - east),
            Some(r) => {
                return Err(value(format!(
                    "tile 'elevation': rotation = {r} puts {f}'s high opening west (floor {west:.1} \
                     m, east {east:.1} m); the base orientation is low west, high east: give \
                     rotation = {}",
                    (r + 2) % 4
                )));
            }
        };
        // Measured a few metres in from the openings, where the floor still climbs.
        if (climb - rise).abs() > 0.25 * rise {
            return Err(value(format!(
                "tile 'elevation': rise = {}: {f}'s floor climbs {climb:.1} m between its \
                 openings (measured); set rise to what the tile climbs",
                rise / manifest.scale
            )));
        }
        assets.push(Arc::new(Asset {
            mesh: m,
            shaft: None,
        }));
    }
    Ok(Hills {
        entry: Entry { assets, cap: None },
        rise,
        rate,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::npy::NpyArray;

    /// A layout from spatial codes (1 dead end, 2 straight), `[levels, rows, cols]`.
    fn layout(shape: [usize; 3], codes: &[u8]) -> Layout {
        let array = NpyArray {
            shape: shape.to_vec(),
            values: codes.iter().map(|&c| f64::from(c)).collect(),
            dtype: "|u1".into(),
        };
        let pipeline = subtgraph_core::Pipeline::parse("[world]\nseed = 3\n", "t.toml").unwrap();
        subtgraph_core::import::import_occupancy(&array, "t.npy", &pipeline, "test")
            .unwrap()
            .0
    }

    fn parts(layout: &Layout, cells: &[(usize, usize, usize)], rate: f64) -> Vec<Option<Part>> {
        cells
            .iter()
            .map(|&(l, r, c)| part(layout, Cell::new(l, r, c), rate))
            .collect()
    }

    #[test]
    fn a_run_climbs_at_its_first_end_and_comes_down_at_its_last() {
        // A row: dead end, four straights, dead end.
        #[rustfmt::skip]
        let row = layout([1, 3, 6], &[
            0, 0, 0, 0, 0, 0,
            1, 2, 2, 2, 2, 1,
            0, 0, 0, 0, 0, 0,
        ]);
        let cells: Vec<_> = (0..6).map(|c| (0, 1, c)).collect();
        use Part::{Climb, Raised};
        assert_eq!(
            parts(&row, &cells, 1.0),
            [
                None,
                Some(Climb(0)),
                Some(Raised),
                Some(Raised),
                Some(Climb(2)),
                None
            ]
        );
        assert_eq!(parts(&row, &cells, 0.0), [None; 6]);
        // A column: its north end turned so the low side faces north.
        #[rustfmt::skip]
        let column = layout([1, 4, 3], &[
            0, 1, 0,
            0, 2, 0,
            0, 2, 0,
            0, 1, 0,
        ]);
        let cells: Vec<_> = (0..4).map(|r| (0, r, 1)).collect();
        assert_eq!(
            parts(&column, &cells, 1.0),
            [None, Some(Climb(3)), Some(Climb(1)), None]
        );
    }

    #[test]
    fn a_run_under_the_level_above_or_beside_it_stays_flat() {
        // Level 0: a run along row 1, a corner, down column 5 to the shaft's foot at row 4.
        // Level 1: from the landing over the foot, up column 5 to row `at`, then west.
        let make = |at: usize| {
            #[rustfmt::skip]
            let mut codes = vec![
                0, 0, 0, 0, 0, 0,
                1, 2, 2, 2, 2, 3,
                0, 0, 0, 0, 0, 2,
                0, 0, 0, 0, 0, 2,
                0, 0, 0, 0, 0, 11,
            ];
            let mut up = vec![0u8; 30];
            up[6 * at..6 * at + 6].copy_from_slice(&[1, 2, 2, 2, 2, 3]);
            for r in at + 1..4 {
                up[6 * r + 5] = 2;
            }
            up[6 * 4 + 5] = 111;
            if at == 4 {
                up[6 * 4..6 * 4 + 6].copy_from_slice(&[1, 2, 2, 2, 2, 111]);
            }
            codes.extend(up);
            layout([2, 5, 6], &codes)
        };
        let run: Vec<_> = (1..5).map(|c| (0, 1, c)).collect();
        let top: Vec<_> = (1..5).map(|c| (1, 4, c)).collect();
        use Part::{Climb, Raised};
        let hill = [Some(Climb(0)), Some(Raised), Some(Raised), Some(Climb(2))];
        // Level 1's row 4 is three rows from the run: both runs get hills.
        let apart = make(4);
        assert_eq!(parts(&apart, &run, 1.0), hill);
        assert_eq!(
            parts(&apart, &top, 1.0),
            hill,
            "nothing above the top level"
        );
        // Level 1's row 2 is beside the run (the 8 neighbours of its cells): it stays flat.
        assert_eq!(parts(&make(2), &run, 1.0), [None; 4]);
        // Row 1, over it: flat too.
        assert_eq!(parts(&make(1), &run, 1.0), [None; 4]);
    }

    /// A closed box over `[-40, 40] x [-10, 10]` whose floor climbs from `z0` at the west to
    /// `z1` at the east, with a ceiling 20 m over it.
    fn ramp(z0: f32, z1: f32) -> Mesh {
        let mut m = Mesh::default();
        for (x, z) in [(-40.0, z0), (40.0, z1)] {
            for y in [-10.0, 10.0] {
                m.positions.push([x, y, z]);
                m.positions.push([x, y, z + 20.0]);
            }
        }
        // 0 (-40,-10) 2 (-40,10) 4 (40,-10) 6 (40,10); +1: the ceiling above.
        m.triangles
            .extend([[0, 4, 6], [0, 6, 2], [1, 7, 5], [1, 3, 7]]);
        m
    }

    #[test]
    fn the_floor_is_read_at_each_opening() {
        let [w, e] = end_floors(&ramp(0.0, 32.0), 80.0).unwrap();
        assert!(
            (w - 0.96).abs() < 1e-6 && (e - 31.04).abs() < 1e-6,
            "{w} {e}"
        );
        let [w, e] = end_floors(&ramp(32.0, 0.0), 80.0).unwrap();
        assert!(w > e);
        assert_eq!(end_floors(&Mesh::default(), 80.0), None);
    }
}
