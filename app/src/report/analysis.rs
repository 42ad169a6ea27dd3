//! The numbers of a report, from the runs: everything `report.json` holds.

use std::collections::{BTreeMap, BTreeSet};
use std::path::PathBuf;

use serde::Serialize;

use super::runs::Run;
use super::sample::{self, Bin, Line};
use super::wilcoxon::{self, Wilcoxon};
use super::world::{self, PARAMETERS, WorldInfo};
use crate::Error;

/// How the bootstrap resamples, in words (`report.json` and the docs).
pub const BOOTSTRAP: &str = "percentile bootstrap of the mean: each interval starts SplitMix64 at the seed; a resample draws n indices, each (u * n) >> 64 of the next 64-bit u, and sums the values in draw order; the interval is the 2.5th and 97.5th percentiles of the resample means, linearly interpolated (numpy's default)";

/// How success is decided, in words.
pub const SUCCESS: &str = "a run succeeded unless a summary of its score folders says \"failed\": true (the trajectory score's divergence or jump); runs with no such flag are left out of the rate";

/// How pairs are made, in words.
pub const PAIRING: &str = "two methods are compared on the worlds both scored (a world scored by one only is listed in `unpaired`); differences are first minus second";

/// One world of the report.
#[derive(Clone, Debug, Serialize)]
pub struct WorldRow {
    /// Its folder's name.
    pub name: String,
    /// Its folder.
    pub path: PathBuf,
    /// Its preset.
    pub preset: String,
    /// Its parameters by name.
    pub parameters: BTreeMap<&'static str, f64>,
    /// Its maps, relative to its folder.
    pub maps: Vec<String>,
}

/// One method on one world.
#[derive(Clone, Debug, Serialize)]
pub struct RunRow {
    /// The method.
    pub method: String,
    /// The world's index in `worlds`.
    pub world: usize,
    /// Its score folders.
    pub score_folders: Vec<PathBuf>,
    /// The failure flag, when a summary has one.
    pub failed: Option<bool>,
    /// Every metric it has.
    pub metrics: BTreeMap<String, f64>,
}

/// A metric's statistics for one method over a set of worlds.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    /// The method.
    pub method: String,
    /// `all`, or `preset NAME`.
    pub scope: String,
    /// The metric.
    pub metric: String,
    /// Worlds with a value.
    pub n: usize,
    /// Mean.
    pub mean: f64,
    /// Median.
    pub median: f64,
    /// The 95 % bootstrap interval of the mean (`None` below two worlds).
    pub ci95: Option<[f64; 2]>,
}

/// A method's success rate over a set of worlds.
#[derive(Clone, Debug, Serialize)]
pub struct Success {
    /// The method.
    pub method: String,
    /// `all`, or `preset NAME`.
    pub scope: String,
    /// Runs with a failure flag.
    pub runs: usize,
    /// Of which failed.
    pub failures: usize,
    /// `(runs - failures) / runs`.
    pub rate: f64,
    /// Wilson's 95 % interval of the rate.
    pub wilson95: Option<[f64; 2]>,
}

/// Two methods' paired differences on one metric.
#[derive(Clone, Debug, Serialize)]
pub struct Paired {
    /// The first method.
    pub a: String,
    /// The second.
    pub b: String,
    /// The metric.
    pub metric: String,
    /// Worlds both have a value on.
    pub n: usize,
    /// Mean of `a - b`.
    pub mean_difference: f64,
    /// Median of `a - b`.
    pub median_difference: f64,
    /// Share of those worlds where `a` is lower (for an error, where `a` wins).
    pub a_lower: f64,
    /// Share where `b` is lower.
    pub b_lower: f64,
    /// Share where they are equal.
    pub equal: f64,
    /// The signed-rank test (`None` when every difference is 0).
    pub wilcoxon: Option<Wilcoxon>,
}

/// A metric against a world parameter, for one method.
#[derive(Clone, Debug, Serialize)]
pub struct Trend {
    /// The method.
    pub method: String,
    /// The metric.
    pub metric: String,
    /// The parameter.
    pub parameter: &'static str,
    /// Worlds.
    pub n: usize,
    /// The least-squares line (`None` when the parameter does not vary).
    pub line: Option<Line>,
}

