//! The machine's roof: a streaming read over a buffer much larger than the caches.
//!
//! Sums a 1 GiB buffer of f64 (8 independent accumulators per thread, so the adds never
//! limit the loop), split into one contiguous part per rayon thread. The bytes read per
//! second is the memory bandwidth a single pass over a record can hope for; the
//! regressor bench (`benches/regressor.rs`) reads its velocities once per row, so
//! `benches/compare_numpy.sh` prints its V bytes / time against this figure.
//!
//! Benchmark id `stream_read/t{threads}/1GiB`; criterion's throughput is bytes.

use std::hint::black_box;
use std::time::Duration;

use criterion::{
    BenchmarkId, Criterion, SamplingMode, Throughput, criterion_group, criterion_main,
};
use rayon::prelude::*;

/// Buffer length in f64 (1 GiB).
const LEN: usize = 1 << 27;

/// Σ x with 8 accumulators.
fn sum(part: &[f64]) -> f64 {
    let mut lanes = [0.0; 8];
    let mut chunks = part.chunks_exact(8);
    for chunk in &mut chunks {
        for (acc, x) in lanes.iter_mut().zip(chunk) {
            *acc += x;
        }
    }
    lanes.iter().sum::<f64>() + chunks.remainder().iter().sum::<f64>()
}

fn bench_stream_read(c: &mut Criterion) {
    let threads = rayon::current_num_threads();
    // Written in parallel, so every page is real memory (not the shared zero page).
    let mut buffer = vec![0.0f64; LEN];
    buffer
        .par_chunks_mut(1 << 16)
        .enumerate()
        .for_each(|(k, chunk)| chunk.iter_mut().for_each(|x| *x = k as f64 + 0.5));
    let part = LEN.div_ceil(threads);
    let mut group = c.benchmark_group("stream_read");
    group
        .sample_size(20)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(5))
        .throughput(Throughput::Bytes((LEN * 8) as u64));
    group.bench_function(BenchmarkId::new(format!("t{threads}"), "1GiB"), |b| {
        b.iter(|| {
            black_box(&buffer)
                .par_chunks(part)
                .map(sum)
                .collect::<Vec<f64>>()
        })
    });
    group.finish();
}

criterion_group!(benches, bench_stream_read);
criterion_main!(benches);
