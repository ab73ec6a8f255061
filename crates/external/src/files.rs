//! Trajectory files computed elsewhere, read for `rsts check` (and answers of external
//! integrators): CSV, JSON, npy and the `/integrated/state` channel of an rsts MCAP log.
//!
//! Every error names what is wrong and where: the line and column of a CSV, the JSON path of a
//! sample, the row and column of an npy array, the message of an MCAP log.

use std::path::Path;

use rsts_harness::StatedStats;
use serde_json::Value;

use crate::samples::{check_component, check_f64, check_text, Number, RawTrajectory};

/// Columns every trajectory has, in the order of `rsts explicit --format csv` and
/// `rsts integrate --format csv`.
pub const COLUMNS: [&str; 10] = [
    "t", "omega1", "omega2", "omega3", "alpha1", "alpha2", "alpha3", "beta1", "beta2", "beta3",
];

/// The formats `rsts check` reads, by file extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FileFormat {
    Csv,
    Json,
    Npy,
    Mcap,
}

impl FileFormat {
    /// The format of a file name (`.csv`, `.json`, `.npy`, `.mcap`, any case).
    pub fn of(path: &Path) -> Result<Self, String> {
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        match ext.as_str() {
            "csv" => Ok(Self::Csv),
            "json" => Ok(Self::Json),
            "npy" => Ok(Self::Npy),
            "mcap" => Ok(Self::Mcap),
            _ => Err(format!(
                "{}: unknown file type '{}' (expected .csv, .json, .npy or .mcap)",
                path.display(),
                ext
            )),
        }
    }
}

/// Read a trajectory file by its extension. The message of an error starts with the file name.
pub fn read_trajectory(path: &Path) -> Result<RawTrajectory, String> {
    let name = path.display().to_string();
    match FileFormat::of(path)? {
        FileFormat::Mcap => {
            let raw = read_mcap(path).map_err(|e| format!("{name}: {e}"))?;
            checked(raw, &name)
        }
        format => {
            let what = "a trajectory read whole";
            let bytes = rsts_io::read_bounded(path, crate::stream::MAX_WHOLE_BYTES, what)
                .map_err(|e| format!("{name}: cannot read ({e})"))?;
            parse_trajectory(&bytes, format, &name)
        }
    }
}

/// A trajectory from the bytes of a CSV, JSON or npy document (standard input, say; an MCAP
/// log is read from a file). The message of an error starts with `name`.
pub fn parse_trajectory(
    bytes: &[u8],
    format: FileFormat,
    name: &str,
) -> Result<RawTrajectory, String> {
    let text = || {
        std::str::from_utf8(bytes)
            .map_err(|e| format!("{name}: not UTF-8 text (byte {})", e.valid_up_to()))
    };
    let raw = match format {
        FileFormat::Csv => parse_csv(text()?),
        FileFormat::Json => {
            text()?;
            read_json_trajectory(bytes).map_err(|e| format!("{name}: {e}"))
        }
        FileFormat::Npy => parse_npy(bytes),
        FileFormat::Mcap => Err("an MCAP log is read from a file, not from a stream".into()),
    }
    .map_err(|e| format!("{name}: {e}"))?;
    checked(raw, name)
}

/// At least one sample, times strictly increasing.
fn checked(raw: RawTrajectory, name: &str) -> Result<RawTrajectory, String> {
    if raw.is_empty() {
        return Err(format!("{name}: no samples"));
    }
    raw.check_times().map_err(|e| format!("{name}: {e}"))?;
    Ok(raw)
}

/// Strip RFC 4180 quotes from a field.
pub(crate) fn unquote(s: &str) -> &str {
    let t = s.trim();
    t.strip_prefix('"')
        .and_then(|x| x.strip_suffix('"'))
        .unwrap_or(t)
}

