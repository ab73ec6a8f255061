//! Trajectories read in chunks of rows, so that `rsts check` holds a bounded part of its input at
//! a time: CSV and npy (C order, what `numpy.save` and `rsts reference` write) stream from a file
//! or standard input; JSON, MCAP logs and Fortran-order npy are read whole (within
//! [`MAX_WHOLE_BYTES`]) and handed out in the same chunks.
//!
//! Every chunk is checked as a whole file is ([`crate::files`]): values, components, times
//! strictly increasing (across chunks too); errors name the file and the line (row, sample).

use std::io::{BufRead, BufReader, Read};
use std::path::Path;

use rsts_harness::{CheckStream, Observer};

use crate::files::{
    npy_open, npy_row, npy_rows, parse_trajectory, read_mcap, CsvHeader, FileFormat,
};
use crate::samples::{time_order, Number, RawTrajectory, F64_TEXT_DIGITS};

mod csv_count;
mod decimal;
mod f64_rows;
mod plain_csv;
pub use f64_rows::{check_rest_f64, F64Chunk, RestF64};
#[cfg(test)]
mod survey_tests;

/// Rows per chunk.
pub const CHUNK_ROWS: usize = 1 << 13;
/// Most significant digits of the values of one chunk of high-precision data (a chunk of 10000
/// digit values holds 160 rows): the memory of a check does not grow with the digits of its
/// data beyond this (~16 MB of text and as much in numbers). f64 data (at most 17 digits a value)
/// always come in chunks of [`CHUNK_ROWS`].
pub const CHUNK_DIGITS: usize = 16_000_000;
/// Most samples one trajectory may have (`rsts check`; docs/output.md).
pub const MAX_ROWS: usize = 100_000_000;
/// Largest input read whole (JSON, MCAP, Fortran-order npy): 2 GiB.
pub const MAX_WHOLE_BYTES: u64 = 2 * 1024 * 1024 * 1024;
/// Longest CSV line (a row of ten 10000-digit values takes 100 kB).
pub const MAX_LINE_BYTES: u64 = 16 * 1024 * 1024;

/// What the precision rule and the reference need before any sample is analysed: known from a
/// first pass over a file, or from the first chunk of a stream.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Survey {
    /// Rows in all (`None`: a CSV stream, not known before its end).
    pub rows: Option<usize>,
    /// The most significant digits of any value surveyed (0: all binary64).
    pub digits: usize,
    /// The largest |t| surveyed.
    pub extent: f64,
}

impl Survey {
    /// True when the precision rule reads decimal texts exactly (some value has > 17 digits).
    pub fn is_high_precision(&self) -> bool {
        self.digits > F64_TEXT_DIGITS
    }

    /// Widen the extent to the times of a chunk read (an npy's extent is not surveyed
    /// beforehand: that of its first chunk, [`TrajectoryReader::open_surveyed`]).
    pub fn add_times(&mut self, times: &[f64]) {
        self.extent = times.iter().fold(self.extent, |m, t| m.max(t.abs()));
    }

    fn add(&mut self, raw: &RawTrajectory) {
        self.digits = self.digits.max(raw.digits());
        self.extent = raw
            .times
            .iter()
            .fold(self.extent, |m, t| m.max(t.to_f64().abs()));
    }
}

/// A trajectory read chunk by chunk.
pub struct TrajectoryReader {
    name: String,
    rows: Rows,
    /// The time and place of the last sample handed out.
    last: Option<(Number, String)>,
    read: usize,
    /// The cost the file states (a JSON file's `stats`; nothing for the streamed formats).
    stats: rsts_harness::StatedStats,
    /// Opened without a survey of its digits ([`TrajectoryReader::open_f64`]).
    reread_if_long: bool,
    /// The precision rule, once decided (by a survey, or by a stream's first chunk): how times
    /// are compared ([`crate::samples::time_order`]).
    high: Option<bool>,
}

