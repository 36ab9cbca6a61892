//! The fused window kernel (src/regressor/kernel/) against the regressor's definition summed
//! directly, sample by sample, for a model that exercises every path:
//!
//!   A_k = Σ_i w_i v(t_i)ᵀ f_k(x(t_i), v(t_i)),   b = Σ_i w_i v(t_i)ᵀ D s(t_i)
//!
//! - element laws on ground and on arbitrary DOF pairs (not a chain, not sorted), shared
//!   and per element, with element weights, laws of x and of v, built-in, closure and
//!   expression laws (the default `Law::power_sum`);
//! - a sparse matrix term (entries one by one) and a dense one (the Gram matrix path);
//! - a load-distribution matrix with one channel that is zero everywhere;
//! - windows longer than many blocks, rectangular (uniform weights), trapezoid (uniform
//!   interior) and spectral (no uniform run) rules;
//!
//! and the result is bitwise the same with 1, 2 and 3 threads.

use dampid::prelude::*;
use dampid::terms::OnElements;
use dampid::terms::laws::Expression;
use faer::Mat;

mod support;

use support::mixed_record::{mixed_record, noise};

const DOFS: usize = 40;

fn record(samples: usize) -> Record {
    mixed_record(DOFS, samples, 7, 7, "kernel")
}

fn pairs() -> Vec<Element> {
    vec![
        Element::between(5, 0),
        Element::between(3, 17),
        Element::between(39, 2),
        Element::to_ground(11),
        Element::between(20, 21),
    ]
}

/// With `dense`, the dense matrix term makes the kernel form the Gram matrix (and read
/// the sparse term from it too); without, the sparse term is summed entry by entry.
fn model(dense: bool) -> DampingModel {
    let mut r = noise(3);
    let sparse = Mat::from_fn(DOFS, DOFS, |j, k| {
        if j == k {
            2.0
        } else if j + 1 == k {
            -0.7
        } else if k == 0 && j == 30 {
            0.4
        } else {
            0.0
        }
    });
    let model = DampingModel::new()
        .with(Term::on_elements(
            Linear,
            pairs(),
            Coefficients::PerElement("lin".into()),
        ))
        .with(Term::weighted(
            Quadratic,
            pairs(),
            vec![0.5, 1.0, 2.0, 0.25, 1.5],
            Coefficients::Shared("quad".into()),
        ))
        .with(Term::per_dof(
            Coulomb,
            DOFS,
            Coefficients::PerElement("coul".into()),
        ))
        .with(Term::on_elements(
            PowerLaw::new(0.5).unwrap(),
            pairs(),
            Coefficients::Shared("pow".into()),
        ))
        .with(Term::on_elements(
            Custom::new("x2v", |x, v| x * x * v),
            pairs(),
            Coefficients::PerElement("xv".into()),
        ))
        .with(Term::on_elements(
            Expression::parse("sign(v)*abs(v)^1.5").unwrap(),
            vec![Element::between(7, 9), Element::to_ground(12)],
            Coefficients::Shared("expr".into()),
        ))
        .with(Term::viscous("sparse", sparse));
    if dense {
        model.with(Term::viscous("dense", Mat::from_fn(DOFS, DOFS, |_, _| r())))
    } else {
        model
    }
}

/// The row and input work of one window summed directly from the definitions.
fn direct_row(model: &DampingModel, record: &Record, start: usize, w: &[f64]) -> (Vec<f64>, f64) {
    let x = record.displacements();
    let v = record.velocities().unwrap();
    let mut row = Vec::new();
    for term in model.terms() {
        match term {
            Term::Matrix(t) => {
                let c = t.matrix();
                let mut total = 0.0;
                for (i, wi) in w.iter().enumerate() {
                    for j in 0..DOFS {
                        for k in 0..DOFS {
                            total += wi * v[(start + i, j)] * c[(j, k)] * v[(start + i, k)];
                        }
                    }
                }
                row.push(total);
            }
            Term::History(_) | Term::Structural(_) => {
                unreachable!("this test's models hold no history term")
            }
            Term::Elements(t) => {
                let columns: Vec<f64> = t
                    .elements()
                    .iter()
                    .enumerate()
                    .map(|(e, el)| {
                        let weight = t.weights().map_or(1.0, |ws| ws[e]);
                        let relative = |m: faer::MatRef<'_, f64>, i: usize| {
                            m[(start + i, el.a)] - el.b.map_or(0.0, |b| m[(start + i, b)])
                        };
                        weight
                            * w.iter()
                                .enumerate()
                                .map(|(i, wi)| {
                                    let (xr, vr) = (relative(x, i), relative(v, i));
                                    wi * vr * t.law().force(xr, vr)
                                })
                                .sum::<f64>()
                    })
                    .collect();
                match t.coefficients() {
                    Coefficients::Shared(_) => row.push(columns.iter().sum()),
                    Coefficients::PerElement(_) => row.extend(columns),
                }
            }
        }
    }
    let forcing = record.forcing();
    let dofs_forces = |i: usize, j: usize| match &forcing.distribution {
        dampid::record::LoadDistribution::Matrix(d) => (0..forcing.signals.ncols())
            .map(|c| d[(j, c)] * forcing.signals[(start + i, c)])
            .sum::<f64>(),
        dampid::record::LoadDistribution::Dofs(_) => unreachable!(),
    };
    let input = w
        .iter()
        .enumerate()
        .map(|(i, wi)| {
            wi * (0..DOFS)
                .map(|j| v[(start + i, j)] * dofs_forces(i, j))
                .sum::<f64>()
        })
        .sum();
    (row, input)
}

