//! The dashboard: a static site written from a history, opened from the file system (no server,
//! no network, no script): `index.html` (cases × methods, each cell coloured by the latest change
//! of its series; the regressions; every night with its environment), `trend/*.html` (per case
//! and method: each tolerance's error, time with its min–max band and fitted levels, and steps
//! over the nights, regressions marked) and `night/*.html` (a night: its build, environments,
//! counts, and links to its report.md, SVG plots and MCAP logs). The plots are SVG drawn by
//! rsts-plots, inline in the pages.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use rsts_plots::{Chart, Scale, Series, Style};
use serde::Serialize;

use crate::detect::{self, Direction, SeriesVerdict};
use crate::series::{summary, Data, Metric, Point, SeriesKey};
use crate::{History, HistoryError};

/// Marker file of a dashboard directory: a directory holding anything else is not replaced.
pub const MARKER: &str = ".rsts-dashboard";
/// Most files listed from one night's report directory.
const MAX_LINKS: usize = 400;

/// The colour class of a cell or series by its latest change.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum State {
    Steady,
    Improved,
    Changed,
    Regressed,
}

impl State {
    fn class(self) -> &'static str {
        match self {
            State::Steady => "steady",
            State::Improved => "improved",
            State::Changed => "changed",
            State::Regressed => "regressed",
        }
    }
}

/// What was written.
#[derive(Debug, Serialize)]
pub struct Built {
    pub out: String,
    pub nights: usize,
    pub series: usize,
    pub cells: usize,
    pub regressions: usize,
    pub pages: usize,
}

/// A figure as text: counts as integers, others in the shortest form that reads back exactly.
fn num(v: f64) -> String {
    if v.is_finite() && v.fract() == 0.0 && v.abs() < 1e15 {
        format!("{}", v as i64)
    } else {
        format!("{v:e}")
    }
}

/// A regression's before or after: exact for accuracy, four digits for a timing level.
fn figure(r: &detect::Regression, v: f64) -> String {
    if r.kind == "timing" {
        format!("{v:.4e} s")
    } else {
        num(v)
    }
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A file name from free text (letters, digits, `-`, `_`, `.`; others as `_XX`).
fn slug(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' || c == '.' {
                c.to_string()
            } else {
                format!("_{:02X}", c as u32 & 0xff)
            }
        })
        .collect()
}

/// `file://` URL of an absolute path.
fn file_url(p: &Path) -> String {
    let mut s = String::from("file://");
    for b in p.to_string_lossy().bytes() {
        if b.is_ascii_alphanumeric() || b"/-_.~".contains(&b) {
            s.push(b as char);
        } else {
            let _ = write!(s, "%{b:02X}");
        }
    }
    s
}

