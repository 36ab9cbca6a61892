//! The energy equations of a measured stepped-sine table, with the first-order noise
//! model of each one.
//!
//! Point p (ω, a on DOF f, X_i, φ_i) gives one equation of the harmonic approximation
//! ([`crate::prep::harmonic::approximation`]): over one period of the synthesized
//! motion,
//!
//! ```text
//!   Σ_k θ_k A_pk = b_p,   A_pk = ∮ ẋᵀ f_k dt,   b_p = ∮ ẋᵀ r dt = π a X_f sin φ̄,
//! ```
//!
//! plus, for structural damping (a loss factor η on an element of stiffness k, see
//! [`StructuralTerm`]), the closed form A_pk = π k |Z_e|² with Z_e = Z_a − Z_b the
//! complex amplitude of the element's deformation, Z_i = X_i e^{−iψ_i}.
//!
//! **Closed form.** When every term of the model has a closed-form work per cycle
//! (viscous and semidefinite matrix terms, linear, quadratic, Coulomb and power laws:
//! [`crate::terms::harmonic_work`]), each row is that exact single-harmonic integral
//! and b_p its closed form, with no period synthesized (`stepped_sine_closed.rs`); the
//! synthesized rows are their quadratures. A model with any other term synthesizes
//! every term.
//!
//! **Noise.** The measured a, X_i, φ_i carry independent noise of standard deviations
//! σ_a, σ_{X,i}, σ_{φ,i} ([`crate::prep::harmonic::sweeps`]). To first order the
//! residual e_p = b_p − Σ θ_k A_pk has
//!
//! ```text
//!   Var e_p(θ) = Σ_i ‖ (σ_{X,i} ∂e_p/∂X_i, σ_{φ,i} ∂e_p/∂φ_i) ‖² + (σ_a ∂b_p/∂a)²,
//! ```
//!
//! stored as the [`RowNoise`] of the noise-robust pipeline (one two-entry whitened
//! vector per DOF), so the fit weights each equation by 1/√Var e_p(θ), iterated, with
//! the same χ² model check and calibrated standard errors
//! (`fit/weighted.rs`, [`crate::analysis::diagnostics`]). The derivatives are
//! forward differences of the rows (synthesized or closed form), steps 10⁻⁶ X_i (relative), 10⁻⁶ rad
//! and 10⁻⁶ a: the columns are smooth in X and φ, so their relative error is about
//! 10⁻⁶, negligible in a variance; b is exactly linear in a.
//!
//! **Residual receptance** ([`Regressor::build`](crate::regressor::Regressor::build)): each point's response, and each
//! perturbed copy of it, is first corrected by its residual R_p of the out-of-band
//! modes, Z_mode = Z − R_p a ([`crate::prep::harmonic::residual`]); the derivatives
//! are still taken with respect to the measured a, X and φ, so the noise model
//! propagates the measured noise through the correction (σ_a now also moves X_mode).
//! b is unchanged by R, the columns read X_mode and φ_mode.
//! Their derivative ∂A/∂R (the Jacobian of a variable projection in the residual
//! unknowns) is in closed form where the rows are (`PointRows::residual_derivative`),
//! else from these forward differences.

use std::sync::Arc;

use faer::Mat;

use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::prep::harmonic::residual;
use crate::prep::harmonic::{
    HarmonicApproximation, PhaseReading, SteppedSinePoint, SteppedSineTable,
};
use crate::regressor::passive::WorkScale;
use crate::regressor::robust::{ChannelSensitivity, NoiseModel, RowNoise, WindowNoise};
use crate::regressor::source::SteppedSineSource;
use crate::regressor::stepped_sine_closed;
pub use crate::regressor::structural_term::StructuralTerm;
use crate::regressor::{Regressor, RegressorSettings, RowLabel};
use crate::terms::harmonic_work::Phasor;

/// Relative step of the forward differences (module doc).
const STEP: f64 = 1e-6;

