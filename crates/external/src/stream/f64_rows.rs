//! f64 data read as f64: when the precision rule takes a trajectory as f64 data (every value of
//! at most 17 significant digits, [`crate::samples`]), `rsts check` reads its rows as f64
//! numbers — each CSV value checked and parsed once ([`text_f64`]), no decimal string, place
//! or MPFR number per value — with every check and message of
//! [`TrajectoryReader::next_chunk`].

use rsts_harness::{CheckStream, Observer};

use super::{
    csv_line, csv_row, line_text, plain_csv, too_many, Rows, Survey, TrajectoryReader, CHUNK_ROWS,
};
use crate::files::{npy_row, unquote, CsvHeader, COLUMNS};
use crate::samples::{
    check_component, comes_after, significant_digits, significant_digits_of_bytes, text_f64,
    time_order, Number, RawTrajectory, F64_TEXT_DIGITS,
};

/// Samples read as f64 numbers: times and states (ω, α, β).
#[derive(Clone, Debug, Default)]
pub struct F64Chunk {
    pub times: Vec<f64>,
    pub states: Vec<[f64; 9]>,
    /// The most significant digits of any value (0: all binary64).
    pub digits: usize,
    /// Where the first value of more than 17 significant digits is (high-precision data) — or,
    /// in a file read in one pass, the first time that only high-precision data tell apart from
    /// the one before (two decimals of one double): either way the file is read again, surveyed.
    pub long_at: Option<String>,
}

impl F64Chunk {
    pub fn len(&self) -> usize {
        self.times.len()
    }

    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// Samples read as numbers (the first chunk of a stream, read before the precision rule
    /// was decided on it) as f64.
    pub fn of_raw(raw: &RawTrajectory) -> Self {
        let long = |k: usize| {
            raw.times[k].digits() > F64_TEXT_DIGITS
                || raw.states[k].iter().any(|x| x.digits() > F64_TEXT_DIGITS)
        };
        Self {
            times: raw.times.iter().map(Number::to_f64).collect(),
            states: raw
                .states
                .iter()
                .map(|s| s.each_ref().map(Number::to_f64))
                .collect(),
            digits: raw.digits(),
            long_at: (0..raw.len())
                .find(|&k| long(k))
                .map(|k| raw.places[k].clone()),
        }
    }

    fn clear(&mut self) {
        self.times.clear();
        self.states.clear();
        self.digits = 0;
        self.long_at = None;
    }
}

/// Where a row was read, formatted only for a message.
enum Place {
    Line(usize),
    Row(usize),
    Named(String),
}

impl Place {
    fn show(&self) -> String {
        match self {
            Place::Line(k) => format!("line {k}"),
            Place::Row(r) => format!("row {}", r + 1),
            Place::Named(p) => p.clone(),
        }
    }
}

/// One row as f64, with its time's text (a decimal text; empty for a binary64 value).
#[derive(Default)]
pub(super) struct Row {
    pub(super) t: f64,
    pub(super) t_text: String,
    pub(super) x: [f64; 9],
    pub(super) digits: usize,
}

impl Row {
    fn time(&self) -> Number {
        if self.t_text.is_empty() {
            Number::F64(self.t)
        } else {
            Number::Text(self.t_text.clone())
        }
    }
}

impl TrajectoryReader {
    /// [`TrajectoryReader::next_chunk`] as f64 numbers, into `chunk`: false after the last
    /// row. Values of more than 17 digits are read (rounded to f64) and noted in the chunk.
    pub fn next_chunk_f64(&mut self, chunk: &mut F64Chunk) -> Result<bool, String> {
        chunk.clear();
        let name = &self.name;
        let mut row = Row::default();
        let mut previous = Row::default();
        let mut has_previous = false;
        if let Some((t, _)) = &self.last {
            previous.t = t.to_f64();
            if let Number::Text(s) = t {
                previous.t_text.push_str(s);
            }
            has_previous = true;
        }
        let mut last_place = None;
        // The first time out of order, reported once the chunk has been read (as next_chunk
        // reports it after the values).
        let mut out_of_order = None;
        while chunk.len() < CHUNK_ROWS {
            let Some(place) = self
                .rows
                .next_row_f64(&mut row)
                .map_err(|e| format!("{name}: {e}"))?
            else {
                break;
            };
            if has_previous && out_of_order.is_none() {
                // A time given as a text that is not 0 but reads as 0.0 is checked by time_order.
                let underflow = row.t == 0.0 && !row.t_text.is_empty();
                let ordered = row.t > previous.t && !underflow;
                if ordered {
                    // The usual case: nothing to say.
                } else if row.t == previous.t
                    && !underflow
                    && self.reread_if_long
                    && comes_after(&previous.time(), &row.time())
                {
                    // One double, two decimals: only high-precision data tell them apart, and a
                    // file read in one pass is f64 data only until a long value shows up. It is
                    // read again, surveyed, where the rule is decided for the whole file.
                    if chunk.long_at.is_none() {
                        chunk.long_at = Some(place.show());
                    }
                } else if let Err(e) =
                    time_order(&previous.time(), &row.time(), false, &place.show())
                {
                    out_of_order = Some(e);
                }
            }
            chunk.times.push(row.t);
            chunk.states.push(row.x);
            chunk.digits = chunk.digits.max(row.digits);
            if row.digits > F64_TEXT_DIGITS && chunk.long_at.is_none() {
                chunk.long_at = Some(place.show());
            }
            previous.t = row.t;
            std::mem::swap(&mut previous.t_text, &mut row.t_text);
            has_previous = true;
            last_place = Some(place);
        }
        if let Some(e) = out_of_order {
            return Err(format!("{name}: {e}"));
        }
        let Some(place) = last_place else {
            if self.read == 0 {
                return Err(format!("{name}: no samples"));
            }
            return Ok(false);
        };
        self.read += chunk.len();
        if self.read > super::MAX_ROWS {
            return Err(too_many(name, self.read));
        }
        self.last = Some((previous.time(), place.show()));
        Ok(true)
    }

