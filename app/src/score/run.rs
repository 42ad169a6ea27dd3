//! `score WORLD --run RUN`: a run folder (what `subtgraph explore` writes, or a team's in the
//! same layout) graded as DARPA graded the SubT teams: an artifact report counts only when it
//! reached the base station over a radio link.
//!
//! Read from the run folder:
//! - `reports.csv` (`time,class,x,y,z,robot`): the reports the base station received, `time`
//!   their arrival. A report counts only when `connectivity.csv` says its robot had a link to
//!   the base station at that instant (`time,robot,hops`, hops empty without one); the others
//!   are left out of the DARPA matching and counted as `reports_without_link`.
//! - `map.ply` (or `map.pcd`): the map, scored as `--map` is (coverage within `--radius` of its
//!   points, map error against the surface).
//! - `explored.npy` (optional): the voxels of the world's free-space grid the robots knew free,
//!   packed as `ground_truth/free_space.npy`: the share of the free space explored, per level.
//! - `radio.csv`, `breadcrumbs.csv` (optional): links up and breadcrumbs dropped, counted.
//!
//! Written beside `score.json`: `run.json` with the explored share, the radio's numbers and
//! the reports left out.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::coverage::{self, Bits, Share};
use super::reports::Report;
use super::world::Cells;
use crate::Error;

/// The files of a run folder.
#[derive(Clone, Debug)]
pub struct RunFiles {
    /// The folder.
    pub dir: PathBuf,
    /// `reports.csv`.
    pub reports: PathBuf,
    /// `map.ply` or `map.pcd`, if there.
    pub map: Option<PathBuf>,
}

/// Finds a run folder's files, or says what it lacks.
pub fn locate(dir: &Path) -> Result<RunFiles, Error> {
    if !dir.is_dir() {
        return Err(Error::Input(format!(
            "{}: no such run folder; pass the folder `subtgraph explore --out` wrote",
            dir.display()
        )));
    }
    for need in ["reports.csv", "connectivity.csv"] {
        if !dir.join(need).is_file() {
            return Err(Error::Input(format!(
                "{}: a run folder needs {need} (reports as the base station received them, and each robot's link to it at each radio instant, as `subtgraph explore` writes them)",
                dir.display()
            )));
        }
    }
    let map = ["map.ply", "map.pcd"]
        .iter()
        .map(|m| dir.join(m))
        .find(|p| p.is_file());
    Ok(RunFiles {
        dir: dir.to_owned(),
        reports: dir.join("reports.csv"),
        map,
    })
}

/// A CSV row: its line number and its cells by column name.
type Row = (usize, BTreeMap<String, String>);

/// Rows of a CSV file with a header.
fn csv_rows(path: &Path) -> Result<Vec<Row>, Error> {
    let bytes = crate::input::read(path)?;
    let text = std::str::from_utf8(&bytes)
        .map_err(|_| Error::Input(format!("{}: not UTF-8 text", path.display())))?;
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let Some((_, header)) = lines.next() else {
        return Ok(Vec::new());
    };
    let names: Vec<String> = header
        .split(',')
        .map(|s| s.trim().to_ascii_lowercase())
        .collect();
    Ok(lines
        .map(|(i, l)| {
            let cells = names
                .iter()
                .cloned()
                .zip(l.split(',').map(|s| s.trim().to_owned()))
                .collect();
            (i + 1, cells)
        })
        .collect())
}

/// Time in milliseconds, the radio log's key.
fn ms(t: f64) -> i64 {
    (t * 1000.0).round() as i64
}

/// The reports that came over a link, and how many did not.
pub fn over_link(files: &RunFiles, list: Vec<Report>) -> Result<(Vec<Report>, usize), Error> {
    let conn = files.dir.join("connectivity.csv");
    let mut linked: BTreeMap<(i64, String), bool> = BTreeMap::new();
    for (line, row) in csv_rows(&conn)? {
        let (Some(t), Some(robot), Some(hops)) =
            (row.get("time"), row.get("robot"), row.get("hops"))
        else {
            return Err(Error::Input(format!(
                "{}: line {line}: needs time, robot and hops",
                conn.display()
            )));
        };
        let t: f64 = t.parse().map_err(|_| {
            Error::Input(format!(
                "{}: line {line}: time '{t}' is not a number",
                conn.display()
            ))
        })?;
        linked.insert((ms(t), robot.clone()), !hops.is_empty());
    }
    let robots: BTreeMap<usize, String> = csv_rows(&files.reports)?
        .into_iter()
        .filter_map(|(line, row)| row.get("robot").map(|r| (line, r.clone())))
        .collect();
    let mut kept = Vec::new();
    let mut without = 0;
    for r in list {
        let ok = robots
            .get(&r.row)
            .and_then(|robot| linked.get(&(ms(r.time), robot.clone())))
            .copied()
            .unwrap_or(false);
        if ok {
            kept.push(r);
        } else {
            without += 1;
        }
    }
    Ok((kept, without))
}