/// The samples of a trajectory read whole, in order.
type WholeRows = std::iter::Zip<
    std::iter::Zip<std::vec::IntoIter<Number>, std::vec::IntoIter<[Number; 9]>>,
    std::vec::IntoIter<String>,
>;

enum Rows {
    Csv {
        input: Box<dyn BufRead + Send>,
        header: Option<CsvHeader>,
        line: usize,
        buf: Vec<u8>,
        /// Where the fields of a plain line go (from the header, for [`plain_csv`]).
        layout: Option<plain_csv::Layout>,
    },
    Npy {
        /// The data after the header (C order, float64 of `big_endian` byte order).
        input: Box<dyn Read + Send>,
        big_endian: bool,
        rows: usize,
        width: usize,
        next: usize,
        row: Vec<f64>,
        /// The bytes of one row.
        bytes: Vec<u8>,
    },
    Whole {
        rows: usize,
        survey: Survey,
        samples: WholeRows,
    },
}

impl TrajectoryReader {
    /// Open a trajectory file by its extension (CSV and npy stream, the others are read whole).
    pub fn open(path: &Path) -> Result<Self, String> {
        let name = path.display().to_string();
        let format = FileFormat::of(path)?;
        if let FileFormat::Mcap | FileFormat::Json = format {
            whole_size_ok(path, &name)?;
        }
        if format == FileFormat::Mcap {
            let raw = read_mcap(path).map_err(|e| format!("{name}: {e}"))?;
            return Self::whole(raw, &name);
        }
        let file = std::fs::File::open(path).map_err(|e| format!("{name}: cannot read ({e})"))?;
        Self::from_reader(Box::new(file), format, &name)
    }

    /// Open a file and read it through once: its survey (rows, digits, extent; every row
    /// checked), and a reader at its start. A C-order npy is not read through: its header
    /// says the rows, its values are binary64 (no digits), and its extent is left at 0 (the
    /// reference reaches further as the rows come, as for a stream).
    pub fn open_surveyed(path: &Path) -> Result<(Self, Survey), String> {
        let mut first = Self::open(path)?;
        if let Rows::Whole { survey, .. } = first.rows {
            // Read whole already: surveyed where it is.
            return Ok((first, survey));
        }
        if let Rows::Npy { rows, .. } = first.rows {
            let survey = Survey {
                rows: Some(rows),
                digits: 0,
                extent: 0.0,
            };
            first.high = Some(false);
            return Ok((first, survey));
        }
        // Read as f64 (digits counted, every row checked): one parse per value.
        let survey = first.survey_f64()?;
        let mut reader = Self::open(path)?;
        reader.high = Some(survey.is_high_precision());
        Ok((reader, survey))
    }

    /// A trajectory in `format` from `input` (standard input, say), named `name` in messages.
    pub fn from_reader(
        input: Box<dyn Read + Send>,
        format: FileFormat,
        name: &str,
    ) -> Result<Self, String> {
        let buffered = BufReader::with_capacity(1 << 20, input);
        let rows = match format {
            FileFormat::Csv => Rows::Csv {
                input: Box::new(buffered),
                header: None,
                line: 0,
                buf: Vec::new(),
                layout: None,
            },
            FileFormat::Npy => {
                let (npy, shape) = npy_open(Box::new(buffered) as Box<dyn Read + Send>)
                    .map_err(|e| format!("{name}: {e}"))?;
                if shape.rows > MAX_ROWS {
                    return Err(too_many(name, shape.rows));
                }
                if shape.order == npyz::Order::Fortran {
                    // Column after column: the rows are only known at the end.
                    if (shape.rows * shape.width * 8) as u64 > MAX_WHOLE_BYTES {
                        return Err(too_big(name));
                    }
                    let data: Vec<f64> = npy.into_vec().map_err(|e| {
                        format!(
                            "{name}: truncated or damaged data: {e} (expected {} rows of {} float64)",
                            shape.rows, shape.width
                        )
                    })?;
                    let raw = npy_rows(&data, shape).map_err(|e| format!("{name}: {e}"))?;
                    return Self::whole(raw, name);
                }
                let big_endian =
                    matches!(npy.dtype(), npyz::DType::Plain(ts) if ts.to_string() == ">f8");
                Rows::Npy {
                    input: Box::new(npy.into_inner()),
                    big_endian,
                    rows: shape.rows,
                    width: shape.width,
                    next: 0,
                    row: Vec::with_capacity(shape.width),
                    bytes: vec![0; 8 * shape.width],
                }
            }
            FileFormat::Json | FileFormat::Mcap => {
                let what = "a JSON trajectory";
                let bytes =
                    rsts_io::read_stream_bounded(buffered, MAX_WHOLE_BYTES, what).map_err(|e| {
                        if e.kind() == std::io::ErrorKind::InvalidData {
                            too_big(name)
                        } else {
                            format!("{name}: cannot read ({e})")
                        }
                    })?;
                return Self::whole(parse_trajectory(&bytes, format, name)?, name);
            }
        };
        Ok(Self {
            name: name.to_string(),
            rows,
            last: None,
            read: 0,
            stats: Default::default(),
            reread_if_long: false,
            high: None,
        })
    }

