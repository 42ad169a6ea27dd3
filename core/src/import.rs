//! Importing occupancy grids saved by the original SubTGraph (or by anyone with numpy), so that
//! published worlds go through the same classification, graph, maps and meshes as generated
//! ones.
//!
//! Accepted encodings, detected from the values:
//! - spatial: 0 empty, 1 dead end, 2 straight, 3 corner, 4 T-junction, 5 intersection,
//!   11 shaft up, 111 shaft landing (shafts are taken from the codes);
//! - topological: 0 empty, 1 edge, 10 node;
//! - structural or plain: 0 empty, 1 occupied.
//!
//! For the last two, shafts follow the original's rule: on each level the first dead end in
//! raster order is the foot of the shaft up, and the next dead end the landing of the shaft
//! from below. Those shafts are not stacked, so each level gets the offset that puts its
//! landing over the foot below (see [`Layout::level_offsets`]).

use std::collections::BTreeMap;

use serde::Serialize;

use crate::config::{IntRange, Pipeline, Provenance, Resolved};
use crate::error::Error;
use crate::grid::{Cell, Grid3, Occupancy};
use crate::layout::{Layout, Shaft};
use crate::npy::NpyArray;
use crate::tile::{TileKind, classify_cell};

/// How an imported grid was encoded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Encoding {
    /// 0/1.
    Binary,
    /// 0 empty, 1 edge, 10 node.
    Topological,
    /// Tile-kind codes 0-5, 11, 111.
    Spatial,
}

/// Turns an array into a layout, with the scale (pitch, level height) of `pipeline`.
pub fn import_occupancy(
    array: &NpyArray,
    source_name: &str,
    pipeline: &Pipeline,
    tool_version: &str,
) -> Result<(Layout, Encoding), Error> {
    let err = |message: String| Error::Import {
        source_name: source_name.to_owned(),
        message,
    };
    let (levels, rows, cols) = match array.shape[..] {
        [r, c] => (1, r, c),
        [l, r, c] => (l, r, c),
        _ => {
            return Err(err(format!(
                "shape {:?}: expected [rows, cols] or [levels, rows, cols]",
                array.shape
            )));
        }
    };
    if levels == 0 || rows < 2 || cols < 2 {
        return Err(err(format!(
            "shape {:?} is empty or too small: a level needs at least 2 x 2 cells",
            array.shape
        )));
    }
    let mut codes = Vec::with_capacity(array.values.len());
    for (i, &v) in array.values.iter().enumerate() {
        if v.fract() != 0.0 || !(0.0..=255.0).contains(&v) {
            return Err(err(format!(
                "value {v} at {} is not one of the SubTGraph codes (0/1, 0/1/10, or 0-5, 11, 111)",
                position(i, rows, cols)
            )));
        }
        codes.push(v as u8);
    }
    let has = |set: &[u8]| codes.iter().any(|c| set.contains(c));
    let encoding = if has(&[2, 3, 4, 5, 11, 111]) {
        Encoding::Spatial
    } else if has(&[10]) {
        Encoding::Topological
    } else {
        Encoding::Binary
    };
    let allowed: &[u8] = match encoding {
        Encoding::Spatial => &[0, 1, 2, 3, 4, 5, 11, 111],
        Encoding::Topological => &[0, 1, 10],
        Encoding::Binary => &[0, 1],
    };
    if let Some(i) = codes.iter().position(|c| !allowed.contains(c)) {
        return Err(err(format!(
            "value {} at {} does not belong to the {encoding:?} encoding the other values imply \
             (allowed: {allowed:?})",
            codes[i],
            position(i, rows, cols)
        )));
    }
    if codes.iter().all(|&c| c == 0) {
        return Err(err("the grid is empty: no occupied cell".into()));
    }
    let occupancy: Occupancy =
        Grid3::from_vec(levels, rows, cols, codes.iter().map(|&c| c != 0).collect())
            .expect("shape checked");
    let shafts = match encoding {
        Encoding::Spatial => {
            let code_at = |c: Cell| codes[(c.level * rows + c.row) * cols + c.col];
            (0..levels.saturating_sub(1))
                .flat_map(|k| {
                    let ups = occupancy.level_cells(k).filter(|&c| code_at(c) == 11);
                    let landings = occupancy
                        .level_cells(k + 1)
                        .filter(|&c| code_at(c) == 111)
                        .collect::<Vec<_>>();
                    ups.zip(landings)
                        .map(|(up, landing)| Shaft {
                            up,
                            landing,
                            block: None,
                        })
                        .collect::<Vec<_>>()
                })
                .collect()
        }
        _ => original_shafts(&occupancy),
    };
    let mut p = pipeline.clone();
    p.world.levels = IntRange::Fixed(levels as u32);
    p.world.min_length = None;
    p.world.rows = Some(rows as u32);
    p.world.cols = Some(cols as u32);
    p.topology.per_level.clear();
    let level_height = p.world.level_height.unwrap_or(0.8 * p.world.tile_pitch);
    p.world.level_height = Some(level_height);
    let (connections, ramp_grade) = p.world.resolve_connections(p.tileset.as_ref());
    let mut shafts = shafts;
    if connections == crate::config::Connections::Ramp {
        spiral_blocks(&occupancy, &mut shafts);
    }
    p.generated = Some(Provenance {
        tool: "subtgraph".into(),
        version: tool_version.to_owned(),
        source: Some(format!("import {source_name} ({encoding:?} encoding)")),
    });
    let resolved = Resolved {
        seed: p.world.seed,
        levels,
        rows,
        cols,
        tile_pitch: p.world.tile_pitch,
        level_height,
        max_width: p
            .world
            .max_width
            .draw(&mut crate::rng::WorldRng::new(0, "import", 0)),
        attempts: 0,
        per_level: vec![Vec::new(); levels],
        exact: false,
        connections,
        ramp_grade,
    };
    let layout = Layout::new(
        p,
        resolved,
        occupancy,
        shafts,
        vec![BTreeMap::new(); levels],
        vec![None; levels],
        vec![0; levels],
    );
    Ok((layout, encoding))
}