/// The header of a CSV trajectory: where the ten [`COLUMNS`] are.
#[derive(Clone, Debug)]
pub(crate) struct CsvHeader {
    pub(crate) index: [usize; 10],
    pub(crate) fields: usize,
}

impl CsvHeader {
    /// The header on line `line` (`# ` of `numpy.savetxt` stripped).
    pub(crate) fn parse(line: usize, text: &str) -> Result<Self, String> {
        let header = text.trim_start_matches('#').trim();
        let names: Vec<&str> = header.split(',').map(unquote).collect();
        let mut index = [0usize; 10];
        let mut missing = Vec::new();
        for (slot, col) in index.iter_mut().zip(COLUMNS) {
            match names.iter().position(|n| *n == col) {
                Some(i) => *slot = i,
                None => missing.push(col),
            }
        }
        if !missing.is_empty() {
            return Err(format!(
                "line {line}: the header lacks column(s) {} (need {})",
                missing.join(", "),
                COLUMNS.join(",")
            ));
        }
        if let Some(twice) = COLUMNS
            .iter()
            .find(|col| names.iter().filter(|n| *n == *col).count() > 1)
        {
            return Err(format!(
                "line {line}: the header names column {twice} more than once (which one is meant?)"
            ));
        }
        Ok(Self {
            index,
            fields: names.len(),
        })
    }

    /// The sample on line `k`; `None` for a blank or comment line.
    pub(crate) fn row(
        &self,
        k: usize,
        line: &str,
    ) -> Result<Option<(Number, [Number; 9])>, String> {
        if line.trim().is_empty() || line.trim_start().starts_with('#') {
            return Ok(None);
        }
        let fields: Vec<&str> = line.split(',').map(unquote).collect();
        if fields.len() != self.fields {
            return Err(format!(
                "line {k}: {} fields, the header has {} (a truncated or malformed row)",
                fields.len(),
                self.fields
            ));
        }
        let index = &self.index;
        let value = |c: usize| {
            check_text(fields[index[c]])
                .and_then(|n| if c > 0 { check_component(n) } else { Ok(n) })
                .map_err(|e| format!("line {k}, column {} ({}): {e}", index[c] + 1, COLUMNS[c]))
        };
        let t = value(0)?;
        let mut state: [Number; 9] = std::array::from_fn(|_| Number::F64(0.0));
        for (c, slot) in state.iter_mut().enumerate() {
            *slot = value(c + 1)?;
        }
        Ok(Some((t, state)))
    }
}

/// CSV with a header naming at least the ten [`COLUMNS`] (any order; other columns are
/// ignored). A header written by `numpy.savetxt(..., header=...)` (starting with `# `) is
/// accepted; other lines starting with `#` and blank lines are skipped.
pub fn parse_csv(text: &str) -> Result<RawTrajectory, String> {
    // A byte-order mark (as spreadsheet programs write) is not part of the first column's name.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(k, l)| (k + 1, l.trim_end_matches('\r')));
    let header = loop {
        match lines.next() {
            None => return Err("empty: no header line".into()),
            Some((_, l)) if l.trim().is_empty() => continue,
            Some((k, l)) => break CsvHeader::parse(k, l)?,
        }
    };
    let mut raw = RawTrajectory::default();
    for (k, line) in lines {
        if let Some((t, state)) = header.row(k, line)? {
            raw.push(t, state, format!("line {k}"));
        }
    }
    Ok(raw)
}

/// A number or a decimal string.
fn json_number(v: &Value) -> Result<Number, String> {
    match v {
        Value::Number(n) => check_f64(n.as_f64().unwrap_or(f64::NAN)),
        Value::String(s) => check_text(s),
        other => Err(format!(
            "expected a number or a decimal string, got {other}"
        )),
    }
}

