//! Velocities from noisy displacements: central differences, spectral differentiation
//! (all harmonics up to 45% of Nyquist) and harmonic projection with the automatic
//! number of harmonics, on the paper's four-mass chain (section 2.2: RK4, h = 0.1,
//! 1000 transient steps, 200 recorded steps, a ∈ {0.25, 0.5, 0.75, 1}, one window of
//! one period per amplitude, spectral quadrature so that the velocity estimate is the
//! only thing that changes).
//!
//! Gaussian noise of standard deviation σ = level × RMS of each DOF's recorded
//! displacement is added to the displacements (seeded, `TRIALS` draws per level); the
//! simulated velocities are the reference. For every noise level and method the table
//! gives, as root-mean-square over trials:
//!
//! - the relative velocity error ‖v̂ − v‖/‖v‖ over the samples the windows read,
//! - the relative errors of the identified c and d against the truth (0.15, 0.10),
//! - for harmonic projection, the mean number of harmonics kept.
//!
//!   cargo run --release --example velocity_comparison
//!
//! The measured table is in docs/velocities.md.

use dampid::prelude::*;
use dampid::prep::velocity::harmonic_selection;
use dampid::reference::{FOUR_MASS_C, FOUR_MASS_D, four_mass_model, four_mass_records};
use faer::Mat;
use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};

/// Noise draws per level.
const TRIALS: usize = 50;
/// Noise standard deviation relative to each DOF's displacement RMS.
const LEVELS: [f64; 6] = [0.0, 1e-4, 1e-3, 3e-3, 1e-2, 3e-2];

/// The records with noise of relative level `level` added to the displacements.
fn noisy(records: &[Record], level: f64, rng: &mut StdRng) -> Result<Vec<Record>> {
    let unit = Normal::new(0.0, 1.0).expect("unit normal");
    records
        .iter()
        .map(|record| {
            let mut parts = record.parts().clone();
            let x = &parts.displacements;
            let (rows, dofs) = x.shape();
            let rms: Vec<f64> = (0..dofs)
                .map(|j| ((0..rows).map(|i| x[(i, j)].powi(2)).sum::<f64>() / rows as f64).sqrt())
                .collect();
            parts.displacements = Mat::from_fn(rows, dofs, |i, j| {
                x[(i, j)] + level * rms[j] * unit.sample(rng)
            });
            Record::new(parts)
        })
        .collect()
}

/// Σ‖v̂ − v‖² and Σ‖v‖² over the window the regressor reads in every record.
fn velocity_error(
    records: &[Record],
    source: VelocitySource,
    quadrature: Quadrature,
) -> Result<(f64, f64)> {
    let mut error = 0.0;
    let mut norm = 0.0;
    for record in records {
        let count = quadrature.samples(record.period(), record.step());
        let estimate = source.window_velocities(record, 0, count)?;
        let estimate = estimate.as_ref();
        let truth = record
            .velocities()
            .ok_or_else(|| Error::MissingVelocities {
                record: record.label().to_string(),
            })?;
        for j in 0..record.dofs() {
            for i in 0..count {
                error += (estimate[(i, j)] - truth[(i, j)]).powi(2);
                norm += truth[(i, j)].powi(2);
            }
        }
    }
    Ok((error, norm))
}

struct Row {
    velocity: f64,
    c: f64,
    d: f64,
    harmonics: Option<f64>,
}

fn main() -> Result<()> {
    let clean = four_mass_records(false, 1)?;
    let model = four_mass_model();
    let quadrature = Quadrature::Spectral;
    let methods = [
        ("central differences", VelocitySource::CentralDifference),
        (
            "spectral (K = 45)",
            VelocitySource::Spectral { harmonics: None },
        ),
        (
            "harmonic projection (automatic K)",
            VelocitySource::HarmonicProjection { harmonics: None },
        ),
    ];
    println!(
        "Four-mass chain, noisy displacements: RMS over {TRIALS} draws per level; spectral quadrature, one period per amplitude"
    );
    println!(
        "{:>8}  {:<36} {:>12} {:>10} {:>10} {:>11}",
        "noise", "velocity method", "velocity err", "c err", "d err", "harmonics"
    );
    for (l, &level) in LEVELS.iter().enumerate() {
        let trials = if level == 0.0 { 1 } else { TRIALS };
        for (name, velocity) in methods {
            // Every method sees the same draws.
            let mut rng = StdRng::seed_from_u64(1000 + l as u64);
            let settings = IdentifySettings {
                regressor: RegressorSettings {
                    windows: WindowSpec::default().into(),
                    quadrature,
                    velocity,
                    ..Default::default()
                },
                ..IdentifySettings::default()
            };
            let mut sums = Row {
                velocity: 0.0,
                c: 0.0,
                d: 0.0,
                harmonics: None,
            };
            let mut kept = 0usize;
            for _ in 0..trials {
                let records = noisy(&clean, level, &mut rng)?;
                let (e, n) = velocity_error(&records, velocity, quadrature)?;
                sums.velocity += e / n;
                let report = identify(
                    &ParametricRegressor::linear(&model, &records),
                    &settings,
                    &silent,
                )?
                .report;
                let c = report.coefficient("c").unwrap_or(f64::NAN);
                let d = report.coefficient("d").unwrap_or(f64::NAN);
                sums.c += ((c - FOUR_MASS_C) / FOUR_MASS_C).powi(2);
                sums.d += ((d - FOUR_MASS_D) / FOUR_MASS_D).powi(2);
                if matches!(velocity, VelocitySource::HarmonicProjection { .. }) {
                    for record in &records {
                        let count = quadrature.samples(record.period(), record.step());
                        kept += harmonic_selection(record, 0, count)?.kept.len();
                    }
                    sums.harmonics = Some(kept as f64 / (records.len() * trials) as f64);
                }
            }
            let rms = |sum: f64| (sum / trials as f64).sqrt();
            println!(
                "{:>8}  {:<36} {:>11.3e} {:>9.3}% {:>9.3}% {:>11}",
                format!("{level:e}"),
                name,
                rms(sums.velocity),
                100.0 * rms(sums.c),
                100.0 * rms(sums.d),
                sums.harmonics
                    .map_or_else(|| "-".to_string(), |k| format!("{k:.2}")),
            );
        }
    }
    Ok(())
}
