//! Stepped-sine tables: for each test point the driving frequency ω, the force a cos ωt
//! on one DOF (the phase reference, phase 0), and every DOF's response amplitude X_i
//! and phase lag φ_i, x_i ≈ X_i cos(ωt − φ_i), φ_i in radians.
//!
//! From records, each window of whole periods gives one point: the fundamentals of the
//! DOFs and of the single force channel ([`super::fundamentals()`]), with
//! a = |F|, X_i = |X_i| and φ_i = wrap(φ_{x,i} − φ_F) into (−π, π].
//!
//! Tables are read from and written to CSV files by [`crate::io::stepped_sine`]. In
//! memory DOFs are 0-based like everywhere else in the API.

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
    pub(crate) fn check(
        &self,
        index: usize,
        dofs: usize,
    ) -> std::result::Result<(), (String, Error)> {
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
                Error::dof_index(name("force"), self.force_dof, dofs),
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
                        &name(&format!("amplitude of DOF {}", j + 1)),
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
