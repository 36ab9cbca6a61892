//! Stepped-sine tables: for each test point the driving frequency ω, the force a cos ωt
//! on one DOF (the phase reference, phase 0), and every DOF's response amplitude X_i
//! and phase lag φ_i, x_i ≈ X_i cos(ωt − φ_i), φ_i in radians.
//!
//! From records, each window of whole periods gives one point: the fundamentals of the
//! DOFs and of the single force channel ([`super::fundamentals()`]), with
//! a = |F|, X_i = |X_i| and φ_i = wrap(φ_{x,i} − φ_F) into (−π, π].
//!
//! CSV layout (a header row, one point per row, `#` starts a comment line):
//!
//! ```text
//!   label,frequency,force_dof,force_amplitude,amplitude_1,phase_1,…,amplitude_n,phase_n
//! ```
//!
//! In files DOFs are numbered from 1, as engineers do (`force_dof = 4` is the fourth
//! DOF, `amplitude_4` its amplitude); in memory they are 0-based like everywhere else
//! in the API. Numbers are written so that they read back bit for bit.

use std::io::{Read, Write};
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::prep::harmonic::fundamentals::fundamentals;
use crate::prep::quadrature::Quadrature;
use crate::prep::window::WindowSpec;
use crate::record::{LoadDistribution, Record};

/// One stepped-sine test point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SteppedSinePoint {
    /// A label for reports and errors (e.g. "a=0.25").
    pub label: String,
    /// Driving frequency ω > 0 (rad per unit time).
    pub frequency: f64,
    /// The DOF the force acts on (0-based).
    pub force_dof: usize,
    /// Force amplitude a ≥ 0; the force is a cos ωt.
    pub force_amplitude: f64,
    /// Response amplitude X_i ≥ 0 of every DOF.
    pub amplitudes: Vec<f64>,
    /// Response phase lag φ_i of every DOF behind the force (rad).
    pub phases: Vec<f64>,
}

impl SteppedSinePoint {
    /// Number of DOFs.
    pub fn dofs(&self) -> usize {
        self.amplitudes.len()
    }

    /// Checks this point (index `index` of its table) against `dofs` DOFs. The error
    /// comes with the CSV column it concerns.
    fn check(&self, index: usize, dofs: usize) -> std::result::Result<(), (String, Error)> {
        let name = |what: &str| format!("{what} of stepped-sine point {index} ('{}')", self.label);
        if self.amplitudes.len() != dofs {
            return Err((
                String::new(),
                Error::mismatch(
                    format!("DOFs (amplitudes) of point {index} vs point 0"),
                    dofs,
                    self.amplitudes.len(),
                ),
            ));
        }
        if self.phases.len() != dofs {
            return Err((
                String::new(),
                Error::mismatch(name("phases vs amplitudes"), dofs, self.phases.len()),
            ));
        }
        if !(self.frequency.is_finite() && self.frequency > 0.0) {
            return Err((
                "frequency".into(),
                Error::invalid(
                    &name("frequency"),
                    self.frequency,
                    "must be finite and positive",
                ),
            ));
        }
        if !self.force_amplitude.is_finite() {
            return Err((
                "force_amplitude".into(),
                Error::NonFinite {
                    what: name("force amplitude"),
                    row: index,
                    column: 0,
                    value: self.force_amplitude,
                },
            ));
        }
        if self.force_amplitude < 0.0 {
            return Err((
                "force_amplitude".into(),
                Error::invalid(
                    &name("force amplitude"),
                    self.force_amplitude,
                    "must be nonnegative (the force is the phase reference)",
                ),
            ));
        }
        if self.force_dof >= dofs {
            return Err((
                "force_dof".into(),
                Error::DofOutOfRange {
                    what: name("force"),
                    dof: self.force_dof,
                    dofs,
                },
            ));
        }
        for (j, (&amplitude, &phase)) in self.amplitudes.iter().zip(&self.phases).enumerate() {
            if !amplitude.is_finite() {
                return Err((
                    format!("amplitude_{}", j + 1),
                    Error::NonFinite {
                        what: name("amplitudes"),
                        row: index,
                        column: j,
                        value: amplitude,
                    },
                ));
            }
            if amplitude < 0.0 {
                return Err((
                    format!("amplitude_{}", j + 1),
                    Error::invalid(
                        &name(&format!("amplitude of DOF {j}")),
                        amplitude,
                        "must be nonnegative (put the sign in the phase)",
                    ),
                ));
            }
            if !phase.is_finite() {
                return Err((
                    format!("phase_{}", j + 1),
                    Error::NonFinite {
                        what: name("phases"),
                        row: index,
                        column: j,
                        value: phase,
                    },
                ));
            }
        }
        Ok(())
    }
}

