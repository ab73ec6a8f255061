//! `rsts check FILE.csv` reads f64 data in one pass (rsts_external::stream, `open_f64`): a file
//! with a value of more than 17 digits, found in the first chunk or after it, is read again as
//! high-precision data — its report is that of the whole trajectory checked exactly (the
//! library's `rsts_harness::check`), its MCAP log holds every sample once.

use crate::common;
use common::{camera_v_dopri5_csv, json_doc, rsts, s, stderr, tmp, whole_check};
use rsts_external::stream::CHUNK_ROWS;

/// The rows of `csv` with value `column` of data line `k` (0: the first row) written with 29
/// significant digits.
fn lengthened(csv: &str, k: usize, column: usize) -> String {
    let mut lines: Vec<String> = csv.lines().map(str::to_string).collect();
    let mut fields: Vec<String> = lines[k + 1].split(',').map(str::to_string).collect();
    let x: f64 = fields[column].parse().unwrap();
    fields[column] = format!("{x:.28e}");
    lines[k + 1] = fields.join(",");
    lines.join("\n") + "\n"
}

#[test]
fn a_long_value_anywhere_makes_a_file_high_precision_data() {
    let n = CHUNK_ROWS + 300;
    let csv = String::from_utf8(camera_v_dopri5_csv("100", n)).unwrap();
    for (what, k) in [("first chunk", 7), ("after it", CHUNK_ROWS + 250)] {
        let text = lengthened(&csv, k, 5);
        let path = tmp(&format!("long-{k}.csv"));
        std::fs::write(&path, &text).unwrap();
        let raw = rsts_external::parse_trajectory(
            text.as_bytes(),
            rsts_external::FileFormat::Csv,
            s(&path),
        )
        .unwrap();
        assert!(raw.is_high_precision());
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let whole = whole_check(&raw, s(&path), &name, raw.digits() as u32);
        assert_eq!(whole["digits"], 29, "{what}: {whole}");

        let mcap = tmp(&format!("long-{k}.mcap"));
        let out = rsts(&["check", s(&path), "--format", "json", "--mcap", s(&mcap)]);
        let mut file = json_doc(&out);
        assert_eq!(file["mcap"], s(&mcap), "{what}");
        file.as_object_mut().unwrap().remove("mcap");
        assert_eq!(
            file, whole,
            "{what}: the file read again vs the whole trajectory"
        );
        let note = stderr(&out);
        assert!(note.contains(&format!("({n} samples,")), "{what}: {note}");
    }
}