/// Gives each ramp the first spiral block (see [`Shaft::block`]) whose cells are empty beside
/// both its ends and in no other ramp's block; a ramp with none turns inside its own cell.
fn spiral_blocks(occ: &Occupancy, shafts: &mut [Shaft]) {
    let mut taken: Vec<Cell> = Vec::new();
    for s in shafts.iter_mut() {
        s.block = Shaft::BLOCKS.into_iter().find(|&b| {
            [s.up, s.landing].iter().all(|&end| {
                Shaft::block_cells(end, b, occ.rows(), occ.cols())
                    .is_some_and(|cells| cells.iter().all(|c| !*occ.get(*c) && !taken.contains(c)))
            })
        });
        if let Some(b) = s.block {
            for end in [s.up, s.landing] {
                taken.extend(
                    Shaft::block_cells(end, b, occ.rows(), occ.cols())
                        .into_iter()
                        .flatten(),
                );
            }
        }
    }
}

/// The original's shafts: first dead end of level `k` up to the next dead end of level `k+1`.
fn original_shafts(occ: &Occupancy) -> Vec<Shaft> {
    let dead_ends = |k: usize| -> Vec<Cell> {
        occ.level_cells(k)
            .filter(|&c| *occ.get(c) && classify_cell(occ, c).kind == TileKind::DeadEnd)
            .filter(|&c| occ.openings(c) != 0)
            .collect()
    };
    let mut shafts = Vec::new();
    for k in 0..occ.levels().saturating_sub(1) {
        let below = dead_ends(k);
        let above = dead_ends(k + 1);
        let Some(&up) = below.first() else { continue };
        // The level above spends its first dead end on its own shaft up, unless it is the top.
        let skip = usize::from(k + 2 < occ.levels());
        if let Some(&landing) = above.get(skip).or(above.first()) {
            shafts.push(Shaft {
                up,
                landing,
                block: None,
            });
        }
    }
    shafts
}

fn position(i: usize, rows: usize, cols: usize) -> String {
    format!(
        "[level {}, row {}, col {}]",
        i / (rows * cols),
        (i / cols) % rows,
        i % cols
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn array(shape: Vec<usize>, values: Vec<f64>) -> NpyArray {
        NpyArray {
            shape,
            values,
            dtype: "<i8".into(),
        }
    }

    #[test]
    fn encodings_are_detected_from_values() {
        let p = Pipeline::default();
        let plain = array(vec![3, 3], vec![0., 1., 0., 0., 1., 0., 0., 1., 0.]);
        assert_eq!(
            import_occupancy(&plain, "a", &p, "0").unwrap().1,
            Encoding::Binary
        );
        let topo = array(vec![3, 3], vec![0., 10., 0., 0., 1., 0., 0., 10., 0.]);
        assert_eq!(
            import_occupancy(&topo, "a", &p, "0").unwrap().1,
            Encoding::Topological
        );
        let spatial = array(vec![3, 3], vec![0., 1., 0., 0., 2., 0., 0., 1., 0.]);
        let (w, e) = import_occupancy(&spatial, "a", &p, "0").unwrap();
        assert_eq!(e, Encoding::Spatial);
        assert_eq!(w.occupancy.occupied_count(), 3);
    }

    #[test]
    fn bad_values_and_shapes_are_refused_with_their_position() {
        let p = Pipeline::default();
        let bad = array(vec![2, 2], vec![0., 1., 7., 0.]);
        let e = import_occupancy(&bad, "w.npy", &p, "0")
            .unwrap_err()
            .to_string();
        assert!(e.contains("value 7 at [level 0, row 1, col 0]"), "{e}");
        let e = import_occupancy(&array(vec![4], vec![1.; 4]), "w.npy", &p, "0")
            .unwrap_err()
            .to_string();
        assert!(e.contains("expected [rows, cols]"), "{e}");
        let e = import_occupancy(&array(vec![2, 2], vec![0., 0.5, 0., 0.]), "w.npy", &p, "0")
            .unwrap_err()
            .to_string();
        assert!(e.contains("0.5"), "{e}");
    }

    #[test]
    fn spatial_shafts_pair_11_with_111_above() {
        // Two levels of a 1 x 4 corridor; shaft at column 0 below, landing at column 3 above.
        let mut v = vec![0.0; 2 * 3 * 4];
        for (c, code) in [11.0, 2.0, 2.0, 1.0].iter().enumerate() {
            v[4 + c] = *code;
        }
        for (c, code) in [1.0, 2.0, 2.0, 111.0].iter().enumerate() {
            v[12 + 4 + c] = *code;
        }
        let (w, _) =
            import_occupancy(&array(vec![2, 3, 4], v), "s", &Pipeline::default(), "0").unwrap();
        assert_eq!(w.shafts.len(), 1);
        assert_eq!(w.shafts[0].up, Cell::new(0, 1, 0));
        assert_eq!(w.shafts[0].landing, Cell::new(1, 1, 3));
        assert_eq!(w.level_offsets[1], [0, -3]);
        assert_eq!(w.reachable_from_start(), 8);
    }
}
