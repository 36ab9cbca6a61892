//! The regressor A θ = b. Row r is one window of one record; column k is one
//! coefficient. With weights w_i of the quadrature rule over the window's samples:
//!
//!   A_rk = Σ_i w_i v(t_i)ᵀ f_k(x(t_i), v(t_i))   (dissipated work per unit θ_k)
//!   b_r  = Σ_i w_i v(t_i)ᵀ r(t_i)                (input work)
//!
//! Mass and stiffness never appear: over whole periods of a periodic motion their
//! stored energy returns to its start.
//!
//! With harmonic-projection velocities the rows come from the noise-robust pipeline
//! ([`crate::regressor::robust`]): columns corrected for the expected noise contribution, and each
//! row's first-order noise sensitivity kept for weighting the fit. With
//! [`WorkForm::DerivativeFree`] the input work is ∫ rᵀ dx and (on raw samples) Coulomb
//! columns are total variations of x ([`crate::regressor::derivative_free`]).

pub(crate) mod derivative_free;
mod kernel;
pub mod nonperiodic;
pub mod robust;

use faer::Mat;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::prep::quadrature::{Quadrature, WindowWeights};
use crate::prep::velocity::VelocitySource;
use crate::prep::window::{Window, WindowSpec};
use crate::record::Record;
use crate::regressor::kernel::{Plan, WindowSamples, build_in_parallel};
use robust::{NoiseModel, NoiseTreatment};

/// How records become equations.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct RegressorSettings {
    /// How records are cut into windows of whole periods.
    pub windows: WindowSpec,
    /// The quadrature rule for window integrals.
    pub quadrature: Quadrature,
    /// Where velocities come from.
    pub velocity: VelocitySource,
    /// Whether columns are corrected for sensor noise (the noise-robust pipeline).
    #[serde(default)]
    pub noise: NoiseTreatment,
    /// Velocity-weighted or derivative-free forms of the input and Coulomb work.
    #[serde(default)]
    pub work_form: WorkForm,
}

/// How the input work (and, on raw samples, Coulomb columns) are integrated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WorkForm {
    /// ∫ vᵀ r dt and ∫ |v| dt with the rule's weights. In the noise-robust pipeline v̂ is
    /// the exact derivative of the projected displacement x̂, so this is ∫ rᵀ dx̂
    /// integrated by the rule (spectrally accurate over whole periods), with no
    /// difference of noisy samples.
    #[default]
    Velocity,
    /// ∫ rᵀ dx as a trapezoidal Stieltjes sum and Coulomb work as the total variation of
    /// the sampled x (see [`crate::regressor::derivative_free`]): no velocity estimate enters them.
    /// Its relative error on a harmonic of phase step δ = kωh is about −δ²/6.
    DerivativeFree,
}

impl RegressorSettings {
    /// The paper's plain pipeline: `velocity` as given, no noise correction,
    /// velocity-weighted work.
    pub fn plain(windows: WindowSpec, quadrature: Quadrature, velocity: VelocitySource) -> Self {
        RegressorSettings {
            windows,
            quadrature,
            velocity,
            noise: NoiseTreatment::Ignore,
            work_form: WorkForm::Velocity,
        }
    }

    /// Whether the noise-robust pipeline runs: `Auto` runs it with harmonic-projection
    /// velocities; `Correct` with any other source is an error.
    pub fn noise_robust(&self) -> Result<bool> {
        let projected = matches!(self.velocity, VelocitySource::HarmonicProjection { .. });
        match self.noise {
            NoiseTreatment::Ignore => Ok(false),
            NoiseTreatment::Auto => Ok(projected),
            NoiseTreatment::Correct if projected => Ok(true),
            NoiseTreatment::Correct => Err(Error::invalid(
                "noise",
                0.0,
                &format!(
                    "noise correction needs velocity = harmonic projection (the noise of a projection is known), not {:?}; set noise = ignore or change the velocity source",
                    self.velocity
                ),
            )),
        }
    }
}