    /// The survey of a file read through as f64 ([`TrajectoryReader::open_surveyed`]). A CSV
    /// is only scanned: the digits of its values counted and its times read; the values are
    /// checked when the rows are read for the analysis.
    pub(super) fn survey_f64(&mut self) -> Result<Survey, String> {
        let mut survey = Survey {
            rows: None,
            digits: 0,
            extent: 0.0,
        };
        if let Rows::Csv { .. } = self.rows {
            let name = &self.name;
            let rows = self
                .rows
                .scan_csv(&mut survey)
                .map_err(|e| format!("{name}: {e}"))?;
            if rows == 0 {
                return Err(format!("{name}: no samples"));
            }
            survey.rows = Some(rows);
            return Ok(survey);
        }
        let mut chunk = F64Chunk::default();
        while self.next_chunk_f64(&mut chunk)? {
            survey.digits = survey.digits.max(chunk.digits);
            survey.extent = chunk
                .times
                .iter()
                .fold(survey.extent, |m, t| m.max(t.abs()));
        }
        survey.rows = Some(self.read);
        Ok(survey)
    }
}

impl Rows {
    /// Scan the rest of a CSV: the most digits of a value and the largest |t| into `survey`,
    /// and the rows (lines that are neither blank nor comments).
    fn scan_csv(&mut self, survey: &mut Survey) -> Result<usize, String> {
        let Rows::Csv {
            input,
            header,
            line,
            buf,
            ..
        } = self
        else {
            return Ok(0);
        };
        let mut rows = 0;
        // The column of each field (None: a field not read).
        let mut column_of: Vec<Option<usize>> = Vec::new();
        while let Some(k) = csv_line(input, header, line, buf)? {
            let h = header.as_ref().expect("read before the rows");
            if column_of.is_empty() {
                let width = h.index.iter().max().map_or(0, |&i| i + 1);
                column_of = (0..width)
                    .map(|i| h.index.iter().position(|&j| j == i))
                    .collect();
            }
            if buf.is_ascii() {
                // The common case, on bytes: no UTF-8 check, no column search per field.
                if scan_ascii_row(buf, &column_of, survey) {
                    rows += 1;
                }
                continue;
            }
            let text = line_text(buf, k)?;
            if text.trim().is_empty() || text.trim_start().starts_with('#') {
                continue;
            }
            rows += 1;
            for (i, field) in text.split(',').enumerate() {
                let Some(c) = h.index.iter().position(|&j| j == i) else {
                    continue;
                };
                let value = unquote(field).trim();
                survey.digits = survey.digits.max(significant_digits(value));
                if c == 0 {
                    if let Ok(t) = value.parse::<f64>() {
                        survey.extent = survey.extent.max(t.abs());
                    }
                }
            }
        }
        Ok(rows)
    }

    /// [`Rows::next_row`] into `row`: its place, `None` after the last row.
    fn next_row_f64(&mut self, row: &mut Row) -> Result<Option<Place>, String> {
        match self {
            Rows::Csv {
                input,
                header,
                line,
                buf,
                layout,
            } => {
                if let Some(h) = header {
                    // A plain line straight from the buffer (the others as below).
                    let layout = layout.get_or_insert_with(|| plain_csv::Layout::of(h));
                    let bytes = input.fill_buf().map_err(|e| format!("cannot read ({e})"))?;
                    if let Some(n) = plain_csv::plain_row(bytes, layout, row) {
                        input.consume(n);
                        *line += 1;
                        return Ok(Some(Place::Line(*line)));
                    }
                }
                let read =
                    |h: &CsvHeader, k, text: &str| Ok(csv_row_f64(h, k, text, row)?.then_some(()));
                Ok(csv_row(input, header, line, buf, read)?.map(|(k, ())| Place::Line(k)))
            }
            Rows::Npy { .. } => {
                let Some(r) = self.next_npy_row()? else {
                    return Ok(None);
                };
                let Rows::Npy { row: cells, .. } = self else {
                    unreachable!()
                };
                let max = rsts_dynamics::state::MAX_COMPONENT;
                let fine = cells[0].is_finite()
                    && cells[1..10].iter().all(|x| x.is_finite() && x.abs() <= max);
                if !fine {
                    // The message of the row read as numbers.
                    npy_row(r, |c| cells[c])?;
                }
                row.t = cells[0];
                row.t_text.clear();
                row.x = std::array::from_fn(|c| cells[c + 1]);
                row.digits = 0;
                Ok(Some(Place::Row(r)))
            }
            Rows::Whole { .. } => {
                let Some((t, state, place)) = self.next_row()? else {
                    return Ok(None);
                };
                row.t = t.to_f64();
                row.t_text.clear();
                if let Number::Text(s) = &t {
                    row.t_text.push_str(s);
                }
                row.x = state.each_ref().map(Number::to_f64);
                row.digits = state
                    .iter()
                    .map(Number::digits)
                    .fold(t.digits(), usize::max);
                Ok(Some(Place::Named(place)))
            }
        }
    }
}