/// `windows` after the first 3 samples, with `quadrature` and measured velocities.
fn settings(quadrature: Quadrature, windows: WindowSpec) -> RegressorSettings {
    support::settings(windows.skipping(3), quadrature, VelocitySource::Measured)
}

fn build(model: &DampingModel, record: &Record, settings: &RegressorSettings) -> Regressor {
    Regressor::build(model, std::slice::from_ref(record), settings).unwrap()
}

#[test]
fn fused_kernel_matches_direct_sums() {
    for dense in [false, true] {
        matches_direct_sums(&model(dense));
    }
}

fn matches_direct_sums(model: &DampingModel) {
    // 120 periods of 628.3 samples: windows of 10 periods cross blocks of 8192 samples,
    // one window of 110 periods crosses more than one wave of blocks.
    let record = record(76_000);
    for (quadrature, windows) in [
        (Quadrature::Rectangular, WindowSpec::cycles(10)),
        (Quadrature::Trapezoid, WindowSpec::cycles(10)),
        (Quadrature::Spectral, WindowSpec::cycles(1).first(3)),
        (Quadrature::Trapezoid, WindowSpec::cycles(110)),
    ] {
        let settings = settings(quadrature, windows);
        let regressor = build(model, &record, &settings);
        let windows = settings
            .windows
            .cycles()
            .unwrap()
            .windows(&record, 0, quadrature)
            .unwrap();
        assert_eq!(regressor.equations(), windows.len());
        // Direct sums are slow (O(m n²) for the matrix terms): check a few windows.
        for (r, window) in windows.iter().enumerate().step_by(5).take(2) {
            let w = quadrature
                .weights(window.span, record.step(), record.period())
                .unwrap();
            let (row, input) = direct_row(model, &record, window.start, &w);
            let scale = row.iter().fold(0.0f64, |m, a| m.max(a.abs()));
            for (k, want) in row.iter().enumerate() {
                let got = regressor.matrix()[(r, k)];
                assert!(
                    (got - want).abs() <= 1e-11 * scale.max(want.abs()),
                    "{quadrature:?} window {r} column {} ({}): {got} vs {want}",
                    k,
                    regressor.columns()[k]
                );
            }
            let got = regressor.rhs()[r];
            assert!(
                (got - input).abs() <= 1e-11 * input.abs(),
                "{quadrature:?} b: {got} vs {input}"
            );
        }
    }
}

#[test]
fn fused_kernel_is_bitwise_independent_of_thread_count() {
    // Windows of 20 periods (12,566 samples) × about 150 sums: past the kernel's
    // threshold (2^20 sample-sums), so 2 and 3 threads run the parallel path and 1 thread
    // the sequential one.
    let model = model(true);
    let record = record(30_000);
    let settings = settings(Quadrature::Trapezoid, WindowSpec::cycles(20));
    let in_pool = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| build(&model, &record, &settings))
    };
    let one = in_pool(1);
    for threads in [2, 3] {
        let many = in_pool(threads);
        assert_eq!(one.rhs(), many.rhs(), "{threads} threads");
        let (m, p) = one.matrix().shape();
        for r in 0..m {
            for k in 0..p {
                assert_eq!(
                    one.matrix()[(r, k)].to_bits(),
                    many.matrix()[(r, k)].to_bits(),
                    "{threads} threads, row {r} column {k}"
                );
            }
        }
    }
}
