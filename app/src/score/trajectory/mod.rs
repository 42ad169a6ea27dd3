//! `subtgraph score WORLD_OR_SEQUENCE --trajectory EST --out DIR`: grades an estimated
//! trajectory (a SLAM or odometry run) against a ground-truth one, with the numbers evo gives
//! on the same files and options.
//!
//! - Reading (`read.rs`, `bag.rs`): TUM or KITTI files or a ROS 2 bag's pose topic, every
//!   row or message checked.
//! - Association and alignment (`align.rs`): nearest in time within `--max-diff`, or the
//!   reference interpolated at the estimate's times (`--associate interpolate`); Umeyama
//!   SE(3) or Sim(3), or origin alignment.
//! - Scores (`metrics.rs`): APE, RPE over frames and over 10 m and 100 m of travel, final
//!   drift, HILTI-style points, a failure flag.
//! - With a world folder (`graph.rs`): the run cut into stretches per graph node and edge,
//!   with the APE increase of each; a picture per level (`levels.rs`).
//! - Output (`files.rs`): `trajectory.json`, `errors.csv`, `trajectory.png` (and `graph.csv`)
//!   in a score folder written atomically, like every folder the tool writes.

mod align;
pub mod bag;
mod files;
pub mod graph;
mod levels;
mod lines;
mod metrics;
pub mod pose;
pub mod read;

use std::fmt;
use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::Error;
use crate::folder::{Kind, Out};

pub use align::Alignment;
pub use metrics::{Failure, POINTS, Stats};
pub use read::{SEQUENCE_GROUND_TRUTH, UNIT_TOLERANCE};

/// How the estimate is put in the reference's frame before it is scored.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Align {
    /// None beyond the start: the estimate's first associated pose is put on the
    /// reference's (evo's `--align_origin`), as LiDAR odometry is judged.
    None,
    /// Umeyama's least-squares rigid transform (evo's `--align`, `-a`).
    Se3,
    /// Umeyama's least-squares similarity, with scale (evo's `--align --correct_scale`,
    /// `-as`), for monocular methods.
    Sim3,
}

impl Align {
    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Align::None => "none",
            Align::Se3 => "se3",
            Align::Sim3 => "sim3",
        }
    }

    /// The `evo_ape`/`evo_rpe` option that does the same.
    pub fn evo_option(self) -> &'static str {
        match self {
            Align::None => "--align_origin",
            Align::Se3 => "--align",
            Align::Sim3 => "--align --correct_scale",
        }
    }
}

/// How estimate poses are paired with reference poses.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Associate {
    /// The nearest reference pose within `--max-diff` (evo's association).
    Nearest,
    /// The reference interpolated at the estimate's time, between reference poses at most
    /// `--max-gap` apart.
    Interpolate,
}

impl Associate {
    /// Its name on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Associate::Nearest => "nearest",
            Associate::Interpolate => "interpolate",
        }
    }
}

/// The travelled distances RPE is also measured over, metres (as KITTI's odometry benchmark
/// reports drift per distance).
pub const SEGMENTS_M: [f64; 2] = [10.0, 100.0];

/// What `score --trajectory` is asked.
#[derive(Clone, Debug)]
pub struct TrajectoryRequest {
    /// The world or sensor sequence folder, or the reference trajectory file itself.
    pub world_or_sequence: PathBuf,
    /// The estimated trajectory (TUM, KITTI, or a ROS 2 bag in MCAP storage).
    pub estimate: PathBuf,
    /// The estimate's topic, when it is a bag with more than one pose topic.
    pub topic: Option<String>,
    /// The estimate's times file, when it is KITTI (else `times.txt` beside it).
    pub times: Option<PathBuf>,
    /// The ground-truth trajectory, when the positional argument is not one (or a sequence).
    pub reference: Option<PathBuf>,
    /// The reference's times file, when it is KITTI.
    pub reference_times: Option<PathBuf>,
    /// The reference's topic, when it is a bag with more than one pose topic.
    pub reference_topic: Option<String>,
    /// How poses are paired.
    pub associate: Associate,
    /// Poses further apart in time are not associated, seconds (evo's `--t_max_diff`;
    /// nearest association).
    pub max_diff: f64,
    /// Reference poses further apart than this are not interpolated between, seconds
    /// (interpolated association).
    pub max_gap: f64,
    /// The alignment.
    pub align: Align,
    /// RPE's pose distance in frames (evo's `--delta N --delta_unit f`).
    pub delta: usize,
    /// An APE above this is a divergence: the run failed, metres.
    pub fail_ape: f64,
    /// A step this much longer than the reference's is a jump: the run failed, metres.
    pub fail_jump: f64,
    /// The output folder.
    pub out: PathBuf,
    /// Replace a score folder the tool wrote.
    pub force: bool,
}