const STYLE: &str = "body{font-family:Helvetica,Arial,sans-serif;margin:24px;color:#222}
table{border-collapse:collapse;margin:8px 0 20px}td,th{border:1px solid #ccc;padding:4px 8px;font-size:13px;text-align:left}
th{background:#f3f3f3}td.cell{text-align:center;min-width:90px}td.cell a{color:#222;text-decoration:none;display:block}
.steady{background:#f4f4f4}.improved{background:#b9e4c0}.changed{background:#fcd9a8}.regressed{background:#f4a6a6;font-weight:bold}
.legend span{padding:2px 8px;margin-right:6px;border:1px solid #ccc}.fail{color:#b00;font-weight:bold}
h2{margin-top:28px}figure{margin:6px 0 18px}code{font-size:12px}";

fn page(title: &str, up: &str, body: &str) -> String {
    format!(
        "<!doctype html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>{}</title>\n<link rel=\"stylesheet\" href=\"{up}style.css\"></head>\n<body>\n{body}</body></html>\n",
        esc(title)
    )
}

/// One cell of the overview: a (suite, case, method) and its series.
struct Cell {
    keys: Vec<SeriesKey>,
    state: State,
    /// Night index of the latest change and what it was.
    latest: Option<(usize, String)>,
    page: String,
}

/// State of a series from its verdict.
fn state_of(v: &SeriesVerdict) -> State {
    if v.regression.is_some() {
        return State::Regressed;
    }
    match v.changes.last().map(|c| c.direction) {
        None => State::Steady,
        Some(Direction::Better) => State::Improved,
        Some(Direction::Worse) | Some(Direction::Mixed) => State::Changed,
    }
}

/// Build the dashboard of the history at `history` into `out` (replaced whole when done; a
/// directory that holds anything but an earlier dashboard is refused).
pub fn build(history: &Path, out: &Path) -> Result<Built, HistoryError> {
    let data = History::open(history)?.load()?;
    if data.nights.is_empty() {
        return Err(HistoryError::Usage(format!(
            "{} holds no night yet: nothing to show",
            history.display()
        )));
    }
    let io = |e: std::io::Error| HistoryError::Io(format!("--out {}: {e}", out.display()));
    if out.is_dir() {
        let mut entries = std::fs::read_dir(out).map_err(io)?;
        if entries.next().is_some() && !out.join(MARKER).is_file() {
            return Err(HistoryError::Usage(format!(
                "--out {}: the directory holds files that are not a dashboard (no {MARKER}); it is replaced whole and they would be lost: give a new or empty directory, or an earlier dashboard",
                out.display()
            )));
        }
    }
    rsts_io::check_writable_dir(out).map_err(io)?;
    let dir = rsts_io::AtomicDir::create(out).map_err(io)?;
    let stage = dir.staging().to_path_buf();
    let verdicts: BTreeMap<&SeriesKey, SeriesVerdict> = data
        .series
        .iter()
        .map(|(k, p)| (k, detect::judge(&data, k, p)))
        .collect();
    // Cells.
    let mut cells: BTreeMap<(String, String, String), Cell> = BTreeMap::new();
    let mut used = BTreeSet::new();
    for (key, v) in &verdicts {
        let id = (key.suite.clone(), key.case.clone(), key.method.clone());
        let cell = cells.entry(id).or_insert_with(|| {
            let mut name = slug(&format!("{}--{}--{}", key.suite, key.case, key.method));
            while !used.insert(name.clone()) {
                name.push('_');
            }
            Cell {
                keys: Vec::new(),
                state: State::Steady,
                latest: None,
                page: format!("trend/{name}.html"),
            }
        });
        cell.keys.push((*key).clone());
        let s = state_of(v);
        cell.state = cell.state.max(s);
        let points = &data.series[*key];
        let latest = v
            .regression
            .as_ref()
            .map(|r| r.point)
            .or(v.changes.last().map(|c| c.point));
        if let Some(k) = latest {
            let night = points[k].night;
            let what = format!("{} {}", key.metric.name(), key.tolerance);
            if cell.latest.as_ref().is_none_or(|(n, _)| night > *n) {
                cell.latest = Some((night, what));
            }
        }
    }
    let write = |rel: &str, text: &str| -> Result<(), HistoryError> {
        let p = stage.join(rel);
        if let Some(d) = p.parent() {
            std::fs::create_dir_all(d).map_err(io)?;
        }
        std::fs::write(&p, text).map_err(io)
    };
    write(MARKER, "written by rsts dashboard\n")?;
    write("style.css", STYLE)?;
    let regressions: Vec<&detect::Regression> = verdicts
        .values()
        .filter_map(|v| v.regression.as_ref())
        .collect();
    write(
        "index.html",
        &overview(&data, &cells, &regressions, history),
    )?;
    let mut pages = 1;
    for ((suite, case, method), cell) in &cells {
        write(
            &cell.page,
            &trend(&data, &verdicts, suite, case, method, cell),
        )?;
        pages += 1;
    }
    for (k, n) in data.nights.iter().enumerate() {
        write(&format!("night/{}.html", n.id), &night_page(&data, k))?;
        pages += 1;
    }
    let built = Built {
        out: out.display().to_string(),
        nights: data.nights.len(),
        series: data.series.len(),
        cells: cells.len(),
        regressions: regressions.len(),
        pages,
    };
    dir.commit()
        .map_err(|e| HistoryError::Io(format!("--out: {e}")))?;
    Ok(built)
}

fn overview(
    data: &Data,
    cells: &BTreeMap<(String, String, String), Cell>,
    regressions: &[&detect::Regression],
    history: &Path,
) -> String {
    let mut b = String::new();
    let last = data.nights.last().expect("a night");
    let _ = writeln!(
        b,
        "<h1>rsts validation history</h1>\n<p>{} nights from {} to {} in <code>{}</code>; latest commit <code>{}</code>.</p>",
        data.nights.len(),
        esc(&data.nights[0].night),
        esc(&last.night),
        esc(&history.display().to_string()),
        esc(&last.commit)
    );
    let _ = writeln!(b, "<p class=\"legend\">Cells coloured by the latest change of their series: <span class=\"regressed\">regressed</span><span class=\"changed\">changed</span><span class=\"improved\">improved</span><span class=\"steady\">steady</span> (accuracy: any change of a bit; time: a step beyond the noise, docs/validation.md). A cell links to its trends.</p>");
    let _ = writeln!(
        b,
        "<h2 id=\"regressions\">Regressions ({})</h2>",
        regressions.len()
    );
    if regressions.is_empty() {
        let _ = writeln!(b, "<p>None.</p>");
    } else {
        let _ = writeln!(b, "<table><tr><th>run</th><th>metric</th><th>kind</th><th>last good night</th><th>first bad night</th><th>before</th><th>after</th><th>environment</th></tr>");
        for r in regressions {
            let page = cells
                .get(&(r.suite.clone(), r.case.clone(), r.method.clone()))
                .map(|c| c.page.clone())
                .unwrap_or_default();
            let _ = writeln!(
                b,
                "<tr class=\"regression\"><td><a href=\"{page}\">{}</a> ({})</td><td>{}</td><td>{}</td><td>{} <code>{}</code></td><td>{} <code>{}</code></td><td>{}</td><td>{}</td><td>{}</td></tr>",
                esc(&r.run_id),
                esc(&r.tolerance),
                r.metric,
                r.kind,
                esc(&r.last_good_night),
                esc(&r.last_good_commit),
                esc(&r.first_bad_night),
                esc(&r.first_bad_commit),
                figure(r, r.before),
                figure(r, r.after),
                esc(&r.environment_text)
            );
        }
        let _ = writeln!(b, "</table>");
    }
    // One table per suite: cases down, methods across.
    let suites: BTreeSet<&String> = cells.keys().map(|k| &k.0).collect();
    for suite in suites {
        let methods: BTreeSet<&String> = cells
            .keys()
            .filter(|k| &k.0 == suite)
            .map(|k| &k.2)
            .collect();
        let cases: BTreeSet<&String> = cells
            .keys()
            .filter(|k| &k.0 == suite)
            .map(|k| &k.1)
            .collect();
        let _ = writeln!(
            b,
            "<h2>Suite {}</h2>\n<table class=\"overview\"><tr><th>case</th><th>camera</th>",
            esc(suite)
        );
        for m in &methods {
            let _ = write!(b, "<th>{}</th>", esc(m));
        }
        let _ = writeln!(b, "</tr>");
        for case in cases {
            let camera = data
                .cameras
                .get(&(suite.clone(), case.clone()))
                .cloned()
                .unwrap_or_default();
            let _ = write!(b, "<tr><td>{}</td><td>{}</td>", esc(case), esc(&camera));
            for m in &methods {
                match cells.get(&(suite.clone(), case.clone(), (*m).clone())) {
                    None => {
                        let _ = write!(b, "<td></td>");
                    }
                    Some(c) => {
                        let what = match (&c.latest, c.state) {
                            (_, State::Steady) | (None, _) => "steady".to_string(),
                            (Some((n, what)), s) => format!(
                                "{} night {}<br><small>{}</small>",
                                s.class(),
                                n + 1,
                                esc(what)
                            ),
                        };
                        let fail = last_night_fails(data, c);
                        let _ = write!(
                            b,
                            "<td class=\"cell {}\" data-case=\"{}\" data-method=\"{}\"><a href=\"{}\">{}{}</a></td>",
                            c.state.class(),
                            esc(case),
                            esc(m),
                            c.page,
                            what,
                            if fail { " <span class=\"fail\">FAIL</span>" } else { "" }
                        );
                    }
                }
            }
            let _ = writeln!(b, "</tr>");
        }
        let _ = writeln!(b, "</table>");
    }
    let _ = writeln!(b, "<h2 id=\"nights\">Nights</h2>\n<table><tr><th>#</th><th>night (UTC)</th><th>commit</th><th>rsts</th><th>suite</th><th>shard</th><th>runs</th><th>passed</th><th>failed</th><th>errors</th><th>environment</th></tr>");
    for (k, n) in data.nights.iter().enumerate() {
        let envs: Vec<String> = n
            .machines
            .iter()
            .map(|(s, _, e)| format!("{s}: {}", env_text(e)))
            .collect();
        let _ = writeln!(
            b,
            "<tr><td><a href=\"night/{}.html\">{}</a></td><td>{}</td><td><code>{}</code></td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            n.id, k + 1, esc(&n.night), esc(&n.commit), esc(&n.rsts_version), esc(&n.suite), esc(&n.shard), n.runs, n.passed, n.failed, n.errors, esc(&envs.join("; "))
        );
    }
    let _ = writeln!(b, "</table>");
    page("rsts validation history", "", &b)
}

fn env_text(e: &rsts_harness::environment::Environment) -> String {
    format!("{}, {} cores, SIMD {}, {}", e.cpu, e.cores, e.simd, e.os)
}

/// Whether a run of the cell failed on the latest night that has it.
fn last_night_fails(data: &Data, c: &Cell) -> bool {
    c.keys.iter().any(|k| {
        data.series[k].last().is_some_and(|p| {
            p.runs
                .iter()
                .any(|(id, _)| data.failures.contains_key(&(p.night, id.clone())))
        })
    })
}

/// The primary exact figure of a cell's series: the state error, the closed form's, or the
/// observed order.
fn error_metric(keys: &[&SeriesKey]) -> Option<Metric> {
    [
        Metric::MaxStateError,
        Metric::ClosedFormF64,
        Metric::ObservedOrder,
    ]
    .into_iter()
    .find(|m| keys.iter().any(|k| k.metric == *m))
}

/// Night numbers (1-based) and worst values of a series.
fn worst_points(metric: Metric, points: &[Point]) -> Vec<(f64, f64)> {
    points
        .iter()
        .map(|p| {
            let v: Vec<f64> = p.runs.iter().map(|r| r.1).collect();
            let w = if metric.larger_is_worse() {
                v.iter().copied().fold(f64::NEG_INFINITY, f64::max)
            } else {
                v.iter().copied().fold(f64::INFINITY, f64::min)
            };
            ((p.night + 1) as f64, w)
        })
        .collect()
}

fn marker(label: &str, color: &str, pts: Vec<(f64, f64)>, labels: Vec<String>) -> Series {
    let mut s = Series::new(label, pts, Style::Markers).with_point_labels(labels);
    s.color = Some(color.into());
    s
}

fn svg(chart: &Chart) -> String {
    rsts_plots::render_svg(chart).unwrap_or_else(|e| format!("<p>({})</p>", esc(&e.to_string())))
}

fn trend(
    data: &Data,
    verdicts: &BTreeMap<&SeriesKey, SeriesVerdict>,
    suite: &str,
    case: &str,
    method: &str,
    cell: &Cell,
) -> String {
    let mut b = String::new();
    let _ = writeln!(
        b,
        "<p><a href=\"../index.html\">overview</a></p>\n<h1>{} · {} <small>({})</small></h1>\n<p>Suite {}. x: night number (the overview lists them). Red markers: a regression's first bad night; orange: another change for the worse; green: a change for the better.</p>",
        esc(case),
        esc(method),
        cell.state.class(),
        esc(suite)
    );
    // Group the cell's series by (tolerance, environment), regressed groups first.
    let mut groups: BTreeMap<(String, i64), Vec<&SeriesKey>> = BTreeMap::new();
    for k in &cell.keys {
        groups
            .entry((k.tolerance.clone(), k.environment))
            .or_default()
            .push(k);
    }
    // Regressed tolerances first.
    let mut groups: Vec<((String, i64), Vec<&SeriesKey>)> = groups.into_iter().collect();
    groups.sort_by_key(|(_, keys)| !keys.iter().any(|k| verdicts[*k].regression.is_some()));
    for ((tol, env), keys) in groups {
        let env_t = data
            .environments
            .get(&env)
            .map(env_text)
            .unwrap_or_default();
        let _ = writeln!(
            b,
            "<h2>{} {} <small>on {}</small></h2>",
            esc(method),
            esc(&tol),
            esc(&env_t)
        );
        for k in &keys {
            if let Some(r) = &verdicts[k].regression {
                let _ = writeln!(
                    b,
                    "<p class=\"regression\"><b>Regression of {}</b> ({}): first bad night {} (<code>{}</code>), last good {} (<code>{}</code>): {} → {}{}.</p>",
                    r.metric, r.kind, esc(&r.first_bad_night), esc(&r.first_bad_commit), esc(&r.last_good_night), esc(&r.last_good_commit), figure(r, r.before), figure(r, r.after),
                    r.ulps.map(|u| format!(", {u} ulps")).or(r.z.map(|z| format!(", {z:.1} standard errors"))).unwrap_or_default()
                );
            }
        }
        let title = format!("{case} {method} {tol}");
        let by = |m: Metric| keys.iter().find(|k| k.metric == m).copied();
        let marks = |key: &SeriesKey, y: &dyn Fn(usize) -> f64| -> Vec<Series> {
            let v = &verdicts[key];
            let points = &data.series[key];
            let mut out = Vec::new();
            let reg = v.regression.as_ref().map(|r| r.point);
            let (mut bad, mut better, mut worse) = (Vec::new(), Vec::new(), Vec::new());
            for c in &v.changes {
                let p = ((points[c.point].night + 1) as f64, y(c.point));
                if Some(c.point) == reg {
                    continue;
                } else if c.direction == Direction::Better {
                    better.push(p);
                } else {
                    worse.push(p);
                }
            }
            if let Some(k) = reg {
                bad.push(((points[k].night + 1) as f64, y(k)));
            }
            if !worse.is_empty() {
                out.push(marker("change (worse)", "#E69F00", worse, vec![]));
            }
            if !better.is_empty() {
                out.push(marker("change (better)", "#009E73", better, vec![]));
            }
            if !bad.is_empty() {
                let n = bad[0].0;
                out.push(marker(
                    "regression",
                    "#D00000",
                    bad,
                    vec![format!("night {n}")],
                ));
            }
            out
        };
        let mut charts = Vec::new();
        if let Some(m) = error_metric(&keys) {
            let key = by(m).expect("found");
            let pts = worst_points(m, &data.series[key]);
            let ys: Vec<f64> = pts.iter().map(|p| p.1).collect();
            let mut series = vec![Series::new(m.name(), pts, Style::LineMarkers)];
            series.extend(marks(key, &|k| ys[k]));
            let scale = if m == Metric::ObservedOrder {
                Scale::Linear
            } else {
                Scale::Log10
            };
            charts.push((
                "error",
                Chart {
                    title: format!("{title}: {} (worst run)", m.name()),
                    x_label: "night".into(),
                    y_label: m.name().into(),
                    x_scale: Scale::Linear,
                    y_scale: scale,
                    series,
                    width: 760,
                    height: 300,
                },
            ));
        }
        if let Some(key) = by(Metric::Seconds) {
            let points = &data.series[key];
            let stats: Vec<(f64, f64, f64, f64)> = points
                .iter()
                .map(|p| {
                    let v: Vec<f64> = p.runs.iter().map(|r| r.1).collect();
                    let (med, lo, hi) = summary(&v);
                    ((p.night + 1) as f64, med, lo, hi)
                })
                .collect();
            let mut median = Series::new(
                "median over the runs",
                stats.iter().map(|s| (s.0, s.1)).collect(),
                Style::LineMarkers,
            );
            median.band = stats.iter().map(|s| ((s.0, s.2), (s.0, s.3))).collect();
            let v = &verdicts[key];
            let mut levels = Series::new(
                "fitted levels",
                v.pieces
                    .iter()
                    .flat_map(|p| {
                        [
                            ((points[p.from].night + 1) as f64, p.level),
                            ((points[p.to - 1].night + 1) as f64, p.level),
                        ]
                    })
                    .collect(),
                Style::Line,
            );
            levels.dashed = true;
            levels.color = Some("#555555".into());
            let mut series = vec![median, levels];
            series.extend(marks(key, &|k| stats[k].1));
            charts.push((
                "time",
                Chart {
                    title: format!("{title}: time (median, min–max band)"),
                    x_label: "night".into(),
                    y_label: "seconds".into(),
                    x_scale: Scale::Linear,
                    y_scale: Scale::Log10,
                    series,
                    width: 760,
                    height: 300,
                },
            ));
        }
        let mut cost = Vec::new();
        for m in [Metric::Steps, Metric::RhsEvals] {
            if let Some(key) = by(m) {
                let pts = worst_points(m, &data.series[key]);
                let ys: Vec<f64> = pts.iter().map(|p| p.1).collect();
                cost.push(Series::new(m.name(), pts, Style::LineMarkers));
                cost.extend(marks(key, &|k| ys[k]));
            }
        }
        if !cost.is_empty() {
            charts.push((
                "steps",
                Chart {
                    title: format!("{title}: steps and evaluations"),
                    x_label: "night".into(),
                    y_label: "count".into(),
                    x_scale: Scale::Linear,
                    y_scale: Scale::Log10,
                    series: cost,
                    width: 760,
                    height: 300,
                },
            ));
        }
        for (kind, chart) in charts {
            let _ = writeln!(b, "<figure class=\"plot {kind}\">{}</figure>", svg(&chart));
        }
        // The figures night by night.
        let _ = writeln!(b, "<table><tr><th>#</th><th>night</th><th>commit</th>");
        for k in &keys {
            let _ = write!(b, "<th>{}</th>", k.metric.name());
        }
        let _ = writeln!(b, "</tr>");
        let nights: BTreeSet<usize> = keys
            .iter()
            .flat_map(|k| data.series[*k].iter().map(|p| p.night))
            .collect();
        for n in nights {
            let info = &data.nights[n];
            let _ = write!(b, "<tr><td><a href=\"../night/{}.html\">{}</a></td><td>{}</td><td><code>{}</code></td>", info.id, n + 1, esc(&info.night), esc(&info.commit));
            for k in &keys {
                let cell = data.series[*k].iter().find(|p| p.night == n).map(|p| {
                    let v: Vec<f64> = p.runs.iter().map(|r| r.1).collect();
                    let (med, _, _) = summary(&v);
                    num(med)
                });
                let _ = write!(b, "<td>{}</td>", cell.unwrap_or_default());
            }
            let _ = writeln!(b, "</tr>");
        }
        let _ = writeln!(b, "</table>");
    }
    page(&format!("{case} {method}: trends"), "../", &b)
}

/// Files of a report directory worth linking: report.md, *.svg, *.mcap, *.png (three levels).
fn report_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![(dir.to_path_buf(), 0)];
    while let Some((d, depth)) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        let mut entries: Vec<PathBuf> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
        entries.sort();
        for p in entries {
            if out.len() >= MAX_LINKS {
                return out;
            }
            if p.is_dir() && depth < 3 {
                stack.push((p, depth + 1));
            } else if p.extension().is_some_and(|e| {
                e == "md" || e == "svg" || e == "mcap" || e == "png" || e == "json"
            }) {
                out.push(p);
            }
        }
    }
    // The report itself first, then its subdirectories' files.
    out.sort_by_key(|p| (p.components().count(), p.clone()));
    out
}

fn night_page(data: &Data, k: usize) -> String {
    let n = &data.nights[k];
    let mut b = String::new();
    let _ = writeln!(
        b,
        "<p><a href=\"../index.html\">overview</a></p>\n<h1>Night {}: {}</h1>",
        k + 1,
        esc(&n.night)
    );
    let _ = writeln!(
        b,
        "<table><tr><th>commit</th><td><code>{}</code></td></tr><tr><th>rsts</th><td>{}</td></tr><tr><th>suite</th><td>{}</td></tr><tr><th>shard</th><td>{}</td></tr><tr><th>runs</th><td>{} ({} passed, {} failed, {} errors)</td></tr><tr><th>wall time</th><td>{:.1} s</td></tr></table>",
        esc(&n.commit), esc(&n.rsts_version), esc(&n.suite), esc(&n.shard), n.runs, n.passed, n.failed, n.errors, n.wall_seconds
    );
    let _ = writeln!(b, "<h2>Environment</h2>\n<table><tr><th>shard</th><th>CPU</th><th>SIMD path</th><th>cores</th><th>OS</th><th>adapters</th></tr>");
    for (shard, _, e) in &n.machines {
        let adapters: Vec<String> = e
            .adapters
            .iter()
            .map(|a| format!("{} {}", a.method, a.version))
            .collect();
        let _ = writeln!(
            b,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            esc(shard),
            esc(&e.cpu),
            esc(&e.simd),
            e.cores,
            esc(&e.os),
            esc(&adapters.join(", "))
        );
    }
    let _ = writeln!(b, "</table>");
    let failing: Vec<&String> = data
        .failures
        .iter()
        .filter(|((night, _), _)| *night == k)
        .map(|((_, id), _)| id)
        .collect();
    if !failing.is_empty() {
        let _ = writeln!(b, "<h2>Runs that did not pass ({})</h2><ul>", failing.len());
        for id in failing {
            let _ = writeln!(b, "<li class=\"fail\">{}</li>", esc(id));
        }
        let _ = writeln!(b, "</ul>");
    }
    let _ = writeln!(b, "<h2>Report</h2>");
    match &n.report_dir {
        None => {
            let _ = writeln!(b, "<p>No report directory recorded.</p>");
        }
        Some(d) => {
            let dir = Path::new(d);
            let files = report_files(dir);
            if files.is_empty() {
                let _ = writeln!(
                    b,
                    "<p>The report directory <code>{}</code> is not here any more.</p>",
                    esc(d)
                );
            } else {
                let _ = writeln!(b, "<p>In <code>{}</code>:</p><ul class=\"files\">", esc(d));
                for f in files {
                    let rel = f.strip_prefix(dir).unwrap_or(&f).display().to_string();
                    let _ = writeln!(b, "<li><a href=\"{}\">{}</a></li>", file_url(&f), esc(&rel));
                }
                let _ = writeln!(b, "</ul>");
            }
        }
    }
    page(&format!("night {}", n.night), "../", &b)
}
