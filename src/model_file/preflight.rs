//! Checks of a model file before any record is simulated or read, so that a mistake in
//! its settings costs no simulation and is reported at its key (`locate.rs`): `dofs`,
//! an empty `terms`, a `[matrices]` entry named like a built-in matrix, more than one
//! source of records, and the `[identification]` settings (windows, harmonics, the
//! steady-state thresholds, the fit's settings, and bounds, fixed values and linear
//! constraints against the model's coefficient names) which the identification would
//! otherwise refuse only after the records exist, without a position; and the bounds of
//! every estimated law parameter, at which the term must build (a power law's `lower =
//! -2` was found only when the search reached a negative exponent, mid-fit).

use super::context::Context;
use super::settings::{identification_settings, steady_state_settings};
use super::spec::{MatrixRef, ModelFileSpec};
use super::terms::{build_term, resolve_matrix};
use crate::error::{Error, Result};
use crate::terms::laws::Registry;

/// The names `[[terms]]` may use for a matrix without defining it.
pub(super) const BUILT_IN_MATRICES: &[&str] = &["identity", "chain"];

/// What the damping model alone needs: at least one DOF and one term, and `[matrices]`
/// names that do not shadow a built-in matrix (a `chain` entry was silently ignored in
/// favour of the built-in).
pub(super) fn model(context: &Context<'_>, spec: &ModelFileSpec) -> Result<()> {
    if spec.dofs == 0 {
        let error = Error::invalid(
            "dofs",
            0.0,
            "a model needs at least one DOF (one per motion channel)",
        );
        return Err(context.located(error, None));
    }
    if spec.terms.is_empty() {
        let error = Error::Empty {
            what: "the damping model (terms = []): give at least one [[terms]] block".into(),
        };
        return Err(context.located(error, None));
    }
    for name in spec.matrices.keys() {
        if BUILT_IN_MATRICES.contains(&name.as_str()) {
            return Err(context.error_at_key(
                Some("matrices"),
                name,
                format!(
                    "[matrices] {name}: '{name}' is the name of a built-in matrix ({}), which `matrix = \"{name}\"` always means; give your matrix another name",
                    if name == "chain" {
                        "tridiag(−1, 2, −1), fixed at both ends"
                    } else {
                        "the identity"
                    }
                ),
            ));
        }
    }
    Ok(())
}

/// The sources of records and the `[identification]` settings (module doc).
pub(super) fn settings(context: &Context<'_>, spec: &ModelFileSpec, laws: &Registry) -> Result<()> {
    // The terms first, as the job builds them: their errors are at their blocks.
    let (model, _) = context.damping_model(spec, laws)?;
    estimated_bounds(context, spec, laws)?;
    let mut units = crate::report::units::Units::default();
    for (dimension, unit) in &spec.units {
        context.at(unit, |u| units.set(dimension, u))?;
    }
    let sources: Vec<&str> = [
        ("simulation", spec.simulation.is_some()),
        ("string_simulation", spec.string_simulation.is_some()),
        ("data", spec.data.is_some()),
        ("stepped_sine", spec.stepped_sine.is_some()),
    ]
    .into_iter()
    .filter_map(|(name, given)| given.then_some(name))
    .collect();
    let exactly_one = "give exactly one of [simulation] (generate the records), [string_simulation] (the paper's string), [data] (read them) or [stepped_sine] (a measured table)";
    match sources.as_slice() {
        // None: the job says so (a file of terms alone is a model for `compare`).
        [] | [_] => {}
        [first, second, ..] => {
            return Err(context.error_at_key(
                None,
                second,
                format!("[{second}] beside [{first}]: {exactly_one}"),
            ));
        }
    }
    unused_high_pass(context, spec)?;
    let identification = |e: Error| context.located(e, Some("identification"));
    let settings = identification_settings(&spec.identification, spec.non_periodic.is_some());
    settings.regressor.validate().map_err(identification)?;
    settings.fit.validate().map_err(identification)?;
    steady_state_settings(&spec.identification)
        .validate()
        .map_err(identification)?;
    // Stepped-sine tables add structural coefficients and non-periodic spans nuisance
    // unknowns, which constraints may name: their names are checked where they exist.
    if spec.non_periodic.is_none() && spec.stepped_sine.is_none() {
        let names = model.coefficient_names();
        let constraints = &settings.fit.constraints;
        constraints
            .resolve(&names, names.len())
            .map_err(identification)?;
        constraints.resolve_linear(&names).map_err(identification)?;
    }
    Ok(())
}

/// Each estimated law parameter's bounds lie in its law's domain: the term builds with
/// the parameter at its lower and at its upper bound (the others at their initial
/// values), as the search may evaluate it at either; an error is at the term's block.
fn estimated_bounds(context: &Context<'_>, spec: &ModelFileSpec, laws: &Registry) -> Result<()> {
    let n = spec.dofs;
    let matrix = |r: &MatrixRef| resolve_matrix(r, spec, n);
    for term in &spec.terms {
        context.at(term, |t| {
            let mut estimated = Vec::new();
            let recipe = build_term(t, n, &matrix, laws, &mut estimated)?;
            let initial: Vec<f64> = estimated.iter().map(|p| p.initial).collect();
            for (k, parameter) in estimated.iter().enumerate() {
                for (side, value) in [("lower", parameter.lower), ("upper", parameter.upper)] {
                    let mut eta = initial.clone();
                    eta[k] = value;
                    recipe.build(&eta).map_err(|e| {
                        Error::invalid(
                            &format!("{side} bound of the estimated parameter '{}'", parameter.name),
                            value,
                            &format!(
                                "the law is not defined there ({e}); the search may evaluate the law at either bound, so keep both within the law's domain"
                            ),
                        )
                    })?;
                }
            }
            Ok(())
        })?;
    }
    Ok(())
}

/// `[non_periodic] high_pass` acts only where velocity or acceleration columns are
/// integrated (a DOF without a displacement column); given where no record has one, it
/// would be silently ignored, so it is refused at its key.
fn unused_high_pass(context: &Context<'_>, spec: &ModelFileSpec) -> Result<()> {
    let Some(high_pass) = spec
        .non_periodic
        .as_ref()
        .and_then(|np| np.get_ref().high_pass.as_ref())
    else {
        return Ok(());
    };
    let integrates = spec.data.iter().any(|data| {
        data.get_ref().records.iter().any(|r| {
            let r = r.get_ref();
            !r.accelerations.is_empty()
                || (!r.velocities.is_empty() && r.displacements.len() < spec.dofs)
        })
    });
    if integrates {
        return Ok(());
    }
    Err(context.error_at(
        high_pass,
        format!(
            "high_pass = {} has no effect: it filters velocity or acceleration columns that are integrated to displacements, and every record here gives displacements; remove it",
            crate::format::number(*high_pass.get_ref())
        ),
    ))
}
