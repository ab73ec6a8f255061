//! report.json and report.md; regressions against a baseline; merging shard reports.
//!
//! Everything in report.json is a function of the suite, the build and the machine, except the
//! `timing` objects (per run and at the top), the regressions of kind `time`, the time the report
//! was made (`created`) and, in a merged report, its shards' `parts`: two runs of the same suite
//! (or a merge of its shards) give reports equal up to those — see [`Report::without_timings`].

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::Path;

use rsts_harness::environment::Environment;
use serde::{Deserialize, Serialize};

use crate::run::{nan_max, RunResult, Status};
use crate::shard::Shard;
use crate::ValidateError;

/// Version of the report format.
pub const FORMAT: u32 = 1;
/// Largest report.json read (a baseline, a shard to merge): a report of the most runs a suite
/// may have ([`crate::suite::MAX_RUNS`]) takes about 500 MiB (26 kB per run, the quick suite's
/// average); it is parsed as a stream into the report, no copy of its text.
pub const MAX_REPORT_BYTES: u64 = 1 << 30;
/// An error counts as grown when it is this many times its baseline…
pub const ERROR_GROWTH: f64 = 10.0;
/// …and the baseline is above this (below it the figure is zero for all purposes).
pub const ERROR_FLOOR: f64 = 1e-300;
/// A time counts as grown when it is this many times its baseline…
pub const TIME_GROWTH: f64 = 2.0;
/// …and the baseline took at least this long (shorter runs are timer noise).
pub const TIME_FLOOR: f64 = 5e-3;

/// Counts over the runs.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Summary {
    pub runs: usize,
    pub passed: usize,
    pub failed: usize,
    pub errors: usize,
    /// Runs per camera.
    pub cameras: BTreeMap<String, usize>,
}

/// A figure that got worse than its baseline.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Regression {
    pub id: String,
    /// `error` or `time`.
    pub kind: String,
    pub figure: String,
    pub baseline: f64,
    pub now: f64,
}

impl Regression {
    pub fn describe(&self) -> String {
        format!(
            "{}: {} {:.3e} -> {:.3e} ({:.1}x)",
            self.id,
            self.figure,
            self.baseline,
            self.now,
            self.now / self.baseline
        )
    }
}

/// What was compared with the baseline.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct BaselineComparison {
    pub runs_compared: usize,
    /// Runs of this report that the baseline does not have.
    pub new_runs: usize,
    pub regressions: Vec<Regression>,
}

/// Wall-clock time of the whole validation.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ReportTiming {
    pub wall_seconds: f64,
}

/// One shard of a merged report: when and where it ran.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Part {
    pub shard: Shard,
    pub created: Option<String>,
    pub environment: Option<Environment>,
}

/// report.json.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Report {
    pub format: u32,
    /// When the report was made (UTC, `2026-11-29T03:04:05Z`; a merged report: its earliest
    /// shard's); absent in reports written before it was recorded.
    #[serde(default)]
    pub created: Option<String>,
    /// The git commit and version of the rsts that ran the suite.
    #[serde(default)]
    pub commit: Option<String>,
    #[serde(default)]
    pub rsts_version: Option<String>,
    /// Where the runs ran (CPU, SIMD path, cores, OS); a merged report whose shards ran in
    /// different environments has none here and each shard's in `parts`.
    #[serde(default)]
    pub environment: Option<Environment>,
    /// A merged report: its shards, each with its time and environment.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub parts: Vec<Part>,
    pub suite: String,
    /// Digest of the expanded suite: shards of one suite share it.
    pub suite_digest: String,
    /// Runs in the whole suite (all shards).
    pub total_runs: usize,
    /// The shard this report covers; absent for a full or merged run.
    pub shard: Option<Shard>,
    pub summary: Summary,
    pub runs: Vec<RunResult>,
    pub baseline: Option<BaselineComparison>,
    pub timing: ReportTiming,
}

