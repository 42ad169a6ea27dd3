//! The report's pictures, one PNG per metric: a panel per world parameter with every run as
//! a dot (a colour per method) and each method's least-squares line; and one of the failure
//! rate per bin of each parameter. Laid out as `plot` figures, drawn by its rasteriser.

use subtgraph_plot::{Anchor, Figure, PALETTE, Rgb, Shape, to_png};

use super::sample::{Bin, Line};
use super::world::PARAMETERS;

const BLACK: Rgb = [0, 0, 0];
const LIGHT: Rgb = [215, 215, 215];
const WHITE: Rgb = [255, 255, 255];
const PANEL: (f64, f64) = (290.0, 210.0);
const COLUMNS: usize = 4;
const HEAD: f64 = 56.0;

/// One method's points and line in one panel.
pub struct Series<'a> {
    /// The method.
    pub method: &'a str,
    /// `(parameter, metric)` per run.
    pub points: Vec<(f64, f64)>,
    /// The fitted line, when there is one.
    pub line: Option<Line>,
}

fn text(f: &mut Figure, x: f64, y: f64, size: f64, anchor: Anchor, t: impl Into<String>) {
    f.shapes.push(Shape::Text {
        x,
        y,
        size,
        anchor,
        vertical: false,
        color: BLACK,
        text: t.into(),
    });
}

fn rect(f: &mut Figure, x: f64, y: f64, w: f64, h: f64, fill: Rgb) {
    f.shapes.push(Shape::Rect { x, y, w, h, fill });
}

fn line(f: &mut Figure, from: (f64, f64), to: (f64, f64), stroke: Rgb, width: f64) {
    f.shapes.push(Shape::Line {
        from,
        to,
        stroke,
        width,
    });
}

fn number(v: f64) -> String {
    if v == 0.0 {
        "0".into()
    } else if v.abs() >= 1000.0 || v.abs() < 0.01 {
        format!("{v:.2e}")
    } else {
        format!("{v:.3}")
            .trim_end_matches('0')
            .trim_end_matches('.')
            .into()
    }
}

fn figure(title: &str, methods: &[&str]) -> Figure {
    let rows = PARAMETERS.len().div_ceil(COLUMNS);
    let mut f = Figure {
        width: PANEL.0 * COLUMNS as f64,
        height: HEAD + PANEL.1 * rows as f64,
        shapes: Vec::new(),
    };
    let (w, h) = (f.width, f.height);
    rect(&mut f, 0.0, 0.0, w, h, WHITE);
    text(&mut f, 12.0, 16.0, 15.0, Anchor::Start, title);
    let mut x = 12.0;
    for (k, m) in methods.iter().enumerate() {
        rect(&mut f, x, 34.0, 10.0, 10.0, PALETTE[k % PALETTE.len()]);
        text(&mut f, x + 14.0, 39.0, 11.0, Anchor::Start, *m);
        x += 30.0 + subtgraph_plot::text_width(m, 11.0);
    }
    f
}

/// A panel's plot area: left, top, right, bottom.
fn area(k: usize) -> (f64, f64, f64, f64) {
    let (col, row) = ((k % COLUMNS) as f64, (k / COLUMNS) as f64);
    let (x, y) = (col * PANEL.0, HEAD + row * PANEL.1);
    (x + 56.0, y + 22.0, x + PANEL.0 - 14.0, y + PANEL.1 - 34.0)
}

/// Frame, title and the range labels of one panel; maps values into it.
fn panel(
    f: &mut Figure,
    k: usize,
    name: &str,
    x: (f64, f64),
    y: (f64, f64),
) -> impl Fn(f64, f64) -> (f64, f64) + use<> {
    let (l, t, r, b) = area(k);
    rect(f, l, t, r - l, b - t, [248, 248, 248]);
    line(f, (l, b), (r, b), BLACK, 1.0);
    line(f, (l, t), (l, b), BLACK, 1.0);
    line(f, (l, t), (r, t), LIGHT, 1.0);
    text(f, (l + r) / 2.0, t - 10.0, 11.0, Anchor::Middle, name);
    text(f, l, b + 10.0, 10.0, Anchor::Start, number(x.0));
    text(f, r, b + 10.0, 10.0, Anchor::End, number(x.1));
    text(f, l - 4.0, b - 4.0, 10.0, Anchor::End, number(y.0));
    text(f, l - 4.0, t + 4.0, 10.0, Anchor::End, number(y.1));
    let span = |(a, c): (f64, f64)| if c > a { c - a } else { 1.0 };
    let (sx, sy) = (span(x), span(y));
    move |u: f64, v: f64| {
        (
            l + (r - l) * ((u - x.0) / sx).clamp(0.0, 1.0),
            b - (b - t) * ((v - y.0) / sy).clamp(0.0, 1.0),
        )
    }
}

fn range(v: impl Iterator<Item = f64>) -> (f64, f64) {
    v.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    })
}

/// A metric against every parameter: `panels[p]` holds each method's series on parameter `p`.
pub fn scatter(metric: &str, methods: &[&str], panels: &[Vec<Series<'_>>]) -> Vec<u8> {
    let mut f = figure(&format!("{metric} against the world's parameters"), methods);
    for (k, series) in panels.iter().enumerate() {
        let x = range(series.iter().flat_map(|s| s.points.iter().map(|p| p.0)));
        let y = range(series.iter().flat_map(|s| s.points.iter().map(|p| p.1)));
        if !x.0.is_finite() {
            continue;
        }
        let at = panel(&mut f, k, PARAMETERS[k], x, y);
        for s in series {
            let colour =
                PALETTE[methods.iter().position(|m| *m == s.method).unwrap_or(0) % PALETTE.len()];
            for &(u, v) in &s.points {
                let (px, py) = at(u, v);
                rect(&mut f, px - 2.0, py - 2.0, 4.0, 4.0, colour);
            }
            if let Some(fit) = s.line {
                line(
                    &mut f,
                    at(x.0, fit.slope * x.0 + fit.intercept),
                    at(x.1, fit.slope * x.1 + fit.intercept),
                    colour,
                    2.0,
                );
            }
        }
    }
    to_png(&f, 1.0)
}

/// Failure rate per bin of every parameter: `panels[p][method]` are its bins.
pub fn failures(methods: &[&str], panels: &[Vec<Vec<Bin>>]) -> Vec<u8> {
    let mut f = figure("failure rate per bin of each world parameter", methods);
    for (k, per_method) in panels.iter().enumerate() {
        let bins = per_method.iter().map(Vec::len).max().unwrap_or(0);
        if bins == 0 {
            continue;
        }
        let first = &per_method[0];
        let x = (first[0].from, first[bins - 1].to);
        let at = panel(&mut f, k, PARAMETERS[k], x, (0.0, 1.0));
        let (l, _, r, b) = area(k);
        let slot = (r - l) / bins as f64;
        let bar = slot * 0.8 / per_method.len().max(1) as f64;
        for (m, list) in per_method.iter().enumerate() {
            for (j, bin) in list.iter().enumerate() {
                let top = at(x.0, bin.rate.unwrap_or(0.0)).1;
                let left = l + slot * j as f64 + slot * 0.1 + bar * m as f64;
                rect(
                    &mut f,
                    left,
                    top,
                    bar * 0.9,
                    b - top,
                    PALETTE[m % PALETTE.len()],
                );
            }
        }
    }
    to_png(&f, 1.0)
}
