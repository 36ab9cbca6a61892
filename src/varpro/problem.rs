//! One trial of variable projection: the model at η, its regressor, the inner fit
//! θ̂(η) and the projected cost φ(η) = Σ_r (e_r / s_r)², e = A(η) θ̂ − b, with s_r the
//! propagated residual standard deviation of a weighted fit (s_r = 1 otherwise).
//!
//! A trial's regressor comes from a builder η → A(η), b: the problem's
//! [`ParametricRegressor::regressor`] (the law's model at η on records, or a stepped-sine
//! table rebuilt with its residual receptances at η, one sweep at a time:
//! `sweep_blocks.rs`), or, in a bootstrap replicate, the resampled rows of it.
//!
//! The regressor of the last projected residual r(η) is kept (keyed by the bits of η,
//! shared, not copied): a Levenberg–Marquardt iteration asks for r(η), then for the
//! q columns of its Jacobian, those of a table's residual unknowns exact from that
//! same A(η) and ∂A/∂η_j (`projected_jacobian.rs`): assembled once per column
//! before, 1412 assemblies on the 12-sweep bench with ordinary weighting, 199 now
//! (BENCHMARKS.md §14). A build is deterministic, so the kept
//! regressor is the one a build would give: the estimates do not change.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

use crate::analysis::diagnostics::REJECTION_P_VALUE;
use crate::error::Result;
use crate::fit::{Fit, FitSettings, Weighting};
use crate::regressor::{NonlinearParameter, ParametricRegressor, Regressor, RegressorSettings};
use crate::report::FitReport;

use super::sweep_blocks::{RowDerivatives, SweepBlocks};

/// The regressor at η (η in the order of the problem's parameters).
pub type TrialBuilder<'a> = dyn Fn(&[f64]) -> Result<Regressor> + Send + Sync + 'a;

/// The data and settings every trial shares, and a count of the trials.
pub(super) struct Problem<'a> {
    parameters: Vec<NonlinearParameter>,
    build: Box<TrialBuilder<'a>>,
    /// The same regressor without its noise model (a table with residual unknowns):
    /// for the projected residuals and Jacobian differences of an ordinary fit, which
    /// read none ([`Problem::shared`], when `bare_fits`), and for the joint
    /// covariance's differences at fixed θ and weights under any weighting
    /// ([`Problem::equations`]).
    bare: Option<Box<TrialBuilder<'a>>>,
    /// Whether the inner fits read no noise model (ordinary weighting), so that the
    /// trials of the searches can be the bare regressor.
    bare_fits: bool,
    fit: &'a FitSettings,
    evaluations: AtomicU64,
    /// The sweep blocks of a table with residual unknowns (∂A/∂η_j in closed form for
    /// those), and the rows of the full regressor this problem's rows are (a bootstrap
    /// replicate's; `None`: all, in order).
    derivatives: Option<(Arc<SweepBlocks<'a>>, Option<Vec<usize>>)>,
    /// The regressor of the last η whose projected residual was asked (the bits of η):
    /// the base of that η's Jacobian differences ([`Problem::shared`]).
    last: Mutex<Option<(Vec<u64>, Arc<Regressor>)>>,
}

/// The regressor and the fit at one η, and its cost.
pub(super) struct Trial {
    pub regressor: Regressor,
    pub fit: Fit,
    pub cost: f64,
}

impl<'a> Problem<'a> {
    /// The trials of `problem`, its records' windows cut by `regressor`, each fitted
    /// with `fit`.
    pub fn new(
        problem: &'a ParametricRegressor<'a>,
        regressor: &'a RegressorSettings,
        fit: &'a FitSettings,
    ) -> Self {
        // a table with residual unknowns per sweep rebuilds only the sweeps that moved
        match SweepBlocks::of(problem) {
            Some(blocks) => {
                let blocks = Arc::new(blocks);
                let builder = Arc::clone(&blocks);
                let bare = Arc::clone(&blocks);
                Problem {
                    derivatives: Some((blocks, None)),
                    bare: Some(Box::new(move |eta: &[f64]| {
                        bare.regressor_without_noise(eta)
                    })),
                    bare_fits: fit.weighting == Weighting::Ordinary,
                    ..Self::with_builder(
                        problem.parameters(),
                        Box::new(move |eta: &[f64]| builder.regressor(eta)),
                        fit,
                    )
                }
            }
            None => Self::with_builder(
                problem.parameters(),
                Box::new(move |eta: &[f64]| problem.regressor(eta, regressor)),
                fit,
            ),
        }
    }

