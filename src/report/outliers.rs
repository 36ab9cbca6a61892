//! Leave-one-record-out: does one record disagree with the others? A record with the
//! wrong units (× 1000), a force on the wrong DOF or velocities read as displacements
//! pulls the whole fit towards it, so its own residual may look ordinary while every
//! record's grows, the noise level of the equations rises, and the identifiability
//! analysis calls coefficients "not separated" as if the experiments were too few.
//! Refitting without each record r (same settings; its rows are those with
//! `RowLabel::record_index` = r) says which record is the cause. With ẽ_i the residual
//! of equation i weighted as the fit weighs it (divided by its propagated standard
//! deviation at the coefficients in question for a weighted fit), θ the whole fit and
//! θ₋ᵣ the fit without record r (m_r of the m equations, f₋ᵣ free coefficients):
//!
//! ```text
//!   remaining_r = Σ_{i∉R} ẽ_i(θ₋ᵣ)² / Σ_i ẽ_i(θ)²          (misfit left without r)
//!   s₋ᵣ² = Σ_{i∉R} ẽ_i(θ₋ᵣ)² / d_r,   d_r = m − m_r − f₋ᵣ
//!   F_r = (Σ_{i∈R} ẽ_i(θ₋ᵣ)² / m_r) / s₋ᵣ²,   p_r = P(F(m_r, d_r) > F_r),   z_r = √F_r
//!   shift_rk = (θ_k − θ₋ᵣ,k) / se₋ᵣ,k                       (in the others' standard errors)
//! ```
//!
//! z_r is the record's deleted standardised residual: its equations against the fit of
//! the others, which the record cannot mask. Record r is *inconsistent* when, with three
//! records or more,
//!
//! - remaining_r ≤ [`REMAINING_MISFIT`] = 0.01: it holds 99 % of the misfit (on clean or
//!   noisy data of one model, dropping one record of n removes about 1/n of it);
//! - p_r < [`OUTLIER_LEVEL`] / n (Bonferroni over the records), or the others fit
//!   exactly;
//! - it moves the estimate: some |shift_rk| ≥ [`SHIFT`] = 3 (or, without standard
//!   errors, by more than 1 % of θ₋ᵣ,k).
//!
//! The most inconsistent such record (smallest remaining_r) is named in
//! [`Warning::InconsistentRecord`], which replaces the "cannot separate … add
//! experiments" diagnosis of [`Warning::Unidentifiable`] (the numbers stay in the
//! identifiability section): with an inconsistent record the design is not the problem.
//!
//! Cost: one refit per record, for up to [`ALL_RECORDS`] records; with more, the
//! [`CANDIDATES`] records of largest residual share. A weighted fit whose χ² check
//! passes has no misfit to explain and is not refitted.

use serde::{Deserialize, Serialize};

use crate::analysis::solved::solved;
use crate::fit::FitSettings;
use crate::regressor::Regressor;
use crate::report::{FitReport, INADEQUATE_P_VALUE, Warning};

/// Family-wise level of the records' outlier tests (divided by the number of records),
/// shared with each record's standardised residual ([`crate::report::records`]).
pub const OUTLIER_LEVEL: f64 = 1e-3;

/// Share of the whole fit's misfit at most left by removing an inconsistent record.
pub const REMAINING_MISFIT: f64 = 0.01;

/// Standard errors (of the fit without the record) by which it must move a coefficient.
pub const SHIFT: f64 = 3.0;

/// Up to this many records, every one is left out in turn.
pub const ALL_RECORDS: usize = 64;

/// With more records, this many of largest residual share are left out.
pub const CANDIDATES: usize = 16;

/// The fit without one record.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LeftOut {
    /// The coefficients θ₋ᵣ, in column order.
    pub coefficients: Vec<f64>,
    /// (θ_k − θ₋ᵣ,k) / se₋ᵣ,k per coefficient (`None` without a standard error).
    pub shifts: Vec<Option<f64>>,
    /// The relative residual of the fit without the record, on its own equations.
    pub relative_residual: f64,
    /// remaining_r (module doc).
    pub remaining_misfit: f64,
    /// z_r, the record's deleted standardised residual (`None` when the others leave no
    /// degrees of freedom or fit exactly).
    pub deleted_residual: Option<f64>,
    /// p_r of its F test (`None` without degrees of freedom; 0 when the others fit
    /// exactly and the record does not).
    pub p_value: Option<f64>,
}

