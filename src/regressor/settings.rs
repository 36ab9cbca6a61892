//! How records become equations: which windows, which quadrature rule, where velocities
//! come from, whether the noise-robust rows are built, and which form of the work.
//!
//! | setting | default | purpose | range |
//! |---|---|---|---|
//! | `windows` | `Cycles`: one window of one period per record | [`Windows`]: whole periods (periodic balance) or fixed spans (non-periodic balance) | cycles ≥ 1; span length > 0 |
//! | `quadrature` | trapezoid | the rule of the window integrals | spans: rectangular or trapezoid |
//! | `velocity` | harmonic projection | measured, central differences, spectral, harmonic projection | spans: measured or central differences |
//! | `noise` | auto | the noise-robust rows ([`crate::regressor::robust`]) | `correct` needs harmonic projection |
//! | `work_form` | velocity | ∫ vᵀr dt, or the derivative-free ∫ rᵀdx | both |

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::prep::free_decay::DecaySettings;
use crate::prep::quadrature::Quadrature;
use crate::prep::velocity::VelocitySource;
use crate::prep::window::WindowSpec;
use crate::regressor::nonperiodic::storage::StorageModel;

/// How records are cut into the windows that become equations.
#[derive(Debug, Clone, PartialEq)]
pub enum Windows {
    /// Windows of whole driving periods: over each the stored energy returns to its
    /// start, so each is one equation in the damping coefficients alone.
    Cycles(WindowSpec),
    /// Consecutive windows of a fixed length, for records that are not periodic: the
    /// change of stored energy and constant forces join the unknowns as nuisance
    /// columns ([`crate::regressor::nonperiodic`]).
    Spans(SpanWindows),
    /// Whole cycles of a mode's free decay (records as
    /// [`crate::prep::free_decay::isolate`] returns them): the stored energy lost over
    /// each is known from the modal mass (`src/regressor/free_decay.rs`).
    Decay(DecaySettings),
}

impl Default for Windows {
    fn default() -> Self {
        Windows::Cycles(WindowSpec::default())
    }
}

impl From<WindowSpec> for Windows {
    fn from(spec: WindowSpec) -> Self {
        Windows::Cycles(spec)
    }
}

impl Windows {
    /// The whole-period windows, or `None` for fixed spans.
    pub fn cycles(&self) -> Option<&WindowSpec> {
        match self {
            Windows::Cycles(spec) => Some(spec),
            Windows::Spans(_) | Windows::Decay(_) => None,
        }
    }

    /// The whole-period windows to edit, or `None` for fixed spans.
    pub fn cycles_mut(&mut self) -> Option<&mut WindowSpec> {
        match self {
            Windows::Cycles(spec) => Some(spec),
            Windows::Spans(_) | Windows::Decay(_) => None,
        }
    }

    /// The free-decay settings, or `None` for other windows.
    pub fn decay(&self) -> Option<&DecaySettings> {
        match self {
            Windows::Decay(decay) => Some(decay),
            _ => None,
        }
    }

    /// The fixed spans, or `None` for whole periods.
    pub fn spans(&self) -> Option<&SpanWindows> {
        match self {
            Windows::Cycles(_) | Windows::Decay(_) => None,
            Windows::Spans(spans) => Some(spans),
        }
    }

    /// The fixed spans to edit, or `None` for whole periods.
    pub fn spans_mut(&mut self) -> Option<&mut SpanWindows> {
        match self {
            Windows::Cycles(_) | Windows::Decay(_) => None,
            Windows::Spans(spans) => Some(spans),
        }
    }
}

/// Windows of a fixed length over records that are not periodic, and what stores
/// energy over them ([`crate::regressor::Windows::Spans`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SpanWindows {
    /// Window length in time units (rounded to whole sample steps of each record).
    pub length: f64,
    /// Samples to skip at the start of each record.
    pub skip: usize,
    /// Kinetic and potential energy and constant forces.
    pub storage: StorageModel,
}

impl SpanWindows {
    /// Windows of `length` time units from the first sample, an unknown lumped mass
    /// per DOF and no springs or constant forces.
    pub fn new(length: f64) -> Self {
        SpanWindows {
            length,
            skip: 0,
            storage: StorageModel::default(),
        }
    }

    /// Checks the window length.
    pub fn validate(&self) -> Result<()> {
        if !(self.length.is_finite() && self.length > 0.0) {
            return Err(Error::invalid(
                "window",
                self.length,
                "the window length must be finite and positive",
            ));
        }
        Ok(())
    }
}

/// Whether columns are corrected for sensor noise.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NoiseTreatment {
    /// Correct when the velocities come from harmonic projection, else ignore.
    #[default]
    Auto,
    /// The plain pipeline: columns as sampled, no noise estimate, no propagation.
    Ignore,
    /// The noise-robust pipeline (needs harmonic-projection velocities).
    Correct,
}

/// How the input work (and, on raw samples, Coulomb columns) are integrated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WorkForm {
    /// ∫ vᵀ r dt and ∫ |v| dt with the rule's weights. In the noise-robust pipeline v̂ is
    /// the exact derivative of the projected displacement x̂, so this is ∫ rᵀ dx̂
    /// integrated by the rule (spectrally accurate over whole periods), with no
    /// difference of noisy samples.
    #[default]
    Velocity,
    /// ∫ rᵀ dx as a trapezoidal Stieltjes sum and Coulomb work as the total variation of
    /// the sampled x (see [`crate::regressor::derivative_free`]): no velocity estimate
    /// enters them. Its relative error on a harmonic of phase step δ = kωh is about
    /// −δ²/6.
    DerivativeFree,
}

