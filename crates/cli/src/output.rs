//! Writers shared by all subcommands: JSON (any `Serialize` value), CSV and aligned text tables
//! (a [`Tabular`]: header and rows of [`Cell`]s).

use std::io::{self, Write};

use clap::ValueEnum;
use serde::Serialize;

/// Output format chosen on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// One JSON document
    Json,
    /// Comma-separated values with one header line, full precision
    Csv,
    /// Aligned human-readable table with a summary
    Table,
}

/// One value of a table.
// Int and Text are for the subcommands that tabulate counts and names (bench, compare).
#[allow(dead_code)]
#[derive(Clone, Debug, PartialEq)]
pub enum Cell {
    Num(f64),
    Int(u64),
    Text(String),
}

impl Cell {
    /// Full precision (shortest representation that reads back to the same f64).
    fn exact(&self) -> String {
        match self {
            Cell::Num(x) => format!("{x:?}"),
            Cell::Int(n) => n.to_string(),
            Cell::Text(s) => s.clone(),
        }
    }

    /// Readable: fixed notation for moderate magnitudes, scientific otherwise.
    fn readable(&self) -> String {
        match self {
            Cell::Num(x) => readable_number(*x),
            other => other.exact(),
        }
    }
}

/// `x` with about 10 significant digits, in fixed notation when 1e-3 <= |x| < 1e6.
pub fn readable_number(x: f64) -> String {
    let m = x.abs();
    if x == 0.0 || (1e-3..1e6).contains(&m) {
        format!("{x:.10}")
    } else {
        format!("{x:.6e}")
    }
}

/// A header and rows of the same width.
#[derive(Clone, Debug, Default)]
pub struct Tabular {
    pub header: Vec<String>,
    pub rows: Vec<Vec<Cell>>,
}

impl Tabular {
    pub fn new<S: Into<String>>(header: impl IntoIterator<Item = S>) -> Self {
        Self {
            header: header.into_iter().map(Into::into).collect(),
            rows: Vec::new(),
        }
    }

    pub fn push(&mut self, row: Vec<Cell>) {
        debug_assert_eq!(
            row.len(),
            self.header.len(),
            "row width differs from header"
        );
        self.rows.push(row);
    }
}

/// Pretty-printed JSON followed by a newline.
pub fn write_json<T: Serialize + ?Sized>(out: &mut dyn Write, value: &T) -> io::Result<()> {
    serde_json::to_writer_pretty(&mut *out, value)?;
    writeln!(out)
}

/// Quote a CSV field when needed (RFC 4180).
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// CSV: one header line, then one line per row; numbers at full precision.
pub fn write_csv(out: &mut dyn Write, table: &Tabular) -> io::Result<()> {
    let header: Vec<String> = table.header.iter().map(|h| csv_field(h)).collect();
    writeln!(out, "{}", header.join(","))?;
    for row in &table.rows {
        let fields: Vec<String> = row.iter().map(|c| csv_field(&c.exact())).collect();
        writeln!(out, "{}", fields.join(","))?;
    }
    Ok(())
}

/// Right-aligned columns separated by two spaces, a header and a rule.
pub fn write_table(out: &mut dyn Write, table: &Tabular) -> io::Result<()> {
    let cells: Vec<Vec<String>> = table
        .rows
        .iter()
        .map(|row| row.iter().map(Cell::readable).collect())
        .collect();
    let mut widths: Vec<usize> = table.header.iter().map(|h| h.chars().count()).collect();
    for row in &cells {
        for (w, c) in widths.iter_mut().zip(row) {
            *w = (*w).max(c.chars().count());
        }
    }
    let line = |items: &[String]| -> String {
        let padded: Vec<String> = items
            .iter()
            .zip(&widths)
            .map(|(s, &w)| format!("{s:>w$}"))
            .collect();
        padded.join("  ")
    };
    writeln!(out, "{}", line(&table.header))?;
    let total = widths.iter().sum::<usize>() + 2 * widths.len().saturating_sub(1);
    writeln!(out, "{}", "-".repeat(total))?;
    for row in &cells {
        writeln!(out, "{}", line(row))?;
    }
    Ok(())
}

/// `key: value` lines with the values aligned.
pub fn write_key_values(out: &mut dyn Write, items: &[(&str, String)]) -> io::Result<()> {
    let width = items
        .iter()
        .map(|(k, _)| k.chars().count())
        .max()
        .unwrap_or(0);
    for (k, v) in items {
        writeln!(out, "{:<width$}  {v}", format!("{k}:"), width = width + 1)?;
    }
    Ok(())
}

/// For the per-camera tables: name the cameras of Table 1 that `found` does not report (a scan
/// of the (m, h) plane misses cameras that are too thin at some b/a).
pub fn write_missing_cameras(out: &mut dyn Write, found: impl Fn(&str) -> bool) -> io::Result<()> {
    let missing: Vec<&str> = rsts_closed_form::Camera::ALL
        .iter()
        .map(|c| c.label())
        .filter(|l| !found(l))
        .collect();
    if missing.is_empty() {
        return Ok(());
    }
    writeln!(
        out,
        "not found on the scan of the (m, h) plane (too thin at this b/a): {}",
        missing.join(", ")
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Tabular {
        let mut t = Tabular::new(["t", "x", "note"]);
        t.push(vec![
            Cell::Num(0.0),
            Cell::Num(0.1 + 0.2),
            Cell::Text("a,b".into()),
        ]);
        t.push(vec![Cell::Num(1.5), Cell::Num(-1e-12), Cell::Int(7)]);
        t
    }

    #[test]
    fn csv_has_header_and_exact_numbers() {
        let mut buf = Vec::new();
        write_csv(&mut buf, &sample()).unwrap();
        let text = String::from_utf8(buf).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 3);
        assert_eq!(lines[0], "t,x,note");
        let x: f64 = lines[1].split(',').nth(1).unwrap().parse().unwrap();
        assert_eq!(x, 0.1 + 0.2, "csv must round-trip f64 exactly");
        assert!(lines[1].ends_with("\"a,b\""));
    }

    #[test]
    fn table_columns_are_aligned() {
        let mut buf = Vec::new();
        write_table(&mut buf, &sample()).unwrap();
        let text = String::from_utf8(buf).unwrap();
        let widths: Vec<usize> = text.lines().map(|l| l.chars().count()).collect();
        assert!(widths.iter().all(|&w| w == widths[0]), "{text}");
    }
}
