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

/// What a table shows for a figure that is not known (JSON: null, CSV: an empty cell).
pub const NA: &str = "n/a";

/// A count, or "n/a" when not known.
pub fn or_na(x: Option<u64>) -> String {
    x.map_or_else(|| NA.to_string(), |x| x.to_string())
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

/// Largest size of one output file (2 GiB): a job whose estimated output is larger is refused
/// before it starts.
pub const MAX_OUTPUT_BYTES: f64 = 2.0 * 1024.0 * 1024.0 * 1024.0;

/// Refuse an output of about `bytes` bytes above [`MAX_OUTPUT_BYTES`], naming the option that
/// sets its size.
pub fn check_output_bytes(option: &str, what: &str, bytes: f64) -> anyhow::Result<()> {
    if bytes > MAX_OUTPUT_BYTES {
        anyhow::bail!(
            "{option}: {what} would take about {} bytes, more than the {} bytes (2 GiB) one output file may have; ask for less",
            rsts_dynamics::short(bytes),
            rsts_dynamics::short(MAX_OUTPUT_BYTES)
        );
    }
    Ok(())
}

/// A non-finite number never reaches the output: it is an error naming the column and row.
fn check_row(header: &[String], r: usize, row: &[Cell]) -> io::Result<()> {
    for (c, cell) in row.iter().enumerate() {
        if let Cell::Num(x) = cell {
            if !x.is_finite() {
                return Err(io::Error::new(
                    io::ErrorKind::InvalidData,
                    format!(
                        "the result is not finite: {} = {x} in row {}",
                        header.get(c).map_or("?", String::as_str),
                        r + 1
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// CSV: one header line, then one line per row; numbers at full precision.
pub fn write_csv(out: &mut dyn Write, table: &Tabular) -> io::Result<()> {
    write_csv_rows(out, &table.header, table.rows.iter().cloned())
}

/// [`write_csv`] of rows made on demand (nothing but the current row is kept).
pub fn write_csv_rows(
    out: &mut dyn Write,
    header: &[String],
    rows: impl Iterator<Item = Vec<Cell>>,
) -> io::Result<()> {
    write_csv_header(out, header)?;
    for (r, row) in rows.enumerate() {
        write_csv_row(out, header, r, &row)?;
    }
    Ok(())
}

/// The header line of a CSV written a row at a time ([`write_csv_row`]).
pub fn write_csv_header(out: &mut dyn Write, header: &[String]) -> io::Result<()> {
    let names: Vec<String> = header.iter().map(|h| csv_field(h)).collect();
    writeln!(out, "{}", names.join(","))
}

/// Row `r` (0-based) of a CSV written a row at a time.
pub fn write_csv_row(
    out: &mut dyn Write,
    header: &[String],
    r: usize,
    row: &[Cell],
) -> io::Result<()> {
    check_row(header, r, row)?;
    let fields: Vec<String> = row.iter().map(|c| csv_field(&c.exact())).collect();
    writeln!(out, "{}", fields.join(","))
}

/// Widest readable number of a table cell (`-999999.9999999999`, `-1.234567e-100`).
pub const READABLE_WIDTH: usize = 18;

/// A table written a row at a time: columns of given widths (at least their header's),
/// right-aligned, two spaces apart; a wider cell shifts its row, nothing is cut.
pub struct StreamedTable {
    header: Vec<String>,
    widths: Vec<usize>,
    rows: usize,
}

impl StreamedTable {
    /// Write the header and the rule.
    pub fn start(out: &mut dyn Write, header: &[&str], widths: &[usize]) -> io::Result<Self> {
        let widths: Vec<usize> = header
            .iter()
            .zip(widths)
            .map(|(h, &w)| w.max(h.chars().count()))
            .collect();
        let table = Self {
            header: header.iter().map(|h| h.to_string()).collect(),
            widths,
            rows: 0,
        };
        table.line(out, header.iter().map(|h| h.to_string()))?;
        let total = table.widths.iter().sum::<usize>() + 2 * table.widths.len().saturating_sub(1);
        writeln!(out, "{}", "-".repeat(total))?;
        Ok(table)
    }

    fn line(&self, out: &mut dyn Write, items: impl Iterator<Item = String>) -> io::Result<()> {
        let padded: Vec<String> = items
            .zip(&self.widths)
            .map(|(s, &w)| format!("{}{s}", " ".repeat(w.saturating_sub(s.chars().count()))))
            .collect();
        writeln!(out, "{}", padded.join("  "))
    }

    /// One more row.
    pub fn row(&mut self, out: &mut dyn Write, row: &[Cell]) -> io::Result<()> {
        check_row(&self.header, self.rows, row)?;
        self.rows += 1;
        self.line(out, row.iter().map(Cell::readable))
    }
}

/// A JSON object `{"KEY": VALUE, ..., "LIST": [ITEM, ...]}` written an item at a time, byte for
/// byte what [`write_json`] writes of the whole object (pretty, two spaces per level).
pub struct StreamedJson {
    items: usize,
}

/// `value` pretty-printed, its lines after the first indented by `indent` spaces.
fn pretty_at<T: Serialize + ?Sized>(value: &T, indent: usize) -> io::Result<String> {
    let text = serde_json::to_string_pretty(value)?;
    Ok(text.replace('\n', &format!("\n{}", " ".repeat(indent))))
}

impl StreamedJson {
    /// Write `{`, the fields before the list and the list's opening.
    pub fn start(
        out: &mut dyn Write,
        fields: &[(&str, &dyn erased::Json)],
        list: &str,
    ) -> io::Result<Self> {
        writeln!(out, "{{")?;
        for (k, v) in fields {
            writeln!(out, "  {}: {},", serde_json::to_string(k)?, v.pretty_at(2)?)?;
        }
        write!(out, "  {}: [", serde_json::to_string(list)?)?;
        Ok(Self { items: 0 })
    }

    /// One more item of the list.
    pub fn item<T: Serialize>(&mut self, out: &mut dyn Write, item: &T) -> io::Result<()> {
        let sep = if self.items == 0 { "" } else { "," };
        write!(out, "{sep}\n    {}", pretty_at(item, 4)?)?;
        self.items += 1;
        Ok(())
    }

    /// Close the list and the object.
    pub fn finish(self, out: &mut dyn Write) -> io::Result<()> {
        if self.items > 0 {
            write!(out, "\n  ")?;
        }
        writeln!(out, "]\n}}")
    }
}

/// A serialisable value behind a `dyn` (for [`StreamedJson::start`]).
pub mod erased {
    /// A value that can be pretty-printed at an indentation.
    pub trait Json {
        fn pretty_at(&self, indent: usize) -> std::io::Result<String>;
    }

    impl<T: serde::Serialize> Json for T {
        fn pretty_at(&self, indent: usize) -> std::io::Result<String> {
            super::pretty_at(self, indent)
        }
    }
}

/// Right-aligned columns separated by two spaces, a header and a rule.
pub fn write_table(out: &mut dyn Write, table: &Tabular) -> io::Result<()> {
    write_table_rows(out, &table.header, || table.rows.iter().cloned())
}

/// [`write_table`] of rows made on demand, twice: once for the column widths, once to print
/// (nothing but the current row is kept).
pub fn write_table_rows<I: Iterator<Item = Vec<Cell>>>(
    out: &mut dyn Write,
    header: &[String],
    rows: impl Fn() -> I,
) -> io::Result<()> {
    let mut widths: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for (r, row) in rows().enumerate() {
        check_row(header, r, &row)?;
        for (w, c) in widths.iter_mut().zip(&row) {
            *w = (*w).max(c.readable().chars().count());
        }
    }
    let line = |items: &mut dyn Iterator<Item = String>| -> String {
        let padded: Vec<String> = items
            .zip(&widths)
            // Padded by hand: a format width is limited to 65535 (a 100000-digit cell panicked).
            .map(|(s, &w)| {
                let pad = w.saturating_sub(s.chars().count());
                format!("{}{s}", " ".repeat(pad))
            })
            .collect();
        padded.join("  ")
    };
    writeln!(out, "{}", line(&mut header.iter().cloned()))?;
    let total = widths.iter().sum::<usize>() + 2 * widths.len().saturating_sub(1);
    writeln!(out, "{}", "-".repeat(total))?;
    for row in rows() {
        writeln!(out, "{}", line(&mut row.iter().map(Cell::readable)))?;
    }
    Ok(())
}

/// A JSON value that keeps the order of object keys (serde_json's `Value` sorts them), so CSV
/// columns come in the order of the document's fields.
enum Ordered {
    Leaf(serde_json::Value),
    Object(Vec<(String, Ordered)>),
    Array(Vec<Ordered>),
}

impl<'de> serde::Deserialize<'de> for Ordered {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::{MapAccess, SeqAccess, Visitor};
        use serde_json::Value;
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = Ordered;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a JSON value")
            }
            fn visit_bool<E>(self, b: bool) -> Result<Ordered, E> {
                Ok(Ordered::Leaf(Value::Bool(b)))
            }
            fn visit_i64<E>(self, x: i64) -> Result<Ordered, E> {
                Ok(Ordered::Leaf(Value::from(x)))
            }
            fn visit_u64<E>(self, x: u64) -> Result<Ordered, E> {
                Ok(Ordered::Leaf(Value::from(x)))
            }
            fn visit_f64<E>(self, x: f64) -> Result<Ordered, E> {
                Ok(Ordered::Leaf(Value::from(x)))
            }
            fn visit_str<E>(self, s: &str) -> Result<Ordered, E> {
                Ok(Ordered::Leaf(Value::from(s)))
            }
            fn visit_unit<E>(self) -> Result<Ordered, E> {
                Ok(Ordered::Leaf(Value::Null))
            }
            fn visit_none<E>(self) -> Result<Ordered, E> {
                Ok(Ordered::Leaf(Value::Null))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut a: A) -> Result<Ordered, A::Error> {
                let mut v = Vec::new();
                while let Some(x) = a.next_element()? {
                    v.push(x);
                }
                Ok(Ordered::Array(v))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut a: A) -> Result<Ordered, A::Error> {
                let mut v = Vec::new();
                while let Some((k, x)) = a.next_entry()? {
                    v.push((k, x));
                }
                Ok(Ordered::Object(v))
            }
        }
        d.deserialize_any(V)
    }
}

/// The leaves of a document as CSV columns, in the order of its fields: object keys joined by
/// `_`, array elements numbered from 1 after the name (`omega1`, `drift_H`); a scalar at the top
/// is the column `value`.
pub fn flatten_columns<T: Serialize + ?Sized>(
    doc: &T,
) -> serde_json::Result<Vec<(String, serde_json::Value)>> {
    fn go(prefix: &str, v: Ordered, out: &mut Vec<(String, serde_json::Value)>) {
        match v {
            Ordered::Object(m) => {
                for (k, x) in m {
                    let name = if prefix.is_empty() {
                        k
                    } else {
                        format!("{prefix}_{k}")
                    };
                    go(&name, x, out);
                }
            }
            Ordered::Array(a) => {
                for (i, x) in a.into_iter().enumerate() {
                    go(&format!("{prefix}{}", i + 1), x, out);
                }
            }
            Ordered::Leaf(leaf) => out.push((
                if prefix.is_empty() {
                    "value".to_string()
                } else {
                    prefix.to_string()
                },
                leaf,
            )),
        }
    }
    let ordered: Ordered = serde_json::from_str(&serde_json::to_string(doc)?)?;
    let mut out = Vec::new();
    go("", ordered, &mut out);
    Ok(out)
}

/// CSV of documents (one row each, [`flatten_columns`]): the header is the union of the columns
/// in order of first appearance; numbers at full precision, null or missing empty.
pub fn write_records_csv<T: Serialize>(out: &mut dyn Write, records: &[T]) -> io::Result<()> {
    use serde_json::Value;
    let flat = records
        .iter()
        .map(flatten_columns)
        .collect::<serde_json::Result<Vec<_>>>()?;
    let mut header: Vec<String> = Vec::new();
    for row in &flat {
        for (k, _) in row {
            if !header.contains(k) {
                header.push(k.clone());
            }
        }
    }
    let mut table = Tabular::new(header.clone());
    for row in flat {
        let cells = header
            .iter()
            .map(|h| match row.iter().find(|(k, _)| k == h).map(|(_, v)| v) {
                Some(Value::Number(n)) => match n.as_f64() {
                    Some(x) if n.is_f64() => Cell::Num(x),
                    _ => Cell::Text(n.to_string()),
                },
                Some(Value::String(s)) => Cell::Text(s.clone()),
                Some(Value::Bool(b)) => Cell::Text(b.to_string()),
                _ => Cell::Text(String::new()),
            })
            .collect();
        table.push(cells);
    }
    write_csv(out, &table)
}

/// `key: value` lines with the values aligned.
pub fn write_key_values(out: &mut dyn Write, items: &[(&str, String)]) -> io::Result<()> {
    let width = items
        .iter()
        .map(|(k, _)| k.chars().count())
        .max()
        .unwrap_or(0);
    write_key_values_at(out, items, width)
}

/// [`write_key_values`] with the values after keys of `width` characters (a block written in
/// parts lines up as one).
pub fn write_key_values_at(
    out: &mut dyn Write,
    items: &[(&str, String)],
    width: usize,
) -> io::Result<()> {
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

/// Count one more done on `bar`, drawing it on stderr once the run has taken a second, and only
/// on a terminal (`shown` remembers that it is drawn).
pub fn tick_progress(bar: &indicatif::ProgressBar, started: std::time::Instant, shown: &mut bool) {
    tick_progress_by(bar, started, shown, 1);
}

/// [`tick_progress`] of `done` more at once (a caller that counts many small steps ticks
/// every so many: a tick reads the clock).
pub fn tick_progress_by(
    bar: &indicatif::ProgressBar,
    started: std::time::Instant,
    shown: &mut bool,
    done: u64,
) {
    use std::io::IsTerminal;
    if !*shown
        && started.elapsed() > std::time::Duration::from_secs(1)
        && std::io::stderr().is_terminal()
    {
        bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
        *shown = true;
    }
    bar.inc(done);
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
