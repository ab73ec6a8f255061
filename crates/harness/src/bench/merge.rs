//! An ensemble beyond one machine: `rsts bench --ensemble N --shard K/N` measures the motions
//! whose index is K − 1 modulo N (the whole ensemble is drawn in every shard, so the motions and
//! their indices are the same everywhere) and marks its report with an [`EnsembleShard`];
//! [`merge_shards`] joins the shards into the report an unsharded run writes: the same rows in
//! the same order (motion by motion, each motion's runs in the request's order), hence the same
//! fits and bands to the bit, the times being each shard's own.
//!
//! The merge refuses what cannot make that report: reports that are not shards, shards of
//! different requests ([`request_digest`]) or of different binaries (rsts version, commit, SIMD
//! path of the Taylor kernels: they may change the last bits), a shard count that differs, a
//! shard given twice or missing, a shard whose rows are not those of its motions or were altered
//! after it was written ([`EnsembleShard::rows`]). Each refusal names the shard and its file.

use std::collections::BTreeMap;
use std::io::Read;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::request::{BenchMethod, EnsemblePlan};
use super::{BenchReport, BenchRow, RowLabel};
use crate::ensemble::bands;
use crate::proportionality::fit_tolerances;
use crate::shard::{digest, Shard};
use crate::{Case, HarnessError};

/// Largest shard file read (a row is about 600 bytes in JSON: 1000 motions of 100 runs each
/// take 60 MB).
pub const MAX_SHARD_BYTES: u64 = 256 << 20;

/// What makes a report a shard of an ensemble (`shard` in its JSON).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EnsembleShard {
    pub k: usize,
    pub n: usize,
    /// [`request_digest`] of the request: the same in every shard of one benchmark.
    pub request: String,
    /// Digest of the rows as written (their JSON): a shard altered afterwards is refused.
    pub rows: String,
    /// Each row's label (taylor-mp with its digits) and whether its method came from outside.
    pub labels: Vec<RowLabel>,
}

impl EnsembleShard {
    pub(super) fn new(
        shard: Shard,
        request: String,
        rows: &[BenchRow],
        labels: &[RowLabel],
    ) -> Self {
        Self {
            k: shard.k,
            n: shard.n,
            request,
            rows: rows_digest(rows),
            labels: labels.to_vec(),
        }
    }

    pub fn shard(&self) -> Shard {
        Shard {
            k: self.k,
            n: self.n,
        }
    }
}

fn rows_digest(rows: &[BenchRow]) -> String {
    digest(
        serde_json::to_string(rows)
            .expect("rows serialise")
            .as_bytes(),
    )
}

/// The digest of what a benchmark over an ensemble is asked: the case (a, b, T, samples and
/// the rest), the methods in their order (a method from outside by its
/// [`OutsideMethod::identity`](super::OutsideMethod::identity)), the tolerances, repeats and
/// digits, the ensemble's size, seed and cameras — not the shard.
pub fn request_digest(
    case: &Case,
    methods: &[BenchMethod<'_>],
    tolerances: &[f64],
    repeats: usize,
    digits: Option<u32>,
    plan: &EnsemblePlan,
) -> String {
    #[derive(Serialize)]
    struct Key<'a> {
        case: &'a Case,
        methods: Vec<String>,
        tolerances: &'a [f64],
        repeats: usize,
        digits: Option<u32>,
        motions: usize,
        seed: u64,
        cameras: Vec<&'static str>,
    }
    let key = Key {
        case,
        methods: methods
            .iter()
            .map(|m| match m {
                BenchMethod::BuiltIn(name) => format!("built-in {}", name.as_str()),
                BenchMethod::Outside(o) => format!("outside {}", o.identity()),
            })
            .collect(),
        tolerances,
        repeats,
        digits,
        motions: plan.n,
        seed: plan.seed,
        cameras: plan.cameras.iter().map(|c| c.label()).collect(),
    };
    digest(
        serde_json::to_string(&key)
            .expect("key serialises")
            .as_bytes(),
    )
}

/// What `rsts bench merge` is asked: the JSON reports of the shards (any order).
#[derive(Clone, Debug, Default)]
pub struct BenchMergeRequest {
    pub shards: Vec<PathBuf>,
}

/// The merged report and notes for the user (shards that ran on different machines).
#[derive(Clone, Debug)]
pub struct BenchMerge {
    pub report: BenchReport,
    pub notes: Vec<String>,
}

fn refuse(message: String) -> HarnessError {
    HarnessError::Merge(message)
}

