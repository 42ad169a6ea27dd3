//! The trajectory score folder's files: `trajectory.json` (every score, the options and the
//! files, and the command that reproduces it), `errors.csv` (each associated pose: times,
//! positions, APE, and the RPE of the `--delta` pair ending there) and `trajectory.png` (top
//! down: the reference in grey, the aligned estimate coloured by APE).

use std::fmt::Write as _;

use serde::Serialize;
use subtgraph_plot::{Anchor, Figure, Rgb, Shape, viridis};

use super::read::Trajectory;
use super::{Align, POINTS, Scored, TrajectoryRequest, TrajectoryScore, UNIT_TOLERANCE};

#[derive(Serialize)]
struct FileJson {
    file: String,
    format: &'static str,
    #[serde(skip_serializing_if = "Option::is_none")]
    topic: Option<String>,
    poses: usize,
    start_s: f64,
    end_s: f64,
}

impl From<&Trajectory> for FileJson {
    fn from(t: &Trajectory) -> Self {
        FileJson {
            file: t.file.display().to_string(),
            format: t.format,
            topic: t.topic.clone(),
            poses: t.poses.len(),
            start_s: t.times[0],
            end_s: t.times[t.times.len() - 1],
        }
    }
}

#[derive(Serialize)]
struct Options {
    align: Align,
    evo_align_option: &'static str,
    associate: super::Associate,
    max_diff_s: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    max_gap_s: Option<f64>,
    delta_frames: usize,
    fail_ape_m: f64,
    fail_jump_m: f64,
    quaternion_tolerance: f64,
    points_thresholds_m: Vec<(f64, u32)>,
}

#[derive(Serialize)]
struct GraphJson {
    world: String,
    stretches: usize,
    poses_outside: usize,
    largest_increases: Vec<super::graph::Stretch>,
}

#[derive(Serialize)]
struct Doc<'a> {
    format: &'static str,
    command: String,
    world_or_sequence: String,
    reference: FileJson,
    estimate: FileJson,
    options: Options,
    associated_poses: usize,
    failed: bool,
    graph: Option<GraphJson>,
    #[serde(flatten)]
    score: &'a TrajectoryScore,
}

/// The files, `(name, bytes)`.
pub(super) struct Files {
    pub list: Vec<(String, Vec<u8>)>,
}

fn quoted(p: &std::path::Path) -> String {
    let s = p.display().to_string();
    if s.chars()
        .all(|c| c.is_ascii_alphanumeric() || "/._-+=:,".contains(c))
    {
        s
    } else {
        format!("'{}'", s.replace('\'', r"'\''"))
    }
}

fn command(r: &TrajectoryRequest) -> String {
    let mut c = format!(
        "subtgraph score {} --trajectory {}",
        quoted(&r.world_or_sequence),
        quoted(&r.estimate)
    );
    let flag = |c: &mut String, name: &str, p: &Option<std::path::PathBuf>| {
        if let Some(p) = p {
            let _ = write!(c, " --{name} {}", quoted(p));
        }
    };
    flag(&mut c, "times", &r.times);
    flag(&mut c, "reference", &r.reference);
    flag(&mut c, "reference-times", &r.reference_times);
    for (name, topic) in [("topic", &r.topic), ("reference-topic", &r.reference_topic)] {
        if let Some(t) = topic {
            let _ = write!(c, " --{name} {}", quoted(std::path::Path::new(t)));
        }
    }
    if r.associate == super::Associate::Interpolate {
        let _ = write!(c, " --associate interpolate --max-gap {}", r.max_gap);
    }
    let _ = write!(
        c,
        " --max-diff {} --align {} --delta {} --fail-ape {} --fail-jump {} --out {}",
        r.max_diff,
        r.align.name(),
        r.delta,
        r.fail_ape,
        r.fail_jump,
        quoted(&r.out)
    );
    c
}

