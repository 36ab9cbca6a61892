//! Cost of structural damping in the noise-robust rows (src/regressor/robust/structural.rs):
//! `Regressor::build` of the default pipeline (harmonic projection, `noise = "auto"`) on
//! the same records with and without a loss-factor term.
//!
//! - `structural/chain2/{without,with}`: the closed-form 2-DOF chain of
//!   tests/support/complex_chain.rs (a loss factor on the spring between the masses,
//!   dashpots to ground), four records of 8 periods × 200 samples at two frequencies
//!   with 2 % white noise, one equation per period (32 rows); the model is a viscous
//!   coefficient on each DOF, and with it η on element [1, 2];
//! - `structural/chain100/{without,with}`: the records of models/chain100.toml (100
//!   DOFs, 250 one-period windows), its model (101 dashpots, 100 quadratic dampers) and
//!   with it one shared η on its 101 chain links (k = 1).
//!
//! Besides criterion's numbers it prints the ratio with / without from medians of 11
//! interleaved runs of each case in the same process (alternating which runs first).

use dampid::terms::OnElements;
use std::hint::black_box;
use std::time::Instant;

#[path = "../tests/support/complex_chain.rs"]
#[allow(dead_code)]
mod complex_chain;

use complex_chain::{Chain, Spring};
use criterion::{Criterion, criterion_group, criterion_main};
use dampid::prelude::*;
use dampid::regressor::NoiseTreatment;
use faer::Mat;
use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};

const PAIRS: usize = 11;

fn median(mut seconds: Vec<f64>) -> f64 {
    seconds.sort_by(f64::total_cmp);
    seconds[seconds.len() / 2]
}

/// The chain2 records with 2 % noise on each displacement (of its largest sample).
fn chain2_records() -> Vec<Record> {
    let chain = Chain {
        mass: vec![1.0, 0.5],
        springs: vec![
            Spring {
                a: 0,
                b: None,
                k: 1000.0,
                eta: 0.0,
            },
            Spring {
                a: 0,
                b: Some(1),
                k: 400.0,
                eta: 0.05,
            },
        ],
        c: 0.3,
    };
    let mut rng = StdRng::seed_from_u64(3);
    let unit = Normal::new(0.0, 1.0).unwrap();
    let none = |_: f64| 0.0;
    [
        (19.0, vec![(1, 1.0), (2, 0.4)]),
        (19.0, vec![(1, 2.0)]),
        (38.0, vec![(1, 1.0)]),
        (38.0, vec![(1, 1.0), (2, 0.5)]),
    ]
    .iter()
    .map(|(omega, harmonics)| {
        let clean = chain.sampled_record(*omega, harmonics, 1.0, &none, 200, 8);
        let x = clean.displacements();
        let sigma: Vec<f64> = (0..x.ncols())
            .map(|j| 0.02 * (0..x.nrows()).map(|i| x[(i, j)].abs()).fold(0.0, f64::max))
            .collect();
        Record::new(RecordParts {
            label: clean.label().to_string(),
            step: clean.step(),
            start_time: 0.0,
            displacements: Mat::from_fn(x.nrows(), x.ncols(), |i, j| {
                x[(i, j)] + sigma[j] * unit.sample(&mut rng)
            }),
            velocities: None,
            forcing: clean.forcing().clone(),
            period: clean.period(),
        })
        .unwrap()
    })
    .collect()
}

fn structural_on(elements: Vec<Element>, k: f64) -> Term {
    let n = elements.len();
    Term::structural(elements, vec![k; n], Coefficients::Shared("eta".into()))
}

struct Case {
    name: &'static str,
    records: Vec<Record>,
    settings: RegressorSettings,
    without: DampingModel,
    with: DampingModel,
}

fn cases() -> Vec<Case> {
    let mut robust = IdentifySettings::default().regressor;
    robust.windows = WindowSpec::cycles(1).into();
    robust.noise = NoiseTreatment::Auto;
    assert!(robust.noise_robust().unwrap());
    let viscous =
        DampingModel::new().with(Term::per_dof(Linear, 2, Coefficients::Shared("c".into())));
    let chain2 = Case {
        name: "chain2",
        records: chain2_records(),
        settings: robust.clone(),
        with: viscous
            .clone()
            .with(structural_on(vec![Element::between(0, 1)], 400.0)),
        without: viscous,
    };
    let job = dampid::model_file::load(
        std::path::Path::new("models/chain100.toml"),
        Default::default(),
    )
    .unwrap();
    let links = job
        .model
        .terms()
        .iter()
        .find_map(|t| match t {
            Term::Elements(t) => Some(t.elements().to_vec()),
            _ => None,
        })
        .unwrap();
    let mut settings = job.settings.regressor.clone();
    settings.velocity = VelocitySource::HarmonicProjection { harmonics: None };
    settings.noise = NoiseTreatment::Auto;
    let chain100 = Case {
        name: "chain100",
        records: job.records.to_vec(),
        settings,
        with: job.model.clone().with(structural_on(links, 1.0)),
        without: job.model.clone(),
    };
    vec![chain2, chain100]
}

fn bench_structural(c: &mut Criterion) {
    let mut group = c.benchmark_group("structural");
    group.sample_size(10);
    for case in cases() {
        let build =
            |model: &DampingModel| Regressor::build(model, &case.records, &case.settings).unwrap();
        let (a, b) = (build(&case.without), build(&case.with));
        assert!(a.noise().is_some() && b.noise().is_some());
        let (mut without, mut with) = (Vec::new(), Vec::new());
        for pair in 0..PAIRS {
            // alternate which goes first: the first build of a pair ran slower
            for first in [pair % 2 == 0, pair % 2 == 1] {
                let (model, times) = if first {
                    (&case.without, &mut without)
                } else {
                    (&case.with, &mut with)
                };
                let t = Instant::now();
                black_box(build(model));
                times.push(t.elapsed().as_secs_f64());
            }
        }
        let (without, with) = (median(without), median(with));
        eprintln!(
            "structural/{}: {} rows, {} → {} columns; medians of {PAIRS} interleaved builds: without {:.3} ms, with {:.3} ms, ratio {:.3}",
            case.name,
            a.matrix().nrows(),
            a.matrix().ncols(),
            b.matrix().ncols(),
            without * 1e3,
            with * 1e3,
            with / without
        );
        group.bench_function(format!("{}/without", case.name), |bench| {
            bench.iter(|| black_box(build(&case.without)))
        });
        group.bench_function(format!("{}/with", case.name), |bench| {
            bench.iter(|| black_box(build(&case.with)))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_structural);
criterion_main!(benches);
