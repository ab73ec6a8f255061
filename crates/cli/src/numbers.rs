//! How the closed-form commands (`explicit`, `events`, `identify`, `reference`) show the numbers
//! of their outcomes: an f64 in full or readable, a decimal string of the digits asked as it is.

use rsts_flows::Number;

use crate::output::Cell;

/// A table or CSV cell of `x`: an f64 as a number; a decimal string as written (CSV) or, in a
/// `table` of at most 17 digits, as the number it reads as.
pub fn cell(x: &Number, table: bool) -> Cell {
    match x {
        Number::F64(v) => Cell::Num(*v),
        Number::Decimal(s) if table => s.parse().map_or(Cell::Text(s.clone()), Cell::Num),
        Number::Decimal(s) => Cell::Text(s.clone()),
    }
}

/// A time in full: the shortest f64 text that reads back to it, or the decimal string.
pub fn time_cell(t: &Number) -> Cell {
    match t {
        Number::F64(v) => Cell::Text(format!("{v:?}")),
        Number::Decimal(s) => Cell::Text(s.clone()),
    }
}

/// A number for a summary line: an f64 shortest, a decimal of up to 24 characters as the f64
/// it reads as (`1.000…e0` → `1`), a longer one as written.
pub fn short(x: &Number) -> String {
    match x {
        Number::F64(v) => format!("{v}"),
        Number::Decimal(s) => match s.parse::<f64>() {
            Ok(v) if s.len() <= 24 => format!("{v}"),
            _ => s.clone(),
        },
    }
}

/// Column names of the vectors `names`, three components each (`omega1`, `omega2`, …).
pub fn vector_columns(names: &[&str]) -> Vec<String> {
    names
        .iter()
        .flat_map(|n| (1..=3).map(move |i| format!("{n}{i}")))
        .collect()
}