/// One row: the columns and the input work.
#[derive(Debug, Clone)]
struct Row {
    columns: Vec<f64>,
    input: f64,
}

/// The rows of `points` under the harmonic approximation: in closed form when every
/// term of the model has one (`stepped_sine_closed.rs`), else one synthesized period
/// each. A mixed model synthesizes every term: the synthesis costs the same for one
/// term as for all, and its round-off check sees the whole row.
fn rows(
    model: &DampingModel,
    structural: &[StructuralTerm],
    points: &[SteppedSinePoint],
    approximation: &HarmonicApproximation,
) -> Result<Vec<Row>> {
    let mut closed: Vec<Option<(Vec<f64>, f64)>> = vec![None; points.len()];
    // each point's phase reading, read once (the closed rows' and the rows' below)
    let mut read: Vec<Option<Vec<f64>>> = vec![None; points.len()];
    if stepped_sine_closed::applies(model) {
        approximation.validate()?;
        let mut validated = None;
        for ((slot, psi_slot), point) in closed.iter_mut().zip(&mut read).zip(points) {
            // A point from a table is valid; one built by hand is checked here, as the
            // synthesis checks it.
            if point.dofs() == 0 {
                SteppedSineTable::new(vec![point.clone()])?;
            }
            point.check(0, point.dofs()).map_err(|(_, e)| e)?;
            if validated != Some(point.dofs()) {
                model.validate_terms(point.dofs())?;
                validated = Some(point.dofs());
            }
            let psi = approximation.phase.phases(point)?;
            *slot = stepped_sine_closed::row(model, point, &psi);
            *psi_slot = Some(psi);
        }
    }
    let synthesized: Vec<usize> = (0..points.len()).filter(|&r| closed[r].is_none()).collect();
    let model_rows = if model.terms().is_empty() || synthesized.is_empty() {
        None
    } else {
        let subset: Vec<SteppedSinePoint> =
            synthesized.iter().map(|&r| points[r].clone()).collect();
        Some(Regressor::build(
            model,
            &approximation.records_of(&subset)?,
            &RegressorSettings::harmonic_approximation(),
        )?)
    };
    let mut next = 0;
    points
        .iter()
        .zip(closed.into_iter().zip(read))
        .map(|(point, (closed, psi))| {
            let psi = match psi {
                Some(psi) => psi,
                None => approximation.phase.phases(point)?,
            };
            let (mut columns, input) = match (closed, &model_rows) {
                (Some(row), _) => row,
                (None, Some(reg)) => {
                    let r = next;
                    next += 1;
                    (
                        (0..reg.columns().len())
                            .map(|k| reg.matrix()[(r, k)])
                            .collect(),
                        reg.rhs()[r],
                    )
                }
                (None, None) => (Vec::new(), input_work(point, &psi)),
            };
            columns.extend(structural.iter().map(|s| s.column(point, &psi)));
            Ok(Row { columns, input })
        })
        .collect()
}

/// π a X_f sin ψ_f, the input work of a cos ωt on DOF f over one period.
fn input_work(point: &SteppedSinePoint, psi: &[f64]) -> f64 {
    let f = point.force_dof;
    std::f64::consts::PI * point.force_amplitude * point.amplitudes[f] * psi[f].sin()
}

/// The regressor of `source` (one equation per point, in table order) with its noise
/// model: the model's terms by the harmonic approximation, then the structural terms in
/// closed form, each point's response first corrected by its residual receptance R_p
/// for the unknowns `residual` (the module doc; empty: as measured). Row labels:
/// `record` the point's sweep, `record_index` the sweep's index, `window` the point's
/// place in its sweep, `frequency` its ω.
pub(crate) fn build(
    model: &DampingModel,
    source: &SteppedSineSource,
    residual: &[f64],
) -> Result<Regressor> {
    let residual = source.per_point(residual)?;
    let indices: Vec<usize> = (0..source.table.table.points().len()).collect();
    let rows = point_rows(model, source, &indices, residual.as_deref(), true)?;
    assemble(model, source, &rows.iter().collect::<Vec<_>>(), true, None)
}