/// RPE over pairs of poses.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Rpe {
    /// The pose distance: frames, or metres travelled on the reference.
    pub delta: f64,
    /// `"frames"` or `"m"`.
    pub unit: &'static str,
    /// Statistics of the translation errors, metres (`None` when no pair is that long).
    pub translation_m: Option<Stats>,
    /// Statistics of the rotation errors, degrees.
    pub rotation_deg: Option<Stats>,
    /// For metres: the mean translation error as a percentage of the distance (KITTI's
    /// translation error).
    pub translation_percent: Option<f64>,
    /// For metres: the mean rotation error per 100 m, degrees (KITTI's rotation error, in
    /// its usual unit).
    pub rotation_deg_per_100m: Option<f64>,
}

/// What a trajectory scored; [`fmt::Display`] writes the summary the command line prints.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TrajectoryScore {
    /// Poses of the estimate, of the reference, and associated pairs.
    pub poses: [usize; 3],
    /// The transform applied to the estimate.
    pub alignment: Alignment,
    /// APE statistics, metres.
    pub ape_m: Stats,
    /// RPE over `--delta` frames.
    pub rpe: Rpe,
    /// RPE over [`SEGMENTS_M`] of travel.
    pub segments: Vec<Rpe>,
    /// The reference's path over the associated poses, metres.
    pub path_length_m: f64,
    /// The last associated pose's APE, metres.
    pub final_drift_m: f64,
    /// The same as a percentage of `path_length_m`.
    pub final_drift_percent: f64,
    /// Mean points per associated pose, 0 to 10.
    pub points_mean: f64,
    /// Points of the last associated pose.
    pub points_final: u32,
    /// The first divergence or jump, if any.
    pub failure: Option<Failure>,
    /// With a world folder: the stretch of the run on one graph node or edge where the APE
    /// grew most (all of them in `graph.csv`).
    #[serde(skip)]
    pub worst_stretch: Option<graph::Stretch>,
    /// The score folder written.
    #[serde(skip)]
    pub out: PathBuf,
}

impl fmt::Display for TrajectoryScore {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [e, r, n] = self.poses;
        let a = &self.ape_m;
        writeln!(
            f,
            "trajectory: {n} pose pairs ({e} estimated, {r} reference); APE RMSE {:.4} m, mean {:.4} m, max {:.4} m",
            a.rmse, a.mean, a.max
        )?;
        if let Some(t) = &self.rpe.translation_m {
            writeln!(
                f,
                "RPE over {} frame(s): RMSE {:.4} m",
                self.rpe.delta, t.rmse
            )?;
        }
        for s in &self.segments {
            if let (Some(p), Some(d)) = (s.translation_percent, s.rotation_deg_per_100m) {
                writeln!(f, "RPE over {} m: {p:.3} %, {d:.3} deg/100 m", s.delta)?;
            }
        }
        writeln!(
            f,
            "final drift {:.4} m, {:.3} % of {:.1} m travelled; points {:.2} per pose (final {})",
            self.final_drift_m,
            self.final_drift_percent,
            self.path_length_m,
            self.points_mean,
            self.points_final
        )?;
        if let Some(w) = &self.worst_stretch {
            let id = w.id.map_or(String::new(), |i| format!(" {i}"));
            let level = w.level.map_or(String::new(), |l| format!(", level {l}"));
            writeln!(
                f,
                "largest APE increase: {}{id} ({}{level}), {:+.3} m between t = {} and {} s",
                w.region, w.kind, w.ape_increase_m, w.time_s[0], w.time_s[1]
            )?;
        }
        match &self.failure {
            None => writeln!(f, "no failure")?,
            Some(x) => writeln!(
                f,
                "FAILED: {} at pose {} (t = {} s, {:.3} m)",
                x.kind, x.pose, x.time, x.value_m
            )?,
        }
        write!(f, "wrote {}", self.out.display())
    }
}

