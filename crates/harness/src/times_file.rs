//! A file of sample times (`rsts reference --times-file`): numbers separated by white space,
//! commas or newlines, `#` starting a comment to the end of its line.
//!
//! Bounded before and while reading: at most [`MAX_TIMES_FILE_BYTES`] (a larger file is refused
//! from its size, a device or FIFO where it passes the bound), at most [`MAX_SAMPLES`] times,
//! each of at most [`MAX_TIME_CHARS`] characters. The file is read as a stream: memory is that
//! of the times kept (8 bytes each), however long its lines.

use std::io::{BufRead, BufReader, Read};
use std::path::Path;

use rsts_dynamics::number::Decimal;
use rsts_io::cut;

use crate::MAX_SAMPLES;

/// Largest times file (bytes): [`MAX_SAMPLES`] times of about 50 characters.
pub const MAX_TIMES_FILE_BYTES: u64 = 512 << 20;
/// Longest time in a times file (characters; a time is read as f64: 17 digits suffice).
pub const MAX_TIME_CHARS: usize = 400;

/// The times of the file `path` (not checked for order: [`crate::reference::check_times`]).
/// Errors name the line (`line 3: 'x' is not a number`), not the path.
pub fn read_times_file(path: &Path) -> Result<Vec<f64>, String> {
    read_times(open(path)?)
}

/// The times of the file `path` as the decimals written ([`Decimal::parse`]), bounded and read
/// as [`read_times_file`] reads them.
pub fn read_decimal_times_file(path: &Path) -> Result<Vec<Decimal>, String> {
    read_times_with(open(path)?, Decimal::parse)
}

fn open(path: &Path) -> Result<rsts_io::Bounded<std::fs::File>, String> {
    rsts_io::open_bounded(path, MAX_TIMES_FILE_BYTES, "a times file")
        .map_err(|e| format!("cannot read: {e}"))
}

/// [`read_times_file`] from any input.
pub fn read_times(input: impl Read) -> Result<Vec<f64>, String> {
    read_times_with(input, |text| {
        let t: f64 = text
            .parse()
            .map_err(|_| format!("'{}' is not a number", cut(text)))?;
        if t.is_finite() {
            Ok(t)
        } else {
            Err(format!("must be a finite number, got {}", cut(text)))
        }
    })
}

/// The times of `input`, each word read by `parse` (its error is given after the line).
pub fn read_times_with<T, E: std::fmt::Display>(
    input: impl Read,
    parse: impl Fn(&str) -> Result<T, E>,
) -> Result<Vec<T>, String> {
    let mut input = BufReader::with_capacity(1 << 16, input);
    let mut times = Vec::new();
    let mut word: Vec<u8> = Vec::new();
    let mut line = 1usize;
    let mut comment = false;
    let mut long = false;
    let mut finish = |word: &mut Vec<u8>, long: &mut bool, line: usize| -> Result<(), String> {
        if word.is_empty() && !*long {
            return Ok(());
        }
        let text = String::from_utf8_lossy(word).into_owned();
        if *long {
            let head: String = text.chars().take(40).collect();
            return Err(format!(
                "line {line}: a value of more than {MAX_TIME_CHARS} characters ('{head}…'), not a time"
            ));
        }
        let t = parse(text.trim()).map_err(|e| format!("line {line}: {e}"))?;
        if times.len() >= MAX_SAMPLES {
            return Err(format!(
                "line {line}: more than {MAX_SAMPLES} times, the most a reference may have"
            ));
        }
        times.push(t);
        word.clear();
        Ok(())
    };
    loop {
        let buf = input.fill_buf().map_err(|e| format!("cannot read: {e}"))?;
        if buf.is_empty() {
            break;
        }
        let n = buf.len();
        for &b in buf {
            match b {
                b'\n' => {
                    finish(&mut word, &mut long, line)?;
                    line += 1;
                    comment = false;
                }
                _ if comment => {}
                b'#' => {
                    finish(&mut word, &mut long, line)?;
                    comment = true;
                }
                b',' | b' ' | b'\t' | b'\r' => finish(&mut word, &mut long, line)?,
                _ if word.len() >= MAX_TIME_CHARS => long = true,
                _ => word.push(b),
            }
        }
        input.consume(n);
    }
    finish(&mut word, &mut long, line)?;
    Ok(times)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> Result<Vec<f64>, String> {
        read_times(text.as_bytes())
    }

    #[test]
    fn separators_comments_and_errors_by_line() {
        assert_eq!(
            read("0, 0.5\t1 # one\n# none\n\n2,3\r\n4").unwrap(),
            vec![0.0, 0.5, 1.0, 2.0, 3.0, 4.0]
        );
        assert_eq!(read("").unwrap(), Vec::<f64>::new());
        assert_eq!(read("0\n1\nx").unwrap_err(), "line 3: 'x' is not a number");
        assert_eq!(
            read("0\n1e400").unwrap_err(),
            "line 2: must be a finite number, got 1e400"
        );
        let long = "1".repeat(MAX_TIME_CHARS + 1);
        let e = read(&format!("0\n{long}\n")).unwrap_err();
        assert!(
            e.starts_with("line 2: a value of more than 400 characters ('1111"),
            "{e}"
        );
        assert!(e.len() < 120, "{e}");
    }

    /// A zero-filled device ends at the bound (here a small one), not when memory runs out.
    #[test]
    fn an_endless_input_stops_at_its_bound() {
        let zeros = std::io::repeat(b'0').take(1 << 22);
        let e = read_times(rsts_io::Bounded::new(zeros, 1 << 20, "a times file")).unwrap_err();
        assert!(
            e.contains("longer than") || e.contains("larger than"),
            "{e}"
        );
        let spaces = std::io::repeat(b' ').take(1 << 22);
        let e = read_times(rsts_io::Bounded::new(spaces, 1 << 20, "a times file")).unwrap_err();
        assert!(
            e.contains("larger than the 1048576 bytes (1 MiB) a times file"),
            "{e}"
        );
    }
}
