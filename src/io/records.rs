//! Records as CSV files, the inverse of reading a record from a table's columns: one
//! row per sample with the columns `t`, `x1`…`xn`, `v1`…`vn` (when the record has
//! velocities) and `f1`…`fk` (one per force channel). `dampid simulate` writes them,
//! and a model file's `[[data.records]]` reads them back by these names.

use std::path::Path;

use crate::error::Result;
use crate::io::csv;
use crate::io::output::Overwrite;
use crate::record::Record;

/// The column names and values of `record` in the layout above.
pub fn record_columns(record: &Record) -> (Vec<String>, Vec<Vec<f64>>) {
    let n = record.dofs();
    let samples = record.samples();
    let mut headers = vec!["t".to_string()];
    let mut columns = vec![
        (0..samples)
            .map(|i| record.start_time() + i as f64 * record.step())
            .collect::<Vec<_>>(),
    ];
    for j in 0..n {
        headers.push(format!("x{}", j + 1));
        columns.push(record.displacements().col(j).iter().copied().collect());
    }
    if let Some(v) = record.velocities() {
        for j in 0..n {
            headers.push(format!("v{}", j + 1));
            columns.push(v.col(j).iter().copied().collect());
        }
    }
    let signals = &record.forcing().signals;
    for c in 0..signals.ncols() {
        headers.push(format!("f{}", c + 1));
        columns.push(signals.col(c).iter().copied().collect());
    }
    (headers, columns)
}

/// Writes `record` as a CSV file at `path` (atomically; an existing file is an error
/// under [`Overwrite::Refuse`]).
pub fn write_record(path: &Path, record: &Record, overwrite: Overwrite) -> Result<()> {
    let (headers, columns) = record_columns(record);
    csv::write(path, &headers, &columns, overwrite)
}