/// A method's failure rate per bin of a parameter.
#[derive(Clone, Debug, Serialize)]
pub struct FailureBins {
    /// The method.
    pub method: String,
    /// The parameter.
    pub parameter: &'static str,
    /// The bins.
    pub bins: Vec<Bin>,
}

/// A world one method scored and another did not.
#[derive(Clone, Debug, Serialize)]
pub struct Unpaired {
    /// The method that has it.
    pub scored_by: String,
    /// The one that has not.
    pub missing_from: String,
    /// The world's name.
    pub world: String,
}

/// Everything `report.json` holds.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    /// `subtgraph-report/1`.
    pub format: &'static str,
    /// The bootstrap's seed.
    pub seed: u64,
    /// Resamples per interval.
    pub resamples: usize,
    /// [`BOOTSTRAP`].
    pub bootstrap: &'static str,
    /// Which Wilcoxon test, in words.
    pub wilcoxon: &'static str,
    /// [`SUCCESS`].
    pub success_rule: &'static str,
    /// [`PAIRING`].
    pub pairing: &'static str,
    /// What a metric is, in words.
    pub metrics_rule: String,
    /// Methods, by name.
    pub methods: Vec<String>,
    /// Metrics that vary, by name.
    pub metrics: Vec<String>,
    /// Numbers equal in every run: settings, not results; left out of the statistics.
    pub constant: BTreeMap<String, f64>,
    /// The world parameters, in column order.
    pub parameters: [&'static str; 7],
    /// Worlds, by name.
    pub worlds: Vec<WorldRow>,
    /// Runs, by method then world.
    pub runs: Vec<RunRow>,
    /// Per method (and preset) and metric.
    pub summary: Vec<Summary>,
    /// Per method (and preset).
    pub success: Vec<Success>,
    /// Per pair of methods and metric.
    pub paired: Vec<Paired>,
    /// Worlds left out of a pair.
    pub unpaired: Vec<Unpaired>,
    /// Per method, metric and parameter.
    pub trends: Vec<Trend>,
    /// Per method and parameter.
    pub failure_bins: Vec<FailureBins>,
}

impl Report {
    /// One line per pair of methods: the metric with the smallest p-value.
    pub fn headline(&self) -> Vec<String> {
        let mut best: BTreeMap<(&str, &str), &Paired> = BTreeMap::new();
        for p in &self.paired {
            let Some(w) = &p.wilcoxon else { continue };
            let e = best.entry((&p.a, &p.b)).or_insert(p);
            if e.wilcoxon.as_ref().is_none_or(|x| w.p < x.p) {
                *e = p;
            }
        }
        best.values()
            .map(|p| {
                let w = p.wilcoxon.as_ref().expect("kept only with a test");
                format!(
                    "{} - {}: {} differs most (mean difference {:.4}, Wilcoxon p = {:.3e}, n = {}; {} lower on {:.0} % of worlds)",
                    p.a,
                    p.b,
                    p.metric,
                    p.mean_difference,
                    w.p,
                    p.n,
                    p.a,
                    100.0 * p.a_lower
                )
            })
            .collect()
    }
}

fn summary(method: &str, scope: &str, metric: &str, x: &[f64], seed: u64, b: usize) -> Summary {
    Summary {
        method: method.to_owned(),
        scope: scope.to_owned(),
        metric: metric.to_owned(),
        n: x.len(),
        mean: sample::mean(x),
        median: sample::median(x),
        ci95: sample::bootstrap(x, seed, b),
    }
}

fn success(method: &str, scope: &str, runs: &[&Run]) -> Option<Success> {
    let flags: Vec<bool> = runs.iter().filter_map(|r| r.failed).collect();
    if flags.is_empty() {
        return None;
    }
    let failures = flags.iter().filter(|f| **f).count();
    let n = flags.len();
    Some(Success {
        method: method.to_owned(),
        scope: scope.to_owned(),
        runs: n,
        failures,
        rate: (n - failures) as f64 / n as f64,
        wilson95: sample::wilson(n - failures, n),
    })
}

