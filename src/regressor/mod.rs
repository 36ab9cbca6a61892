//! The regressor A θ = b. Row r is one window of one record; column k is one
//! coefficient. With weights w_i of the quadrature rule over the window's samples:
//!
//!   A_rk = Σ_i w_i v(t_i)ᵀ f_k(x(t_i), v(t_i))   (dissipated work per unit θ_k)
//!   b_r  = Σ_i w_i v(t_i)ᵀ r(t_i)                (input work)
//!
//! Mass and stiffness never appear: over whole periods of a periodic motion their
//! stored energy returns to its start.
//!
//! One type, one [`Regressor::build`], three row builders:
//!
//! | windows | velocities | rows from |
//! |---|---|---|
//! | whole periods | measured, central differences, spectral | `periodic.rs`: one fused kernel pass per window (`kernel/`) |
//! | whole periods | harmonic projection (noise `auto`) | [`robust`]: columns corrected for the expected noise contribution, each row's first-order noise sensitivity kept for weighting the fit |
//! | fixed spans | measured, central differences | [`nonperiodic`]: the same kernel, plus nuisance columns for the change of stored energy and constant forces |
//!
//! With [`WorkForm::DerivativeFree`] the input work is ∫ rᵀ dx and (on raw samples)
//! Coulomb columns are total variations of x ([`derivative_free`]).
//!
//! Every build starts by checking that each motion channel moves ([`dead_motion`]) and
//! ends by checking that the input work is there ([`input_work`]): a record whose force
//! does no work (a dead sensor) is an error, not a row of zeros. The gross work of each
//! row is kept ([`passive::WorkScale`]) for the passivity check before the fit.

pub mod dead_motion;
pub mod derivative_free;
mod free_decay;
pub(crate) use free_decay::DecayCache;
pub(crate) mod history;
pub mod input_work;
mod kernel;
pub mod nonlinear;
pub mod nonperiodic;
pub mod parametric;
pub mod passive;
mod periodic;
pub mod robust;
pub mod round_off;
mod serde_mat;
mod settings;
pub mod source;
mod stack;
pub mod stepped_sine;
mod stepped_sine_closed;
pub mod structural_term;
pub mod velocity_bias;

pub use nonlinear::{NonlinearParameter, Parametric, ParametricModel};
pub use parametric::ParametricRegressor;
pub use settings::{NoiseTreatment, RegressorSettings, SpanWindows, Windows, WorkForm};
pub use source::{KnownModal, Source, SteppedSineSource};
use velocity_bias::VelocityBias;

use std::sync::Arc;

use faer::Mat;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::prep::fourier::RecordNoises;
use crate::prep::steady_state::SteadyStateReport;
use crate::prep::window::Window;
use crate::record::Record;
use robust::NoiseModel;

/// One equation: the columns (one per coefficient) and the input work.
pub(crate) type Row = (Vec<f64>, f64);

/// `row` of every window, in window order; on the rayon pool when `parallel`. The
/// build's rate is measured and extrapolated against the time limit
/// ([`crate::budget::Stopwatch`]), so a build that would run past it (history terms
/// whose orbits take long, huge windows) is refused early.
pub(crate) fn map_windows<T: Send>(
    parallel: bool,
    windows: &[Window],
    row: impl Fn(&Window) -> Result<T> + Sync + Send,
) -> Result<Vec<T>> {
    let total = windows.len() as u64;
    let done = std::sync::atomic::AtomicU64::new(0);
    let stopwatch = std::sync::Mutex::new(crate::budget::Stopwatch::start());
    let checked = |w: &Window| {
        crate::cancel::check("building the regressor")?;
        let value = row(w)?;
        let finished = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        stopwatch
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
            .check(
                finished,
                total,
                &format!("building the regressor of {total} windows"),
                "use fewer or shorter records, or cheaper terms (a history term's orbit is integrated per window)",
            )?;
        Ok(value)
    };
    if parallel {
        windows.par_iter().map(checked).collect()
    } else {
        windows.iter().map(checked).collect()
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
    /// The driving frequency ω of a stepped-sine point (rad per unit time; `None` for
    /// windows of records).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frequency: Option<f64>,
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
            frequency: None,
        }
    }
}

