//! The residual receptance of the modes outside a stepped-sine band, removed from each
//! measured point.
//!
//! A point's measured complex response (lag convention, x = Re Z e^{iωt}) is the mode's
//! plus the quasi-static response of the other modes to the same force a:
//!
//! ```text
//!   Z = X e^{−iφ} = Z_mode + R(ω) a,     R(ω) = r_k − r_m / ω²,
//! ```
//!
//! with r_k = 1/K_r the compliance of the higher modes (their residual stiffness K_r)
//! and r_m = 1/M_r that of the lower ones (residual mass M_r), both per sweep and free
//! in sign (zero allowed). R is real: R a is in phase with the force, does no work, and
//! leaves the input work π a X sin φ = −π a Im Z unchanged; but the mode's amplitude
//! and lag, which every damping column reads, are those of
//!
//! ```text
//!   Z_mode = (X cos φ − R a) − i X sin φ,   X_mode = |Z_mode|,   φ_mode = −arg Z_mode.
//! ```

use serde::Deserialize;

use crate::error::{Error, Result};

use super::SteppedSinePoint;
use super::sweeps::SweptTable;

/// Which residual unknowns each sweep carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ResidualKind {
    /// No residual: the points as measured.
    #[default]
    None,
    /// r_k per sweep (R = r_k).
    Stiffness,
    /// r_k and r_m per sweep (R = r_k − r_m/ω²).
    MassAndStiffness,
}

impl std::fmt::Display for ResidualKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ResidualKind::None => "none",
            ResidualKind::Stiffness => "stiffness",
            ResidualKind::MassAndStiffness => "mass_and_stiffness",
        })
    }
}

impl ResidualKind {
    /// Unknowns per sweep: 0, 1 (r_k) or 2 (r_k, r_m).
    pub fn per_sweep(self) -> usize {
        match self {
            ResidualKind::None => 0,
            ResidualKind::Stiffness => 1,
            ResidualKind::MassAndStiffness => 2,
        }
    }
}

/// R of each point of `swept` from the unknowns `values` (per sweep in sweep order:
/// r_k, then r_m for [`ResidualKind::MassAndStiffness`]).
pub fn per_point(kind: ResidualKind, values: &[f64], swept: &SweptTable) -> Result<Vec<f64>> {
    let per = kind.per_sweep();
    let expected = per * swept.sweep_names.len();
    if values.len() != expected {
        return Err(Error::mismatch(
            "residual unknowns vs sweeps × unknowns per sweep",
            expected,
            values.len(),
        ));
    }
    Ok(swept
        .table
        .points()
        .iter()
        .zip(&swept.sweeps)
        .map(|(p, &s)| match kind {
            ResidualKind::None => 0.0,
            ResidualKind::Stiffness => values[s],
            ResidualKind::MassAndStiffness => {
                values[2 * s] - values[2 * s + 1] / (p.frequency * p.frequency)
            }
        })
        .collect())
}

/// `point` with the residual response `r` a removed from its force DOF's response
/// (module doc). The input work is unchanged; a corrected amplitude that is not
/// positive and finite (the point would say nothing) is an error naming the point.
pub fn correct(point: &SteppedSinePoint, r: f64) -> Result<SteppedSinePoint> {
    correct_owned(point.clone(), r)
}

/// [`correct`] on a point the caller gives up (no copy: the trials of a variable
/// projection correct every perturbed copy of every point).
pub fn correct_owned(mut point: SteppedSinePoint, r: f64) -> Result<SteppedSinePoint> {
    correct_in_place(&mut point, r)?;
    Ok(point)
}

/// [`correct`] in place (a point the caller reuses); on error `point` is as given.
pub fn correct_in_place(point: &mut SteppedSinePoint, r: f64) -> Result<()> {
    if r == 0.0 {
        return Ok(());
    }
    let f = point.force_dof;
    let (x, phi) = (point.amplitudes[f], point.phases[f]);
    let re = x * phi.cos() - r * point.force_amplitude;
    let lag_im = x * phi.sin();
    let amplitude = re.hypot(lag_im);
    if !(amplitude.is_finite() && amplitude > 0.0) {
        return Err(Error::invalid(
            &format!(
                "amplitude of stepped-sine point '{}' after removing the residual receptance {r:e}",
                point.label
            ),
            amplitude,
            "must be finite and positive: the residual would cancel the whole response",
        ));
    }
    point.amplitudes[f] = amplitude;
    point.phases[f] = lag_im.atan2(re);
    Ok(())
}

/// The default bound B_s of |r_k| in each sweep: the smallest measured receptance
/// min_p X_p / a_p of the sweep. In a band around one mode the residual of the others
/// is a correction: at the band's edges, where the mode's own response is smallest, it
/// is still at least comparable with the residual, so |R| beyond every measured
/// |Z|/a of the sweep would leave the mode's response dominated by the other modes.
/// The bound of |r_m| is B_s ω²_min,s (so that |r_m|/ω² ≤ B_s over the sweep).
/// Both scale as the data do (force × k scales them by 1/k).
pub fn default_bounds(swept: &SweptTable) -> Vec<(f64, f64)> {
    let mut bounds = vec![(f64::INFINITY, f64::INFINITY); swept.sweep_names.len()];
    for (p, &s) in swept.table.points().iter().zip(&swept.sweeps) {
        let receptance = p.amplitudes[p.force_dof] / p.force_amplitude;
        bounds[s].0 = bounds[s].0.min(receptance);
        bounds[s].1 = bounds[s].1.min(p.frequency * p.frequency);
    }
    bounds.into_iter().map(|(b, w2)| (b, b * w2)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(x: f64, phi: f64, a: f64) -> SteppedSinePoint {
        SteppedSinePoint {
            label: "p".into(),
            frequency: 2.0,
            force_dof: 0,
            force_amplitude: a,
            amplitudes: vec![x],
            phases: vec![phi],
        }
    }

    /// Z_mode + R a is the measured Z, and the input work X sin φ is kept.
    #[test]
    fn correction_inverts_the_residual() {
        let (x, phi, a, r) = (0.3, 1.1, 2.0, -0.05);
        let mode = point(x, phi, a);
        // Z = X e^{−iφ} + R a
        let (re, im) = (x * phi.cos() + r * a, -x * phi.sin());
        let measured = point(re.hypot(im), (-im).atan2(re), a);
        let back = correct(&measured, r).unwrap();
        assert!((back.amplitudes[0] - mode.amplitudes[0]).abs() < 1e-14);
        assert!((back.phases[0] - mode.phases[0]).abs() < 1e-14);
        let work = |p: &SteppedSinePoint| p.amplitudes[0] * p.phases[0].sin();
        assert!((work(&back) - work(&measured)).abs() < 1e-14);
    }

    /// A residual equal to the whole (real) response leaves nothing: an error.
    #[test]
    fn residual_cancelling_the_response_is_an_error() {
        let p = point(0.5, 0.0, 2.0);
        assert!(correct(&p, 0.25).is_err());
    }
}
