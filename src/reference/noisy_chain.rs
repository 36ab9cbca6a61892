//! The noise benchmark of issue #8: a chain of six unit masses between two walls with
//! unit springs, a viscous dashpot of its own on each of the seven springs and Coulomb
//! friction on mass 3. Driven at each of the six natural frequencies ω_j = 2 sin(jπ/14)
//! on mass 1 or mass 6 (no mode has a node there) at two force amplitudes: 24
//! steady-state experiments, each recorded for a whole number of periods.
//!
//! Sensor noise is white and Gaussian on every displacement channel, with a standard
//! deviation of `level` times the RMS displacement of the experiment (all channels
//! together), so that quiet channels get the same absolute noise as loud ones, as
//! displacement sensors of one kind would.

use faer::Mat;
use rand::SeedableRng;
use rand::rngs::StdRng;
use rand_distr::{Distribution, Normal};

use super::dashpot_chain::chain_dashpots;
use crate::error::{Error, Result};
use crate::model::DampingModel;
use crate::record::Record;
use crate::simulate::chain_stiffness;
use crate::simulate::{HarmonicForce, SimSettings, System, simulate};
use crate::terms::laws::Coulomb;
use crate::terms::{Coefficients, Element, Term};

/// DOFs of the chain.
pub const NOISY_CHAIN_DOFS: usize = 6;
/// True dashpot coefficients, walls included (0-1, 1-2, …, 6-7).
pub const NOISY_CHAIN_DASHPOTS: [f64; 7] = [0.06, 0.04, 0.08, 0.05, 0.07, 0.03, 0.05];
/// True Coulomb friction force on mass 3.
pub const NOISY_CHAIN_FRICTION: f64 = 0.01;
/// Force amplitudes.
pub const NOISY_CHAIN_AMPLITUDES: [f64; 2] = [0.1, 0.25];
/// The forced masses (0-based).
pub const NOISY_CHAIN_FORCED: [usize; 2] = [0, 5];
/// Recording step.
pub const NOISY_CHAIN_STEP: f64 = 0.02;

/// The damping model: `c[i-j]` per dashpot and `mu` on mass 3.
pub fn noisy_chain_model() -> DampingModel {
    DampingModel::new()
        .with(chain_dashpots(NOISY_CHAIN_DOFS, "c"))
        .with(Term::on_elements(
            Coulomb,
            vec![Element::to_ground(2)],
            Coefficients::Shared("mu".into()),
        ))
}

/// The true coefficients in the model's column order.
pub fn noisy_chain_truth() -> Vec<f64> {
    let mut truth = NOISY_CHAIN_DASHPOTS.to_vec();
    truth.push(NOISY_CHAIN_FRICTION);
    truth
}

/// Natural frequency j = 1..6 of the chain.
pub fn noisy_chain_frequency(j: usize) -> f64 {
    2.0 * (j as f64 * std::f64::consts::PI / (2.0 * (NOISY_CHAIN_DOFS as f64 + 1.0))).sin()
}

/// The 24 clean steady-state records, each `cycles` periods long (plus two samples).
pub fn noisy_chain_records(cycles: usize) -> Result<Vec<Record>> {
    let mut records = Vec::new();
    for mode in 1..=NOISY_CHAIN_DOFS {
        let frequency = noisy_chain_frequency(mode);
        let period = 2.0 * std::f64::consts::PI / frequency;
        // Starting from rest excites every mode, so every experiment waits 15 time
        // constants of the slowest viscous modal decay (friction only adds to it): the
        // transient falls below 10⁻⁶ of the steady state.
        let slowest = (1..=NOISY_CHAIN_DOFS)
            .map(modal_decay_rate)
            .fold(f64::INFINITY, f64::min);
        let transient = 15.0 / slowest;
        let settings = SimSettings {
            step: NOISY_CHAIN_STEP,
            // RK4 across the friction's sign changes is only first order: a fine inner
            // step keeps the simulated energy balance to 10⁻⁴.
            substeps: 3,
            transient_steps: (transient / NOISY_CHAIN_STEP).ceil() as usize,
            recorded_steps: (cycles as f64 * period / NOISY_CHAIN_STEP).ceil() as usize + 2,
        };
        for &dof in &NOISY_CHAIN_FORCED {
            for &amplitude in &NOISY_CHAIN_AMPLITUDES {
                let system = System {
                    mass: Mat::identity(NOISY_CHAIN_DOFS, NOISY_CHAIN_DOFS),
                    stiffness: chain_stiffness(NOISY_CHAIN_DOFS),
                    damping: noisy_chain_model(),
                    damping_coefficients: noisy_chain_truth(),
                    conservative: Vec::new(),
                    forcing: vec![HarmonicForce {
                        dof,
                        amplitude,
                        frequency,
                        phase: 0.0,
                    }],
                };
                let mut parts =
                    simulate(&system, &settings, &crate::progress::silent)?.into_parts();
                parts.label = format!("mode {mode}, mass {}, F = {amplitude}", dof + 1);
                records.push(Record::new(parts)?);
            }
        }
    }
    Ok(records)
}

/// The viscous decay rate φᵀCφ / (2 φᵀφ) of mode j (modal damping read off the diagonal), φ_k = sin(jkπ/7) (unit masses, so
/// φᵀMφ = φᵀφ), from the dashpots.
fn modal_decay_rate(mode: usize) -> f64 {
    let n = NOISY_CHAIN_DOFS;
    let shape = |k: usize| {
        // k = 0 and k = n + 1 are the walls
        (mode as f64 * k as f64 * std::f64::consts::PI / (n as f64 + 1.0)).sin()
    };
    let dissipation: f64 = NOISY_CHAIN_DASHPOTS
        .iter()
        .enumerate()
        .map(|(e, c)| c * (shape(e + 1) - shape(e)).powi(2))
        .sum();
    let norm: f64 = (1..=n).map(|k| shape(k).powi(2)).sum();
    dissipation / (2.0 * norm)
}