/// The explored share of the free space.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Explored {
    /// Free voxels of the world.
    pub free_voxels: u64,
    /// Of them, known free by the robots.
    pub explored_voxels: u64,
    /// The share.
    pub coverage: f64,
    /// The same per level.
    pub levels: Vec<f64>,
}

/// The radio's numbers.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Radio {
    /// Robot-instants in the log.
    pub robot_instants: usize,
    /// Share of them with a link to the base station.
    pub connected_share: f64,
    /// Rows of `radio.csv` (links up).
    pub links_logged: usize,
    /// Breadcrumbs dropped.
    pub breadcrumbs: usize,
}

/// What `--run` adds to a score.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RunScore {
    /// `subtgraph-run-score/1`.
    pub format: &'static str,
    /// The run folder.
    pub run: String,
    /// Reports the base station logged without a link at their time: not counted.
    pub reports_without_link: usize,
    /// The explored share, with `explored.npy`.
    pub explored: Option<Explored>,
    /// The radio.
    pub radio: Radio,
}

/// The radio's numbers and the explored share of a run folder.
pub fn measure(
    files: &RunFiles,
    without: usize,
    free: Option<(&super::cloud::Grid, &Bits)>,
    cells: &Cells,
) -> Result<RunScore, Error> {
    let conn = csv_rows(&files.dir.join("connectivity.csv"))?;
    let linked = conn
        .iter()
        .filter(|(_, r)| r.get("hops").is_some_and(|h| !h.is_empty()))
        .count();
    let count = |name: &str| -> Result<usize, Error> {
        let p = files.dir.join(name);
        Ok(if p.is_file() { csv_rows(&p)?.len() } else { 0 })
    };
    let radio = Radio {
        robot_instants: conn.len(),
        connected_share: if conn.is_empty() {
            0.0
        } else {
            linked as f64 / conn.len() as f64
        },
        links_logged: count("radio.csv")?,
        breadcrumbs: count("breadcrumbs.csv")?,
    };
    let explored_file = files.dir.join("explored.npy");
    let explored = match free {
        Some((grid, free)) if explored_file.is_file() => {
            Some(explored(&explored_file, grid, free, cells)?)
        }
        _ => None,
    };
    Ok(RunScore {
        format: "subtgraph-run-score/1",
        run: files.dir.display().to_string(),
        reports_without_link: without,
        explored,
        radio,
    })
}

/// The share of the free voxels `explored.npy` marks, overall and per level.
fn explored(
    path: &Path,
    grid: &super::cloud::Grid,
    free: &Bits,
    cells: &Cells,
) -> Result<Explored, Error> {
    let bytes = crate::input::read(path)?;
    let info = subtgraph_core::npy::info(&bytes).map_err(|source| Error::Npy {
        file: path.display().to_string(),
        source,
    })?;
    let [nx, ny, nz] = grid.n;
    let packed = [nz, ny, nx.div_ceil(8)];
    if info.shape != packed || info.size != 1 || info.fortran {
        return Err(Error::Input(format!(
            "{}: an array of shape {:?}, but the world's free-space grid packs to {packed:?} bytes (uint8, bits along x as ground_truth/free_space.npy)",
            path.display(),
            info.shape
        )));
    }
    let data = &bytes[info.data_start..info.data_start + info.count];
    let mut seen = Bits::from_packed(grid.n, data);
    for (s, f) in seen.data.iter_mut().zip(&free.data) {
        *s &= *f;
    }
    // Per level through the coverage's own bookkeeping: the explored voxels' centres as a
    // map scored with radius 0 (each covers its own voxel).
    let mut points = Vec::new();
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                if seen.get([x, y, z]) {
                    points.push([x, y, z].map(|_| 0.0f32));
                    let p = points.last_mut().expect("pushed");
                    for (k, i) in [x, y, z].into_iter().enumerate() {
                        p[k] = (grid.origin[k] + (i as f64 + 0.5) * grid.voxel) as f32;
                    }
                }
            }
        }
    }
    let c = coverage::measure(&points, grid, free, cells, 0.0, 0.0);
    let share = |s: &Share| s.share();
    Ok(Explored {
        free_voxels: c.total.free,
        explored_voxels: c.total.covered,
        coverage: share(&c.total),
        levels: c.levels.iter().map(share).collect(),
    })
}

/// The run's lines of the score's summary.
pub fn summary(r: &RunScore) -> String {
    let mut s = format!(
        "run: {} report(s) without a link left out; radio: linked {:.1} % of robot-seconds, {} breadcrumb(s)",
        r.reports_without_link,
        100.0 * r.radio.connected_share,
        r.radio.breadcrumbs
    );
    if let Some(e) = &r.explored {
        s.push_str(&format!(
            "\nexplored: {:.1} % of the free space ({} of {} voxels)",
            100.0 * e.coverage,
            e.explored_voxels,
            e.free_voxels
        ));
    }
    s
}
