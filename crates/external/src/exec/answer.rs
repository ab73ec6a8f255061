//! The answer of an [`Exec`]: JSON (samples, `name`, `stats`, `digits`, `version`, `events`,
//! `dense`) or the CSV of `rsts check`, checked against the request's times.

use rug::Float;
use serde_json::Value;

use rsts_dynamics::integrators::Stats;
use rsts_harness::HarnessError;

use super::answer_doc::AnswerDoc;
use super::Exec;
use crate::files::parse_csv;

impl Exec {
    /// Parse an answer for `times` into states at `bits` bits.
    pub fn parse_answer(
        &mut self,
        stdout: &[u8],
        stderr: &[u8],
        times: &[f64],
        bits: u32,
    ) -> Result<(Vec<rsts_dynamics::State<Float>>, Stats), HarnessError> {
        let text = std::str::from_utf8(stdout)
            .map_err(|_| self.fail("its answer is not UTF-8 text", stderr))?;
        let garbage = |e: String| {
            let start: String = text.trim().chars().take(200).collect();
            self.fail(
                format_args!(
                    "its answer is not an rsts-integrator/1 answer ({e}); it begins with: {start:?}"
                ),
                stderr,
            )
        };
        if text.trim().is_empty() {
            return Err(self.fail("it wrote no answer on stdout", stderr));
        }
        let mut answered = None;
        let mut digits = None;
        let mut version = None;
        let mut answered_events = None;
        let mut answered_dense = None;
        let (raw, stats) = if text.trim_start().starts_with('{') {
            // Read as a stream: only the samples asked for (and the dense ones) are kept.
            let doc =
                AnswerDoc::read(stdout, times.len()).map_err(|e| garbage(json_error(text, &e)))?;
            if let Some(name) = &doc.name {
                let name = name
                    .as_str()
                    .filter(|s| !s.trim().is_empty())
                    .ok_or_else(|| garbage("\"name\" must be a non-empty string".into()))?;
                answered = Some(name.to_string());
            }
            let stats = parse_stats(doc.stats.as_ref()).map_err(garbage)?;
            if let Some(d) = doc.digits.as_ref().filter(|d| !d.is_null()) {
                let d = d
                    .as_u64()
                    .filter(|d| (1..=10_000).contains(d))
                    .ok_or_else(|| {
                        garbage("\"digits\" must be a whole number from 1 to 10000".into())
                    })?;
                digits = Some(d as u32);
            }
            if let Some(k) = self.dense {
                let t_end = times.last().copied().unwrap_or(0.0);
                answered_dense = Some(
                    crate::dense::dense_of_answer(&doc, k, t_end)
                        .map_err(|e| self.fail(e, stderr))?,
                );
            }
            if let Some(v) = doc.version.as_ref().filter(|v| !v.is_null()) {
                version = Some(check_version(v).map_err(garbage)?);
            }
            answered_events = match doc.events {
                None => None,
                Some(events) => Some(events.map_err(garbage)?),
            };
            let samples = doc.samples.ok_or_else(|| {
                garbage(
                    "expected an object with \"samples\": [{\"t\", \"omega\", \"alpha\", \"beta\"}, ...]"
                        .to_string(),
                )
            })?;
            if let Some(e) = samples.error {
                return Err(garbage(e));
            }
            if samples.count != times.len() {
                return Err(self.fail(
                    format_args!(
                        "it answered {} samples for {} requested times",
                        samples.count,
                        times.len()
                    ),
                    stderr,
                ));
            }
            (samples.raw, stats)
        } else {
            if let Some(why) = stray_lines(text) {
                return Err(garbage(why));
            }
            (parse_csv(text).map_err(garbage)?, (None, None, None))
        };
        if answered.is_some() {
            self.answered_name = answered;
        }
        if digits.is_some() {
            self.answered_digits = digits;
        }
        if version.is_some() {
            self.answered_version = version;
        }
        self.answered_events = answered_events;
        self.answered_dense = answered_dense;
        if let (Some(k), None) = (self.dense, &self.answered_dense) {
            return Err(self.fail(
                format_args!("--dense {k} needs a JSON answer with \"stats.step_times\" and \"dense\" (docs/own-integrator.md); it answered CSV"),
                stderr,
            ));
        }
        if raw.len() != times.len() {
            return Err(self.fail(
                format_args!(
                    "it answered {} samples for {} requested times",
                    raw.len(),
                    times.len()
                ),
                stderr,
            ));
        }
        for (k, (t, want)) in raw.times.iter().zip(times).enumerate() {
            let got = t.to_f64();
            if (got - want).abs() > 1e-12 * want.abs().max(1.0) {
                return Err(self.fail(
                    format_args!("sample {k} is at t = {got}, requested t = {want}"),
                    stderr,
                ));
            }
        }
        let samples = raw.to_samples(bits);
        let (steps, rhs_evals, seconds) = stats;
        self.answered_stats = rsts_harness::StatedStats {
            steps,
            rejected_steps: None,
            rhs_evals,
            integration_seconds: seconds,
        };
        Ok((
            samples.states,
            Stats {
                accepted_steps: steps.unwrap_or(0),
                rejected_steps: 0,
                rhs_evals: rhs_evals.unwrap_or(0),
                integration_seconds: seconds.unwrap_or(f64::NAN),
            },
        ))
    }
}

