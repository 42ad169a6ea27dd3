//! A floor and a roof height field per tile: the world's passages as simulators that load
//! height fields fast (MuJoCo's `hfield`) can collide with them.
//!
//! Along every vertical line of a regular grid (`step` metres apart, lines on the tile edges so
//! two neighbours share their edge lines), the free stretches of the closed collision surface
//! are found exactly by ray parity, or by the triangles' facing where the surface overlaps
//! itself (as for the free-space ground truth, [`crate::passages`]). For a tile on level `L`,
//! the stretches meeting the level's band (from a quarter of a level height below its floor
//! to three quarters above, moved up by the tile's floor lift on a hill) give the **floor**
//! (the lowest bottom) and the **roof** (the highest top) of that line; a line with no free
//! stretch in the band is rock, where floor and roof meet in the middle of the band. So a
//! tunnel's section, however rounded, is what lies between two height functions: the floor
//! field rises steeply into the rock at the walls and meets the roof field there, which comes
//! down to the same height. A shaft's lines are free from the floor below to the roof above,
//! on both levels.
//!
//! What is lost: rock that hangs inside a line's free stretch (an overhang, a ledge) becomes
//! free, and a wall stands up to one `step` into the passage (the field rises between the last
//! free line and the first rock line). Nothing free is ever filled: the passage is never
//! blocked. One field per tile keeps every field small and the loader fast (MuJoCo builds no
//! hull for a field); the lines a tile shares with its neighbours have the same heights, so a
//! body crosses the seam without a step.

use rayon::prelude::*;
use subtgraph_core::World;
use subtgraph_core::assembly::WorldMesh;
use subtgraph_core::survey::{Columns, Survey};

/// The heights of one tile's floor and roof.
#[derive(Clone, Debug, PartialEq)]
pub struct TileField {
    /// Samples per side, minus one: the tile's pitch over the step.
    pub n: usize,
    /// The tile's centre (x, y), metres.
    pub centre: [f64; 2],
    /// Half the tile's pitch: the field spans `centre ± half` in x and y.
    pub half: f64,
    /// `(n + 1)²` floor heights (metres), rows south to north, each west to east.
    pub floor: Vec<f32>,
    /// The roof heights, in the same order.
    pub roof: Vec<f32>,
}

/// The samples per tile side (minus one) for a wanted step: at least 2.
pub fn samples_per_tile(pitch: f64, step: f64) -> usize {
    ((pitch / step).round() as usize).max(2)
}