/// The rows of one point: its equation, then its rows with a + h, and X_i + h and
/// φ_i + h for each DOF (the forward differences of the noise model), each computed
/// from the point corrected by its residual receptance. A point's rows depend on that
/// point alone, so rows computed for some points and assembled with others' give the
/// regressor [`build`] gives (`varpro/sweep_blocks.rs` rebuilds one sweep at a time).
///
/// Without the noise model (`complete` false) the row with a + h, which only the noise
/// model reads, is not computed: it holds a copy of the equation's row.
///
/// When the point's rows have a closed form, its residual is corrected and the phase
/// reading follows the force DOF's own phase (one DOF, or [`PhaseReading::PerDof`]),
/// ∂A/∂R is computed in closed form with the equation's row (`slope`); without the
/// noise model the copies with X_i + h and φ_i + h are then not computed either, and
/// `rows` holds the equation's row alone.
#[derive(Debug, Clone)]
pub(crate) struct PointRows {
    rows: Vec<Row>,
    complete: bool,
    slope: Option<Vec<f64>>,
}

impl PointRows {
    /// Whether these rows carry the row with a + h ([`point_rows`] with `noise`), so
    /// that [`assemble`] can build the noise model from them.
    pub(crate) fn complete(&self) -> bool {
        self.complete
    }

    /// ∂A/∂R of the point's equation (its columns), R its residual receptance: the
    /// mode's response Z_mode = Z − R a moves by −a dR. In closed form where the rows
    /// have one (the struct doc): the phasor of the force DOF, Z_mode itself, moves by
    /// dZ_f = −a and every other DOF's not at all, so ∂A/∂R is the columns' derivative
    /// along that direction ([`crate::terms::Term::harmonic_columns_and_slope_into`]).
    /// Otherwise from the forward differences: Z_mode moves as it does when the
    /// measured response of the force DOF f moves by dX_f = −a cos φ_f dR and
    /// dφ_f = (a sin φ_f / X_f) dR, so
    ///
    /// ```text
    ///   ∂A/∂R = −a cos φ_f ∂A/∂X_f + (a sin φ_f / X_f) ∂A/∂φ_f,
    /// ```
    ///
    /// with ∂A/∂X_f, ∂A/∂φ_f the forward differences of the noise model (relative error
    /// about 10⁻⁶). b does not depend on R. `point` is the point as measured.
    pub(crate) fn residual_derivative(&self, point: &SteppedSinePoint) -> Vec<f64> {
        if let Some(slope) = &self.slope {
            return slope.clone();
        }
        // reads the rows of X_f + h and φ_f + h, computed with or without the noise model
        let f = point.force_dof;
        let (step_x, step_phi) = (amplitude_step(point, f), STEP);
        let base = &self.rows[0].columns;
        let (x, phi, a) = (point.amplitudes[f], point.phases[f], point.force_amplitude);
        let (dx, dphi) = (-a * phi.cos(), a * phi.sin() / x);
        let (rx, rp) = (&self.rows[2 + 2 * f], &self.rows[3 + 2 * f]);
        (0..base.len())
            .map(|k| {
                dx * (rx.columns[k] - base[k]) / step_x
                    + dphi * (rp.columns[k] - base[k]) / step_phi
            })
            .collect()
    }
}

#[cfg(test)]
impl PointRows {
    /// The equation's row (columns, input work), printed.
    pub(crate) fn equation(&self) -> String {
        format!("{:?}", self.rows[0])
    }

    /// ∂A/∂R in closed form, when computed.
    pub(crate) fn slope(&self) -> Option<&[f64]> {
        self.slope.as_deref()
    }

    /// These rows without ∂A/∂R in closed form.
    pub(crate) fn without_slope(mut self) -> Self {
        self.slope = None;
        self
    }
}