impl LeftOut {
    /// Whether the record is inconsistent among `records` records (module doc).
    pub fn inconsistent(&self, records: usize, values: &[f64]) -> bool {
        let moved = self
            .shifts
            .iter()
            .zip(values.iter().zip(&self.coefficients))
            .any(|(shift, (full, without))| match shift {
                Some(z) => z.abs() >= SHIFT,
                None => (full - without).abs() > 0.01 * without.abs(),
            });
        records >= 3
            && self.remaining_misfit <= REMAINING_MISFIT
            && self
                .p_value
                .is_some_and(|p| p < OUTLIER_LEVEL / records as f64)
            && moved
    }
}

/// The fit of `regressor` with `settings`, its report, and each record left out in turn
/// ([`with_left_out`]): the linear fit of [`crate::identify()`], and the one at the
/// estimated parameters of variable projection.
pub fn reported(regressor: &Regressor, settings: &FitSettings) -> crate::error::Result<FitReport> {
    let crate::analysis::solved::Solved { fit, diagnostics } = solved(regressor, settings)?;
    Ok(with_left_out(
        FitReport::new(regressor, fit, diagnostics),
        regressor,
        settings,
    ))
}

/// `report` (the fit of `regressor` with `settings`) with each record's fit without it
/// and, when one record is inconsistent, [`Warning::InconsistentRecord`] (module doc).
pub fn with_left_out(
    mut report: FitReport,
    regressor: &Regressor,
    settings: &FitSettings,
) -> FitReport {
    let n = report.records.len();
    if n < 3 || report.rows.len() != regressor.equations() {
        return report;
    }
    if let Some(noise) = &report.noise
        && noise.p_value.is_none_or(|p| p >= INADEQUATE_P_VALUE)
    {
        return report;
    }
    // one scratch buffer for every row's std (the same numbers as `RowNoise::std`)
    let buffer = std::cell::RefCell::new(Vec::new());
    let weight = |i: usize, theta: &[f64]| -> f64 {
        regressor
            .noise()
            .map(|noise| noise.rows[i].std_with(theta, &mut buffer.borrow_mut()))
            .filter(|s| s.is_finite() && *s > 0.0)
            .unwrap_or(1.0)
    };
    let full: Vec<f64> = report
        .coefficients
        .iter()
        .chain(&report.nuisance)
        .map(|c| c.value)
        .collect();
    let total: f64 = (0..regressor.equations())
        .map(|i| (residual(regressor, i, &full) / weight(i, &full)).powi(2))
        .sum();
    if !(total > 0.0 && total.is_finite()) {
        return report;
    }
    let mut order: Vec<usize> = (0..n).collect();
    if n > ALL_RECORDS {
        order.sort_by(|&a, &b| {
            report.records[b]
                .residual_share
                .total_cmp(&report.records[a].residual_share)
        });
        order.truncate(CANDIDATES);
    }
    for c in order {
        if crate::cancel::check("leaving records out").is_err() {
            break;
        }
        let index = report.records[c].record_index;
        let (inside, others): (Vec<usize>, Vec<usize>) =
            (0..regressor.equations()).partition(|&i| regressor.rows()[i].record_index == index);
        let Ok(sub) = regressor.select_rows_to_refit(&others) else {
            continue;
        };
        let Ok(without) = solved(&sub, settings) else {
            continue;
        };
        if !without.fit.status.is_usable() {
            continue;
        }
        let theta = &without.fit.coefficients;
        let squares = |rows: &[usize]| -> f64 {
            rows.iter()
                .map(|&i| (residual(regressor, i, theta) / weight(i, theta)).powi(2))
                .sum()
        };
        let (rss_in, rss_out) = (squares(&inside), squares(&others));
        let free = theta.len().saturating_sub(without.fit.active.len());
        let dof = others.len().saturating_sub(free);
        let m = inside.len().max(1) as f64;
        let (deleted_residual, p_value) = if dof == 0 {
            (None, None)
        } else if rss_out > 0.0 {
            let f = (rss_in / m) / (rss_out / dof as f64);
            (
                Some(f.sqrt()),
                Some(crate::analysis::stats::f_upper_tail(f, m, dof as f64)),
            )
        } else {
            (None, Some(if rss_in > 0.0 { 0.0 } else { 1.0 }))
        };
        let shifts = full
            .iter()
            .zip(theta)
            .zip(&without.diagnostics.std_errors)
            .map(|((a, b), se)| se.filter(|s| *s > 0.0).map(|s| (a - b) / s))
            .collect();
        report.records[c].left_out = Some(LeftOut {
            coefficients: theta.clone(),
            shifts,
            relative_residual: without.diagnostics.relative_residual,
            remaining_misfit: rss_out / total,
            deleted_residual,
            p_value,
        });
    }
    let worst = report
        .records
        .iter()
        .filter_map(|r| r.left_out.as_ref().map(|l| (r, l)))
        .filter(|(_, l)| l.inconsistent(n, &full))
        .min_by(|a, b| a.1.remaining_misfit.total_cmp(&b.1.remaining_misfit));
    if let Some((record, left)) = worst {
        let names = regressor.columns();
        let warning = Warning::InconsistentRecord {
            record: record.record.clone(),
            remaining_misfit: left.remaining_misfit,
            deleted_residual: left.deleted_residual,
            p_value: left.p_value,
            shifts: names
                .iter()
                .zip(&left.coefficients)
                .zip(&left.shifts)
                .take(report.coefficients.len())
                .map(|((name, value), shift)| (name.clone(), *value, *shift))
                .collect(),
            undetermined: report
                .coefficients
                .iter()
                .filter(|c| !c.determined)
                .map(|c| c.name.clone())
                .collect(),
        };
        report
            .warnings
            .retain(|w| !matches!(w, Warning::Unidentifiable { .. }));
        report.warnings.insert(0, warning);
    }
    report
}

