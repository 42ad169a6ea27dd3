//! `free-space`: a 3D occupancy grid of the passages, `ground_truth/free_space.npy` with its
//! description in `ground_truth/free_space.json`, for exploration coverage and volumetric
//! mapping scores.
//!
//! Voxel `[k, j, i]` (axes z, y, x; j grows north) is free when its centre
//! `origin + ((i + ½) v, (j + ½) v, (k + ½) v)` is inside a passage, decided exactly by ray
//! parity on the closed collision surface (the survey's passages, `survey/src/passages.rs`). The array is bit-packed
//! along x, most significant bit first, as `numpy.packbits` makes it:
//! `numpy.unpackbits(numpy.load(path), axis=2, count=nx).astype(bool)` gives the
//! `[nz, ny, nx]` grid. Bits keep the file 8 × smaller than bytes: free space is a small
//! share of a world's box, and a 5-level lava tube is 1.5 km × 1.5 km × 100 m.
//!
//! `voxel` defaults to 0.5 m, doubled until the file is at most 100 MB (a 1.1 km cave stays at
//! 0.5 m, about 27 MB; a 5-level 1.5 km lava tube gets 1 m, about 30 MB). The box spans the
//! world's grid in the plane and the collision surface's heights (the levels without one).
//! The file is streamed a few z slices at a time, made in parallel.

use rayon::prelude::*;
use subtgraph_core::World;
use subtgraph_core::export::{ExportError, Exporter, WorldWriter, stream_file};
use subtgraph_core::survey::{Columns, Source, Survey, grid_clear_height};

use super::{FRAME, Settings, extent};

/// The largest file the default voxel may make, bytes.
const DEFAULT_BYTES: f64 = 100e6;
/// The largest file any voxel may make, bytes.
const MAX_BYTES: f64 = 4e9;

/// Writes `ground_truth/free_space.npy` and `ground_truth/free_space.json`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FreeSpace {
    /// Voxel edge in metres; `None` picks one from the world's size.
    pub voxel: Option<f64>,
}

/// The voxel grid: origin (south-west-bottom corner), edge and counts.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Voxels {
    origin: [f64; 3],
    v: f64,
    n: [usize; 3],
}

impl Voxels {
    fn packed_bytes(&self) -> usize {
        self.n[2] * self.n[1] * self.n[0].div_ceil(8)
    }

    /// The first voxel layer whose centre is above `z` (or at it, with `or_at`).
    fn layer_above(&self, z: f64, or_at: bool) -> usize {
        let centre = |k: usize| self.origin[2] + (k as f64 + 0.5) * self.v;
        let above = |k: usize| if or_at { centre(k) >= z } else { centre(k) > z };
        let guess = ((z - self.origin[2]) / self.v - 0.5).floor().max(0.0) as usize;
        let mut k = guess.min(self.n[2]);
        while k > 0 && above(k - 1) {
            k -= 1;
        }
        while k < self.n[2] && !above(k) {
            k += 1;
        }
        k
    }
}

type Document = subtgraph_schema::FreeSpace<&'static str>;

impl FreeSpace {
    /// The keys it takes.
    pub const KEYS: [&str; 1] = ["voxel"];

    /// From checked settings.
    pub fn from_settings(s: &Settings) -> FreeSpace {
        FreeSpace { voxel: s.voxel }
    }

