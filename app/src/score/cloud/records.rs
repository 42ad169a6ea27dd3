//! Point records: a scalar type read as `f32`, fixed-layout binary records, and ASCII lines.

use super::{Points, bad};
use crate::Error;

/// A property's scalar type: its size and how to read it as `f32`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Scalar {
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
    /// A PLY type name.
    pub fn ply(name: &str) -> Option<Scalar> {
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

    /// A PCD `TYPE` and `SIZE`.
    pub fn pcd(kind: &str, size: usize) -> Option<Scalar> {
        Some(match (kind, size) {
            ("F", 4) => Scalar::F32,
            ("F", 8) => Scalar::F64,
            ("I", 1) => Scalar::I8,
            ("U", 1) => Scalar::U8,
            ("I", 2) => Scalar::I16,
            ("U", 2) => Scalar::U16,
            ("I", 4) => Scalar::I32,
            ("U", 4) => Scalar::U32,
            _ => return None,
        })
    }

    /// Bytes per value.
    pub fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::F32 | Scalar::I32 | Scalar::U32 => 4,
            Scalar::F64 => 8,
        }
    }

    /// The little-endian value at the start of `b` (which holds at least [`Scalar::size`]
    /// bytes).
    pub fn read(self, b: &[u8]) -> f32 {
        let n = |k: usize| -> [u8; 8] {
            let mut a = [0u8; 8];
            a[..k].copy_from_slice(&b[..k]);
            a
        };
        match self {
            Scalar::F32 => f32::from_le_bytes(n(4)[..4].try_into().expect("4 bytes")),
            Scalar::F64 => f64::from_le_bytes(n(8)) as f32,
            Scalar::I8 => f32::from(b[0] as i8),
            Scalar::U8 => f32::from(b[0]),
            Scalar::I16 => f32::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f32::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => i32::from_le_bytes(n(4)[..4].try_into().expect("4 bytes")) as f32,
            Scalar::U32 => u32::from_le_bytes(n(4)[..4].try_into().expect("4 bytes")) as f32,
        }
    }

    /// The unsigned value at the start of `b`, for a PLY list's length (`None` for a float
    /// or a negative length).
    pub fn length(self, b: &[u8]) -> Option<u64> {
        let v = self.read(b);
        match self {
            Scalar::F32 | Scalar::F64 => None,
            Scalar::U32 => Some(u64::from(u32::from_le_bytes(b[..4].try_into().ok()?))),
            Scalar::I32 => u64::try_from(i32::from_le_bytes(b[..4].try_into().ok()?)).ok(),
            _ => (v >= 0.0).then_some(v as u64),
        }
    }
}

/// Where x, y and z are in a record: byte offsets and types (binary) or column indices
/// (ASCII), and the values an ASCII record has.
#[derive(Clone, Copy, Debug)]
pub(super) struct Xyz {
    pub offset: [usize; 3],
    pub scalar: [Scalar; 3],
    pub column: [usize; 3],
    pub columns: usize,
}

/// Reads `count` fixed-layout records of `stride` bytes from the start of `data`, whose
/// length is checked first (a count the data cannot hold is an error, before anything is
/// reserved). Returns the points and the bytes they took.
pub(super) fn binary(
    data: &[u8],
    count: u64,
    stride: usize,
    xyz: &Xyz,
    name: &str,
) -> Result<(Points, usize), Error> {
    let need = usize::try_from(count)
        .ok()
        .and_then(|c| c.checked_mul(stride))
        .filter(|&n| n <= data.len())
        .ok_or_else(|| {
            bad(
                name,
                format!(
                    "the header promises {count} points of {stride} bytes ({}), the file holds {} after its header; it is cut short",
                    u128::from(count)
                        .checked_mul(stride as u128)
                        .map_or_else(|| "more than any file".to_owned(), |n| format!("{n} bytes")),
                    data.len()
                ),
            )
        })?;
    if stride == 0 {
        return Err(bad(name, "the points have no fields"));
    }
    let [ox, oy, oz] = xyz.offset;
    let [tx, ty, tz] = xyz.scalar;
    let points = data[..need]
        .chunks_exact(stride)
        .map(|r| [tx.read(&r[ox..]), ty.read(&r[oy..]), tz.read(&r[oz..])])
        .collect();
    Ok((points, need))
}

/// Reads `count` whitespace-separated ASCII records, one per non-blank line, taking columns
/// `xyz.column`; `first_line` is the line number of the first one, for messages. Nothing is
/// reserved for the count: points grow as lines are read.
pub(super) fn ascii(
    text: &str,
    count: u64,
    xyz: &Xyz,
    name: &str,
    first_line: usize,
) -> Result<Points, Error> {
    let mut out = Vec::new();
    let lines = text.lines().filter(|l| !l.trim().is_empty());
    for (k, line) in lines.enumerate() {
        if k as u64 >= count {
            break;
        }
        let cells: Vec<&str> = line.split_ascii_whitespace().collect();
        if cells.len() < xyz.columns {
            return Err(bad(
                name,
                format!(
                    "point {k} (line {}): {} values, but the header gives each point {}",
                    first_line + k,
                    cells.len(),
                    xyz.columns
                ),
            ));
        }
        let mut p = [0f32; 3];
        for (axis, &c) in xyz.column.iter().enumerate() {
            let cell = cells.get(c).ok_or_else(|| {
                bad(
                    name,
                    format!("point {k} (line {}): too few values", first_line + k),
                )
            })?;
            p[axis] = match cell.to_ascii_lowercase().as_str() {
                "nan" | "-nan" => f32::NAN,
                _ => cell.parse().map_err(|_| {
                    bad(
                        name,
                        format!(
                            "point {k} (line {}): '{}' is not a number",
                            first_line + k,
                            subtgraph_core::error::excerpt(cell)
                        ),
                    )
                })?,
            };
        }
        out.push(p);
    }
    if (out.len() as u64) < count {
        return Err(bad(
            name,
            format!(
                "the header promises {count} points, the file has {}",
                out.len()
            ),
        ));
    }
    Ok(out)
}

/// The index of each of x, y and z among `names`.
pub(super) fn xyz_of(names: &[&str], name: &str) -> Result<[usize; 3], Error> {
    let find = |k: &str| {
        names.iter().position(|n| *n == k).ok_or_else(|| {
            bad(
                name,
                format!(
                    "the points have no `{k}` field (they have {})",
                    subtgraph_core::error::excerpt_to(&names.join(", "), 200)
                ),
            )
        })
    };
    Ok([find("x")?, find("y")?, find("z")?])
}
