//! A CSV file opened for f64 data in one pass ([`TrajectoryReader::open_f64`]): before the
//! analysis, only its line ends are looked at (its rows counted: the length the progress shows)
//! and its last row's time read (the extent: times increase, so |t| is largest at an end).
//! Its digits are not surveyed beforehand: the rows are read as f64 and a value of more than
//! 17 digits is noted where it is read ([`TrajectoryReader::reread_if_long`]: `rsts check` then
//! reads the file again as high-precision data, surveyed as before).

use std::io::Read;
use std::path::Path;

use super::{line_text, Survey, TrajectoryReader, MAX_LINE_BYTES};
use crate::files::{unquote, CsvHeader, FileFormat};

/// Bytes read at a time.
const BLOCK: usize = 1 << 20;

impl TrajectoryReader {
    /// Open a file whose values are expected to be f64 data, with its survey: a CSV in the
    /// plain case (ASCII, a header, rows) by [`count_csv`], with its digits left to the reading
    /// ([`TrajectoryReader::reread_if_long`]); any other file, or a CSV in another case, by
    /// [`TrajectoryReader::open_surveyed`] (its messages).
    pub fn open_f64(path: &Path) -> Result<(Self, Survey), String> {
        if FileFormat::of(path)? == FileFormat::Csv {
            if let Some(survey) = count_csv(path) {
                let mut reader = Self::open(path)?;
                reader.reread_if_long = true;
                return Ok((reader, survey));
            }
        }
        Self::open_surveyed(path)
    }

    /// True for a file opened by [`TrajectoryReader::open_f64`] without a survey of its
    /// digits: a value of more than 17 digits means it is to be read again, surveyed.
    pub fn reread_if_long(&self) -> bool {
        self.reread_if_long
    }
}

/// The rows and the extent of a CSV file of ASCII text with a header and rows (lines that are
/// neither blank nor comments, as the reader sees them), its values not read but its last
/// row's time; `None` for any other file.
fn count_csv(path: &Path) -> Option<Survey> {
    let mut file = std::fs::File::open(path).ok()?;
    // The bytes read and not yet looked at are data[..len]; the buffer is zeroed only where
    // it grows (not for every block read).
    let mut data: Vec<u8> = Vec::new();
    let mut len = 0;
    let mut header: Option<CsvHeader> = None;
    let (mut line, mut rows) = (0, 0);
    let mut last_row = Vec::new();
    loop {
        if data.len() < len + BLOCK {
            data.resize(len + BLOCK, 0);
        }
        let n = loop {
            match file.read(&mut data[len..len + BLOCK]) {
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                read => break read.ok()?,
            }
        };
        len += n;
        let end = match n {
            0 => len,
            _ => match memchr::memrchr(b'\n', &data[..len]) {
                Some(i) => i + 1,
                None if len as u64 > MAX_LINE_BYTES => return None,
                None => continue,
            },
        };
        let lines = &data[..end];
        if !lines.is_ascii() {
            return None;
        }
        let mut last = None;
        let mut start = 0;
        let ends = memchr::memchr_iter(b'\n', lines).chain((end > start && n == 0).then_some(end));
        for stop in ends {
            if start >= end {
                break;
            }
            let text = &lines[start..stop];
            let (from, to) = (start, stop);
            start = stop + 1;
            line += 1;
            if text.len() as u64 > MAX_LINE_BYTES {
                return None;
            }
            let Some(first) = text.iter().position(|b| !matches!(b, 9..=13 | b' ')) else {
                continue;
            };
            if header.is_none() {
                header = Some(CsvHeader::parse(line, line_text(text, line).ok()?).ok()?);
            } else if text[first] != b'#' {
                rows += 1;
                last = Some((from, to));
            }
        }
        if let Some((from, to)) = last {
            last_row.clear();
            last_row.extend_from_slice(&data[from..to]);
        }
        data.copy_within(end..len, 0);
        len -= end;
        if n == 0 {
            break;
        }
    }
    let h = header?;
    let text = std::str::from_utf8(&last_row).ok()?;
    let t: f64 = unquote(text.split(',').nth(h.index[0])?).parse().ok()?;
    (rows > 0 && t.is_finite()).then_some(Survey {
        rows: Some(rows),
        digits: 0,
        extent: t.abs(),
    })
}