/// The checked columns of `model` and the table's structural terms on `source`.
fn checked_columns(model: &DampingModel, source: &SteppedSineSource) -> Result<Vec<String>> {
    source.approximation.validate()?;
    let dofs = source.table.table.dofs();
    model.validate_terms(dofs)?;
    let mut columns = model.coefficient_names();
    for s in &source.structural {
        s.validate(dofs)?;
        if columns.contains(&s.coefficient) {
            return Err(Error::DuplicateCoefficient {
                name: s.coefficient.clone(),
            });
        }
        columns.push(s.coefficient.clone());
    }
    Ok(columns)
}

/// The finite-difference steps of `p`'s rows: 1 for its equation, then a, and X_i and
/// φ_i per DOF (the order of [`perturbed`]).
fn steps(p: &SteppedSinePoint) -> Vec<f64> {
    let dofs = p.dofs();
    let mut out = Vec::with_capacity(2 + 2 * dofs);
    out.push(1.0);
    out.push(STEP * p.force_amplitude.max(f64::MIN_POSITIVE));
    for j in 0..dofs {
        out.push(amplitude_step(p, j));
        out.push(STEP);
    }
    out
}

/// Entry `c` of [`steps`] without the vector: the same number.
fn step(p: &SteppedSinePoint, c: usize) -> f64 {
    match c {
        0 => 1.0,
        1 => STEP * p.force_amplitude.max(f64::MIN_POSITIVE),
        c if c % 2 == 0 => amplitude_step(p, (c - 2) / 2),
        _ => STEP,
    }
}

/// The step of X_j + h in [`steps`]: 10⁻⁶ of the largest amplitude of `p`.
fn amplitude_step(p: &SteppedSinePoint, j: usize) -> f64 {
    let largest = p.amplitudes.iter().fold(0.0f64, |m, x| m.max(*x));
    STEP * p.amplitudes[j].max(largest).max(f64::MIN_POSITIVE)
}

/// The perturbed copies of `p` its rows belong to, with their steps ([`steps`]): `p`
/// itself, then a + h, and X_i + h and φ_i + h for each DOF.
fn perturbed(p: &SteppedSinePoint) -> Vec<(SteppedSinePoint, f64)> {
    let steps = steps(p);
    let mut out = Vec::with_capacity(steps.len());
    out.push((p.clone(), steps[0]));
    let mut q = p.clone();
    q.force_amplitude += steps[1];
    out.push((q, steps[1]));
    for j in 0..p.dofs() {
        let mut q = p.clone();
        q.amplitudes[j] += steps[2 + 2 * j];
        out.push((q, steps[2 + 2 * j]));
        let mut q = p.clone();
        q.phases[j] += steps[3 + 2 * j];
        out.push((q, steps[3 + 2 * j]));
    }
    out
}

/// The [`PointRows`] of the table's points `indices` (table order not required), each
/// point's response first corrected by `residual[i]` for `indices[i]` (`None`: as
/// measured). One synthesis of all their perturbed copies; without `noise`, not of the
/// copies with a + h, which only the noise model reads (each other row is the same to
/// the last bit: a point's rows depend on that point alone).
pub(crate) fn point_rows(
    model: &DampingModel,
    source: &SteppedSineSource,
    indices: &[usize],
    residual: Option<&[f64]>,
    noise: bool,
) -> Result<Vec<PointRows>> {
    checked_columns(model, source)?;
    if let Some(r) = residual
        && r.len() != indices.len()
    {
        return Err(Error::mismatch(
            "residual receptances vs stepped-sine points",
            indices.len(),
            r.len(),
        ));
    }
    match closed_point_rows(model, source, indices, residual, noise) {
        Some(rows) => Ok(rows),
        None => copied_point_rows(model, source, indices, residual, noise),
    }
}