impl Report {
    pub fn new(
        suite: &str,
        digest: &str,
        total_runs: usize,
        shard: Option<Shard>,
        mut runs: Vec<RunResult>,
        wall_seconds: f64,
    ) -> Report {
        runs.sort_by(|x, y| x.id.cmp(&y.id));
        let mut summary = Summary {
            runs: runs.len(),
            ..Summary::default()
        };
        for r in &runs {
            match r.status {
                Status::Pass => summary.passed += 1,
                Status::Fail => summary.failed += 1,
                Status::Error => summary.errors += 1,
            }
            *summary.cameras.entry(r.camera.clone()).or_default() += 1;
        }
        let env = Environment::detect();
        Report {
            format: FORMAT,
            created: Some(rsts_io::utc::now_utc()),
            commit: Some(env.commit.clone()),
            rsts_version: Some(env.rsts_version.clone()),
            environment: Some(env),
            parts: Vec::new(),
            suite: suite.to_string(),
            suite_digest: digest.to_string(),
            total_runs,
            shard,
            summary,
            runs,
            baseline: None,
            timing: ReportTiming { wall_seconds },
        }
    }

    /// Read DIR/report.json (or a report.json path).
    pub fn read(path: &Path) -> Result<Report, ValidateError> {
        let file = if path.is_dir() {
            path.join("report.json")
        } else {
            path.to_path_buf()
        };
        let cannot = |e: &dyn std::fmt::Display| {
            ValidateError::Io(format!("cannot read {}: {e}", file.display()))
        };
        // Read as a stream (no copy of the text): at most MAX_REPORT_BYTES.
        let input =
            rsts_io::open_bounded(&file, MAX_REPORT_BYTES, "a report").map_err(|e| cannot(&e))?;
        let report: Report =
            serde_json::from_reader(std::io::BufReader::new(input)).map_err(|e| {
                if e.is_io() {
                    cannot(&e)
                } else {
                    ValidateError::Usage(format!(
                        "{} is not a validation report: {e}",
                        file.display()
                    ))
                }
            })?;
        if report.format != FORMAT {
            return Err(ValidateError::Usage(format!(
                "{}: report format {} (this rsts reads {FORMAT})",
                file.display(),
                report.format
            )));
        }
        Ok(report)
    }

    /// The report as JSON with every `timing` object, `created` and a merge's `parts` removed and
    /// time regressions dropped: what must be identical between a run and a rerun or a merge of
    /// shards on one machine.
    pub fn without_timings(&self) -> serde_json::Value {
        let mut v = serde_json::to_value(self).expect("report serialises");
        strip_timing(&mut v);
        if let Some(top) = v.as_object_mut() {
            top.remove("created");
            top.remove("parts");
        }
        if let Some(regs) = v
            .pointer_mut("/baseline/regressions")
            .and_then(|r| r.as_array_mut())
        {
            regs.retain(|r| r["kind"] != "time");
        }
        v
    }

    /// Compare with a baseline report, per run id.
    pub fn compare_with(&mut self, baseline: &Report) {
        let old: BTreeMap<&str, &RunResult> =
            baseline.runs.iter().map(|r| (r.id.as_str(), r)).collect();
        let mut cmp = BaselineComparison::default();
        for r in &self.runs {
            let Some(b) = old.get(r.id.as_str()) else {
                cmp.new_runs += 1;
                continue;
            };
            cmp.runs_compared += 1;
            for (figure, before, now) in error_figures(b)
                .into_iter()
                .zip(error_figures(r))
                .filter_map(|((name, before), (_, now))| Some((name, before?, now?)))
            {
                // NaN now, finite before: a regression too.
                if before > ERROR_FLOOR && (now.is_nan() || now > ERROR_GROWTH * before) {
                    cmp.regressions.push(Regression {
                        id: r.id.clone(),
                        kind: "error".into(),
                        figure: figure.into(),
                        baseline: before,
                        now,
                    });
                }
            }
            let (before, now) = (time_of(b), time_of(r));
            if before >= TIME_FLOOR && now > TIME_GROWTH * before {
                cmp.regressions.push(Regression {
                    id: r.id.clone(),
                    kind: "time".into(),
                    figure: time_name(r).into(),
                    baseline: before,
                    now,
                });
            }
        }
        cmp.regressions
            .sort_by(|x, y| (&x.id, &x.figure).cmp(&(&y.id, &y.figure)));
        self.baseline = Some(cmp);
    }

