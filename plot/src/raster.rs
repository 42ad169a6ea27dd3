//! A small rasteriser for [`Figure`]s: rectangles, lines and labels in the built-in bitmap
//! font (scaled by nearest neighbour), into an RGB image encoded as PNG.

use crate::figure::{Anchor, Figure, Rgb, Shape, text_width};
use crate::font;

struct Canvas {
    width: usize,
    height: usize,
    pixels: Vec<u8>,
}

impl Canvas {
    fn set(&mut self, x: i64, y: i64, c: Rgb) {
        if x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height {
            let i = (y as usize * self.width + x as usize) * 3;
            self.pixels[i..i + 3].copy_from_slice(&c);
        }
    }

    fn fill(&mut self, x0: f64, y0: f64, x1: f64, y1: f64, c: Rgb) {
        let (xa, xb) = (x0.round() as i64, x1.round() as i64);
        let (ya, yb) = (y0.round() as i64, y1.round() as i64);
        for y in ya.max(0)..yb.min(self.height as i64) {
            for x in xa.max(0)..xb.min(self.width as i64) {
                self.set(x, y, c);
            }
        }
    }

    fn line(&mut self, from: (f64, f64), to: (f64, f64), width: f64, c: Rgb) {
        let half = (width / 2.0).max(0.5);
        if !half.is_finite() {
            return;
        }
        // Only the part on the canvas is stepped along: a line from far outside (a coordinate
        // of 1e308) would otherwise take forever.
        let Some(((x0, y0), (x1, y1))) = clip(from, to, self.width, self.height, half) else {
            return;
        };
        let steps = (x1 - x0).abs().max((y1 - y0).abs()).ceil().max(1.0) as usize;
        for k in 0..=steps {
            let t = k as f64 / steps as f64;
            let (x, y) = (x0 + (x1 - x0) * t, y0 + (y1 - y0) * t);
            self.fill(x - half, y - half, x + half, y + half, c);
        }
    }

    /// Draws a label whose glyph cell is `size` pixels high.
    fn text(&mut self, s: &Shape, scale: f64) {
        let Shape::Text {
            x,
            y,
            size,
            anchor,
            vertical,
            color,
            text,
        } = s
        else {
            return;
        };
        let px = size * scale / font::HEIGHT as f64;
        let length = text_width(text, *size) * scale;
        let shift = match anchor {
            Anchor::Start => 0.0,
            Anchor::Middle => length / 2.0,
            Anchor::End => length,
        };
        let (x, y) = (x * scale, y * scale);
        let half = size * scale / 2.0;
        let w = (font::WIDTH as f64 * px).round() as i64;
        let h = (font::HEIGHT as f64 * px).round() as i64;
        for (i, ch) in text.chars().enumerate() {
            let glyph = font::glyph(ch);
            let along = -shift + i as f64 * font::WIDTH as f64 * px;
            for v in 0..h {
                let row = ((v as f64 / px) as usize).min(font::HEIGHT - 1);
                for u in 0..w {
                    let col = ((u as f64 / px) as usize).min(font::WIDTH - 1);
                    if glyph[row] >> (font::WIDTH - 1 - col) & 1 == 0 {
                        continue;
                    }
                    let (gx, gy) = (along + u as f64, v as f64 - half);
                    // Turned a quarter counter-clockwise, the text runs up and its top faces left.
                    let (dx, dy) = if *vertical { (gy, -gx) } else { (gx, gy) };
                    self.set((x + dx).round() as i64, (y + dy).round() as i64, *color);
                }
            }
        }
    }
}

/// The part of the segment `a`-`b` within `pad` of a `width` x `height` canvas (Liang and
/// Barsky's clipping), or `None` when no part of it is (or a coordinate is not a number).
fn clip(
    a: (f64, f64),
    b: (f64, f64),
    width: usize,
    height: usize,
    pad: f64,
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    if ![a.0, a.1, dx, dy].iter().all(|v| v.is_finite()) {
        return None;
    }
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 + pad),
        (dx, width as f64 + pad - a.0),
        (-dy, a.1 + pad),
        (dy, height as f64 + pad - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else if p < 0.0 {
            t0 = t0.max(q / p);
        } else {
            t1 = t1.min(q / p);
        }
    }
    let (p0, p1) = (
        (a.0 + t0 * dx, a.1 + t0 * dy),
        (a.0 + t1 * dx, a.1 + t1 * dy),
    );
    (t0 <= t1).then_some((p0, p1))
}

/// The largest side of a picture, pixels: a figure's size out of range (not a number, or
/// beyond this) is brought within 1 to this many pixels, so no figure makes an empty or a huge
/// picture.
pub const MAX_SIDE: usize = 16384;

/// Renders a figure at `scale` pixels per figure unit and encodes it as an RGB PNG (each side
/// of 1 to [`MAX_SIDE`] pixels, whatever the figure's size says).
pub fn to_png(figure: &Figure, scale: f64) -> Vec<u8> {
    let side = |v: f64| {
        let v = (v * scale).round();
        if v.is_finite() {
            v.clamp(1.0, MAX_SIDE as f64) as usize
        } else {
            1
        }
    };
    let (width, height) = (side(figure.width), side(figure.height));
    let mut canvas = Canvas {
        width,
        height,
        pixels: vec![255; width * height * 3],
    };
    for shape in &figure.shapes {
        match shape {
            Shape::Rect { x, y, w, h, fill } => canvas.fill(
                x * scale,
                y * scale,
                (x + w) * scale,
                (y + h) * scale,
                *fill,
            ),
            Shape::Line {
                from,
                to,
                stroke,
                width,
            } => canvas.line(
                (from.0 * scale, from.1 * scale),
                (to.0 * scale, to.1 * scale),
                width * scale,
                *stroke,
            ),
            Shape::Text { .. } => canvas.text(shape, scale),
        }
    }
    let mut bytes = Vec::new();
    {
        let mut encoder = png::Encoder::new(&mut bytes, width as u32, height as u32);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        let mut writer = encoder.write_header().expect("writing to memory");
        writer
            .write_image_data(&canvas.pixels)
            .expect("writing to memory");
    }
    bytes
}
