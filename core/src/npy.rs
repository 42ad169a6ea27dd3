//! The NumPy `.npy` format (version 1.0 to 3.0), as bytes: writing `uint8` grids and reading
//! the integer, boolean and float arrays the original tool and numpy users save.
//!
//! The reader is our own rather than the `npyz` crate's: it is one function over a byte
//! slice (core does no file I/O), it converts every accepted dtype to the `f64` values the
//! importer checks cell by cell, which `npyz` would make us dispatch by hand over its typed
//! readers anyway, and the one writer and the reader share this file. What it must get right
//! on hostile files it does here: every size read from the header (header length, each
//! dimension, their product, the bytes it takes) is computed with checked arithmetic and
//! compared with the bytes actually present *before* anything is allocated, so a crafted
//! shape can neither panic, wrap around to a small or empty array, nor reserve memory the
//! file does not back.

/// A decoded array: its shape and its values in C (row-major) order.
#[derive(Clone, Debug, PartialEq)]
pub struct NpyArray {
    /// Dimensions.
    pub shape: Vec<usize>,
    /// Values, converted to `f64` (exact for every integer type up to 2^53).
    pub values: Vec<f64>,
    /// The numpy type string as found (`<i8`, `|u1`, ...).
    pub dtype: String,
}

/// Encodes a `uint8` array of the given shape (C order) as `.npy` version 1.0.
pub fn encode_u8(shape: &[usize], data: &[u8]) -> Vec<u8> {
    assert_eq!(
        shape.iter().product::<usize>(),
        data.len(),
        "shape and data disagree"
    );
    let dims: Vec<String> = shape.iter().map(|d| d.to_string()).collect();
    let shape_text = if dims.len() == 1 {
        format!("({},)", dims[0])
    } else {
        format!("({})", dims.join(", "))
    };
    let mut header = format!("{{'descr': '|u1', 'fortran_order': False, 'shape': {shape_text}, }}");
    // Pad with spaces so that magic (6) + version (2) + length (2) + header ends on a multiple
    // of 64 bytes, newline last.
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat((64 - unpadded % 64) % 64));
    header.push('\n');
    let mut out = Vec::with_capacity(10 + header.len() + data.len());
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    out.extend_from_slice(data);
    out
}

/// What a `.npy` header says, checked against the file's size.
struct Header {
    shape: Vec<usize>,
    count: usize,
    dtype: String,
    fortran: bool,
    data_start: usize,
    endian: u8,
    kind: u8,
    size: usize,
}

/// What is wrong with a `.npy` file; every message says what to change or what is corrupt.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum NpyError {
    /// No `\x93NUMPY` magic.
    #[error("not a .npy file (no \\x93NUMPY magic); save the array with numpy.save")]
    NotNpy,
    /// The header ends before it should.
    #[error("truncated .npy header")]
    Truncated,
    /// A format version other than 1, 2 or 3.
    #[error("unsupported .npy version {0}")]
    Version(u8),
    /// The header is not UTF-8 text.
    #[error("the .npy header is not text")]
    NotText,
    /// The header lacks a key (`descr` or `shape`).
    #[error("the .npy header has no '{0}'")]
    Missing(&'static str),
    /// A dimension is not a whole number (the shape text, cut to a readable length).
    #[error("bad shape {0}: the dimensions must be whole numbers")]
    BadShape(String),
    /// The shape's product overflows.
    #[error("shape {0} has more elements than any file can hold; the header is corrupt")]
    TooManyElements(String),
    /// A dtype this reader does not decode (cut to a readable length).
    #[error("unsupported dtype '{0}'")]
    Dtype(String),
    /// A dtype of a kind or size that is not integer, boolean or float.
    #[error("unsupported dtype '{0}': use an integer, boolean or float array")]
    DtypeKind(String),
    /// The shape times the value size overflows.
    #[error("shape {shape} with {size}-byte values is larger than any file can hold")]
    TooLarge {
        /// The shape text.
        shape: String,
        /// Bytes per value.
        size: usize,
    },
    /// Fewer data bytes than the header promises.
    #[error(
        "the file holds {have} bytes of data, the header promises {promised} ({count} values of {size} bytes)"
    )]
    Short {
        /// Data bytes present.
        have: usize,
        /// Data bytes promised.
        promised: usize,
        /// Values promised.
        count: usize,
        /// Bytes per value.
        size: usize,
    },
}

