//! What MCAP readers need from a file beyond the specification: the structural properties
//! that every current and older reader (Foxglove Studio's @mcap/core, Lichtblick, the Python
//! and Rust `mcap` libraries) relies on when it opens a file through its summary.
//!
//! [`reader_problems`] lists the violations of an indexed, chunked file. Files written by
//! [`crate::TrajectoryLog`] and by the surfaces scene have none (tested for every kind of
//! file `rsts` writes).

use std::collections::BTreeMap;

/// The structural problems of an MCAP file that keep some reader from opening it; empty when
/// there are none. Checked, with the `mcap` crate's reader:
/// * the file has a summary section with statistics, and the statistics' chunk and message
///   counts equal what the chunk indexes and a linear read find;
/// * every chunk index has a non-empty message index (`message_index_length > 0` and at
///   least one channel in `message_index_offsets`) — @mcap/core 2.1.0 (Foxglove Studio
///   1.x) stops with "Chunks without message indexes are not
///   currently supported" otherwise;
/// * every chunk holds at least one message, and its message index lists each of them.
pub fn reader_problems(mcap: &[u8]) -> Vec<String> {
    let mut problems = Vec::new();
    let summary = match mcap::Summary::read(mcap) {
        Ok(Some(s)) => s,
        Ok(None) => return vec!["no summary section: indexed readers cannot open it".into()],
        Err(e) => return vec![format!("the summary cannot be read: {e}")],
    };
    let Some(stats) = &summary.stats else {
        return vec!["the summary has no statistics record".into()];
    };
    if stats.chunk_count as usize != summary.chunk_indexes.len() {
        problems.push(format!(
            "statistics count {} chunks, the summary indexes {}",
            stats.chunk_count,
            summary.chunk_indexes.len()
        ));
    }
    let mut indexed_messages = 0u64;
    for (i, index) in summary.chunk_indexes.iter().enumerate() {
        let at = format!("chunk {i} (offset {})", index.chunk_start_offset);
        if index.message_index_length == 0 || index.message_index_offsets.is_empty() {
            problems.push(format!(
                "{at} has no message index (message_index_length {}): @mcap/core 2.1.0 \
                 (Foxglove Studio 1.x) rejects the file",
                index.message_index_length
            ));
        }
        let messages = match summary.stream_chunk(mcap, index) {
            Ok(it) => it.filter(|m| m.is_ok()).count() as u64,
            Err(e) => {
                problems.push(format!("{at} cannot be read: {e}"));
                continue;
            }
        };
        if messages == 0 {
            problems.push(format!("{at} holds no message"));
        }
        let listed: u64 = match summary.read_message_indexes(mcap, index) {
            Ok(by_channel) => by_channel.values().map(|v| v.len() as u64).sum(),
            Err(_) => 0,
        };
        if listed != messages {
            problems.push(format!(
                "{at}: its message index lists {listed} messages, it holds {messages}"
            ));
        }
        indexed_messages += messages;
    }
    let mut linear = BTreeMap::<u16, u64>::new();
    match mcap::MessageStream::new(mcap) {
        Ok(stream) => {
            for m in stream {
                match m {
                    Ok(m) => *linear.entry(m.channel.id).or_default() += 1,
                    Err(e) => {
                        problems.push(format!("linear read failed: {e}"));
                        break;
                    }
                }
            }
        }
        Err(e) => problems.push(format!("linear read failed: {e}")),
    }
    let linear_total: u64 = linear.values().sum();
    if stats.message_count != linear_total || indexed_messages != linear_total {
        problems.push(format!(
            "message counts disagree: statistics {}, chunks {indexed_messages}, linear read {linear_total}",
            stats.message_count
        ));
    }
    if stats.channel_message_counts != linear {
        problems.push(format!(
            "per-channel counts disagree: statistics {:?}, linear read {linear:?}",
            stats.channel_message_counts
        ));
    }
    problems
}

/// The same file in the layout `rsts` wrote before it was fixed: a first chunk holding only
/// the schemas and channels (the metadata records, or a flush, close it before the first
/// message). For tests and `scripts/check_viewer.sh --self-test`, which show that the checks
/// ([`reader_problems`], @mcap/core 2.1.0, Foxglove Studio) reject such a file.
pub fn with_empty_first_chunk(mcap: &[u8]) -> Result<Vec<u8>, mcap::McapError> {
    use std::collections::HashMap;
    use std::io::Cursor;

    let summary = mcap::Summary::read(mcap)?.ok_or(mcap::McapError::UnexpectedEof)?;
    let mut w = mcap::WriteOptions::new()
        .compression(Some(mcap::Compression::Zstd))
        .profile("")
        .create(Cursor::new(Vec::new()))?;
    let mut schema_ids = HashMap::new();
    let mut schemas: Vec<_> = summary.schemas.values().collect();
    schemas.sort_by_key(|s| s.id);
    for s in schemas {
        schema_ids.insert(s.id, w.add_schema(&s.name, &s.encoding, &s.data)?);
    }
    let mut channel_ids = HashMap::new();
    let mut channels: Vec<_> = summary.channels.values().collect();
    channels.sort_by_key(|c| c.id);
    for c in channels {
        let schema = c.schema.as_ref().map_or(0, |s| schema_ids[&s.id]);
        let id = w.add_channel(schema, &c.topic, &c.message_encoding, &c.metadata)?;
        channel_ids.insert(c.id, id);
    }
    w.flush()?;
    for record in mcap::read::LinearReader::new(mcap)? {
        if let mcap::records::Record::Metadata(m) = record? {
            w.write_metadata(&m)?;
        }
    }
    for m in mcap::MessageStream::new(mcap)? {
        let m = m?;
        w.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id: channel_ids[&m.channel.id],
                sequence: m.sequence,
                log_time: m.log_time,
                publish_time: m.publish_time,
            },
            &m.data,
        )?;
    }
    w.finish()?;
    Ok(w.into_inner().into_inner())
}