/// The `samples` of `rsts integrate --format json` (or of an external integrator's answer):
/// `{"samples": [{"t", "omega": [3], "alpha": [3], "beta": [3], ...}]}`, values as numbers or
/// decimal strings, and the `stats` block when there is one ([`parse_stats`]); other keys are
/// ignored.
pub fn parse_json(doc: &Value) -> Result<RawTrajectory, String> {
    let samples = doc
        .get("samples")
        .ok_or_else(|| {
            "expected an object with \"samples\": [{\"t\", \"omega\", \"alpha\", \"beta\"}, ...]"
                .to_string()
        })?
        .as_array()
        .ok_or_else(|| "\"samples\" must be an array".to_string())?;
    let mut raw = RawTrajectory::default();
    for (k, s) in samples.iter().enumerate() {
        let place = format!("samples[{k}]");
        let t = s
            .get("t")
            .ok_or_else(|| format!("{place}: no \"t\""))
            .and_then(|t| json_number(t).map_err(|e| format!("{place}.t: {e}")))?;
        let mut state: [Number; 9] = std::array::from_fn(|_| Number::F64(0.0));
        for (v, key) in ["omega", "alpha", "beta"].iter().enumerate() {
            let arr = s
                .get(key)
                .and_then(Value::as_array)
                .filter(|a| a.len() == 3)
                .ok_or_else(|| format!("{place}: \"{key}\" must be an array of 3 numbers"))?;
            for (i, x) in arr.iter().enumerate() {
                state[3 * v + i] = json_number(x)
                    .and_then(check_component)
                    .map_err(|e| format!("{place}.{key}[{i}]: {e}"))?;
            }
        }
        raw.push(t, state, place);
    }
    raw.stats = parse_stats(doc.get("stats"))?;
    Ok(raw)
}

/// A JSON trajectory file ([`parse_json`]'s layout and messages) read as a stream: the samples
/// go into the trajectory as they are parsed, other keys are skipped unread (memory is that of
/// the samples kept, not of a tree of the document). At most [`crate::stream::MAX_ROWS`]
/// samples are kept; more is refused.
pub fn read_json_trajectory(bytes: &[u8]) -> Result<RawTrajectory, String> {
    use crate::exec::answer_doc::AnswerDoc;
    let max = crate::stream::MAX_ROWS;
    let doc = AnswerDoc::read(bytes, max).map_err(|e| format!("not valid JSON ({e})"))?;
    let list = doc.samples.ok_or_else(|| {
        "expected an object with \"samples\": [{\"t\", \"omega\", \"alpha\", \"beta\"}, ...]"
            .to_string()
    })?;
    if let Some(e) = list.error {
        return Err(e);
    }
    if list.count > max {
        return Err(format!(
            "{} samples, above the limit of {max} (10⁸); check it in parts",
            list.count
        ));
    }
    let mut raw = list.raw;
    raw.stats = parse_stats(doc.stats.as_ref())?;
    Ok(raw)
}

/// The `stats` block of a JSON trajectory as `rsts integrate --format json` writes it
/// (`accepted_steps`, `rejected_steps`, `rhs_evals`, `integration_seconds`; `steps` as an
/// external integrator's answer names the accepted steps): every key optional, numbers or
/// decimal strings, non-negative, counts whole.
pub fn parse_stats(v: Option<&Value>) -> Result<StatedStats, String> {
    let Some(v) = v.filter(|v| !v.is_null()) else {
        return Ok(StatedStats::default());
    };
    if !v.is_object() {
        return Err("\"stats\" must be an object".into());
    }
    let num = |key: &str| -> Result<Option<f64>, String> {
        let x = match v.get(key) {
            None | Some(Value::Null) => return Ok(None),
            Some(Value::Number(n)) => n.as_f64(),
            Some(Value::String(s)) => s.trim().parse().ok(),
            Some(_) => None,
        };
        match x {
            Some(x) if x.is_finite() && x >= 0.0 => Ok(Some(x)),
            _ => Err(format!("stats.{key} must be a non-negative number")),
        }
    };
    let count = |key: &str| -> Result<Option<u64>, String> {
        match num(key)? {
            Some(x) if x.fract() == 0.0 && x < u64::MAX as f64 => Ok(Some(x as u64)),
            Some(_) => Err(format!("stats.{key} must be a whole number")),
            None => Ok(None),
        }
    };
    let steps = match (count("accepted_steps")?, count("steps")?) {
        (Some(a), Some(s)) if a != s => {
            return Err(format!(
                "stats.accepted_steps ({a}) and stats.steps ({s}) disagree"
            ))
        }
        (a, s) => a.or(s),
    };
    Ok(StatedStats {
        steps,
        rejected_steps: count("rejected_steps")?,
        rhs_evals: count("rhs_evals")?,
        integration_seconds: num("integration_seconds")?,
    })
}