/// Where a `.npy` file's values are and how they are laid out, from its header, checked
/// against the file's size: what a reader needs to read values in place without decoding them
/// all (an occupancy map of a million voxels is a million bytes, not eight million).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Info {
    /// Dimensions.
    pub shape: Vec<usize>,
    /// Whether the first index varies fastest (Fortran order) rather than the last (C order).
    pub fortran: bool,
    /// Where the values start: the bytes `data_start..data_start + count * size` hold them,
    /// whatever follows.
    pub data_start: usize,
    /// Values (the shape's product).
    pub count: usize,
    /// `b'u'`, `b'i'`, `b'b'` (bool) or `b'f'`.
    pub kind: u8,
    /// Bytes per value.
    pub size: usize,
    /// Whether multi-byte values are big-endian.
    pub big_endian: bool,
}

/// The header of a `.npy` file, checked as [`decode`] checks it, without reading any value.
pub fn info(bytes: &[u8]) -> Result<Info, NpyError> {
    header(bytes).map(|h| Info {
        shape: h.shape,
        fortran: h.fortran,
        data_start: h.data_start,
        count: h.count,
        kind: h.kind,
        size: h.size,
        big_endian: h.endian == b'>',
    })
}

/// The shape a `.npy` file declares, read from its header alone (no values decoded; the dtype
/// and that the file holds the bytes the shape needs are checked), so a caller can size the
/// work before decoding. Errors as [`decode`]'s.
pub fn shape(bytes: &[u8]) -> Result<Vec<usize>, NpyError> {
    header(bytes).map(|h| h.shape)
}

fn header(bytes: &[u8]) -> Result<Header, NpyError> {
    if bytes.len() < 10 || &bytes[..6] != b"\x93NUMPY" {
        return Err(NpyError::NotNpy);
    }
    let major = bytes[6];
    let (header_len, start) = match major {
        1 => (
            usize::from(u16::from_le_bytes([bytes[8], bytes[9]])),
            10usize,
        ),
        2 | 3 => {
            if bytes.len() < 12 {
                return Err(NpyError::Truncated);
            }
            (
                u32::from_le_bytes([bytes[8], bytes[9], bytes[10], bytes[11]]) as usize,
                12,
            )
        }
        v => return Err(NpyError::Version(v)),
    };
    let header = start
        .checked_add(header_len)
        .and_then(|end| bytes.get(start..end))
        .ok_or(NpyError::Truncated)?;
    let header = std::str::from_utf8(header).map_err(|_| NpyError::NotText)?;
    let dtype = dict_value(header, "descr")
        .map(|v| v.trim_matches(|c| c == '\'' || c == '"').to_owned())
        .ok_or(NpyError::Missing("descr"))?;
    let fortran = dict_value(header, "fortran_order").is_some_and(|v| v.trim() == "True");
    let shape_text = dict_value(header, "shape").ok_or(NpyError::Missing("shape"))?;
    let shape: Vec<usize> = shape_text
        .trim_matches(|c| c == '(' || c == ')')
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| {
            s.parse::<usize>()
                .map_err(|_| NpyError::BadShape(crate::error::excerpt(shape_text).into_owned()))
        })
        .collect::<Result<_, _>>()?;
    let count = shape
        .iter()
        .try_fold(1usize, |n, &d| n.checked_mul(d))
        .ok_or_else(|| NpyError::TooManyElements(crate::error::excerpt(shape_text).into_owned()))?;
    let data = &bytes[start + header_len..];
    let (endian, kind, size) = {
        let b = dtype.as_bytes();
        if b.len() < 3 {
            return Err(NpyError::Dtype(crate::error::excerpt(&dtype).into_owned()));
        }
        let size: usize = dtype
            .get(2..)
            .unwrap_or_default()
            .parse()
            .map_err(|_| NpyError::Dtype(crate::error::excerpt(&dtype).into_owned()))?;
        (b[0], b[1], size)
    };
    if !matches!(
        (kind, size),
        (b'u' | b'i', 1 | 2 | 4 | 8) | (b'b', 1) | (b'f', 4 | 8)
    ) {
        return Err(NpyError::DtypeKind(
            crate::error::excerpt(&dtype).into_owned(),
        ));
    }
    let promised = count.checked_mul(size).ok_or_else(|| NpyError::TooLarge {
        shape: crate::error::excerpt(shape_text).into_owned(),
        size,
    })?;
    if data.len() < promised {
        return Err(NpyError::Short {
            have: data.len(),
            promised,
            count,
            size,
        });
    }
    Ok(Header {
        shape,
        count,
        dtype,
        fortran,
        data_start: start + header_len,
        endian,
        kind,
        size,
    })
}

