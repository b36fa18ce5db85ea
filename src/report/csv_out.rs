//! Sweep results to CSV, and reading a column back.
//!
//! Floats are written by the csv crate's serializer, which uses `ryu`: the shortest
//! decimal that parses back to the same `f64` (so a write/read round trip is exact).
//! Non-finite floats are written as `NaN`, `inf`, `-inf` and read back as such.

use serde::Serialize;
use std::path::Path;

fn err_at(path: &Path, what: impl std::fmt::Display) -> String {
    format!("{}: {what}", path.display())
}

/// Write `rows` to `path` with a header line taken from the struct's field names
/// (`#[serde(rename = "...")]` renames a column). Parent directories are created;
/// the file is replaced atomically (`report::atomic`).
///
/// Zero rows write an empty file (the header comes from the first row, so there is
/// none). Rows must be flat (no nested structs or sequences): the csv crate rejects
/// them, and the error is returned naming the path and the row.
pub fn write_csv<T: Serialize>(path: &Path, rows: &[T]) -> Result<(), String> {
    // Serialised in memory first: a row the csv crate refuses leaves the old file.
    let mut w = csv::Writer::from_writer(Vec::new());
    for (i, r) in rows.iter().enumerate() {
        w.serialize(r)
            .map_err(|e| err_at(path, format!("row {i}: {e}")))?;
    }
    let bytes = w.into_inner().map_err(|e| err_at(path, e))?;
    crate::report::atomic::write_bytes(path, &bytes)
}

/// The values of the column named `column` (header match, exact), parsed as `f64`,
/// in row order. Errors name the path, and the row and column for a bad value.
pub fn read_csv_column(path: &Path, column: &str) -> Result<Vec<f64>, String> {
    let mut r = csv::Reader::from_path(path).map_err(|e| err_at(path, e))?;
    let headers = r.headers().map_err(|e| err_at(path, e))?.clone();
    let idx = headers.iter().position(|h| h == column).ok_or_else(|| {
        err_at(
            path,
            format!(
                "no column \"{column}\" (columns: {})",
                headers.iter().collect::<Vec<_>>().join(", ")
            ),
        )
    })?;
    let mut out = Vec::new();
    for (i, rec) in r.records().enumerate() {
        let rec = rec.map_err(|e| err_at(path, e))?;
        let cell = rec
            .get(idx)
            .ok_or_else(|| err_at(path, format!("row {i}: no field for column \"{column}\"")))?;
        let v: f64 = cell.trim().parse().map_err(|e| {
            err_at(
                path,
                format!("row {i}, column \"{column}\": \"{cell}\" is not a number ({e})"),
            )
        })?;
        out.push(v);
    }
    Ok(out)
}