/// An npy file (as `numpy.save` writes it): float64, shape (N, 10), columns t and the nine
/// components, or (N, 13) as `rsts reference` writes it (H, K, G after them, not read); C or
/// Fortran order.
pub fn parse_npy(bytes: &[u8]) -> Result<RawTrajectory, String> {
    let (npy, shape) = npy_open(bytes)?;
    let NpyShape { rows, width, .. } = shape;
    let data: Vec<f64> = npy.into_vec().map_err(|e| {
        format!("truncated or damaged data: {e} (expected {rows} rows of {width} float64)")
    })?;
    if data.len() != rows * width {
        return Err(format!(
            "truncated: {} values, expected {rows} rows of {width}",
            data.len()
        ));
    }
    npy_rows(&data, shape)
}

/// The rows of an npy trajectory from all its values (in the order of `shape`).
pub(crate) fn npy_rows(data: &[f64], shape: NpyShape) -> Result<RawTrajectory, String> {
    let NpyShape { rows, width, order } = shape;
    let at = |r: usize, c: usize| match order {
        npyz::Order::C => data[r * width + c],
        npyz::Order::Fortran => data[c * rows + r],
    };
    let mut raw = RawTrajectory::default();
    for r in 0..rows {
        let (t, state) = npy_row(r, |c| at(r, c))?;
        raw.push(t, state, format!("row {}", r + 1));
    }
    Ok(raw)
}

/// Rows, columns and order of an npy trajectory.
#[derive(Clone, Copy, Debug)]
pub(crate) struct NpyShape {
    pub rows: usize,
    pub width: usize,
    pub order: npyz::Order,
}

/// Longest npy header read (bytes after the length field): numpy's own `max_header_size`.
/// The header of an (N, 10) float64 array takes 118.
pub const MAX_NPY_HEADER_BYTES: u64 = 10_000;

/// The input with its npy header length checked against [`MAX_NPY_HEADER_BYTES`] before the
/// npy library reads it (a version 2 or 3 header whose length field says 4 GiB would otherwise
/// be allocated first). The bytes read to check it come first again.
pub(crate) fn npy_bounded<R: std::io::Read>(
    mut reader: R,
) -> Result<std::io::Chain<std::io::Cursor<Vec<u8>>, R>, String> {
    use std::io::Read;
    let mut prefix = Vec::with_capacity(12);
    // Magic (6), version (2), header length (2 bytes in version 1, 4 in versions 2 and 3).
    (&mut reader)
        .take(10)
        .read_to_end(&mut prefix)
        .map_err(|e| format!("cannot read ({e})"))?;
    if prefix.len() == 10 && prefix.starts_with(b"\x93NUMPY") {
        let len = match prefix[6] {
            1 => u64::from(u16::from_le_bytes([prefix[8], prefix[9]])),
            _ => {
                (&mut reader)
                    .take(2)
                    .read_to_end(&mut prefix)
                    .map_err(|e| format!("cannot read ({e})"))?;
                if prefix.len() < 12 {
                    return Err("not a valid npy file (truncated header)".into());
                }
                u64::from(u32::from_le_bytes([
                    prefix[8], prefix[9], prefix[10], prefix[11],
                ]))
            }
        };
        if len > MAX_NPY_HEADER_BYTES {
            return Err(format!(
                "not a valid npy file (its header says it is {len} bytes long, more than the \
                 {MAX_NPY_HEADER_BYTES} an npy header may have)"
            ));
        }
    }
    Ok(std::io::Cursor::new(prefix).chain(reader))
}

