//! Speed of the proper orthogonal decomposition of a large record: n = 1000 DOFs,
//! N = 1e5 samples (800 MB of displacements), `Pod::from_displacements`: the
//! correlation matrix R = XᵀX/N (lower triangle, one matrix product) and its
//! eigendecomposition (n × n).
//!
//! X is a chain-like response: five standing-wave shapes sin(kπ(i+1)/(n+1)) with
//! amplitudes 1/k at frequencies k·ω, plus a small deterministic ripple on every DOF so
//! that R has full rank. Ids `pod/t{threads}/n1000_N100000` (the paper's setting, mean
//! kept) and `pod_centred/...` (mean removed, centred block by block).

use std::f64::consts::PI;
use std::hint::black_box;
use std::time::Duration;

use criterion::{
    BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group, criterion_main,
};
use dampid::prelude::*;
use faer::Mat;
use rayon::prelude::*;

const DOFS: usize = 1000;
const SAMPLES: usize = 100_000;

fn displacements() -> Mat<f64> {
    let mut x = Mat::<f64>::zeros(SAMPLES, DOFS);
    x.par_col_iter_mut().enumerate().for_each(|(i, col)| {
        let col = col.try_as_col_major_mut().unwrap().as_slice_mut();
        let shape: Vec<f64> = (1..=5)
            .map(|k| (k as f64 * PI * (i + 1) as f64 / (DOFS + 1) as f64).sin() / k as f64)
            .collect();
        for (s, out) in col.iter_mut().enumerate() {
            let t = s as f64 * 0.01;
            *out = shape
                .iter()
                .enumerate()
                .map(|(k, a)| a * ((k + 1) as f64 * 0.7 * t).cos())
                .sum::<f64>()
                + 1e-3 * ((i * 7919 + s * 104_729) % 1000) as f64 / 1000.0;
        }
    });
    x
}

fn bench_pod(c: &mut Criterion) {
    let threads = rayon::current_num_threads();
    let x = displacements();
    for (group_name, remove_mean) in [("pod", false), ("pod_centred", true)] {
        let mut group = c.benchmark_group(group_name);
        group
            .sample_size(10)
            .sampling_mode(SamplingMode::Flat)
            .warm_up_time(Duration::from_secs(1))
            .measurement_time(Duration::from_secs(10))
            .throughput(Throughput::Elements((DOFS * SAMPLES) as u64));
        let settings = PodSettings {
            remove_mean,
            ..PodSettings::default()
        };
        let id = BenchmarkId::new(format!("t{threads}"), format!("n{DOFS}_N{SAMPLES}"));
        group.bench_function(id, |b| {
            b.iter(|| Pod::from_displacements(black_box(x.as_ref()), &settings).unwrap())
        });
        group.finish();
    }
}

criterion_group!(benches, bench_pod);
criterion_main!(benches);
