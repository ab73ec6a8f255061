//! Truncated, corrupted and garbage files: `summarize` and `extract` return an error or a
//! recovered result with a clear note, and never panic (a panic hook records any panic,
//! including one caught inside the reader's own `catch_unwind` safety net).

use crate::common;

use std::cell::Cell;
use std::sync::Once;

use common::{samples, tmp, write_log};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rsts_mcap::demo::{self, Precession};
use rsts_mcap::{inspect, topics, InspectError, TrajectoryLog};

// Per thread: the hook is the whole process's, and the tests of the other files of this binary
// run beside these (a panic of theirs is not one of the reader's here); the reader runs on the
// calling thread.
thread_local! {
    static PANICKED: Cell<bool> = const { Cell::new(false) };
}
static HOOK: Once = Once::new();

fn watch_panics() {
    HOOK.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            PANICKED.with(|p| p.set(true));
            default(info);
        }));
    });
}

fn assert_no_panic() {
    assert!(!PANICKED.with(Cell::get), "a panic happened while reading");
}

/// Summarises `bytes` written to a file; checks the invariants of a damaged-file result.
fn check_damaged(name: &str, bytes: &[u8], full_messages: u64) -> Option<inspect::Summary> {
    let path = tmp(name);
    std::fs::write(&path, bytes).unwrap();
    let r = inspect::summarize(&path);
    // extract must not panic either.
    let e = inspect::extract(&path, topics::ERRORS);
    assert_no_panic();
    if let Ok(series) = &e {
        if series.recovered {
            assert!(!series.notes.is_empty());
        }
    }
    match r {
        Ok(s) => {
            assert!(s.message_count <= full_messages);
            let listed: u64 = s.channels.iter().map(|c| c.message_count).sum();
            assert_eq!(listed, s.message_count);
            if s.recovered {
                assert!(!s.notes.is_empty(), "recovered without a note");
                assert!(s.to_string().contains("DAMAGED OR INCOMPLETE"));
            } else {
                assert!(s.notes.is_empty());
            }
            Some(s)
        }
        Err(e) => {
            // A clear error naming the file.
            let msg = e.to_string();
            assert!(msg.contains(name), "{msg}");
            assert!(!matches!(e, InspectError::ReaderPanicked { .. }), "{msg}");
            None
        }
    }
}

#[test]
fn cut_in_half() {
    watch_panics();
    let n = 400;
    let (path, _) = write_log("half-src.mcap", n);
    let buf = std::fs::read(&path).unwrap();
    let full = 1 + 9 * n as u64;
    let s = check_damaged("half.mcap", &buf[..buf.len() / 2], full).expect("a recovered summary");
    assert!(s.recovered);
    assert!(!s.has_summary_section);
    assert!(
        s.notes.iter().any(|n| n.contains("truncated")),
        "{:?}",
        s.notes
    );
    // About half of the messages survive (all complete chunks of the first half).
    assert!(
        s.message_count > full / 3 && s.message_count < full * 2 / 3,
        "{} of {full}",
        s.message_count
    );
    // Metadata (written first) is still there; channels were all seen.
    assert_eq!(s.metadata.len(), 1);
    assert_eq!(s.channels.len(), topics::ALL.len());
    // The recovered errors series is a prefix of the logged one.
    let series = inspect::extract(tmp("half.mcap"), topics::ERRORS).unwrap();
    assert!(series.recovered);
    let all = samples(n);
    assert!(!series.points.is_empty());
    for (p, smp) in series.points.iter().zip(&all) {
        assert_eq!(
            p.value["state_error"].as_f64().unwrap(),
            smp.errors.unwrap().state_error
        );
    }
}

#[test]
fn truncated_at_many_lengths() {
    watch_panics();
    let n = 150;
    let (path, _) = write_log("trunc-src.mcap", n);
    let buf = std::fs::read(&path).unwrap();
    let full = 1 + 9 * n as u64;
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut lengths: Vec<usize> = (0..64).collect();
    lengths.extend((0..150).map(|_| rng.gen_range(0..buf.len())));
    lengths.extend(buf.len() - 40..buf.len());
    let mut last_count = 0;
    lengths.sort();
    for len in lengths {
        let r = check_damaged("trunc.mcap", &buf[..len], full);
        if len < 8 {
            assert!(r.is_none(), "{len} bytes cannot be MCAP");
        } else {
            let s = r.unwrap_or_else(|| panic!("a file with the magic gives a summary ({len})"));
            // Only a complete file is reported as healthy.
            assert!(s.recovered, "cut at {len} of {} not flagged", buf.len());
            // Longer prefixes never recover fewer messages.
            assert!(s.message_count >= last_count);
            last_count = s.message_count;
        }
    }
}

