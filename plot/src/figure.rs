//! A picture as a list of rectangles, lines and labels, in figure units, and its SVG text
//! written by hand. The report's plots are laid out once as a [`Figure`] and written twice
//! from it: as SVG here and as PNG by the rasteriser (`raster.rs`), so both show the same.

use std::fmt::Write as _;

/// An sRGB colour.
pub type Rgb = [u8; 3];

/// Where a label sits relative to its point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Anchor {
    /// The point is the label's left end.
    Start,
    /// The point is its middle.
    Middle,
    /// The point is its right end.
    End,
}

/// One thing to draw, in figure units (SVG user units; the PNG doubles them).
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    /// A filled rectangle.
    Rect {
        /// Left.
        x: f64,
        /// Top.
        y: f64,
        /// Width.
        w: f64,
        /// Height.
        h: f64,
        /// Fill.
        fill: Rgb,
    },
    /// A straight line.
    Line {
        /// Start.
        from: (f64, f64),
        /// End.
        to: (f64, f64),
        /// Colour.
        stroke: Rgb,
        /// Width.
        width: f64,
    },
    /// A label, vertically centred on `y`; `vertical` runs it bottom to top.
    Text {
        /// Anchor point x.
        x: f64,
        /// Anchor point y (the label's vertical centre).
        y: f64,
        /// Line height.
        size: f64,
        /// How the label sits on x.
        anchor: Anchor,
        /// Turned a quarter counter-clockwise.
        vertical: bool,
        /// Colour.
        color: Rgb,
        /// The label.
        text: String,
    },
}

/// A picture: its size and what to draw, in order.
#[derive(Clone, Debug, Default)]
pub struct Figure {
    /// Width.
    pub width: f64,
    /// Height.
    pub height: f64,
    /// Shapes, drawn in order.
    pub shapes: Vec<Shape>,
}

pub(super) const BLACK: Rgb = [0, 0, 0];
pub(super) const LIGHT: Rgb = [225, 225, 225];
pub(super) const WHITE: Rgb = [255, 255, 255];
/// Distinct colours for series (Tableau 10).
pub const PALETTE: [Rgb; 10] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [127, 127, 127],
    [188, 189, 34],
    [23, 190, 207],
];

/// Width of a label of `size`: the bitmap font's cells are 7 x 13.
pub fn text_width(text: &str, size: f64) -> f64 {
    text.chars().count() as f64 * size * 7.0 / 13.0
}

impl Figure {
    pub(super) fn new(width: f64, height: f64) -> Figure {
        let mut f = Figure {
            width,
            height,
            shapes: Vec::new(),
        };
        f.rect(0.0, 0.0, width, height, WHITE);
        f
    }
    pub(super) fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, fill: Rgb) {
        self.shapes.push(Shape::Rect { x, y, w, h, fill });
    }
    pub(super) fn line(&mut self, from: (f64, f64), to: (f64, f64), stroke: Rgb, width: f64) {
        self.shapes.push(Shape::Line {
            from,
            to,
            stroke,
            width,
        });
    }
    pub(super) fn text(
        &mut self,
        x: f64,
        y: f64,
        size: f64,
        anchor: Anchor,
        text: impl Into<String>,
    ) {
        self.shapes.push(Shape::Text {
            x,
            y,
            size,
            anchor,
            vertical: false,
            color: BLACK,
            text: text.into(),
        });
    }
    pub(super) fn vtext(&mut self, x: f64, y: f64, size: f64, text: impl Into<String>) {
        self.shapes.push(Shape::Text {
            x,
            y,
            size,
            anchor: Anchor::Middle,
            vertical: true,
            color: BLACK,
            text: text.into(),
        });
    }

    /// The figure as an SVG document.
    pub fn to_svg(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="DejaVu Sans Mono, monospace">"#,
            w = self.width,
            h = self.height
        );
        let rgb = |c: Rgb| format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2]);
        for shape in &self.shapes {
            match shape {
                Shape::Rect { x, y, w, h, fill } => {
                    let _ = writeln!(
                        s,
                        r#"<rect x="{x:.2}" y="{y:.2}" width="{w:.2}" height="{h:.2}" fill="{}"/>"#,
                        rgb(*fill)
                    );
                }
                Shape::Line {
                    from,
                    to,
                    stroke,
                    width,
                } => {
                    let _ = writeln!(
                        s,
                        r#"<line x1="{:.2}" y1="{:.2}" x2="{:.2}" y2="{:.2}" stroke="{}" stroke-width="{width}"/>"#,
                        from.0,
                        from.1,
                        to.0,
                        to.1,
                        rgb(*stroke)
                    );
                }
                Shape::Text {
                    x,
                    y,
                    size,
                    anchor,
                    vertical,
                    color,
                    text,
                } => {
                    let anchor = match anchor {
                        Anchor::Start => "start",
                        Anchor::Middle => "middle",
                        Anchor::End => "end",
                    };
                    let turn = if *vertical {
                        format!(r#" transform="rotate(-90 {x:.2} {y:.2})""#)
                    } else {
                        String::new()
                    };
                    let escaped = text
                        .replace('&', "&amp;")
                        .replace('<', "&lt;")
                        .replace('>', "&gt;");
                    let _ = writeln!(
                        s,
                        r#"<text x="{x:.2}" y="{y:.2}" font-size="{:.1}" text-anchor="{anchor}" dominant-baseline="central" fill="{}"{turn}>{escaped}</text>"#,
                        size * 0.9,
                        rgb(*color)
                    );
                }
            }
        }
        s.push_str("</svg>\n");
        s
    }
}
