//! Series: one figure of one (case, method, tolerance) of a suite in one environment, night after
//! night. The runs of a series on a night are its tori (the quick suite runs every torus of a
//! point: mirror images doing the same work, docs/closed-form.md).

use std::collections::BTreeMap;

use rsts_harness::environment::Environment;
use rsts_validate::RunResult;
use rusqlite::params;
use serde::Serialize;

use crate::store::History;
use crate::HistoryError;

/// A figure kept per run.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub enum Metric {
    MaxStateError,
    MaxDrift,
    OffN,
    ClosedFormF64,
    ClosedFormResidual,
    MescdMin,
    ObservedOrder,
    Steps,
    RhsEvals,
    /// The timed figure: integration time, or the whole run for a closed-form check or a
    /// convergence run.
    Seconds,
}

impl Metric {
    pub const ALL: [Metric; 10] = [
        Metric::MaxStateError,
        Metric::MaxDrift,
        Metric::OffN,
        Metric::ClosedFormF64,
        Metric::ClosedFormResidual,
        Metric::MescdMin,
        Metric::ObservedOrder,
        Metric::Steps,
        Metric::RhsEvals,
        Metric::Seconds,
    ];

    /// The name in the database, in JSON and on the dashboard (report.json's names).
    pub fn name(self) -> &'static str {
        match self {
            Metric::MaxStateError => "max_state_error",
            Metric::MaxDrift => "max_drift",
            Metric::OffN => "off_N",
            Metric::ClosedFormF64 => "closed_form_f64",
            Metric::ClosedFormResidual => "closed_form_residual",
            Metric::MescdMin => "mescd_min",
            Metric::ObservedOrder => "observed_order",
            Metric::Steps => "steps",
            Metric::RhsEvals => "rhs_evals",
            Metric::Seconds => "seconds",
        }
    }

    pub fn from_name(name: &str) -> Option<Metric> {
        Metric::ALL.into_iter().find(|m| m.name() == name)
    }

    /// A timing (noisy; judged by step detection) rather than an exact figure.
    pub fn is_timing(self) -> bool {
        self == Metric::Seconds
    }

    /// Larger is worse (errors, drifts, cost, time); false for correct digits and the order.
    pub fn larger_is_worse(self) -> bool {
        !matches!(self, Metric::MescdMin | Metric::ObservedOrder)
    }
}

/// The figures of a run that a history keeps (exact values; NaN kept).
pub fn figures_of(run: &RunResult) -> Vec<(Metric, f64)> {
    let mut out = Vec::new();
    if let Some(f) = &run.figures {
        out.push((Metric::MaxStateError, f.max_state_error));
        out.push((Metric::MaxDrift, f.max_drift()));
        out.push((Metric::OffN, f.off_n));
        if let Some(d) = f.mescd_min {
            out.push((Metric::MescdMin, d));
        }
        if let Some(s) = f.steps {
            out.push((Metric::Steps, s as f64));
        }
        if let Some(e) = f.rhs_evals {
            out.push((Metric::RhsEvals, e as f64));
        }
    }
    if let Some(c) = &run.closed_form {
        out.push((Metric::ClosedFormF64, c.f64_error));
        out.push((Metric::ClosedFormResidual, c.residual));
    }
    if let Some(fit) = &run.convergence {
        out.push((Metric::ObservedOrder, fit.order));
    }
    let seconds = if run.figures.is_some() {
        run.timing.integration_seconds
    } else {
        run.timing.wall_seconds
    };
    // An untimed run (0) has no timing figure.
    if seconds > 0.0 {
        out.push((Metric::Seconds, seconds));
    }
    out
}

/// What names a series.
#[derive(Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub struct SeriesKey {
    pub suite: String,
    pub case: String,
    pub method: String,
    pub tolerance: String,
    pub metric: Metric,
    /// Id of the environment (CPU, SIMD path, cores, OS) in the history.
    pub environment: i64,
}

/// A night as the analysis and the dashboard see it.
#[derive(Clone, Debug, Serialize)]
pub struct NightInfo {
    pub id: i64,
    pub night: String,
    pub commit: String,
    pub rsts_version: String,
    pub suite: String,
    pub shard: String,
    pub runs: i64,
    pub passed: i64,
    pub failed: i64,
    pub errors: i64,
    pub wall_seconds: f64,
    pub report_dir: Option<String>,
    /// (shard, environment id, environment) of each machine of the night.
    pub machines: Vec<(String, i64, Environment)>,
}

/// One night of a series: its runs' (run id, value), sorted by run id.
#[derive(Clone, Debug, PartialEq)]
pub struct Point {
    /// Index into [`Data::nights`].
    pub night: usize,
    pub runs: Vec<(String, f64)>,
}