impl TrajectoryRequest {
    fn reference_file(&self) -> Result<PathBuf, Error> {
        if let Some(r) = &self.reference {
            return Ok(r.clone());
        }
        read::reference_in(&self.world_or_sequence).ok_or_else(|| {
            Error::Usage(format!(
                "{} is neither a trajectory file, a ROS 2 bag nor a sensor sequence folder (one with {SEQUENCE_GROUND_TRUTH}): give the ground truth with --reference FILE",
                self.world_or_sequence.display()
            ))
        })
    }

    /// Scores the trajectory and writes the score folder (`--out` checked before anything
    /// is read).
    pub fn run(&self) -> Result<TrajectoryScore, Error> {
        for (what, v) in [
            ("--max-diff", self.max_diff),
            ("--max-gap", self.max_gap),
            ("--fail-ape", self.fail_ape),
            ("--fail-jump", self.fail_jump),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::Usage(format!(
                    "{what} must be a number, 0 or more (seconds for --max-diff and --max-gap, metres for the others)"
                )));
            }
        }
        if self.delta == 0 {
            return Err(Error::Usage("--delta must be 1 or more frames".to_owned()));
        }
        let reference_file = self.reference_file()?;
        let mut reading: Vec<&Path> =
            vec![&self.world_or_sequence, &self.estimate, &reference_file];
        reading.extend(self.times.as_deref());
        reading.extend(self.reference_times.as_deref());
        let out = Out {
            path: &self.out,
            kind: Kind::Score,
            force: self.force,
            reading: &reading,
        };
        out.check()?;
        let reference = read::read_any(
            &reference_file,
            self.reference_times.as_deref(),
            self.reference_topic.as_deref(),
        )?;
        let estimate =
            read::read_any(&self.estimate, self.times.as_deref(), self.topic.as_deref())?;
        let world = self.world_or_sequence.join("topology.json").is_file();
        let cells = match world {
            true => Some(crate::score::world::cells(&self.world_or_sequence)?),
            false => None,
        };
        let scored = score(self, &reference, &estimate, cells.as_ref())?;
        let mut files = files::files(self, &reference, &estimate, &scored);
        if let Some(cells) = &cells {
            for (level, png) in levels::pictures(cells, &scored) {
                files
                    .list
                    .push((format!("trajectory-level-{level}.png"), png));
            }
        }
        crate::folder::write_atomically(&out, |w| {
            for (name, bytes) in &files.list {
                std::fs::write(w.root().join(name), bytes)
                    .map_err(Error::io(format!("writing {name}")))?;
            }
            Ok::<(), Error>(())
        })?;
        Ok(scored.summary)
    }
}

/// Powers of ten a unit slip makes, with their likely cause.
const SLIPS: [(f64, &str); 6] = [
    (1e3, "millimetres where metres are expected"),
    (1e2, "centimetres where metres are expected"),
    (1e-3, "kilometres where metres are expected"),
    (1e9, "nanoseconds where seconds are expected"),
    (1e6, "microseconds where seconds are expected"),
    (1e-9, "seconds where nanoseconds are expected"),
];

/// The power-of-ten slip `ratio` is nearest to (within a factor of 3), if any.
fn slip(ratio: f64) -> Option<(f64, &'static str)> {
    SLIPS
        .into_iter()
        .find(|&(k, _)| ratio.is_finite() && ratio > 0.0 && (ratio / k).ln().abs() < 3f64.ln())
}

/// What to say when too few poses pair: the times' units, if they differ by a power of ten.
fn clock_guess(reference: &read::Trajectory, estimate: &read::Trajectory) -> String {
    let mid = |t: &read::Trajectory| 0.5 * (t.times[0] + t.times[t.times.len() - 1]);
    let (a, b) = (mid(estimate), mid(reference));
    let seconds = [(a / b, "the estimate's"), (b / a, "the reference's")];
    for (ratio, whose) in seconds {
        if let Some((k, what)) = slip(ratio).filter(|(k, _)| *k >= 1e6) {
            return format!(
                "{whose} times are about {k:e} times the other's: {what}? Give both in seconds on the same clock"
            );
        }
    }
    "are both in seconds on the same clock? (widen --max-diff or --max-gap for sparser poses)"
        .to_owned()
}