    fn voxels(&self, world: &World) -> Result<Voxels, ExportError> {
        let [x0, y0, x1, y1] = extent(world);
        let (z0, z1) = match world.mesh() {
            Some(m) if !m.collision.positions.is_empty() => m
                .collision
                .positions
                .iter()
                .fold((f64::MAX, f64::MIN), |(lo, hi), p| {
                    (lo.min(f64::from(p[2])), hi.max(f64::from(p[2])))
                }),
            _ => {
                let lh = world.resolved.level_height;
                let top = (world.occupancy.levels() as f64 - 1.0) * lh + grid_clear_height(world);
                (0.0, top)
            }
        };
        let grid = |v: f64| {
            let origin = [
                (x0 / v).floor() * v,
                (y0 / v).floor() * v,
                (z0 / v).floor() * v,
            ];
            let n = [
                ((x1 - origin[0]) / v).ceil() as usize,
                ((y1 - origin[1]) / v).ceil() as usize,
                ((z1 - origin[2]) / v).ceil().max(1.0) as usize,
            ];
            Voxels { origin, v, n }
        };
        match self.voxel {
            Some(v) => {
                let g = grid(v);
                if g.packed_bytes() as f64 > MAX_BYTES {
                    return Err(ExportError::Unsupported(format!(
                        "free-space: voxel = {v} makes a {:.1} GB grid; use a larger voxel (the default picks one that stays under 100 MB)",
                        g.packed_bytes() as f64 / 1e9
                    )));
                }
                Ok(g)
            }
            None => {
                let mut v = 0.5;
                while grid(v).packed_bytes() as f64 > DEFAULT_BYTES {
                    v *= 2.0;
                }
                Ok(grid(v))
            }
        }
    }
}

/// The `.npy` (version 1.0) header of a `uint8` array, padded to 64 bytes.
fn npy_header(shape: [usize; 3]) -> Vec<u8> {
    let mut header = format!(
        "{{'descr': '|u1', 'fortran_order': False, 'shape': ({}, {}, {}), }}",
        shape[0], shape[1], shape[2]
    );
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat((64 - unpadded % 64) % 64));
    header.push('\n');
    let mut out = b"\x93NUMPY\x01\x00".to_vec();
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    out
}

