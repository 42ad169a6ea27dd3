//! The report folder's files: `report.json` (everything), CSV tables (`summary.csv`,
//! `success.csv`, `paired.csv`, `trends.csv`, `failure_bins.csv`, `runs.csv`), a PNG per
//! metric under `plots/`, and `index.html`: one page with no script and nothing from the
//! network, its images and links relative, so it opens offline and moves with the folder
//! as long as the worlds stay where they are.

use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};

use std::collections::BTreeMap;

use super::analysis::{Report, RunRow};
use super::plots::{self, Series};
use super::sample::Line;
use super::world::PARAMETERS;

fn opt(v: Option<f64>) -> String {
    v.map_or(String::new(), |v| v.to_string())
}

fn pair(v: Option<[f64; 2]>) -> (String, String) {
    (opt(v.map(|v| v[0])), opt(v.map(|v| v[1])))
}

/// The failure rates' plot.
const FAILURE_PLOT: &str = "plots/failure-rate.png";

/// Each metric's plot's file name, in the metrics' order: the name's letters, digits and `_`,
/// anything else `-`; a name another metric (or the failure plot) already has, ignoring
/// case, gets `-2`, `-3`, ... (issue 37, item 16: `zz.y` and `zz-y` shared one picture).
pub fn plot_names(metrics: &[String]) -> Vec<String> {
    let mut taken = std::collections::BTreeSet::from([FAILURE_PLOT.to_ascii_lowercase()]);
    metrics
        .iter()
        .map(|metric| {
            let s: String = metric
                .chars()
                .map(|c| {
                    if c.is_ascii_alphanumeric() || c == '_' {
                        c
                    } else {
                        '-'
                    }
                })
                .collect();
            let name = (1..)
                .map(|k| match k {
                    1 => format!("plots/{s}.png"),
                    k => format!("plots/{s}-{k}.png"),
                })
                .find(|n| !taken.contains(&n.to_ascii_lowercase()))
                .expect("a free name");
            taken.insert(name.to_ascii_lowercase());
            name
        })
        .collect()
}

/// `to` relative to the folder `from` (both absolute).
fn relative(from: &Path, to: &Path) -> String {
    let f: Vec<Component> = from.components().collect();
    let t: Vec<Component> = to.components().collect();
    let common = f.iter().zip(&t).take_while(|(a, b)| a == b).count();
    let mut p = PathBuf::new();
    for _ in common..f.len() {
        p.push("..");
    }
    for c in &t[common..] {
        p.push(c.as_os_str());
    }
    p.to_string_lossy().replace('\\', "/")
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn num(v: f64) -> String {
    if v == 0.0 || (v.abs() >= 0.001 && v.abs() < 1e6) {
        format!("{v:.4}")
    } else {
        format!("{v:.3e}")
    }
}

/// A text field of a CSV row, quoted when it must be (RFC 4180).
fn q(s: &str) -> std::borrow::Cow<'_, str> {
    super::csv::field(s)
}