/// Where a row came from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RowLabel {
    /// The record's label.
    pub record: String,
    /// The record's index in the list given.
    pub record_index: usize,
    /// The window's index within its record.
    pub window: usize,
    /// Time of the window's first sample.
    pub start_time: f64,
    /// Whole periods in the window.
    pub cycles: usize,
}

impl RowLabel {
    /// The label of `window` of `record`.
    pub(crate) fn of(window: &Window, record: &Record) -> Self {
        RowLabel {
            record: record.label().to_string(),
            record_index: window.record,
            window: window.index,
            start_time: record.start_time() + window.start as f64 * record.step(),
            cycles: window.cycles,
        }
    }
}

/// The regressor A (equations × coefficients), right-hand side b, and their labels.
#[derive(Debug, Clone)]
pub struct Regressor {
    matrix: Mat<f64>,
    rhs: Vec<f64>,
    columns: Vec<String>,
    rows: Vec<RowLabel>,
    noise: Option<NoiseModel>,
    /// The last `nuisance` columns are stored-energy and offset unknowns
    /// ([`crate::regressor::nonperiodic`]), not damping coefficients.
    nuisance: usize,
}

impl Regressor {
    /// Builds one row per window of every record.
    pub fn build(
        model: &DampingModel,
        records: &[Record],
        settings: &RegressorSettings,
    ) -> Result<Self> {
        if records.is_empty() {
            return Err(Error::Empty {
                what: "record list".into(),
            });
        }
        let columns = model.coefficient_names();
        model.validate_names(&columns)?;
        for record in records {
            model.validate_terms(record.dofs())?;
        }
        let mut windows: Vec<Window> = Vec::new();
        for (index, record) in records.iter().enumerate() {
            windows.extend(
                settings
                    .windows
                    .windows(record, index, settings.quadrature)?,
            );
        }
        let noise_robust = settings.noise_robust()?;
        let (rows, noise): (Vec<(Vec<f64>, f64)>, Option<NoiseModel>) = if noise_robust {
            let robust: Vec<robust::RobustRow> = windows
                .par_iter()
                .map(|w| robust::robust_row(model, &records[w.record], w, settings))
                .collect::<Result<_>>()?;
            let mut rows = Vec::with_capacity(robust.len());
            let mut model_rows = Vec::with_capacity(robust.len());
            let mut summaries = Vec::with_capacity(robust.len());
            for r in robust {
                rows.push((r.columns, r.input));
                model_rows.push(r.noise);
                summaries.push(r.window);
            }
            let noise = NoiseModel {
                rows: model_rows,
                windows: summaries,
            };
            (rows, Some(noise))
        } else {
            let weights = record_weights(records, &windows, settings)?;
            // Small builds stay on the calling thread: every parallel call below would
            // otherwise be a hand-off to the pool costing more than its work.
            let parallel = build_in_parallel(records, columns.len());
            let share = |(record, weights): (&Record, WindowWeights)| RecordShared {
                plan: Plan::new(model, record),
                weights,
            };
            let shared: Vec<RecordShared<'_>> = if parallel {
                records.par_iter().zip(weights).map(share).collect()
            } else {
                records.iter().zip(weights).map(share).collect()
            };
            let row =
                |w: &Window| window_row(&shared[w.record], model, &records[w.record], w, settings);
            let rows = if parallel {
                windows.par_iter().map(row).collect::<Result<_>>()?
            } else {
                windows.iter().map(row).collect::<Result<_>>()?
            };
            (rows, None)
        };
        let matrix = Mat::from_fn(rows.len(), columns.len(), |r, k| rows[r].0[k]);
        let rhs = rows.iter().map(|(_, b)| *b).collect();
        let labels = windows
            .iter()
            .map(|w| RowLabel::of(w, &records[w.record]))
            .collect();
        let mut regressor = Self::from_parts(matrix, rhs, columns, labels)?;
        regressor.noise = noise;
        Ok(regressor)
    }

    /// A regressor from its parts (for research use and tests); validates shapes and
    /// finiteness.
    pub fn from_parts(
        matrix: Mat<f64>,
        rhs: Vec<f64>,
        columns: Vec<String>,
        rows: Vec<RowLabel>,
    ) -> Result<Self> {
        if matrix.nrows() != rhs.len() {
            return Err(Error::mismatch(
                "regressor rows vs right-hand side",
                matrix.nrows(),
                rhs.len(),
            ));
        }
        if matrix.ncols() != columns.len() {
            return Err(Error::mismatch(
                "regressor columns vs coefficient names",
                columns.len(),
                matrix.ncols(),
            ));
        }
        if rows.len() != rhs.len() {
            return Err(Error::mismatch(
                "row labels vs regressor rows",
                rhs.len(),
                rows.len(),
            ));
        }
        for (r, value) in rhs.iter().enumerate() {
            if !value.is_finite() {
                return Err(Error::NonFinite {
                    what: "input work b".into(),
                    row: r,
                    column: 0,
                    value: *value,
                });
            }
        }
        for k in 0..matrix.ncols() {
            for r in 0..matrix.nrows() {
                let value = matrix[(r, k)];
                if !value.is_finite() {
                    return Err(Error::NonFinite {
                        what: format!("regressor column '{}'", columns[k]),
                        row: r,
                        column: k,
                        value,
                    });
                }
            }
        }
        Ok(Regressor {
            matrix,
            rhs,
            columns,
            rows,
            noise: None,
            nuisance: 0,
        })
    }

    /// This regressor with its last `count` columns marked as nuisance unknowns
    /// (stored energy and constant forces of the non-periodic balance).
    pub fn with_nuisance_count(mut self, count: usize) -> Result<Self> {
        if count > self.columns.len() {
            return Err(Error::mismatch(
                "nuisance columns vs regressor columns",
                self.columns.len(),
                count,
            ));
        }
        self.nuisance = count;
        Ok(self)
    }

    /// This regressor with a noise model (one row each), for research use and tests.
    pub fn with_noise(mut self, noise: NoiseModel) -> Result<Self> {
        if noise.rows.len() != self.rhs.len() {
            return Err(Error::mismatch(
                "noise model rows vs regressor rows",
                self.rhs.len(),
                noise.rows.len(),
            ));
        }
        self.noise = Some(noise);
        Ok(self)
    }

    /// The rows `indices` (repeats allowed), with their labels and noise model.
    pub fn select_rows(&self, indices: &[usize]) -> Result<Self> {
        let matrix = Mat::from_fn(indices.len(), self.columns.len(), |r, k| {
            self.matrix[(indices[r], k)]
        });
        let rhs = indices.iter().map(|&i| self.rhs[i]).collect();
        let rows = indices.iter().map(|&i| self.rows[i].clone()).collect();
        let mut selected = Self::from_parts(matrix, rhs, self.columns.clone(), rows)?;
        selected.noise = self.noise.as_ref().map(|n| n.select(indices));
        selected.nuisance = self.nuisance;
        Ok(selected)
    }

    /// Each row multiplied by `weights` (a weighted system W^{1/2}A, W^{1/2}b); the noise
    /// model is dropped (it describes the unweighted rows).
    pub fn weighted(&self, weights: &[f64]) -> Result<Self> {
        if weights.len() != self.rhs.len() {
            return Err(Error::mismatch(
                "row weights vs regressor rows",
                self.rhs.len(),
                weights.len(),
            ));
        }
        let matrix = Mat::from_fn(self.rhs.len(), self.columns.len(), |r, k| {
            weights[r] * self.matrix[(r, k)]
        });
        let rhs = self.rhs.iter().zip(weights).map(|(b, w)| w * b).collect();
        Self::from_parts(matrix, rhs, self.columns.clone(), self.rows.clone())?
            .with_nuisance_count(self.nuisance)
    }

    /// A (equations × coefficients).
    pub fn matrix(&self) -> &Mat<f64> {
        &self.matrix
    }
    /// b, the input work per window.
    pub fn rhs(&self) -> &[f64] {
        &self.rhs
    }
    /// Coefficient names, one per column.
    pub fn columns(&self) -> &[String] {
        &self.columns
    }
    /// Row labels, one per equation.
    pub fn rows(&self) -> &[RowLabel] {
        &self.rows
    }
    /// Number of equations.
    pub fn equations(&self) -> usize {
        self.rhs.len()
    }
    /// The noise model, when the noise-robust pipeline built the rows.
    pub fn noise(&self) -> Option<&NoiseModel> {
        self.noise.as_ref()
    }
    /// How many trailing columns are nuisance unknowns (0 for periodic regressors).
    pub fn nuisance_count(&self) -> usize {
        self.nuisance
    }
}