/// b_i − A_i θ.
fn residual(regressor: &Regressor, i: usize, theta: &[f64]) -> f64 {
    let a = regressor.matrix();
    regressor.rhs()[i] - (0..a.ncols()).map(|k| a[(i, k)] * theta[k]).sum::<f64>()
}

#[cfg(test)]
mod tests {
    use std::path::Path;

    use super::*;
    use crate::fit::Weighting;

    /// A sweep left out of the shipped residual example (7 sweeps, with its noise
    /// model): the refit of the rows selected without the noise model's windows is the
    /// refit of the rows `select_rows` copies, fit and diagnostics bit for bit, under
    /// propagated and ordinary weighting.
    #[test]
    fn refit_rows_equal_copied_rows() {
        let text =
            std::fs::read_to_string("models/bolted_joint_stepped_sine_residual.toml").unwrap();
        let job = crate::model_file::parse(
            &text,
            "residual.toml",
            Path::new("models"),
            Default::default(),
        )
        .unwrap();
        let problem = job.problem();
        let regressor = problem
            .regressor(&problem.initial_values(), &job.settings.regressor)
            .unwrap();
        assert!(regressor.noise().is_some());
        for weighting in [Weighting::Propagated, Weighting::Ordinary] {
            let settings = FitSettings {
                weighting,
                ..job.settings.fit.clone()
            };
            for left in 0..3 {
                let others: Vec<usize> = (0..regressor.equations())
                    .filter(|&i| regressor.rows()[i].record_index != left)
                    .collect();
                assert!(others.len() < regressor.equations());
                let copied = solved(&regressor.select_rows(&others).unwrap(), &settings).unwrap();
                let viewed =
                    solved(&regressor.select_rows_to_refit(&others).unwrap(), &settings).unwrap();
                assert_eq!(format!("{:?}", copied.fit), format!("{:?}", viewed.fit));
                assert_eq!(
                    format!("{:?}", copied.diagnostics),
                    format!("{:?}", viewed.diagnostics)
                );
            }
        }
    }
}