    /// A trajectory read whole (checked: samples, times increasing).
    fn whole(raw: RawTrajectory, name: &str) -> Result<Self, String> {
        if raw.is_empty() {
            return Err(format!("{name}: no samples"));
        }
        raw.check_times().map_err(|e| format!("{name}: {e}"))?;
        if raw.len() > MAX_ROWS {
            return Err(too_many(name, raw.len()));
        }
        let rows = raw.len();
        let mut survey = Survey {
            rows: Some(rows),
            digits: 0,
            extent: 0.0,
        };
        survey.add(&raw);
        let RawTrajectory {
            times,
            states,
            places,
            stats,
        } = raw;
        Ok(Self {
            name: name.to_string(),
            rows: Rows::Whole {
                rows,
                survey,
                samples: times.into_iter().zip(states).zip(places),
            },
            last: None,
            read: 0,
            stats,
            reread_if_long: false,
            high: Some(survey.is_high_precision()),
        })
    }

    /// The cost the file states about its run (a JSON file's `stats` block).
    pub fn stated_stats(&self) -> rsts_harness::StatedStats {
        self.stats
    }

    /// Rows in all, when known before the end (npy, inputs read whole).
    pub fn total_rows(&self) -> Option<usize> {
        match &self.rows {
            Rows::Csv { .. } => None,
            Rows::Npy { rows, .. } | Rows::Whole { rows, .. } => Some(*rows),
        }
    }

    /// Rows handed out so far.
    pub fn rows_read(&self) -> usize {
        self.read
    }

    /// The survey of a stream from its first chunk (the precision rule is decided there).
    pub fn survey_of_first(&self, first: &RawTrajectory) -> Survey {
        let mut survey = Survey {
            rows: self.total_rows(),
            digits: 0,
            extent: 0.0,
        };
        survey.add(first);
        survey
    }

    /// The next chunk of at most [`CHUNK_ROWS`] samples, checked; `None` after the last one. A
    /// trajectory without samples is an error.
    pub fn next_chunk(&mut self) -> Result<Option<RawTrajectory>, String> {
        let name = &self.name;
        let mut raw = RawTrajectory::default();
        // Digits held in the chunk: long values make it shorter, so that a chunk of
        // high-precision data holds at most CHUNK_DIGITS digits (and their numbers).
        let mut digits = 0;
        while raw.len() < CHUNK_ROWS && digits < CHUNK_DIGITS {
            match self.rows.next_row().map_err(|e| format!("{name}: {e}"))? {
                Some((t, state, place)) => {
                    digits += t.digits() + state.iter().map(Number::digits).sum::<usize>();
                    raw.push(t, state, place)
                }
                None => break,
            }
        }
        if raw.is_empty() {
            if self.read == 0 {
                return Err(format!("{name}: no samples"));
            }
            return Ok(None);
        }
        // A stream's precision is decided by its first chunk (as its survey is).
        let high = *self.high.get_or_insert_with(|| raw.is_high_precision());
        if let Some((previous, _)) = &self.last {
            time_order(previous, &raw.times[0], high, &raw.places[0])
                .map_err(|e| format!("{name}: {e}"))?;
        }
        raw.check_times_at(high)
            .map_err(|e| format!("{name}: {e}"))?;
        self.read += raw.len();
        if self.read > MAX_ROWS {
            return Err(too_many(name, self.read));
        }
        let k = raw.len() - 1;
        self.last = Some((raw.times[k].clone(), raw.places[k].clone()));
        Ok(Some(raw))
    }
}

