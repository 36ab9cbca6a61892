//! A bounded Levenberg–Marquardt on the projected residual of variable projection.
//!
//! In the unit box u_j = (η_j − l_j)/(u_j − l_j) ∈ [0, 1] (every parameter on the same
//! scale), with r(u) the projected residual of a trial (the inner fit's
//! (A θ̂ − b)_r / s_r) and its Jacobian J: the columns of a table's residual unknowns,
//! when the caller gives them, exact (Golub–Pereyra, from the closed-form ∂A/∂η_j on
//! its sweep's rows and the inner fit's own SVD, `projected_jacobian.rs`; for a
//! constrained inner fit the fit of A(η) + δη_j ∂A/∂η_j, a forward difference), the
//! others by forward differences of whole trials, step δu = 10⁻⁶ (backward at the
//! upper bound; the derivative of the projected residual, so no Kaufman term is
//! dropped and constrained inner fits are differentiated as they are). Each iteration
//! solves
//!
//! ```text
//!   (JᵀJ + λ (diag JᵀJ + ε I)) δ = −Jᵀ r,      ε = 10⁻¹² max diag JᵀJ,
//! ```
//!
//! over the free parameters (a parameter on a bound whose descent direction points out
//! of the box is held there) and tries u + δ clipped to the box: accepted when the cost
//! ‖r‖² falls (λ ← λ/3), else λ ← 4λ and solved again (at most [`MAX_REJECTIONS`] times
//! in a row). Converged when an accepted step lowers the cost by at most `tolerance`
//! of it, when the step is below 10⁻¹⁰, or when no λ lowers it (a minimum to working
//! precision). Per iteration one trial per column without a closed form (the law
//! parameters) and one per step tried; the exact columns need no trial (one SVD of the
//! inner fit's rows at η for all of them).
//!
//! Multistart: before the first iteration the cost is evaluated at the initial values
//! and at the 2^q corners of the box [0.25, 0.75]^q (q ≤ [`MULTISTART_MAX`]; a coarse
//! grid against the false minima a single start finds, as Nelder–Mead did on the
//! four-mass chain), and the loop starts from the lowest.

use faer::Mat;
use faer::prelude::Solve;

use crate::error::{Error, Result};

use super::minimum::{Column, Minimum, Residuals, Shifted};
use super::{NonlinearParameter, VarProSettings};

/// Forward-difference step in the unit box.
const DIFFERENCE_STEP: f64 = 1e-6;

/// Rejected steps in a row before the point is taken as the minimum.
const MAX_REJECTIONS: usize = 20;

/// Multistart corners only up to this many parameters (2^q trials).
pub(super) const MULTISTART_MAX: usize = 4;

/// Initial damping λ.
const INITIAL_DAMPING: f64 = 1e-3;

fn squared(r: &[f64]) -> f64 {
    r.iter().map(|e| e * e).sum()
}

/// JᵀJ of the Jacobian given by its q `columns`: entry (a, b) the sum over i of
/// J_ia J_ib in row order, the lower triangle mirrored from the upper (the same
/// products in the same order, so the same bits as summing it again).
fn normal_matrix(columns: &[Vec<f64>]) -> Mat<f64> {
    let q = columns.len();
    let mut normal = Mat::<f64>::zeros(q, q);
    for a in 0..q {
        for b in a..q {
            let sum = columns[a]
                .iter()
                .zip(&columns[b])
                .map(|(x, y)| x * y)
                .sum::<f64>();
            normal[(a, b)] = sum;
            normal[(b, a)] = sum;
        }
    }
    normal
}