    /// Runs that missed thresholds or could not be done, then regressions: one line each.
    pub fn problems(&self) -> Vec<String> {
        let mut out = Vec::new();
        for r in &self.runs {
            match r.status {
                Status::Pass => {}
                Status::Fail => out.push(format!("FAIL {}: {}", r.id, r.failures.join("; "))),
                Status::Error => out.push(format!(
                    "ERROR {}: {}",
                    r.id,
                    r.error.as_deref().unwrap_or("")
                )),
            }
        }
        if let Some(b) = &self.baseline {
            for reg in &b.regressions {
                out.push(format!("REGRESSION {}", reg.describe()));
            }
        }
        out
    }

    /// Write report.json and report.md into `dir` (plots are written by [`crate::plots`]).
    pub fn write(&self, dir: &Path, plots: &[(String, String)]) -> Result<(), ValidateError> {
        std::fs::create_dir_all(dir)
            .map_err(|e| ValidateError::Io(format!("cannot create {}: {e}", dir.display())))?;
        let json = serde_json::to_string_pretty(self).expect("report serialises");
        let put = |name: &str, text: &str| {
            let p = dir.join(name);
            std::fs::write(&p, text)
                .map_err(|e| ValidateError::Io(format!("cannot write {}: {e}", p.display())))
        };
        put("report.json", &(json + "\n"))?;
        put("report.md", &self.markdown(plots))
    }