/// The floor and roof of every tile of `mesh` (the world's), from the passages its `survey`
/// found, in the order of [`WorldMesh::tiles`]. Computed when an exporter asks (MuJoCo's
/// writer), with its `step`: a world exported in other formats never pays for them.
pub fn tile_fields(
    world: &World,
    survey: &dyn Survey,
    mesh: &WorldMesh,
    step: f64,
) -> Vec<TileField> {
    let pitch = world.resolved.tile_pitch;
    let lh = world.resolved.level_height;
    let n = samples_per_tile(pitch, step);
    let step = pitch / n as f64;
    let rows = world.occupancy.rows() as i64;
    // Tile coordinates in the world's tile lattice: x = gx * pitch, y = gy * pitch.
    let lattice = |t: &subtgraph_core::assembly::PlacedTile| {
        let off = world.level_offsets[t.cell.level];
        (
            t.cell.col as i64 + off[1],
            rows - 1 - t.cell.row as i64 - off[0],
        )
    };
    if mesh.tiles.is_empty() {
        return Vec::new();
    }
    let (mut lo, mut hi) = ((i64::MAX, i64::MAX), (i64::MIN, i64::MIN));
    for t in &mesh.tiles {
        let (x, y) = lattice(t);
        lo = (lo.0.min(x), lo.1.min(y));
        hi = (hi.0.max(x), hi.1.max(y));
    }
    // Line i stands at x = (lo.0 - ½) pitch + i step (Columns puts it at x0 + (i + ½) step).
    let cols = Columns {
        x0: (lo.0 as f64 - 0.5) * pitch - 0.5 * step,
        y0: (lo.1 as f64 - 0.5) * pitch - 0.5 * step,
        step,
        nx: (hi.0 - lo.0 + 1) as usize * n + 1,
        ny: (hi.1 - lo.1 + 1) as usize * n + 1,
    };
    // Every free stretch of every line, row by row: (line, bottom, top).
    let raster = survey.raster(&cols, |_, spans, _| {
        spans
            .iter()
            .map(|s| (s.i, s.z0 as f32, s.z1 as f32))
            .collect::<Vec<_>>()
    });
    let lines = &raster.rows;
    mesh.tiles
        .par_iter()
        .map(|t| {
            let (gx, gy) = lattice(t);
            let z = t.cell.level as f64 * lh;
            // Moved up with the tile's floor where the tile set lifted it (a hill's tiles).
            let [low, high] = t.floor_lift;
            let (band_lo, band_hi) = ((z + low - 0.25 * lh) as f32, (z + high + 0.75 * lh) as f32);
            let rock = (z + 0.5 * (low + high) + 0.25 * lh) as f32;
            let (i0, j0) = ((gx - lo.0) as usize * n, (gy - lo.1) as usize * n);
            let mut floor = Vec::with_capacity((n + 1) * (n + 1));
            let mut roof = Vec::with_capacity((n + 1) * (n + 1));
            for row in &lines[j0..=j0 + n] {
                for i in i0..=i0 + n {
                    let first = row.partition_point(|s| (s.0 as usize) < i);
                    let (mut f, mut r) = (f32::MAX, f32::MIN);
                    for s in row[first..].iter().take_while(|s| s.0 as usize == i) {
                        if s.2 > band_lo && s.1 < band_hi {
                            f = f.min(s.1);
                            r = r.max(s.2);
                        }
                    }
                    if f < r {
                        floor.push(f);
                        roof.push(r);
                    } else {
                        floor.push(rock);
                        roof.push(rock);
                    }
                }
            }
            TileField {
                n,
                centre: [gx as f64 * pitch, gy as f64 * pitch],
                half: 0.5 * pitch,
                floor,
                roof,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn neighbours_share_their_edge_heights_and_every_tile_has_a_passage() {
        let world = crate::tests::coarse_world_with_mesh();
        let mesh = world.mesh().unwrap();
        let survey = crate::WorldSurvey::new(&world).unwrap();
        let fields = tile_fields(&world, &survey, mesh, 1.25);
        let passages = crate::passages::Passages::of(&world);
        let mut centres = 0;
        assert_eq!(fields.len(), mesh.tiles.len());
        let pitch = world.resolved.tile_pitch;
        let mut shared = 0;
        for (a, fa) in mesh.tiles.iter().zip(&fields) {
            let n = fa.n;
            // The centre sample is the free stretch through the tile's centre, found alone.
            let pos = world.cell_position(a.cell);
            let column = passages.column(pos[0], pos[1]);
            assert_eq!(fa.centre, [pos[0], pos[1]]);
            let k = (n / 2) * (n + 1) + n / 2;
            if let Some(s) = column
                .iter()
                .find(|s| s[1] > pos[2] - 5.0 && s[0] < pos[2] + 20.0)
            {
                assert!((f64::from(fa.floor[k]) - s[0]).abs() < 1e-4, "{:?}", a.cell);
                assert!((f64::from(fa.roof[k]) - s[1]).abs() < 1e-4, "{:?}", a.cell);
                centres += 1;
            } else {
                assert_eq!(fa.floor[k], fa.roof[k], "rock at {:?}", a.cell);
            }
            for (b, fb) in mesh.tiles.iter().zip(&fields) {
                // b east of a on the same level: a's east column is b's west column.
                if b.cell.level == a.cell.level
                    && b.cell.row == a.cell.row
                    && b.cell.col == a.cell.col + 1
                {
                    assert!((fb.centre[0] - fa.centre[0] - pitch).abs() < 1e-9);
                    for j in 0..=n {
                        let (ka, kb) = (j * (n + 1) + n, j * (n + 1));
                        assert_eq!(fa.floor[ka], fb.floor[kb]);
                        assert_eq!(fa.roof[ka], fb.roof[kb]);
                    }
                    shared += 1;
                }
            }
        }
        assert!(shared > 3, "{shared} east-west neighbours");
        assert!(centres > mesh.tiles.len() / 2, "{centres} free centres");
    }
}
