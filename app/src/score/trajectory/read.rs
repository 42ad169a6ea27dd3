//! Trajectory files: TUM (`t x y z qx qy qz qw` a line, as the TUM RGB-D benchmark, evo and
//! the sensor sequences' `ground_truth.tum` write them) and KITTI (a row-major 3x4 pose
//! matrix a line, with the times in a separate file of one time a line, as the KITTI odometry
//! benchmark's `poses/NN.txt` and `sequences/NN/times.txt`).
//!
//! Every row is checked before anything is scored, and a bad one is refused naming the file
//! and its line: a wrong number of columns, a NaN or infinity, a time not after the one
//! before (unsorted or duplicate), a quaternion whose norm is off 1 by more than
//! [`UNIT_TOLERANCE`] or a KITTI rotation that is not one within it, or fewer than two poses.
//! Quaternions within the tolerance are normalised, as evo does.

use std::path::{Path, PathBuf};

use super::lines;
use super::pose::{Pose, from_matrix};
use crate::Error;

/// How far a quaternion's norm may be from 1 (and a KITTI rotation's columns from
/// orthonormal) before the row is refused: 1e-3, loose enough for poses printed with six
/// digits, tight enough to catch a scale or a column in the wrong place.
pub const UNIT_TOLERANCE: f64 = 1e-3;

/// The file name of the ground truth in a sensor sequence folder (`subtgraph sense`).
pub const SEQUENCE_GROUND_TRUTH: &str = "ground_truth.tum";

/// A trajectory as read: strictly increasing times, one pose each.
#[derive(Clone, Debug)]
pub struct Trajectory {
    /// The file it was read from.
    pub file: PathBuf,
    /// `"tum"`, `"kitti"` or `"ros2-bag"`.
    pub format: &'static str,
    /// The bag's topic the poses were read from (bags only).
    pub topic: Option<String>,
    /// Times, seconds.
    pub times: Vec<f64>,
    /// Poses, one per time.
    pub poses: Vec<Pose>,
    /// The file's line of each pose (1-based), for messages.
    pub lines: Vec<usize>,
}

/// The trajectory a positional argument names: the file itself, a sensor sequence folder's
/// `ground_truth.tum`, or a ROS 2 bag folder; `None` for a folder without one (a world
/// folder).
pub fn reference_in(path: &Path) -> Option<PathBuf> {
    if path.is_file() {
        return Some(path.to_path_buf());
    }
    let gt = path.join(SEQUENCE_GROUND_TRUTH);
    if gt.is_file() {
        return Some(gt);
    }
    super::bag::is_bag(path).then(|| path.to_path_buf())
}

fn bad(file: &Path, line: usize, what: impl std::fmt::Display) -> Error {
    Error::Input(format!("{}: line {line}: {what}", file.display()))
}

/// Reads a TUM or KITTI file (told by the number of columns of its first line: 8 or 12) a
/// line at a time, each line checked as it is read; a KITTI file's times come from `times`,
/// or `times.txt` beside it.
pub fn read(file: &Path, times: Option<&Path>) -> Result<Trajectory, Error> {
    let mut traj = Trajectory {
        file: file.to_path_buf(),
        format: "tum",
        topic: None,
        times: Vec::new(),
        poses: Vec::new(),
        lines: Vec::new(),
    };
    let mut want = 0;
    lines::each_row(file, |line, n, v| {
        if want == 0 {
            want = match n {
                8 => 8,
                12 => 12,
                _ => {
                    return Err(bad(
                        file,
                        line,
                        format!(
                            "{n} number{}, but a trajectory line has 8 or 12: TUM lines are `t x y z qx qy qz qw` (8), KITTI lines a 3x4 pose matrix row by row (12)",
                            if n == 1 { "" } else { "s" }
                        ),
                    ));
                }
            };
        }
        if n != want {
            return Err(bad(
                file,
                line,
                format!(
                    "{n} numbers, but this file's first line has {want}: TUM lines are `t x y z qx qy qz qw` (8), KITTI lines a 3x4 pose matrix row by row (12)"
                ),
            ));
        }
        let pose = if want == 12 {
            kitti_pose(v, file, line)?
        } else {
            traj.times.push(v[0]);
            Pose {
                q: unit([v[4], v[5], v[6], v[7]]).map_err(|why| bad(file, line, why))?,
                t: [v[1], v[2], v[3]],
            }
        };
        if let Some(why) = lines::too_far(pose.t) {
            return Err(bad(file, line, why));
        }
        traj.poses.push(pose);
        traj.lines.push(line);
        Ok(())
    })?;
    if traj.poses.is_empty() {
        return Err(Error::Input(format!(
            "{}: no poses: a trajectory needs TUM lines `t x y z qx qy qz qw` or KITTI lines of 12 numbers (a 3x4 pose matrix, row by row)",
            file.display()
        )));
    }
    let (time_file, time_lines) = if want == 12 {
        traj.format = "kitti";
        let (path, t, lines) = kitti_times(file, times, traj.poses.len())?;
        traj.times = t;
        (path, lines)
    } else {
        (file.to_path_buf(), traj.lines.clone())
    };
    increasing(&traj, |k, why| bad(&time_file, time_lines[k], why))?;
    Ok(traj)
}

/// `[w x y z]`, normalised, of a `[x y z w]` quaternion within [`UNIT_TOLERANCE`] of unit
/// norm; else why not.
fn unit(q: [f64; 4]) -> Result<[f64; 4], String> {
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    if (n - 1.0).abs() > UNIT_TOLERANCE {
        return Err(format!(
            "the quaternion (qx qy qz qw) = ({} {} {} {}) has norm {n:.6}, not 1 within {UNIT_TOLERANCE}: columns out of order, or not a rotation",
            q[0], q[1], q[2], q[3]
        ));
    }
    Ok([q[3] / n, q[0] / n, q[1] / n, q[2] / n])
}