impl Rows {
    /// The next sample and its place.
    fn next_row(&mut self) -> Result<Option<(Number, [Number; 9], String)>, String> {
        match self {
            Rows::Csv {
                input,
                header,
                line,
                buf,
                ..
            } => {
                let row = csv_row(input, header, line, buf, |h, k, text| h.row(k, text))?;
                Ok(row.map(|(k, (t, state))| (t, state, format!("line {k}"))))
            }
            Rows::Npy { .. } => {
                let Some(r) = self.next_npy_row()? else {
                    return Ok(None);
                };
                let Rows::Npy { row, .. } = self else {
                    unreachable!()
                };
                let (t, state) = npy_row(r, |c| row[c])?;
                Ok(Some((t, state, format!("row {}", r + 1))))
            }
            Rows::Whole { samples, .. } => Ok(samples.next().map(|((t, s), p)| (t, s, p))),
        }
    }
}

impl Rows {
    /// Read the next row of an npy array into its `row`: its index, `None` after the last.
    fn next_npy_row(&mut self) -> Result<Option<usize>, String> {
        let Rows::Npy {
            input,
            big_endian,
            rows,
            width,
            next,
            row,
            bytes,
        } = self
        else {
            return Ok(None);
        };
        if *next >= *rows {
            return Ok(None);
        }
        // One read per row (not per value).
        input.read_exact(bytes).map_err(|e| {
            format!("truncated or damaged data: {e} (expected {rows} rows of {width} float64)")
        })?;
        row.clear();
        row.extend(bytes.chunks_exact(8).map(|b| {
            let b: [u8; 8] = b.try_into().expect("8 bytes");
            if *big_endian {
                f64::from_be_bytes(b)
            } else {
                f64::from_le_bytes(b)
            }
        }));
        *next += 1;
        Ok(Some(*next - 1))
    }
}

/// The next row of a CSV stream after its header, read from its line's text by `read` (`None`:
/// a blank or comment line, skipped): its line number and what `read` made of it; `None` at the
/// end.
fn csv_row<R>(
    input: &mut Box<dyn BufRead + Send>,
    header: &mut Option<CsvHeader>,
    line: &mut usize,
    buf: &mut Vec<u8>,
    mut read: impl FnMut(&CsvHeader, usize, &str) -> Result<Option<R>, String>,
) -> Result<Option<(usize, R)>, String> {
    loop {
        let Some(k) = csv_line(input, header, line, buf)? else {
            return Ok(None);
        };
        let h = header.as_ref().expect("read before the rows");
        if let Some(r) = read(h, k, line_text(buf, k)?)? {
            return Ok(Some((k, r)));
        }
    }
}