fn csvs(r: &Report, files: &mut Vec<(String, Vec<u8>)>) {
    let mut s = String::from("method,scope,metric,n,mean,median,ci95_low,ci95_high\n");
    for x in &r.summary {
        let (lo, hi) = pair(x.ci95);
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{lo},{hi}",
            q(&x.method),
            q(&x.scope),
            q(&x.metric),
            x.n,
            x.mean,
            x.median
        );
    }
    files.push(("summary.csv".into(), s.into_bytes()));
    let mut s = String::from("method,scope,runs,failures,rate,wilson95_low,wilson95_high\n");
    for x in &r.success {
        let (lo, hi) = pair(x.wilson95);
        let _ = writeln!(
            s,
            "{},{},{},{},{},{lo},{hi}",
            q(&x.method),
            q(&x.scope),
            x.runs,
            x.failures,
            x.rate
        );
    }
    files.push(("success.csv".into(), s.into_bytes()));
    let mut s = String::from(
        "a,b,metric,n,mean_difference,median_difference,a_lower,b_lower,equal,wilcoxon_n,zeros,statistic,p,method\n",
    );
    for x in &r.paired {
        let w = x.wilcoxon.as_ref();
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            q(&x.a),
            q(&x.b),
            q(&x.metric),
            x.n,
            x.mean_difference,
            x.median_difference,
            x.a_lower,
            x.b_lower,
            x.equal,
            w.map_or(String::new(), |w| w.n.to_string()),
            w.map_or(String::new(), |w| w.zeros.to_string()),
            opt(w.map(|w| w.statistic)),
            opt(w.map(|w| w.p)),
            w.map_or("", |w| w.method)
        );
    }
    files.push(("paired.csv".into(), s.into_bytes()));
    let mut s = String::from("method,metric,parameter,n,slope,intercept,r\n");
    for x in &r.trends {
        let l = x.line.as_ref();
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{}",
            q(&x.method),
            q(&x.metric),
            x.parameter,
            x.n,
            opt(l.map(|l| l.slope)),
            opt(l.map(|l| l.intercept)),
            opt(l.and_then(|l| l.r))
        );
    }
    files.push(("trends.csv".into(), s.into_bytes()));
    let mut s = String::from("method,parameter,from,to,runs,failures,rate\n");
    for x in &r.failure_bins {
        for b in &x.bins {
            let _ = writeln!(
                s,
                "{},{},{},{},{},{},{}",
                q(&x.method),
                x.parameter,
                b.from,
                b.to,
                b.runs,
                b.failures,
                opt(b.rate)
            );
        }
    }
    files.push(("failure_bins.csv".into(), s.into_bytes()));
    let metrics: Vec<String> = r.metrics.iter().map(|m| q(m).into_owned()).collect();
    let mut s = format!(
        "method,world,preset,failed,{},{}\n",
        PARAMETERS.join(","),
        metrics.join(",")
    );
    for x in &r.runs {
        let w = &r.worlds[x.world];
        let _ = write!(
            s,
            "{},{},{},{}",
            q(&x.method),
            q(&w.name),
            q(&w.preset),
            x.failed.map_or(String::new(), |f| f.to_string())
        );
        for p in PARAMETERS {
            let _ = write!(s, ",{}", w.parameters[p]);
        }
        for m in &r.metrics {
            let _ = write!(s, ",{}", opt(x.metrics.get(m).copied()));
        }
        s.push('\n');
    }
    files.push(("runs.csv".into(), s.into_bytes()));
}

fn pictures(r: &Report, files: &mut Vec<(String, Vec<u8>)>) {
    let methods: Vec<&str> = r.methods.iter().map(String::as_str).collect();
    // Looked up once, not per plot, parameter and method (issue 37, item 11).
    let mut runs_of: BTreeMap<&str, Vec<&RunRow>> = BTreeMap::new();
    for x in &r.runs {
        runs_of.entry(x.method.as_str()).or_default().push(x);
    }
    let lines: BTreeMap<(&str, &str, &str), Option<Line>> = r
        .trends
        .iter()
        .map(|t| ((t.method.as_str(), t.metric.as_str(), t.parameter), t.line))
        .collect();
    for (metric, name) in r.metrics.iter().zip(plot_names(&r.metrics)) {
        let panels: Vec<Vec<Series>> = PARAMETERS
            .iter()
            .map(|p| {
                methods
                    .iter()
                    .map(|m| Series {
                        method: m,
                        points: runs_of
                            .get(m)
                            .into_iter()
                            .flatten()
                            .filter_map(|x| {
                                Some((r.worlds[x.world].parameters[p], *x.metrics.get(metric)?))
                            })
                            .collect(),
                        line: lines.get(&(*m, metric.as_str(), *p)).copied().flatten(),
                    })
                    .collect()
            })
            .collect();
        files.push((name, plots::scatter(metric, &methods, &panels)));
    }
    if !r.failure_bins.is_empty() {
        let panels: Vec<Vec<Vec<_>>> = PARAMETERS
            .iter()
            .map(|p| {
                r.failure_bins
                    .iter()
                    .filter(|b| b.parameter == *p)
                    .map(|b| b.bins.clone())
                    .collect()
            })
            .collect();
        let flagged: Vec<&str> = methods
            .iter()
            .copied()
            .filter(|m| r.failure_bins.iter().any(|b| b.method == *m))
            .collect();
        files.push((FAILURE_PLOT.into(), plots::failures(&flagged, &panels)));
    }
}