/// [`point_rows`] through one point per perturbed copy ([`perturbed`]) and [`rows`]:
/// any model, synthesized or closed form, and the errors of the copies.
pub(crate) fn copied_point_rows(
    model: &DampingModel,
    source: &SteppedSineSource,
    indices: &[usize],
    residual: Option<&[f64]>,
    noise: bool,
) -> Result<Vec<PointRows>> {
    let points = source.table.table.points();
    let per_point = 2 + 2 * source.table.table.dofs();
    // the copy with a + h is second ([`perturbed`])
    let computed = if noise { per_point } else { per_point - 1 };
    let mut expanded = Vec::with_capacity(indices.len() * computed);
    for (i, &p) in indices.iter().enumerate() {
        for (c, (q, _)) in perturbed(&points[p]).into_iter().enumerate() {
            if c == 1 && !noise {
                continue;
            }
            expanded.push(match residual {
                Some(r) => residual::correct_owned(q, r[i])?,
                None => q,
            });
        }
    }
    let all = rows(model, &source.structural, &expanded, &source.approximation)?;
    let mut all = all.into_iter();
    Ok((0..indices.len())
        .map(|_| {
            let mut rows: Vec<Row> = all.by_ref().take(computed).collect();
            if !noise && let Some(base) = rows.first() {
                rows.insert(1, base.clone());
            }
            PointRows {
                rows,
                complete: noise,
                slope: None,
            }
        })
        .collect())
}

/// [`point_rows`] when every row has a closed form (`stepped_sine_closed.rs`), without
/// a point per perturbed copy: each copy is set up in one reused point (its numbers
/// only: a copy's label names it in errors alone), corrected by its residual
/// receptance and read in place, the same arithmetic in the same order as the general
/// path, so the same rows to the last bit (test). `None` when any copy would need
/// the synthesis or meets an error: the general path then computes them, and raises
/// the error with the copy's label.
fn closed_point_rows(
    model: &DampingModel,
    source: &SteppedSineSource,
    indices: &[usize],
    residual: Option<&[f64]>,
    noise: bool,
) -> Option<Vec<PointRows>> {
    let approximation = &source.approximation;
    if !stepped_sine_closed::applies(model) || approximation.validate().is_err() {
        return None;
    }
    let points = source.table.table.points();
    let mut copy = points.get(*indices.first()?)?.clone();
    let (mut psi, mut z) = (Vec::new(), Vec::new());
    let mut validated = None;
    let mut out = Vec::with_capacity(indices.len());
    // ∂A/∂R in closed form (PointRows): the phase reading of the force DOF is its own
    let analytic = residual.is_some()
        && source.structural.is_empty()
        && (source.table.table.dofs() == 1 || approximation.phase == PhaseReading::PerDof);
    let mut dz: Vec<Phasor> = Vec::new();
    for (i, &p) in indices.iter().enumerate() {
        let point = points.get(p)?;
        let count = 2 + 2 * point.dofs();
        let mut rows = Vec::with_capacity(count);
        let mut slope = None;
        for c in 0..count {
            // the copy with a + h is second ([`perturbed`]): for the noise model alone;
            // with ∂A/∂R in closed form the others are too
            if c == 1 && !noise || c > 0 && !noise && slope.is_some() {
                continue;
            }
            let step = step(point, c);
            copy.frequency = point.frequency;
            copy.force_dof = point.force_dof;
            copy.force_amplitude = point.force_amplitude;
            copy.amplitudes.clone_from(&point.amplitudes);
            copy.phases.clone_from(&point.phases);
            match c {
                0 => {}
                1 => copy.force_amplitude += step,
                c if c % 2 == 0 => copy.amplitudes[(c - 2) / 2] += step,
                c => copy.phases[(c - 3) / 2] += step,
            }
            if let Some(r) = residual {
                residual::correct_in_place(&mut copy, r[i]).ok()?;
            }
            if copy.dofs() == 0 || copy.check(0, copy.dofs()).is_err() {
                return None;
            }
            if validated != Some(copy.dofs()) {
                model.validate_terms(copy.dofs()).ok()?;
                validated = Some(copy.dofs());
            }
            approximation.phase.phases_into(&copy, &mut psi).ok()?;
            let (mut columns, input) = if c == 0 && analytic {
                // dZ_f = −a: the mode's response Z − R a along R
                dz.clear();
                dz.resize(copy.dofs(), (0.0, 0.0));
                dz[copy.force_dof] = (-copy.force_amplitude, 0.0);
                let mut d = Vec::with_capacity(model.coefficient_count());
                let row = stepped_sine_closed::row_and_slope(
                    model,
                    &copy,
                    &psi,
                    &mut z,
                    Some((&dz, &mut d)),
                )?;
                slope = d.iter().all(|v| v.is_finite()).then_some(d);
                row
            } else {
                stepped_sine_closed::row_with(model, &copy, &psi, &mut z)?
            };
            columns.extend(source.structural.iter().map(|s| s.column(&copy, &psi)));
            rows.push(Row { columns, input });
        }
        if !noise && slope.is_none() {
            let base = rows.first()?.clone();
            rows.insert(1, base);
        }
        out.push(PointRows {
            rows,
            complete: noise,
            slope,
        });
    }
    Some(out)
}

