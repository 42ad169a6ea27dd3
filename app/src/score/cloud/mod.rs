//! A robot's map as points in the world frame: PLY (ASCII or binary little endian), PCD
//! (ASCII, binary or binary_compressed) with `x`, `y`, `z` fields of any numeric type, or a 3-D
//! occupancy `.npy` on the grid of the world's `ground_truth/free_space.npy` (any integer,
//! bool or float dtype, `[z, y, x]`, C or Fortran order; each non-zero voxel is a mapped point
//! at its centre).
//!
//! Every reader takes the file's bytes and trusts nothing its header says: counts and sizes
//! are checked (with checked arithmetic) against the bytes that follow before anything is
//! allocated for them, and what is reserved grows with the data read, never with a promise,
//! so a crafted header ends in an error naming the file, not an abort
//! (`app/tests/fuzz_readers.rs` mutates headers and counts of valid files to hold them to
//! it).
//!
//! A point with a NaN or infinite coordinate is refused naming the point: mappers write NaN
//! for "no return", and such points must be dropped before scoring, not counted as mapped.

mod lzf;
mod npy;
mod pcd;
mod ply;
mod records;

use std::path::Path;

use crate::Error;

/// Points as `f32` triples (a 10 M-point map is 120 MB).
pub type Points = Vec<[f32; 3]>;

/// The grid of `ground_truth/free_space.npy`, for `.npy` maps.
#[derive(Clone, Copy, Debug)]
pub struct Grid {
    /// South-west-bottom corner.
    pub origin: [f64; 3],
    /// Voxel edge, metres.
    pub voxel: f64,
    /// Voxels along x, y, z.
    pub n: [usize; 3],
}

/// A map's file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Format {
    /// Stanford PLY.
    Ply,
    /// PCL's PCD.
    Pcd,
    /// A numpy occupancy array on the free-space grid.
    Npy,
}

impl Format {
    /// The format a file's extension names.
    pub fn of(path: &Path) -> Result<Format, Error> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        match ext.as_str() {
            "ply" => Ok(Format::Ply),
            "pcd" => Ok(Format::Pcd),
            "npy" => Ok(Format::Npy),
            _ => Err(Error::Input(format!(
                "{}: unknown map format; use a .ply or .pcd point cloud or a .npy occupancy grid",
                path.display()
            ))),
        }
    }
}

/// Reads a map by its extension (`.ply`, `.pcd`, `.npy`).
pub fn read(path: &Path, grid: Option<&Grid>) -> Result<Points, Error> {
    let format = Format::of(path)?;
    let bytes = crate::input::read(path)?;
    parse(&bytes, format, &path.display().to_string(), grid)
}

/// Reads a map from its bytes; `name` names it in messages.
pub fn parse(
    bytes: &[u8],
    format: Format,
    name: &str,
    grid: Option<&Grid>,
) -> Result<Points, Error> {
    if bytes.is_empty() {
        return Err(Error::Input(format!(
            "{name}: the file is empty; a map is a point cloud (PLY, PCD) or an occupancy .npy"
        )));
    }
    let points = match format {
        Format::Ply => ply::read(bytes, name)?,
        Format::Pcd => pcd::read(bytes, name)?,
        Format::Npy => npy::read(bytes, name, grid)?,
    };
    if points.is_empty() {
        return Err(Error::Input(format!("{name}: the map has no points")));
    }
    if let Some(i) = points.iter().position(|p| p.iter().any(|v| !v.is_finite())) {
        return Err(Error::Input(format!(
            "{name}: point {i} is ({}, {}, {}): every coordinate must be a finite number (drop the points without a return before scoring)",
            points[i][0], points[i][1], points[i][2]
        )));
    }
    Ok(points)
}

/// The header's end: the offset just past its last line (`end_header` or `DATA ...`).
fn header_end(bytes: &[u8], last: &[u8]) -> Option<usize> {
    let mut start = 0;
    while start < bytes.len() {
        let end = bytes[start..].iter().position(|&b| b == b'\n')? + start;
        let line = bytes[start..end].trim_ascii();
        if line.starts_with(last) {
            return Some(end + 1);
        }
        start = end + 1;
    }
    None
}

/// An error about map `name`.
fn bad(name: &str, what: impl std::fmt::Display) -> Error {
    Error::Input(format!("{name}: {what}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(name: &str, bytes: &[u8]) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join(format!("subtgraph-cloud-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, bytes).unwrap();
        p
    }

    #[test]
    fn ply_and_pcd_read_back_in_ascii_and_binary() {
        let pts = [[1.5f32, -2.0, 3.25], [0.0, 4.0, -1.0]];
        let mut bin = b"ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty double x\nproperty float y\nproperty uchar intensity\nproperty float z\nend_header\n".to_vec();
        for p in pts {
            bin.extend_from_slice(&f64::from(p[0]).to_le_bytes());
            bin.extend_from_slice(&p[1].to_le_bytes());
            bin.push(7);
            bin.extend_from_slice(&p[2].to_le_bytes());
        }
        assert_eq!(read(&write("a.ply", &bin), None).unwrap(), pts);
        let ascii = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n1.5 -2 3.25\n0 4 -1\n";
        assert_eq!(read(&write("b.ply", ascii.as_bytes()), None).unwrap(), pts);
        let pcd = "VERSION .7\nFIELDS x y z rgb\nSIZE 4 4 4 4\nTYPE F F F U\nCOUNT 1 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1.5 -2 3.25 0\n0 4 -1 0\n";
        assert_eq!(read(&write("c.pcd", pcd.as_bytes()), None).unwrap(), pts);
        let mut bin = b"VERSION .7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA binary\n".to_vec();
        for p in pts {
            for v in p {
                bin.extend_from_slice(&v.to_le_bytes());
            }
        }
        assert_eq!(read(&write("d.pcd", &bin), None).unwrap(), pts);
        let nan = "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nend_header\n1 2 3\nnan 0 0\n";
        let err = read(&write("e.ply", nan.as_bytes()), None)
            .unwrap_err()
            .to_string();
        assert!(err.contains("point 1") && err.contains("finite"), "{err}");
        let short = &bin[..bin.len() - 4];
        let err = read(&write("f.pcd", short), None).unwrap_err().to_string();
        assert!(err.contains("cut short"), "{err}");
        let err = read(&write("g.ply", b""), None).unwrap_err().to_string();
        assert!(err.contains("empty"), "{err}");
    }
}
