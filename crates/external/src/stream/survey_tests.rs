//! The survey of a file before its analysis ([`TrajectoryReader::open_surveyed`]).

use super::TrajectoryReader;

/// A file `name` in a fresh temporary directory holding `bytes`.
fn file(name: &str, bytes: &[u8]) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("rsts-survey-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// A CSV's rows, digits and extent: blank lines (white space `str::trim` removes, a vertical
/// tab too), comments (one not ASCII), CRLF ends, quoted values, columns in another order and
/// one more; the longest value (18 digits) on a line of its own, the largest |t| negative.
#[test]
fn a_csv_survey_counts_rows_digits_and_extent_as_the_text_reads() {
    let rows = [
        "omega1,\"t\",omega2,omega3,alpha1,alpha2,alpha3,beta1,beta2,beta3,note\n",
        "0.1,-7.25,0.2,0.3,1,0,0,0,1,0,a\n",
        "\n",
        " \x0b \r\n",
        "  # a comment, café\n",
        "0.1,\"2.5\",0.2,0.3,1,0,0,0,1,0,b\r\n",
        "0.123456789012345678,3,0.2,0.3,1,0,0,0,1,0,c\n",
    ];
    let path = file("t.csv", rows.concat().as_bytes());
    let (_, survey) = TrajectoryReader::open_surveyed(&path).unwrap();
    assert_eq!(survey.rows, Some(3), "{survey:?}");
    assert_eq!(survey.digits, 18, "{survey:?}");
    assert_eq!(survey.extent, 7.25, "{survey:?}");
    assert!(survey.is_high_precision());
}

/// An npy (C order) is surveyed from its header: its rows, no digits (binary64), its extent
/// left to the rows read; its rows read as written.
#[test]
fn an_npy_survey_is_its_header() {
    let rows = 3usize;
    let mut data = Vec::new();
    for r in 0..rows {
        let t = 10.0 * r as f64;
        data.extend([t, 0.1, 0.2, 0.3, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
    }
    // Format 1.0: magic, header length, the header padded to 64 bytes, the data.
    let mut header = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': ({rows}, 10), }}");
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend((header.len() as u16).to_le_bytes());
    bytes.extend(header.as_bytes());
    bytes.extend(data.iter().flat_map(|x| x.to_le_bytes()));
    let path = file("t.npy", &bytes);
    let (mut reader, survey) = TrajectoryReader::open_surveyed(&path).unwrap();
    assert_eq!(
        (survey.rows, survey.digits, survey.extent),
        (Some(3), 0, 0.0)
    );
    let mut chunk = super::F64Chunk::default();
    assert!(reader.next_chunk_f64(&mut chunk).unwrap());
    assert_eq!(chunk.times, [0.0, 10.0, 20.0]);
    assert_eq!(
        chunk.states[2],
        [0.1, 0.2, 0.3, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
    );
}

/// A CSV opened for f64 data in one pass: its rows counted from its lines (blank lines, a
/// comment, CRLF ends, a quoted time, a last line without its end) and its extent from its
/// last row's time (negative times: |t| largest at the start, read with the first chunk);
/// its digits are left to the reading. A CSV that is not ASCII is surveyed as before.
#[test]
fn a_csv_opened_in_one_pass_counts_its_rows_and_reads_its_last_time() {
    let rows = [
        "\n",
        "omega1,\"t\",omega2,omega3,alpha1,alpha2,alpha3,beta1,beta2,beta3,note\n",
        "0.1,-7.25,0.2,0.3,1,0,0,0,1,0,a\n",
        " \x0b \r\n",
        "  # a comment\n",
        "0.1,\"-2.5\",0.2,0.3,1,0,0,0,1,0,b\r\n",
        "0.123456789012345678,3.5,0.2,0.3,1,0,0,0,1,0,c",
    ];
    let path = file("one.csv", rows.concat().as_bytes());
    let (mut reader, survey) = TrajectoryReader::open_f64(&path).unwrap();
    assert!(reader.reread_if_long());
    assert_eq!(
        (survey.rows, survey.digits, survey.extent),
        (Some(3), 0, 3.5)
    );
    let mut chunk = super::F64Chunk::default();
    assert!(reader.next_chunk_f64(&mut chunk).unwrap());
    assert_eq!(chunk.times, [-7.25, -2.5, 3.5]);
    assert_eq!(chunk.digits, 18);
    assert_eq!(chunk.long_at.as_deref(), Some("line 7"));

    let mut other = rows.concat();
    other = other.replace("a comment", "a comment, café");
    let path = file("two.csv", other.as_bytes());
    let (reader, survey) = TrajectoryReader::open_f64(&path).unwrap();
    assert!(!reader.reread_if_long());
    assert_eq!(
        (survey.rows, survey.digits, survey.extent),
        (Some(3), 18, 7.25)
    );
}

/// A CSV of more than one block read (1 MiB; lines across the blocks' ends) opened in one
/// pass: every row counted and the last row's time read.
#[test]
fn a_csv_of_many_blocks_counts_every_row() {
    let mut text = String::from("t,omega1,omega2,omega3,alpha1,alpha2,alpha3,beta1,beta2,beta3\n");
    let rows = 50_000;
    for k in 0..rows {
        let t = 0.125 * k as f64;
        text.push_str(&format!("{t},0.1,0.2,0.3,1,0,0,0,1,-0.{k:0>17}\n"));
    }
    assert!(text.len() > 2 << 20);
    let path = file("blocks.csv", text.as_bytes());
    let (_, survey) = TrajectoryReader::open_f64(&path).unwrap();
    assert_eq!(
        (survey.rows, survey.extent),
        (Some(rows), 0.125 * (rows - 1) as f64)
    );
}
