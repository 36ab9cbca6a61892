//! The harmonic approximation (Feeny 2009, eq. 4) by numerical synthesis.
//!
//! For each stepped-sine point (ω, a on DOF f, X_i, φ_i) the motion over one period
//! T = 2π/ω is synthesized on N samples per period (t_j = jT/N, j = 0..N):
//!
//! ```text
//!   x_i(t) = X_i cos(ωt − ψ_i),   ẋ_i(t) = −ω X_i sin(ωt − ψ_i),   r_f(t) = a cos ωt,
//! ```
//!
//! with ψ_i = φ̄ for every DOF (the paper's synchronous motion) or ψ_i = φ_i (the
//! non-synchronous reading [`PhaseReading::PerDof`]). The record goes through the
//! ordinary regressor with the spectral rule and these exact velocities, one window
//! of one period (`RegressorSettings::harmonic_approximation`; identify with
//! `identify(&model, &approximation.records(&table)?, &settings)`): row = (∮ ẋᵀ f_k dt)_k, right-hand side ∮ ẋᵀ r dt. For a synchronous
//! motion this is, to quadrature accuracy,
//!
//! ```text
//!   C₀ matrix term:   π ω XᵀC₀X          quadratic on DOF i:  (8/3) ω² X_i³
//!   linear on DOF i:  π ω X_i²           Coulomb on DOF i:    4 X_i
//!   input work:       π a X_f sin φ̄
//! ```
//!
//! so the four-mass chain gives eq. 4 exactly. The spectral rule on a whole number N of
//! samples per period equals the periodic trapezoid: exact for trigonometric
//! polynomials (linear terms, input work), relative error O(N⁻⁴) for |v|³ and
//! O(N⁻²) for |v| (≈ 10⁻⁵ at the default N = 512).
//!
//! **Which mean phase.** The paper's φ̄ is "the mean phase lag of the masses with
//! respect to the excitation". [`PhaseReading::ArithmeticMean`] (the default, and the
//! reading that reproduces the paper's c_h = 0.1341, d_h = 0.1216 to 1.6% and 0.4%) is
//! the plain average of the lags, taken on the branch centred on their circular mean c
//! so that lags on both sides of ±π average correctly:
//!
//! ```text
//!   c = arg Σ_i e^{iφ_i},   φ̄ = c + (1/n) Σ_i wrap(φ_i − c),   wrap into (−π, π].
//! ```
//!
//! The circular mean c itself and the amplitude-weighted arg Σ X_i e^{iφ_i} are
//! offered too; on the four-mass chain all three agree to 0.02% in c_h. Taking the
//! driven mass's lag alone ([`PhaseReading::Dof`]) does not reproduce the paper (c_h
//! 0.150, d_h 0.105), and keeping every DOF's own lag ([`PhaseReading::PerDof`])
//! removes the synchronicity error the paper blames and lands near the truth.
//!
//! **Which window.** The paper's numbers are reproduced from the least-squares
//! fundamentals over the first whole period of its 200 recorded steps
//! (`SteppedSineTable::from_records` with `WindowSpec::default()`); the last whole
//! period, or an eight times longer transient, moves c_h by at most 0.15%
//! (`examples/paper_harmonic.rs` prints every reading).

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::prep::fourier::wrap_phase;
use crate::prep::harmonic::table::{SteppedSinePoint, SteppedSineTable};
use crate::record::{Forcing, Record, RecordParts};

use faer::Mat;

/// The smallest number of synthesized samples per period.
const MIN_SAMPLES_PER_PERIOD: usize = 16;

/// Which phase each DOF gets in the synthesized motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PhaseReading {
    /// Synchronous, φ̄ = c + mean_i wrap(φ_i − c) with c the circular mean (the paper's
    /// reading; see the module doc).
    #[default]
    ArithmeticMean,
    /// Synchronous, φ̄ = arg Σ_i e^{iφ_i}.
    CircularMean,
    /// Synchronous, φ̄ = arg Σ_i X_i e^{iφ_i}.
    AmplitudeWeightedMean,
    /// Synchronous with the lag of one DOF (0-based), e.g. the driven one.
    Dof(usize),
    /// Not synchronous: every DOF keeps its own lag φ_i.
    PerDof,
}

impl PhaseReading {
    /// The phase lag ψ_i of every DOF of `point` in the synthesized motion.
    pub fn phases(&self, point: &SteppedSinePoint) -> Result<Vec<f64>> {
        let mut out = Vec::with_capacity(point.dofs());
        self.phases_into(point, &mut out)?;
        Ok(out)
    }

    /// [`PhaseReading::phases`] into `out` (cleared first; no allocation when it holds
    /// enough room: the trials of a variable projection read every perturbed copy of
    /// every point).
    pub fn phases_into(&self, point: &SteppedSinePoint, out: &mut Vec<f64>) -> Result<()> {
        out.clear();
        let n = point.dofs();
        let circular = |weights: &dyn Fn(usize) -> f64| {
            let (s, c) = (0..n).fold((0.0, 0.0), |(s, c), i| {
                (
                    s + weights(i) * point.phases[i].sin(),
                    c + weights(i) * point.phases[i].cos(),
                )
            });
            s.atan2(c)
        };
        let common = match *self {
            PhaseReading::PerDof => {
                out.extend_from_slice(&point.phases);
                return Ok(());
            }
            PhaseReading::ArithmeticMean => {
                let centre = circular(&|_| 1.0);
                let offset: f64 = point
                    .phases
                    .iter()
                    .map(|phi| wrap_phase(phi - centre))
                    .sum::<f64>()
                    / n as f64;
                centre + offset
            }
            PhaseReading::CircularMean => circular(&|_| 1.0),
            PhaseReading::AmplitudeWeightedMean => circular(&|i| point.amplitudes[i]),
            PhaseReading::Dof(dof) => {
                if dof >= n {
                    return Err(Error::dof_index("phase reading", dof, n));
                }
                point.phases[dof]
            }
        };
        out.resize(n, common);
        Ok(())
    }
}

