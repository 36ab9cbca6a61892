//! Constrained least squares through clarabel:
//!
//!   min ½‖A θ − b‖²  subject to  l ≤ θ ≤ u  (θ_i = v_i for fixed coefficients).
//!
//! Set-up. The column-scaled problem is first reduced by a thin QR, A_s = Q R, so that
//! ‖A_s θ_s − b_s‖² = ‖R θ_s − Qᵀ b_s‖² + const, and then posed in lifted form,
//!
//!   min ½‖r‖²  s.t.  R θ_s − r = Qᵀ b_s,  bounds on θ_s,
//!
//! which never forms AᵀA (whose conditioning is the square of A's). A linear constraint
//! Σ a_j θ_j (= | ≤ | ≥) v becomes the row Σ (a_j ‖b‖/S_j) θ_s,j in the scaled
//! coefficients (θ_j = ‖b‖ θ_s,j / S_j), normalised to a largest weight of 1: an
//! equality joins the zero cone beside R θ_s − r = c, an inequality the nonnegative
//! cone beside the bounds.
//!
//! Polish. An interior-point solution sits a little inside the bounds (a coefficient
//! whose true value is 0 comes out near 1e-9 rather than 0). The polish step takes the
//! bounds the solution nearly touches as active, solves the equality-constrained
//! least-squares problem on the free coefficients exactly, and iterates on the active
//! set (adding violated bounds, releasing bounds with the wrong multiplier sign). It
//! keeps the result only if it is feasible and satisfies the KKT sign conditions
//! (gradient gᵢ = [Rᵀ(Rθ − c)]ᵢ ≥ 0 at a lower bound, ≤ 0 at an upper bound), which for
//! this convex problem certify the exact optimum. Otherwise the solver's point is kept.
//! The polish knows only bounds, so it is skipped when there are linear constraints
//! (`SolverInfo::polished` is then false): the interior-point solution is kept, with
//! coefficients within 1e-6 (scaled) of a bound put on it.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
use faer::Mat;

use crate::error::{Error, Result};
use crate::fit::constraints::{Constraints, Interval, LinearRow, Relation};
use crate::fit::least_squares::solve_subset;
use crate::fit::scaling::Scaling;
use crate::fit::{
    ActiveConstraint, BoundSide, Fit, FitMethod, FitStatus, SolverInfo, SolverSettings,
};
use crate::regressor::Regressor;

/// Distance (in scaled units, where coefficients are of order one) within which a
/// solution is taken to touch a bound.
const ACTIVE_TOLERANCE: f64 = 1e-6;

/// Distance within which the polish first guesses a bound active. Interior-point
/// iterates approach a degenerate bound (zero multiplier) only like √μ, so the guess is
/// generous; the active-set iteration releases any wrong guess.
const POLISH_GUESS: f64 = 1e-3;

/// Least squares under `constraints`, solved by clarabel.
pub fn constrained(
    regressor: &Regressor,
    constraints: &Constraints,
    settings: &SolverSettings,
) -> Result<Fit> {
    settings.validate()?;
    let names = regressor.columns();
    let intervals = constraints.resolve(names)?;
    let linear = constraints.resolve_linear(names)?;
    let a = regressor.matrix();
    let (m, p) = a.shape();
    let free_count = intervals.iter().filter(|iv| !iv.is_fixed()).count();
    if m < free_count {
        return Err(Error::TooFewEquations {
            equations: m,
            coefficients: free_count,
        });
    }
    let scaling = Scaling::of(a, regressor.rhs());
    let a_s = scaling.matrix(a);
    let b_s = scaling.rhs(regressor.rhs());
    let scaled: Vec<Interval> = intervals
        .iter()
        .enumerate()
        .map(|(j, iv)| Interval {
            lower: scaling.scale(j, iv.lower),
            upper: scaling.scale(j, iv.upper),
        })
        .collect();
    let scaled_linear: Vec<LinearRow> = linear
        .iter()
        .map(|row| {
            // Σ a_j θ_j = Σ (a_j β / S_j) θ_s,j, then normalised.
            let weights: Vec<f64> = row
                .weights
                .iter()
                .zip(&scaling.columns)
                .map(|(a, s)| a * scaling.rhs / s)
                .collect();
            let largest = weights.iter().fold(0.0f64, |m, w| m.max(w.abs()));
            LinearRow {
                weights: weights.iter().map(|w| w / largest).collect(),
                relation: row.relation,
                value: row.value / largest,
            }
        })
        .collect();

    // Reduce by QR when there are more equations than coefficients.
    let (r, c) = if m > p {
        let qr = a_s.qr();
        let r = qr.thin_R().to_owned();
        let c = qr.compute_thin_Q().transpose() * &b_s;
        (r, c)
    } else {
        (a_s, b_s)
    };

    let (x, status, iterations) = solve_lifted(&r, &c, &scaled, &scaled_linear, settings)?;
    let mut theta_s: Vec<f64> = x
        .iter()
        .zip(&scaled)
        .map(|(t, iv)| t.clamp(iv.lower, iv.upper))
        .collect();

    let mut polished = false;
    if settings.polish
        && scaled_linear.is_empty()
        && matches!(status, FitStatus::Solved | FitStatus::AlmostSolved)
        && let Some(better) = polish(&r, &c, &scaled, &theta_s)
    {
        theta_s = better;
        polished = true;
    }

    let active = scaled
        .iter()
        .zip(&theta_s)
        .enumerate()
        .filter_map(|(j, (iv, t))| {
            side_touched(*t, iv).map(|side| ActiveConstraint {
                name: names[j].clone(),
                side,
                value: if side == BoundSide::Lower {
                    intervals[j].lower
                } else {
                    intervals[j].upper
                },
            })
        })
        .collect();

    let mut coefficients = scaling.unscale(&theta_s);
    // Put coefficients that touch a bound exactly on it (unscaling may round).
    for (j, (coef, iv)) in coefficients.iter_mut().zip(&intervals).enumerate() {
        match side_touched(theta_s[j], &scaled[j]) {
            Some(BoundSide::Lower) | Some(BoundSide::Fixed) => *coef = iv.lower,
            Some(BoundSide::Upper) => *coef = iv.upper,
            None => {}
        }
    }
    Ok(Fit {
        coefficients,
        status,
        method: FitMethod::Constrained,
        active,
        solver: Some(SolverInfo {
            iterations,
            polished,
        }),
        residual_std: None,
    })
}

