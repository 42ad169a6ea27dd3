//! The run folder a mission writes: what `subtgraph score --run` reads, as it reads a team's.
//!
//! | file | what |
//! |---|---|
//! | `run.json` | the options, the world, the radio model and its source, per-robot totals |
//! | `robot-N.tum` | robot N's trajectory, `t x y z qx qy qz qw` per control step (its reference point: on the floor under a ground robot, the body's centre for an aerial one) |
//! | `map.ply` | the robots' merged map: every occupied voxel's centre (binary PLY, float32 x y z) |
//! | `explored.npy` | with a ground-truth grid: each of its voxels whose centre the map knows free, bits packed along x as `ground_truth/free_space.npy` |
//! | `reports.csv` | the reports the base station received, `time` the arrival: `time,class,x,y,z,robot,detected` |
//! | `detections.csv` | every report made, delivered or not: `time,robot,class,x,y,z,delivered` |
//! | `radio.csv` | every link up at each radio instant (with a robot at an end; links between fixed nodes when made): `time,a,b,ax,ay,az,bx,by,bz,distance_m,power_dbm` |
//! | `connectivity.csv` | each robot's hops to the base station at each radio instant (empty: no link) |
//! | `breadcrumbs.csv` | `time,robot,crumb,x,y,z` of each breadcrumb's antenna |
//!
//! Numbers are written with fixed decimals in a fixed order: the same run gives the same bytes.

use std::fmt::Write as _;
use std::path::Path;

use serde_json::json;
use subtgraph_sensors::frames::{quaternion, rotation_zyx};

use crate::error::ExploreError;
use crate::map::{Grid, Voxel, VoxelMap};
use crate::mission::Mission;
use crate::radio::Link;

/// What the radio model is, in the run's words.
pub const RADIO_SOURCE: &str = "the DARPA SubT virtual competition's communication model (osrf/subt, subt-communication: VisibilityRFModel's log-normal path loss, its QPSK packet model, the competition's comms_model numbers), with exact line of sight between antennas for the visibility cost (no link out of sight) and a link up when its mean power delivers a 1000-byte packet half the time";

/// What was written.
#[derive(Clone, Debug, PartialEq)]
pub struct Written {
    /// Files, `(name, bytes)`.
    pub files: Vec<(String, u64)>,
    /// Distinct artifacts some robot detected.
    pub detected: usize,
    /// Distinct artifacts whose report reached the base station.
    pub delivered: usize,
    /// Points in `map.ply`.
    pub map_points: usize,
    /// Free voxels of the robots' merged map.
    pub free_voxels: u64,
}

fn write(
    dir: &Path,
    name: &str,
    bytes: &[u8],
    files: &mut Vec<(String, u64)>,
) -> Result<(), ExploreError> {
    let path = dir.join(name);
    std::fs::write(&path, bytes).map_err(|source| ExploreError::Io {
        what: "writing",
        path,
        source,
    })?;
    files.push((name.to_owned(), bytes.len() as u64));
    Ok(())
}

/// Writes the run folder of a finished mission into `dir` (which exists); `about` is the world
/// as the caller names it (its folder, its seed), `truth` the world's ground-truth grid for
/// `explored.npy`.
pub fn write_run(
    dir: &Path,
    m: &Mission,
    about: serde_json::Value,
    truth: Option<&Grid>,
) -> Result<Written, ExploreError> {
    let mut files = Vec::new();
    for r in &m.robots {
        write(
            dir,
            &format!("robot-{}.tum", r.id),
            tum(r).as_bytes(),
            &mut files,
        )?;
    }
    let map = m.union_map();
    let occupied = map.voxels(Voxel::Occupied);
    write(dir, "map.ply", &ply(&map, &occupied), &mut files)?;
    if let Some(g) = truth {
        write(dir, "explored.npy", &explored(&map, g), &mut files)?;
    }
    let (reports, detections, delivered) = reports(m);
    write(dir, "reports.csv", reports.as_bytes(), &mut files)?;
    write(dir, "detections.csv", detections.as_bytes(), &mut files)?;
    write(dir, "radio.csv", radio(m).as_bytes(), &mut files)?;
    write(
        dir,
        "connectivity.csv",
        connectivity(m).as_bytes(),
        &mut files,
    )?;
    write(dir, "breadcrumbs.csv", crumbs(m).as_bytes(), &mut files)?;
    let detected = (0..m.site.artifacts.len())
        .filter(|&i| m.robots.iter().any(|r| r.detected[i]))
        .count();
    let summary = summary(m, about, detected, delivered, occupied.len(), map.free);
    let text = serde_json::to_string_pretty(&summary).expect("plain data") + "\n";
    write(dir, "run.json", text.as_bytes(), &mut files)?;
    Ok(Written {
        files,
        detected,
        delivered,
        map_points: occupied.len(),
        free_voxels: map.free,
    })
}