/// Minimises ‖r(η)‖² over the box of `parameters` (see the module doc); `shifted`, when
/// given, answers the Jacobian's differences it can (the columns of a table's residual
/// unknowns, `sweep_blocks.rs`), the others are whole trials.
pub(super) fn levenberg_marquardt(
    residuals: Residuals<'_>,
    shifted: Option<Shifted<'_>>,
    parameters: &[NonlinearParameter],
    settings: &VarProSettings,
    multistart: bool,
) -> Result<Minimum> {
    let q = parameters.len();
    let lower: Vec<f64> = parameters.iter().map(|p| p.lower).collect();
    let span: Vec<f64> = parameters.iter().map(|p| p.upper - p.lower).collect();
    let eta_of = |u: &[f64]| -> Vec<f64> {
        u.iter()
            .zip(lower.iter().zip(&span))
            .map(|(u, (l, s))| l + s * u)
            .collect()
    };
    let mut starts: Vec<Vec<f64>> = vec![
        parameters
            .iter()
            .map(|p| ((p.initial - p.lower) / (p.upper - p.lower)).clamp(0.0, 1.0))
            .collect(),
    ];
    if multistart && q <= MULTISTART_MAX {
        for corner in 0..1usize << q {
            starts.push(
                (0..q)
                    .map(|j| if (corner >> j) & 1 == 1 { 0.75 } else { 0.25 })
                    .collect(),
            );
        }
    }
    let mut best: Option<(Vec<f64>, Vec<f64>, f64)> = None;
    for start in starts {
        let r = residuals(&eta_of(&start))?;
        let c = squared(&r);
        if best.as_ref().is_none_or(|(_, _, b)| c < *b) {
            best = Some((start, r, c));
        }
    }
    // cannot fail: `starts` holds the initial values at least.
    let (mut u, mut r, mut cost) = best.expect("at least one start");
    let m = r.len();
    let mut lambda = INITIAL_DAMPING;
    let mut iterations = 0;
    let mut converged = false;
    let mut reason = String::from("maximum number of iterations reached");
    while iterations < settings.max_iterations {
        iterations += 1;
        if cost == 0.0 {
            (converged, reason) = (true, "converged (zero residual)".into());
            break;
        }
        // J by columns (column j the difference in η_j)
        let mut jacobian: Vec<Vec<f64>> = Vec::with_capacity(q);
        let eta = eta_of(&u);
        for j in 0..q {
            let h = if u[j] + DIFFERENCE_STEP <= 1.0 {
                DIFFERENCE_STEP
            } else {
                -DIFFERENCE_STEP
            };
            let mut moved = u.clone();
            moved[j] += h;
            let at = eta_of(&moved);
            let cheap = match shifted {
                Some(shifted) => shifted(&eta, j, at[j] - eta[j])?,
                None => None,
            };
            let (rj, exact) = match cheap {
                Some(Column::Derivative(d)) => (d, true),
                Some(Column::Shifted(rj)) => (rj, false),
                None => (residuals(&at)?, false),
            };
            if rj.len() != m {
                return Err(Error::mismatch(
                    "projected residual length between trials",
                    m,
                    rj.len(),
                ));
            }
            jacobian.push(if exact {
                // ∂r/∂u_j = (u_j's span in η) ∂r/∂η_j
                rj.iter().map(|d| d * span[j]).collect()
            } else {
                rj.iter().zip(&r).map(|(a, b)| (a - b) / h).collect()
            });
        }
        let gradient: Vec<f64> = jacobian
            .iter()
            .map(|column| column.iter().zip(&r).map(|(x, e)| x * e).sum())
            .collect();
        let normal = normal_matrix(&jacobian);
        let free: Vec<usize> = (0..q)
            .filter(|&j| {
                !((u[j] <= 0.0 && gradient[j] > 0.0) || (u[j] >= 1.0 && gradient[j] < 0.0))
            })
            .collect();
        if free.is_empty() {
            (converged, reason) = (true, "converged (every parameter on a bound)".into());
            break;
        }
        let floor = 1e-12
            * free
                .iter()
                .map(|&j| normal[(j, j)])
                .fold(0.0, f64::max)
                .max(f64::MIN_POSITIVE);
        let mut accepted = None;
        for _ in 0..MAX_REJECTIONS {
            let k = free.len();
            let system = Mat::from_fn(k, k, |a, b| {
                let (ja, jb) = (free[a], free[b]);
                normal[(ja, jb)]
                    + if a == b {
                        lambda * (normal[(ja, ja)] + floor)
                    } else {
                        0.0
                    }
            });
            let rhs = Mat::from_fn(k, 1, |a, _| -gradient[free[a]]);
            let delta = system.partial_piv_lu().solve(rhs);
            let mut trial = u.clone();
            for (a, &j) in free.iter().enumerate() {
                trial[j] = (u[j] + delta[(a, 0)]).clamp(0.0, 1.0);
            }
            let step = trial
                .iter()
                .zip(&u)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            if !step.is_finite() {
                lambda *= 4.0;
                continue;
            }
            let r_trial = residuals(&eta_of(&trial))?;
            let c_trial = squared(&r_trial);
            if c_trial < cost {
                lambda = (lambda / 3.0).max(1e-12);
                accepted = Some((trial, r_trial, c_trial, step));
                break;
            }
            if step <= 1e-10 {
                break;
            }
            lambda *= 4.0;
        }
        let Some((trial, r_trial, c_trial, step)) = accepted else {
            (converged, reason) = (true, "converged (no step lowers the cost)".into());
            break;
        };
        let gain = cost - c_trial;
        (u, r, cost) = (trial, r_trial, c_trial);
        if gain <= settings.tolerance * (cost + gain) || step <= 1e-10 {
            (converged, reason) = (true, "converged".into());
            break;
        }
    }
    Ok(Minimum {
        values: eta_of(&u),
        converged,
        iterations,
        method: "levenberg_marquardt",
        reason,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// JᵀJ from the columns with its mirrored lower triangle is the entry-by-entry sum
    /// over the matrix, bit for bit.
    #[test]
    fn normal_matrix_is_the_entrywise_sum() {
        let jacobian = Mat::from_fn(37, 5, |i, j| {
            ((i * 7 + j * 13) as f64).sin() * 10f64.powi(j as i32 - 2)
        });
        let columns: Vec<Vec<f64>> = (0..5)
            .map(|j| (0..37).map(|i| jacobian[(i, j)]).collect())
            .collect();
        let normal = normal_matrix(&columns);
        for a in 0..5 {
            for b in 0..5 {
                let sum = (0..37)
                    .map(|i| jacobian[(i, a)] * jacobian[(i, b)])
                    .sum::<f64>();
                assert_eq!(normal[(a, b)].to_bits(), sum.to_bits(), "({a}, {b})");
            }
        }
    }
}
