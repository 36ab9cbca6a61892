//! The common form of every data file: named numeric columns of one length, with the
//! file they came from for error messages. Every reader in [`crate::io`] returns one.
//!
//! A time column t_0..t_{N−1} gives the records' step without resampling: the mean
//! step h = (t_{N−1} − t_0)/(N − 1), and the jitter max_i |t_{i+1} − t_i − h| / h.
//! Exported clocks carry some (a 1 kHz MATLAB export: 2.4e-5); up to
//! [`MAX_TIME_JITTER`] it is accepted and the samples are taken as uniform with the
//! mean step (a timing error of 1e-3 h shifts the phase at a frequency with P samples
//! per period by at most 2π·1e-3/P), beyond it the column is
//! [`Error::TimeJitter`]: give the step (`step = h`) instead of the time column.

use faer::Mat;

use crate::error::{Error, Result};

/// The largest relative jitter of a time column accepted as uniform sampling.
pub const MAX_TIME_JITTER: f64 = 1e-3;

/// The step of a time column: its mean step and its jitter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimeStep {
    /// The mean step h = (t_{N−1} − t_0)/(N − 1).
    pub step: f64,
    /// max_i |t_{i+1} − t_i − h| / h.
    pub jitter: f64,
}

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

    /// The mean step of the time column `name` and its jitter (module doc); a jitter
    /// above [`MAX_TIME_JITTER`] is [`Error::TimeJitter`], a column that does not
    /// increase or has fewer than two rows is [`Error::Data`].
    pub fn uniform_step(&self, name: &str) -> Result<TimeStep> {
        let t = self.column(name)?;
        let data = |row: usize, message: String| Error::Data {
            file: self.file.clone(),
            row,
            column: name.to_string(),
            message,
        };
        if t.len() < 2 {
            return Err(data(1, "a time column needs at least two rows".into()));
        }
        let step = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
        // Values are finite (the table rejects others), so plain comparisons are safe.
        if step <= 0.0 {
            return Err(data(
                2,
                format!(
                    "time does not increase: mean step {}",
                    crate::format::number(step)
                ),
            ));
        }
        let mut worst = (0.0, 0);
        for (i, pair) in t.windows(2).enumerate() {
            let dt = pair[1] - pair[0];
            if dt <= 0.0 {
                return Err(data(i + 2, format!("time step {dt} does not increase")));
            }
            let jitter = (dt - step).abs() / step;
            if jitter > worst.0 {
                worst = (jitter, i + 2);
            }
        }
        let (jitter, row) = worst;
        if jitter > MAX_TIME_JITTER {
            return Err(Error::TimeJitter {
                file: self.file.clone(),
                column: name.to_string(),
                row,
                jitter,
                tolerance: MAX_TIME_JITTER,
                step,
            });
        }
        Ok(TimeStep { step, jitter })
    }
}