impl Exporter for FreeSpace {
    fn export(
        &self,
        world: &World,
        survey: &dyn Survey,
        out: &mut dyn WorldWriter,
    ) -> Result<(), ExportError> {
        let g = self.voxels(world)?;
        let cols = Columns {
            x0: g.origin[0],
            y0: g.origin[1],
            step: g.v,
            nx: g.n[0],
            ny: g.n[1],
        };
        // Per row, the free voxel layers `k0..k1` of each line `i`.
        let raster = survey.raster(&cols, |_, spans, _| {
            spans
                .iter()
                .map(|s| (s.i, g.layer_above(s.z0, false), g.layer_above(s.z1, true)))
                .filter(|(_, k0, k1)| k0 < k1)
                .map(|(i, k0, k1)| (i, k0 as u32, k1 as u32))
                .collect::<Vec<_>>()
        });
        let rows = &raster.rows;
        let free_voxels: u64 = rows
            .iter()
            .flatten()
            .map(|&(_, k0, k1)| u64::from(k1 - k0))
            .sum();
        let row_bytes = g.n[0].div_ceil(8);
        let layer = |k: usize| -> Vec<u8> {
            let k = k as u32;
            let mut bytes = vec![0u8; row_bytes * g.n[1]];
            for (j, row) in rows.iter().enumerate() {
                for &(i, k0, k1) in row {
                    if k0 <= k && k < k1 {
                        bytes[j * row_bytes + i as usize / 8] |= 0x80 >> (i % 8);
                    }
                }
            }
            bytes
        };
        let packed_shape = [g.n[2], g.n[1], row_bytes];
        stream_file(out, "ground_truth/free_space.npy", |w| {
            w.write_all(&npy_header(packed_shape))?;
            let batch = 2 * rayon::current_num_threads().max(1);
            let mut k = 0;
            while k < g.n[2] {
                let end = (k + batch).min(g.n[2]);
                let layers: Vec<Vec<u8>> = (k..end).into_par_iter().map(layer).collect();
                for l in layers {
                    w.write_all(&l)?;
                }
                k = end;
            }
            Ok(())
        })?;
        let doc = Document {
            format: "subtgraph-free-space/1",
            seed: world.resolved.seed,
            frame: FRAME,
            units: "metres",
            file: "free_space.npy",
            source: survey.source().name(),
            source_note: match survey.source() {
                Source::CollisionMesh => "inside the closed collision surface (mesh/collision.obj), exact ray parity at voxel centres".into(),
                Source::Grid => format!(
                    "no mesh: each occupied cell's whole square, from its floor up {} m (half the level height); a shaft's foot reaches into the landing above",
                    grid_clear_height(world)
                ),
            },
            dtype: "uint8",
            axes: ["z", "y", "x"],
            shape: [g.n[2], g.n[1], g.n[0]],
            packed_shape,
            encoding: "bits packed along x, most significant bit first (numpy.packbits); 1 = free",
            read_with: format!(
                "numpy.unpackbits(numpy.load('free_space.npy'), axis=2, count={}).astype(bool)",
                g.n[0]
            ),
            voxel_m: g.v,
            origin: g.origin,
            voxel_centre: "origin + ((i + 0.5) * voxel_m, (j + 0.5) * voxel_m, (k + 0.5) * voxel_m) for index [k, j, i]; j grows north",
            free_voxels,
            open_lines: raster.open_lines,
        };
        crate::write_json(out, "ground_truth/free_space.json", &doc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use subtgraph_core::export::MemoryWriter;
    use subtgraph_core::npy;

    #[test]
    fn the_grid_world_is_free_over_its_cells_up_to_half_a_level() {
        let world = crate::test_world();
        let fs = FreeSpace { voxel: Some(5.0) };
        let mut out = MemoryWriter::default();
        fs.export(&world, &crate::survey_of(&world), &mut out)
            .unwrap();
        let a = npy::decode(out.get("ground_truth/free_space.npy").unwrap()).unwrap();
        let g = fs.voxels(&world).unwrap();
        assert_eq!(a.shape, vec![g.n[2], g.n[1], g.n[0].div_ceil(8)]);
        let bit = |k: usize, j: usize, i: usize| {
            let byte = a.values[(k * g.n[1] + j) * g.n[0].div_ceil(8) + i / 8] as u8;
            byte & (0x80 >> (i % 8)) != 0
        };
        let lh = world.resolved.level_height;
        let tile_at = |level: usize, x: f64, y: f64| {
            world.cell_at(level, x, y).and_then(|c| *world.tiles.get(c))
        };
        let shaft = |t: Option<subtgraph_core::tile::Tile>| {
            t.is_some_and(|t| t.kind == subtgraph_core::tile::TileKind::ShaftUp)
        };
        let mut free = 0;
        for k in 0..g.n[2] {
            let z = g.origin[2] + (k as f64 + 0.5) * g.v;
            let level = (z / lh).floor() as usize;
            let low = z - level as f64 * lh < 0.5 * lh;
            for j in 0..g.n[1] {
                for i in 0..g.n[0] {
                    let x = g.origin[0] + (i as f64 + 0.5) * g.v;
                    let y = g.origin[1] + (j as f64 + 0.5) * g.v;
                    let (below, here) = (tile_at(0, x, y), tile_at(1, x, y));
                    let expect = match level {
                        0 => (below.is_some() && low) || shaft(below),
                        1 => low && (here.is_some() || shaft(below)),
                        _ => false,
                    };
                    assert_eq!(bit(k, j, i), expect, "voxel [{k}, {j}, {i}]");
                    free += u64::from(expect);
                }
            }
        }
        let doc: serde_json::Value =
            serde_json::from_slice(out.get("ground_truth/free_space.json").unwrap()).unwrap();
        assert_eq!(doc["free_voxels"], free);
        assert_eq!(doc["source"], "grid");
    }

    #[test]
    fn the_default_voxel_keeps_the_file_under_100_mb() {
        let world = crate::test_world();
        let g = FreeSpace::default().voxels(&world).unwrap();
        assert_eq!(g.v, 0.5);
        assert!(g.packed_bytes() as f64 <= DEFAULT_BYTES);
        assert!(FreeSpace { voxel: Some(0.01) }.voxels(&world).is_err());
    }
}
