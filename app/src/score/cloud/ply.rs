//! PLY: ASCII or binary little endian. The header's elements are read in the order it declares
//! them; those before `vertex` (faces written first, say) are skipped record by record, those
//! after it are ignored.

use super::records::{self, Scalar, Xyz};
use super::{Points, bad, header_end};
use crate::Error;

/// A property of an element.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Property {
    /// One value.
    Scalar(Scalar),
    /// A length, then that many values.
    List { length: Scalar, item: Scalar },
}

/// An element of the header: its name, how many records, their properties.
#[derive(Debug)]
struct Element<'a> {
    name: &'a str,
    count: u64,
    properties: Vec<(&'a str, Property)>,
}

/// The header: the format and the elements in order.
struct Header<'a> {
    format: &'a str,
    elements: Vec<Element<'a>>,
    lines: usize,
}

fn header<'a>(text: &'a str, name: &str) -> Result<Header<'a>, Error> {
    let mut format = "";
    let mut elements: Vec<Element> = Vec::new();
    for line in text.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.as_slice() {
            ["format", f, ..] => format = f,
            ["element", element, n] => {
                let count = n.parse::<u64>().map_err(|_| {
                    bad(
                        name,
                        format!(
                            "element {} count '{}' is not a number",
                            subtgraph_core::error::excerpt(element),
                            subtgraph_core::error::excerpt(n)
                        ),
                    )
                })?;
                elements.push(Element {
                    name: element,
                    count,
                    properties: Vec::new(),
                });
            }
            ["property", rest @ ..] => {
                let Some(e) = elements.last_mut() else {
                    return Err(bad(name, "a property before any element in the header"));
                };
                let scalar = |t: &str| {
                    Scalar::ply(t).ok_or_else(|| {
                        bad(
                            name,
                            format!(
                                "unknown PLY property type '{}'",
                                subtgraph_core::error::excerpt(t)
                            ),
                        )
                    })
                };
                let (property_name, property) = match rest {
                    ["list", length, item, n] => (
                        *n,
                        Property::List {
                            length: scalar(length)?,
                            item: scalar(item)?,
                        },
                    ),
                    [t, n] => (*n, Property::Scalar(scalar(t)?)),
                    _ => {
                        return Err(bad(
                            name,
                            format!(
                                "the header line '{}' is not a property",
                                subtgraph_core::error::excerpt(line)
                            ),
                        ));
                    }
                };
                e.properties.push((property_name, property));
            }
            _ => {}
        }
    }
    Ok(Header {
        format,
        elements,
        lines: text.lines().count(),
    })
}

/// Reads a PLY file's vertices.
pub(super) fn read(bytes: &[u8], name: &str) -> Result<Points, Error> {
    if !bytes.starts_with(b"ply") {
        return Err(bad(name, "not a PLY file (it does not start with `ply`)"));
    }
    let end = header_end(bytes, b"end_header")
        .ok_or_else(|| bad(name, "the PLY header has no end_header"))?;
    let text = String::from_utf8_lossy(&bytes[..end]);
    let h = header(&text, name)?;
    let v = h
        .elements
        .iter()
        .position(|e| e.name == "vertex")
        .ok_or_else(|| bad(name, "no `element vertex` in the header"))?;
    let vertex = &h.elements[v];
    let mut scalars = Vec::new();
    for (_, p) in &vertex.properties {
        match p {
            Property::Scalar(s) => scalars.push(*s),
            Property::List { .. } => {
                return Err(bad(name, "list properties on vertices are not supported"));
            }
        }
    }
    let names: Vec<&str> = vertex.properties.iter().map(|(n, _)| *n).collect();
    let idx = records::xyz_of(&names, name)?;
    let offset = |k: usize| scalars[..k].iter().map(|s| s.size()).sum::<usize>();
    let xyz = Xyz {
        offset: idx.map(offset),
        scalar: idx.map(|k| scalars[k]),
        column: idx,
        columns: scalars.len(),
    };
    let data = &bytes[end..];
    match h.format {
        "binary_little_endian" => {
            let mut at = 0;
            for e in &h.elements[..v] {
                at += skip_binary(&data[at..], e, name)?;
            }
            let stride = scalars.iter().map(|s| s.size()).sum();
            records::binary(&data[at..], vertex.count, stride, &xyz, name).map(|(p, _)| p)
        }
        "ascii" => {
            let text =
                std::str::from_utf8(data).map_err(|_| bad(name, "ASCII PLY data is not text"))?;
            let mut rest = text;
            let mut line = h.lines + 1;
            for e in &h.elements[..v] {
                let (skipped, lines) = skip_ascii(rest, e, name)?;
                rest = &rest[skipped..];
                line += lines;
            }
            records::ascii(rest, vertex.count, &xyz, name, line)
        }
        other => Err(bad(
            name,
            format!(
                "PLY format '{}' is not supported; write ascii or binary_little_endian",
                subtgraph_core::error::excerpt(other)
            ),
        )),
    }
}

/// The bytes the binary records of element `e` take at the start of `data`.
fn skip_binary(data: &[u8], e: &Element, name: &str) -> Result<usize, Error> {
    let short = || {
        bad(
            name,
            format!(
                "the header promises {} `{}` records before the vertices, the file holds fewer; it is cut short",
                e.count,
                subtgraph_core::error::excerpt(e.name)
            ),
        )
    };
    if e.properties.is_empty() {
        return Ok(0);
    }
    if e.properties
        .iter()
        .all(|(_, p)| matches!(p, Property::Scalar(_)))
    {
        let stride: usize = e
            .properties
            .iter()
            .map(|(_, p)| match p {
                Property::Scalar(s) => s.size(),
                Property::List { .. } => 0,
            })
            .sum();
        return usize::try_from(e.count)
            .ok()
            .and_then(|c| c.checked_mul(stride))
            .filter(|&n| n <= data.len())
            .ok_or_else(short);
    }
    // Records of varying length: each takes at least a byte, so the loop ends with the data.
    let mut at = 0usize;
    for _ in 0..e.count {
        for (_, p) in &e.properties {
            let size = match *p {
                Property::Scalar(s) => s.size(),
                Property::List { length, item } => {
                    let n = data.get(at..at + length.size()).ok_or_else(short)?;
                    let n = length.length(n).ok_or_else(|| {
                        bad(name, format!("a list of `{}` has a bad length", e.name))
                    })?;
                    at += length.size();
                    usize::try_from(n)
                        .ok()
                        .and_then(|n| n.checked_mul(item.size()))
                        .ok_or_else(short)?
                }
            };
            at = at
                .checked_add(size)
                .filter(|&a| a <= data.len())
                .ok_or_else(short)?;
        }
    }
    Ok(at)
}

/// The bytes and lines the ASCII records of element `e` (one non-blank line each) take at the
/// start of `text`.
fn skip_ascii(text: &str, e: &Element, name: &str) -> Result<(usize, usize), Error> {
    let (mut at, mut lines, mut records) = (0, 0, 0u64);
    while records < e.count {
        let Some(end) = text[at..]
            .find('\n')
            .map(|i| at + i + 1)
            .or_else(|| (at < text.len()).then_some(text.len()))
        else {
            return Err(bad(
                name,
                format!(
                    "the header promises {} `{}` records before the vertices, the file has {records}",
                    e.count,
                    subtgraph_core::error::excerpt(e.name)
                ),
            ));
        };
        if !text[at..end].trim().is_empty() {
            records += 1;
        }
        lines += 1;
        at = end;
    }
    Ok((at, lines))
}