/// The regressor of `source` from the rows of every point in table order (`rows[p]`
/// of point p, from [`point_rows`] for `model`), with its labels, work scale and, when
/// `with_noise`, its noise model (see [`build`]). Without it the matrix, b, labels and
/// work scale are the same to the last bit: for a trial whose fit reads no noise model
/// (ordinary weighting, `varpro/problem.rs`). `labels`, when given, are the table's
/// [`row_labels`], shared instead of made again (a caller assembling many trials).
pub(crate) fn assemble(
    model: &DampingModel,
    source: &SteppedSineSource,
    rows: &[&PointRows],
    with_noise: bool,
    labels: Option<&Arc<[RowLabel]>>,
) -> Result<Regressor> {
    let columns = checked_columns(model, source)?;
    let swept = &source.table;
    let table = &swept.table;
    let points = table.points();
    if rows.len() != points.len() {
        return Err(Error::mismatch(
            "rows vs stepped-sine points",
            points.len(),
            rows.len(),
        ));
    }
    let p_count = columns.len();
    let matrix = Mat::from_fn(points.len(), p_count, |r, k| rows[r].rows[0].columns[k]);
    let rhs: Vec<f64> = (0..points.len()).map(|r| rows[r].rows[0].input).collect();
    let places = places(source);
    if with_noise && rows.iter().any(|r| !r.complete) {
        return Err(Error::Numerical {
            stage: "stepped-sine noise model".into(),
            detail: "rows computed without the row of a + h cannot give the noise model".into(),
        });
    }
    let noise = with_noise.then(|| noise_model(source, rows, &places, p_count));
    let labels = match labels {
        Some(labels) if labels.len() == points.len() => Arc::clone(labels),
        _ => labels_at(source, &places).into(),
    };
    for (r, b) in rhs.iter().enumerate() {
        if *b == 0.0 {
            return Err(Error::NoInputWork {
                record: source.point_label(r),
                window: None,
                channels: format!("force on DOF {}", points[r].force_dof + 1),
                reason: "π a X sin φ is zero at this stepped-sine point (phase lag 0 or π, or a zero amplitude)".into(),
            });
        }
    }
    // The gross work π a X_f of each point (|sin φ| ≤ 1), by sweep, for the passivity
    // check (crate::regressor::passive).
    let scale = WorkScale {
        gross: points
            .iter()
            .map(|p| std::f64::consts::PI * p.force_amplitude * p.amplitudes[p.force_dof])
            .collect(),
        samples: vec![0; points.len()],
        group: swept.sweeps.clone(),
        names: swept.sweep_names.clone(),
        unit: "sweep".into(),
    };
    let regressor = Regressor::from_shared_parts(matrix, rhs, columns, labels)?;
    match noise {
        Some(noise) => regressor.with_noise(noise)?,
        None => regressor,
    }
    .with_work_scale(scale)
}