/// Everything the analysis and the dashboard read from a history.
#[derive(Clone, Debug, Default)]
pub struct Data {
    /// Nights in time order (then by id).
    pub nights: Vec<NightInfo>,
    pub environments: BTreeMap<i64, Environment>,
    /// Each series' points in night order.
    pub series: BTreeMap<SeriesKey, Vec<Point>>,
    /// The camera of each case (for the overview).
    pub cameras: BTreeMap<(String, String), String>,
    /// (night index, run id) of the runs that did not pass, with their status.
    pub failures: BTreeMap<(usize, String), String>,
}

impl History {
    /// Read the nights and every series.
    pub fn load(&self) -> Result<Data, HistoryError> {
        let mut data = Data::default();
        let mut stmt = self.conn.prepare(
            "SELECT id, night, commit_id, rsts_version, suite, shard, runs, passed, failed, errors,
                    wall_seconds, report_dir FROM nights ORDER BY night, id",
        )?;
        let rows = stmt.query_map([], |r| {
            Ok(NightInfo {
                id: r.get(0)?,
                night: r.get(1)?,
                commit: r.get(2)?,
                rsts_version: r.get(3)?,
                suite: r.get(4)?,
                shard: r.get(5)?,
                runs: r.get(6)?,
                passed: r.get(7)?,
                failed: r.get(8)?,
                errors: r.get(9)?,
                wall_seconds: r.get(10)?,
                report_dir: r.get(11)?,
                machines: Vec::new(),
            })
        })?;
        for n in rows {
            data.nights.push(n?);
        }
        let index: BTreeMap<i64, usize> = data
            .nights
            .iter()
            .enumerate()
            .map(|(k, n)| (n.id, k))
            .collect();
        let mut stmt = self.conn.prepare(
            "SELECT night_id, shard, environment_id, environment FROM night_machines ORDER BY night_id, shard",
        )?;
        let rows = stmt.query_map([], |r| {
            Ok((
                r.get::<_, i64>(0)?,
                r.get::<_, String>(1)?,
                r.get::<_, i64>(2)?,
                r.get::<_, String>(3)?,
            ))
        })?;
        for row in rows {
            let (night, shard, env_id, json) = row?;
            let env: Environment = serde_json::from_str(&json)
                .map_err(|e| HistoryError::Corrupt(format!("environment of night {night}: {e}")))?;
            data.environments
                .entry(env_id)
                .or_insert_with(|| env.clone());
            if let Some(&k) = index.get(&night) {
                data.nights[k].machines.push((shard, env_id, env));
            }
        }
        let mut stmt = self.conn.prepare(
            "SELECT r.night_id, n.suite, r.case_name, r.camera, r.method, r.tolerance,
                    r.environment_id, r.run_id, r.status, f.metric, f.bits
             FROM runs r JOIN nights n ON n.id = r.night_id
             JOIN figures f ON f.night_id = r.night_id AND f.run_id = r.run_id
             ORDER BY r.night_id, r.run_id, f.metric",
        )?;
        let mut rows = stmt.query(params![])?;
        while let Some(r) = rows.next()? {
            let night_id: i64 = r.get(0)?;
            let Some(&night) = index.get(&night_id) else {
                continue;
            };
            let metric_name: String = r.get(9)?;
            let Some(metric) = Metric::from_name(&metric_name) else {
                continue;
            };
            let (suite, case, camera): (String, String, String) = (r.get(1)?, r.get(2)?, r.get(3)?);
            let run_id: String = r.get(7)?;
            let status: String = r.get(8)?;
            if status != "pass" {
                data.failures.insert((night, run_id.clone()), status);
            }
            data.cameras.insert((suite.clone(), case.clone()), camera);
            let key = SeriesKey {
                suite,
                case,
                method: r.get(4)?,
                tolerance: r.get(5)?,
                metric,
                environment: r.get(6)?,
            };
            let value = f64::from_bits(r.get::<_, i64>(10)? as u64);
            let points = data.series.entry(key).or_default();
            match points.last_mut() {
                Some(p) if p.night == night => p.runs.push((run_id, value)),
                _ => points.push(Point {
                    night,
                    runs: vec![(run_id, value)],
                }),
            }
        }
        // Rows came in night-id order; nights are listed in time order.
        for points in data.series.values_mut() {
            points.sort_by_key(|p| p.night);
            for p in points.iter_mut() {
                p.runs.sort_by(|a, b| a.0.cmp(&b.0));
            }
        }
        Ok(data)
    }
}

/// The summary of a night's runs of a series: median, min and max (NaN counts as the worst).
pub fn summary(values: &[f64]) -> (f64, f64, f64) {
    if values.iter().any(|v| v.is_nan()) {
        return (f64::NAN, f64::NAN, f64::NAN);
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    let median = if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    };
    (median, v[0], v[n - 1])
}
