//! Speed of regressor building, sized like the NumPy baseline
//! (`../shared/baselines/regressor_numpy.py`, default arguments).
//!
//! One record of a chain of n DOFs fixed at both ends, N samples with h = 0.01 and
//! measured velocities. The model has a linear dashpot per chain element (n + 1
//! columns) and a quadratic damper per DOF (n columns), so one row reads
//!
//! ```text
//!   dashpot_e = h Σ_t (v_{e-1} − v_e)²,  e = 0..n  (v_{-1} = v_n = 0)
//!   quad_i    = h Σ_t |v_i|³,            i = 0..n−1
//!   b         = h Σ_t Σ_i v_i f_i
//! ```
//!
//! The force is stored densely as in the baseline's default: an N × n generalized force
//! that is zero except column n − 1 = cos t. The record's period is set to N h, so one
//! window of one "cycle" with the rectangular rule integrates over exactly all N samples
//! with weights h, the same sum the baseline takes.
//!
//! Data generation is not timed. Benchmark ids are `build_row/t{threads}/n{n}_N{N}`,
//! where `threads` is the size of rayon's global pool (set with `RAYON_NUM_THREADS`),
//! so runs with different thread counts keep separate criterion histories.
//! `benches/compare_numpy.sh` runs this next to the baseline and prints the ratios.
//! The bench prints the instruction set its loops use ("simd: avx2"); `DAMPID_SIMD=avx2`
//! (or avx512, baseline) forces a level the CPU has.

use std::f64::consts::PI;
use std::hint::black_box;
use std::time::Duration;

use criterion::{
    BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group, criterion_main,
};
use dampid::prelude::*;
use dampid::reference::dashpot_chain_model;
use dampid::terms::simd::{self, Level};
use faer::Mat;
use rayon::prelude::*;

mod support;
use support::SplitMix64;

/// Sampling step, as in the baseline.
const STEP: f64 = 0.01;

/// Sizes timed: (DOFs n, samples N). The first is the baseline's default; the other two
/// scale one dimension down by 10 each, so the scaling in n and in N is visible.
const SIZES: [(usize, usize); 3] = [(1000, 100_000), (100, 100_000), (1000, 10_000)];

/// Velocities V (N × n) and the dense force F (N × n), generated like the baseline's
/// `make_data`: v_i(t) = Σ_{k ∈ {1,3,5}} a_{k,i} cos(k t + φ_{k,i}) with φ uniform on
/// [0, 2π) and a uniform on [0.5, 1.5) times 1, 0.2, 0.05; F zero except column
/// n − 1 = cos t. The displacements X are V's integral, x_i(t) = Σ_k a_{k,i}/k sin(k t + φ_{k,i}).
fn make_data(samples: usize, dofs: usize, seed: u64) -> (Mat<f64>, Mat<f64>, Mat<f64>) {
    let mut rng = SplitMix64(seed);
    let phase: Vec<[f64; 3]> = (0..dofs)
        .map(|_| std::array::from_fn(|_| rng.uniform(0.0, 2.0 * PI)))
        .collect();
    let scale = [1.0, 0.2, 0.05];
    let amp: Vec<[f64; 3]> = (0..dofs)
        .map(|_| std::array::from_fn(|k| rng.uniform(0.5, 1.5) * scale[k]))
        .collect();
    let harmonics = |integral: bool| {
        let mut m = Mat::<f64>::zeros(samples, dofs);
        m.par_col_iter_mut().enumerate().for_each(|(i, col)| {
            let col = col.try_as_col_major_mut().unwrap().as_slice_mut();
            for (s, out) in col.iter_mut().enumerate() {
                let t = s as f64 * STEP;
                *out = (0..3)
                    .map(|k| {
                        let order = (2 * k + 1) as f64;
                        let angle = order * t + phase[i][k];
                        if integral {
                            amp[i][k] / order * angle.sin()
                        } else {
                            amp[i][k] * angle.cos()
                        }
                    })
                    .sum();
            }
        });
        m
    };
    let (x, v) = (harmonics(true), harmonics(false));
    let mut f = Mat::<f64>::zeros(samples, dofs);
    for (s, out) in f.col_as_slice_mut(dofs - 1).iter_mut().enumerate() {
        *out = (s as f64 * STEP).cos();
    }
    (x, v, f)
}

/// The record for (X, V, F). The linear and quadratic laws never read displacements,
/// but `Record::new` requires them, and a column of zeros would be refused as a dead
/// sensor (`Error::DeadMotionSensor`).
fn make_record(x: Mat<f64>, v: Mat<f64>, f: Mat<f64>) -> Record {
    let (samples, dofs) = v.shape();
    Record::new(RecordParts {
        label: format!("n={dofs} N={samples}"),
        step: STEP,
        start_time: 0.0,
        displacements: x,
        velocities: Some(v),
        forcing: Forcing::generalized(f),
        period: samples as f64 * STEP,
    })
    .expect("valid benchmark record")
}

