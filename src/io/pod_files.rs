//! Proper orthogonal decomposition of record files (`dampid pod`): read each file
//! (the columns named, or every column it gives: [`super::data_file::DataFile::usable`]), choose its displacement columns, and report the modes'
//! energy shares λ_k / Σ λ (see [`crate::prep::pod`] for the decomposition).

use std::fmt;
use std::path::PathBuf;

use faer::Mat;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::io::table::Table;
use crate::prep::pod::{Pod, PodBasis, PodReport, PodSettings};

/// Column names that are taken for time and left out of [`Columns::AllButTime`].
pub const TIME_COLUMNS: [&str; 2] = ["t", "time"];

/// Which columns of a file are the displacements.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Columns {
    /// Every column except one named `t` or `time` (any case).
    AllButTime,
    /// These columns, in this order.
    Named(Vec<String>),
    /// Every column whose name starts with this prefix, in file order.
    Prefix(String),
}

/// The POD of one file (or of all files stacked, for a shared basis).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FilePod {
    /// The file, or "all files (stacked)".
    pub file: String,
    /// The displacement columns, in mode-shape order.
    pub columns: Vec<String>,
    /// Values, energy shares and shapes.
    pub report: PodReport,
}

/// One POD per file, or one of all files stacked with [`PodBasis::Shared`].
pub fn pod_of_files(
    files: &[PathBuf],
    columns: &Columns,
    settings: &PodSettings,
) -> Result<Vec<FilePod>> {
    if files.is_empty() {
        return Err(Error::Empty {
            what: "file list for the POD".into(),
        });
    }
    let mut blocks = Vec::new();
    for path in files {
        // Named columns are read as `identify` reads them; otherwise every column the
        // file gives (arrays that cannot be columns, scalars and shorter arrays left out).
        let file = super::data_file::DataFile::open(path)?;
        let table = match columns {
            Columns::Named(names) => {
                let names: Vec<&str> = names.iter().map(String::as_str).collect();
                file.into_table(&names)?
            }
            _ => file.usable()?.0,
        };
        let names = chosen(&table, columns)?;
        let values = names
            .iter()
            .map(|name| table.column(name))
            .collect::<Result<Vec<_>>>()?;
        let rows = values.first().map_or(0, |c| c.len());
        let x = Mat::from_fn(rows, values.len(), |i, j| values[j][i]);
        blocks.push((path.display().to_string(), names, x));
    }
    match settings.basis {
        PodBasis::PerRecord => blocks
            .into_iter()
            .map(|(file, columns, x)| {
                Ok(FilePod {
                    report: Pod::from_displacements(x.as_ref(), settings)?.report(),
                    file,
                    columns,
                })
            })
            .collect(),
        PodBasis::Shared => {
            let (_, first_columns, _) = &blocks[0];
            for (file, names, _) in &blocks {
                if names != first_columns {
                    return Err(Error::Data {
                        file: file.clone(),
                        row: 0,
                        column: names.join(","),
                        message: format!(
                            "a shared basis needs the same columns in every file; the first file has {}",
                            first_columns.join(",")
                        ),
                    });
                }
            }
            let rows: usize = blocks.iter().map(|(_, _, x)| x.nrows()).sum();
            let n = first_columns.len();
            let mut stacked = Mat::<f64>::zeros(rows, n);
            let mut row = 0;
            for (_, _, x) in &blocks {
                for i in 0..x.nrows() {
                    for j in 0..n {
                        stacked[(row + i, j)] = x[(i, j)];
                    }
                }
                row += x.nrows();
            }
            Ok(vec![FilePod {
                file: "all files (stacked)".into(),
                columns: first_columns.clone(),
                report: Pod::from_displacements(stacked.as_ref(), settings)?.report(),
            }])
        }
    }
}

/// The columns of `table` that `choice` selects (at least one).
fn chosen(table: &Table, choice: &Columns) -> Result<Vec<String>> {
    let names: Vec<String> = match choice {
        Columns::Named(names) => names.clone(),
        Columns::AllButTime => table
            .headers
            .iter()
            .filter(|h| !TIME_COLUMNS.iter().any(|t| h.eq_ignore_ascii_case(t)))
            .cloned()
            .collect(),
        Columns::Prefix(prefix) => table
            .headers
            .iter()
            .filter(|h| h.starts_with(prefix.as_str()))
            .cloned()
            .collect(),
    };
    if names.is_empty() {
        return Err(Error::Data {
            file: table.file.clone(),
            row: 0,
            column: String::new(),
            message: format!(
                "no displacement columns selected by {choice:?}; the file has: {}",
                table.headers.join(", ")
            ),
        });
    }
    Ok(names)
}

/// The energy tables of [`pod_of_files`], for printing.
pub struct PodTables<'a>(pub &'a [FilePod]);

impl fmt::Display for PodTables<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for pod in self.0 {
            let r = &pod.report;
            writeln!(
                f,
                "{}: {} samples, {} columns ({}){}",
                pod.file,
                r.samples,
                r.dofs,
                pod.columns.join(", "),
                if r.mean_removed {
                    ", means removed"
                } else {
                    ""
                }
            )?;
            writeln!(
                f,
                "  {:>4} {:>13} {:>9} {:>11}  shape",
                "mode", "value λ", "share", "cumulative"
            )?;
            for m in &r.modes {
                let shape: Vec<String> = m.shape.iter().map(|u| format!("{u:+.4}")).collect();
                writeln!(
                    f,
                    "  {:>4} {:>13.6e} {:>8.4}% {:>10.4}%  [{}]",
                    m.index,
                    m.value,
                    100.0 * m.energy_share,
                    100.0 * m.cumulative_share,
                    shape.join(", ")
                )?;
            }
            writeln!(
                f,
                "  retained: {} mode{} ({:.4}% of the energy)",
                r.retained,
                if r.retained == 1 { "" } else { "s" },
                100.0 * r.retained_share
            )?;
        }
        Ok(())
    }
}