#[test]
fn corrupt_middle() {
    watch_panics();
    let n = 300;
    let (path, _) = write_log("corrupt-src.mcap", n);
    let buf = std::fs::read(&path).unwrap();
    let full = 1 + 9 * n as u64;
    let mut rng = ChaCha8Rng::seed_from_u64(11);

    // A block of garbage in the middle: flagged, fewer messages than written.
    let mut bad = buf.clone();
    let mid = bad.len() / 2;
    for b in &mut bad[mid..mid + 64] {
        *b = rng.gen();
    }
    let s = check_damaged("corrupt.mcap", &bad, full).expect("a recovered summary");
    assert!(s.recovered, "corruption not detected");
    assert!(s.message_count < full);
    assert!(s.message_count > 0);

    // A damaged chunk is skipped whole and reading goes on with the next chunks.
    let summary = mcap::Summary::read(&buf).unwrap().unwrap();
    let ci = &summary.chunk_indexes[summary.chunk_indexes.len() / 2];
    let lost = summary.stream_chunk(&buf, ci).unwrap().count() as u64;
    assert!(lost > 0);
    let mut bad = buf.clone();
    let at = (ci.chunk_start_offset + ci.chunk_length - 20) as usize;
    bad[at] ^= 0x55;
    let s = check_damaged("bad-chunk.mcap", &bad, full).expect("a recovered summary");
    assert!(s.recovered);
    assert!(
        s.notes
            .iter()
            .any(|n| n.contains("damaged and was skipped")),
        "{:?}",
        s.notes
    );
    assert_eq!(s.message_count, full - lost);
    // Messages after the damaged chunk were recovered, up to the last one.
    let end = summary.stats.as_ref().unwrap().message_end_time;
    assert_eq!(s.end_time_ns, Some(end));

    // Single-byte flips all over the data section: never a panic; every flip that changes
    // a message, a chunk or the summary is either flagged or leaves the counts intact.
    for _ in 0..150 {
        let mut bad = buf.clone();
        let i = rng.gen_range(8..bad.len());
        bad[i] ^= 1 << rng.gen_range(0..8);
        if let Some(s) = check_damaged("flip.mcap", &bad, full) {
            if !s.recovered {
                assert_eq!(s.message_count, full, "silent loss after flipping byte {i}");
            }
        }
    }
}

#[test]
fn garbage_input() {
    watch_panics();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for k in 0..200 {
        let len = rng.gen_range(0..4000);
        let mut bytes: Vec<u8> = (0..len).map(|_| rng.gen()).collect();
        if k % 2 == 0 && len >= 8 {
            // With a valid magic, so the reader goes past the first check.
            bytes[..8].copy_from_slice(mcap::MAGIC);
        }
        let r = check_damaged("garbage.mcap", &bytes, u64::MAX);
        if k % 2 == 1 {
            assert!(r.is_none(), "random bytes accepted as MCAP");
        }
    }
    // Not a file at all.
    match inspect::summarize(tmp("does-not-exist.mcap")) {
        Err(InspectError::Io { .. }) => {}
        other => panic!("{other:?}"),
    }
    assert_no_panic();
}

/// The temporary a log is written to until it is finished (`.NAME.tmp-PID-N` beside `path`):
/// all a killed process leaves (the target itself is untouched).
fn temporary_of(path: &std::path::Path) -> std::path::PathBuf {
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    let prefix = format!(".{name}.tmp-");
    std::fs::read_dir(path.parent().unwrap())
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with(&prefix)
        })
        .expect("the temporary of an open log")
}

#[test]
fn flushed_log_of_a_killed_process_is_readable() {
    watch_panics();
    // Simulate a process killed right after a flush: copy the temporary while the writer is
    // open (the target does not exist until the log is finished).
    let path = tmp("live.mcap");
    let _ = std::fs::remove_file(&path);
    let n = 100;
    let mut log =
        TrajectoryLog::create(&path, &demo::metadata(&Precession::EXAMPLE, 10.0, n)).unwrap();
    let all = samples(n);
    for s in &all[..60] {
        log.log_sample(s).unwrap();
    }
    log.flush().unwrap();
    assert!(
        !path.exists(),
        "the target appears before the log is finished"
    );
    let snapshot = std::fs::read(temporary_of(&path)).unwrap();
    for s in &all[60..] {
        log.log_sample(s).unwrap();
    }
    log.finish().unwrap();
    let s = check_damaged("killed.mcap", &snapshot, 1 + 9 * n as u64).unwrap();
    assert!(s.recovered);
    // Everything logged before the flush is there.
    assert_eq!(s.message_count, 1 + 9 * 60);
    let errors = s
        .channels
        .iter()
        .find(|c| c.topic == topics::ERRORS)
        .unwrap();
    assert_eq!(errors.message_count, 60);
}

#[test]
fn process_killed_mid_run_leaves_a_readable_prefix() {
    watch_panics();
    // `forget` skips every destructor, as a SIGKILL would: the buffered tail and the open
    // chunk never reach the file, no summary is written.
    let path = tmp("killed-mid-run.mcap");
    let n = 600;
    let all = samples(n);
    let mut log =
        TrajectoryLog::create(&path, &demo::metadata(&Precession::EXAMPLE, 10.0, n)).unwrap();
    for s in &all[..400] {
        log.log_sample(s).unwrap();
    }
    std::mem::forget(log);
    let bytes = std::fs::read(temporary_of(&path)).unwrap();
    std::fs::remove_file(temporary_of(&path)).unwrap();
    let s = check_damaged("killed-mid-run-copy.mcap", &bytes, 1 + 9 * n as u64).unwrap();
    assert!(s.recovered);
    assert!(!s.has_summary_section);
    // At most one chunk (≈ 20 samples) plus the write buffer is lost.
    let errors = s
        .channels
        .iter()
        .find(|c| c.topic == topics::ERRORS)
        .map_or(0, |c| c.message_count);
    eprintln!("{errors} of 400 samples recovered");
    assert!(
        (340..=400).contains(&errors),
        "{errors} of 400 samples recovered"
    );
    let series =
        inspect::extract(tmp("killed-mid-run-copy.mcap"), topics::INTEGRATED_STATE).unwrap();
    for (p, smp) in series.points.iter().zip(&all) {
        assert_eq!(
            p.value["omega"][2].as_f64().unwrap(),
            smp.integrated.unwrap().omega[2]
        );
    }
}

#[test]
fn log_is_send() {
    fn is_send<T: Send>() {}
    is_send::<TrajectoryLog>();
}
