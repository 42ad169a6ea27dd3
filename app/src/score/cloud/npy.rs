//! An occupancy `.npy` map on the world's free-space grid: every non-zero voxel is a mapped
//! point at its centre. The values are read where they lie in the file (the bytes after the
//! header, in C or Fortran order, of any dtype), so a map takes its file's bytes and its points
//! in memory, nothing more.

use subtgraph_core::npy;

use super::{Grid, Points, bad};
use crate::Error;

/// Reads the map's non-zero voxels as points, in C order (`[z, y, x]`, x fastest).
pub(super) fn read(bytes: &[u8], name: &str, grid: Option<&Grid>) -> Result<Points, Error> {
    let grid = grid.ok_or_else(|| {
        bad(
            name,
            "an occupancy .npy map is read on the world's free-space grid: make the world again with `subtgraph generate PIPELINE --format free-space` (or ground-truth), PIPELINE being its world.toml",
        )
    })?;
    let info = npy::info(bytes).map_err(|source| Error::Npy {
        file: name.to_owned(),
        source,
    })?;
    let [nx, ny, nz] = grid.n;
    let want = [nz, ny, nx];
    if info.shape != want {
        return Err(bad(
            name,
            format!(
                "shape {:?}, but the world's free-space grid is {want:?} ([z, y, x], {} m voxels from {:?}, as in ground_truth/free_space.json)",
                info.shape, grid.voxel, grid.origin
            ),
        ));
    }
    // The header checked that the file holds `count * size` bytes after it; any more are not
    // the array's.
    let data = &bytes[info.data_start..info.data_start + info.count * info.size];
    let size = info.size;
    let float = info.kind == b'f';
    let big = info.big_endian;
    // Whether the value at index `i` (in the file's order) is non-zero; a float's -0.0 is zero.
    let set = |i: usize| {
        let v = &data[i * size..(i + 1) * size];
        if float {
            let sign = if big { 0 } else { size - 1 };
            v.iter()
                .enumerate()
                .any(|(k, &b)| if k == sign { b & 0x7f != 0 } else { b != 0 })
        } else {
            v.iter().any(|&b| b != 0)
        }
    };
    let v = grid.voxel;
    let mut out = Vec::new();
    for iz in 0..nz {
        for iy in 0..ny {
            for ix in 0..nx {
                let i = if info.fortran {
                    iz + nz * (iy + ny * ix)
                } else {
                    (iz * ny + iy) * nx + ix
                };
                if set(i) {
                    out.push([
                        (grid.origin[0] + (ix as f64 + 0.5) * v) as f32,
                        (grid.origin[1] + (iy as f64 + 0.5) * v) as f32,
                        (grid.origin[2] + (iz as f64 + 0.5) * v) as f32,
                    ]);
                }
            }
        }
    }
    Ok(out)
}
