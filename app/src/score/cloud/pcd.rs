//! PCD (PCL's point cloud data): ASCII, binary, or binary_compressed (LZF, fields one after
//! another). A field with `COUNT` n takes n columns; it is read as its first value.

use super::records::{self, Scalar, Xyz};
use super::{Points, bad, header_end, lzf};
use crate::Error;

/// A field: its type and how many values it has per point.
struct Field {
    scalar: Scalar,
    count: usize,
}

/// Reads a PCD file's points.
pub(super) fn read(bytes: &[u8], name: &str) -> Result<Points, Error> {
    let end =
        header_end(bytes, b"DATA").ok_or_else(|| bad(name, "not a PCD file (no DATA line)"))?;
    let header = String::from_utf8_lossy(&bytes[..end]);
    let (mut names, mut sizes, mut kinds, mut counts) = (Vec::new(), None, None, None);
    let (mut points, mut data) = (None, "");
    let number = |key: &str, s: &str| {
        s.parse::<usize>().map_err(|_| {
            bad(
                name,
                format!(
                    "{key} '{}' is not a whole number",
                    subtgraph_core::error::excerpt(s)
                ),
            )
        })
    };
    for line in header.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        let rest = w.get(1..).unwrap_or_default();
        match w.first().copied() {
            Some("FIELDS") => names = rest.to_vec(),
            Some("SIZE") => {
                sizes = Some(
                    rest.iter()
                        .map(|s| number("SIZE", s))
                        .collect::<Result<Vec<_>, _>>()?,
                )
            }
            Some("TYPE") => kinds = Some(rest.to_vec()),
            Some("COUNT") => {
                counts = Some(
                    rest.iter()
                        .map(|s| number("COUNT", s))
                        .collect::<Result<Vec<_>, _>>()?,
                )
            }
            Some("POINTS") => {
                let n = rest
                    .first()
                    .ok_or_else(|| bad(name, "POINTS has no number"))?;
                points = Some(n.parse::<u64>().map_err(|_| {
                    bad(
                        name,
                        format!(
                            "POINTS '{}' is not a whole number",
                            subtgraph_core::error::excerpt(n)
                        ),
                    )
                })?);
            }
            Some("DATA") => data = rest.first().copied().unwrap_or(""),
            _ => {}
        }
    }
    let count = points.ok_or_else(|| bad(name, "no POINTS line in the header"))?;
    let sizes = sizes.ok_or_else(|| bad(name, "no SIZE line in the header"))?;
    let kinds = kinds.ok_or_else(|| bad(name, "no TYPE line in the header"))?;
    let counts = counts.unwrap_or_else(|| vec![1; names.len()]);
    if sizes.len() != names.len() || kinds.len() != names.len() || counts.len() != names.len() {
        return Err(bad(
            name,
            format!(
                "FIELDS names {} fields, SIZE {}, TYPE {} and COUNT {}: each gives one per field",
                names.len(),
                sizes.len(),
                kinds.len(),
                counts.len()
            ),
        ));
    }
    let mut fields = Vec::new();
    for (k, field) in names.iter().enumerate() {
        let scalar = Scalar::pcd(kinds[k], sizes[k]).ok_or_else(|| {
            bad(
                name,
                format!(
                    "field {}: TYPE {} SIZE {} is not supported",
                    subtgraph_core::error::excerpt(field),
                    subtgraph_core::error::excerpt(kinds[k]),
                    sizes[k]
                ),
            )
        })?;
        if counts[k] == 0 {
            return Err(bad(
                name,
                format!("field {field}: COUNT 0; every field has at least 1 value"),
            ));
        }
        fields.push(Field {
            scalar,
            count: counts[k],
        });
    }
    let idx = records::xyz_of(&names, name)?;
    // Bytes and columns before each field; the sums are checked, as COUNT may be anything.
    let too_wide = || {
        bad(
            name,
            "the fields' COUNTs add up to more values than any file holds",
        )
    };
    let mut offsets = Vec::with_capacity(fields.len() + 1);
    let mut columns = Vec::with_capacity(fields.len() + 1);
    let (mut offset, mut column) = (0usize, 0usize);
    for f in &fields {
        offsets.push(offset);
        columns.push(column);
        offset = f
            .count
            .checked_mul(f.scalar.size())
            .and_then(|n| offset.checked_add(n))
            .ok_or_else(too_wide)?;
        column = column.checked_add(f.count).ok_or_else(too_wide)?;
    }
    let stride = offset;
    let xyz = Xyz {
        offset: idx.map(|k| offsets[k]),
        scalar: idx.map(|k| fields[k].scalar),
        column: idx.map(|k| columns[k]),
        columns: column,
    };
    let body = &bytes[end..];
    match data {
        "binary" => records::binary(body, count, stride, &xyz, name).map(|(p, _)| p),
        "binary_compressed" => compressed(body, count, stride, &fields, idx, name),
        "ascii" => {
            let text =
                std::str::from_utf8(body).map_err(|_| bad(name, "ASCII PCD data is not text"))?;
            records::ascii(text, count, &xyz, name, header.lines().count() + 1)
        }
        other => Err(bad(
            name,
            format!(
                "PCD DATA {} is not supported; save it as ascii, binary or binary_compressed",
                subtgraph_core::error::excerpt(other)
            ),
        )),
    }
}

/// `binary_compressed`: the compressed and uncompressed sizes (`u32` each), then LZF data
/// which holds each field's values for every point, field after field.
fn compressed(
    body: &[u8],
    count: u64,
    stride: usize,
    fields: &[Field],
    idx: [usize; 3],
    name: &str,
) -> Result<Points, Error> {
    let word = |k: usize| {
        body.get(4 * k..4 * k + 4)
            .map(|b| u32::from_le_bytes(b.try_into().expect("4 bytes")) as usize)
            .ok_or_else(|| bad(name, "binary_compressed data without its two sizes"))
    };
    let (packed, unpacked) = (word(0)?, word(1)?);
    let expected = usize::try_from(count)
        .ok()
        .and_then(|c| c.checked_mul(stride))
        .filter(|&n| n == unpacked)
        .ok_or_else(|| {
            bad(
                name,
                format!(
                    "binary_compressed data unpacks to {unpacked} bytes, but POINTS {count} of {stride} bytes need {}",
                    u128::from(count) * stride as u128
                ),
            )
        })?;
    let input = body
        .get(8..)
        .and_then(|b| b.get(..packed))
        .ok_or_else(|| {
            bad(
                name,
                format!(
                    "binary_compressed data of {packed} bytes, the file holds {} after its header; it is cut short",
                    body.len().saturating_sub(8)
                ),
            )
        })?;
    let data = lzf::decompress(input, expected).map_err(|why| bad(name, why))?;
    let n = expected / stride.max(1);
    // Where each field's block of values starts.
    let mut starts = Vec::with_capacity(fields.len());
    let mut at = 0;
    for f in fields {
        starts.push(at);
        at += n * f.count * f.scalar.size();
    }
    let value = |k: usize, i: usize| {
        let f = &fields[k];
        f.scalar
            .read(&data[starts[k] + i * f.count * f.scalar.size()..])
    };
    Ok((0..n)
        .map(|i| [value(idx[0], i), value(idx[1], i), value(idx[2], i)])
        .collect())
}
