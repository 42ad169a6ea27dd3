//! With a world folder: a top-down picture per level the run visits
//! (`trajectory-level-N.png`), the level's passages as their tiles in light grey, the
//! reference in dark grey and the aligned estimate coloured by APE, so where on the level the
//! error grew is seen against the level's own layout (what the paper's figures 14 and 15 show
//! by hand). A pair belongs to the level of its reference position's graph region; a stretch
//! between two pairs is drawn on a level when both ends are on it.

use subtgraph_plot::{Figure, Rgb, Shape, viridis};

use super::Scored;
use crate::score::world::Cells;

const TILE: Rgb = [222, 222, 222];
const REFERENCE: Rgb = [90, 90, 90];

/// `(level, PNG)` for each level at least two consecutive pairs lie on.
pub(super) fn pictures(cells: &Cells, s: &Scored) -> Vec<(usize, Vec<u8>)> {
    let level: Vec<Option<usize>> = s
        .refs
        .iter()
        .map(|p| cells.region(p.t[0], p.t[1], p.t[2]).map(|(l, _)| l))
        .collect();
    let top = s.summary.ape_m.max.max(1e-12);
    let mut out = Vec::new();
    for l in 0..cells.levels {
        let on = |k: usize| level[k] == Some(l) && level[k + 1] == Some(l);
        if !(0..s.refs.len().saturating_sub(1)).any(on) {
            continue;
        }
        let [x0, y0, x1, y1] = cells.extent();
        let span = (x1 - x0).max(y1 - y0).max(1e-9);
        let k = 900.0 / span;
        let (pad, head) = (16.0, 44.0);
        let at = |x: f64, y: f64| (pad + (x - x0) * k, head + pad + (y1 - y) * k);
        let mut f = Figure {
            width: (x1 - x0) * k + 2.0 * pad,
            height: (y1 - y0) * k + 2.0 * pad + head,
            shapes: Vec::new(),
        };
        for row in 0..cells.rows {
            for col in 0..cells.cols {
                if !cells.occupied([l, row, col]) {
                    continue;
                }
                let c = cells.centre([l, row, col]);
                let h = 0.5 * cells.pitch;
                let (x, y) = at(c[0] - h, c[1] + h);
                f.shapes.push(Shape::Rect {
                    x,
                    y,
                    w: cells.pitch * k,
                    h: cells.pitch * k,
                    fill: TILE,
                });
            }
        }
        let pairs: Vec<usize> = (0..s.refs.len() - 1).filter(|&i| on(i)).collect();
        let worst = pairs.iter().map(|&i| s.ape[i + 1]).fold(0.0_f64, f64::max);
        super::files::heading(
            &mut f,
            pad,
            format!(
                "level {l}: {} of {} pairs here; APE here up to {worst:.3} m",
                level.iter().filter(|&&x| x == Some(l)).count(),
                s.refs.len()
            ),
            format!(
                "grey tiles: the level's passages; dark grey: reference; estimate by APE, dark 0 m to yellow {:.3} m",
                s.summary.ape_m.max
            ),
        );
        for &i in &pairs {
            let (a, b) = (s.refs[i].t, s.refs[i + 1].t);
            f.shapes.push(Shape::Line {
                from: at(a[0], a[1]),
                to: at(b[0], b[1]),
                stroke: REFERENCE,
                width: 3.0,
            });
        }
        for &i in &pairs {
            let (a, b) = (s.aligned[i].t, s.aligned[i + 1].t);
            f.shapes.push(Shape::Line {
                from: at(a[0], a[1]),
                to: at(b[0], b[1]),
                stroke: viridis(s.ape[i + 1] / top),
                width: 1.5,
            });
        }
        out.push((l, subtgraph_plot::to_png(&f, 1.0)));
    }
    out
}