    /// A problem whose trial at η fits the regressor `build(η)`.
    pub fn with_builder(
        parameters: Vec<NonlinearParameter>,
        build: Box<TrialBuilder<'a>>,
        fit: &'a FitSettings,
    ) -> Self {
        Problem {
            parameters,
            build,
            bare: None,
            bare_fits: false,
            fit,
            evaluations: AtomicU64::new(0),
            derivatives: None,
            last: Mutex::new(None),
        }
    }

    /// This problem, whose regressor at η is the rows `rows` of `parent`'s (a bootstrap
    /// replicate), with the closed-form derivatives of `parent`.
    pub fn with_derivatives_of(mut self, parent: &Problem<'a>, rows: &[usize]) -> Self {
        self.derivatives = parent
            .derivatives
            .as_ref()
            .map(|(blocks, _)| (Arc::clone(blocks), Some(rows.to_vec())));
        self
    }

    /// A(η) + h ∂A/∂η_j with b and labels of `base` = A(η), ∂A/∂η_j on its rows
    /// `derivative` ([`Problem::derivative_rows`]): the difference column of a
    /// constrained inner fit (`projected_jacobian.rs`). Its fit differs from the trial
    /// at η + h e_j by O(h²) in A. It carries no noise model: it is for a fit whose row
    /// weights are fixed (`fixed_weights.rs`, whose `weighted` rows drop it) or absent
    /// (ordinary weighting, which reads none), so copying the base's would be waste.
    pub fn shifted_by(base: &Regressor, derivative: &RowDerivatives, h: f64) -> Result<Regressor> {
        let mut matrix = base.matrix().clone();
        let p = matrix.ncols();
        for (row, d) in derivative {
            for (k, x) in d.iter().enumerate().take(p) {
                matrix[(*row, k)] += h * x;
            }
        }
        Regressor::from_shared_parts(
            matrix,
            base.rhs().to_vec(),
            base.columns().to_vec(),
            base.shared_rows(),
        )?
        .with_nuisance_count(base.nuisance_count())
    }

    /// ∂A/∂η_j at `eta` on the rows it touches, numbered as this problem's rows (a
    /// bootstrap replicate's repeats each have their own), when it is known in closed
    /// form (a residual unknown of a table, `sweep_blocks.rs`); `None` otherwise.
    pub fn derivative_rows(&self, eta: &[f64], j: usize) -> Result<Option<RowDerivatives>> {
        let Some((blocks, selection)) = &self.derivatives else {
            return Ok(None);
        };
        let Some(derivative) = blocks.derivative(eta, j)? else {
            return Ok(None);
        };
        let Some(rows) = selection else {
            return Ok(Some(derivative));
        };
        let mut of_row: Vec<Option<usize>> = vec![None; rows.iter().max().map_or(0, |m| m + 1)];
        for (i, (row, _)) in derivative.iter().enumerate() {
            if let Some(slot) = of_row.get_mut(*row) {
                *slot = Some(i);
            }
        }
        Ok(Some(
            rows.iter()
                .enumerate()
                .filter_map(|(i, &row)| match of_row.get(row) {
                    Some(Some(k)) => Some((i, derivative[*k].1.clone())),
                    _ => None,
                })
                .collect(),
        ))
    }

    /// The nonlinear parameters.
    pub fn parameters(&self) -> &[NonlinearParameter] {
        &self.parameters
    }