/// Refuses an estimate whose path is a power of ten longer or shorter than the reference's
/// (over the pairs): a unit slip, not drift, which no method makes. Sim(3) alignment, which
/// fits a scale, is not checked.
fn unit_guess(
    refs: &[pose::Pose],
    ests: &[pose::Pose],
    reference: &read::Trajectory,
    estimate: &read::Trajectory,
) -> Result<(), Error> {
    let (a, b) = (metrics::path_length(ests), metrics::path_length(refs));
    if b < 1.0 || a < 1e-9 {
        return Ok(());
    }
    let ratio = a / b;
    if let Some((k, what)) = slip(ratio).filter(|(k, _)| *k <= 1e3) {
        return Err(Error::Input(format!(
            "{}: its path over the paired poses is {a:.3} m, {ratio:.4} times the {b:.3} m of {} (about {k:e}): {what}? Give both in metres, or score with --align sim3 when the estimate's scale is unknown (monocular methods)",
            estimate.file.display(),
            reference.file.display()
        )));
    }
    Ok(())
}

/// Refuses a reference that is not in the world folder's frame: most of its poses more than a
/// tile outside the world's grid (another origin, or another unit).
fn frame_guess(
    cells: &crate::score::world::Cells,
    refs: &[pose::Pose],
    reference: &read::Trajectory,
) -> Result<(), Error> {
    let [x0, y0, x1, y1] = cells.extent();
    let m = cells.pitch;
    let top = cells.levels as f64 * cells.level_height;
    let outside = refs
        .iter()
        .filter(|p| {
            let [x, y, z] = p.t;
            x < x0 - m || x > x1 + m || y < y0 - m || y > y1 + m || z < -m || z > top + m
        })
        .count();
    if 2 * outside > refs.len() {
        let p = refs[0].t;
        return Err(Error::Input(format!(
            "{}: {outside} of its {} paired poses lie more than a tile ({m} m) outside the world (x {x0:.1} to {x1:.1}, y {y0:.1} to {y1:.1}, z 0 to {top:.1} m; the first at ({:.1}, {:.1}, {:.1})): the reference must be in the world frame in metres (x east, y north, z up, as topology.json), not in millimetres or the robot's odometry frame",
            reference.file.display(),
            refs.len(),
            p[0],
            p[1],
            p[2]
        )));
    }
    Ok(())
}

/// Everything computed, per pose and in summary.
pub(crate) struct Scored {
    /// The time of each associated pair (the reference's, or the estimate's when
    /// interpolated).
    times: Vec<f64>,
    /// The reference pose of each pair (interpolated, or as read).
    refs: Vec<pose::Pose>,
    /// The estimate's index of each pair.
    estimate_index: Vec<usize>,
    /// The estimate's associated poses, aligned.
    aligned: Vec<pose::Pose>,
    /// APE per associated pose.
    ape: Vec<f64>,
    /// RPE `(translation, rotation degrees)` of the pair ending at each associated pose.
    rpe_at: Vec<Option<(f64, f64)>>,
    /// With a world folder: the run's stretches on its graph.
    stretches: Option<Vec<graph::Stretch>>,
    summary: TrajectoryScore,
}

