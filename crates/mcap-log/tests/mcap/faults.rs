//! Fault injection over a whole log: the file cut at many lengths and one bit flipped at many
//! bytes — every byte of its first and last 600 (header, first chunk, data end, summary,
//! footer) and a stride of 17 through the rest, ~3000 offsets in all. `summarize` and `extract`
//! never panic, never call a damaged file complete, agree with each other on whether it is
//! damaged (so `rsts inspect` exits with the same code with or without `--channel`), and a cut
//! file says "truncated at byte N".

use crate::common;

use common::{samples, tmp, T_END};
use rsts_mcap::demo::{self, Precession};
use rsts_mcap::{inspect, topics, InspectError, LogOptions, TrajectoryLog};

/// A small log with several chunks (so chunk boundaries, message indexes, the data end, the
/// summary and the footer are all a few hundred bytes apart).
fn small_log() -> Vec<u8> {
    let n = 8;
    let path = tmp("faults-src.mcap");
    let mut log = TrajectoryLog::create_with_options(
        &path,
        &demo::metadata(&Precession::EXAMPLE, T_END, n),
        &LogOptions {
            chunk_size: 4 * 1024,
            compression_level: 0,
        },
    )
    .unwrap();
    for s in &samples(n) {
        log.log_sample(s).unwrap();
    }
    log.finish().unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let s = inspect::summarize(&path).unwrap();
    assert!(!s.recovered, "{:?}", s.notes);
    bytes
}

/// The offsets tried in a file of `len` bytes: all of the first and last 600, every 17th between.
fn offsets(len: usize) -> Vec<usize> {
    (0..len)
        .filter(|&i| i < 600 || i + 600 >= len || i % 17 == 3)
        .collect()
}

/// (damaged?, notes) as `summarize` and `extract` see `bytes`; both must agree.
fn read_both(file: &str, bytes: &[u8], what: &str) -> Result<(bool, Vec<String>), String> {
    let path = tmp(file);
    std::fs::write(&path, bytes).unwrap();
    let summary = std::panic::catch_unwind(|| inspect::summarize(&path))
        .map_err(|_| format!("{what}: summarize panicked"))?;
    let series = std::panic::catch_unwind(|| inspect::extract(&path, topics::ERRORS))
        .map_err(|_| format!("{what}: extract panicked"))?;
    match (summary, series) {
        (Ok(s), Ok(e)) => {
            if s.recovered != e.recovered {
                return Err(format!(
                    "{what}: summarize says recovered = {}, extract {} ({:?} / {:?})",
                    s.recovered, e.recovered, s.notes, e.notes
                ));
            }
            if s.recovered && s.notes.is_empty() {
                return Err(format!("{what}: recovered without a note"));
            }
            Ok((s.recovered, s.notes))
        }
        (Err(a), Err(b)) => {
            for e in [&a, &b] {
                if matches!(e, InspectError::ReaderPanicked { .. }) {
                    return Err(format!("{what}: {e}"));
                }
            }
            Ok((true, vec![a.to_string()]))
        }
        (a, b) => Err(format!(
            "{what}: summarize and extract disagree: {:?} / {:?}",
            a.map(|s| s.notes),
            b.map(|s| s.notes)
        )),
    }
}

#[test]
fn a_file_cut_at_many_lengths_is_reported_truncated_at_that_byte() {
    let bytes = small_log();
    let mut failures = Vec::new();
    let tried = offsets(bytes.len());
    for &len in &tried {
        match read_both("cut.mcap", &bytes[..len], &format!("cut at {len}")) {
            Err(e) => failures.push(e),
            Ok((damaged, notes)) => {
                let said = notes
                    .iter()
                    .any(|n| n.contains(&format!("truncated at byte {len}")));
                if !damaged || (len > 0 && !said) {
                    failures.push(format!("cut at {len}: {notes:?}"));
                }
            }
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} lengths: {:#?}",
        failures.len(),
        tried.len(),
        &failures[..failures.len().min(10)]
    );
}

#[test]
fn a_flipped_bit_at_many_bytes_is_reported_damaged() {
    let bytes = small_log();
    let mut failures = Vec::new();
    for off in offsets(bytes.len()) {
        let bit = if off % 2 == 0 { 0x01u8 } else { 0x80 };
        let mut b = bytes.clone();
        b[off] ^= bit;
        match read_both("flipped.mcap", &b, &format!("bit {bit:#04x} at byte {off}")) {
            Err(e) => failures.push(e),
            Ok((false, _)) => failures.push(format!(
                "bit {bit:#04x} at byte {off} of {}: reported complete",
                bytes.len()
            )),
            Ok(_) => {}
        }
    }
    assert!(
        failures.is_empty(),
        "{} failures: {:#?}",
        failures.len(),
        &failures[..failures.len().min(10)]
    );
}
