//! Every reader opens the files: no chunk without messages (the first chunk used to hold only
//! the schemas and channels, closed by the metadata record — @mcap/core 2.1.0, the reader of
//! Foxglove Studio 1.x, rejects such a file), and the indexes agree with a linear read.
//! `rsts_mcap::compat::reader_problems` is the check; it is shown here to flag the old layout.

use crate::common;

use std::collections::BTreeMap;
use std::io::Cursor;

use common::{samples, tmp, write_log};
use rsts_mcap::compat::reader_problems;
use rsts_mcap::demo::{self, Precession};
use rsts_mcap::{schemas, topics, TrajectoryLog};

#[test]
fn logs_have_no_chunk_without_messages() {
    for n in [1, 7, 300] {
        let (path, _) = write_log(&format!("compat{n}.mcap"), n);
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(reader_problems(&bytes), Vec::<String>::new(), "{n} samples");
        let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
        assert!(!summary.chunk_indexes.is_empty());
    }
}

#[test]
fn no_empty_chunk_with_no_samples_or_repeated_flushes() {
    let path = tmp("compat-flush.mcap");
    let meta = demo::metadata(&Precession::EXAMPLE, 1.0, 4);
    // No sample at all: the /metadata message is the chunk's content.
    TrajectoryLog::create(&path, &meta)
        .unwrap()
        .finish()
        .unwrap();
    assert_eq!(
        reader_problems(&std::fs::read(&path).unwrap()),
        Vec::<String>::new()
    );
    // Flushes with nothing new to write, and a flush right before finish.
    let mut log = TrajectoryLog::create(&path, &meta).unwrap();
    log.flush().unwrap();
    log.flush().unwrap();
    for s in samples(4) {
        log.log_sample(&s).unwrap();
        log.flush().unwrap();
        log.flush().unwrap();
    }
    log.finish().unwrap();
    let bytes = std::fs::read(&path).unwrap();
    assert_eq!(reader_problems(&bytes), Vec::<String>::new());
    assert_eq!(
        mcap::Summary::read(&bytes)
            .unwrap()
            .unwrap()
            .chunk_indexes
            .len(),
        5
    );
}

/// A file laid out as the writer did before: schemas and channels, then the metadata record
/// (which closes the chunk holding them), then the messages.
fn old_layout() -> Vec<u8> {
    let mut w = mcap::WriteOptions::new()
        .compression(Some(mcap::Compression::Zstd))
        .profile("")
        .create(Cursor::new(Vec::new()))
        .unwrap();
    let s = w
        .add_schema(
            schemas::ERRORS_NAME,
            "jsonschema",
            schemas::ERRORS.as_bytes(),
        )
        .unwrap();
    let c = w
        .add_channel(s, topics::ERRORS, "json", &BTreeMap::new())
        .unwrap();
    w.write_metadata(&mcap::records::Metadata {
        name: "rsts".into(),
        metadata: BTreeMap::new(),
    })
    .unwrap();
    for i in 0..3u32 {
        w.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id: c,
                sequence: i,
                log_time: i.into(),
                publish_time: i.into(),
            },
            br#"{"t": 0}"#,
        )
        .unwrap();
    }
    w.finish().unwrap();
    w.into_inner().into_inner()
}

#[test]
fn the_check_flags_the_old_layout_and_damaged_files() {
    let old = old_layout();
    let problems = reader_problems(&old);
    assert_eq!(problems.len(), 2, "{problems:?}");
    assert!(problems[0].contains("chunk 0") && problems[0].contains("no message index"));
    assert!(problems[1].contains("chunk 0 (offset") && problems[1].contains("holds no message"));

    let (path, _) = write_log("compat-cut.mcap", 50);
    let bytes = std::fs::read(&path).unwrap();
    // Without its summary (a killed writer).
    let problems = reader_problems(&bytes[..bytes.len() / 2]);
    assert_eq!(problems.len(), 1, "{problems:?}");
    // Not MCAP at all.
    assert_eq!(reader_problems(b"not an mcap file").len(), 1);
}

#[test]
fn the_old_layout_rewrite_keeps_every_message() {
    let (path, _) = write_log("compat-rewrite.mcap", 40);
    let bytes = std::fs::read(&path).unwrap();
    let old = rsts_mcap::compat::with_empty_first_chunk(&bytes).unwrap();
    let problems = reader_problems(&old);
    assert!(
        problems
            .iter()
            .any(|p| p.contains("chunk 0") && p.contains("no message index")),
        "{problems:?}"
    );
    let read = |b: &[u8]| -> Vec<(String, u64, Vec<u8>)> {
        mcap::MessageStream::new(b)
            .unwrap()
            .map(|m| {
                let m = m.unwrap();
                (m.channel.topic.clone(), m.log_time, m.data.to_vec())
            })
            .collect()
    };
    assert_eq!(read(&old), read(&bytes));
    let meta = |b: &[u8]| {
        mcap::read::LinearReader::new(b)
            .unwrap()
            .filter_map(|r| match r.unwrap() {
                mcap::records::Record::Metadata(m) => Some(m),
                _ => None,
            })
            .collect::<Vec<_>>()
    };
    assert_eq!(meta(&old), meta(&bytes));
}
