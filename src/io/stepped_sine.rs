//! Stepped-sine tables as CSV files: a header row, one point per row, `#` starts a
//! comment line.
//!
//! ```text
//!   label,frequency,force_dof,force_amplitude,amplitude_1,phase_1,…,amplitude_n,phase_n
//! ```
//!
//! In files DOFs are numbered from 1, as engineers do (`force_dof = 4` is the fourth
//! DOF, `amplitude_4` its amplitude); in memory they are 0-based
//! ([`SteppedSineTable`]). Numbers are written so that they read back bit for bit.

use std::io::{Read, Write};
use std::path::Path;

use crate::error::{Error, Result};
use crate::io::output::{self, Overwrite};
use crate::prep::harmonic::{SteppedSinePoint, SteppedSineTable};

/// The leading columns, before the amplitude and phase of each DOF.
const LEADING: [&str; 4] = ["label", "frequency", "force_dof", "force_amplitude"];

impl SteppedSineTable {
    /// The CSV header for `dofs` DOFs.
    fn header(dofs: usize) -> Vec<String> {
        let mut header: Vec<String> = LEADING.iter().map(|s| s.to_string()).collect();
        for j in 1..=dofs {
            header.push(format!("amplitude_{j}"));
            header.push(format!("phase_{j}"));
        }
        header
    }

    /// Writes the table as CSV to `writer` (`file` names it in errors).
    pub fn write_csv<W: Write>(&self, writer: W, file: &str) -> Result<()> {
        let io_error = |row: usize, e: &dyn std::fmt::Display| Error::Data {
            file: file.to_string(),
            row,
            column: String::new(),
            message: e.to_string(),
        };
        let mut out = ::csv::Writer::from_writer(writer);
        out.write_record(Self::header(self.dofs()))
            .map_err(|e| io_error(0, &e))?;
        for (index, p) in self.points().iter().enumerate() {
            let mut fields = vec![
                p.label.clone(),
                number(p.frequency),
                (p.force_dof + 1).to_string(),
                number(p.force_amplitude),
            ];
            for (x, phi) in p.amplitudes.iter().zip(&p.phases) {
                fields.push(number(*x));
                fields.push(number(*phi));
            }
            out.write_record(&fields)
                .map_err(|e| io_error(index + 1, &e))?;
        }
        out.flush().map_err(|e| io_error(0, &e))
    }

    /// Writes the table as a CSV file (atomically; an existing file is an error under
    /// [`Overwrite::Refuse`]).
    pub fn save_csv(&self, path: &Path, overwrite: Overwrite) -> Result<()> {
        let file = path.display().to_string();
        output::write_file(path, overwrite, |sink| self.write_csv(sink, &file)).map(drop)
    }

    /// Reads a CSV file.
    pub fn load_csv(path: &Path) -> Result<Self> {
        let file = path.display().to_string();
        super::require_data_file(path)?;
        let handle = std::fs::File::open(path).map_err(|e| Error::Data {
            file: file.clone(),
            row: 0,
            column: String::new(),
            message: e.to_string(),
        })?;
        Self::read_csv(handle, &file)
    }

    /// Reads CSV from `reader` (`file` names it in errors). Every problem with a cell,
    /// including a value the table would reject (NaN, a negative amplitude, a force DOF
    /// out of range), is an [`Error::Data`] naming the 1-based data row and the column.
    pub fn read_csv<R: Read>(reader: R, file: &str) -> Result<Self> {
        let data_error = |row: usize, column: &str, message: String| Error::Data {
            file: file.to_string(),
            row,
            column: column.to_string(),
            message,
        };
        let mut input = ::csv::ReaderBuilder::new()
            .trim(::csv::Trim::All)
            .comment(Some(b'#'))
            .from_reader(reader);
        let header: Vec<String> = input
            .headers()
            .map_err(|e| data_error(0, "", e.to_string()))?
            .iter()
            .map(str::to_string)
            .collect();
        let extra = header.len().saturating_sub(LEADING.len());
        if header.len() < LEADING.len() + 2 || !extra.is_multiple_of(2) {
            return Err(data_error(
                0,
                "",
                format!(
                    "the header has {} columns; expected {} then amplitude_i, phase_i for each DOF i = 1..n",
                    header.len(),
                    LEADING.join(",")
                ),
            ));
        }
        let dofs = extra / 2;
        let expected = Self::header(dofs);
        if let Some((got, want)) = header.iter().zip(&expected).find(|(g, w)| g != w) {
            return Err(data_error(
                0,
                got,
                format!(
                    "expected column '{want}' here (layout: {})",
                    expected.join(",")
                ),
            ));
        }
        let mut points = Vec::new();
        for (index, row) in input.records().enumerate() {
            let line = index + 1;
            let row = row.map_err(|e| data_error(line, "", e.to_string()))?;
            let real = |k: usize| -> Result<f64> {
                row[k].parse::<f64>().map_err(|_| {
                    data_error(line, &header[k], format!("'{}' is not a number", &row[k]))
                })
            };
            let force_dof: usize = row[2].parse().map_err(|_| {
                data_error(
                    line,
                    "force_dof",
                    format!("'{}' is not a DOF number (1..{dofs})", &row[2]),
                )
            })?;
            if force_dof == 0 || force_dof > dofs {
                return Err(data_error(
                    line,
                    "force_dof",
                    format!(
                        "DOF {force_dof} does not exist: DOFs are numbered 1..{dofs} in table files"
                    ),
                ));
            }
            let point = SteppedSinePoint {
                label: row[0].to_string(),
                frequency: real(1)?,
                force_dof: force_dof - 1,
                force_amplitude: real(3)?,
                amplitudes: (0..dofs).map(|j| real(4 + 2 * j)).collect::<Result<_>>()?,
                phases: (0..dofs).map(|j| real(5 + 2 * j)).collect::<Result<_>>()?,
            };
            point
                .check(points.len(), dofs)
                .map_err(|(column, e)| data_error(line, &column, e.to_string()))?;
            points.push(point);
        }
        if points.is_empty() {
            return Err(data_error(0, "", "no data rows".into()));
        }
        Self::new(points)
    }
}

/// A number that reads back bit for bit, in plain notation when it is of moderate size.
fn number(value: f64) -> String {
    let magnitude = value.abs();
    if value == 0.0 || (1e-4..1e15).contains(&magnitude) {
        format!("{value}")
    } else {
        format!("{value:e}")
    }
}
