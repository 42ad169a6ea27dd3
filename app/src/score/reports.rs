//! A team's artifact reports (CSV or JSON: time, class, x, y, z in the world frame) and the
//! DARPA Subterranean Challenge's matching rule: taken in time order, a report scores when
//! an artifact of its class not yet found lies within 5 m of it (the nearest such artifact,
//! ties to the lower id); each artifact scores once. A report that does not score is a
//! duplicate (an artifact of its class within 5 m was found already), a wrong class (only
//! artifacts of other classes within 5 m) or a false report (no artifact within 5 m).

use std::path::Path;

use subtgraph_core::artifacts::ArtifactClass;

use crate::Error;

type Result<T> = std::result::Result<T, Error>;
use serde::Serialize;

/// The DARPA rule's distance, metres.
pub const MATCH_RADIUS: f64 = 5.0;

/// One report as read.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// Its row in the file (CSV: 1 is the header, so the first report is row 2), or its
    /// index in the JSON list (0 up).
    pub row: usize,
    /// Seconds from the start of the run.
    pub time: f64,
    /// Reported class.
    pub class: ArtifactClass,
    /// Reported position, world frame.
    pub position: [f64; 3],
}

/// A ground-truth artifact as the scorer needs it.
#[derive(Clone, Debug, PartialEq)]
pub struct Truth {
    /// Id in `artifacts.json`.
    pub id: usize,
    /// `class-id`.
    pub name: String,
    /// Class.
    pub class: ArtifactClass,
    /// The centre of its base.
    pub position: [f64; 3],
    /// Level.
    pub level: usize,
}

/// What became of a report.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Outcome {
    /// It found an artifact.
    Scored,
    /// Its artifact had been found already.
    Duplicate,
    /// Near artifacts of other classes only.
    WrongClass,
    /// Near no artifact.
    False,
}

impl Outcome {
    /// The name in the outputs.
    pub fn name(self) -> &'static str {
        match self {
            Outcome::Scored => "scored",
            Outcome::Duplicate => "duplicate",
            Outcome::WrongClass => "wrong-class",
            Outcome::False => "false",
        }
    }
}

/// A report's verdict.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Verdict {
    /// Row (CSV) or index (JSON) in the reports file.
    pub row: usize,
    /// Seconds.
    pub time: f64,
    /// Reported class.
    pub class: &'static str,
    /// Reported position.
    pub position: [f64; 3],
    /// What became of it.
    pub outcome: Outcome,
    /// The artifact it scored or duplicated (or the nearest of another class, for a wrong
    /// class), by id.
    pub artifact: Option<usize>,
    /// Distance to that artifact, metres.
    pub distance_m: Option<f64>,
}

fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// Applies the rule; returns each report's verdict (in the file's order) and, per artifact,
/// the index of the verdict that found it.
pub fn score(reports: &[Report], truth: &[Truth]) -> (Vec<Verdict>, Vec<Option<usize>>) {
    let mut order: Vec<usize> = (0..reports.len()).collect();
    order.sort_by(|&a, &b| reports[a].time.total_cmp(&reports[b].time).then(a.cmp(&b)));
    let mut found_by: Vec<Option<usize>> = vec![None; truth.len()];
    let mut verdicts: Vec<Option<Verdict>> = vec![None; reports.len()];
    for k in order {
        let r = &reports[k];
        let near = |same: bool, found: Option<bool>| {
            truth
                .iter()
                .filter(|t| (t.class == r.class) == same)
                .filter(|t| found.is_none_or(|f| found_by[t.id].is_some() == f))
                .map(|t| (distance(t.position, r.position), t.id))
                .filter(|(d, _)| *d <= MATCH_RADIUS)
                .min_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
        };
        let (outcome, hit) = if let Some(hit) = near(true, Some(false)) {
            found_by[hit.1] = Some(k);
            (Outcome::Scored, Some(hit))
        } else if let Some(hit) = near(true, Some(true)) {
            (Outcome::Duplicate, Some(hit))
        } else if let Some(hit) = near(false, None) {
            (Outcome::WrongClass, Some(hit))
        } else {
            (Outcome::False, None)
        };
        verdicts[k] = Some(Verdict {
            row: r.row,
            time: r.time,
            class: r.class.name(),
            position: r.position,
            outcome,
            artifact: hit.map(|h| h.1),
            distance_m: hit.map(|h| h.0),
        });
    }
    (
        verdicts
            .into_iter()
            .map(|v| v.expect("every report judged"))
            .collect(),
        found_by,
    )
}

