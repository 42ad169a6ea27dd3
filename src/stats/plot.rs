//! The report's plots: grouped bar charts, box plots and IoU heatmaps, laid out once as a
//! list of rectangles, lines and labels ([`Figure`]) and written twice from it: as SVG by
//! hand, and as PNG by our own rasteriser (`raster.rs`). No plotting crate, and the
//! same numbers always give the same bytes.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result};

use super::Group;
use super::report::{GroupStats, PAPER_KINDS, Stats, Summary};
use crate::dataset::index::write_atomic;

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

const BLACK: Rgb = [0, 0, 0];
const LIGHT: Rgb = [225, 225, 225];
const WHITE: Rgb = [255, 255, 255];
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
    fn new(width: f64, height: f64) -> Figure {
        let mut f = Figure {
            width,
            height,
            shapes: Vec::new(),
        };
        f.rect(0.0, 0.0, width, height, WHITE);
        f
    }
    fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, fill: Rgb) {
        self.shapes.push(Shape::Rect { x, y, w, h, fill });
    }
    fn line(&mut self, from: (f64, f64), to: (f64, f64), stroke: Rgb, width: f64) {
        self.shapes.push(Shape::Line {
            from,
            to,
            stroke,
            width,
        });
    }
    fn text(&mut self, x: f64, y: f64, size: f64, anchor: Anchor, text: impl Into<String>) {
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
    fn vtext(&mut self, x: f64, y: f64, size: f64, text: impl Into<String>) {
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

/// A "nice" tick step (1, 2 or 5 times a power of ten) for about five ticks up to `max`.
fn tick_step(max: f64) -> f64 {
    let raw = (max / 5.0).max(1e-12);
    let mag = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw)
        .unwrap_or(10.0 * mag)
}

fn label(v: f64, step: f64) -> String {
    if step >= 1.0 {
        format!("{v:.0}")
    } else {
        let digits = (-step.log10().floor()) as usize;
        format!("{v:.digits$}")
    }
}

/// Plot area and a value axis from 0 to a nice maximum: title, axis labels, grid.
struct Axes {
    left: f64,
    top: f64,
    right: f64,
    bottom: f64,
    max: f64,
}

impl Axes {
    fn new(
        f: &mut Figure,
        title: &str,
        y_label: &str,
        x_label: &str,
        max: f64,
        legend: bool,
    ) -> Axes {
        let (left, top) = (78.0, 46.0);
        let right = f.width - if legend { 190.0 } else { 24.0 };
        let bottom = f.height - 58.0;
        f.text(f.width / 2.0, 20.0, 16.0, Anchor::Middle, title);
        f.vtext(20.0, (top + bottom) / 2.0, 13.0, y_label);
        f.text(
            (left + right) / 2.0,
            f.height - 16.0,
            13.0,
            Anchor::Middle,
            x_label,
        );
        let step = tick_step(if max > 0.0 { max } else { 1.0 });
        let top_value = (max / step).ceil().max(1.0) * step;
        let mut v = 0.0;
        while v <= top_value + step * 1e-9 {
            let y = bottom - (bottom - top) * v / top_value;
            f.line((left, y), (right, y), LIGHT, 1.0);
            f.text(left - 6.0, y, 11.0, Anchor::End, label(v, step));
            v += step;
        }
        f.line((left, top), (left, bottom), BLACK, 1.0);
        f.line((left, bottom), (right, bottom), BLACK, 1.0);
        Axes {
            left,
            top,
            right,
            bottom,
            max: top_value,
        }
    }
    fn y(&self, v: f64) -> f64 {
        self.bottom - (self.bottom - self.top) * (v / self.max).clamp(0.0, 1.0)
    }
}

fn legend(f: &mut Figure, axes: &Axes, names: &[(String, Rgb)]) {
    let x = axes.right + 16.0;
    for (i, (name, color)) in names.iter().enumerate() {
        let y = axes.top + 8.0 + 18.0 * i as f64;
        f.rect(x, y - 6.0, 12.0, 12.0, *color);
        f.text(x + 18.0, y, 11.0, Anchor::Start, name.clone());
    }
}

/// A grouped bar chart: one cluster per category, one bar per series.
pub fn bars(
    title: &str,
    x_label: &str,
    y_label: &str,
    categories: &[String],
    series: &[(String, Rgb, Vec<f64>)],
) -> Figure {
    let mut f = Figure::new(900.0, 520.0);
    let max = series
        .iter()
        .flat_map(|s| s.2.iter().copied())
        .fold(0.0, f64::max);
    let axes = Axes::new(&mut f, title, y_label, x_label, max, series.len() > 1);
    let slot = (axes.right - axes.left) / categories.len().max(1) as f64;
    let bar = slot * 0.8 / series.len().max(1) as f64;
    for (c, name) in categories.iter().enumerate() {
        let x0 = axes.left + slot * c as f64 + slot * 0.1;
        for (s, (_, color, values)) in series.iter().enumerate() {
            let v = values.get(c).copied().unwrap_or(0.0);
            let y = axes.y(v);
            f.rect(x0 + bar * s as f64, y, bar * 0.92, axes.bottom - y, *color);
        }
        f.text(
            axes.left + slot * (c as f64 + 0.5),
            axes.bottom + 14.0,
            11.0,
            Anchor::Middle,
            name.clone(),
        );
    }
    if series.len() > 1 {
        let names: Vec<(String, Rgb)> = series.iter().map(|s| (s.0.clone(), s.1)).collect();
        legend(&mut f, &axes, &names);
    }
    f
}

/// Box plots: per group, the box from the first to the third quartile, the median, and
/// whiskers to the smallest and largest values; a dot at the mean.
pub fn boxes(title: &str, y_label: &str, groups: &[(String, Summary)]) -> Figure {
    let mut f = Figure::new(900.0, 520.0);
    let max = groups.iter().map(|g| g.1.max).fold(0.0, f64::max);
    let axes = Axes::new(
        &mut f,
        title,
        y_label,
        "group (box: quartiles; line: median; whiskers: min and max; square: mean)",
        max,
        false,
    );
    let slot = (axes.right - axes.left) / groups.len().max(1) as f64;
    for (i, (name, s)) in groups.iter().enumerate() {
        let cx = axes.left + slot * (i as f64 + 0.5);
        let half = (slot * 0.25).min(60.0);
        let color = PALETTE[i % PALETTE.len()];
        f.line((cx, axes.y(s.min)), (cx, axes.y(s.q1)), BLACK, 1.0);
        f.line((cx, axes.y(s.q3)), (cx, axes.y(s.max)), BLACK, 1.0);
        for v in [s.min, s.max] {
            f.line(
                (cx - half / 2.0, axes.y(v)),
                (cx + half / 2.0, axes.y(v)),
                BLACK,
                1.0,
            );
        }
        // A box of equal quartiles is drawn 6 units high about the median, to stay visible.
        let (top, bottom) = (axes.y(s.q3), axes.y(s.q1));
        let (top, bottom) = if bottom - top < 6.0 {
            (axes.y(s.median) - 3.0, axes.y(s.median) + 3.0)
        } else {
            (top, bottom)
        };
        f.rect(cx - half, top, 2.0 * half, bottom - top, color);
        f.line(
            (cx - half, axes.y(s.median)),
            (cx + half, axes.y(s.median)),
            BLACK,
            2.0,
        );
        f.rect(cx - 3.0, axes.y(s.mean) - 3.0, 6.0, 6.0, BLACK);
        f.text(
            cx,
            axes.bottom + 14.0,
            11.0,
            Anchor::Middle,
            format!("{name} (n={})", s.n),
        );
    }
    f
}

/// Viridis, sampled at five stops and interpolated: dark blue for 0, yellow for 1.
pub fn viridis(t: f64) -> Rgb {
    const STOPS: [[f64; 3]; 5] = [
        [68.0, 1.0, 84.0],
        [59.0, 82.0, 139.0],
        [33.0, 145.0, 140.0],
        [94.0, 201.0, 98.0],
        [253.0, 231.0, 37.0],
    ];
    let x = t.clamp(0.0, 1.0) * 4.0;
    let i = (x.floor() as usize).min(3);
    let u = x - i as f64;
    let mix = |k: usize| (STOPS[i][k] + (STOPS[i + 1][k] - STOPS[i][k]) * u).round() as u8;
    [mix(0), mix(1), mix(2)]
}

/// The largest heatmap side drawn cell by cell; larger matrices are averaged in blocks.
const MAX_CELLS: usize = 150;

/// A heatmap of a square matrix of values in [0, 1] (missing values grey), with the groups'
/// blocks marked on both axes.
pub fn heatmap(
    title: &str,
    axis: &str,
    matrix: &[Vec<Option<f64>>],
    blocks: &[(String, usize, usize)],
) -> Figure {
    let n = matrix.len();
    let block = n.div_ceil(MAX_CELLS).max(1);
    let m = n.div_ceil(block);
    let mut f = Figure::new(820.0, 760.0);
    let (left, top, side) = (110.0, 50.0, 600.0);
    let title = if block > 1 {
        format!("{title} ({block} x {block} worlds per cell, averaged)")
    } else {
        title.to_owned()
    };
    f.text(f.width / 2.0, 20.0, 16.0, Anchor::Middle, title);
    let cell = side / m.max(1) as f64;
    for bi in 0..m {
        for bj in 0..m {
            let values: Vec<f64> = (bi * block..((bi + 1) * block).min(n))
                .flat_map(|i| (bj * block..((bj + 1) * block).min(n)).map(move |j| (i, j)))
                .filter_map(|(i, j)| matrix[i][j])
                .collect();
            let color = if values.is_empty() {
                [190, 190, 190]
            } else {
                viridis(values.iter().sum::<f64>() / values.len() as f64)
            };
            // Cells overlap by a hair so no background shows between them.
            f.rect(
                left + cell * bj as f64,
                top + cell * bi as f64,
                cell + 0.3,
                cell + 0.3,
                color,
            );
        }
    }
    let at = |k: usize| k as f64 / n.max(1) as f64 * side;
    for (name, start, len) in blocks {
        if *start > 0 {
            f.line(
                (left + at(*start), top),
                (left + at(*start), top + side),
                WHITE,
                2.0,
            );
            f.line(
                (left, top + at(*start)),
                (left + side, top + at(*start)),
                WHITE,
                2.0,
            );
        }
        let mid = at(*start) + at(*len) / 2.0;
        f.text(
            left + mid,
            top + side + 14.0,
            11.0,
            Anchor::Middle,
            name.clone(),
        );
        f.vtext(left - 14.0, top + mid, 11.0, name.clone());
    }
    f.text(
        left + side / 2.0,
        top + side + 40.0,
        13.0,
        Anchor::Middle,
        axis,
    );
    f.vtext(left - 40.0, top + side / 2.0, 13.0, axis);
    // Colour bar.
    let (bx, bw) = (left + side + 30.0, 20.0);
    for k in 0..100 {
        let t = 1.0 - k as f64 / 100.0;
        f.rect(
            bx,
            top + side * k as f64 / 100.0,
            bw,
            side / 100.0 + 0.3,
            viridis(t),
        );
    }
    for k in 0..=5 {
        let v = k as f64 / 5.0;
        let y = top + side * (1.0 - v);
        f.line((bx + bw, y), (bx + bw + 4.0, y), BLACK, 1.0);
        f.text(bx + bw + 7.0, y, 11.0, Anchor::Start, format!("{v:.1}"));
    }
    f.vtext(bx + bw + 50.0, top + side / 2.0, 13.0, "IoU (true union)");
    f
}

fn save(out: &Path, stem: &str, figure: &Figure) -> Result<()> {
    write_atomic(&out.join(format!("{stem}.svg")), figure.to_svg().as_bytes())
        .with_context(|| format!("writing {stem}.svg"))?;
    let png = super::raster::to_png(figure, 2.0);
    write_atomic(&out.join(format!("{stem}.png")), &png)
        .with_context(|| format!("writing {stem}.png"))
}

/// A file-name-safe form of a group name.
fn slug(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '-'
            }
        })
        .collect()
}

