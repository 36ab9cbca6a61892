//! Speed of nonnegative fits with many coefficients, sized like the NumPy baseline's
//! `--solve` mode (`../shared/baselines/regressor_numpy.py`): E = 2P equations,
//! A_ij = |N(0, 1)| + 0.1, θ_j uniform on [0.01, 0.1), b = A θ, and the fit
//! min ‖Aθ − b‖ subject to θ ≥ 0 (scipy's NNLS in the baseline, `fit::constrained` here).
//!
//! Two groups:
//!
//! - `constrained_fit/interior/p{P}`: the baseline's problem. Every true coefficient is
//!   positive, so the least-squares solution is feasible and is the optimum (the QR, a
//!   back substitution and the check; clarabel is not called).
//! - `constrained_fit/active/p{P}`: one coefficient in three is truly zero and b carries
//!   noise of 1e-3, so about a fifth of the bounds are active at the optimum: the QR,
//!   clarabel and the polish all run.
//!
//! Before timing, every size is fitted once and the bench panics unless the fit is
//! solved, satisfies the KKT conditions, and (interior) recovers θ to 1e-10. With
//! `DAMPID_FIT_ERRORS=path` it writes max |θ̂ − θ| per size there as JSON, which
//! `benches/compare_numpy.sh` prints beside the baseline's `nnls_max_abs_err`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{BenchmarkId, Criterion, SamplingMode, criterion_group, criterion_main};
use dampid::fit::{self, Constraints, FitStatus, SolverSettings};
use dampid::prelude::*;
use dampid::regressor::RowLabel;
use faer::Mat;

mod support;
use support::SplitMix64;

/// Coefficients P per size (2001 is the baseline's `--solve --dofs 1000`).
const SIZES: [usize; 4] = [101, 301, 1001, 2001];

/// Sizes of the active-set group (larger ones take tens of seconds per fit).
const ACTIVE_SIZES: [usize; 3] = [101, 301, 1001];

/// The regressor (2P × P) and the true θ; with `active`, every third θ_j is 0 and b
/// carries uniform noise of ±5e-4.
fn problem(p: usize, active: bool) -> (Regressor, Vec<f64>) {
    let e = 2 * p;
    let mut rng = SplitMix64(p as u64);
    let a = Mat::from_fn(e, p, |_, _| rng.normal().abs() + 0.1);
    let theta: Vec<f64> = (0..p)
        .map(|j| {
            let value = rng.uniform(0.01, 0.1);
            if active && j % 3 == 0 { 0.0 } else { value }
        })
        .collect();
    let b: Vec<f64> = (0..e)
        .map(|i| {
            let exact: f64 = (0..p).map(|j| a[(i, j)] * theta[j]).sum();
            if active {
                exact + rng.uniform(-5e-4, 5e-4)
            } else {
                exact
            }
        })
        .collect();
    let columns = (0..p).map(|j| format!("theta[{j}]")).collect();
    let rows = (0..e)
        .map(|i| RowLabel {
            frequency: None,
            record: "synthetic".into(),
            record_index: 0,
            window: i,
            start_time: 0.0,
            cycles: 1,
        })
        .collect();
    let regressor = Regressor::from_parts(a, b, columns, rows).expect("finite problem");
    (regressor, theta)
}

fn fit(regressor: &Regressor) -> Fit {
    fit::constrained(
        regressor,
        &Constraints::nonnegative(),
        &SolverSettings::default(),
    )
    .expect("fit runs")
}

/// Panics unless the fit is solved and satisfies KKT for θ ≥ 0: θ ≥ 0, gradient
/// g = Aᵀ(Aθ − b) ≥ −tol where θ = 0 and |g| ≤ tol where θ > 0. Returns max |θ̂ − θ|.
fn check(regressor: &Regressor, theta: &[f64], fit: &Fit, interior: bool) -> f64 {
    assert_eq!(fit.status, FitStatus::Solved);
    let a = regressor.matrix();
    let x = Mat::from_fn(theta.len(), 1, |j, _| fit.coefficients[j]);
    let b = Mat::from_fn(regressor.equations(), 1, |i, _| regressor.rhs()[i]);
    let gradient = a.transpose() * (a * &x - &b);
    let tolerance = 1e-8 * (a.transpose() * &b).norm_max();
    for (j, value) in fit.coefficients.iter().enumerate() {
        let g = gradient[(j, 0)];
        assert!(*value >= 0.0, "θ[{j}] = {value} < 0");
        if *value == 0.0 {
            assert!(g >= -tolerance, "KKT: θ[{j}] = 0 with gradient {g}");
        } else {
            assert!(
                g.abs() <= tolerance,
                "KKT: θ[{j}] = {value} with gradient {g}"
            );
        }
    }
    let error = fit
        .coefficients
        .iter()
        .zip(theta)
        .fold(0.0f64, |m, (x, t)| m.max((x - t).abs()));
    if interior {
        assert!(error < 1e-10, "max |θ̂ − θ| = {error}");
    }
    error
}

fn bench_constrained_fit(c: &mut Criterion) {
    let mut errors = Vec::new();
    let mut group = c.benchmark_group("constrained_fit");
    group
        .sample_size(10)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5));
    for (kind, sizes, interior) in [
        ("interior", &SIZES[..], true),
        ("active", &ACTIVE_SIZES[..], false),
    ] {
        for &p in sizes {
            let id = BenchmarkId::new(kind, format!("p{p}"));
            // Made and checked on the first call only (and only if the id passes the
            // filter), outside the timed loop.
            let mut made: Option<Regressor> = None;
            group.bench_function(id, |b| {
                let regressor = made.get_or_insert_with(|| {
                    let (regressor, theta) = problem(p, !interior);
                    let error = check(&regressor, &theta, &fit(&regressor), interior);
                    errors.push(format!("\"{kind}/p{p}\": {error:e}"));
                    regressor
                });
                b.iter(|| fit(black_box(regressor)));
            });
        }
    }
    group.finish();
    if let Ok(path) = std::env::var("DAMPID_FIT_ERRORS") {
        std::fs::write(&path, format!("{{{}}}\n", errors.join(", ")))
            .expect("write DAMPID_FIT_ERRORS");
    }
}

criterion_group!(benches, bench_constrained_fit);
criterion_main!(benches);