/// At least two poses, at strictly increasing times; `at(k, why)` words the error at pose `k`.
fn increasing(t: &Trajectory, at: impl Fn(usize, String) -> Error) -> Result<(), Error> {
    if t.poses.len() < 2 {
        return Err(Error::Input(format!(
            "{}{}: {} pose(s): a trajectory needs at least 2",
            t.file.display(),
            t.topic
                .as_ref()
                .map_or(String::new(), |x| format!(": topic {x}")),
            t.poses.len()
        )));
    }
    for (k, w) in t.times.windows(2).enumerate() {
        let (before, now) = (w[0], w[1]);
        if now <= before {
            let word = if now == before {
                "duplicate"
            } else {
                "unsorted"
            };
            return Err(at(
                k + 1,
                format!(
                    "{word} time {now} (the pose before is at {before}): times must increase strictly"
                ),
            ));
        }
    }
    Ok(())
}

/// Reads a trajectory file ([`read`]) or a ROS 2 bag's pose topic (`topic`, or the bag's
/// only pose topic), with the same checks: the header stamps must increase strictly and the
/// quaternions be unit within [`UNIT_TOLERANCE`].
pub fn read_any(
    file: &Path,
    times: Option<&Path>,
    topic: Option<&str>,
) -> Result<Trajectory, Error> {
    if !super::bag::is_bag(file) {
        if file.is_dir() {
            return Err(Error::Input(format!(
                "{}: a folder, but not a ROS 2 bag (no metadata.yaml or .mcap file in it): give a TUM or KITTI file, or a bag folder",
                file.display()
            )));
        }
        return read(file, times);
    }
    let (topic, messages) = super::bag::read(file, topic)?;
    let at = |number: usize, why: String| {
        Error::Input(format!(
            "{}: topic {topic}: message {number}: {why}",
            file.display()
        ))
    };
    let mut traj = Trajectory {
        file: file.to_path_buf(),
        format: "ros2-bag",
        topic: Some(topic.clone()),
        times: Vec::with_capacity(messages.len()),
        poses: Vec::with_capacity(messages.len()),
        lines: Vec::with_capacity(messages.len()),
    };
    for m in &messages {
        if !(m.time.is_finite()
            && m.position
                .iter()
                .chain(&m.orientation)
                .all(|x| x.is_finite()))
        {
            return Err(at(
                m.number,
                "a NaN or infinite value: every stamp and pose value must be finite".to_owned(),
            ));
        }
        let q = unit(m.orientation).map_err(|why| at(m.number, why))?;
        if let Some(why) = lines::too_far(m.position) {
            return Err(at(m.number, why));
        }
        traj.times.push(m.time);
        traj.poses.push(Pose { q, t: m.position });
        traj.lines.push(m.number);
    }
    increasing(&traj, |k, why| at(traj.lines[k], why))?;
    Ok(traj)
}

fn kitti_pose(v: &[f64], file: &Path, line: usize) -> Result<Pose, Error> {
    let r = [[v[0], v[1], v[2]], [v[4], v[5], v[6]], [v[8], v[9], v[10]]];
    let mut worst: f64 = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            let d: f64 = (0..3).map(|k| r[k][i] * r[k][j]).sum();
            worst = worst.max((d - if i == j { 1.0 } else { 0.0 }).abs());
        }
    }
    let det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1])
        - r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0])
        + r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
    if worst > UNIT_TOLERANCE || det < 0.0 {
        return Err(bad(
            file,
            line,
            format!(
                "the 3x3 part is not a rotation (RᵀR is off the identity by {worst:.6}, determinant {det:.6}; tolerance {UNIT_TOLERANCE}): KITTI lines are r11 r12 r13 tx r21 r22 r23 ty r31 r32 r33 tz"
            ),
        ));
    }
    Ok(Pose {
        q: from_matrix(r),
        t: [v[3], v[7], v[11]],
    })
}

/// The times of a KITTI file: `(times file, times, their lines)`.
fn kitti_times(
    file: &Path,
    times: Option<&Path>,
    poses: usize,
) -> Result<(PathBuf, Vec<f64>, Vec<usize>), Error> {
    let path = match times {
        Some(p) => p.to_path_buf(),
        None => {
            let beside = file.with_file_name("times.txt");
            if !beside.is_file() {
                return Err(Error::Input(format!(
                    "{}: a KITTI trajectory has no times: give its times file (one time a line) with --times (the estimate's) or --reference-times, or put it beside as times.txt",
                    file.display()
                )));
            }
            beside
        }
    };
    let mut out = Vec::with_capacity(poses);
    let mut numbers = Vec::with_capacity(poses);
    lines::each_row(&path, |line, n, v| {
        if n != 1 {
            return Err(bad(
                &path,
                line,
                format!("{n} numbers: a times file has one time (seconds) a line"),
            ));
        }
        if out.len() == poses {
            return Err(Error::Input(format!(
                "{}: more than the {poses} times of the {poses} poses of {}: a KITTI times file has one line per pose",
                path.display(),
                file.display()
            )));
        }
        out.push(v[0]);
        numbers.push(line);
        Ok(())
    })?;
    if out.len() != poses {
        return Err(Error::Input(format!(
            "{}: {} times for the {poses} poses of {}: a KITTI times file has one line per pose",
            path.display(),
            out.len(),
            file.display()
        )));
    }
    Ok((path, out, numbers))
}
