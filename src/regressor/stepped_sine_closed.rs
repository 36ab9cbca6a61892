//! A stepped-sine point's row in closed form, when every term of the model has one
//! ([`crate::terms::harmonic_work`]): the row the synthesis of one period would give
//! (`regressor/stepped_sine.rs`, [`crate::prep::harmonic::approximation`]), without the
//! period. With the synthesized motion's phasors Z_j = X_j e^{−iψ_j} (ψ from the
//! approximation's phase reading) at the point's ω,
//!
//! ```text
//!   A_pk = W_k(ω, Z)   (terms::harmonic_work),   b_p = π a X_f sin ψ_f,
//! ```
//!
//! the exact single-harmonic integrals; the synthesized rows are their 512-sample
//! quadratures (exact for viscous terms and the input work, relative error up to
//! 2.4·10⁻⁹ for a power law of exponent 1.5, 1.3·10⁻⁵ for Coulomb friction).
//!
//! With a direction dZ of the phasors, the row's derivative along it comes with it
//! (`row_and_slope`: the stepped-sine ∂A/∂R, dZ_f = −a).
//!
//! A point keeps the synthesis (`None`) where the synthesized record would meet one of
//! the build's refusals, so that it still raises them: a force or motion that is zero or
//! nearly so (no input work, `regressor/input_work.rs`; a DOF that does not move,
//! `regressor/dead_motion.rs`), a lag whose input work is nothing beside the gross
//! work, magnitudes far from double precision's comfortable range
//! (`prep/data_scale.rs`), or a column that is not finite.

use std::f64::consts::PI;

use crate::model::DampingModel;
use crate::prep::harmonic::SteppedSinePoint;
use crate::terms::Term;
use crate::terms::harmonic_work::Phasor;

/// A DOF moving less than this share of the largest amplitude is synthesized.
const MOTION_SHARE: f64 = 1e-9;

/// A point whose |sin ψ_f| is at most this is synthesized (its input work is then
/// within a factor 10⁻⁶ of the gross work's floor of the synthesized check).
const LAG_FLOOR: f64 = 1e-6;

/// Magnitudes of a, X and ω outside [1/RANGE, RANGE] are synthesized.
const RANGE: f64 = 1e100;

/// Whether the rows of `model` have a closed form: some terms, each with one.
pub(crate) fn applies(model: &DampingModel) -> bool {
    !model.terms().is_empty() && model.terms().iter().all(Term::has_harmonic_work)
}

/// The model's columns and the input work of `point` whose DOFs lag by `psi` (the
/// approximation's phase reading), or `None` when the point keeps the synthesis
/// (module doc).
pub(crate) fn row(
    model: &DampingModel,
    point: &SteppedSinePoint,
    psi: &[f64],
) -> Option<(Vec<f64>, f64)> {
    row_with(model, point, psi, &mut Vec::new())
}

/// [`row`] with the phasors in `z`, a buffer the caller reuses over many points.
pub(crate) fn row_with(
    model: &DampingModel,
    point: &SteppedSinePoint,
    psi: &[f64],
    z: &mut Vec<Phasor>,
) -> Option<(Vec<f64>, f64)> {
    row_and_slope(model, point, psi, z, None)
}

/// [`row_with`], and with `derivative` = (dZ, slope) the columns' derivative along the
/// phasors' direction dZ (one per DOF) into `slope` (cleared first;
/// [`Term::harmonic_columns_and_slope_into`]): the columns are those of [`row_with`]
/// to the last bit. A slope that is not finite is left for the caller to refuse.
pub(crate) fn row_and_slope(
    model: &DampingModel,
    point: &SteppedSinePoint,
    psi: &[f64],
    z: &mut Vec<Phasor>,
    mut derivative: Option<(&[Phasor], &mut Vec<f64>)>,
) -> Option<(Vec<f64>, f64)> {
    let f = point.force_dof;
    let in_range = |v: f64| (1.0 / RANGE..=RANGE).contains(&v);
    let largest = point.amplitudes.iter().fold(0.0f64, |m, x| m.max(*x));
    // sin ψ_f, read once: the lag's floor and the input work
    let sin_f = match psi.get(f) {
        Some(p) if !p.is_nan() => p.sin(),
        _ => return None,
    };
    if !in_range(point.force_amplitude)
        || !in_range(point.frequency)
        || !in_range(largest)
        || point
            .amplitudes
            .iter()
            .any(|&x| x.is_nan() || x <= MOTION_SHARE * largest)
        || psi.len() != point.amplitudes.len()
        || sin_f.abs() <= LAG_FLOOR
    {
        return None;
    }
    z.clear();
    z.extend(point.amplitudes.iter().zip(psi).map(|(x, p)| {
        let (s, c) = p.sin_cos();
        (x * c, -x * s)
    }));
    let mut columns = Vec::with_capacity(model.coefficient_count());
    if let Some((_, slope)) = derivative.as_mut() {
        slope.clear();
    }
    for term in model.terms() {
        let done = match derivative.as_mut() {
            Some((dz, slope)) => {
                term.harmonic_columns_and_slope_into(point.frequency, z, dz, &mut columns, slope)
            }
            None => term.harmonic_columns_into(point.frequency, z, &mut columns),
        };
        if !done {
            return None;
        }
    }
    let input = PI * point.force_amplitude * point.amplitudes[f] * sin_f;
    (input.is_finite() && columns.iter().all(|c| c.is_finite())).then_some((columns, input))
}
