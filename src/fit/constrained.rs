//! Constrained least squares through clarabel:
//!
//!   min ½‖A θ − b‖²  subject to  l ≤ θ ≤ u  (θ_i = v_i for fixed coefficients).
//!
//! Set-up. The column-scaled problem is first reduced by a thin QR of the augmented
//! matrix, [A_s | b_s] = Q [R c; 0 ρ], so that ‖A_s θ_s − b_s‖² = ‖R θ_s − c‖² + ρ²
//! (c = Qᵀ b_s without forming Q), and then posed in lifted form,
//!
//!   min ½‖r‖²  s.t.  R θ_s − r = c,  bounds on θ_s,
//!
//! which never forms AᵀA (whose conditioning is the square of A's). clarabel factors
//! its KKT matrix with faer's supernodal LDLᵀ (`direct_solve_method = "faer"`): R makes
//! a dense block there, which QDLDL factors column by column. A linear constraint
//! Σ a_j θ_j (= | ≤ | ≥) v becomes the row Σ (a_j ‖b‖/S_j) θ_s,j in the scaled
//! coefficients (θ_j = ‖b‖ θ_s,j / S_j), normalised to a largest weight of 1: an
//! equality joins the zero cone beside R θ_s − r = c, an inequality the nonnegative
//! cone beside the bounds.
//!
//! Polish. An interior-point solution sits a little inside the bounds (a coefficient
//! whose true value is 0 comes out near 1e-9 rather than 0). The polish takes as active
//! the bounds whose interior-point multiplier exceeds their slack (z > s, a test that
//! does not depend on scaling), and then iterates on the active set by block principal
//! pivoting: solve the least-squares problem on the free coefficients exactly (QR) with
//! the others on their bounds, and exchange every coefficient that is infeasible (a free
//! one outside its bounds, a held one whose gradient gᵢ = [Rᵀ(Rθ − c)]ᵢ pulls it inside).
//! It keeps the result only when nothing is infeasible, i.e. the point is feasible and
//! satisfies the KKT sign conditions (gᵢ ≥ 0 at a lower bound, ≤ 0 at an upper bound),
//! which for this convex problem certify the exact optimum, with active coefficients
//! exactly on their bounds. Otherwise the solver's point is kept. The polish knows only
//! bounds, so it is skipped when there are linear constraints (`SolverInfo::polished`
//! is then false): the interior-point solution is kept, with coefficients within 1e-6
//! (scaled) of a bound put on it.
//!
//! Interior optimum. With the polish on and no linear constraints, the least-squares
//! solution of R θ_s = c (fixed coefficients held) is tried first: when R is well
//! conditioned and that solution meets every bound, it is the constrained optimum (the
//! KKT conditions hold with every multiplier zero), and clarabel is not needed
//! (`SolverInfo::iterations` is then 0). This is the usual case for well-posed
//! identification, and it costs one triangular solve after the QR.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};
use faer::linalg::triangular_solve::solve_upper_triangular_in_place;
use faer::{Mat, Par};

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

/// A polished coefficient within this fraction of the largest scaled coefficient of a
/// bound is on it (round-off of an exact solution; polished active coefficients are
/// exactly on their bounds already).
const POLISHED_TOLERANCE: f64 = 1e-12;

/// R is taken as well conditioned for the interior-optimum check when
/// min |r_ii| > this · max |r_ii| (a lower bound on its condition number).
const INTERIOR_CONDITION: f64 = 1e-10;