/// Which bound (if any) the scaled value `t` touches.
fn side_touched(t: f64, iv: &Interval) -> Option<BoundSide> {
    if iv.is_fixed() {
        Some(BoundSide::Fixed)
    } else if iv.lower.is_finite()
        && (t - iv.lower).abs() <= ACTIVE_TOLERANCE * iv.lower.abs().max(1.0)
    {
        Some(BoundSide::Lower)
    } else if iv.upper.is_finite()
        && (t - iv.upper).abs() <= ACTIVE_TOLERANCE * iv.upper.abs().max(1.0)
    {
        Some(BoundSide::Upper)
    } else {
        None
    }
}

/// Clarabel on min ½‖r‖² s.t. Rθ − r = c, bounds, linear rows. Returns θ, status and
/// iterations.
fn solve_lifted(
    r: &Mat<f64>,
    c: &Mat<f64>,
    bounds: &[Interval],
    linear: &[LinearRow],
    settings: &SolverSettings,
) -> Result<(Vec<f64>, FitStatus, u32)> {
    let (q, p) = r.shape();
    let n = p + q;
    // P = diag(0_p, I_q), upper triangular.
    let p_mat =
        CscMatrix::new_from_triplets(n, n, (p..n).collect(), (p..n).collect(), vec![1.0; q]);
    let (mut rows, mut cols, mut vals, mut rhs) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    // Equalities R θ − r = c.
    for i in 0..q {
        for j in 0..p {
            let value = r[(i, j)];
            if value != 0.0 {
                rows.push(i);
                cols.push(j);
                vals.push(value);
            }
        }
        rows.push(i);
        cols.push(p + i);
        vals.push(-1.0);
        rhs.push(c[(i, 0)]);
    }
    let mut row = q;
    for (j, iv) in bounds.iter().enumerate() {
        if iv.is_fixed() {
            rows.push(row);
            cols.push(j);
            vals.push(1.0);
            rhs.push(iv.lower);
            row += 1;
        }
    }
    // Linear rows (clarabel: A x + s = b, s in the cone): a·θ = v in the zero cone;
    // a·θ ≤ v as (a, v) and a·θ ≥ v as (−a, −v) in the nonnegative cone, after the bounds.
    let equalities = linear.iter().filter(|l| l.relation == Relation::Equal);
    let inequalities = linear.iter().filter(|l| l.relation != Relation::Equal);
    for l in equalities {
        for (j, w) in l.weights.iter().enumerate().filter(|(_, w)| **w != 0.0) {
            rows.push(row);
            cols.push(j);
            vals.push(*w);
        }
        rhs.push(l.value);
        row += 1;
    }
    let zero_rows = row;
    for (j, iv) in bounds.iter().enumerate() {
        if iv.is_fixed() {
            continue;
        }
        if iv.lower.is_finite() {
            rows.push(row);
            cols.push(j);
            vals.push(-1.0);
            rhs.push(-iv.lower);
            row += 1;
        }
        if iv.upper.is_finite() {
            rows.push(row);
            cols.push(j);
            vals.push(1.0);
            rhs.push(iv.upper);
            row += 1;
        }
    }
    for l in inequalities {
        let sign = if l.relation == Relation::AtMost {
            1.0
        } else {
            -1.0
        };
        for (j, w) in l.weights.iter().enumerate().filter(|(_, w)| **w != 0.0) {
            rows.push(row);
            cols.push(j);
            vals.push(sign * w);
        }
        rhs.push(sign * l.value);
        row += 1;
    }
    let a_mat = CscMatrix::new_from_triplets(row, n, rows, cols, vals);
    let mut cones = vec![SupportedConeT::ZeroConeT(zero_rows)];
    if row > zero_rows {
        cones.push(SupportedConeT::NonnegativeConeT(row - zero_rows));
    }
    let clarabel_settings = DefaultSettings {
        max_iter: settings.max_iterations,
        verbose: false,
        tol_gap_abs: settings.tolerance,
        tol_gap_rel: settings.tolerance,
        tol_feas: settings.tolerance,
        tol_ktratio: settings.tolerance.sqrt().min(1e-6),
        ..DefaultSettings::default()
    };
    let mut solver = DefaultSolver::new(
        &p_mat,
        &vec![0.0; n],
        &a_mat,
        &rhs,
        &cones,
        clarabel_settings,
    )
    .map_err(|e| Error::Numerical {
        stage: "constrained solver set-up".into(),
        detail: format!("{e}"),
    })?;
    solver.solve();
    let status = match solver.solution.status {
        SolverStatus::Solved => FitStatus::Solved,
        SolverStatus::AlmostSolved => FitStatus::AlmostSolved,
        SolverStatus::PrimalInfeasible
        | SolverStatus::AlmostPrimalInfeasible
        | SolverStatus::DualInfeasible
        | SolverStatus::AlmostDualInfeasible => FitStatus::Infeasible,
        SolverStatus::MaxIterations => FitStatus::MaxIterations,
        SolverStatus::MaxTime => FitStatus::MaxTime,
        SolverStatus::InsufficientProgress => FitStatus::InsufficientProgress,
        SolverStatus::NumericalError
        | SolverStatus::Unsolved
        | SolverStatus::CallbackTerminated => FitStatus::NumericalError,
    };
    let theta = solver.solution.x[..p].to_vec();
    Ok((theta, status, solver.solution.iterations))
}

