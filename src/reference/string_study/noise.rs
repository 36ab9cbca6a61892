//! The noisy repetitions of the string study: U(−1, 1)·2⁻³ added to every sensor
//! displacement (StdRng seeded with [`SEED`], a fresh draw for every record and every
//! repetition), velocities dropped, the POD of the noisy displacements, velocities from
//! a least-squares Fourier series of K harmonics; over the draws, the mean and the
//! sample standard deviation s² = Σ (θ̂ − θ̄)² / (n − 1) of each estimate and the mean
//! energy share of each mode.

use faer::Mat;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use serde::Serialize;

use super::{SEED, labelled, pod_settings};
use crate::error::{Error, Result};
use crate::identify::identify;
use crate::prep::pod::{PodReport, reduce};
use crate::prep::velocity::VelocitySource;
use crate::record::Record;
use crate::reference::string::{
    STRING_AMPLITUDES, STRING_NOISE_AMPLITUDE, STRING_SENSORS, string_identify_settings,
    string_model, with_displacement_noise,
};
use crate::report::FitReport;
use crate::simulate::string::StringSystem;

/// Statistics of the noisy repetitions.
#[derive(Debug, Clone, Serialize)]
pub struct NoiseStats {
    /// Repetitions.
    pub draws: usize,
    /// Harmonics of the velocity fit.
    pub harmonics: usize,
    /// Mean of ĉ.
    pub mean_c: f64,
    /// Sample standard deviation of ĉ.
    pub std_c: f64,
    /// Mean of d̂.
    pub mean_d: f64,
    /// Sample standard deviation of d̂.
    pub std_d: f64,
    /// Mean energy share of each mode, per record.
    pub mean_energy_shares: Vec<(String, Vec<f64>)>,
}

/// Mean and sample standard deviation.
fn mean_std(values: &[f64]) -> (f64, f64) {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (mean, var.sqrt())
}

/// The records with fresh noise U(−1, 1)·2⁻³ on every displacement.
fn noisy(records: &[Record], rng: &mut StdRng) -> Result<Vec<Record>> {
    records
        .iter()
        .map(|r| {
            let noise = Mat::from_fn(r.samples(), r.dofs(), |_, _| {
                STRING_NOISE_AMPLITUDE * rng.random_range(-1.0..=1.0)
            });
            with_displacement_noise(r, &noise)
        })
        .collect()
}

/// The first draw's fit and POD, and the statistics over all draws.
pub(super) struct NoisyFits {
    pub report: FitReport,
    pub pods: Vec<(String, PodReport)>,
    pub stats: NoiseStats,
}

/// `draws` noisy repetitions of the `retained`-mode fit with K = `harmonics`; returns
/// the first draw's fit and POD with the statistics.
pub(super) fn noisy_fits(
    records: &[Record],
    retained: usize,
    harmonics: usize,
    draws: usize,
) -> Result<NoisyFits> {
    let model = string_model(&StringSystem::paper(STRING_AMPLITUDES[0]));
    let settings = string_identify_settings(VelocitySource::Spectral {
        harmonics: Some(harmonics),
    });
    let mut rng = StdRng::seed_from_u64(SEED);
    let (mut cs, mut ds) = (Vec::new(), Vec::new());
    let mut share_sums = vec![vec![0.0; STRING_SENSORS]; records.len()];
    let mut first = None;
    for _ in 0..draws.max(1) {
        let data = noisy(records, &mut rng)?;
        let reduction = reduce(&data, &pod_settings(retained))?;
        let report = identify(
            &crate::regressor::ParametricRegressor::linear(&model, &reduction.records),
            &settings,
            &crate::progress::silent,
        )?
        .report;
        cs.push(report.coefficient("c").unwrap_or(f64::NAN));
        ds.push(report.coefficient("d").unwrap_or(f64::NAN));
        for (sums, basis) in share_sums.iter_mut().zip(&reduction.bases) {
            for (s, share) in sums.iter_mut().zip(basis.energy_shares()) {
                *s += share;
            }
        }
        if first.is_none() {
            first = Some((report, labelled(&reduction, records)));
        }
    }
    let (mean_c, std_c) = mean_std(&cs);
    let (mean_d, std_d) = mean_std(&ds);
    let n = cs.len() as f64;
    let stats = NoiseStats {
        draws: cs.len(),
        harmonics,
        mean_c,
        std_c,
        mean_d,
        std_d,
        mean_energy_shares: records
            .iter()
            .zip(share_sums)
            .map(|(r, sums)| (r.label().to_string(), sums.iter().map(|s| s / n).collect()))
            .collect(),
    };
    let (report, pods) = first.ok_or(Error::Empty {
        what: "noise draws".into(),
    })?;
    Ok(NoisyFits {
        report,
        pods,
        stats,
    })
}