    /// report.md: summary, problems, the table of runs, the plots.
    pub fn markdown(&self, plots: &[(String, String)]) -> String {
        let mut s = String::new();
        let sm = &self.summary;
        let _ = writeln!(s, "# Validation report: {}\n", self.suite);
        let _ = writeln!(
            s,
            "Suite digest `{}`; {} of {} runs{}. **{} passed, {} failed, {} errors**{}.\n",
            self.suite_digest,
            sm.runs,
            self.total_runs,
            self.shard
                .map(|sh| format!(" (shard {sh})"))
                .unwrap_or_default(),
            sm.passed,
            sm.failed,
            sm.errors,
            match &self.baseline {
                Some(b) => format!(
                    "; against the baseline: {} runs compared, {} new, {} regressions",
                    b.runs_compared,
                    b.new_runs,
                    b.regressions.len()
                ),
                None => String::new(),
            }
        );
        let cams: Vec<String> = sm
            .cameras
            .iter()
            .map(|(c, n)| format!("{c}: {n}"))
            .collect();
        let _ = writeln!(s, "Runs per camera: {}.\n", cams.join(", "));
        let problems = self.problems();
        if !problems.is_empty() {
            let _ = writeln!(s, "## Problems\n");
            for p in &problems {
                let _ = writeln!(s, "- {}", p.replace('|', "\\|"));
            }
            s.push('\n');
        }
        let _ = writeln!(s, "## Runs\n");
        let _ = writeln!(
            s,
            "Max error: max |x_int − x_exact| over (ω, α, β) and the samples (closed form: |f64 − 50 digits|). Drift: max over H, K, G and the constraints (closed form: Euler–Poisson residual at 50 digits). Growth: fit of log(state error) against log t or t (p of t^p, λ of e^(λt)); off N likewise. Off N: drift of the on-N integral relations max(|K − r⁴m²|, |2G − p²H − r⁴m|) (blind to a departure from N inside the level set of the integrals). The error is: what dominates the state error — drift along the torus (phase error) or departure from N (distance of the state from its nearest point of N), with its growth and N's normal type (docs/stability.md). Time: integration (closed form: the whole check).\n"
        );
        let _ = writeln!(
            s,
            "| run | case | camera | method | max error | drift | off N | growth (error; off N) | the error is | time (s) | result |"
        );
        let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|---|");
        let e = |x: f64| format!("{x:.2e}");
        for r in &self.runs {
            let method = match (r.rtol, r.digits) {
                (Some(t), Some(d)) => format!("{} {t:e} ({d} digits)", r.method),
                (Some(t), None) => format!("{} {t:e}", r.method),
                _ => r.method.clone(),
            };
            let (err, drift, off) = match (&r.figures, &r.closed_form) {
                (Some(f), _) => (e(f.max_state_error), e(f.max_drift()), e(f.off_n)),
                (None, Some(c)) => (e(c.f64_error), e(c.residual), "".into()),
                _ => ("".into(), "".into(), "".into()),
            };
            let g = |x: &Option<crate::growth::Growth>| {
                x.map(|g| g.describe()).unwrap_or_else(|| "–".into())
            };
            let growth = if r.figures.is_some() {
                format!("{}; {}", g(&r.growth.state_error), g(&r.growth.off_n))
            } else {
                String::new()
            };
            // A convergence run shows its observed order in the "the error is" column.
            let order = r.convergence.as_ref().map(|f| {
                format!(
                    "observed order {:.3} ± {:.3} (steps {:.2e} to {:.2e})",
                    f.order, f.order_stderr, f.window[0], f.window[1]
                )
            });
            let split = match (&r.error_split, &r.normal, &r.phase_error) {
                (Some(s), Some(n), Some(p)) => {
                    let growth = if s.dominant == "departure from N" {
                        &n.growth
                    } else {
                        &p.growth
                    };
                    let g = growth.map(|g| format!(", {}", g.describe()));
                    format!("{}{} (N {})", s.dominant, g.unwrap_or_default(), n.kind)
                }
                _ => order.unwrap_or_default(),
            };
            let result = match r.status {
                Status::Pass => "pass".to_string(),
                Status::Fail => format!("**FAIL**: {}", r.failures.join("; ")),
                Status::Error => format!("**ERROR**: {}", r.error.as_deref().unwrap_or("")),
            };
            let _ = writeln!(
                s,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.3} | {} |",
                r.id,
                r.case,
                r.camera,
                method,
                err,
                drift,
                off,
                growth,
                split,
                time_of(r),
                result.replace('|', "\\|")
            );
        }
        if !plots.is_empty() {
            let _ = writeln!(s, "\n## Plots\n");
            for (file, title) in plots {
                let _ = writeln!(s, "- [{title}]({file})");
            }
        }
        s
    }
}

fn strip_timing(v: &mut serde_json::Value) {
    match v {
        serde_json::Value::Object(map) => {
            map.remove("timing");
            for x in map.values_mut() {
                strip_timing(x);
            }
        }
        serde_json::Value::Array(a) => a.iter_mut().for_each(strip_timing),
        _ => {}
    }
}

/// The error figures of a run compared with the baseline.
fn error_figures(r: &RunResult) -> Vec<(&'static str, Option<f64>)> {
    let f = r.figures.as_ref();
    let c = r.closed_form.as_ref();
    vec![
        ("max_state_error", f.map(|f| f.max_state_error)),
        ("max_drift", f.map(|f| f.max_drift())),
        ("off_N", f.map(|f| f.off_n)),
        ("closed_form_f64", c.map(|c| c.f64_error)),
        ("closed_form_residual", c.map(|c| c.residual)),
    ]
}

fn time_of(r: &RunResult) -> f64 {
    if r.figures.is_some() {
        r.timing.integration_seconds
    } else {
        r.timing.wall_seconds
    }
}

fn time_name(r: &RunResult) -> &'static str {
    if r.figures.is_some() {
        "integration_seconds"
    } else {
        "wall_seconds"
    }
}

