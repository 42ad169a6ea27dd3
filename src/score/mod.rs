//! `subtgraph score WORLD --reports FILE [--map CLOUD] --out DIR`: grades a robot's run
//! against a world's ground truth, as the DARPA Subterranean Challenge graded teams.
//!
//! - Reports (`reports.rs`): matched to `ground_truth/artifacts.json` by the DARPA rule (same
//!   class within 5 m, each artifact once, in time order); duplicates, wrong classes and false
//!   reports counted.
//! - A map (`cloud.rs`, `coverage.rs`): coverage of the world's free space per level, graph
//!   edge and node, and map error, on `ground_truth/free_space.npy`.
//! - Output: `score.json`, `reports.csv`, `artifacts.csv`, `coverage.csv`, `level-N.png`
//!   (`picture.rs`) in a folder written atomically like every folder the tool writes (an
//!   existing one is replaced only with `--force` and only if the tool wrote all of it), and a
//!   summary on the terminal.
//!
//! Bad input is an error naming the file and the row or point: an unknown class, a NaN, an
//! empty file, or positions far outside the world (another frame or unit).

mod cloud;
mod coverage;
mod picture;
mod reports;
mod world;

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use serde::Serialize;

pub use reports::MATCH_RADIUS;

/// What `score` was asked.
#[derive(Clone, Debug)]
pub struct Options {
    /// The world folder.
    pub world: PathBuf,
    /// The reports file (CSV or JSON).
    pub reports: PathBuf,
    /// A map (PLY, PCD, occupancy .npy), if any.
    pub map: Option<PathBuf>,
    /// A free voxel within this distance of a mapped point is covered, metres.
    pub radius: f64,
    /// A mapped point farther than this from the surface is an error, metres.
    pub tolerance: f64,
    /// The output folder.
    pub out: PathBuf,
    /// Replace an output folder the tool wrote.
    pub force: bool,
}

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
struct MapJson {
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
struct Counts {
    scored: usize,
    duplicate: usize,
    wrong_class: usize,
    false_reports: usize,
}

#[derive(Serialize)]
struct ScoreJson<'a> {
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

/// Refuses reports far outside the world: another frame or unit.
fn check_reports(list: &[reports::Report], cells: &world::Cells, file: &Path) -> Result<()> {
    let [x0, y0, x1, y1] = cells.extent();
    let margin = (2.0 * cells.pitch).max(20.0);
    let (z0, z1) = (
        -cells.level_height,
        cells.levels as f64 * cells.level_height,
    );
    for r in list {
        let [x, y, z] = r.position;
        if x < x0 - margin
            || x > x1 + margin
            || y < y0 - margin
            || y > y1 + margin
            || z < z0 - margin
            || z > z1 + margin
        {
            bail!(
                "{}: row {}: ({x}, {y}, {z}) is more than {margin:.0} m outside the world (x {x0:.1} to {x1:.1}, y {y0:.1} to {y1:.1}, z {z0:.1} to {z1:.1} m): reports must be in the world frame in metres (x east, y north, z up, as ground_truth/artifacts.json)",
                file.display(),
                r.row
            );
        }
    }
    Ok(())
}

/// Scores a run; returns the terminal summary.
pub fn run(o: &Options) -> Result<String> {
    for (what, v) in [("--radius", o.radius), ("--tolerance", o.tolerance)] {
        if !(v.is_finite() && v >= 0.0) {
            bail!("{what} must be a number of metres, 0 or more");
        }
    }
    let cells = world::cells(&o.world)?;
    let truth = world::artifacts(&o.world)?;
    let list = reports::read(&o.reports)?;
    check_reports(&list, &cells, &o.reports)?;
    let (verdicts, found) = reports::score(&list, &truth);
    let map = match &o.map {
        None => None,
        Some(path) => {
            let (grid, free) = world::free_space(&o.world)?;
            let points = cloud::read(path, Some(&grid))?;
            let margin = (2.0 * cells.pitch).max(20.0);
            coverage::check_bounds(&points, &grid, margin, &path.display().to_string())?;
            let c = coverage::measure(&points, &grid, &free, &cells, o.radius, o.tolerance);
            Some((path.clone(), grid, c))
        }
    };
    let count = |k: reports::Outcome| verdicts.iter().filter(|v| v.outcome == k).count();
    let outcomes = Counts {
        scored: count(reports::Outcome::Scored),
        duplicate: count(reports::Outcome::Duplicate),
        wrong_class: count(reports::Outcome::WrongClass),
        false_reports: count(reports::Outcome::False),
    };
    let errors: Vec<f64> = found
        .iter()
        .flatten()
        .filter_map(|&k| verdicts[k].distance_m)
        .collect();
    let mean_error_m =
        (!errors.is_empty()).then(|| errors.iter().sum::<f64>() / errors.len() as f64);
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
    let map_json = map.as_ref().map(|(path, grid, c)| MapJson {
        file: path.display().to_string(),
        points: c.points,
        outside_grid: c.outside,
        errors: c.errors,
        error_share: c.errors as f64 / c.points.max(1) as f64,
        tolerance_m: o.tolerance,
        radius_m: o.radius,
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
        world: o.world.display().to_string(),
        reports_file: o.reports.display().to_string(),
        rule: format!(
            "DARPA: a report scores when an artifact of its class not yet found is within {MATCH_RADIUS} m (the nearest); reports in time order; each artifact once"
        ),
        score: outcomes.scored,
        artifacts_total: truth.len(),
        reports_total: list.len(),
        outcomes,
        mean_error_m,
        artifacts,
        reports: &verdicts,
        map: map_json,
    };
    let mut json = serde_json::to_string_pretty(&doc).context("serializing the score")?;
    json.push('\n');
    let mut reports_csv = String::from("row,time,class,x,y,z,outcome,artifact,distance_m\n");
    for v in &verdicts {
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
    if let Some((_, _, c)) = &map {
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
        .map(|l| {
            picture::level(
                l,
                &cells,
                &truth,
                &found,
                &verdicts,
                map.as_ref().map(|m| &m.2),
            )
        })
        .collect();
    crate::folder::write_atomically(&o.out, o.force, |w| {
        let root = w.root();
        let put = |name: &str, bytes: &[u8]| {
            std::fs::write(root.join(name), bytes).with_context(|| format!("writing {name}"))
        };
        put("score.json", json.as_bytes())?;
        put("reports.csv", reports_csv.as_bytes())?;
        put("artifacts.csv", artifacts_csv.as_bytes())?;
        if !coverage_csv.is_empty() {
            put("coverage.csv", coverage_csv.as_bytes())?;
        }
        for (l, png) in pictures.iter().enumerate() {
            put(&format!("level-{l}.png"), png)?;
        }
        Ok(())
    })?;
    let mut s = format!(
        "score {} of {} artifacts ({} reports: {} scored, {} duplicate, {} wrong class, {} false)",
        doc.score,
        doc.artifacts_total,
        doc.reports_total,
        doc.outcomes.scored,
        doc.outcomes.duplicate,
        doc.outcomes.wrong_class,
        doc.outcomes.false_reports
    );
    if let Some(e) = mean_error_m {
        let _ = write!(s, "; mean error of scored reports {e:.2} m");
    }
    if let Some((_, _, c)) = &map {
        let _ = write!(
            s,
            "\nmap: {} points, coverage {:.1} % of the free space (radius {} m); per level:",
            c.points,
            100.0 * c.total.share(),
            o.radius
        );
        for (l, x) in c.levels.iter().enumerate() {
            let _ = write!(s, " {l}: {:.1} %", 100.0 * x.share());
        }
        let _ = write!(
            s,
            "\nmap error: {} points ({:.2} %) farther than {} m from the surface",
            c.errors,
            100.0 * c.errors as f64 / c.points.max(1) as f64,
            o.tolerance
        );
    }
    let _ = write!(s, "\nwrote {}", o.out.display());
    Ok(s)
}
