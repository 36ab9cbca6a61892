//! Where the equations come from: the one input of [`super::Regressor::build`].
//!
//! - **Records** (time histories): one equation per window of whole periods, or per
//!   fixed span of a non-periodic record, as the [`super::RegressorSettings`] cut them:
//!   A_rk = ∫_r vᵀ f_k dt, b_r = ∫_r vᵀ r dt.
//! - **A stepped-sine table**: one equation per measured point p (ω, a, X_i, φ_i) by
//!   the harmonic approximation (eq. 4), b_p = π a X_f sin φ̄, each point's response
//!   first corrected by its sweep's residual receptance when that is estimated
//!   ([`crate::prep::harmonic::residual`]), plus closed-form structural damping
//!   (`regressor/stepped_sine.rs`). The settings' windows, rule and velocity do not
//!   apply to a table: each point is one period of its synthesized harmonic motion.
//!
//! - **Rows built already** (by hand, or stacked from a campaign's records): the
//!   regressor as it is; nothing in it can be rebuilt at other parameter values.
//!
//! Each equation keeps its identity ([`super::RowLabel`]): record and window for
//! records; sweep, the point's place in it and its frequency for a table, so that
//! reports speak of sweeps ("sweep RC3, 80.15 Hz"), not of synthesized records.

use std::sync::Arc;

use crate::error::{Error, Result};
use crate::prep::harmonic::HarmonicApproximation;
use crate::prep::harmonic::residual::{self, ResidualKind};
use crate::prep::harmonic::sweeps::SweptTable;
use crate::record::Record;
use crate::regressor::Regressor;
use crate::regressor::nonlinear::NonlinearParameter;
use crate::regressor::structural_term::StructuralTerm;

/// The equations' source.
#[derive(Debug, Clone, Copy)]
pub enum Source<'a> {
    /// Time records, cut into windows by the regressor settings.
    Records(&'a [Record]),
    /// A measured stepped-sine table; `residual` holds the values of its residual
    /// receptance unknowns (per sweep, in the order of
    /// [`SteppedSineSource::residual_parameters`]; empty: the response as measured).
    Table {
        /// The table.
        table: &'a SteppedSineSource,
        /// The residual receptance unknowns (empty: none).
        residual: &'a [f64],
    },
    /// A regressor built already.
    Rows(&'a Regressor),
}

impl<'a> Source<'a> {
    /// The table as measured (no residual correction).
    pub fn table(table: &'a SteppedSineSource) -> Self {
        Source::Table {
            table,
            residual: &[],
        }
    }

    /// The records, for a records source.
    pub fn records(&self) -> Option<&'a [Record]> {
        match self {
            Source::Records(records) => Some(records),
            _ => None,
        }
    }

    /// The table, for a table source.
    pub fn stepped_sine(&self) -> Option<&'a SteppedSineSource> {
        match self {
            Source::Table { table, .. } => Some(table),
            _ => None,
        }
    }

    /// What one group of equations is called in reports: a record, or a sweep.
    pub fn unit(&self) -> &'static str {
        match self {
            Source::Table { .. } => "sweep",
            _ => "record",
        }
    }

    /// How many records or sweeps the equations come from.
    pub fn groups(&self) -> usize {
        match self {
            Source::Records(records) => records.len(),
            Source::Table { table, .. } => table.table.sweep_names.len(),
            Source::Rows(rows) => {
                let mut seen: Vec<usize> = rows.rows().iter().map(|r| r.record_index).collect();
                seen.sort_unstable();
                seen.dedup();
                seen.len()
            }
        }
    }
}

impl<'a> From<&'a [Record]> for Source<'a> {
    fn from(records: &'a [Record]) -> Self {
        Source::Records(records)
    }
}

impl<'a> From<&'a Vec<Record>> for Source<'a> {
    fn from(records: &'a Vec<Record>) -> Self {
        Source::Records(records)
    }
}

impl<'a, const N: usize> From<&'a [Record; N]> for Source<'a> {
    fn from(records: &'a [Record; N]) -> Self {
        Source::Records(records)
    }
}

impl<'a> From<&'a Arc<[Record]>> for Source<'a> {
    fn from(records: &'a Arc<[Record]>) -> Self {
        Source::Records(records)
    }
}

impl<'a> From<&'a Regressor> for Source<'a> {
    fn from(rows: &'a Regressor) -> Self {
        Source::Rows(rows)
    }
}

impl<'a> From<&'a SteppedSineSource> for Source<'a> {
    fn from(table: &'a SteppedSineSource) -> Self {
        Source::table(table)
    }
}

/// A known modal mass and stiffness of a one-mode table (a model file's `[system]`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KnownModal {
    /// m.
    pub mass: f64,
    /// k.
    pub stiffness: f64,
}

/// A measured stepped-sine table ready to give equations.
#[derive(Debug, Clone)]
pub struct SteppedSineSource {
    /// The points, their sweeps and noise.
    pub table: SweptTable,
    /// Structural damping terms (their columns follow the model's).
    pub structural: Vec<StructuralTerm>,
    /// How the synthesized motion's phases are read.
    pub approximation: HarmonicApproximation,
    /// Which residual receptance unknowns each sweep carries.
    pub residual: ResidualKind,
    /// The residual unknowns with their bounds (per sweep in sweep order: r_k, then
    /// r_m for [`ResidualKind::MassAndStiffness`]; empty for [`ResidualKind::None`]).
    pub residual_parameters: Vec<NonlinearParameter>,
    /// The file the table was read from (`None`: built in memory).
    pub file: Option<String>,
    /// The modal mass and stiffness when known (`[system]`).
    pub system: Option<KnownModal>,
}

impl SteppedSineSource {
    /// A table of `approximation` without structural terms or residual unknowns.
    pub fn new(table: SweptTable, approximation: HarmonicApproximation) -> Self {
        SteppedSineSource {
            table,
            structural: Vec::new(),
            approximation,
            residual: ResidualKind::None,
            residual_parameters: Vec::new(),
            file: None,
            system: None,
        }
    }

    /// Each point's residual receptance R_p for the unknowns `values` (`None` when the
    /// table estimates none and `values` is empty).
    pub(crate) fn per_point(&self, values: &[f64]) -> Result<Option<Vec<f64>>> {
        if values.len() != self.residual_parameters.len() {
            return Err(Error::mismatch(
                "residual receptance values vs the table's residual unknowns",
                self.residual_parameters.len(),
                values.len(),
            ));
        }
        match self.residual {
            ResidualKind::None => Ok(None),
            kind => residual::per_point(kind, values, &self.table).map(Some),
        }
    }

    /// The label of point `p`: its sweep, and its frequency in Hz (ω/2π).
    pub fn point_label(&self, p: usize) -> String {
        let omega = self.table.table.points()[p].frequency;
        format!(
            "{}, {:.2} Hz",
            self.table.sweep_names[self.table.sweeps[p]],
            omega / (2.0 * std::f64::consts::PI)
        )
    }
}
