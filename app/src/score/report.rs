//! The score folder's files: `score.json` (everything), `reports.csv` (each report's
//! verdict), `artifacts.csv` (each artifact, found or not), `coverage.csv` (per world, level,
//! edge and node, with a map) and a picture per level.

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use super::coverage::{self, Coverage};
use super::reports::{self, MATCH_RADIUS, Truth, Verdict};
use super::world::Cells;
use super::{Counts, ScoreRequest, picture};

#[derive(Serialize)]
struct ArtifactRow<'a> {
    id: usize,
    name: &'a str,
    class: &'static str,
    level: usize,
    position: [f64; 3],
    found: bool,
    report_row: Option<usize>,
    time: Option<f64>,
    distance_m: Option<f64>,
}

#[derive(Serialize)]
struct ShareJson {
    free_voxels: u64,
    covered_voxels: u64,
    coverage: f64,
}

impl From<coverage::Share> for ShareJson {
    fn from(s: coverage::Share) -> Self {
        ShareJson {
            free_voxels: s.free,
            covered_voxels: s.covered,
            coverage: s.share(),
        }
    }
}

#[derive(Serialize)]
struct EdgeShare {
    id: usize,
    kind: String,
    from: usize,
    to: usize,
    level: usize,
    length_m: f64,
    #[serde(flatten)]
    share: ShareJson,
}

#[derive(Serialize)]
struct NodeShare {
    id: usize,
    level: usize,
    #[serde(flatten)]
    share: ShareJson,
}

#[derive(Serialize)]
pub(super) struct MapJson {
    file: String,
    points: usize,
    outside_grid: usize,
    errors: usize,
    error_share: f64,
    tolerance_m: f64,
    radius_m: f64,
    voxel_m: f64,
    total: ShareJson,
    levels: Vec<ShareJson>,
    edges: Vec<EdgeShare>,
    nodes: Vec<NodeShare>,
}

#[derive(Serialize)]
pub(super) struct ScoreJson<'a> {
    format: &'static str,
    world: String,
    reports_file: String,
    rule: String,
    score: usize,
    artifacts_total: usize,
    reports_total: usize,
    outcomes: Counts,
    mean_error_m: Option<f64>,
    artifacts: Vec<ArtifactRow<'a>>,
    reports: &'a [reports::Verdict],
    map: Option<MapJson>,
}

fn opt<T: std::fmt::Display>(v: Option<T>) -> String {
    v.map_or(String::new(), |v| v.to_string())
}

/// Everything the score folder's files are made from.
pub(super) struct Inputs<'a> {
    pub cells: &'a Cells,
    pub truth: &'a [Truth],
    pub verdicts: &'a [Verdict],
    pub found: &'a [Option<usize>],
    /// The map's file, grid and coverage, when one was scored.
    pub map: Option<(&'a Path, &'a super::cloud::Grid, &'a Coverage)>,
}

