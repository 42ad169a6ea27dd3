//! A robot's map as points in the world frame: PLY (ASCII or binary little endian), PCD
//! (ASCII or binary) with `x`, `y`, `z` fields of any float type, or a 3-D occupancy `.npy`
//! on the grid of the world's `ground_truth/free_space.npy` (`uint8` or `bool` `[z, y, x]`;
//! each non-zero voxel is a mapped point at its centre).
//!
//! A point with a NaN or infinite coordinate is refused naming the point: mappers write NaN
//! for "no return", and such points must be dropped before scoring, not counted as mapped.

use std::path::Path;

use crate::Error;

type Result<T> = std::result::Result<T, Error>;

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

/// Reads a map by its extension (`.ply`, `.pcd`, `.npy`).
pub fn read(path: &Path, grid: Option<&Grid>) -> Result<Points> {
    let bytes = std::fs::read(path).map_err(Error::io(format!("reading {}", path.display())))?;
    if bytes.is_empty() {
        return Err(Error::Input(format!(
            "{}: the file is empty; a map is a point cloud (PLY, PCD) or an occupancy .npy",
            path.display()
        )));
    }
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    let points = match ext.as_str() {
        "ply" => ply(path, &bytes)?,
        "pcd" => pcd(path, &bytes)?,
        "npy" => npy(path, &bytes, grid)?,
        _ => {
            return Err(Error::Input(format!(
                "{}: unknown map format; use a .ply or .pcd point cloud or a .npy occupancy grid",
                path.display()
            )));
        }
    };
    if points.is_empty() {
        return Err(Error::Input(format!(
            "{}: the map has no points",
            path.display()
        )));
    }
    if let Some(i) = points.iter().position(|p| p.iter().any(|v| !v.is_finite())) {
        return Err(Error::Input(format!(
            "{}: point {i} is ({}, {}, {}): every coordinate must be a finite number (drop the points without a return before scoring)",
            path.display(),
            points[i][0],
            points[i][1],
            points[i][2]
        )));
    }
    Ok(points)
}

/// A property's scalar type: its size and how to read it as `f32`.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Scalar {
    F32,
    F64,
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
}

impl Scalar {
    fn ply(name: &str) -> Option<Scalar> {
        Some(match name {
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            _ => return None,
        })
    }
    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::F32 | Scalar::I32 | Scalar::U32 => 4,
            Scalar::F64 => 8,
        }
    }
    fn read(self, b: &[u8]) -> f32 {
        match self {
            Scalar::F32 => f32::from_le_bytes(b[..4].try_into().expect("4 bytes")),
            Scalar::F64 => f64::from_le_bytes(b[..8].try_into().expect("8 bytes")) as f32,
            Scalar::I8 => f32::from(b[0] as i8),
            Scalar::U8 => f32::from(b[0]),
            Scalar::I16 => f32::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f32::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => i32::from_le_bytes(b[..4].try_into().expect("4 bytes")) as f32,
            Scalar::U32 => u32::from_le_bytes(b[..4].try_into().expect("4 bytes")) as f32,
        }
    }
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

/// Reads the records of fixed layout `fields` (with `xyz` the indices of x, y, z) from `data`.
fn binary_records(
    data: &[u8],
    count: usize,
    fields: &[Scalar],
    xyz: [usize; 3],
    path: &Path,
) -> Result<Points> {
    let stride: usize = fields.iter().map(|f| f.size()).sum();
    let need = count
        .checked_mul(stride)
        .ok_or_else(|| Error::Input(format!("{}: the point count overflows", path.display())))?;
    if data.len() < need {
        return Err(Error::Input(format!(
            "{}: the header promises {count} points of {stride} bytes ({need} bytes), the file holds {} after its header; it is cut short",
            path.display(),
            data.len()
        )));
    }
    let offset = |k: usize| fields[..k].iter().map(|f| f.size()).sum::<usize>();
    let (ox, oy, oz) = (offset(xyz[0]), offset(xyz[1]), offset(xyz[2]));
    let (tx, ty, tz) = (fields[xyz[0]], fields[xyz[1]], fields[xyz[2]]);
    Ok(data[..need]
        .chunks_exact(stride)
        .map(|r| [tx.read(&r[ox..]), ty.read(&r[oy..]), tz.read(&r[oz..])])
        .collect())
}

