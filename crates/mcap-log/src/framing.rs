//! The top-level structure of an MCAP file, checked byte by byte for `rsts inspect`.
//!
//! An MCAP file is the magic, a data section of records (opcode u8, length u64, body), a
//! DataEnd record holding the CRC-32 of every byte before it, a summary section, a Footer
//! (summary start, summary offset start, the CRC-32 of the summary and the footer's own first
//! fields) and the magic again. [`walk`] frames every record itself — so it knows the byte
//! offset of each, and where a cut file ends — hands the data-section records to a callback,
//! and checks both CRCs, the footer and the end magic. Together with the per-chunk CRC (checked
//! by the caller) every byte of a file written by `rsts` is covered: a flipped byte anywhere is
//! reported, and a file cut anywhere is reported as "truncated at byte N".

use mcap::records::op;

/// Length of the record header: opcode (1) and length (8).
const RECORD_HEADER: usize = 9;
/// The footer record: header and summary start (8), summary offset start (8), CRC (4).
const FOOTER_RECORD: usize = RECORD_HEADER + 20;

/// Where the data section ended and what was wrong with the file's structure.
#[derive(Debug, Default)]
pub(crate) struct Layout {
    /// Problems, in plain words (empty for a sound file).
    pub notes: Vec<String>,
    /// The file reached a DataEnd record.
    pub saw_data_end: bool,
    /// The summary section, the footer and the closing magic are whole and the summary CRC
    /// matches: the summary section can be trusted.
    pub summary_sound: bool,
}

fn u64_at(buf: &[u8], at: usize) -> u64 {
    let mut b = [0u8; 8];
    b.copy_from_slice(&buf[at..at + 8]);
    u64::from_le_bytes(b)
}

fn u32_at(buf: &[u8], at: usize) -> u32 {
    let mut b = [0u8; 4];
    b.copy_from_slice(&buf[at..at + 4]);
    u32::from_le_bytes(b)
}

/// A known record type of the data section (0x80 and above are private records).
fn data_opcode(opcode: u8) -> bool {
    matches!(
        opcode,
        op::HEADER
            | op::SCHEMA
            | op::CHANNEL
            | op::MESSAGE
            | op::CHUNK
            | op::MESSAGE_INDEX
            | op::CHUNK_INDEX
            | op::ATTACHMENT
            | op::ATTACHMENT_INDEX
            | op::STATISTICS
            | op::METADATA
            | op::METADATA_INDEX
            | op::SUMMARY_OFFSET
            | op::DATA_END
    ) || opcode >= 0x80
}

/// The record at `pos`: (opcode, body range end) or the note that says why it cannot be framed.
fn frame(buf: &[u8], pos: usize, section: &str) -> Result<(u8, usize), String> {
    let n = buf.len();
    if n - pos < RECORD_HEADER {
        return Err(format!(
            "truncated at byte {n}: the file ends inside the header of the record at byte {pos} \
             ({section})"
        ));
    }
    let opcode = buf[pos];
    let len = u64_at(buf, pos + 1);
    let end = (pos as u64 + RECORD_HEADER as u64).saturating_add(len);
    if end > n as u64 {
        return Err(format!(
            "truncated at byte {n}: the record at byte {pos} ({section}, opcode {opcode:#04x}) \
             claims {len} bytes and the file ends first (or that record's length is damaged)"
        ));
    }
    Ok((opcode, end as usize))
}