/// Per-dashpot linear terms on the chain (n + 1 columns), then per-DOF quadratic terms
/// (n columns).
fn make_model(dofs: usize) -> DampingModel {
    dashpot_chain_model(dofs, Coefficients::PerElement("quad".into()))
}

/// One window over all N samples (period N h), rectangular weights h, measured velocities.
fn settings() -> RegressorSettings {
    RegressorSettings {
        windows: WindowSpec::cycles(1).first(1).into(),
        quadrature: Quadrature::Rectangular,
        velocity: VelocitySource::Measured,
        ..RegressorSettings::default()
    }
}

/// The baseline's formulas, summed directly: (row, b).
fn baseline_row(v: &Mat<f64>, f: &Mat<f64>) -> (Vec<f64>, f64) {
    let (samples, dofs) = v.shape();
    let at = |s: usize, i: isize| -> f64 {
        if i < 0 || i as usize >= dofs {
            0.0
        } else {
            v[(s, i as usize)]
        }
    };
    let mut row = Vec::with_capacity(2 * dofs + 1);
    for e in 0..=dofs as isize {
        let sum: f64 = (0..samples)
            .map(|s| (at(s, e - 1) - at(s, e)).powi(2))
            .sum();
        row.push(STEP * sum);
    }
    for i in 0..dofs {
        let sum: f64 = (0..samples).map(|s| v[(s, i)].abs().powi(3)).sum();
        row.push(STEP * sum);
    }
    let b: f64 = (0..samples)
        .map(|s| (0..dofs).map(|i| v[(s, i)] * f[(s, i)]).sum::<f64>())
        .sum();
    (row, STEP * b)
}

/// Panics unless the regressor row equals the baseline's formulas to relative 1e-10.
fn check_against_baseline_formula() {
    for (dofs, samples) in [(7, 1000), (50, 5000), (1, 3001)] {
        let (x, v, f) = make_data(samples, dofs, 1);
        let (expected_row, expected_b) = baseline_row(&v, &f);
        let record = make_record(x, v, f);
        let reg =
            Regressor::build(&make_model(dofs), &[record], &settings()).expect("regressor builds");
        assert_eq!(reg.equations(), 1, "one window expected");
        assert_eq!(reg.columns().len(), 2 * dofs + 1, "2n + 1 columns expected");
        let rel = |got: f64, want: f64| (got - want).abs() / want.abs().max(1e-300);
        let mut worst = rel(reg.rhs()[0], expected_b);
        for (k, want) in expected_row.iter().enumerate() {
            worst = worst.max(rel(reg.matrix()[(0, k)], *want));
        }
        assert!(
            worst < 1e-10,
            "regressor differs from the baseline formula: n={dofs} N={samples}, \
             max relative difference {worst:.3e}"
        );
    }
}

/// The instruction set of the packed loops: `DAMPID_SIMD` (avx512, avx2, baseline)
/// forces a level the CPU has; printed as "simd: <level>" for compare_numpy.sh.
fn choose_simd_level() {
    if let Ok(name) = std::env::var("DAMPID_SIMD") {
        let level = Level::ALL
            .into_iter()
            .find(|l| l.name() == name)
            .unwrap_or_else(|| panic!("DAMPID_SIMD={name}: not one of avx512, avx2, baseline"));
        assert!(
            simd::force(Some(level)),
            "DAMPID_SIMD={name}: this CPU cannot run it"
        );
    }
    println!(
        "simd: {} (widest on this CPU: {})",
        simd::level().name(),
        Level::detected().name()
    );
}

fn bench_build_row(c: &mut Criterion) {
    choose_simd_level();
    check_against_baseline_formula();

    let threads = rayon::current_num_threads();
    let mut group = c.benchmark_group("build_row");
    group
        .sample_size(10)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_secs(2))
        .measurement_time(Duration::from_secs(8));
    for (dofs, samples) in SIZES {
        group.throughput(Throughput::Elements((dofs * samples) as u64));
        let id = BenchmarkId::new(format!("t{threads}"), format!("n{dofs}_N{samples}"));
        let model = make_model(dofs);
        let settings = settings();
        // Criterion calls the closure once per sample; the data are made on the first
        // call only (and only when the id passes the filter), outside the timed loop.
        let mut record: Option<Record> = None;
        group.bench_function(id, |b| {
            let record = record.get_or_insert_with(|| {
                let (x, v, f) = make_data(samples, dofs, 0);
                make_record(x, v, f)
            });
            let records = std::slice::from_ref(&*record);
            b.iter(|| Regressor::build(black_box(&model), black_box(records), &settings).unwrap());
        });
    }
    group.finish();
}

criterion_group!(benches, bench_build_row);
criterion_main!(benches);