/// How records become equations.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RegressorSettings {
    /// How records are cut into windows: whole periods, or fixed spans.
    pub windows: Windows,
    /// The quadrature rule for window integrals.
    pub quadrature: Quadrature,
    /// Where velocities come from.
    pub velocity: VelocitySource,
    /// Whether columns are corrected for sensor noise (the noise-robust pipeline).
    pub noise: NoiseTreatment,
    /// Velocity-weighted or derivative-free forms of the input and Coulomb work.
    pub work_form: WorkForm,
}

impl RegressorSettings {
    /// The paper's plain pipeline: `velocity` as given, no noise correction,
    /// velocity-weighted work.
    pub fn plain(windows: WindowSpec, quadrature: Quadrature, velocity: VelocitySource) -> Self {
        RegressorSettings {
            windows: Windows::Cycles(windows),
            quadrature,
            velocity,
            noise: NoiseTreatment::Ignore,
            work_form: WorkForm::Velocity,
        }
    }

    /// The non-periodic balance over `spans`: trapezoid rule, central-difference
    /// velocities (a harmonic projection needs a period), velocity-weighted work.
    pub fn non_periodic(spans: SpanWindows) -> Self {
        RegressorSettings {
            windows: Windows::Spans(spans),
            quadrature: Quadrature::Trapezoid,
            velocity: VelocitySource::CentralDifference,
            noise: NoiseTreatment::Auto,
            work_form: WorkForm::Velocity,
        }
    }

    /// How the synthesized records of a harmonic approximation
    /// ([`crate::prep::harmonic::HarmonicApproximation`]) are integrated: one window of
    /// one period, the spectral rule, the synthesized (exact) velocities.
    pub fn harmonic_approximation() -> Self {
        RegressorSettings {
            windows: Windows::Cycles(WindowSpec::default()),
            quadrature: Quadrature::Spectral,
            velocity: VelocitySource::Measured,
            ..RegressorSettings::default()
        }
    }

    /// The whole-period windows of these settings, with `spec` instead.
    pub fn with_windows(mut self, spec: WindowSpec) -> Self {
        self.windows = Windows::Cycles(spec);
        self
    }

    /// Checks the settings themselves (not against a record): the window settings, and
    /// for fixed spans a rule and a velocity source that need no period.
    pub fn validate(&self) -> Result<()> {
        if let VelocitySource::Spectral { harmonics: Some(0) }
        | VelocitySource::HarmonicProjection { harmonics: Some(0) } = self.velocity
        {
            return Err(Error::invalid(
                "harmonics",
                0.0,
                "must be at least 1 (the harmonics of the drive the velocities are built from)",
            ));
        }
        match &self.windows {
            Windows::Cycles(spec) => spec.validate(),
            Windows::Spans(spans) => {
                spans.validate()?;
                if self.quadrature == Quadrature::Spectral {
                    return Err(Error::choice(
                        "quadrature",
                        "spectral",
                        "a spectral rule integrates whole periods; non-periodic windows take `trapezoid` or `rectangular`",
                    ));
                }
                if !matches!(
                    self.velocity,
                    VelocitySource::Measured | VelocitySource::CentralDifference
                ) {
                    return Err(Error::choice(
                        "velocity",
                        self.velocity.name(),
                        "it needs a driving period; non-periodic windows take `measured` or `central_difference` velocities",
                    ));
                }
                Ok(())
            }
            Windows::Decay(decay) => {
                decay.validate()?;
                if self.velocity != VelocitySource::Measured
                    || self.quadrature == Quadrature::Spectral
                {
                    return Err(Error::choice(
                        "velocity",
                        self.velocity.name(),
                        "a free decay's velocity is the mode's, integrated with its displacement (`measured`, over the `trapezoid` or `rectangular` rule)",
                    ));
                }
                Ok(())
            }
        }
    }

    /// The harmonics a harmonic projection keeps: `Some(K)` for 1..K, `None` for those
    /// above the noise floor (and for every other velocity source).
    pub fn projection_harmonics(&self) -> Option<usize> {
        match self.velocity {
            VelocitySource::HarmonicProjection { harmonics } => harmonics,
            _ => None,
        }
    }

    /// Whether the noise-robust pipeline runs: `Auto` runs it with harmonic-projection
    /// velocities; `Correct` with any other source is an error.
    pub fn noise_robust(&self) -> Result<bool> {
        let projected = matches!(self.velocity, VelocitySource::HarmonicProjection { .. });
        match self.noise {
            NoiseTreatment::Ignore => Ok(false),
            NoiseTreatment::Auto => Ok(projected),
            NoiseTreatment::Correct if projected => Ok(true),
            NoiseTreatment::Correct => Err(Error::choice(
                "noise",
                "correct",
                &format!(
                    "noise correction needs velocity = harmonic_projection (the noise of a projection is known), not {}; set noise = ignore or change the velocity source",
                    self.velocity.name()
                ),
            )),
        }
    }
}
