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

    fn line(&mut self, (x0, y0): (f64, f64), (x1, y1): (f64, f64), width: f64, c: Rgb) {
        let half = (width / 2.0).max(0.5);
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

/// Renders a figure at `scale` pixels per figure unit and encodes it as an RGB PNG.
pub fn to_png(figure: &Figure, scale: f64) -> Vec<u8> {
    let width = (figure.width * scale).round() as usize;
    let height = (figure.height * scale).round() as usize;
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