/// Read the shards' reports named in `request` (each at most [`MAX_SHARD_BYTES`]) and
/// [`merge_shards`] them.
pub fn bench_merge(request: &BenchMergeRequest) -> Result<BenchMerge, HarnessError> {
    if request.shards.is_empty() {
        return Err(refuse("no shards given".into()));
    }
    let parts = request
        .shards
        .iter()
        .map(|p| Ok((p.display().to_string(), read_shard(p)?)))
        .collect::<Result<Vec<_>, HarnessError>>()?;
    merge_shards(parts)
}

/// A report of `rsts bench --format json` (or `--json FILE`) read back.
pub fn read_shard(path: &Path) -> Result<BenchReport, HarnessError> {
    let what = path.display();
    let file = std::fs::File::open(path).map_err(|e| refuse(format!("{what}: {e}")))?;
    let meta = file
        .metadata()
        .map_err(|e| refuse(format!("{what}: {e}")))?;
    if !meta.is_file() {
        return Err(refuse(format!(
            "{what}: not a file (give the JSON reports of the shards)"
        )));
    }
    let mut text = String::new();
    file.take(MAX_SHARD_BYTES + 1)
        .read_to_string(&mut text)
        .map_err(|e| refuse(format!("{what}: {e}")))?;
    if text.len() as u64 > MAX_SHARD_BYTES {
        return Err(refuse(format!(
            "{what}: more than {MAX_SHARD_BYTES} bytes, larger than any shard's report"
        )));
    }
    if text.trim().is_empty() {
        return Err(refuse(format!(
            "{what}: empty (the shard did not finish: its task's log tells why)"
        )));
    }
    serde_json::from_str(&text).map_err(|e| {
        refuse(format!(
            "{what} is not the JSON report of `rsts bench --ensemble N --shard K/N`: {e}"
        ))
    })
}