/// An npy file opened for reading: the header read, the values next.
pub(crate) type NpyReader<R> = npyz::NpyFile<std::io::Chain<std::io::Cursor<Vec<u8>>, R>>;

/// The header of an npy trajectory, checked: float64, (N, 10) or (N, 13); its length bounded
/// first ([`npy_bounded`]).
pub(crate) fn npy_open<R: std::io::Read>(reader: R) -> Result<(NpyReader<R>, NpyShape), String> {
    let npy = npyz::NpyFile::new(npy_bounded(reader)?)
        .map_err(|e| format!("not a valid npy file ({e})"))?;
    let dtype = match npy.dtype() {
        npyz::DType::Plain(ts) => ts.to_string(),
        other => other.descr(),
    };
    if dtype != "<f8" && dtype != ">f8" {
        return Err(format!(
            "dtype {dtype}: expected float64 ('<f8'); save with numpy.asarray(x, dtype=numpy.float64)"
        ));
    }
    let shape = npy.shape().to_vec();
    if shape.len() != 2 || (shape[1] != 10 && shape[1] != 13) {
        return Err(format!(
            "shape {shape:?}: expected (N, 10) (columns {}) or (N, 13) (with H,K,G)",
            COLUMNS.join(",")
        ));
    }
    let shape = NpyShape {
        rows: shape[0] as usize,
        width: shape[1] as usize,
        order: npy.order(),
    };
    Ok((npy, shape))
}

/// Row `r` (0-based) of an npy trajectory from its cells (t and the nine components first).
pub(crate) fn npy_row(
    r: usize,
    at: impl Fn(usize) -> f64,
) -> Result<(Number, [Number; 9]), String> {
    let cell = |c: usize| {
        check_f64(at(c))
            .and_then(|n| if c > 0 { check_component(n) } else { Ok(n) })
            .map_err(|e| format!("row {}, column {} ({}): {e}", r + 1, c + 1, COLUMNS[c]))
    };
    let t = cell(0)?;
    let mut state: [Number; 9] = std::array::from_fn(|_| Number::F64(0.0));
    for (c, slot) in state.iter_mut().enumerate() {
        *slot = cell(c + 1)?;
    }
    Ok((t, state))
}

/// The `/integrated/state` channel of an rsts MCAP log (`rsts compare --mcap`, `rsts check
/// --mcap`). A damaged log is refused (with how to recover what it holds).
pub fn read_mcap(path: &Path) -> Result<RawTrajectory, String> {
    let topic = rsts_mcap::topics::INTEGRATED_STATE;
    let series = rsts_mcap::inspect::extract(path, topic).map_err(|e| e.to_string())?;
    if series.recovered {
        return Err(format!(
            "the MCAP file is damaged ({}); extract what it holds with `rsts inspect {} --channel {topic} --format csv`",
            series.notes.join("; "),
            path.display()
        ));
    }
    let mut raw = RawTrajectory::default();
    for (k, p) in series.points.iter().enumerate() {
        let place = format!("message {} of {topic}", k + 1);
        let num = |v: Option<&Value>, what: &str| -> Result<Number, String> {
            v.and_then(Value::as_f64)
                .ok_or_else(|| format!("{place}: no number {what}"))
                .and_then(|x| check_f64(x).map_err(|e| format!("{place}: {what}: {e}")))
        };
        let t = num(p.value.get("t"), "t")?;
        let mut state: [Number; 9] = std::array::from_fn(|_| Number::F64(0.0));
        for (v, key) in ["omega", "alpha", "beta"].iter().enumerate() {
            let arr = p
                .value
                .get(key)
                .and_then(Value::as_array)
                .filter(|a| a.len() == 3)
                .ok_or_else(|| format!("{place}: \"{key}\" must be an array of 3 numbers"))?;
            for (i, x) in arr.iter().enumerate() {
                state[3 * v + i] = num(Some(x), &format!("{key}[{i}]")).and_then(|n| {
                    check_component(n).map_err(|e| format!("{place}: {key}[{i}]: {e}"))
                })?;
            }
        }
        raw.push(t, state, place);
    }
    Ok(raw)
}