/// The active-set polish described in the module docs: a primal active-set iteration
/// started from the bounds the interior-point solution nearly touches (within
/// [`POLISH_GUESS`]); it adds violated bounds, releases bounds whose KKT sign is wrong,
/// and returns a point only if it is feasible and satisfies KKT, i.e. is the optimum.
fn polish(r: &Mat<f64>, c: &Mat<f64>, bounds: &[Interval], start: &[f64]) -> Option<Vec<f64>> {
    let p = start.len();
    let near = |t: f64, b: f64| b.is_finite() && (t - b).abs() <= POLISH_GUESS * b.abs().max(1.0);
    let mut side: Vec<Option<BoundSide>> = start
        .iter()
        .zip(bounds)
        .map(|(&t, iv)| {
            if iv.is_fixed() {
                Some(BoundSide::Fixed)
            } else if near(t, iv.lower) {
                Some(BoundSide::Lower)
            } else if near(t, iv.upper) {
                Some(BoundSide::Upper)
            } else {
                None
            }
        })
        .collect();
    let bound_value = |j: usize, s: BoundSide| {
        if s == BoundSide::Upper {
            bounds[j].upper
        } else {
            bounds[j].lower
        }
    };
    let scale = (r.transpose() * c).norm_max().max(1.0);
    let tolerance = 1e-9 * scale;
    let mut theta = start.to_vec();
    for _ in 0..(4 * p + 10) {
        for j in 0..p {
            if let Some(s) = side[j] {
                theta[j] = bound_value(j, s);
            }
        }
        let free: Vec<usize> = (0..p).filter(|&j| side[j].is_none()).collect();
        if !free.is_empty() {
            // c' = c − R_A θ_A
            let mut rhs = c.clone();
            for j in (0..p).filter(|&j| side[j].is_some()) {
                for i in 0..r.nrows() {
                    rhs[(i, 0)] -= r[(i, j)] * theta[j];
                }
            }
            let theta_free = solve_subset(r, &rhs, &free);
            for (k, &j) in free.iter().enumerate() {
                theta[j] = theta_free[(k, 0)];
            }
        }
        if theta.iter().any(|t| !t.is_finite()) {
            return None;
        }
        // Primal feasibility: hold the most violated free coefficient at its bound.
        let violated = free
            .iter()
            .map(|&j| {
                let below = bounds[j].lower - theta[j];
                let above = theta[j] - bounds[j].upper;
                let side = if below > above {
                    BoundSide::Lower
                } else {
                    BoundSide::Upper
                };
                (j, below.max(above), side)
            })
            .filter(|(_, violation, _)| *violation > 0.0)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        if let Some((j, _, s)) = violated {
            side[j] = Some(s);
            continue;
        }
        // Dual feasibility: release the active bound whose gradient pulls hardest inward.
        let theta_col = Mat::from_fn(p, 1, |j, _| theta[j]);
        let gradient = r.transpose() * (r * &theta_col - c);
        let wrong = (0..p)
            .filter_map(|j| match side[j] {
                Some(BoundSide::Lower) if gradient[(j, 0)] < -tolerance => {
                    Some((j, -gradient[(j, 0)]))
                }
                Some(BoundSide::Upper) if gradient[(j, 0)] > tolerance => {
                    Some((j, gradient[(j, 0)]))
                }
                _ => None,
            })
            .max_by(|a, b| a.1.total_cmp(&b.1));
        match wrong {
            Some((j, _)) => side[j] = None,
            None => return Some(theta),
        }
    }
    None
}
