//! `linear`: no bend, as in operational mines. Corridors run straight along the rows and columns
//! and turn at right angles: the guide is an L (the longer leg first, then one turn), and every
//! turn costs the search [`TURN_COST`] more, so where the L is blocked the route goes round
//! with few straight runs instead of a staircase of corners. A mine's drifts meet at right
//! angles, with a corner share near the original's published mines (under 5 %).

use subtgraph_core::error::ConfigError;
use subtgraph_core::params::Params;
use subtgraph_core::route::{RouteDescriptor, Segment};

/// `[route] type = "linear"`. Takes no parameters.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Linear;

impl Linear {
    /// Refuses any parameter: a straight line has nothing to set.
    pub fn from_params(p: &Params) -> Result<Self, ConfigError> {
        p.expect_none()?;
        Ok(Linear)
    }
}

/// What a right-angle turn costs a linear route, in steps on its guide: a turn is worth a
/// detour of about seven cells off the guide, so a blocked route takes a longer straight run
/// rather than a jog of two extra corners.
pub const TURN_COST: u32 = 40;

impl RouteDescriptor for Linear {
    fn offset(&self, _t: f64, _segment: &Segment) -> f64 {
        0.0
    }

    fn turn_cost(&self) -> u32 {
        TURN_COST
    }

    /// An L from start to end: along the axis with the longer run first (the segment's side
    /// decides a tie), one turn, then along the other. Every step is one cell, so the guide is
    /// a shortest path and the search keeps to it wherever it is free.
    fn guide(&self, segment: &Segment) -> Vec<[i32; 2]> {
        let clamp = |v: f64, n: usize| v.round().clamp(0.0, n.saturating_sub(1) as f64) as i32;
        let start = [
            clamp(segment.start[0], segment.rows),
            clamp(segment.start[1], segment.cols),
        ];
        let end = [
            clamp(segment.end[0], segment.rows),
            clamp(segment.end[1], segment.cols),
        ];
        let (dr, dc) = ((end[0] - start[0]).abs(), (end[1] - start[1]).abs());
        let rows_first = dr > dc || (dr == dc && segment.side > 0.0);
        let corner = if rows_first {
            [end[0], start[1]]
        } else {
            [start[0], end[1]]
        };
        let mut cells = vec![start];
        for target in [corner, end] {
            let mut at = *cells.last().expect("starts with the start");
            while at != target {
                at[0] += (target[0] - at[0]).signum();
                at[1] += (target[1] - at[1]).signum();
                cells.push(at);
            }
        }
        cells
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn guides_run_straight_and_parameters_are_refused() {
        let s = Segment {
            start: [5.0, 5.0],
            end: [25.0, 5.0],
            rows: 30,
            cols: 30,
            side: -1.0,
        };
        assert!(Linear.guide(&s).iter().all(|c| c[1] == 5));
        // Off the axes: an L with the longer leg first, each step one cell, one turn.
        let s = Segment {
            start: [5.0, 5.0],
            end: [8.0, 15.0],
            ..s
        };
        let g = Linear.guide(&s);
        assert_eq!(g.first(), Some(&[5, 5]));
        assert_eq!(g.last(), Some(&[8, 15]));
        assert_eq!(g.len(), 3 + 10 + 1);
        assert!(
            g[..11].iter().all(|c| c[0] == 5),
            "columns first: the longer run"
        );
        assert!(g[10..].iter().all(|c| c[1] == 15));
        assert!(Linear.turn_cost() > 0);
        let mut t = toml::Table::new();
        t.insert("amplitude".into(), toml::Value::Float(1.0));
        let e = Linear::from_params(&Params::from_table("route", t)).unwrap_err();
        assert_eq!(e.key, "route.amplitude");
    }
}