    /// The settings of the inner fits.
    pub fn fit(&self) -> &'a FitSettings {
        self.fit
    }

    /// Regressors built so far.
    pub fn evaluations(&self) -> u64 {
        self.evaluations.load(Ordering::Relaxed)
    }

    /// The regressor of the model at `eta`.
    pub fn regressor(&self, eta: &[f64]) -> Result<Regressor> {
        self.evaluations.fetch_add(1, Ordering::Relaxed);
        (self.build)(eta)
    }

    /// A(η) and b at `eta` (the regressor, without its noise model where the problem
    /// can build it so: a table with residual unknowns, whose bare regressor has the
    /// whole build's A and b bit for bit): for differences of the residual at fixed θ
    /// and weights, which read no noise model (the joint covariance, `joint.rs`).
    pub fn equations(&self, eta: &[f64]) -> Result<Regressor> {
        match &self.bare {
            Some(bare) => {
                self.evaluations.fetch_add(1, Ordering::Relaxed);
                bare(eta)
            }
            None => self.regressor(eta),
        }
    }

    /// The trial at `eta`.
    pub fn trial(&self, eta: &[f64]) -> Result<Trial> {
        let regressor = self.regressor(eta)?;
        let fit = crate::fit::solve(&regressor, self.fit)?;
        let cost = weighted_residuals(&regressor, &fit.coefficients, fit.residual_std.as_deref())
            .iter()
            .map(|e| e * e)
            .sum();
        Ok(Trial {
            regressor,
            fit,
            cost,
        })
    }

    /// φ(η). Under ordinary weighting a table with residual unknowns fits the
    /// regressor without its noise model (the same cost: no fit of it reads one).
    pub fn cost(&self, eta: &[f64]) -> Result<f64> {
        let Some(bare) = self.bare.as_ref().filter(|_| self.bare_fits) else {
            return self.trial(eta).map(|t| t.cost);
        };
        self.evaluations.fetch_add(1, Ordering::Relaxed);
        let regressor = bare(eta)?;
        let fit = crate::fit::solve(&regressor, self.fit)?;
        Ok(
            weighted_residuals(&regressor, &fit.coefficients, fit.residual_std.as_deref())
                .iter()
                .map(|e| e * e)
                .sum(),
        )
    }

    /// The projected residual r(η) = (A(η) θ̂(η) − b)_r / s_r, whose squared norm is φ(η).
    /// Its regressor is kept ([`Problem::shared`]) for the Jacobian differences at η
    /// that follow.
    pub fn residuals(&self, eta: &[f64]) -> Result<Vec<f64>> {
        let regressor = self.shared(eta)?;
        let fit = crate::fit::solve(&regressor, self.fit)?;
        Ok(weighted_residuals(
            &regressor,
            &fit.coefficients,
            fit.residual_std.as_deref(),
        ))
    }

    /// The regressor at `eta`, built unless it is the one last asked for (the same
    /// bits of η; a build is deterministic, so the kept one is what a build would
    /// give): a Levenberg–Marquardt iteration asks for the residual at η, then for
    /// q differences from the same A(η) ([`Problem::shifted`]), which would otherwise
    /// assemble it q more times. Under ordinary weighting a table with residual
    /// unknowns assembles it without its noise model (no fit of these reads one; the
    /// trial at the optimum, [`Problem::trial`], keeps it for the report).
    pub fn shared(&self, eta: &[f64]) -> Result<Arc<Regressor>> {
        let key: Vec<u64> = eta.iter().map(|v| v.to_bits()).collect();
        // cannot fail: no code panics while holding the lock.
        if let Some((at, regressor)) = self.last.lock().expect("last lock").as_ref()
            && *at == key
        {
            return Ok(Arc::clone(regressor));
        }
        let regressor = Arc::new(match self.bare.as_ref().filter(|_| self.bare_fits) {
            Some(bare) => {
                self.evaluations.fetch_add(1, Ordering::Relaxed);
                bare(eta)?
            }
            None => self.regressor(eta)?,
        });
        // cannot fail: no code panics while holding the lock.
        *self.last.lock().expect("last lock") = Some((key, Arc::clone(&regressor)));
        Ok(regressor)
    }
}

/// (A θ − b)_r / s_r (s_r = 1 without `std`).
pub(super) fn weighted_residuals(
    regressor: &Regressor,
    theta: &[f64],
    std: Option<&[f64]>,
) -> Vec<f64> {
    let a = regressor.matrix();
    let b = regressor.rhs();
    (0..a.nrows())
        .map(|r| {
            let e: f64 = (0..a.ncols()).map(|k| a[(r, k)] * theta[k]).sum::<f64>() - b[r];
            e / std.map_or(1.0, |s| s[r])
        })
        .collect()
}

/// The variance scale of the cost at the optimum: s² = φ̂/ν for an unweighted fit
/// (estimated), 1 for a weighted fit whose χ² check passes (plug-in), χ²/ν when it
/// rejects the fit (scaled plug-in), as [`crate::analysis::diagnostics`] rules.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Variance {
    /// σ² multiplying (JᵀJ)⁻¹ and the interval's quantile.
    pub scale: f64,
    /// True when σ² was estimated from the residuals of an unweighted fit (Student t
    /// and F quantiles), false for the plug-in of a weighted one (normal and χ²).
    pub estimated: bool,
}

impl Variance {
    pub fn of(report: &FitReport, cost: f64, dof: Option<usize>) -> Self {
        let Some(dof) = dof else {
            return Variance {
                scale: f64::NAN,
                estimated: true,
            };
        };
        let per_dof = cost / dof as f64;
        match &report.noise {
            None => Variance {
                scale: per_dof,
                estimated: true,
            },
            Some(noise) => Variance {
                scale: if noise.p_value.is_some_and(|p| p < REJECTION_P_VALUE) {
                    per_dof
                } else {
                    1.0
                },
                estimated: false,
            },
        }
    }
}
