//! Where a run's error grew, on the world's graph: when the positional argument is a world
//! folder, each associated pose is placed by its reference position in the graph region of
//! `topology.json` it lies in (a node's tile or an edge's corridor tiles, on its level, as the
//! map coverage places voxels), and the run is cut into stretches of consecutive poses in one
//! region. A stretch's APE increase is its last pose's APE minus the APE on entering it (the
//! pose before it; 0 for the first), so the increases add up to the final APE: the largest
//! ones say which junction, dead end, corridor, shaft or ramp the method lost its way in.

use std::fmt::Write as _;

use serde::Serialize;

use super::pose::Pose;
use crate::score::world::{Cells, Region};

/// One stretch of the run in one graph region.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Stretch {
    /// `"node"`, `"edge"`, or `"outside"` (in no region: off the grid or in rock).
    pub region: &'static str,
    /// The node's or edge's id in `topology.json`.
    pub id: Option<usize>,
    /// An edge's kind (`corridor`, `shaft`, `ramp`, ...) or a node's (`dead end` with one
    /// edge, `bend` with two, `junction` with more).
    pub kind: String,
    /// The level.
    pub level: Option<usize>,
    /// First and last associated pose (0-based).
    pub poses: [usize; 2],
    /// Reference times of those, seconds.
    pub time_s: [f64; 2],
    /// APE on entering and at the last pose, metres.
    pub ape_m: [f64; 2],
    /// `ape_m[1] - ape_m[0]`.
    pub ape_increase_m: f64,
}

fn node_kind(cells: &Cells, n: usize) -> String {
    let degree = cells
        .edges
        .iter()
        .filter(|e| e.from == n || e.to == n)
        .count();
    match degree {
        0 | 1 => "dead end",
        2 => "bend",
        _ => "junction",
    }
    .to_owned()
}

/// The stretches of the run, in time order.
pub fn stretches(cells: &Cells, times: &[f64], reference: &[Pose], ape: &[f64]) -> Vec<Stretch> {
    let place = |p: &Pose| cells.region(p.t[0], p.t[1], p.t[2]);
    let mut out: Vec<Stretch> = Vec::new();
    let mut current = None;
    for (k, p) in reference.iter().enumerate() {
        let here = place(p);
        if k > 0 && here == current {
            let s = out.last_mut().expect("a stretch is open");
            s.poses[1] = k;
            s.time_s[1] = times[k];
            s.ape_m[1] = ape[k];
            s.ape_increase_m = ape[k] - s.ape_m[0];
            continue;
        }
        current = here;
        let entry = if k == 0 { 0.0 } else { ape[k - 1] };
        let (region, id, kind, level) = match here {
            None => ("outside", None, String::new(), None),
            Some((l, Region::Node(n))) => ("node", Some(n), node_kind(cells, n), Some(l)),
            Some((l, Region::Edge(e))) => ("edge", Some(e), cells.edges[e].kind.clone(), Some(l)),
        };
        out.push(Stretch {
            region,
            id,
            kind,
            level,
            poses: [k, k],
            time_s: [times[k], times[k]],
            ape_m: [entry, ape[k]],
            ape_increase_m: ape[k] - entry,
        });
    }
    out
}

/// `graph.csv`: a row per stretch.
pub fn csv(stretches: &[Stretch]) -> String {
    let mut s = String::from(
        "region,id,kind,level,first_pose,last_pose,time_start,time_end,ape_entry_m,ape_end_m,ape_increase_m\n",
    );
    let opt = |v: Option<usize>| v.map_or(String::new(), |v| v.to_string());
    for t in stretches {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{}",
            t.region,
            opt(t.id),
            t.kind,
            opt(t.level),
            t.poses[0],
            t.poses[1],
            t.time_s[0],
            t.time_s[1],
            t.ape_m[0],
            t.ape_m[1],
            t.ape_increase_m
        );
    }
    s
}

/// The `n` stretches whose APE grew most, largest first (earlier first on a tie).
pub fn largest(stretches: &[Stretch], n: usize) -> Vec<Stretch> {
    let mut v: Vec<&Stretch> = stretches.iter().collect();
    v.sort_by(|a, b| b.ape_increase_m.total_cmp(&a.ape_increase_m));
    v.into_iter().take(n).cloned().collect()
}