fn class_of(text: &str, file: &Path, at: &str) -> Result<ArtifactClass> {
    ArtifactClass::parse(text).ok_or_else(|| {
        let known: Vec<&str> = ArtifactClass::ALL.iter().map(|c| c.name()).collect();
        Error::Input(format!(
            "{}: {at}: unknown artifact class '{text}'; the classes are {}",
            file.display(),
            known.join(", ")
        ))
    })
}

fn number(text: &str, file: &Path, at: &str, what: &str) -> Result<f64> {
    let v: f64 = text.trim().parse().map_err(|_| {
        Error::Input(format!(
            "{}: {at}: {what} is '{text}', not a number",
            file.display()
        ))
    })?;
    if !v.is_finite() {
        return Err(Error::Input(format!(
            "{}: {at}: {what} is {text}; every time and coordinate must be a finite number",
            file.display()
        )));
    }
    Ok(v)
}

/// Reads a reports file: JSON (a list of objects with `time`, `class`, `x`, `y`, `z`, or an
/// object holding such a list under `reports`) or CSV with a header naming those columns
/// (any order, any case, other columns ignored).
pub fn read(path: &Path) -> Result<Vec<Report>> {
    parse(&crate::input::read(path)?, path)
}

/// Reads reports from a file's bytes (see [`read`]); `path` names the file in messages and
/// its extension (`.json`) tells JSON from CSV, as does a first `[` or `{`. A UTF-8 byte-order
/// mark, which spreadsheet programs write first, is skipped.
pub fn parse(bytes: &[u8], path: &Path) -> Result<Vec<Report>> {
    let bytes = bytes.strip_prefix("\u{feff}".as_bytes()).unwrap_or(bytes);
    let text = std::str::from_utf8(bytes).map_err(|_| {
        Error::Input(format!(
            "{}: not UTF-8 text; reports are CSV or JSON",
            path.display()
        ))
    })?;
    if text.trim().is_empty() {
        return Err(Error::Input(format!(
            "{}: the file is empty; write a header `time,class,x,y,z` and one row per report (CSV), or a JSON list of {{\"time\", \"class\", \"x\", \"y\", \"z\"}}",
            path.display()
        )));
    }
    let json = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
        || text.trim_start().starts_with(['[', '{']);
    if json {
        read_json(path, text)
    } else {
        read_csv(path, text)
    }
}

fn read_json(path: &Path, text: &str) -> Result<Vec<Report>> {
    let doc: serde_json::Value = serde_json::from_str(text)
        .map_err(|e| Error::Input(format!("{}: not valid JSON: {e}", path.display())))?;
    let list = match &doc {
        serde_json::Value::Array(a) => a,
        serde_json::Value::Object(o) => match o.get("reports") {
            Some(serde_json::Value::Array(a)) => a,
            _ => {
                return Err(Error::Input(format!(
                    "{}: a JSON reports file is a list of reports, or an object with a `reports` list",
                    path.display()
                )));
            }
        },
        _ => {
            return Err(Error::Input(format!(
                "{}: a JSON reports file is a list of reports",
                path.display()
            )));
        }
    };
    list.iter()
        .enumerate()
        .map(|(i, r)| {
            let at = format!("report {i}");
            let field = |k: &str| -> Result<f64> {
                match r.get(k) {
                    Some(serde_json::Value::Number(n)) => number(&n.to_string(), path, &at, k),
                    Some(serde_json::Value::String(s)) => number(s, path, &at, k),
                    _ => Err(Error::Input(format!(
                        "{}: {at}: needs a number `{k}` (reports have time, class, x, y, z)",
                        path.display()
                    ))),
                }
            };
            let class = match r.get("class") {
                Some(serde_json::Value::String(s)) => class_of(s, path, &at)?,
                _ => {
                    return Err(Error::Input(format!(
                        "{}: {at}: needs a string `class`",
                        path.display()
                    )));
                }
            };
            Ok(Report {
                row: i,
                time: field("time")?,
                class,
                position: [field("x")?, field("y")?, field("z")?],
            })
        })
        .collect()
}

