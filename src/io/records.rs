//! Records as CSV files, the inverse of reading a record from a table's columns: one
//! row per sample with the columns `t`, `x1`…`xn`, `v1`…`vn` (when the record has
//! velocities) and one per force channel, named by the DOF it acts on (`f4` for DOF 4;
//! [`force_columns`]). `dampid simulate` writes them,
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
    let names = force_columns(record);
    for (c, (name, _)) in names.iter().enumerate().take(signals.ncols()) {
        headers.push(name.clone());
        columns.push(signals.col(c).iter().copied().collect());
    }
    (headers, columns)
}

/// The name of each force channel's column and the DOF (1-based) it acts on: `f4` for
/// the force on DOF 4 when every channel acts on a DOF of its own; `force1`, `force2`, …
/// (by channel, no DOF) when channels share a DOF or act through a distribution matrix.
pub fn force_columns(record: &Record) -> Vec<(String, Option<usize>)> {
    let channels = record.forcing().signals.ncols();
    if let crate::record::LoadDistribution::Dofs(dofs) = &record.forcing().distribution {
        let mut sorted = dofs.clone();
        sorted.sort_unstable();
        sorted.dedup();
        if sorted.len() == dofs.len() {
            return dofs
                .iter()
                .map(|d| (format!("f{}", d + 1), Some(d + 1)))
                .collect();
        }
    }
    (1..=channels)
        .map(|c| (format!("force{c}"), None))
        .collect()
}

/// Writes `record` as a CSV file at `path` (atomically; an existing file is an error
/// under [`Overwrite::Refuse`]).
pub fn write_record(path: &Path, record: &Record, overwrite: Overwrite) -> Result<()> {
    let (headers, columns) = record_columns(record);
    csv::write(path, &headers, &columns, overwrite)
}