/// The score folder's files, `(name, bytes)`.
pub(super) fn files(r: &ScoreRequest, s: &super::Scored, i: &Inputs<'_>) -> Vec<(String, Vec<u8>)> {
    let Inputs {
        cells,
        truth,
        verdicts,
        found,
        map,
    } = *i;
    let artifacts: Vec<ArtifactRow> = truth
        .iter()
        .map(|t| {
            let v = found[t.id].map(|k| &verdicts[k]);
            ArtifactRow {
                id: t.id,
                name: &t.name,
                class: t.class.name(),
                level: t.level,
                position: t.position,
                found: v.is_some(),
                report_row: v.map(|v| v.row),
                time: v.map(|v| v.time),
                distance_m: v.and_then(|v| v.distance_m),
            }
        })
        .collect();
    let map_json = map.map(|(path, grid, c)| MapJson {
        file: path.display().to_string(),
        points: c.points,
        outside_grid: c.outside,
        errors: c.errors,
        error_share: c.errors as f64 / c.points.max(1) as f64,
        tolerance_m: r.tolerance,
        radius_m: r.radius,
        voxel_m: grid.voxel,
        total: c.total.into(),
        levels: c.levels.iter().map(|&s| s.into()).collect(),
        edges: cells
            .edges
            .iter()
            .map(|e| EdgeShare {
                id: e.id,
                kind: e.kind.clone(),
                from: e.from,
                to: e.to,
                level: e.level,
                length_m: e.length_m,
                share: c.edges[e.id].into(),
            })
            .collect(),
        nodes: cells
            .node_cells
            .iter()
            .enumerate()
            .map(|(id, cell)| NodeShare {
                id,
                level: cell[0],
                share: c.nodes[id].into(),
            })
            .collect(),
    });
    let doc = ScoreJson {
        format: "subtgraph-score/1",
        world: r.world.display().to_string(),
        reports_file: r.reports.display().to_string(),
        rule: format!(
            "DARPA: a report scores when an artifact of its class not yet found is within {MATCH_RADIUS} m (the nearest); reports in time order; each artifact once"
        ),
        score: s.outcomes.scored,
        artifacts_total: truth.len(),
        reports_total: s.reports_total,
        outcomes: s.outcomes,
        mean_error_m: s.mean_error_m,
        artifacts,
        reports: verdicts,
        map: map_json,
    };
    let mut json = serde_json::to_string_pretty(&doc).expect("plain data serializes");
    json.push('\n');
    let mut reports_csv = String::from("row,time,class,x,y,z,outcome,artifact,distance_m\n");
    for v in verdicts {
        let [x, y, z] = v.position;
        let _ = writeln!(
            reports_csv,
            "{},{},{},{x},{y},{z},{},{},{}",
            v.row,
            v.time,
            v.class,
            v.outcome.name(),
            opt(v.artifact),
            opt(v.distance_m.map(|d| format!("{d:.3}")))
        );
    }
    let mut artifacts_csv =
        String::from("id,name,class,level,x,y,z,found,report_row,time,distance_m\n");
    for a in &doc.artifacts {
        let [x, y, z] = a.position;
        let _ = writeln!(
            artifacts_csv,
            "{},{},{},{},{x:.4},{y:.4},{z:.4},{},{},{},{}",
            a.id,
            a.name,
            a.class,
            a.level,
            a.found,
            opt(a.report_row),
            opt(a.time),
            opt(a.distance_m.map(|d| format!("{d:.3}")))
        );
    }
    let mut coverage_csv = String::new();
    if let Some((_, _, c)) = map {
        coverage_csv.push_str("scope,id,level,free_voxels,covered_voxels,coverage\n");
        let mut row = |scope: &str, id: usize, level: String, s: coverage::Share| {
            let _ = writeln!(
                coverage_csv,
                "{scope},{id},{level},{},{},{:.6}",
                s.free,
                s.covered,
                s.share()
            );
        };
        row("world", 0, String::new(), c.total);
        for (l, s) in c.levels.iter().enumerate() {
            row("level", l, l.to_string(), *s);
        }
        for e in &cells.edges {
            row("edge", e.id, e.level.to_string(), c.edges[e.id]);
        }
        for (id, cell) in cells.node_cells.iter().enumerate() {
            row("node", id, cell[0].to_string(), c.nodes[id]);
        }
    }
    let pictures: Vec<Vec<u8>> = (0..cells.levels)
        .map(|l| picture::level(l, cells, truth, found, verdicts, map.map(|m| m.2)))
        .collect();
    let mut files = vec![
        ("score.json".to_owned(), json.into_bytes()),
        ("reports.csv".to_owned(), reports_csv.into_bytes()),
        ("artifacts.csv".to_owned(), artifacts_csv.into_bytes()),
    ];
    if !coverage_csv.is_empty() {
        files.push(("coverage.csv".to_owned(), coverage_csv.into_bytes()));
    }
    for (l, png) in pictures.into_iter().enumerate() {
        files.push((format!("level-{l}.png"), png));
    }
    files
}
