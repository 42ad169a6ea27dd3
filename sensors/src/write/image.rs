//! Image files of a camera's frames: PNG for what every image reader reads (8-bit RGB or grey,
//! 16-bit class ids and TUM depth), TIFF for what PNG cannot hold (float32 depth in metres,
//! 32-bit instance ids). Both compressed with DEFLATE at its fastest (`fdeflate`, as the PNG
//! crate's `Fast` uses it): a frame's files are written at camera rate, and the images'
//! noise leaves little for a slower search to find.
//!
//! The TIFFs are baseline single-strip, little-endian files with DEFLATE (compression 8) and
//! a predictor, which OpenCV (`imread(..., IMREAD_UNCHANGED)`), libtiff, tifffile and Pillow
//! read: the floating-point predictor (3) for depth, its bytes split into planes and
//! differenced along each row, which turns a smooth depth image into small numbers; the
//! horizontal predictor (2) for the instance ids, whose long runs then become zeros.

/// An 8-bit PNG, RGB (`channels` 3) or grey (1), rows from the top.
pub fn png8(width: usize, height: usize, channels: usize, pixels: &[u8]) -> Vec<u8> {
    let colour = if channels == 3 {
        png::ColorType::Rgb
    } else {
        png::ColorType::Grayscale
    };
    encode_png(width, height, colour, png::BitDepth::Eight, pixels)
}

/// A 16-bit grey PNG (PNG stores its samples big-endian).
pub fn png16(width: usize, height: usize, values: &[u16]) -> Vec<u8> {
    let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_be_bytes()).collect();
    encode_png(
        width,
        height,
        png::ColorType::Grayscale,
        png::BitDepth::Sixteen,
        &bytes,
    )
}

fn encode_png(
    width: usize,
    height: usize,
    colour: png::ColorType,
    depth: png::BitDepth,
    data: &[u8],
) -> Vec<u8> {
    let mut out = Vec::with_capacity(data.len() / 2 + 1024);
    {
        let mut enc = png::Encoder::new(&mut out, width as u32, height as u32);
        enc.set_color(colour);
        enc.set_depth(depth);
        enc.set_compression(png::Compression::Fast);
        let mut w = enc
            .write_header()
            .expect("writing into memory does not fail");
        w.write_image_data(data)
            .expect("the data is the image's size");
    }
    out
}

/// A float32 TIFF (depth, metres).
pub fn tiff_f32(width: usize, height: usize, values: &[f32]) -> Vec<u8> {
    let mut data = Vec::with_capacity(values.len() * 4);
    let mut row = vec![0u8; width * 4];
    for r in values.chunks_exact(width) {
        // The floating-point predictor: byte planes, most significant first, then each byte
        // less the one before it along the row (libtiff's fpDiff).
        for (i, v) in r.iter().enumerate() {
            let b = v.to_le_bytes();
            for plane in 0..4 {
                row[plane * width + i] = b[3 - plane];
            }
        }
        for i in (1..row.len()).rev() {
            row[i] = row[i].wrapping_sub(row[i - 1]);
        }
        data.extend_from_slice(&row);
    }
    tiff(width, height, &data, 3, 3)
}

/// A signed 32-bit integer TIFF (instance ids).
pub fn tiff_i32(width: usize, height: usize, values: &[u32]) -> Vec<u8> {
    let mut data = Vec::with_capacity(values.len() * 4);
    for r in values.chunks_exact(width) {
        let mut last = 0u32;
        for &v in r {
            data.extend_from_slice(&v.wrapping_sub(last).to_le_bytes());
            last = v;
        }
    }
    tiff(width, height, &data, 2, 2)
}

/// A one-strip, one-sample, 32-bit TIFF of already predicted `data`, DEFLATE-compressed.
fn tiff(width: usize, height: usize, data: &[u8], predictor: u16, sample_format: u16) -> Vec<u8> {
    let strip = fdeflate::compress_to_vec(data);
    // Header (8 bytes), the strip, then the directory (word-aligned).
    let mut out = Vec::with_capacity(strip.len() + 200);
    out.extend_from_slice(b"II*\0");
    let dir_at = (8 + strip.len()).next_multiple_of(2);
    out.extend_from_slice(&(dir_at as u32).to_le_bytes());
    out.extend_from_slice(&strip);
    out.resize(dir_at, 0);
    // (tag, type: 3 SHORT or 4 LONG, value), ascending tags.
    let entries: [(u16, u16, u32); 12] = [
        (256, 4, width as u32),
        (257, 4, height as u32),
        (258, 3, 32),
        (259, 3, 8),
        (262, 3, 1),
        (273, 4, 8),
        (277, 3, 1),
        (278, 4, height as u32),
        (279, 4, strip.len() as u32),
        (284, 3, 1),
        (317, 3, u32::from(predictor)),
        (339, 3, u32::from(sample_format)),
    ];
    out.extend_from_slice(&(entries.len() as u16).to_le_bytes());
    for (tag, kind, value) in entries {
        out.extend_from_slice(&tag.to_le_bytes());
        out.extend_from_slice(&kind.to_le_bytes());
        out.extend_from_slice(&1u32.to_le_bytes());
        if kind == 3 {
            out.extend_from_slice(&(value as u16).to_le_bytes());
            out.extend_from_slice(&[0, 0]);
        } else {
            out.extend_from_slice(&value.to_le_bytes());
        }
    }
    out.extend_from_slice(&0u32.to_le_bytes());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reads back what [`tiff_f32`] wrote: the strip its directory points to, inflated, the
    /// predictor undone.
    fn read_f32(bytes: &[u8], width: usize) -> Vec<f32> {
        let u32_at = |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().unwrap()) as usize;
        let dir = u32_at(4);
        let n = u16::from_le_bytes([bytes[dir], bytes[dir + 1]]) as usize;
        let tag = |t: u16| {
            (0..n)
                .map(|k| dir + 2 + 12 * k)
                .find(|&e| u16::from_le_bytes([bytes[e], bytes[e + 1]]) == t)
                .map(|e| u32_at(e + 8))
                .unwrap()
        };
        let (at, len) = (tag(273), tag(279));
        let data = fdeflate::decompress_to_vec(&bytes[at..at + len]).unwrap();
        let mut out = Vec::new();
        for row in data.chunks_exact(width * 4) {
            let mut r = row.to_vec();
            for i in 1..r.len() {
                r[i] = r[i].wrapping_add(r[i - 1]);
            }
            for i in 0..width {
                let b = [r[3 * width + i], r[2 * width + i], r[width + i], r[i]];
                out.push(f32::from_le_bytes(b));
            }
        }
        out
    }

    #[test]
    fn depth_survives_the_predictor_and_deflate() {
        let (w, h) = (37, 5);
        let depth: Vec<f32> = (0..w * h).map(|i| 1.0 + (i as f32) * 0.013).collect();
        let file = tiff_f32(w, h, &depth);
        assert_eq!(&file[..4], b"II*\0");
        assert_eq!(read_f32(&file, w), depth);
        let png = png16(4, 1, &[0, 1, 256, 65535]);
        let mut dec = png::Decoder::new(std::io::Cursor::new(png))
            .read_info()
            .unwrap();
        let mut buf = vec![0; dec.output_buffer_size().unwrap()];
        dec.next_frame(&mut buf).unwrap();
        assert_eq!(buf, [0, 0, 0, 1, 1, 0, 255, 255]);
    }
}
