//! One model's least-squares fit in a comparison and the tests on pairs of them: the
//! fit at the numerical rank of the column-scaled rows with RSS, AIC = m ln(RSS/m) + 2k,
//! BIC = m ln(RSS/m) + k ln m (k = rank + estimated parameters) and leave-one-out
//! PRESS = Σ_i (e_i/(1 − h_ii))², h_ii = ‖U_i‖² over the rank's left singular vectors;
//! whether two regressors share their input work b; and how far a smaller model's
//! columns lie outside the larger one's column space (the nesting test).

use faer::Mat;

use super::{Candidate, ModelFit};
use crate::error::{Error, Result};
use crate::fit::ScaledSvd;
use crate::regressor::Regressor;

/// The least-squares fit of one regressor at its numerical rank, with the orthonormal
/// basis of its column space (for the nesting test).
pub(super) struct Solved {
    pub(super) fit: ModelFit,
    pub(super) basis: Mat<f64>,
}

pub(super) fn solve(candidate: Candidate<'_>, tolerance: f64) -> Result<Solved> {
    let (label, r) = (candidate.label, candidate.regressor);
    let a = r.matrix();
    let (m, p) = a.shape();
    if p == 0 {
        return Err(Error::Empty {
            what: format!("the coefficients of model {label}"),
        });
    }
    if m == 0 {
        return Err(Error::TooFewEquations {
            equations: 0,
            coefficients: p,
        });
    }
    let svd = ScaledSvd::new(a, r.rhs(), tolerance)?;
    let (u, b_s) = (svd.u(), svd.rhs());
    let rank = svd.rank();
    let theta_s = svd.scaled_solution();
    let mut fitted = vec![0.0; m];
    for (i, ub) in svd.projections().iter().enumerate().take(rank) {
        for (row, value) in fitted.iter_mut().enumerate() {
            *value += u[(row, i)] * ub;
        }
    }
    let rss_s: f64 = (0..m).map(|i| (b_s[(i, 0)] - fitted[i]).powi(2)).sum();
    // Leverages h_ii = ‖U_i‖² over the rank's left singular vectors (the hat matrix of
    // the column-scaled rows, which scaling columns does not change).
    let press_s = (0..m).try_fold(0.0, |sum, i| {
        let h: f64 = (0..rank).map(|k| u[(i, k)] * u[(i, k)]).sum();
        (h < 1.0 - 1e-10).then(|| sum + ((b_s[(i, 0)] - fitted[i]) / (1.0 - h)).powi(2))
    });
    let scaling = svd.scaling();
    let rss = rss_s * scaling.rhs * scaling.rhs;
    let mf = m as f64;
    let log_likelihood_term = mf * (rss.max(f64::MIN_POSITIVE) / mf).ln();
    let basis = Mat::from_fn(m, rank, |i, k| u[(i, k)]);
    let k = rank + candidate.estimated.len() + candidate.nuisance.len();
    Ok(Solved {
        fit: ModelFit {
            label: label.to_string(),
            coefficients: r.columns().to_vec(),
            values: scaling.unscale(&theta_s),
            parameters: k,
            estimated: candidate.estimated.to_vec(),
            nuisance: candidate.nuisance.to_vec(),
            residual_sum_of_squares: rss,
            relative_residual: rss_s.sqrt(),
            aic: log_likelihood_term + 2.0 * k as f64,
            bic: log_likelihood_term + k as f64 * mf.ln(),
            cross_validation: press_s.map(|p| p * scaling.rhs * scaling.rhs),
        },
        basis,
    })
}

/// The first equation whose input work differs between two regressors of as many
/// equations by more than round-off, 10⁻¹² of the largest |b| (a stepped-sine table's
/// residual receptance leaves b = −π a Im Z unchanged analytically, R a being real,
/// but the synthesized periods integrate it again).
pub(super) fn differing_input_work(a: &Regressor, b: &Regressor) -> Option<usize> {
    let scale = a.rhs().iter().fold(0.0f64, |m, x| m.max(x.abs()));
    // NaN differs too.
    let same = |i: usize| (a.rhs()[i] - b.rhs()[i]).abs() <= 1e-12 * scale;
    (0..a.equations()).find(|&i| !same(i))
}

/// Largest relative residual of `small`'s columns projected on the span of `basis`.
pub(super) fn nesting_residual(small: &Regressor, basis: &Mat<f64>) -> f64 {
    let a = small.matrix();
    let (m, p) = a.shape();
    (0..p)
        .map(|j| {
            let column: Vec<f64> = (0..m).map(|i| a[(i, j)]).collect();
            let norm = crate::fit::scaling::norm(&column);
            if norm == 0.0 {
                return 0.0;
            }
            let mut residual: Vec<f64> = column.iter().map(|c| c / norm).collect();
            for k in 0..basis.ncols() {
                let dot: f64 = (0..m).map(|i| basis[(i, k)] * residual[i]).sum();
                for (i, r) in residual.iter_mut().enumerate() {
                    *r -= dot * basis[(i, k)];
                }
            }
            crate::fit::scaling::norm(&residual)
        })
        .fold(0.0, f64::max)
}