impl std::fmt::Display for RowLabel {
    /// "sweep RC3, 80.15 Hz" for a stepped-sine point (ω/2π), "record 2, window 3" for
    /// a window (numbered from 1).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.frequency {
            Some(omega) => write!(
                f,
                "sweep {}, {:.2} Hz",
                self.record,
                omega / (2.0 * std::f64::consts::PI)
            ),
            None => write!(f, "{}, window {}", self.record, self.window + 1),
        }
    }
}

/// The regressor A (equations × coefficients), right-hand side b, and their labels,
/// with what the fit and the report read beside them (the noise model, the gross work,
/// the velocity-noise bias, the steady-state check of a campaign's rows). Serialisable,
/// so that rows built on one machine are fitted on another bit for bit
/// ([`crate::campaign`]).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Regressor {
    #[serde(with = "serde_mat")]
    matrix: Mat<f64>,
    rhs: Vec<f64>,
    columns: Vec<String>,
    /// Shared, not copied, by the clones of a regressor and by the regressors made
    /// from it with other numbers ([`Regressor::weighted`], the shifted trials of a
    /// variable projection).
    rows: Arc<[RowLabel]>,
    /// Shared, not copied, by the clones of a regressor (a campaign's may be large).
    noise: Option<Arc<NoiseModel>>,
    /// The last `nuisance` columns are stored-energy and offset unknowns
    /// ([`crate::regressor::nonperiodic`]), not damping coefficients.
    nuisance: usize,
    /// The expected velocity-noise bias of each entry, for a differencing velocity
    /// estimator ([`velocity_bias`]).
    velocity_bias: Option<VelocityBias>,
    /// The gross work of each row and its record or sweep, for the passivity check.
    work_scale: Option<passive::WorkScale>,
    /// Columns whose every entry was round-off of its inputs ([`round_off`]), now zero.
    round_off: Vec<String>,
    /// The steady-state check of the windows behind the rows, when the rows were built
    /// apart from the fit ([`crate::campaign::rows`]) and carry it.
    steady_state: Option<Arc<SteadyStateReport>>,
}