fn read_csv(path: &Path, text: &str) -> Result<Vec<Report>> {
    let mut lines = text
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty());
    let (_, header) = lines.next().expect("the text is not blank");
    let names: Vec<String> = header
        .split(',')
        .map(|s| s.trim().trim_matches('"').to_ascii_lowercase())
        .collect();
    let col = |k: &str| -> Result<usize> {
        names.iter().position(|n| n == k).ok_or_else(|| {
            Error::Input(format!(
                "{}: line 1: the header has no `{k}` column (it has {}); reports need time, class, x, y, z",
                path.display(),
                names.join(", ")
            ))
        })
    };
    let (t, c, x, y, z) = (col("time")?, col("class")?, col("x")?, col("y")?, col("z")?);
    lines
        .map(|(i, line)| {
            let at = format!("row {}", i + 1);
            let cells: Vec<&str> = line
                .split(',')
                .map(|s| s.trim().trim_matches('"'))
                .collect();
            let cell = |k: usize| -> Result<&str> {
                cells.get(k).copied().ok_or_else(|| {
                    Error::Input(format!(
                        "{}: {at}: has {} values, the header {}",
                        path.display(),
                        cells.len(),
                        names.len()
                    ))
                })
            };
            Ok(Report {
                row: i + 1,
                time: number(cell(t)?, path, &at, "time")?,
                class: class_of(cell(c)?, path, &at)?,
                position: [
                    number(cell(x)?, path, &at, "x")?,
                    number(cell(y)?, path, &at, "y")?,
                    number(cell(z)?, path, &at, "z")?,
                ],
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn truth() -> Vec<Truth> {
        let t = |id: usize, class, x: f64| Truth {
            id,
            name: format!("a{id}"),
            class,
            position: [x, 0.0, 0.0],
            level: 0,
        };
        vec![
            t(0, ArtifactClass::Survivor, 0.0),
            t(1, ArtifactClass::Backpack, 100.0),
            t(2, ArtifactClass::Survivor, 8.0),
        ]
    }

    fn report(time: f64, class: ArtifactClass, x: f64) -> Report {
        Report {
            row: 0,
            time,
            class,
            position: [x, 0.0, 0.0],
        }
    }

    #[test]
    fn the_darpa_rule_scores_each_artifact_once_in_time_order() {
        use ArtifactClass::*;
        let reports = [
            report(5.0, Survivor, 3.0), // nearest unfound survivor: 0 (3 m; 2 is 5 m)
            report(1.0, Survivor, 4.9), // earlier: scores 2 (3.1 m) before 0 (4.9 m)? nearest: 2
            report(7.0, Survivor, 1.0), // 0 found by then: duplicate
            report(8.0, Helmet, 99.0),  // only a backpack near: wrong class
            report(9.0, Backpack, 105.01), // 5.01 m: false
        ];
        let (v, found) = score(&reports, &truth());
        let outcomes: Vec<Outcome> = v.iter().map(|v| v.outcome).collect();
        assert_eq!(
            outcomes,
            [
                Outcome::Scored,
                Outcome::Scored,
                Outcome::Duplicate,
                Outcome::WrongClass,
                Outcome::False
            ]
        );
        assert_eq!(v[1].artifact, Some(2));
        assert_eq!(v[0].artifact, Some(0));
        assert_eq!(found, [Some(0), None, Some(1)]);
    }
}