/// Walk the file (which starts with the magic): call `on_record(opcode, offset, body)` for every
/// record of the data section before DataEnd, then check the data section CRC, the summary
/// section, the footer and the end magic. `damaged_before` tells whether the caller already
/// found damage inside the records (a corrupt chunk), which explains a data CRC mismatch.
pub(crate) fn walk(
    buf: &[u8],
    on_record: &mut dyn FnMut(u8, usize, &[u8]),
    damaged_before: &dyn Fn() -> bool,
) -> Layout {
    let mut layout = Layout::default();
    let n = buf.len();
    let mut pos = mcap::MAGIC.len();
    // The data section.
    let data_end = loop {
        if pos == n {
            layout.notes.push(format!(
                "truncated at byte {n}: the data section ends there without its end record (the \
                 writer did not finish)"
            ));
            return layout;
        }
        let (opcode, end) = match frame(buf, pos, "data section") {
            Ok(x) => x,
            Err(note) => {
                layout.notes.push(note);
                return layout;
            }
        };
        if !data_opcode(opcode) {
            layout.notes.push(format!(
                "unreadable record at byte {pos} (opcode {opcode:#04x} is no MCAP record): the \
                 file is damaged there; reading stopped, everything before it was recovered"
            ));
            return layout;
        }
        if opcode == op::DATA_END {
            break (pos, end);
        }
        on_record(opcode, pos, &buf[pos + RECORD_HEADER..end]);
        pos = end;
    };
    layout.saw_data_end = true;
    let (data_end_pos, summary_start) = data_end;
    let mut sound = true;
    if summary_start - data_end_pos >= RECORD_HEADER + 4 {
        let stored = u32_at(buf, data_end_pos + RECORD_HEADER);
        let computed = crc32fast::hash(&buf[..data_end_pos]);
        if stored != 0 && stored != computed && !damaged_before() {
            layout.notes.push(format!(
                "the data section's CRC does not match (stored {stored:08x}, computed \
                 {computed:08x}): bytes outside the chunks' contents (record headers, \
                 indexes, metadata) are damaged"
            ));
        }
    } else {
        layout.notes.push(format!(
            "the data end record at byte {data_end_pos} is damaged (too short)"
        ));
    }
    // The summary section: frame its records up to the footer.
    let mut pos = summary_start;
    let footer = loop {
        if pos == n {
            layout.notes.push(format!(
                "truncated at byte {n}: the file ends before its footer (summary section \
                 incomplete)"
            ));
            return layout;
        }
        let (opcode, end) = match frame(buf, pos, "summary section") {
            Ok(x) => x,
            Err(note) => {
                layout.notes.push(note);
                return layout;
            }
        };
        if opcode == op::FOOTER {
            break (pos, end);
        }
        if !data_opcode(opcode) || opcode == op::DATA_END {
            layout.notes.push(format!(
                "unreadable record at byte {pos} in the summary section (opcode {opcode:#04x}): \
                 the summary section is damaged"
            ));
            return layout;
        }
        pos = end;
    };
    let (footer_pos, footer_end) = footer;
    if footer_end - footer_pos != FOOTER_RECORD {
        layout.notes.push(format!(
            "the footer at byte {footer_pos} is damaged (length {})",
            footer_end - footer_pos - RECORD_HEADER
        ));
        return layout;
    }
    let magic_end = footer_end + mcap::MAGIC.len();
    if n < magic_end {
        layout.notes.push(format!(
            "truncated at byte {n}: the file ends inside its closing magic"
        ));
        return layout;
    }
    if &buf[footer_end..magic_end] != mcap::MAGIC {
        layout
            .notes
            .push("the closing MCAP magic is damaged".to_string());
        sound = false;
    }
    if n > magic_end {
        layout.notes.push(format!(
            "{} unexpected bytes after the closing magic at byte {magic_end}",
            n - magic_end
        ));
        sound = false;
    }
    let claimed_start = u64_at(buf, footer_pos + RECORD_HEADER);
    let summary_from = if claimed_start == 0 {
        footer_pos
    } else {
        claimed_start as usize
    };
    if claimed_start != 0 && summary_from != summary_start {
        layout.notes.push(format!(
            "the footer puts the summary section at byte {claimed_start}, it starts at byte \
             {summary_start}: the footer is damaged"
        ));
        layout.summary_sound = false;
        return layout;
    }
    let stored = u32_at(buf, footer_pos + RECORD_HEADER + 16);
    let computed = crc32fast::hash(&buf[summary_from..footer_pos + RECORD_HEADER + 16]);
    if stored != 0 && stored != computed {
        layout.notes.push(format!(
            "the summary section's CRC does not match (stored {stored:08x}, computed \
             {computed:08x}): the summary section or the footer is damaged; the statistics \
             shown are those of the data that could be read"
        ));
        sound = false;
    }
    layout.summary_sound = sound;
    layout
}