impl Regressor {
    /// Builds the equations of `source` ([`Source`]): one row per window of every
    /// record (windows of whole periods, plain or noise-robust rows, or fixed spans of
    /// non-periodic records, as `settings` say), or one per point of a stepped-sine
    /// table (`settings` do not apply to a table).
    pub fn build<'a>(
        model: &DampingModel,
        source: impl Into<Source<'a>>,
        settings: &RegressorSettings,
    ) -> Result<Self> {
        Self::build_with(model, source, settings, None, None)
    }

    /// [`Regressor::build`], a free decay's η-independent part kept in `cache` across
    /// calls (`free_decay.rs`), and the noise-robust rows reading the records' harmonics
    /// and noise from `noises` where they are of these records
    /// (`prep/fourier/record_noise.rs`).
    pub(crate) fn build_with<'a>(
        model: &DampingModel,
        source: impl Into<Source<'a>>,
        settings: &RegressorSettings,
        cache: Option<&free_decay::DecayCache>,
        noises: Option<&RecordNoises>,
    ) -> Result<Self> {
        let records = match source.into() {
            Source::Records(records) => records,
            Source::Table { table, residual } => {
                return stepped_sine::build(model, table, residual);
            }
            Source::Rows(rows) => return Ok(rows.clone()),
        };
        dead_motion::require_motion(records)?;
        crate::prep::data_scale::require_representable(records)?;
        let spec = match &settings.windows {
            Windows::Spans(spans) => {
                settings.validate()?;
                history::refuse(
                    model,
                    "non-periodic spans",
                    "a hysteretic element stores energy that depends on its internal state, which the stored-energy columns (½ΔvᵀMv, ½ΔxᵀKx) cannot express, and a span has no periodic orbit to start its state on; use windows of whole periods (`cycles`)",
                )?;
                history::refuse_structural(
                    model,
                    "non-periodic spans",
                    "its force −ηk H[x] is defined per harmonic of a periodic motion: a span that is not whole periods has no harmonics, and H[x] at a time depends on the motion before and after the span (it is non-causal); use windows of whole periods (`cycles`)",
                )?;
                let regressor = nonperiodic::build(
                    model,
                    records,
                    spans,
                    settings.quadrature,
                    settings.velocity,
                    settings.work_form,
                )?;
                input_work::require_span_work(records, &regressor)?;
                return Ok(regressor);
            }
            Windows::Decay(decay) => {
                settings.validate()?;
                history::refuse(
                    model,
                    "free-decay cycles",
                    "a hysteretic element stores energy that depends on its internal state, which the stored energy of a mode (½mv² + ½mω²x²) cannot express",
                )?;
                history::refuse_structural(
                    model,
                    "free-decay cycles",
                    "its force −ηk H[x] is defined per harmonic of a periodic motion, which a decay is not",
                )?;
                return match cache {
                    Some(cache) => {
                        free_decay::build_cached(model, records, decay, settings.quadrature, cache)
                    }
                    None => free_decay::build(model, records, decay, settings.quadrature),
                };
            }
            Windows::Cycles(spec) => spec,
        };
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
            windows.extend(spec.windows(record, index, settings.quadrature)?);
        }
        input_work::require_force(records)?;
        if settings.noise_robust()? {
            history::refuse(
                model,
                "the noise-robust rows",
                "their columns are corrected for the noise of each law's f(x, v), which a force with memory does not have; use `velocity = \"measured\"`, `central_difference` or `spectral`, or `noise = \"ignore\"`",
            )?;
            let (rows, noise) = robust::rows(
                model,
                records,
                &windows,
                settings.quadrature,
                settings.projection_harmonics(),
                settings.work_form,
                noises,
            )?;
            let mut regressor = Self::assemble(records, &windows, rows, columns)?;
            regressor.noise = Some(Arc::new(noise));
            regressor.zero_round_off(model, records, &windows);
            return input_work::require_periodic_work(records, &windows, regressor);
        }
        let (rows, bias) = periodic::rows(model, records, &windows, spec, settings, columns.len())?;
        let mut regressor = Self::assemble(records, &windows, rows, columns)?;
        regressor.velocity_bias = bias;
        regressor.zero_round_off(model, records, &windows);
        input_work::require_periodic_work(records, &windows, regressor)
    }

    /// Entries that are round-off of their inputs set to zero ([`round_off`]), and the
    /// columns left zero in every row named.
    fn zero_round_off(&mut self, model: &DampingModel, records: &[Record], windows: &[Window]) {
        let zeroed = round_off::zero_round_off(model, records, windows, &mut self.matrix);
        self.round_off = zeroed.iter().map(|&k| self.columns[k].clone()).collect();
    }

    /// The regressor of one row per window: the frame every row builder shares.
    fn assemble(
        records: &[Record],
        windows: &[Window],
        rows: Vec<Row>,
        columns: Vec<String>,
    ) -> Result<Self> {
        let matrix = Mat::from_fn(rows.len(), columns.len(), |r, k| rows[r].0[k]);
        let rhs = rows.iter().map(|(_, b)| *b).collect();
        let labels = windows
            .iter()
            .map(|w| RowLabel::of(w, &records[w.record]))
            .collect();
        Self::from_parts(matrix, rhs, columns, labels)
    }

    /// A regressor from its parts (for research use and tests); validates shapes and
    /// finiteness.
    pub fn from_parts(
        matrix: Mat<f64>,
        rhs: Vec<f64>,
        columns: Vec<String>,
        rows: Vec<RowLabel>,
    ) -> Result<Self> {
        Self::from_shared_parts(matrix, rhs, columns, rows.into())
    }

    /// [`Regressor::from_parts`] with row labels shared with other regressors (the
    /// labels of the same rows with other numbers: [`Regressor::shared_rows`]).
    pub(crate) fn from_shared_parts(
        matrix: Mat<f64>,
        rhs: Vec<f64>,
        columns: Vec<String>,
        rows: Arc<[RowLabel]>,
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
            velocity_bias: None,
            work_scale: None,
            round_off: Vec::new(),
            steady_state: None,
        })
    }

    /// This regressor with the gross work of each row and its group
    /// ([`passive::WorkScale`], one entry per row), for the passivity check.
    pub fn with_work_scale(mut self, scale: passive::WorkScale) -> Result<Self> {
        let rows = self.rhs.len();
        for (what, found) in [
            ("gross work entries vs regressor rows", scale.gross.len()),
            ("sample counts vs regressor rows", scale.samples.len()),
            ("row groups vs regressor rows", scale.group.len()),
        ] {
            if found != rows {
                return Err(Error::mismatch(what, rows, found));
            }
        }
        if let Some(&g) = scale.group.iter().find(|&&g| g >= scale.names.len()) {
            return Err(Error::mismatch(
                "row group vs group names",
                scale.names.len(),
                g,
            ));
        }
        self.work_scale = Some(scale);
        Ok(self)
    }

    /// The columns that were round-off of their inputs in every row and count as zero
    /// ([`round_off`]).
    pub fn round_off_columns(&self) -> &[String] {
        &self.round_off
    }

    /// The gross work of each row and its group, when the builder knew them.
    pub fn work_scale(&self) -> Option<&passive::WorkScale> {
        self.work_scale.as_ref()
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
        self.noise = Some(Arc::new(noise));
        Ok(self)
    }

    /// The rows `indices` (repeats allowed), with their labels and noise model.
    pub fn select_rows(&self, indices: &[usize]) -> Result<Self> {
        self.select(indices, true)
    }

    /// [`Regressor::select_rows`] for a refit ([`crate::analysis::solved::solved`], as
    /// the leave-one-record-out refits of [`crate::report::outliers`] make it): of the
    /// noise model only the rows' sensitivities ([`NoiseModel::rows`], what the weighted
    /// fit and the passivity check read) are copied, not what each window estimated
    /// ([`NoiseModel::windows`], left empty: read by the report only). The fit and its
    /// diagnostics are those of [`Regressor::select_rows`] bit for bit.
    pub(crate) fn select_rows_to_refit(&self, indices: &[usize]) -> Result<Self> {
        self.select(indices, false)
    }

    /// The rows `indices`; the noise model's windows too when `windows`.
    fn select(&self, indices: &[usize], windows: bool) -> Result<Self> {
        let matrix = Mat::from_fn(indices.len(), self.columns.len(), |r, k| {
            self.matrix[(indices[r], k)]
        });
        let rhs = indices.iter().map(|&i| self.rhs[i]).collect();
        let rows = indices.iter().map(|&i| self.rows[i].clone()).collect();
        let mut selected = Self::from_parts(matrix, rhs, self.columns.clone(), rows)?;
        selected.noise = self.noise.as_ref().map(|n| {
            Arc::new(if windows {
                n.select(indices)
            } else {
                NoiseModel {
                    rows: indices.iter().map(|&i| n.rows[i].clone()).collect(),
                    windows: Vec::new(),
                }
            })
        });
        selected.nuisance = self.nuisance;
        selected.velocity_bias = self.velocity_bias.as_ref().map(|b| VelocityBias {
            matrix: Mat::from_fn(indices.len(), b.matrix.ncols(), |r, k| {
                b.matrix[(indices[r], k)]
            }),
            ..b.clone()
        });
        selected.work_scale = self.work_scale.as_ref().map(|s| s.select(indices));
        selected.round_off = self.round_off.clone();
        selected.steady_state = (self.steady_state.as_ref()).map(|s| Arc::new(s.select(indices)));
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
        Self::from_shared_parts(matrix, rhs, self.columns.clone(), Arc::clone(&self.rows))?
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
    /// The row labels, shared (for [`Regressor::from_shared_parts`]).
    pub(crate) fn shared_rows(&self) -> Arc<[RowLabel]> {
        Arc::clone(&self.rows)
    }
    /// Number of equations.
    pub fn equations(&self) -> usize {
        self.rhs.len()
    }
    /// The noise model, when the noise-robust pipeline built the rows.
    pub fn noise(&self) -> Option<&NoiseModel> {
        self.noise.as_deref()
    }
    /// How many trailing columns are nuisance unknowns (0 for periodic regressors).
    pub fn nuisance_count(&self) -> usize {
        self.nuisance
    }
    /// The expected velocity-noise bias of each entry, when the velocity estimator is
    /// one whose bias is assessed ([`velocity_bias`]).
    pub fn velocity_bias(&self) -> Option<&VelocityBias> {
        self.velocity_bias.as_ref()
    }
    /// The steady-state check of the windows behind the rows, when they carry it
    /// (rows built apart from the fit, [`crate::campaign::rows`]).
    pub fn steady_state(&self) -> Option<&SteadyStateReport> {
        self.steady_state.as_deref()
    }

    /// [`Regressor::steady_state`], shared rather than copied (what an identification
    /// of these rows reports).
    pub fn shared_steady_state(&self) -> Option<Arc<SteadyStateReport>> {
        self.steady_state.clone()
    }
}