type AnswerStats = (Option<u64>, Option<u64>, Option<f64>);

/// Longest `"version"` an answer may carry (characters).
pub const MAX_VERSION_CHARS: usize = 200;

/// Characters that change how the text around them is shown: the bidirectional embeddings,
/// overrides and isolates (U+202A–U+202E, U+2066–U+2069, and the marks U+200E, U+200F, U+061C)
/// and the line and paragraph separators (U+2028, U+2029). A version holding one could print as
/// another or break a table line.
pub fn is_format_control(c: char) -> bool {
    matches!(
        c,
        '\u{202A}'..='\u{202E}'
            | '\u{2066}'..='\u{2069}'
            | '\u{200E}'
            | '\u{200F}'
            | '\u{061C}'
            | '\u{2028}'
            | '\u{2029}'
    )
}

/// `version` of an answer: a non-empty string of at most [`MAX_VERSION_CHARS`] characters,
/// without control characters, bidirectional controls or line separators
/// ([`is_format_control`]; it is printed in tables).
fn check_version(v: &Value) -> Result<String, String> {
    let s = v
        .as_str()
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .ok_or("\"version\" must be a non-empty string")?;
    if s.chars().count() > MAX_VERSION_CHARS {
        return Err(format!(
            "\"version\" has {} characters, at most {MAX_VERSION_CHARS} are taken",
            s.chars().count()
        ));
    }
    if let Some(c) = s.chars().find(|&c| c.is_control() || is_format_control(c)) {
        return Err(format!(
            "\"version\" must not hold control characters, bidirectional controls or line \
             separators (it holds U+{:04X})",
            c as u32
        ));
    }
    Ok(s.to_string())
}

/// `stats` of an answer: every field optional, numbers or decimal strings (read as a JSON
/// trajectory file's, [`crate::files::parse_stats`]).
fn parse_stats(v: Option<&Value>) -> Result<AnswerStats, String> {
    let s = crate::files::parse_stats(v)?;
    Ok((s.steps, s.rhs_evals, s.integration_seconds))
}

/// stdout that is a JSON document after other lines (a stray print): the lines before it, named.
fn stray_lines(text: &str) -> Option<String> {
    let lines: Vec<&str> = text.lines().collect();
    let json = lines.iter().position(|l| l.trim_start().starts_with('{'))?;
    let first = lines.iter().find(|l| !l.trim().is_empty()).copied()?;
    let first: String = first.chars().take(80).collect();
    Some(format!(
        "stdout is not one JSON document: {json} line(s) before the JSON on line {} (the first: \
         {first:?}); write notes and progress to stderr, only the answer to stdout",
        json + 1
    ))
}