/// Read the next line of a CSV stream after its header (read and parsed on the way, blank
/// lines before it skipped) into `buf`: its number, or `None` at the end.
fn csv_line(
    input: &mut Box<dyn BufRead + Send>,
    header: &mut Option<CsvHeader>,
    line: &mut usize,
    buf: &mut Vec<u8>,
) -> Result<Option<usize>, String> {
    loop {
        buf.clear();
        let n = input
            .by_ref()
            .take(MAX_LINE_BYTES + 1)
            .read_until(b'\n', buf)
            .map_err(|e| format!("cannot read ({e})"))?;
        if n == 0 {
            return match header {
                None => Err("empty: no header line".into()),
                Some(_) => Ok(None),
            };
        }
        *line += 1;
        let k = *line;
        if n as u64 > MAX_LINE_BYTES {
            return Err(format!(
                "line {k}: longer than {MAX_LINE_BYTES} bytes (a row is ten numbers)"
            ));
        }
        if header.is_some() {
            return Ok(Some(k));
        }
        let text = line_text(buf, k)?;
        if !text.trim().is_empty() {
            *header = Some(CsvHeader::parse(k, text)?);
        }
    }
}

/// The text of line `k` read into `buf`, without its line end (and a byte-order mark on line
/// 1, as spreadsheet programs write: not part of a name).
fn line_text(buf: &[u8], k: usize) -> Result<&str, String> {
    let text = std::str::from_utf8(buf)
        .map_err(|e| format!("line {k}: not UTF-8 text (byte {})", e.valid_up_to() + 1))?;
    let text = text.strip_suffix('\n').unwrap_or(text);
    let text = text.strip_suffix('\r').unwrap_or(text);
    Ok(if k == 1 {
        text.strip_prefix('\u{feff}').unwrap_or(text)
    } else {
        text
    })
}

/// Refuse an input read whole beyond [`MAX_WHOLE_BYTES`], before reading it.
fn whole_size_ok(path: &Path, name: &str) -> Result<(), String> {
    match std::fs::metadata(path) {
        Ok(meta) if meta.is_file() && meta.len() > MAX_WHOLE_BYTES => Err(format!(
            "{name}: {} bytes, more than the {MAX_WHOLE_BYTES} bytes (2 GiB) a JSON or MCAP trajectory may have (it is read whole; CSV and npy stream); check it in parts",
            meta.len()
        )),
        _ => Ok(()),
    }
}

fn too_big(name: &str) -> String {
    format!("{name}: more than the {MAX_WHOLE_BYTES} bytes (2 GiB) a JSON or Fortran-order npy trajectory may have (it is read whole; CSV and C-order npy stream); check it in parts")
}

fn too_many(name: &str, rows: usize) -> String {
    format!(
        "{name}: {rows} samples or more, above the limit of {MAX_ROWS} (10⁸); check it in parts"
    )
}

/// The refusal of a value of more than 17 digits at `place` after a stream's first chunk.
fn long_after_f64(name: &str, place: &str) -> String {
    format!(
        "{name}: {place}: a value of more than {F64_TEXT_DIGITS} digits after {CHUNK_ROWS} rows of f64 data: a stream's precision is decided by its first {CHUNK_ROWS} rows (give the trajectory as a file, which is read twice)"
    )
}

/// Analyse the rest of `reader` with `check`, chunk after chunk, at `bits` bits with the
/// precision rule decided already (`high`: decimal texts read exactly). A chunk of a stream
/// with a longer value than its survey allowed is refused. Stops when the observer asks.
pub fn check_rest(
    reader: &mut TrajectoryReader,
    check: &mut CheckStream,
    bits: u32,
    high: bool,
    observer: &mut dyn Observer,
) -> Result<(), String> {
    while let Some(raw) = reader.next_chunk()? {
        if !high && raw.is_high_precision() {
            let k = (0..raw.len())
                .find(|&k| {
                    raw.times[k].digits() > F64_TEXT_DIGITS
                        || raw.states[k].iter().any(|x| x.digits() > F64_TEXT_DIGITS)
                })
                .unwrap_or(0);
            return Err(long_after_f64(&reader.name, &raw.places[k]));
        }
        let samples = raw.to_samples_at(bits, high);
        drop(raw);
        let more = check
            .feed(&samples.times, &samples.states, observer)
            .map_err(|e| e.to_string())?;
        if !more {
            break;
        }
    }
    Ok(())
}