/// `records` with white Gaussian displacement noise of `level` times each record's RMS
/// displacement, and the measured velocities removed (they must be estimated).
pub fn with_displacement_noise(records: &[Record], level: f64, seed: u64) -> Result<Vec<Record>> {
    let mut rng = StdRng::seed_from_u64(seed);
    records
        .iter()
        .map(|record| {
            let mut parts = record.parts().clone();
            let x = &parts.displacements;
            let count = (x.nrows() * x.ncols()) as f64;
            let mut sum_sq = 0.0;
            for j in 0..x.ncols() {
                for i in 0..x.nrows() {
                    sum_sq += x[(i, j)] * x[(i, j)];
                }
            }
            let sigma = level * (sum_sq / count).sqrt();
            // σ = 0 (no noise asked) is a valid normal distribution in rand_distr; a
            // negative or non-finite level is the caller's error.
            let normal = Normal::new(0.0, sigma).map_err(|_| {
                Error::invalid(
                    "noise level",
                    level,
                    "must be finite and ≥ 0 (a fraction of the RMS displacement)",
                )
            })?;
            let (rows, columns) = x.shape();
            for j in 0..columns {
                for i in 0..rows {
                    parts.displacements[(i, j)] += normal.sample(&mut rng);
                }
            }
            parts.velocities = None;
            Record::new(parts)
        })
        .collect()
}

/// How a pipeline did over many noise draws: per coefficient, relative to the truth.
#[derive(Debug, Clone, PartialEq)]
pub struct NoiseStudy {
    /// Root-mean-square relative error.
    pub rms: Vec<f64>,
    /// Mean relative error.
    pub bias: Vec<f64>,
    /// Mean reported standard error, relative to the truth.
    pub mean_std_error: Vec<f64>,
    /// Share of (coefficient, draw) pairs with |θ̂ − θ| ≤ 1.96 se.
    pub coverage: f64,
}

impl NoiseStudy {
    /// The largest RMS relative error over the coefficients.
    pub fn worst_rms(&self) -> f64 {
        self.rms.iter().copied().fold(0.0, f64::max)
    }
    /// The largest |bias| over the coefficients.
    pub fn worst_bias(&self) -> f64 {
        self.bias.iter().fold(0.0f64, |m, b| m.max(b.abs()))
    }
}

/// Identifies the chain from `clean` with displacement noise `level` for seeds
/// `0..seeds`, each time with `settings`, and compares with the truth.
pub fn noise_study(
    clean: &[Record],
    level: f64,
    seeds: u64,
    settings: &crate::identify::IdentifySettings,
) -> Result<NoiseStudy> {
    let truth = noisy_chain_truth();
    let model = noisy_chain_model();
    let p = truth.len();
    let (mut squares, mut sums, mut std_errors) = (vec![0.0; p], vec![0.0; p], vec![0.0; p]);
    let (mut covered, mut intervals) = (0usize, 0usize);
    for seed in 0..seeds {
        let noisy = with_displacement_noise(clean, level, seed)?;
        let report = crate::identify::identify(
            &crate::regressor::ParametricRegressor::linear(&model, &noisy),
            settings,
            &crate::progress::silent,
        )?
        .report;
        for (k, c) in report.coefficients.iter().enumerate() {
            let error = (c.value - truth[k]) / truth[k];
            squares[k] += error * error;
            sums[k] += error;
            if let Some(se) = c.std_error {
                std_errors[k] += se / truth[k];
                intervals += 1;
                if (c.value - truth[k]).abs() <= 1.959_963_985 * se {
                    covered += 1;
                }
            }
        }
    }
    let n = seeds.max(1) as f64;
    Ok(NoiseStudy {
        rms: squares.iter().map(|s| (s / n).sqrt()).collect(),
        bias: sums.iter().map(|s| s / n).collect(),
        mean_std_error: std_errors.iter().map(|s| s / n).collect(),
        coverage: covered as f64 / intervals.max(1) as f64,
    })
}

/// The settings the noise study compares: the noise-robust pipeline (harmonic
/// projection on the noise floor, bias-corrected columns, propagated weights), or the
/// plain one (15-harmonic velocities, ordinary least squares); `cycles` periods per
/// equation, one equation per record.
pub fn noise_study_settings(cycles: usize, robust: bool) -> crate::identify::IdentifySettings {
    use crate::fit::Weighting;
    use crate::prep::velocity::VelocitySource;
    use crate::prep::window::WindowSpec;
    use crate::regressor::NoiseTreatment;
    let mut settings = crate::identify::IdentifySettings::default();
    settings.regressor.windows = WindowSpec::cycles(cycles).first(1).into();
    if robust {
        settings.regressor.velocity = VelocitySource::HarmonicProjection { harmonics: None };
        settings.regressor.noise = NoiseTreatment::Correct;
        settings.fit.weighting = Weighting::Propagated;
    } else {
        settings.regressor.velocity = VelocitySource::HarmonicProjection {
            harmonics: Some(15),
        };
        settings.regressor.noise = NoiseTreatment::Ignore;
        settings.fit.weighting = Weighting::Ordinary;
    }
    settings
}