pub(super) fn files(
    r: &TrajectoryRequest,
    reference: &Trajectory,
    estimate: &Trajectory,
    s: &Scored,
) -> Files {
    let doc = Doc {
        format: "subtgraph-trajectory-score/1",
        command: command(r),
        world_or_sequence: r.world_or_sequence.display().to_string(),
        reference: reference.into(),
        estimate: estimate.into(),
        options: Options {
            align: r.align,
            evo_align_option: r.align.evo_option(),
            associate: r.associate,
            max_diff_s: r.max_diff,
            max_gap_s: (r.associate == super::Associate::Interpolate).then_some(r.max_gap),
            delta_frames: r.delta,
            fail_ape_m: r.fail_ape,
            fail_jump_m: r.fail_jump,
            quaternion_tolerance: UNIT_TOLERANCE,
            points_thresholds_m: POINTS.to_vec(),
        },
        associated_poses: s.times.len(),
        failed: s.summary.failure.is_some(),
        graph: s.stretches.as_ref().map(|st| GraphJson {
            world: r.world_or_sequence.display().to_string(),
            stretches: st.len(),
            poses_outside: st
                .iter()
                .filter(|t| t.region == "outside")
                .map(|t| t.poses[1] - t.poses[0] + 1)
                .sum(),
            largest_increases: super::graph::largest(st, 5),
        }),
        score: &s.summary,
    };
    let mut json = serde_json::to_string_pretty(&doc).expect("plain data serializes");
    json.push('\n');
    let mut csv = String::from(
        "pose,time,time_estimate,x,y,z,x_estimate,y_estimate,z_estimate,ape_m,rpe_m,rpe_deg\n",
    );
    for (k, &j) in s.estimate_index.iter().enumerate() {
        let q = s.refs[k].t;
        let p = s.aligned[k].t;
        let (rt, ra) = match s.rpe_at[k] {
            Some((t, a)) => (t.to_string(), a.to_string()),
            None => (String::new(), String::new()),
        };
        let _ = writeln!(
            csv,
            "{k},{},{},{},{},{},{},{},{},{},{rt},{ra}",
            s.times[k], estimate.times[j], q[0], q[1], q[2], p[0], p[1], p[2], s.ape[k]
        );
    }
    let mut list = vec![
        ("trajectory.json".to_owned(), json.into_bytes()),
        ("errors.csv".to_owned(), csv.into_bytes()),
        ("trajectory.png".to_owned(), picture(s)),
    ];
    if let Some(st) = &s.stretches {
        list.push(("graph.csv".to_owned(), super::graph::csv(st).into_bytes()));
    }
    Files { list }
}

const GREY: Rgb = [170, 170, 170];
const BLACK: Rgb = [0, 0, 0];

/// Top down (x east, y north): the reference in grey, the aligned estimate coloured by APE
/// (viridis, dark 0 to yellow at the largest), on one scale for both axes.
fn picture(s: &Scored) -> Vec<u8> {
    let refs: Vec<[f64; 3]> = s.refs.iter().map(|p| p.t).collect();
    let all = refs.iter().chain(s.aligned.iter().map(|p| &p.t));
    let (mut x0, mut y0, mut x1, mut y1) = (f64::MAX, f64::MAX, f64::MIN, f64::MIN);
    for p in all {
        x0 = x0.min(p[0]);
        y0 = y0.min(p[1]);
        x1 = x1.max(p[0]);
        y1 = y1.max(p[1]);
    }
    let span = (x1 - x0).max(y1 - y0).max(1e-9);
    let size = 800.0;
    let k = size / span;
    let (pad, head) = (16.0, 44.0);
    let mut f = Figure {
        width: (x1 - x0) * k + 2.0 * pad,
        height: (y1 - y0) * k + 2.0 * pad + head,
        shapes: Vec::new(),
    };
    let at = |p: [f64; 3]| (pad + (p[0] - x0) * k, head + pad + (y1 - p[1]) * k);
    let a = &s.summary.ape_m;
    heading(
        &mut f,
        pad,
        format!(
            "APE RMSE {:.3} m, max {:.3} m; final drift {:.2} %",
            a.rmse, a.max, s.summary.final_drift_percent
        ),
        format!(
            "grey: reference; estimate coloured by APE, dark 0 m to yellow {:.3} m",
            a.max
        ),
    );
    for w in refs.windows(2) {
        f.shapes.push(Shape::Line {
            from: at(w[0]),
            to: at(w[1]),
            stroke: GREY,
            width: 3.0,
        });
    }
    let top = a.max.max(1e-12);
    for (w, e) in s.aligned.windows(2).zip(&s.ape[1..]) {
        f.shapes.push(Shape::Line {
            from: at(w[0].t),
            to: at(w[1].t),
            stroke: viridis(e / top),
            width: 1.5,
        });
    }
    subtgraph_plot::to_png(&f, 1.0)
}

/// A picture's two heading lines, a title and a key under it, at the left margin `pad`.
pub(super) fn heading(f: &mut Figure, pad: f64, title: String, key: String) {
    for (text, y, size) in [(title, 14.0, 14.0), (key, 32.0, 10.0)] {
        f.shapes.push(Shape::Text {
            x: pad,
            y,
            size,
            anchor: Anchor::Start,
            vertical: false,
            color: BLACK,
            text,
        });
    }
}
