//! `ground_truth/free_space.json`: what `free_space.npy` holds (its shape, voxel, origin and
//! bit packing), written by the exporters' `FreeSpace` and read by `score` for a map's
//! coverage.
//!
//! `S` is the type of the fixed texts: `&'static str` where the writer fills them in,
//! `String` (the default) where a file is read.

use serde::{Deserialize, Serialize};

use crate::{Document, SchemaError, finite};

/// `ground_truth/free_space.json`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FreeSpace<S = String> {
    /// [`FreeSpace::FORMAT`](Document::FORMAT).
    pub format: S,
    /// The world's seed.
    pub seed: u64,
    /// The frame, in words.
    pub frame: S,
    /// Units, in words.
    pub units: S,
    /// The array's file name, beside this one.
    pub file: S,
    /// Where the free space came from (`mesh` or `grid`).
    pub source: S,
    /// How, in words.
    pub source_note: String,
    /// The array's dtype.
    pub dtype: S,
    /// The axes of `shape`: `["z", "y", "x"]`.
    pub axes: [S; 3],
    /// Voxels along z, y, x.
    pub shape: [usize; 3],
    /// The array's shape: `[z, y, ceil(x / 8)]` bytes.
    pub packed_shape: [usize; 3],
    /// The bit packing, in words.
    pub encoding: S,
    /// How to unpack it with numpy.
    pub read_with: String,
    /// A voxel's edge, metres.
    pub voxel_m: f64,
    /// The grid's south-west-bottom corner, metres.
    pub origin: [f64; 3],
    /// Where voxel `[k, j, i]`'s centre is, in words.
    pub voxel_centre: S,
    /// Free voxels.
    pub free_voxels: u64,
    /// Vertical lines through the grid with free space open to the outside (0 for a closed
    /// surface).
    pub open_lines: usize,
}

impl Document for FreeSpace {
    const PATH: &'static str = "ground_truth/free_space.json";
    const FORMAT: &'static str = "subtgraph-free-space/1";

    fn format(&self) -> &str {
        &self.format
    }

    fn check(&self) -> Result<(), SchemaError> {
        let [nz, ny, nx] = self.shape;
        if nz == 0 || ny == 0 || nx == 0 {
            return Err(SchemaError::invalid::<Self>(format!(
                "shape {:?} has an axis of 0 voxels",
                self.shape
            )));
        }
        if self.packed_shape != [nz, ny, nx.div_ceil(8)] {
            return Err(SchemaError::invalid::<Self>(format!(
                "packed_shape {:?} is not shape {:?} with x packed 8 voxels to a byte",
                self.packed_shape, self.shape
            )));
        }
        if nz.checked_mul(ny).and_then(|n| n.checked_mul(nx)).is_none() {
            return Err(SchemaError::invalid::<Self>(format!(
                "shape {:?} has more voxels than any machine holds",
                self.shape
            )));
        }
        if !(self.voxel_m.is_finite() && self.voxel_m > 0.0) {
            return Err(SchemaError::invalid::<Self>(format!(
                "voxel_m is {}: it must be a positive number of metres",
                self.voxel_m
            )));
        }
        finite::<Self>(|| "origin".into(), &self.origin)
    }
}