/// What the windows of one record share: the kernel's plan and the quadrature weights
/// (every window of a record spans the same k periods).
struct RecordShared<'m> {
    plan: Plan<'m>,
    weights: WindowWeights,
}

/// The quadrature weights of every record's windows. Every window of a record spans the
/// same k periods. Spectral weights scale with the step, w(kT, h, T) = h w(kT/h, 1, T/h),
/// so they are computed once per distinct (kT/h, T/h): once for a stepped-sine table
/// sampled at a fixed number of samples per period, however many points it has (the
/// spectral rule costs a QR of the Fourier basis).
fn record_weights(
    records: &[Record],
    windows: &[Window],
    settings: &RegressorSettings,
) -> Result<Vec<WindowWeights>> {
    let span_of = |index: usize, record: &Record| {
        windows
            .iter()
            .find(|w| w.record == index)
            .map_or(settings.windows.cycles as f64 * record.period(), |w| w.span)
    };
    if settings.quadrature != Quadrature::Spectral {
        // Rectangular and trapezoid weights are a few numbers each (no per-sample
        // vector): made directly at each record's step.
        return records
            .iter()
            .enumerate()
            .map(|(index, record)| {
                settings.quadrature.window_weights(
                    span_of(index, record),
                    record.step(),
                    record.period(),
                )
            })
            .collect();
    }
    let ratios: Vec<(f64, f64)> = records
        .iter()
        .enumerate()
        .map(|(index, record)| {
            (
                span_of(index, record) / record.step(),
                record.period() / record.step(),
            )
        })
        .collect();
    let key = |(span, period): (f64, f64)| (span.to_bits(), period.to_bits());
    let mut distinct: Vec<(f64, f64)> = Vec::new();
    for &ratio in &ratios {
        if !distinct.iter().any(|&d| key(d) == key(ratio)) {
            distinct.push(ratio);
        }
    }
    let per_step: Vec<Vec<f64>> = distinct
        .par_iter()
        .map(|&(span, period)| settings.quadrature.weights(span, 1.0, period))
        .collect::<Result<_>>()?;
    Ok(records
        .iter()
        .zip(&ratios)
        .map(|(record, &ratio)| {
            let unit = distinct
                .iter()
                .position(|&d| key(d) == key(ratio))
                .expect("every ratio is in the distinct list");
            WindowWeights::PerSample(per_step[unit].iter().map(|w| w * record.step()).collect())
        })
        .collect())
}

/// One row: every term's columns and the input work for window `w`, in one fused pass
/// over the window's samples (`src/kernel/`).
fn window_row(
    shared: &RecordShared<'_>,
    model: &DampingModel,
    record: &Record,
    w: &Window,
    settings: &RegressorSettings,
) -> Result<(Vec<f64>, f64)> {
    let weights = &shared.weights;
    let count = weights.len();
    let v = settings
        .velocity
        .window_velocities(record, w.start, count)?;
    let samples = WindowSamples {
        x: record.displacements().subrows(w.start, count),
        v: v.as_ref(),
        signals: record.forcing().signals.as_ref().subrows(w.start, count),
        weights,
    };
    let (mut row, mut input) = shared.plan.row(&samples);
    if settings.work_form == WorkForm::DerivativeFree {
        input = derivative_free::replace_with_raw(model, record, w, &mut row)?;
    }
    Ok((row, input))
}
