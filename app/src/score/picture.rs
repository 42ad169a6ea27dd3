//! A top-down picture per level (`level-N.png`): the level's passages, each tile coloured by
//! the coverage of its graph edge or node when a map was scored (red none, green all; grey
//! without a map), found artifacts as green squares, missed ones red, and reports that did
//! not score as black crosses. Drawn with the statistics' own figure and rasteriser.

use subtgraph_plot::{Anchor, Figure, Rgb, Shape};

use super::coverage::Coverage;
use super::reports::{Outcome, Truth, Verdict};
use super::world::{Cells, Region};

const BLACK: Rgb = [0, 0, 0];
const FOUND: Rgb = [20, 170, 40];
const MISSED: Rgb = [220, 20, 20];
const PASSAGE: Rgb = [190, 190, 190];

fn mix(t: f64) -> Rgb {
    let t = t.clamp(0.0, 1.0);
    let a = [225.0, 90.0, 80.0];
    let b = [70.0, 175.0, 90.0];
    [0, 1, 2].map(|k| (a[k] + (b[k] - a[k]) * t).round() as u8)
}

fn rect(f: &mut Figure, x: f64, y: f64, w: f64, h: f64, fill: Rgb) {
    f.shapes.push(Shape::Rect { x, y, w, h, fill });
}

fn line(f: &mut Figure, from: (f64, f64), to: (f64, f64), width: f64) {
    f.shapes.push(Shape::Line {
        from,
        to,
        stroke: BLACK,
        width,
    });
}

fn text(f: &mut Figure, x: f64, y: f64, size: f64, s: String) {
    f.shapes.push(Shape::Text {
        x,
        y,
        size,
        anchor: Anchor::Start,
        vertical: false,
        color: BLACK,
        text: s,
    });
}

/// The PNG of one level.
pub fn level(
    level: usize,
    cells: &Cells,
    truth: &[Truth],
    found: &[Option<usize>],
    verdicts: &[Verdict],
    coverage: Option<&Coverage>,
) -> Vec<u8> {
    let [x0, y0, x1, y1] = cells.extent();
    let px = (900.0 / (cells.rows.max(cells.cols) as f64)).clamp(4.0, 24.0);
    let s = px / cells.pitch; // figure units per metre
    let (pad, head) = (12.0, 44.0);
    let mut f = Figure {
        width: (x1 - x0) * s + 2.0 * pad,
        height: (y1 - y0) * s + 2.0 * pad + head,
        shapes: Vec::new(),
    };
    let at = |x: f64, y: f64| (pad + (x - x0) * s, head + pad + (y1 - y) * s);
    let on_level: Vec<&Truth> = truth.iter().filter(|t| t.level == level).collect();
    let got = on_level.iter().filter(|t| found[t.id].is_some()).count();
    let mut title = format!("level {level}: found {got} of {} artifacts", on_level.len());
    if let Some(c) = coverage {
        title.push_str(&format!(
            ", coverage {:.1} %",
            100.0 * c.levels.get(level).map_or(0.0, |l| l.share())
        ));
    }
    text(&mut f, pad, 14.0, 14.0, title);
    text(
        &mut f,
        pad,
        32.0,
        10.0,
        "green: found, red: missed, x: report that did not score".into(),
    );
    for row in 0..cells.rows {
        for col in 0..cells.cols {
            let c = [level, row, col];
            if !cells.occupied(c) {
                continue;
            }
            let [cx, cy, cz] = cells.centre(c);
            let fill = match coverage {
                None => PASSAGE,
                Some(cov) => match cells.region(cx, cy, cz + 0.5) {
                    Some((_, Region::Node(n))) => mix(cov.nodes[n].share()),
                    Some((_, Region::Edge(e))) => mix(cov.edges[e].share()),
                    None => PASSAGE,
                },
            };
            let (x, y) = at(cx - 0.5 * cells.pitch, cy + 0.5 * cells.pitch);
            rect(&mut f, x + 0.5, y + 0.5, px - 1.0, px - 1.0, fill);
        }
    }
    let mark = (0.5 * px).max(5.0);
    for t in &on_level {
        let (x, y) = at(t.position[0], t.position[1]);
        rect(
            &mut f,
            x - 0.5 * mark - 1.0,
            y - 0.5 * mark - 1.0,
            mark + 2.0,
            mark + 2.0,
            BLACK,
        );
        let fill = if found[t.id].is_some() { FOUND } else { MISSED };
        rect(&mut f, x - 0.5 * mark, y - 0.5 * mark, mark, mark, fill);
    }
    let z0 = level as f64 * cells.level_height;
    for v in verdicts {
        let z = v.position[2];
        if v.outcome == Outcome::Scored
            || z < z0 - 0.25 * cells.level_height
            || z >= z0 + 0.75 * cells.level_height
        {
            continue;
        }
        let (x, y) = at(v.position[0], v.position[1]);
        let h = 0.5 * mark;
        line(&mut f, (x - h, y - h), (x + h, y + h), 1.5);
        line(&mut f, (x - h, y + h), (x + h, y - h), 1.5);
    }
    subtgraph_plot::to_png(&f, 1.0)
}