/// Reads whitespace-separated ASCII records, taking columns `xyz`.
fn ascii_records(
    text: &str,
    count: usize,
    xyz: [usize; 3],
    path: &Path,
    first_line: usize,
) -> Result<Points> {
    let mut out = Vec::with_capacity(count);
    for (k, line) in text
        .lines()
        .filter(|l| !l.trim().is_empty())
        .take(count)
        .enumerate()
    {
        let cells: Vec<&str> = line.split_ascii_whitespace().collect();
        let mut p = [0f32; 3];
        for (axis, &c) in xyz.iter().enumerate() {
            let cell = cells.get(c).ok_or_else(|| {
                Error::Input(format!(
                    "{}: point {k} (line {}): too few values",
                    path.display(),
                    first_line + k
                ))
            })?;
            p[axis] = match cell.to_ascii_lowercase().as_str() {
                "nan" | "-nan" => f32::NAN,
                _ => cell.parse().map_err(|_| {
                    Error::Input(format!(
                        "{}: point {k} (line {}): '{cell}' is not a number",
                        path.display(),
                        first_line + k
                    ))
                })?,
            };
        }
        out.push(p);
    }
    if out.len() < count {
        return Err(Error::Input(format!(
            "{}: the header promises {count} points, the file has {}",
            path.display(),
            out.len()
        )));
    }
    Ok(out)
}

fn xyz_of(names: &[String], path: &Path) -> Result<[usize; 3]> {
    let find = |k: &str| {
        names.iter().position(|n| n == k).ok_or_else(|| {
            Error::Input(format!(
                "{}: the points have no `{k}` field (they have {})",
                path.display(),
                names.join(", ")
            ))
        })
    };
    Ok([find("x")?, find("y")?, find("z")?])
}

fn ply(path: &Path, bytes: &[u8]) -> Result<Points> {
    if !bytes.starts_with(b"ply") {
        return Err(Error::Input(format!(
            "{}: not a PLY file (it does not start with `ply`)",
            path.display()
        )));
    }
    let end = header_end(bytes, b"end_header").ok_or_else(|| {
        Error::Input(format!(
            "{}: the PLY header has no end_header",
            path.display()
        ))
    })?;
    let header = String::from_utf8_lossy(&bytes[..end]);
    let mut format = "";
    let mut count = None;
    let mut in_vertex = false;
    let mut names = Vec::new();
    let mut types = Vec::new();
    for line in header.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.as_slice() {
            ["format", f, ..] => format = f,
            ["element", "vertex", n] => {
                in_vertex = true;
                count = Some(n.parse::<usize>().map_err(|_| {
                    Error::Input(format!(
                        "{}: element vertex count '{n}' is not a number",
                        path.display()
                    ))
                })?);
            }
            ["element", ..] => in_vertex = false,
            ["property", "list", ..] if in_vertex => {
                return Err(Error::Input(format!(
                    "{}: list properties on vertices are not supported",
                    path.display()
                )));
            }
            ["property", t, name] if in_vertex => {
                let s = Scalar::ply(t).ok_or_else(|| {
                    Error::Input(format!(
                        "{}: unknown PLY property type '{t}'",
                        path.display()
                    ))
                })?;
                names.push((*name).to_owned());
                types.push(s);
            }
            _ => {}
        }
    }
    let count = count.ok_or_else(|| {
        Error::Input(format!(
            "{}: no `element vertex` in the header",
            path.display()
        ))
    })?;
    let xyz = xyz_of(&names, path)?;
    match format {
        "binary_little_endian" => binary_records(&bytes[end..], count, &types, xyz, path),
        "ascii" => {
            let text = std::str::from_utf8(&bytes[end..]).map_err(|_| {
                Error::Input(format!("{}: ASCII PLY data is not text", path.display()))
            })?;
            let first = header.lines().count() + 1;
            ascii_records(text, count, xyz, path, first)
        }
        other => Err(Error::Input(format!(
            "{}: PLY format '{other}' is not supported; write ascii or binary_little_endian",
            path.display()
        ))),
    }
}

