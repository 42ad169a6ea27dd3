//! The kinds of plot: grouped bar charts, box plots and heatmaps, laid out as
//! [`Figure`]s with titled, labelled axes. No plotting crate, and the same numbers always
//! give the same figure.

use crate::Summary;
use crate::figure::{Anchor, BLACK, Figure, LIGHT, PALETTE, Rgb, WHITE};

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