/// The unvalidated form a table is deserialized from.
#[derive(Deserialize)]
struct TableParts {
    points: Vec<SteppedSinePoint>,
}

impl TryFrom<TableParts> for SteppedSineTable {
    type Error = Error;
    fn try_from(parts: TableParts) -> Result<Self> {
        SteppedSineTable::new(parts.points)
    }
}

/// A validated stepped-sine table. Construct with [`SteppedSineTable::new`],
/// [`SteppedSineTable::from_records`] or [`SteppedSineTable::read_csv`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(try_from = "TableParts")]
pub struct SteppedSineTable {
    points: Vec<SteppedSinePoint>,
}

/// The fixed leading columns of the CSV layout.
const LEADING: [&str; 4] = ["label", "frequency", "force_dof", "force_amplitude"];

impl SteppedSineTable {
    /// Validates the points: at least one; the same number of DOFs (≥ 1) and as many
    /// phases as amplitudes in each; finite values; ω > 0; a ≥ 0; X_i ≥ 0; the force
    /// DOF in range.
    pub fn new(points: Vec<SteppedSinePoint>) -> Result<Self> {
        let Some(first) = points.first() else {
            return Err(Error::Empty {
                what: "stepped-sine table".into(),
            });
        };
        let dofs = first.dofs();
        if dofs == 0 {
            return Err(Error::Empty {
                what: format!("amplitudes of stepped-sine point 0 ('{}')", first.label),
            });
        }
        for (index, point) in points.iter().enumerate() {
            point.check(index, dofs).map_err(|(_, e)| e)?;
        }
        Ok(SteppedSineTable { points })
    }

    /// The points.
    pub fn points(&self) -> &[SteppedSinePoint] {
        &self.points
    }

    /// Number of DOFs.
    pub fn dofs(&self) -> usize {
        self.points[0].dofs()
    }

    /// One point per window of every record. Each record must have exactly one force
    /// channel acting on one DOF; its fundamental is the phase reference.
    pub fn from_records(records: &[Record], windows: &WindowSpec) -> Result<Self> {
        if records.is_empty() {
            return Err(Error::Empty {
                what: "record list".into(),
            });
        }
        let mut points = Vec::new();
        for (index, record) in records.iter().enumerate() {
            let force_dof = single_force_dof(record)?;
            // The spectral rule reads exactly the samples of the window's whole periods.
            let list = windows.windows(record, index, Quadrature::Spectral)?;
            let several = list.len() > 1;
            for window in list {
                let f = fundamentals(record, window.start, window.cycles)?;
                let force = f.forces[0];
                let label = if several {
                    format!("{} #{}", record.label(), window.index)
                } else {
                    record.label().to_string()
                };
                points.push(SteppedSinePoint {
                    label,
                    frequency: f.frequency,
                    force_dof,
                    force_amplitude: force.amplitude,
                    amplitudes: f.displacements.iter().map(|p| p.amplitude).collect(),
                    phases: f
                        .displacements
                        .iter()
                        .map(|p| crate::prep::fourier::wrap_phase(p.phase - force.phase))
                        .collect(),
                });
            }
        }
        Self::new(points)
    }

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
        let mut out = csv::Writer::from_writer(writer);
        out.write_record(Self::header(self.dofs()))
            .map_err(|e| io_error(0, &e))?;
        for (index, p) in self.points.iter().enumerate() {
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

    /// Writes the table as a CSV file.
    pub fn save_csv(&self, path: &Path) -> Result<()> {
        let file = path.display().to_string();
        let handle = std::fs::File::create(path).map_err(|e| Error::Data {
            file: file.clone(),
            row: 0,
            column: String::new(),
            message: e.to_string(),
        })?;
        self.write_csv(handle, &file)
    }

    /// Reads a CSV file.
    pub fn load_csv(path: &Path) -> Result<Self> {
        let file = path.display().to_string();
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
        let mut input = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
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

/// The DOF of a record's single force channel.
fn single_force_dof(record: &Record) -> Result<usize> {
    let forcing = record.forcing();
    let channels = forcing.signals.ncols();
    if channels != 1 {
        return Err(Error::mismatch(
            format!(
                "force channels of record '{}' for a stepped-sine point",
                record.label()
            ),
            1,
            channels,
        ));
    }
    match &forcing.distribution {
        LoadDistribution::Dofs(dofs) => Ok(dofs[0]),
        LoadDistribution::Matrix(_) => Err(Error::invalid(
            "load distribution",
            channels as f64,
            &format!(
                "record '{}' spreads its force over a distribution matrix; a stepped-sine point needs the force on one DOF",
                record.label()
            ),
        )),
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