/// An invalid JSON answer named by what is there: NaN and Infinity (not JSON) said as such,
/// with the offending text, its line and column, and the sample index and field it is in.
fn json_error(text: &str, e: &serde_json::Error) -> String {
    let (line, column) = (e.line(), e.column());
    // The byte offset of the error: its line's start plus the column (1-based).
    let start: usize = text
        .split_inclusive('\n')
        .take(line.saturating_sub(1))
        .map(str::len)
        .sum();
    let at = (start + column.saturating_sub(1)).min(text.len());
    let at = (0..=at)
        .rev()
        .find(|&i| text.is_char_boundary(i))
        .unwrap_or(0);
    // The token where the parser stopped (it stops on its first character or just after).
    let from = text[..at]
        .rfind([',', ':', '[', '{', ' ', '\n'])
        .map_or(0, |i| i + 1);
    let token: String = text[from..]
        .chars()
        .take_while(|c| !matches!(c, ',' | ']' | '}' | '\n'))
        .take(40)
        .collect();
    let before = &text[..from];
    let field = before.rfind("\":").and_then(|end| {
        before[..end]
            .rfind('"')
            .map(|q| before[q + 1..end].to_string())
    });
    let samples = before.find("\"samples\"");
    let sample = samples.map(|s| before[s..].matches("\"t\"").count().saturating_sub(1));
    let mut place = format!("line {line}, column {column}");
    if let Some(k) = sample {
        place.push_str(&format!(", sample {k}"));
    }
    if let Some(f) = field {
        place.push_str(&format!(", field \"{f}\""));
    }
    let t = token.trim();
    if ["NaN", "-NaN", "Infinity", "-Infinity", "inf", "-inf", "nan"].contains(&t) {
        format!(
            "{t} at {place}: NaN and Infinity are not JSON numbers (the integrator failed \
             there, or its writer allows them: write finite numbers, or decimals as strings)"
        )
    } else {
        format!("invalid JSON at {place}, at {t:?}: {e}")
    }
}

/// The most bytes an answer of `samples` samples at `digits` digits may take: 1 MiB, plus per
/// sample ten values of up to `digits` + 40 characters and 400 of keys and layout (pretty JSON),
/// doubled. Far more than any honest answer; a bound on what an adapter can make us hold.
pub fn max_answer(samples: usize, digits: u32) -> usize {
    let per_sample = 10 * (digits as usize + 40) + 400;
    (1 << 20) + 2 * samples.saturating_mul(per_sample)
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;
    /// A stray line before the JSON and a NaN inside it are named as such (old texts: "line 1:
    /// the header lacks column(s) t, omega1, …" and "invalid JSON: … at line 1 column 47").
    #[test]
    fn stray_lines_and_nan_are_named() {
        let why = stray_lines("progress 10%\n{\"samples\": []}\n").unwrap();
        assert!(
            why.contains("not one JSON document") && why.contains("\"progress 10%\""),
            "{why}"
        );
        assert!(stray_lines("t,omega1\n0,1\n").is_none());
        let text = r#"{"samples": [{"t": 0, "omega": [1, 2, 3]}, {"t": 1, "omega": [NaN, 2, 3]}]}"#;
        let e = serde_json::from_str::<serde_json::Value>(text).unwrap_err();
        let why = json_error(text, &e);
        assert!(
            why.starts_with("NaN at line 1")
                && why.contains("sample 1")
                && why.contains("field \"omega\""),
            "{why}"
        );
        let text = "{\"samples\": [{\"t\": 0,\n \"alpha\": [Infinity]}]}";
        let e = serde_json::from_str::<serde_json::Value>(text).unwrap_err();
        let why = json_error(text, &e);
        assert!(
            why.starts_with("Infinity at line 2") && why.contains("\"alpha\""),
            "{why}"
        );
    }

    /// Bidirectional controls and line separators are refused like control characters.
    #[test]
    fn versions_cannot_reorder_or_break_a_line() {
        assert_eq!(check_version(&json!(" 1.2.3 ")).unwrap(), "1.2.3");
        for bad in [
            "1.0\u{202E}3.2",
            "a\u{2028}b",
            "x\u{2066}y",
            "v\u{200F}",
            "1\u{7}",
        ] {
            let e = check_version(&json!(bad)).unwrap_err();
            assert!(e.contains("must not hold"), "{bad:?}: {e}");
        }
        assert!(check_version(&json!("Ünïcode 1.0 — ok")).is_ok());
    }

    #[test]
    fn stats_are_optional_numbers_or_strings() {
        let s = parse_stats(Some(
            &json!({"steps": 10, "rhs_evals": "40", "integration_seconds": 0.5}),
        ))
        .unwrap();
        assert_eq!(s, (Some(10), Some(40), Some(0.5)));
        assert_eq!(parse_stats(None).unwrap(), (None, None, None));
        assert!(parse_stats(Some(&json!({"steps": -1}))).is_err());
        assert!(parse_stats(Some(&json!({"steps": 1.5}))).is_err());
        assert!(parse_stats(Some(&json!([1]))).is_err());
    }
}