const STYLE: &str = "body{font-family:sans-serif;margin:24px;color:#222}table{border-collapse:collapse;margin:8px 0 20px}td,th{border:1px solid #ccc;padding:3px 7px;text-align:right;font-size:13px}th{background:#f0f0f0}td.l,th.l{text-align:left}img.plot{max-width:100%;border:1px solid #ddd;margin:6px 0}img.map{height:48px;image-rendering:pixelated}p.note{color:#555;font-size:13px;max-width:70em}";

fn html(r: &Report, out: &Path) -> String {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>subtgraph report</title><style>{STYLE}</style></head><body>\n<h1>subtgraph report</h1>\n<p>{} method(s): {}; {} world(s); {} run(s); {} metric(s). Data: <a href=\"report.json\">report.json</a>, <a href=\"summary.csv\">summary.csv</a>, <a href=\"paired.csv\">paired.csv</a>, <a href=\"success.csv\">success.csv</a>, <a href=\"trends.csv\">trends.csv</a>, <a href=\"failure_bins.csv\">failure_bins.csv</a>, <a href=\"runs.csv\">runs.csv</a>.</p>\n<p class=\"note\">Intervals: {}; B = {}, seed {}.</p>\n",
        r.methods.len(),
        esc(&r.methods.join(", ")),
        r.worlds.len(),
        r.runs.len(),
        r.metrics.len(),
        esc(r.bootstrap),
        r.resamples,
        r.seed
    );
    if !r.success.is_empty() {
        h.push_str("<h2>Success rate</h2>\n<table><tr><th class=\"l\">method</th><th class=\"l\">worlds</th><th>runs</th><th>failures</th><th>success</th><th>Wilson 95 %</th></tr>\n");
        for s in &r.success {
            let ci = s
                .wilson95
                .map_or(String::new(), |c| format!("{} to {}", num(c[0]), num(c[1])));
            let _ = writeln!(
                h,
                "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{ci}</td></tr>",
                esc(&s.method),
                esc(&s.scope),
                s.runs,
                s.failures,
                num(s.rate)
            );
        }
        let _ = writeln!(h, "</table>\n<p class=\"note\">{}</p>", esc(r.success_rule));
    }
    h.push_str("<h2>Plots</h2>\n");
    if !r.failure_bins.is_empty() {
        h.push_str("<p><img class=\"plot\" src=\"plots/failure-rate.png\" alt=\"failure rate per bin\"></p>\n");
    }
    for (m, name) in r.metrics.iter().zip(plot_names(&r.metrics)) {
        let _ = writeln!(
            h,
            "<p><img class=\"plot\" src=\"{}\" alt=\"{}\"></p>",
            esc(&name),
            esc(m)
        );
    }
    if !r.paired.is_empty() {
        h.push_str("<h2>Paired comparisons</h2>\n<table><tr><th class=\"l\">first - second</th><th class=\"l\">metric</th><th>n</th><th>mean difference</th><th>median difference</th><th>first lower</th><th>second lower</th><th>Wilcoxon p</th><th class=\"l\">test</th></tr>\n");
        for p in &r.paired {
            let w = p.wilcoxon.as_ref();
            let _ = writeln!(
                h,
                "<tr><td class=\"l\">{} - {}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{:.0} %</td><td>{:.0} %</td><td>{}</td><td class=\"l\">{}</td></tr>",
                esc(&p.a),
                esc(&p.b),
                esc(&p.metric),
                p.n,
                num(p.mean_difference),
                num(p.median_difference),
                100.0 * p.a_lower,
                100.0 * p.b_lower,
                w.map_or(String::new(), |w| format!("{:.3e}", w.p)),
                w.map_or("", |w| w.method)
            );
        }
        let _ = writeln!(
            h,
            "</table>\n<p class=\"note\">{}. Test: {}.</p>",
            esc(r.pairing),
            esc(r.wilcoxon)
        );
        if !r.unpaired.is_empty() {
            h.push_str("<p class=\"note\">Unpaired: ");
            let list: Vec<String> = r
                .unpaired
                .iter()
                .map(|u| {
                    format!(
                        "{} (scored by {}, not by {})",
                        esc(&u.world),
                        esc(&u.scored_by),
                        esc(&u.missing_from)
                    )
                })
                .collect();
            h.push_str(&list.join("; "));
            h.push_str("</p>\n");
        }
    }
    h.push_str("<h2>Every metric</h2>\n<table><tr><th class=\"l\">method</th><th class=\"l\">worlds</th><th class=\"l\">metric</th><th>n</th><th>mean</th><th>median</th><th>95 % CI of the mean</th></tr>\n");
    for s in &r.summary {
        let ci = s
            .ci95
            .map_or(String::new(), |c| format!("{} to {}", num(c[0]), num(c[1])));
        let _ = writeln!(
            h,
            "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{ci}</td></tr>",
            esc(&s.method),
            esc(&s.scope),
            esc(&s.metric),
            s.n,
            num(s.mean),
            num(s.median)
        );
    }
    h.push_str("</table>\n<h2>Worlds</h2>\n<table><tr><th class=\"l\">world</th><th class=\"l\">preset</th>");
    for p in PARAMETERS {
        let _ = write!(h, "<th>{p}</th>");
    }
    h.push_str("<th class=\"l\">maps</th><th class=\"l\">runs</th></tr>\n");
    let mut by_world: BTreeMap<usize, Vec<&RunRow>> = BTreeMap::new();
    for x in &r.runs {
        by_world.entry(x.world).or_default().push(x);
    }
    for (k, w) in r.worlds.iter().enumerate() {
        let abs = w.path.canonicalize().unwrap_or_else(|_| w.path.clone());
        let link = relative(out, &abs);
        let _ = write!(
            h,
            "<tr><td class=\"l\"><a href=\"{}/\">{}</a></td><td class=\"l\">{}</td>",
            esc(&link),
            esc(&w.name),
            esc(&w.preset)
        );
        for p in PARAMETERS {
            let _ = write!(h, "<td>{}</td>", num(w.parameters[p]));
        }
        h.push_str("<td class=\"l\">");
        for m in &w.maps {
            let src = esc(&format!("{link}/{m}"));
            let _ = write!(
                h,
                "<a href=\"{src}\"><img class=\"map\" src=\"{src}\" alt=\"{}\"></a> ",
                esc(m)
            );
        }
        h.push_str("</td><td class=\"l\">");
        for run in by_world.get(&k).into_iter().flatten() {
            let state = match run.failed {
                Some(true) => " (failed)",
                _ => "",
            };
            for f in &run.score_folders {
                let abs = f.canonicalize().unwrap_or_else(|_| f.clone());
                let _ = write!(
                    h,
                    "<a href=\"{}/\">{}</a>{state} ",
                    esc(&relative(out, &abs)),
                    esc(&run.method)
                );
            }
        }
        h.push_str("</td></tr>\n");
    }
    h.push_str("</table>\n</body></html>\n");
    h
}

/// The report folder's files, `(name, bytes)`; `out` is where the folder will be (absolute),
/// for the relative links to the worlds.
pub(super) fn files(r: &Report, out: &Path) -> Vec<(String, Vec<u8>)> {
    let mut json = serde_json::to_string_pretty(r).expect("plain data serializes");
    json.push('\n');
    let mut files = vec![("report.json".to_owned(), json.into_bytes())];
    csvs(r, &mut files);
    pictures(r, &mut files);
    files.push(("index.html".into(), html(r, out).into_bytes()));
    files
}