/// Write `rows` (t and the nine components, or more columns) as an npy float64 array of shape
/// (N, width), C order, version 1.0 (what `numpy.save` writes).
pub fn npy_bytes(rows: &[Vec<f64>], width: usize) -> Vec<u8> {
    let mut out = npy_header(rows.len(), width);
    out.reserve(8 * rows.len() * width);
    for row in rows {
        debug_assert_eq!(row.len(), width);
        for x in row {
            out.extend_from_slice(&x.to_le_bytes());
        }
    }
    out
}

/// The header of a `.npy` file of `rows` × `width` float64 values (little-endian, C order); the
/// values follow it, row after row (so a file can be written one row at a time).
pub fn npy_header(rows: usize, width: usize) -> Vec<u8> {
    let mut header =
        format!("{{'descr': '<f8', 'fortran_order': False, 'shape': ({rows}, {width}), }}");
    // Magic (6) + version (2) + length (2) + header + '\n', padded to a multiple of 64.
    let total = 10 + header.len() + 1;
    header.push_str(&" ".repeat((64 - total % 64) % 64));
    header.push('\n');
    let mut out = Vec::with_capacity(10 + header.len());
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEADER: &str = "t,omega1,omega2,omega3,alpha1,alpha2,alpha3,beta1,beta2,beta3";

    #[test]
    fn csv_with_extra_and_reordered_columns() {
        let text =
            format!("H,{HEADER}\n1.5,0,0.1,0.2,0.3,1,0,0,0,1,0\n9,0.5,0.1,0.2,0.3,1,0,0,0,1,0\n");
        let raw = parse_csv(&text).unwrap();
        assert_eq!(raw.len(), 2);
        assert_eq!(raw.times[1], Number::Text("0.5".into()));
        assert_eq!(raw.states[0][0], Number::Text("0.1".into()));
        assert_eq!(raw.places[1], "line 3");
        let numpy = format!("# {HEADER}\n0,0,0,0,1,0,0,0,1,0\n");
        assert_eq!(parse_csv(&numpy).unwrap().len(), 1);
    }

    #[test]
    fn csv_errors_name_line_and_column() {
        let e = parse_csv("t,omega1\n0,1\n").unwrap_err();
        assert!(e.contains("lacks column(s) omega2"), "{e}");
        let e = parse_csv(&format!(
            "{HEADER}\n0,0,0,0,1,0,0,0,1,0\n1,0,nan,0,1,0,0,0,1,0\n"
        ))
        .unwrap_err();
        assert!(
            e.starts_with("line 3, column 3 (omega2)") && e.contains("NaN"),
            "{e}"
        );
        let e = parse_csv(&format!("{HEADER}\n0,0,0,0,1,0,0\n")).unwrap_err();
        assert!(e.starts_with("line 2: 7 fields, the header has 10"), "{e}");
        assert!(parse_csv("").unwrap_err().contains("empty"));
    }

    /// integrate's `stats` layout, the answer's `steps` for the accepted steps, absent keys
    /// unknown; values that are not counts are refused by name.
    #[test]
    fn json_stats_are_read_where_stated() {
        use serde_json::json;
        let s = parse_stats(Some(&json!({"accepted_steps": 341, "rejected_steps": 2,
            "rhs_evals": "2049", "integration_seconds": 1e-4})))
        .unwrap();
        assert_eq!(
            (
                s.steps,
                s.rejected_steps,
                s.rhs_evals,
                s.integration_seconds
            ),
            (Some(341), Some(2), Some(2049), Some(1e-4))
        );
        let s = parse_stats(Some(&json!({"steps": 7}))).unwrap();
        assert_eq!((s.steps, s.rhs_evals), (Some(7), None));
        assert_eq!(parse_stats(None).unwrap(), StatedStats::default());
        for (bad, key) in [
            (json!({"steps": 1.5}), "stats.steps must be a whole"),
            (
                json!({"rhs_evals": -1}),
                "stats.rhs_evals must be a non-negative",
            ),
            (json!({"steps": 1, "accepted_steps": 2}), "disagree"),
            (json!([1]), "must be an object"),
        ] {
            let e = parse_stats(Some(&bad)).unwrap_err();
            assert!(e.contains(key), "{bad}: {e}");
        }
    }

    #[test]
    fn json_samples_with_numbers_and_strings() {
        let doc: Value = serde_json::from_str(
            r#"{"samples": [{"t": 0, "omega": [0.1, "0.2", 0.3], "alpha": [1, 0, 0], "beta": [0, 1, 0], "H": 3}]}"#,
        )
        .unwrap();
        let raw = parse_json(&doc).unwrap();
        assert_eq!(raw.states[0][1], Number::Text("0.2".into()));
        let bad: Value =
            serde_json::from_str(r#"{"samples": [{"t": 0, "omega": [0.1, 0.3], "alpha": [1, 0, 0], "beta": [0, 1, 0]}]}"#)
                .unwrap();
        let e = parse_json(&bad).unwrap_err();
        assert!(e.starts_with("samples[0]: \"omega\""), "{e}");
        let e = parse_json(&serde_json::json!({"rows": []})).unwrap_err();
        assert!(e.contains("\"samples\""), "{e}");
    }

    #[test]
    fn npy_round_trip_and_errors() {
        let rows: Vec<Vec<f64>> = (0..3)
            .map(|k| (0..10).map(|c| k as f64 + 0.1 * c as f64).collect())
            .collect();
        let bytes = npy_bytes(&rows, 10);
        assert_eq!((bytes.len() - 8 * 30) % 64, 0, "header padded to 64");
        let raw = parse_npy(&bytes).unwrap();
        assert_eq!(raw.len(), 3);
        assert_eq!(raw.states[2][8], Number::F64(2.0 + 0.9));
        let e = parse_npy(&bytes[..bytes.len() - 5]).unwrap_err();
        assert!(e.contains("truncated"), "{e}");
        // The (N, 13) of `rsts reference`: H, K, G after the state are not read.
        let wide: Vec<Vec<f64>> = (0..3)
            .map(|k| (0..13).map(|c| k as f64 + 0.1 * c as f64).collect())
            .collect();
        let narrow: Vec<Vec<f64>> = wide.iter().map(|r| r[..10].to_vec()).collect();
        assert_eq!(
            parse_npy(&npy_bytes(&wide, 13)).unwrap(),
            parse_npy(&npy_bytes(&narrow, 10)).unwrap()
        );
        assert!(parse_npy(&npy_bytes(&[vec![0.0; 12]], 12)).is_err());
        let e = parse_npy(&npy_bytes(&[vec![0.0; 9]], 9)).unwrap_err();
        assert!(e.contains("shape [1, 9]"), "{e}");
        let e = parse_npy(b"hello").unwrap_err();
        assert!(e.contains("not a valid npy"), "{e}");
        let mut nan = rows.clone();
        nan[1][4] = f64::NAN;
        let e = parse_npy(&npy_bytes(&nan, 10)).unwrap_err();
        assert!(e.starts_with("row 2, column 5 (alpha1)"), "{e}");
    }
}