/// Settings of the harmonic approximation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct HarmonicApproximation {
    /// How the DOFs' phases are read.
    pub phase: PhaseReading,
    /// Samples per synthesized period N (≥ 16; default 512).
    pub samples_per_period: usize,
}

impl Default for HarmonicApproximation {
    /// The paper's synchronous motion with the arithmetic mean lag, 512 samples per period.
    fn default() -> Self {
        HarmonicApproximation {
            phase: PhaseReading::ArithmeticMean,
            samples_per_period: 512,
        }
    }
}

impl HarmonicApproximation {
    /// Checks the settings themselves.
    pub fn validate(&self) -> Result<()> {
        if self.samples_per_period < MIN_SAMPLES_PER_PERIOD {
            return Err(Error::invalid(
                "samples_per_period",
                self.samples_per_period as f64,
                &format!("must be at least {MIN_SAMPLES_PER_PERIOD}"),
            ));
        }
        Ok(())
    }

    /// The motion of `point` over one period as a record with exact velocities.
    pub fn synthesize(&self, point: &SteppedSinePoint) -> Result<Record> {
        self.validate()?;
        self.synthesize_on(point, &self.angles())
    }

    /// (sin θ_j, cos θ_j) of the N + 1 sample angles θ_j = 2πj/N, shared by every point:
    /// with cos(θ − φ) = cos θ cos φ + sin θ sin φ and sin(θ − φ) = sin θ cos φ −
    /// cos θ sin φ a point then costs no trigonometric call per sample (the table
    /// builds of variable projection synthesize thousands of points).
    fn angles(&self) -> Vec<(f64, f64)> {
        let per_period = self.samples_per_period;
        (0..=per_period)
            .map(|j| (2.0 * std::f64::consts::PI * j as f64 / per_period as f64).sin_cos())
            .collect()
    }

    /// [`Self::synthesize`] on the sample angles `trig` of [`Self::angles`].
    fn synthesize_on(&self, point: &SteppedSinePoint, trig: &[(f64, f64)]) -> Result<Record> {
        // A point from a table is valid; one built by hand is checked here.
        SteppedSineTable::new(vec![point.clone()])?;
        let phases = self.phase.phases(point)?;
        let n = point.dofs();
        let omega = point.frequency;
        let period = 2.0 * std::f64::consts::PI / omega;
        let per_period = self.samples_per_period;
        let samples = per_period + 1;
        let lag: Vec<(f64, f64)> = phases.iter().map(|p| p.sin_cos()).collect();
        let x = Mat::from_fn(samples, n, |j, i| {
            let ((s, c), (sp, cp)) = (trig[j], lag[i]);
            point.amplitudes[i] * (c * cp + s * sp)
        });
        let v = Mat::from_fn(samples, n, |j, i| {
            let ((s, c), (sp, cp)) = (trig[j], lag[i]);
            -omega * point.amplitudes[i] * (s * cp - c * sp)
        });
        let force = Mat::from_fn(samples, 1, |j, _| point.force_amplitude * trig[j].1);
        Record::new(RecordParts {
            label: point.label.clone(),
            step: period / per_period as f64,
            start_time: 0.0,
            displacements: x,
            velocities: Some(v),
            forcing: Forcing::on_dofs(force, vec![point.force_dof]),
            period,
        })
    }

    /// The synthesized record of every point of `table`.
    pub fn records(&self, table: &SteppedSineTable) -> Result<Vec<Record>> {
        self.records_of(table.points())
    }

    /// The synthesized record of each of `points`.
    pub fn records_of(&self, points: &[SteppedSinePoint]) -> Result<Vec<Record>> {
        self.validate()?;
        // Every synthesized record is held at once: N + 1 samples of x and v per DOF
        // and one force channel, and the table of sample angles.
        let channels = points.iter().map(|p| 2 * p.dofs() + 1).max().unwrap_or(1);
        let samples = self.samples_per_period.saturating_add(1);
        crate::budget::require(
            &format!(
                "the harmonic approximation's records: {} point{} × {} samples × {channels} channels",
                points.len(),
                if points.len() == 1 { "" } else { "s" },
                crate::format::integer(samples as u128)
            ),
            crate::budget::f64s(
                (samples as u128)
                    .saturating_mul(channels as u128)
                    .saturating_mul(points.len() as u128)
                    .saturating_add(2 * samples as u128),
            ),
            "lower `samples_per_period` in [harmonic_approximation] (512 is plenty for one harmonic)",
        )?;
        let trig = self.angles();
        points
            .iter()
            .map(|point| self.synthesize_on(point, &trig))
            .collect()
    }
}