fn tum(r: &crate::robot::Robot) -> String {
    let mut s = String::with_capacity(r.trajectory.len() * 80);
    for p in &r.trajectory {
        let q = quaternion(&rotation_zyx(p.ypr));
        let _ = writeln!(
            s,
            "{:.3} {:.4} {:.4} {:.4} {:.6} {:.6} {:.6} {:.6}",
            p.time, p.position[0], p.position[1], p.position[2], q[0], q[1], q[2], q[3]
        );
    }
    s
}

fn ply(map: &VoxelMap, voxels: &[[i32; 3]]) -> Vec<u8> {
    let header = format!(
        "ply\nformat binary_little_endian 1.0\ncomment subtgraph explore: occupied voxel centres of the robots' merged map, voxel {} m, world frame\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nend_header\n",
        map.grid.voxel,
        voxels.len()
    );
    let mut out = header.into_bytes();
    out.reserve(voxels.len() * 12);
    for &v in voxels {
        for c in map.grid.centre(v) {
            out.extend_from_slice(&(c as f32).to_le_bytes());
        }
    }
    out
}

/// The voxels of `truth` whose centres the map knows free, packed along x (most significant
/// bit first), `[nz, ny, ceil(nx / 8)]` as `free_space.npy`.
fn explored(map: &VoxelMap, truth: &Grid) -> Vec<u8> {
    let [nx, ny, nz] = truth.n;
    let row = nx.div_ceil(8);
    let mut bits = vec![0u8; row * ny * nz];
    let g = map.grid;
    // The truth voxels whose centres lie in [lo, hi) along an axis.
    let range = |k: usize, lo: f64, hi: f64| -> (usize, usize) {
        let first = ((lo - truth.origin[k]) / truth.voxel - 0.5).ceil().max(0.0) as usize;
        let end = ((hi - truth.origin[k]) / truth.voxel - 0.5).ceil().max(0.0) as usize;
        (first.min(truth.n[k]), end.min(truth.n[k]))
    };
    for v in map.voxels(Voxel::Free) {
        let lo = [0, 1, 2].map(|k| g.origin[k] + f64::from(v[k]) * g.voxel);
        let (x0, x1) = range(0, lo[0], lo[0] + g.voxel);
        let (y0, y1) = range(1, lo[1], lo[1] + g.voxel);
        let (z0, z1) = range(2, lo[2], lo[2] + g.voxel);
        for z in z0..z1 {
            for y in y0..y1 {
                for x in x0..x1 {
                    bits[(z * ny + y) * row + x / 8] |= 0x80 >> (x % 8);
                }
            }
        }
    }
    subtgraph_core::npy::encode_u8(&[nz, ny, row], &bits)
}

/// `reports.csv` (delivered, by arrival), `detections.csv` (all), and how many distinct
/// artifacts were delivered.
fn reports(m: &Mission) -> (String, String, usize) {
    let mut all: Vec<&crate::detect::Report> = m.robots.iter().flat_map(|r| &r.reports).collect();
    all.sort_by(|a, b| {
        a.detected
            .total_cmp(&b.detected)
            .then(a.robot.cmp(&b.robot))
            .then(a.artifact.cmp(&b.artifact))
    });
    let mut detections = String::from("time,robot,class,x,y,z,delivered\n");
    for r in &all {
        let _ = writeln!(
            detections,
            "{:.3},{},{},{:.3},{:.3},{:.3},{}",
            r.detected,
            r.robot,
            r.class.name(),
            r.position[0],
            r.position[1],
            r.position[2],
            r.delivered.map_or(String::new(), |t| format!("{t:.3}"))
        );
    }
    let mut delivered: Vec<&&crate::detect::Report> =
        all.iter().filter(|r| r.delivered.is_some()).collect();
    delivered.sort_by(|a, b| {
        a.delivered
            .unwrap_or(0.0)
            .total_cmp(&b.delivered.unwrap_or(0.0))
            .then(a.robot.cmp(&b.robot))
            .then(a.detected.total_cmp(&b.detected))
            .then(a.artifact.cmp(&b.artifact))
    });
    let mut csv = String::from("time,class,x,y,z,robot,detected\n");
    for r in &delivered {
        let _ = writeln!(
            csv,
            "{:.3},{},{:.3},{:.3},{:.3},{},{:.3}",
            r.delivered.unwrap_or(0.0),
            r.class.name(),
            r.position[0],
            r.position[1],
            r.position[2],
            r.robot,
            r.detected
        );
    }
    let mut ids: Vec<usize> = delivered.iter().map(|r| r.artifact).collect();
    ids.sort_unstable();
    ids.dedup();
    (csv, detections, ids.len())
}