fn score(
    r: &TrajectoryRequest,
    reference: &read::Trajectory,
    estimate: &read::Trajectory,
    cells: Option<&crate::score::world::Cells>,
) -> Result<Scored, Error> {
    let (times, refs, estimate_index): (Vec<f64>, Vec<pose::Pose>, Vec<usize>) = match r.associate {
        Associate::Nearest => align::associate(&reference.times, &estimate.times, r.max_diff)
            .into_iter()
            .map(|(i, j)| (reference.times[i], reference.poses[i], j))
            .collect(),
        Associate::Interpolate => align::interpolate(
            &reference.times,
            &reference.poses,
            &estimate.times,
            r.max_gap,
        )
        .into_iter()
        .map(|(j, t, p)| (t, p, j))
        .collect(),
    };
    let need = if r.align == Align::None { 2 } else { 3 };
    if times.len() < need {
        let clock = clock_guess(reference, estimate);
        let within = match r.associate {
            Associate::Nearest => format!("within --max-diff {} s", r.max_diff),
            Associate::Interpolate => format!(
                "inside the reference's span (with reference poses at most --max-gap {} s apart)",
                r.max_gap
            ),
        };
        let span =
            |t: &read::Trajectory| format!("{} to {} s", t.times[0], t.times[t.times.len() - 1]);
        return Err(Error::Input(format!(
            "{} pose pair(s) {within} between {} ({}) and {} ({}); scoring needs at least {need}: {clock}",
            times.len(),
            reference.file.display(),
            span(reference),
            estimate.file.display(),
            span(estimate)
        )));
    }
    let ests: Vec<pose::Pose> = estimate_index.iter().map(|&j| estimate.poses[j]).collect();
    if r.align != Align::Sim3 {
        unit_guess(&refs, &ests, reference, estimate)?;
    }
    if let Some(cells) = cells {
        frame_guess(cells, &refs, reference)?;
    }
    let alignment = match r.align {
        Align::None => align::origin(&ests[0], &refs[0]),
        Align::Se3 | Align::Sim3 => {
            let x: Vec<pose::Vec3> = ests.iter().map(|p| p.t).collect();
            let y: Vec<pose::Vec3> = refs.iter().map(|p| p.t).collect();
            align::umeyama(&x, &y, r.align == Align::Sim3).map_err(|why| {
                Error::Input(format!(
                    "{}: cannot align with --align {}: {why}; try --align none",
                    estimate.file.display(),
                    r.align.name()
                ))
            })?
        }
    };
    let aligned: Vec<pose::Pose> = ests.iter().map(|p| alignment.apply(p)).collect();
    let ape = metrics::ape(&refs, &aligned);
    let frame_pairs = metrics::pairs_by_frames(refs.len(), r.delta);
    let frame_rpe = metrics::rpe(&refs, &aligned, &frame_pairs);
    let mut rpe_at = vec![None; refs.len()];
    for (&(_, j), &e) in frame_pairs.iter().zip(&frame_rpe) {
        rpe_at[j] = Some(e);
    }
    let rpe = |delta: f64, unit: &'static str, errors: &[(f64, f64)]| {
        let t: Vec<f64> = errors.iter().map(|e| e.0).collect();
        let a: Vec<f64> = errors.iter().map(|e| e.1).collect();
        let (ts, rs) = if t.is_empty() {
            (None, None)
        } else {
            (Some(Stats::of(&t)), Some(Stats::of(&a)))
        };
        let per = |s: Option<Stats>, k: f64| {
            (unit == "m")
                .then_some(s.map(|s| s.mean / delta * k))
                .flatten()
        };
        Rpe {
            delta,
            unit,
            translation_m: ts,
            rotation_deg: rs,
            translation_percent: per(ts, 100.0),
            rotation_deg_per_100m: per(rs, 100.0),
        }
    };
    let segments = SEGMENTS_M
        .iter()
        .map(|&d| {
            rpe(
                d,
                "m",
                &metrics::rpe(&refs, &aligned, &metrics::pairs_by_path(&refs, d)),
            )
        })
        .collect();
    let path_length_m = metrics::path_length(&refs);
    let final_drift_m = ape[ape.len() - 1];
    let points: Vec<u32> = ape.iter().map(|&e| metrics::points(e)).collect();
    let stretches = cells.map(|c| graph::stretches(c, &times, &refs, &ape));
    let summary = TrajectoryScore {
        poses: [estimate.poses.len(), reference.poses.len(), times.len()],
        alignment,
        ape_m: Stats::of(&ape),
        rpe: rpe(r.delta as f64, "frames", &frame_rpe),
        segments,
        path_length_m,
        final_drift_m,
        final_drift_percent: if path_length_m > 0.0 {
            100.0 * final_drift_m / path_length_m
        } else {
            0.0
        },
        points_mean: points.iter().map(|&p| f64::from(p)).sum::<f64>() / points.len() as f64,
        points_final: points[points.len() - 1],
        failure: metrics::failure(&times, &refs, &aligned, &ape, r.fail_ape, r.fail_jump),
        worst_stretch: stretches
            .as_deref()
            .and_then(|s| graph::largest(s, 1).pop()),
        out: r.out.clone(),
    };
    Ok(Scored {
        times,
        refs,
        estimate_index,
        aligned,
        ape,
        rpe_at,
        stretches,
        summary,
    })
}