/// Writes every plot of the report.
pub fn write_all(stats: &Stats, groups: &[Group], out: &Path) -> Result<()> {
    let gs: &[GroupStats] = &stats.groups;
    let color = |i: usize| PALETTE[i % PALETTE.len()];

    // Heatmaps: every world, then each group's.
    let mut blocks = Vec::new();
    let mut start = 0;
    for g in groups {
        blocks.push((g.name.clone(), start, g.samples.len()));
        start += g.samples.len();
    }
    let true_iou = |rows: std::ops::Range<usize>| -> Vec<Vec<Option<f64>>> {
        stats.matrix[rows.clone()]
            .iter()
            .map(|r| r[rows.clone()].iter().map(|v| v.map(|v| v.0)).collect())
            .collect()
    };
    save(
        out,
        "iou-heatmap-all",
        &heatmap(
            "Pairwise IoU of level 0, all worlds",
            "world (by group)",
            &true_iou(0..start),
            &blocks,
        ),
    )?;
    for (name, s, len) in &blocks {
        save(
            out,
            &format!("iou-heatmap-{}", slug(name)),
            &heatmap(
                &format!("Pairwise IoU of level 0, {name}"),
                "world (by name)",
                &true_iou(*s..s + len),
                &[(name.clone(), 0, *len)],
            ),
        )?;
    }

    let series = |f: &dyn Fn(&GroupStats) -> Vec<f64>| -> Vec<(String, Rgb, Vec<f64>)> {
        gs.iter()
            .enumerate()
            .map(|(i, g)| (g.name.clone(), color(i), f(g)))
            .collect()
    };
    save(
        out,
        "mirror-asymmetry",
        &bars(
            "Mirror asymmetry (paper eqs. 20-22): IoU of each level with its mirror",
            "transformation",
            "mean IoU over levels",
            &[
                "horizontal mirror",
                "vertical mirror",
                "rotations 90/180/270",
            ]
            .map(String::from),
            &series(&|g| vec![g.mirror.horizontal, g.mirror.vertical, g.mirror.rotational]),
        ),
    )?;
    save(
        out,
        "tile-mix",
        &bars(
            "Tile appearance distribution",
            "tile kind (shaft ends counted as dead ends)",
            "share of tiles (%)",
            &PAPER_KINDS.map(String::from),
            &series(&|g| {
                PAPER_KINDS
                    .iter()
                    .map(|k| g.tile_mix_paper_percent[*k])
                    .collect()
            }),
        ),
    )?;
    let summaries = |f: &dyn Fn(&GroupStats) -> Summary| -> Vec<(String, Summary)> {
        gs.iter().map(|g| (g.name.clone(), f(g))).collect()
    };
    save(
        out,
        "size-cells",
        &boxes(
            "Environment size: occupied cells per world",
            "occupied cells",
            &summaries(&|g| g.cells),
        ),
    )?;
    save(
        out,
        "size-length",
        &boxes(
            "Environment size: total passage length per world",
            "passage length (m)",
            &summaries(&|g| g.length_m),
        ),
    )?;
    save(
        out,
        "size-levels",
        &boxes(
            "Environment size: levels per world",
            "levels",
            &summaries(&|g| g.levels),
        ),
    )?;
    save(
        out,
        "corridor-length",
        &boxes(
            "Corridor lengths (between graph nodes)",
            "corridor length (cells)",
            &summaries(&|g| g.graph.corridor_length_cells),
        ),
    )?;
    save(
        out,
        "cycles",
        &boxes(
            "Independent cycles per world",
            "cycles (edges - cells + pieces, per level, summed)",
            &summaries(&|g| g.graph.cycles),
        ),
    )?;
    save(
        out,
        "node-degree",
        &bars(
            "Node degree distribution of the topological graph",
            "degree (corridors and shafts at the node)",
            "share of nodes (%)",
            &["1", "2", "3", "4", "5+"].map(String::from),
            &series(&|g| {
                ["1", "2", "3", "4", "5+"]
                    .iter()
                    .map(|d| g.graph.degree_percent[*d])
                    .collect()
            }),
        ),
    )?;
    let structures = ["t-junction", "intersection", "loop"];
    let mut constraint_series = Vec::new();
    for (i, g) in gs.iter().enumerate() {
        if g.constraints.is_empty() {
            continue;
        }
        let per_world = |pick: fn(&super::report::Constraint) -> u64| -> Vec<f64> {
            structures
                .iter()
                .map(|s| {
                    g.constraints
                        .get(*s)
                        .map_or(0.0, |c| pick(c) as f64 / g.worlds.max(1) as f64)
                })
                .collect()
        };
        let base = color(i);
        let pale = base.map(|v| ((u16::from(v) + 2 * 255) / 3) as u8);
        constraint_series.push((
            format!("{} requested", g.name),
            pale,
            per_world(|c| c.requested),
        ));
        constraint_series.push((
            format!("{} achieved", g.name),
            base,
            per_world(|c| c.achieved),
        ));
    }
    if !constraint_series.is_empty() {
        save(
            out,
            "constraints",
            &bars(
                "Constraint satisfaction: requested and achieved structures",
                "structure",
                "mean per world (levels summed)",
                &structures.map(String::from),
                &constraint_series,
            ),
        )?;
    }
    Ok(())
}