/// Decodes a `.npy` file. The error says what is wrong with it.
pub fn decode(bytes: &[u8]) -> Result<NpyArray, NpyError> {
    let Header {
        shape,
        count,
        dtype,
        fortran,
        data_start,
        endian,
        kind,
        size,
    } = header(bytes)?;
    let data = &bytes[data_start..];
    let big = endian == b'>';
    let read = |i: usize| -> f64 {
        let mut b = [0u8; 8];
        b[..size].copy_from_slice(&data[i * size..(i + 1) * size]);
        if big {
            b[..size].reverse();
        }
        match (kind, size) {
            (b'i', _) => {
                let shift = 64 - 8 * size as u32;
                ((i64::from_le_bytes(b) << shift) >> shift) as f64
            }
            (b'f', 4) => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            (b'f', _) => f64::from_le_bytes(b),
            _ => u64::from_le_bytes(b) as f64,
        }
    };
    let mut values: Vec<f64> = (0..count).map(read).collect();
    if fortran && shape.len() > 1 {
        // Fortran order: the first index varies fastest. Reorder to C order.
        let mut c_order = vec![0.0; count];
        let mut strides_f = vec![1usize; shape.len()];
        for d in 1..shape.len() {
            strides_f[d] = strides_f[d - 1] * shape[d - 1];
        }
        for (ci, slot) in c_order.iter_mut().enumerate() {
            let mut rest = ci;
            let mut fi = 0;
            for d in (0..shape.len()).rev() {
                fi += (rest % shape[d]) * strides_f[d];
                rest /= shape[d];
            }
            *slot = values[fi];
        }
        values = c_order;
    }
    Ok(NpyArray {
        shape,
        values,
        dtype,
    })
}