/// Join the shards of one benchmark over an ensemble (each with the name of its file, for the
/// messages) into the report of the whole ensemble; see the module doc for what is refused.
pub fn merge_shards(parts: Vec<(String, BenchReport)>) -> Result<BenchMerge, HarnessError> {
    // Each part as (its shard, its name, its report), checked on its own first.
    let mut shards = Vec::with_capacity(parts.len());
    for (name, report) in parts {
        let Some(sh) = report.shard.clone() else {
            return Err(refuse(format!(
                "{name} is a whole report, not a shard (a shard is written by `rsts bench --ensemble N --shard K/N`)"
            )));
        };
        let Some(ensemble) = &report.ensemble else {
            return Err(refuse(format!("{name}: a shard without its ensemble")));
        };
        let shard = sh.shard();
        if shard.k == 0 || shard.k > shard.n {
            return Err(refuse(format!("{name}: shard {shard} (need 1 <= K <= N)")));
        }
        let named = format!("shard {shard} ({name})");
        if rows_digest(&report.rows) != sh.rows || sh.labels.len() != report.rows.len() {
            return Err(refuse(format!(
                "{named}: its rows are not those it was written with (altered afterwards?)"
            )));
        }
        // Its rows: every motion of its slice, in order, the same runs for each.
        let mine: Vec<usize> = (0..ensemble.n).filter(|&i| shard.holds(i)).collect();
        let mut by_motion: BTreeMap<usize, usize> = BTreeMap::new();
        for r in &report.rows {
            let Some(m) = r.motion.filter(|m| shard.holds(*m) && *m < ensemble.n) else {
                return Err(refuse(format!(
                    "{named}: a row of motion {} does not belong to this shard",
                    r.motion.map_or("(none)".into(), |m| m.to_string())
                )));
            };
            *by_motion.entry(m).or_default() += 1;
        }
        let in_order = report.rows.windows(2).all(|w| w[0].motion <= w[1].motion);
        if by_motion.len() != mine.len() || !in_order {
            return Err(refuse(format!(
                "{named}: holds {} of its {} motions{}",
                by_motion.len(),
                mine.len(),
                if in_order { "" } else { ", out of order" }
            )));
        }
        shards.push((shard, name, report));
    }
    shards.sort_by_key(|(sh, ..)| sh.k);
    let Some((first_shard, first_name, first)) = shards.first() else {
        return Err(refuse("no shards given".into()));
    };
    let first_sh = first.shard.as_ref().expect("checked");
    let mut notes = Vec::new();
    let mut seen: BTreeMap<usize, &str> = BTreeMap::new();
    for (shard, name, report) in &shards {
        let sh = report.shard.as_ref().expect("checked");
        if sh.request != first_sh.request
            || report.ensemble != first.ensemble
            || report.case != first.case
            || report.repeats != first.repeats
            || report.taylor_mp_digits != first.taylor_mp_digits
        {
            return Err(refuse(format!(
                "shard {first_shard} ({first_name}) and shard {shard} ({name}) are shards of different requests (digests {} and {}): every task must be given the same options but --shard",
                first_sh.request, sh.request
            )));
        }
        let (a, b) = (&first.environment, &report.environment);
        if (&a.rsts_version, &a.commit, &a.simd) != (&b.rsts_version, &b.commit, &b.simd) {
            return Err(refuse(format!(
                "shard {first_shard} ({first_name}) and shard {shard} ({name}) were computed by different binaries (rsts {} ({}), SIMD {} and rsts {} ({}), SIMD {}): the last bits may differ; run every shard with one build",
                a.rsts_version, a.commit, a.simd, b.rsts_version, b.commit, b.simd
            )));
        }
        if shard.n != first_shard.n {
            return Err(refuse(format!(
                "shards of different counts: {first_shard} ({first_name}) and {shard} ({name})"
            )));
        }
        if let Some(other) = seen.insert(shard.k, name) {
            return Err(refuse(format!(
                "shard {shard} given twice ({other} and {name})"
            )));
        }
        if (&a.cpu, a.cores, &a.os) != (&b.cpu, b.cores, &b.os) {
            notes.push(format!(
                "note: shard {shard} ran on {}, {} cores ({}), shard {first_shard} on {}, {} cores ({}): the time bands mix the machines",
                b.cpu, b.cores, b.os, a.cpu, a.cores, a.os
            ));
        }
    }
    let n = first_shard.n;
    let missing: Vec<String> = (1..=n)
        .filter(|k| !seen.contains_key(k))
        .map(|k| format!("{k}/{n}"))
        .collect();
    if !missing.is_empty() {
        return Err(refuse(format!(
            "missing shard(s) {} (given: {})",
            missing.join(", "),
            shards
                .iter()
                .map(|(sh, name, _)| format!("{sh} {name}"))
                .collect::<Vec<_>>()
                .join(", ")
        )));
    }
    // Every motion runs the same jobs: the labels of one motion's rows, the same in each shard.
    let mut pattern: Option<(&[RowLabel], &str)> = None;
    for (shard, name, report) in &shards {
        let sh = report.shard.as_ref().expect("checked");
        for (m, labels) in motion_runs(&report.rows, &sh.labels) {
            match pattern {
                None => pattern = Some((labels, name)),
                Some((p, _)) if p == labels => {}
                Some((_, first)) => {
                    return Err(refuse(format!(
                        "shard {shard} ({name}): motion {m} has other runs than the motions of {first} (another request?)"
                    )))
                }
            }
        }
    }

    // The rows motion by motion (each shard's rows are in order: a stable sort interleaves).
    let mut rows: Vec<(BenchRow, RowLabel)> = Vec::new();
    let mut environment = first.environment.clone();
    for (_, _, report) in &shards {
        let sh = report.shard.as_ref().expect("checked");
        rows.extend(report.rows.iter().cloned().zip(sh.labels.iter().cloned()));
        for a in &report.environment.adapters {
            if !environment.adapters.contains(a) {
                environment.adapters.push(a.clone());
            }
        }
    }
    rows.sort_by_key(|(r, _)| r.motion);
    let (rows, labels): (Vec<BenchRow>, Vec<RowLabel>) = rows.into_iter().unzip();
    let report = BenchReport {
        case: first.case.clone(),
        repeats: first.repeats,
        taylor_mp_digits: first.taylor_mp_digits,
        ensemble: first.ensemble.clone(),
        fits: fit_tolerances(&rows),
        bands: bands(&rows),
        rows,
        environment,
        shard: None,
        labels,
    };
    Ok(BenchMerge { report, notes })
}

/// The labels of each motion's rows (rows in motion order).
fn motion_runs<'a>(rows: &[BenchRow], labels: &'a [RowLabel]) -> Vec<(usize, &'a [RowLabel])> {
    let mut out = Vec::new();
    let mut start = 0;
    for i in 1..=rows.len() {
        if i == rows.len() || rows[i].motion != rows[start].motion {
            out.push((rows[start].motion.unwrap_or_default(), &labels[start..i]));
            start = i;
        }
    }
    out
}