/// Least squares under `constraints`, solved by clarabel.
pub fn constrained(
    regressor: &Regressor,
    constraints: &Constraints,
    settings: &SolverSettings,
) -> Result<Fit> {
    settings.validate()?;
    let names = regressor.columns();
    let intervals = constraints.resolve(names, names.len() - regressor.nuisance_count())?;
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

    // Reduce by QR when there are more equations than coefficients. The QR of the
    // augmented [A_s | b_s] = Q [R c; 0 ρ] gives c = Qᵀb_s in its last column, without
    // forming Q.
    let (r, c) = if m >= p {
        let augmented = Mat::from_fn(
            m,
            p + 1,
            |i, j| {
                if j < p { a_s[(i, j)] } else { b_s[(i, 0)] }
            },
        );
        drop((a_s, b_s));
        let r_augmented = augmented.qr().thin_R().to_owned();
        let r = r_augmented.submatrix(0, 0, p, p).to_owned();
        let c = r_augmented.submatrix(0, p, p, 1).to_owned();
        (r, c)
    } else {
        (a_s, b_s)
    };

    let interior = (settings.polish && scaled_linear.is_empty())
        .then(|| interior_optimum(&r, &c, &scaled))
        .flatten();
    let (theta_s, status, iterations, polished) = match interior {
        Some(theta_s) => (theta_s, FitStatus::Solved, 0, true),
        None => {
            let lifted = solve_lifted(&r, &c, &scaled, &scaled_linear, settings)?;
            if lifted.primal_infeasible {
                // Bounds alone were checked by `resolve`: the linear constraints, with
                // them, admit no coefficients. That is bad input, not a failed fit.
                return Err(Error::InfeasibleConstraints {
                    constraints: constraints
                        .linear
                        .iter()
                        .map(ToString::to_string)
                        .collect::<Vec<_>>()
                        .join("; "),
                });
            }
            let theta_s: Vec<f64> = lifted
                .theta
                .iter()
                .zip(&scaled)
                .map(|(t, iv)| t.clamp(iv.lower, iv.upper))
                .collect();
            let polished = (settings.polish
                && scaled_linear.is_empty()
                && matches!(lifted.status, FitStatus::Solved | FitStatus::AlmostSolved))
            .then(|| polish(&r, &c, &scaled, &lifted.active_guess))
            .flatten();
            match polished {
                Some(better) => (better, lifted.status, lifted.iterations, true),
                None => (theta_s, lifted.status, lifted.iterations, false),
            }
        }
    };

    // A polished solution holds its active coefficients exactly on their bounds; an
    // interior-point one only comes within a tolerance of them.
    let round_off = POLISHED_TOLERANCE * theta_s.iter().fold(0.0f64, |m, t| m.max(t.abs()));
    let touched = |t: f64, iv: &Interval| {
        if polished {
            side_held(t, iv, round_off)
        } else {
            side_touched(t, iv)
        }
    };
    let active = scaled
        .iter()
        .zip(&theta_s)
        .enumerate()
        .filter_map(|(j, (iv, t))| {
            touched(*t, iv).map(|side| ActiveConstraint {
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
        match touched(theta_s[j], &scaled[j]) {
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

/// Which bound (if any) the scaled value `t` is on, up to `round_off`.
fn side_held(t: f64, iv: &Interval, round_off: f64) -> Option<BoundSide> {
    if iv.is_fixed() {
        Some(BoundSide::Fixed)
    } else if (t - iv.lower).abs() <= round_off {
        Some(BoundSide::Lower)
    } else if (t - iv.upper).abs() <= round_off {
        Some(BoundSide::Upper)
    } else {
        None
    }
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

/// What clarabel returns on the lifted problem.
struct Lifted {
    /// θ_s (not yet clamped to the bounds).
    theta: Vec<f64>,
    status: FitStatus,
    /// Clarabel found (or nearly found) a certificate that no θ meets the constraints.
    primal_infeasible: bool,
    iterations: u32,
    /// Per coefficient, the bound whose multiplier exceeds its slack (z > s): the
    /// interior-point estimate of the active set, independent of scaling.
    active_guess: Vec<Option<BoundSide>>,
}

/// Clarabel on min ½‖r‖² s.t. Rθ − r = c, bounds, linear rows.
fn solve_lifted(
    r: &Mat<f64>,
    c: &Mat<f64>,
    bounds: &[Interval],
    linear: &[LinearRow],
    settings: &SolverSettings,
) -> Result<Lifted> {
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
    // (row, coefficient, side) of every bound row, to read the active set back.
    let mut bound_rows = Vec::new();
    for (j, iv) in bounds.iter().enumerate() {
        if iv.is_fixed() {
            continue;
        }
        if iv.lower.is_finite() {
            rows.push(row);
            cols.push(j);
            vals.push(-1.0);
            rhs.push(-iv.lower);
            bound_rows.push((row, j, BoundSide::Lower));
            row += 1;
        }
        if iv.upper.is_finite() {
            rows.push(row);
            cols.push(j);
            vals.push(1.0);
            rhs.push(iv.upper);
            bound_rows.push((row, j, BoundSide::Upper));
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
        // faer's supernodal LDLᵀ: the reduced R makes a dense block in the KKT matrix,
        // which QDLDL factors column by column (about 10x slower at 2000 coefficients).
        direct_solve_method: "faer".to_string(),
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
    let primal_infeasible = matches!(
        solver.solution.status,
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible
    );
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
    let mut active_guess: Vec<Option<BoundSide>> = bounds
        .iter()
        .map(|iv| iv.is_fixed().then_some(BoundSide::Fixed))
        .collect();
    let (slack, dual) = (&solver.solution.s, &solver.solution.z);
    for &(row, j, side) in &bound_rows {
        if dual[row] > slack[row] {
            active_guess[j] = Some(side);
        }
    }
    Ok(Lifted {
        theta: solver.solution.x[..p].to_vec(),
        status,
        primal_infeasible,
        iterations: solver.solution.iterations,
        active_guess,
    })
}

/// The least-squares solution of R θ = c with the fixed coefficients held, if R is well
/// conditioned and the solution meets every bound: then it is the constrained optimum.
fn interior_optimum(r: &Mat<f64>, c: &Mat<f64>, bounds: &[Interval]) -> Option<Vec<f64>> {
    let diagonal: Vec<f64> = (0..r.nrows().min(r.ncols()))
        .map(|i| r[(i, i)].abs())
        .collect();
    let largest = diagonal.iter().fold(0.0f64, |m, d| m.max(*d));
    let smallest = diagonal.iter().fold(f64::INFINITY, |m, d| m.min(*d));
    let well_conditioned = smallest > INTERIOR_CONDITION * largest;
    if r.nrows() < r.ncols() || !well_conditioned {
        return None;
    }
    let held: Vec<Option<BoundSide>> = bounds
        .iter()
        .map(|iv| iv.is_fixed().then_some(BoundSide::Fixed))
        .collect();
    let theta = solve_with_active(r, c, bounds, &held)?;
    theta
        .iter()
        .zip(bounds)
        .all(|(t, iv)| iv.is_fixed() || (*t >= iv.lower && *t <= iv.upper))
        .then_some(theta)
}

/// θ with the coefficients in `side` at their bounds and the others from the
/// least-squares problem min ‖R_F θ_F − (c − R_A θ_A)‖; `None` if not finite.
fn solve_with_active(
    r: &Mat<f64>,
    c: &Mat<f64>,
    bounds: &[Interval],
    side: &[Option<BoundSide>],
) -> Option<Vec<f64>> {
    let p = bounds.len();
    let mut theta = vec![0.0; p];
    for j in 0..p {
        if let Some(s) = side[j] {
            theta[j] = if s == BoundSide::Upper {
                bounds[j].upper
            } else {
                bounds[j].lower
            };
        }
    }
    let free: Vec<usize> = (0..p).filter(|&j| side[j].is_none()).collect();
    if free.len() == p && r.nrows() == p {
        // Nothing held and R square (upper triangular): back substitution.
        let mut solution = c.clone();
        solve_upper_triangular_in_place(r.as_ref(), solution.as_mut(), Par::Seq);
        theta
            .iter_mut()
            .enumerate()
            .for_each(|(j, t)| *t = solution[(j, 0)]);
    } else if !free.is_empty() {
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
    theta.iter().all(|t| t.is_finite()).then_some(theta)
}

/// The active-set polish described in the module docs, as block principal pivoting
/// (Júdice and Pires 1994; Kim and Park 2011) started from the interior-point estimate
/// of the active set (`guess`). Each step solves the least-squares problem on the free
/// coefficients with the others at their bounds, then finds the infeasible ones: free
/// coefficients outside their bounds, and held ones whose gradient
/// gᵢ = [Rᵀ(Rθ − c)]ᵢ pulls them inside. It exchanges all of them at once while their
/// number keeps falling, and otherwise (after three tries) only the last one (Murty's
/// rule, which cannot cycle). Returns a point only if none is infeasible: feasible and
/// KKT, i.e. the optimum.
fn polish(
    r: &Mat<f64>,
    c: &Mat<f64>,
    bounds: &[Interval],
    guess: &[Option<BoundSide>],
) -> Option<Vec<f64>> {
    let p = bounds.len();
    let mut side = guess.to_vec();
    let scale = (r.transpose() * c).norm_max().max(1.0);
    let tolerance = 1e-9 * scale;
    let mut fewest = usize::MAX;
    let mut full_exchanges_left: u32 = 3;
    for _ in 0..(4 * p + 10) {
        let theta = solve_with_active(r, c, bounds, &side)?;
        let theta_col = Mat::from_fn(p, 1, |j, _| theta[j]);
        let gradient = r.transpose() * (r * &theta_col - c);
        // (coefficient, what it becomes) for every infeasible one, in index order.
        let infeasible: Vec<(usize, Option<BoundSide>)> = (0..p)
            .filter_map(|j| {
                let (iv, g) = (&bounds[j], gradient[(j, 0)]);
                match side[j] {
                    None if theta[j] < iv.lower => Some((j, Some(BoundSide::Lower))),
                    None if theta[j] > iv.upper => Some((j, Some(BoundSide::Upper))),
                    Some(BoundSide::Lower) if g < -tolerance => Some((j, None)),
                    Some(BoundSide::Upper) if g > tolerance => Some((j, None)),
                    _ => None,
                }
            })
            .collect();
        if infeasible.is_empty() {
            return Some(theta);
        }
        if infeasible.len() < fewest {
            fewest = infeasible.len();
            full_exchanges_left = 3;
        } else {
            full_exchanges_left = full_exchanges_left.saturating_sub(1);
        }
        if full_exchanges_left > 0 {
            for &(j, becomes) in &infeasible {
                side[j] = becomes;
            }
        } else {
            // cannot fail: an empty list returned above.
            let (j, becomes) = *infeasible.last().expect("not empty");
            side[j] = becomes;
        }
    }
    None
}