/// The text of a key's value in a numpy header dict (`{'descr': '<i8', ...}`).
fn dict_value<'a>(header: &'a str, key: &str) -> Option<&'a str> {
    let k = header
        .find(&format!("'{key}'"))
        .or_else(|| header.find(&format!("\"{key}\"")))?;
    let rest = &header[k + key.len() + 2..];
    let rest = rest.trim_start().strip_prefix(':')?.trim_start();
    let end = if rest.starts_with('(') {
        rest.find(')')? + 1
    } else {
        rest.find(',').or_else(|| rest.find('}'))?
    };
    Some(rest[..end].trim())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn written_arrays_read_back_and_align_to_64_bytes() {
        let data: Vec<u8> = (0..24).collect();
        let bytes = encode_u8(&[2, 3, 4], &data);
        let header_len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        assert_eq!((10 + header_len) % 64, 0);
        let a = decode(&bytes).unwrap();
        assert_eq!(a.shape, vec![2, 3, 4]);
        assert_eq!(
            a.values,
            data.iter().map(|&v| f64::from(v)).collect::<Vec<_>>()
        );
        assert_eq!(a.dtype, "|u1");
    }

    fn with_header(descr: &str, fortran: bool, shape: &str, data: &[u8]) -> Vec<u8> {
        let h = format!(
            "{{'descr': '{descr}', 'fortran_order': {}, 'shape': {shape}, }}\n",
            if fortran { "True" } else { "False" }
        );
        let mut out = b"\x93NUMPY\x01\x00".to_vec();
        out.extend_from_slice(&(h.len() as u16).to_le_bytes());
        out.extend_from_slice(h.as_bytes());
        out.extend_from_slice(data);
        out
    }

    #[test]
    fn reads_int64_float64_and_fortran_order() {
        let ints: Vec<u8> = [-1i64, 10, 111]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let a = decode(&with_header("<i8", false, "(3,)", &ints)).unwrap();
        assert_eq!(a.values, vec![-1.0, 10.0, 111.0]);
        let floats: Vec<u8> = [1.0f64, 2.0, 3.0, 4.0, 5.0, 6.0]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        // Fortran order 2x3: memory is column by column.
        let a = decode(&with_header("<f8", true, "(2, 3)", &floats)).unwrap();
        assert_eq!(a.values, vec![1.0, 3.0, 5.0, 2.0, 4.0, 6.0]);
    }

    #[test]
    fn refuses_what_it_cannot_read() {
        assert!(
            decode(b"hello world")
                .unwrap_err()
                .to_string()
                .contains("magic")
        );
        let e = decode(&with_header("<c16", false, "(1,)", &[0; 16]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("unsupported dtype"), "{e}");
        let e = decode(&with_header("<i8", false, "(4,)", &[0; 16]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("header promises"), "{e}");
    }

    #[test]
    fn crafted_shapes_are_refused_not_wrapped_or_panicking() {
        // 4611686018427388004 * 4 wraps to 400 in 64 bits: the header must not be believed
        // because 400 bytes happen to follow (issue 10, item 3).
        let e = decode(&with_header(
            "|u1",
            false,
            "(4611686018427388004, 4)",
            &[1; 400],
        ))
        .unwrap_err()
        .to_string();
        assert!(e.contains("more elements than any file can hold"), "{e}");
        // 2^62 * 4 * 4 wraps to 0: not an "empty grid".
        let e = decode(&with_header(
            "|u1",
            false,
            "(4611686018427387904, 4, 4)",
            &[],
        ))
        .unwrap_err()
        .to_string();
        assert!(e.contains("more elements"), "{e}");
        // The element count fits, the bytes do not.
        let e = decode(&with_header(
            "<f8",
            false,
            "(4611686018427387904,)",
            &[0; 8],
        ))
        .unwrap_err()
        .to_string();
        assert!(e.contains("larger than any file can hold"), "{e}");
        // Fortran order with an overflowing shape.
        let e = decode(&with_header(
            "<i8",
            true,
            "(4294967296, 4294967296, 2)",
            &[0; 16],
        ))
        .unwrap_err()
        .to_string();
        assert!(e.contains("more elements"), "{e}");
        // A dtype with a multibyte character is an error, not a panic.
        let e = decode(&with_header("<\u{e9}8", false, "(1,)", &[0; 8]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("unsupported dtype"), "{e}");
        // Negative and non-numeric dimensions.
        for shape in ["(-1, 4)", "(4, x)"] {
            let e = decode(&with_header("|u1", false, shape, &[0; 4]))
                .unwrap_err()
                .to_string();
            assert!(e.contains("bad shape"), "{shape}: {e}");
        }
        // A version-2 header whose length runs past the file.
        let mut v2 = b"\x93NUMPY\x02\x00".to_vec();
        v2.extend_from_slice(&u32::MAX.to_le_bytes());
        v2.extend_from_slice(b"{}");
        assert!(decode(&v2).unwrap_err().to_string().contains("truncated"));
    }
}
