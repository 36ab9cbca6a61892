//! The common form of every data file: named numeric columns of one length, with the
//! file they came from for error messages. Every reader in [`crate::io`] returns one.

use faer::Mat;

use crate::error::{Error, Result};

/// A numeric table: column names and column-major values.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// The file it came from (for error messages).
    pub file: String,
    /// Column names from the header row.
    pub headers: Vec<String>,
    /// One vector per column.
    pub columns: Vec<Vec<f64>>,
}

impl Table {
    /// The column named `name`.
    pub fn column(&self, name: &str) -> Result<&[f64]> {
        self.headers
            .iter()
            .position(|h| h == name)
            .map(|k| self.columns[k].as_slice())
            .ok_or_else(|| Error::UnknownName {
                what: format!("column in {}", self.file),
                name: name.to_string(),
                known: self.headers.join(", "),
            })
    }

    /// Number of data rows.
    pub fn rows(&self) -> usize {
        self.columns[0].len()
    }

    /// The columns `names` side by side, one row per sample.
    pub fn matrix(&self, names: &[String]) -> Result<Mat<f64>> {
        let columns = names
            .iter()
            .map(|name| self.column(name))
            .collect::<Result<Vec<_>>>()?;
        Ok(Mat::from_fn(self.rows(), columns.len(), |i, j| {
            columns[j][i]
        }))
    }

    /// The step of the uniformly sampled time column `name`; rows whose spacing departs
    /// from it by more than 1e-6 h are reported.
    pub fn uniform_step(&self, name: &str) -> Result<f64> {
        let table = self;
        let t = table.column(name)?;
        if t.len() < 2 {
            return Err(Error::Data {
                file: table.file.clone(),
                row: 1,
                column: name.to_string(),
                message: "a time column needs at least two rows".into(),
            });
        }
        let step = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
        for (i, pair) in t.windows(2).enumerate() {
            let dt = pair[1] - pair[0];
            // Values are finite (the table rejects others), so a plain comparison is safe.
            if (dt - step).abs() > 1e-6 * step.abs() || step <= 0.0 {
                return Err(Error::Data {
                    file: table.file.clone(),
                    row: i + 2,
                    column: name.to_string(),
                    message: format!("time step {dt} departs from the uniform step {step}"),
                });
            }
        }
        Ok(step)
    }
}