/// The row labels [`assemble`] gives the regressor of `source`: `record` the point's
/// sweep, `record_index` the sweep's index, `window` the point's place in its sweep,
/// `frequency` its ω.
pub(crate) fn row_labels(source: &SteppedSineSource) -> Vec<RowLabel> {
    labels_at(source, &places(source))
}

/// Each point's place in its sweep.
fn places(source: &SteppedSineSource) -> Vec<usize> {
    let swept = &source.table;
    let mut count = vec![0usize; swept.sweep_names.len()];
    swept
        .sweeps
        .iter()
        .map(|&s| {
            count[s] += 1;
            count[s] - 1
        })
        .collect()
}

/// [`row_labels`] with each point's place in its sweep given.
fn labels_at(source: &SteppedSineSource, places: &[usize]) -> Vec<RowLabel> {
    let swept = &source.table;
    (0..swept.table.points().len())
        .map(|r| {
            let s = swept.sweeps[r];
            RowLabel {
                record: swept.sweep_names[s].clone(),
                record_index: s,
                window: places[r],
                start_time: 0.0,
                cycles: 1,
                frequency: Some(swept.table.points()[r].frequency),
            }
        })
        .collect()
}

/// The noise model of the rows `rows` of `source`'s points (module doc: the forward
/// differences of each point's perturbed rows, whitened by the point's σ), `places`
/// each point's place in its sweep, `p_count` columns.
fn noise_model(
    source: &SteppedSineSource,
    rows: &[&PointRows],
    places: &[usize],
    p_count: usize,
) -> NoiseModel {
    let swept = &source.table;
    let points = swept.table.points();
    let dofs = swept.table.dofs();
    let mut noise = NoiseModel {
        rows: Vec::with_capacity(points.len()),
        windows: Vec::with_capacity(points.len()),
    };
    for r in 0..points.len() {
        let own = &rows[r].rows;
        let steps = steps(&points[r]);
        let base = &own[0];
        let sigma = &swept.noise[r];
        // (∂b, ∂A_k) of the row perturbed at `offset`, h its step
        let db = |offset: usize| (own[offset].input - base.input) / steps[offset];
        let da =
            |offset: usize, k: usize| (own[offset].columns[k] - base.columns[k]) / steps[offset];
        let channels: Vec<ChannelSensitivity> = (0..dofs)
            .map(|j| {
                let (x, p) = (2 + 2 * j, 3 + 2 * j);
                let (sx, sp) = (sigma.amplitudes[j], sigma.phases[j]);
                ChannelSensitivity {
                    channel: j,
                    input: vec![sx * db(x), sp * db(p)],
                    columns: (0..p_count)
                        .map(|k| (k, vec![sx * da(x, k), sp * da(p, k)]))
                        .collect(),
                }
            })
            .collect();
        noise
            .rows
            .push(RowNoise::new(&channels, (sigma.force * db(1)).abs()));
        noise.windows.push(WindowNoise {
            record: swept.sweep_names[swept.sweeps[r]].clone(),
            window: places[r],
            harmonics: vec![1],
            displacement_noise: sigma.amplitudes.clone(),
            sensors: Vec::new(),
            force_noise: vec![sigma.force],
        });
    }
    noise
}

/// The columns (model terms, then `structural`) of each of `points`, as
/// [`Regressor::build`](crate::regressor::Regressor::build) computes them: the dissipated energy per cycle per unit coefficient.
pub fn columns_of(
    model: &DampingModel,
    structural: &[StructuralTerm],
    approximation: &HarmonicApproximation,
    points: &[SteppedSinePoint],
) -> Result<Vec<Vec<f64>>> {
    Ok(rows(model, structural, points, approximation)?
        .into_iter()
        .map(|r| r.columns)
        .collect())
}