/// Join shard reports into the report of the whole suite.
pub fn merge(parts: &[Report]) -> Result<Report, ValidateError> {
    let first = parts
        .first()
        .ok_or_else(|| ValidateError::Usage("merge: no reports given".into()))?;
    let bad = |m: String| ValidateError::Usage(format!("merge: {m}"));
    let mut seen_shards = BTreeSet::new();
    let mut ids = BTreeSet::new();
    let mut runs = Vec::new();
    let mut wall = 0.0f64;
    let n = first.shard.map_or(1, |s| s.n);
    for p in parts {
        if p.suite_digest != first.suite_digest || p.suite != first.suite {
            return Err(bad(format!(
                "reports of different suites ({} {} and {} {})",
                first.suite, first.suite_digest, p.suite, p.suite_digest
            )));
        }
        let sh = p.shard.unwrap_or(Shard { k: 1, n: 1 });
        if sh.n != n {
            return Err(bad(format!(
                "shards of different counts ({n} and {})",
                sh.n
            )));
        }
        if !seen_shards.insert(sh.k) {
            return Err(bad(format!("shard {sh} given twice")));
        }
        for r in &p.runs {
            if !ids.insert(r.id.clone()) {
                return Err(bad(format!("run {} occurs in two reports", r.id)));
            }
            runs.push(r.clone());
        }
        wall = nan_max(wall, p.timing.wall_seconds);
    }
    let missing: Vec<String> = (1..=n)
        .filter(|k| !seen_shards.contains(k))
        .map(|k| format!("{k}/{n}"))
        .collect();
    if !missing.is_empty() {
        return Err(bad(format!("missing shard(s) {}", missing.join(", "))));
    }
    if runs.len() != first.total_runs {
        return Err(bad(format!(
            "the shards hold {} runs, the suite has {}",
            runs.len(),
            first.total_runs
        )));
    }
    let mut merged = Report::new(
        &first.suite,
        &first.suite_digest,
        first.total_runs,
        None,
        runs,
        wall,
    );
    // The night is the shards': their earliest time, their build, their environment (when they
    // share one), each shard's own in `parts`.
    merged.created = parts.iter().filter_map(|p| p.created.clone()).min();
    merged.commit = first.commit.clone();
    merged.rsts_version = first.rsts_version.clone();
    merged.environment = first
        .environment
        .clone()
        .filter(|e| parts.iter().all(|p| p.environment.as_ref() == Some(e)));
    merged.parts = parts
        .iter()
        .map(|p| Part {
            shard: p.shard.unwrap_or(Shard { k: 1, n: 1 }),
            created: p.created.clone(),
            environment: p.environment.clone(),
        })
        .collect();
    merged.parts.sort_by_key(|p| p.shard.k);
    // Regressions found by the shards against their baseline carry over.
    let with_baseline: Vec<&BaselineComparison> =
        parts.iter().filter_map(|p| p.baseline.as_ref()).collect();
    if !with_baseline.is_empty() {
        let mut b = BaselineComparison::default();
        for x in with_baseline {
            b.runs_compared += x.runs_compared;
            b.new_runs += x.new_runs;
            b.regressions.extend(x.regressions.iter().cloned());
        }
        b.regressions
            .sort_by(|x, y| (&x.id, &x.figure).cmp(&(&y.id, &y.figure)));
        merged.baseline = Some(b);
    }
    Ok(merged)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::{Figures, GrowthFits, Series, Timing};
    use crate::suite::Thresholds;

    fn result(id: &str, err: f64, seconds: f64) -> RunResult {
        RunResult {
            id: id.into(),
            case: "c".into(),
            camera: "I+".into(),
            a: 1.0,
            b: 0.5,
            m: 0.3,
            h: -0.375,
            torus: 0,
            t_end: 1.0,
            samples: 2,
            method: "dop853".into(),
            rtol: Some(1e-12),
            digits: None,
            thresholds: Thresholds::default(),
            status: Status::Pass,
            failures: vec![],
            error: None,
            figures: Some(Figures {
                max_state_error: err,
                ..Figures::default()
            }),
            closed_form: None,
            convergence: None,
            growth: GrowthFits::default(),
            series: Series::default(),
            normal: None,
            phase_error: None,
            error_split: None,
            timing: Timing {
                integration_seconds: seconds,
                wall_seconds: seconds,
            },
        }
    }

    fn report(runs: Vec<RunResult>) -> Report {
        Report::new("s", "d", runs.len(), None, runs, 1.0)
    }

    #[test]
    fn regressions_are_errors_grown_10x_and_times_grown_2x_above_the_floors() {
        let old = report(vec![
            result("a", 1e-10, 0.1),   // error ×10 exactly: not a regression
            result("b", 1e-10, 0.1),   // error ×11: regression
            result("c", 1e-310, 0.1),  // below the error floor: ignored
            result("d", 1e-10, 0.004), // faster than 5 ms: time ignored
            result("e", 1e-10, 0.01),  // time ×2.5: regression
            result("f", 1e-10, 0.1),   // NaN now: regression
        ]);
        let mut now = report(vec![
            result("a", 1e-9, 0.1),
            result("b", 1.1e-9, 0.1),
            result("c", 1.0, 0.1),
            result("d", 1e-10, 1.0),
            result("e", 1e-10, 0.025),
            result("f", f64::NAN, 0.1),
            result("g", 1.0, 1.0),
        ]);
        now.compare_with(&old);
        let b = now.baseline.as_ref().unwrap();
        assert_eq!((b.runs_compared, b.new_runs), (6, 1));
        let found: Vec<(&str, &str, &str)> = b
            .regressions
            .iter()
            .map(|r| (r.id.as_str(), r.kind.as_str(), r.figure.as_str()))
            .collect();
        assert_eq!(
            found,
            [
                ("b", "error", "max_state_error"),
                ("e", "time", "integration_seconds"),
                ("f", "error", "max_state_error"),
            ]
        );
        // Time regressions are not part of the report's identity; error regressions are.
        let v = now.without_timings();
        let kinds: Vec<&str> = v["baseline"]["regressions"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r["kind"].as_str().unwrap())
            .collect();
        assert_eq!(kinds, ["error", "error"]);
        assert!(v["runs"][0].get("timing").is_none() && v.get("timing").is_none());
        assert_eq!(now.problems().len(), 3);
    }

    #[test]
    fn merge_rejects_mixed_suites_duplicates_and_gaps() {
        let part = |k: usize, ids: &[&str], digest: &str| {
            let mut r = Report::new(
                "s",
                digest,
                3,
                Some(Shard { k, n: 2 }),
                ids.iter().map(|i| result(i, 1e-9, 0.1)).collect(),
                1.0,
            );
            r.shard = Some(Shard { k, n: 2 });
            r
        };
        let ok = merge(&[part(2, &["b"], "d"), part(1, &["a", "c"], "d")]).unwrap();
        let ids: Vec<&str> = ok.runs.iter().map(|r| r.id.as_str()).collect();
        assert_eq!(
            (ids, ok.shard, ok.summary.runs),
            (vec!["a", "b", "c"], None, 3)
        );
        let err = |parts: &[Report]| merge(parts).unwrap_err().to_string();
        assert!(
            err(&[part(1, &["a", "c"], "d"), part(2, &["b"], "x")]).contains("different suites")
        );
        assert!(err(&[part(1, &["a", "c"], "d"), part(1, &["b"], "d")]).contains("given twice"));
        assert!(err(&[part(1, &["a", "c"], "d")]).contains("missing shard(s) 2/2"));
        assert!(err(&[part(1, &["a", "c"], "d"), part(2, &["c"], "d")]).contains("two reports"));
        assert!(err(&[]).contains("no reports"));
    }
}
