//! What happens to the records between reading them and identifying: an optional POD
//! reduction (`[pod]`) and an optional harmonic approximation (`[harmonic_approximation]`),
//! applied in that order.

use super::spec::{HarmonicApproximationSpec, PhaseName, PodSpec};
use crate::error::{Error, Result};
use crate::prep::harmonic::{HarmonicApproximation, PhaseReading};
use crate::prep::pod::{PodSettings, Retain};

/// `[pod]` as settings.
pub(super) fn pod_settings(spec: &PodSpec) -> Result<PodSettings> {
    let retain = match (spec.modes, spec.energy) {
        (Some(m), None) => Retain::Count(m),
        (None, Some(share)) => Retain::Energy(share),
        (None, None) => Retain::default(),
        (Some(m), Some(_)) => {
            return Err(Error::invalid(
                "modes",
                m as f64,
                "give at most one of `modes` (a count) or `energy` (a cumulative share)",
            ));
        }
    };
    Ok(PodSettings {
        remove_mean: spec.remove_mean,
        retain,
        basis: spec.basis,
    })
}

/// `[harmonic_approximation]` as settings, for `dofs` DOFs.
pub(super) fn harmonic_settings(
    spec: &HarmonicApproximationSpec,
    dofs: usize,
) -> Result<HarmonicApproximation> {
    let phase = match (spec.phase, spec.dof) {
        (PhaseName::Dof, Some(dof)) => {
            PhaseReading::Dof(dof.checked_sub(1).filter(|d| *d < dofs).ok_or_else(|| {
                Error::DofOutOfRange {
                    what: "harmonic_approximation.dof".into(),
                    dof,
                    dofs,
                }
            })?)
        }
        (PhaseName::Dof, None) => {
            return Err(Error::missing(
                "dof",
                "phase = \"dof\" needs `dof`, the DOF whose lag is used",
            ));
        }
        (_, Some(dof)) => {
            return Err(Error::invalid(
                "dof",
                dof as f64,
                "`dof` belongs to phase = \"dof\"",
            ));
        }
        (PhaseName::ArithmeticMean, None) => PhaseReading::ArithmeticMean,
        (PhaseName::CircularMean, None) => PhaseReading::CircularMean,
        (PhaseName::AmplitudeWeightedMean, None) => PhaseReading::AmplitudeWeightedMean,
        (PhaseName::PerDof, None) => PhaseReading::PerDof,
    };
    let settings = HarmonicApproximation {
        phase,
        samples_per_period: spec
            .samples_per_period
            .unwrap_or(HarmonicApproximation::default().samples_per_period),
    };
    settings.validate()?;
    Ok(settings)
}