/// [`Rows::scan_csv`] of one ASCII line `buf`: false for a blank or comment line (blank as
/// `str::trim` sees it: the ASCII white space of `char::is_whitespace`).
fn scan_ascii_row(buf: &[u8], column_of: &[Option<usize>], survey: &mut Survey) -> bool {
    let space = |b: &u8| matches!(b, 9..=13 | b' ');
    let start = buf.iter().position(|b| !space(b));
    let Some(start) = start else {
        return false;
    };
    if buf[start] == b'#' {
        return false;
    }
    for (i, field) in buf.split(|&b| b == b',').enumerate() {
        let Some(Some(c)) = column_of.get(i) else {
            continue;
        };
        // Quotes and white space have no digits: counted on the field as it is.
        survey.digits = survey.digits.max(significant_digits_of_bytes(field));
        if *c == 0 {
            let t = std::str::from_utf8(field).map(|f| unquote(f).trim().parse::<f64>());
            if let Ok(Ok(t)) = t {
                survey.extent = survey.extent.max(t.abs());
            }
        }
    }
    true
}

/// The sample on CSV line `k` into `row` (false for a blank or comment line), each value
/// checked as [`CsvHeader::row`] checks it, with its messages.
fn csv_row_f64(h: &CsvHeader, k: usize, line: &str, row: &mut Row) -> Result<bool, String> {
    if line.trim().is_empty() || line.trim_start().starts_with('#') {
        return Ok(false);
    }
    let mut fields = [""; 10];
    let mut n = 0;
    for (i, field) in line.split(',').enumerate() {
        n += 1;
        if let Some(c) = h.index.iter().position(|&j| j == i) {
            fields[c] = unquote(field);
        }
    }
    if n != h.fields {
        return Err(format!(
            "line {k}: {n} fields, the header has {} (a truncated or malformed row)",
            h.fields
        ));
    }
    row.digits = 0;
    for (c, field) in fields.iter().enumerate() {
        let (x, digits) = text_f64(field)
            .and_then(|(x, d)| {
                if c > 0 {
                    check_component(Number::F64(x))?;
                }
                Ok((x, d))
            })
            .map_err(|e| format!("line {k}, column {} ({}): {e}", h.index[c] + 1, COLUMNS[c]))?;
        row.digits = row.digits.max(digits);
        if c == 0 {
            row.t = x;
            row.t_text.clear();
            row.t_text.push_str(field.trim());
        } else {
            row.x[c - 1] = x;
        }
    }
    Ok(true)
}

/// How [`check_rest_f64`] ended.
#[derive(Clone, Debug, PartialEq)]
pub enum RestF64 {
    /// Every row analysed (or the observer stopped the check).
    Done,
    /// A value of more than 17 digits at this place of a file opened without a survey of its
    /// digits ([`TrajectoryReader::open_f64`]): high-precision data, to be read again surveyed.
    HighPrecision(String),
}

/// [`super::check_rest`] of f64 data: the rows read as f64 and analysed in double-double
/// ([`CheckStream::feed_f64`]). A stream's value of more than 17 digits is refused; a file's
/// read in one pass ends the check with [`RestF64::HighPrecision`].
pub fn check_rest_f64(
    reader: &mut TrajectoryReader,
    check: &mut CheckStream,
    observer: &mut dyn Observer,
) -> Result<RestF64, String> {
    let mut chunk = F64Chunk::default();
    while reader.next_chunk_f64(&mut chunk)? {
        if let Some(place) = chunk.long_at.take() {
            if reader.reread_if_long {
                return Ok(RestF64::HighPrecision(place));
            }
            return Err(super::long_after_f64(&reader.name, &place));
        }
        let more = check
            .feed_f64(&chunk.times, &chunk.states, observer)
            .map_err(|e| e.to_string())?;
        if !more {
            break;
        }
    }
    Ok(RestF64::Done)
}