fn pcd(path: &Path, bytes: &[u8]) -> Result<Points> {
    let end = header_end(bytes, b"DATA").ok_or_else(|| {
        Error::Input(format!("{}: not a PCD file (no DATA line)", path.display()))
    })?;
    let header = String::from_utf8_lossy(&bytes[..end]);
    let mut names: Vec<String> = Vec::new();
    let (mut sizes, mut kinds, mut counts) = (Vec::new(), Vec::new(), Vec::new());
    let (mut points, mut data) = (None, "");
    for line in header.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.first().copied() {
            Some("FIELDS") => names = w[1..].iter().map(|s| (*s).to_owned()).collect(),
            Some("SIZE") => sizes = w[1..].iter().map(|s| s.parse().unwrap_or(0)).collect(),
            Some("TYPE") => kinds = w[1..].to_vec(),
            Some("COUNT") => counts = w[1..].iter().map(|s| s.parse().unwrap_or(1)).collect(),
            Some("POINTS") => points = w.get(1).and_then(|s| s.parse::<usize>().ok()),
            Some("DATA") => data = w.get(1).copied().unwrap_or(""),
            _ => {}
        }
    }
    let count = points
        .ok_or_else(|| Error::Input(format!("{}: no POINTS line in the header", path.display())))?;
    if counts.is_empty() {
        counts = vec![1usize; names.len()];
    }
    // Expand fields with COUNT > 1 into one column each.
    let mut cols = Vec::new();
    let mut types = Vec::new();
    for (k, name) in names.iter().enumerate() {
        let (size, kind) = (
            sizes.get(k).copied().unwrap_or(0),
            kinds.get(k).copied().unwrap_or(""),
        );
        let s = match (kind, size) {
            ("F", 4) => Scalar::F32,
            ("F", 8) => Scalar::F64,
            ("I", 1) => Scalar::I8,
            ("U", 1) => Scalar::U8,
            ("I", 2) => Scalar::I16,
            ("U", 2) => Scalar::U16,
            ("I", 4) => Scalar::I32,
            ("U", 4) => Scalar::U32,
            _ => {
                return Err(Error::Input(format!(
                    "{}: field {name}: TYPE {kind} SIZE {size} is not supported",
                    path.display()
                )));
            }
        };
        for _ in 0..counts.get(k).copied().unwrap_or(1) {
            cols.push(name.clone());
            types.push(s);
        }
    }
    let xyz = xyz_of(&cols, path)?;
    match data {
        "binary" => binary_records(&bytes[end..], count, &types, xyz, path),
        "ascii" => {
            let text = std::str::from_utf8(&bytes[end..]).map_err(|_| {
                Error::Input(format!("{}: ASCII PCD data is not text", path.display()))
            })?;
            ascii_records(text, count, xyz, path, header.lines().count() + 1)
        }
        other => Err(Error::Input(format!(
            "{}: PCD DATA {other} is not supported; save it as ascii or binary",
            path.display()
        ))),
    }
}

fn npy(path: &Path, bytes: &[u8], grid: Option<&Grid>) -> Result<Points> {
    let grid = grid.ok_or_else(|| {
        Error::Input(format!(
            "{}: an occupancy .npy map is read on the world's free-space grid: make the world again with `subtgraph generate PIPELINE --format free-space` (or ground-truth), PIPELINE being its world.toml",
            path.display()
        ))
    })?;
    let npy_error = |source| Error::Npy {
        file: path.display().to_string(),
        source,
    };
    let shape = subtgraph_core::npy::shape(bytes).map_err(npy_error)?;
    let want = [grid.n[2], grid.n[1], grid.n[0]];
    if shape != want {
        return Err(Error::Input(format!(
            "{}: shape {shape:?}, but the world's free-space grid is {want:?} ([z, y, x], {} m voxels from {:?}, as in ground_truth/free_space.json)",
            path.display(),
            grid.voxel,
            grid.origin
        )));
    }
    // One-byte C-order arrays (what numpy writes for uint8 and bool) are read in place; other
    // dtypes through the decoder.
    let count = want.iter().product::<usize>();
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(256)]);
    let one_byte = (head.contains("'|u1'") || head.contains("'|b1'"))
        && head.contains("'fortran_order': False")
        && bytes.len() >= count;
    let decoded;
    let values: Box<dyn Iterator<Item = bool>> = if one_byte {
        Box::new(bytes[bytes.len() - count..].iter().map(|&b| b != 0))
    } else {
        decoded = subtgraph_core::npy::decode(bytes).map_err(npy_error)?;
        Box::new(decoded.values.iter().map(|&x| x != 0.0))
    };
    let mut out = Vec::new();
    let v = grid.voxel;
    for (i, x) in values.enumerate() {
        if x {
            let (ix, rest) = (i % grid.n[0], i / grid.n[0]);
            let (iy, iz) = (rest % grid.n[1], rest / grid.n[1]);
            out.push([
                (grid.origin[0] + (ix as f64 + 0.5) * v) as f32,
                (grid.origin[1] + (iy as f64 + 0.5) * v) as f32,
                (grid.origin[2] + (iz as f64 + 0.5) * v) as f32,
            ]);
        }
    }
    Ok(out)
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