fn link_row(s: &mut String, t: f64, l: &Link) {
    let d =
        ((l.pa[0] - l.pb[0]).powi(2) + (l.pa[1] - l.pb[1]).powi(2) + (l.pa[2] - l.pb[2]).powi(2))
            .sqrt();
    let _ = writeln!(
        s,
        "{:.3},{},{},{:.3},{:.3},{:.3},{:.3},{:.3},{:.3},{:.3},{:.2}",
        t,
        l.a.name(),
        l.b.name(),
        l.pa[0],
        l.pa[1],
        l.pa[2],
        l.pb[0],
        l.pb[1],
        l.pb[2],
        d,
        l.power_dbm
    );
}

fn radio(m: &Mission) -> String {
    let mut s = String::from("time,a,b,ax,ay,az,bx,by,bz,distance_m,power_dbm\n");
    for r in &m.links {
        link_row(&mut s, r.time, &r.link);
    }
    s
}

fn connectivity(m: &Mission) -> String {
    let mut s = String::from("time,robot,hops\n");
    for (t, hops) in &m.connectivity {
        for (i, h) in hops.iter().enumerate() {
            let _ = writeln!(
                s,
                "{t:.3},{i},{}",
                h.map_or(String::new(), |h| h.to_string())
            );
        }
    }
    s
}

fn crumbs(m: &Mission) -> String {
    let mut s = String::from("time,robot,crumb,x,y,z\n");
    for (k, c) in m.crumbs.iter().enumerate() {
        let _ = writeln!(
            s,
            "{:.3},{},{},{:.3},{:.3},{:.3}",
            c.time, c.robot, k, c.position[0], c.position[1], c.position[2]
        );
    }
    s
}

fn summary(
    m: &Mission,
    about: serde_json::Value,
    detected: usize,
    delivered: usize,
    map_points: usize,
    free_voxels: u64,
) -> serde_json::Value {
    let o = &m.options;
    let robots: Vec<serde_json::Value> = m
        .robots
        .iter()
        .map(|r| {
            json!({
                "robot": r.id,
                "distance_m": round(r.odometer, 3),
                "rays": r.rays,
                "refused": {
                    "collision": r.refusals[0],
                    "step": r.refusals[1],
                    "gap": r.refusals[2],
                    "slope": r.refusals[3],
                },
                "reports": r.reports.len(),
                "delivered": r.reports.iter().filter(|p| p.delivered.is_some()).count(),
                "breadcrumbs_dropped": m.crumbs.iter().filter(|c| c.robot == r.id).count(),
                "mode_at_end": r.planner.mode,
            })
        })
        .collect();
    let connected: usize = m
        .connectivity
        .iter()
        .map(|(_, h)| h.iter().filter(|h| h.is_some()).count())
        .sum();
    let instants: usize = m.connectivity.iter().map(|(_, h)| h.len()).sum();
    json!({
        "format": "subtgraph-run/1",
        "world": about,
        "policy": o.policy,
        "robots": o.robots,
        "platform": {
            "name": o.body.name,
            "max_speed_mps": o.body.max_speed,
            "max_acceleration_mps2": o.body.max_acceleration,
            "max_yaw_rate_rps": o.body.max_yaw_rate,
            "clearance_m": o.body.clearance,
            "clearance_height_m": o.body.clearance_height,
            "max_step_m": o.body.max_step,
            "max_grade_deg": o.body.max_grade_deg,
            "on_collision": "refuse the motion (stop where the last free piece ended)",
        },
        "lidar": {
            "model": o.lidar.model.name,
            "rings": o.lidar.rings,
            "columns": o.lidar.columns,
            "rays_per_scan": o.lidar.rays(),
            "rate_hz": o.lidar.model.rate_hz,
            "range_m": o.lidar.model.range_m,
            "noiseless": o.noiseless,
        },
        "duration_s": o.duration,
        "control_hz": o.control_hz,
        "map_voxel_m": m.robots[0].map.grid.voxel,
        "seed": o.seed,
        "radio": {
            "source": RADIO_SOURCE,
            "model": o.radio,
            "reach_in_sight_m": round(o.radio.reach_m(), 2),
            "period_s": crate::mission::RADIO_PERIOD,
            "breadcrumbs_per_robot": o.breadcrumbs,
            "breadcrumbs_dropped": m.crumbs.len(),
            "connected_share": if instants > 0 { round(connected as f64 / instants as f64, 6) } else { 0.0 },
        },
        "detector": o.detector,
        "artifacts": {
            "in_world": m.site.artifacts.len(),
            "detected": detected,
            "delivered": delivered,
        },
        "map": {
            "points": map_points,
            "free_voxels": free_voxels,
        },
        "per_robot": robots,
    })
}

fn round(v: f64, digits: i32) -> f64 {
    let s = 10f64.powi(digits);
    (v * s).round() / s
}