/// Computes the report of merged runs.
pub fn analyse(list: &[Run], seed: u64, resamples: usize) -> Result<Report, Error> {
    let mut infos: BTreeMap<PathBuf, (PathBuf, WorldInfo)> = BTreeMap::new();
    for r in list {
        if !infos.contains_key(&r.key) {
            infos.insert(r.key.clone(), (r.world.clone(), world::read(&r.world)?));
        }
    }
    let mut order: Vec<&PathBuf> = infos.keys().collect();
    order.sort_by(|a, b| infos[*a].1.name.cmp(&infos[*b].1.name).then(a.cmp(b)));
    let index: BTreeMap<&PathBuf, usize> = order.iter().enumerate().map(|(i, k)| (*k, i)).collect();
    let worlds: Vec<WorldRow> = order
        .iter()
        .map(|k| {
            let (path, w) = &infos[*k];
            WorldRow {
                name: w.name.clone(),
                path: path.clone(),
                preset: w.preset.clone(),
                parameters: PARAMETERS.iter().copied().zip(w.parameters).collect(),
                maps: w.maps.clone(),
            }
        })
        .collect();
    let methods: Vec<String> = list
        .iter()
        .map(|r| r.method.clone())
        .collect::<BTreeSet<_>>()
        .into_iter()
        .collect();
    // A number equal in every run is a setting.
    let mut seen: BTreeMap<&str, (f64, bool)> = BTreeMap::new();
    for r in list {
        for (m, v) in &r.metrics {
            let e = seen.entry(m).or_insert((*v, true));
            e.1 &= e.0 == *v;
        }
    }
    let constant: BTreeMap<String, f64> = seen
        .iter()
        .filter(|(_, (_, same))| *same)
        .map(|(m, (v, _))| ((*m).to_owned(), *v))
        .collect();
    let metrics: Vec<String> = seen
        .iter()
        .filter(|(_, (_, same))| !*same)
        .map(|(m, _)| (*m).to_owned())
        .collect();
    super::bounds::comparisons(methods.len(), metrics.len())?;
    let presets: BTreeSet<&str> = worlds.iter().map(|w| w.preset.as_str()).collect();
    let mut scopes: Vec<(String, Option<&str>)> = vec![("all".into(), None)];
    if presets.len() > 1 {
        scopes.extend(presets.iter().map(|p| (format!("preset {p}"), Some(*p))));
    }
    // Each method's runs in world order, gathered once (looked for in every pair before: a
    // thousand methods made that quadratic in the runs).
    let mut by_method: BTreeMap<&str, Vec<&Run>> = BTreeMap::new();
    for r in list {
        by_method.entry(r.method.as_str()).or_default().push(r);
    }
    for v in by_method.values_mut() {
        v.sort_by_key(|r| index[&r.key]);
    }
    let of = |m: &str| -> Vec<&Run> { by_method.get(m).cloned().unwrap_or_default() };
    let (mut summaries, mut successes, mut trends, mut failure_bins) =
        (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for m in &methods {
        let runs = of(m);
        for (scope, preset) in &scopes {
            let here: Vec<&Run> = runs
                .iter()
                .copied()
                .filter(|r| preset.is_none_or(|p| worlds[index[&r.key]].preset == p))
                .collect();
            for metric in &metrics {
                let x: Vec<f64> = here
                    .iter()
                    .filter_map(|r| r.metrics.get(metric).copied())
                    .collect();
                if !x.is_empty() {
                    summaries.push(summary(m, scope, metric, &x, seed, resamples));
                }
            }
            successes.extend(success(m, scope, &here));
        }
        for metric in &metrics {
            let have: Vec<&&Run> = runs
                .iter()
                .filter(|r| r.metrics.contains_key(metric))
                .collect();
            let y: Vec<f64> = have.iter().map(|r| r.metrics[metric]).collect();
            for (p, name) in PARAMETERS.iter().enumerate() {
                let x: Vec<f64> = have.iter().map(|r| infos[&r.key].1.parameters[p]).collect();
                trends.push(Trend {
                    method: m.clone(),
                    metric: metric.clone(),
                    parameter: name,
                    n: x.len(),
                    line: sample::fit(&x, &y),
                });
            }
        }
        let flagged: Vec<&&Run> = runs.iter().filter(|r| r.failed.is_some()).collect();
        if !flagged.is_empty() {
            let failed: Vec<bool> = flagged.iter().map(|r| r.failed == Some(true)).collect();
            for (p, name) in PARAMETERS.iter().enumerate() {
                let all: Vec<f64> = infos.values().map(|(_, w)| w.parameters[p]).collect();
                let x: Vec<f64> = flagged
                    .iter()
                    .map(|r| infos[&r.key].1.parameters[p])
                    .collect();
                failure_bins.push(FailureBins {
                    method: m.clone(),
                    parameter: name,
                    bins: sample::bins(&all, &x, &failed),
                });
            }
        }
    }
    let (mut paired, mut unpaired) = (Vec::new(), Vec::new());
    let keyed: BTreeMap<&str, BTreeMap<&PathBuf, &Run>> = by_method
        .iter()
        .map(|(m, v)| (*m, v.iter().map(|r| (&r.key, *r)).collect()))
        .collect();
    let no_runs = Vec::new();
    for (i, a) in methods.iter().enumerate() {
        for b in &methods[i + 1..] {
            let ra = by_method.get(a.as_str()).unwrap_or(&no_runs);
            let rb = by_method.get(b.as_str()).unwrap_or(&no_runs);
            let (by_a, by_b) = (&keyed[a.as_str()], &keyed[b.as_str()]);
            for (x, y, have) in [(a, b, ra), (b, a, rb)] {
                let other = if x == a { by_b } else { by_a };
                for r in have.iter().filter(|r| !other.contains_key(&r.key)) {
                    unpaired.push(Unpaired {
                        scored_by: x.clone(),
                        missing_from: y.clone(),
                        world: worlds[index[&r.key]].name.clone(),
                    });
                }
            }
            for metric in &metrics {
                let d: Vec<f64> = ra
                    .iter()
                    .filter_map(|r| {
                        let u = r.metrics.get(metric)?;
                        let v = by_b.get(&r.key)?.metrics.get(metric)?;
                        Some(u - v)
                    })
                    .collect();
                if d.is_empty() {
                    continue;
                }
                let n = d.len() as f64;
                let share = |f: fn(&f64) -> bool| d.iter().filter(|x| f(x)).count() as f64 / n;
                paired.push(Paired {
                    a: a.clone(),
                    b: b.clone(),
                    metric: metric.clone(),
                    n: d.len(),
                    mean_difference: sample::mean(&d),
                    median_difference: sample::median(&d),
                    a_lower: share(|x| *x < 0.0),
                    b_lower: share(|x| *x > 0.0),
                    equal: share(|x| *x == 0.0),
                    wilcoxon: wilcoxon::test(&d),
                });
            }
        }
    }
    let runs = methods
        .iter()
        .flat_map(|m| of(m))
        .map(|r| RunRow {
            method: r.method.clone(),
            world: index[&r.key],
            score_folders: r.folders.clone(),
            failed: r.failed,
            metrics: r.metrics.clone(),
        })
        .collect();
    Ok(Report {
        format: "subtgraph-report/1",
        seed,
        resamples,
        bootstrap: BOOTSTRAP,
        wilcoxon: "two-sided signed-rank test as scipy.stats.wilcoxon's defaults (zero_method='wilcox', correction=False, method='auto'): exact without ties or zeros; ties or zeros among at most 13 differences: every sign flip counted; otherwise the normal approximation with the tie-corrected variance",
        success_rule: SUCCESS,
        pairing: PAIRING,
        metrics_rule: format!(
            "every number in a score folder's top-level JSON files, named FILE-STEM.KEY.KEY (arrays and the {} subtrees left out); a number equal in every run is a setting and is listed in `constant`",
            super::runs::NOT_METRICS.join(", ")
        ),
        methods,
        metrics,
        constant,
        parameters: PARAMETERS,
        worlds,
        runs,
        summary: summaries,
        success: successes,
        paired,
        unpaired,
        trends,
        failure_bins,
    })
}
