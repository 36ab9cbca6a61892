//! Model-file sections as library settings: `[identification]`, `[non_periodic]`,
//! `[design]`, and the mass and stiffness of `[simulation]` or `[system]`. DOFs are
//! 1-based in the file and 0-based here. `[identification]` keys that only windows of
//! whole periods read ([`PERIODIC_ONLY`]) are refused beside `[non_periodic]`, never
//! ignored.

use std::collections::BTreeMap;

use faer::Mat;
use serde::Deserialize;
use toml::Spanned;

use super::spec::{
    CubicSpec, DesignSpec, ElementsSpec, IdentificationSpec, MatrixRef, NonPeriodicSpec,
    OffsetsSpec, StorageSpec, VelocityName,
};
use super::terms::build_elements;
use crate::analysis::design::DesignSettings;
use crate::error::{Error, Result};
use crate::fit::{Bound, Constraints, Fixed, LinearConstraint, LinearTerm};
use crate::identify::IdentifySettings;
use crate::prep::steady_state::{SteadyStateSettings, StoredEnergy};
use crate::prep::velocity::VelocitySource;
use crate::prep::window::WindowSpec;
use crate::regressor::nonperiodic::{Kinetic, Potential, StorageModel};
use crate::regressor::{RegressorSettings, SpanWindows, Windows};

/// The `[identification]` keys that apply only to windows of whole periods, with the
/// reason; beside `[non_periodic]` each is an error, not silently ignored. (No key
/// applies only to the non-periodic mode: its settings live in `[non_periodic]`.)
pub const PERIODIC_ONLY: &[(&str, &str)] = &[
    (
        "cycles",
        "it sets the whole periods per window; [non_periodic] windows are `window` time units long",
    ),
    (
        "windows",
        "it sets the windows of whole periods per record; [non_periodic] cuts as many windows of `window` time units as fit",
    ),
    (
        "harmonics",
        "it sets the harmonics of the drive for spectral or harmonic-projection velocities; non-periodic records have no drive period",
    ),
    (
        "noise",
        "the noise-robust rows project whole periods on harmonics; the non-periodic mode builds plain rows",
    ),
    (
        "max_energy_mismatch",
        "it is a threshold of the steady-state check of windows of whole periods; the non-periodic mode needs no steady state",
    ),
    (
        "max_state_mismatch",
        "it is a threshold of the steady-state check of windows of whole periods; the non-periodic mode needs no steady state",
    ),
    (
        "accept_transient",
        "it accepts windows of whole periods that fail the steady-state check; the non-periodic mode needs no steady state",
    ),
];

/// The keys of `[identification]` as written, with their positions.
#[derive(Deserialize)]
struct RawIdentification {
    #[serde(default)]
    identification: BTreeMap<String, Spanned<toml::Value>>,
}

/// The first `[identification]` key of `text` that the non-periodic mode does not read:
/// its value (for its position) and the error ([`Error::InvalidChoice`] naming the key,
/// the value and the reason).
pub(super) fn periodic_only_key(text: &str) -> Option<(Spanned<toml::Value>, Error)> {
    let raw: RawIdentification = toml::from_str(text).ok()?;
    PERIODIC_ONLY.iter().find_map(|(key, reason)| {
        raw.identification.get(*key).map(|value| {
            let error = Error::choice(
                key,
                value.get_ref(),
                &format!(
                    "[identification] {key} does not apply beside [non_periodic]: {reason}; remove it"
                ),
            );
            (value.clone(), error)
        })
    })
}

/// The keys `[identification]` accepts, in the order of [`IdentificationSpec`]'s fields
/// (a unit test checks the list against the deserializer's own).
pub const IDENTIFICATION_KEYS: &[&str] = &[
    "quadrature",
    "velocity",
    "harmonics",
    "noise",
    "weighting",
    "work_form",
    "cycles",
    "windows",
    "skip",
    "nonnegative",
    "bounds",
    "fixed",
    "constraints",
    "max_energy_mismatch",
    "max_state_mismatch",
    "accept_transient",
    "accept_negative_work",
];

/// `[identification]` given as keys and values rather than in a model file (the Python
/// package's `identify(model, records, cycles=2, ...)`), read by the same translation
/// as model files (windows of whole periods: `[non_periodic]` is a model-file section).
/// An unknown key is [`Error::UnknownName`] listing [`IDENTIFICATION_KEYS`]; a bad
/// value is [`Error::InvalidChoice`] naming its key. The settings hold the steady-state
/// check of the windows (its thresholds, and whether transients are accepted).
pub fn identification(table: &toml::Table) -> Result<IdentifySettings> {
    for (key, value) in table {
        if !IDENTIFICATION_KEYS.contains(&key.as_str()) {
            return Err(Error::UnknownName {
                what: "[identification] key".into(),
                name: key.clone(),
                known: IDENTIFICATION_KEYS.join(", "),
            });
        }
        // One key at a time, so that a wrong type or value is reported at its key.
        let single = toml::Table::from_iter([(key.clone(), value.clone())]);
        IdentificationSpec::deserialize(single).map_err(|e| {
            Error::choice(
                key,
                value,
                &format!("[identification] {key}: {}", e.message()),
            )
        })?;
    }
    let spec = IdentificationSpec::deserialize(table.clone())
        .map_err(|e| Error::choice("[identification]", table, e.message()))?;
    let steady_state = steady_state_settings(&spec);
    steady_state.validate()?;
    Ok(IdentifySettings {
        steady_state: Some(steady_state),
        ..identification_settings(&spec, false)
    })
}

/// `[identification]` and `[non_periodic]` given as tables rather than in a model file
/// (the Python package's `identify(model, records, non_periodic={"window": 0.25}, ...)`),
/// for the model of `model_text` (its `dofs`, and its `[matrices]` for a `known` mass or
/// stiffness), read by the model file's own translation (`span_settings`): same keys,
/// same defaults (central-difference velocities), same errors. An `[identification]` key
/// of [`PERIODIC_ONLY`] is [`Error::InvalidChoice`] naming it, as in a model file;
/// `high_pass` is returned apart (it acts where velocity or acceleration records are
/// integrated, which the caller does).
pub fn non_periodic_identification(
    identification_table: &toml::Table,
    non_periodic: &toml::Table,
    model_text: &str,
    file: &str,
) -> Result<(IdentifySettings, Option<f64>)> {
    // Keys and values checked one at a time, as for the periodic mode.
    identification(identification_table)?;
    if let Some((key, reason)) = PERIODIC_ONLY
        .iter()
        .find(|(key, _)| identification_table.contains_key(*key))
    {
        return Err(Error::choice(
            key,
            &identification_table[*key],
            &format!(
                "[identification] {key} does not apply beside [non_periodic]: {reason}; remove it"
            ),
        ));
    }
    let spec = IdentificationSpec::deserialize(identification_table.clone())
        .map_err(|e| Error::choice("[identification]", identification_table, e.message()))?;
    // Through TOML text, so the section reads as a model file's (`high_pass` is spanned).
    #[derive(Deserialize)]
    struct Section {
        non_periodic: NonPeriodicSpec,
    }
    let section = toml::Table::from_iter([(
        "non_periodic".to_string(),
        toml::Value::Table(non_periodic.clone()),
    )]);
    let text = toml::to_string(&section)
        .map_err(|e| Error::choice("[non_periodic]", non_periodic, &e.to_string()))?;
    let np = toml::from_str::<Section>(&text)
        .map_err(|e| Error::choice("[non_periodic]", non_periodic, e.message()))?
        .non_periodic;
    let model = super::parse_spec(model_text, file)?;
    let n = model.dofs;
    let matrix = |r: &MatrixRef| super::terms::resolve_matrix(r, &model, n);
    let mut settings = identification_settings(&spec, true);
    settings.regressor = span_settings(&np, &settings.regressor, n, &matrix)?;
    settings.steady_state = Some(steady_state_settings(&spec));
    Ok((settings, np.high_pass.map(|h| *h.get_ref())))
}

/// The steady-state check `[identification]` asks for.
pub(super) fn steady_state_settings(spec: &IdentificationSpec) -> SteadyStateSettings {
    SteadyStateSettings {
        max_energy_mismatch: spec.max_energy_mismatch,
        max_state_mismatch: spec.max_state_mismatch,
        accept_transient: spec.accept_transient,
        ..SteadyStateSettings::default()
    }
}

pub(super) fn identification_settings(
    spec: &IdentificationSpec,
    non_periodic: bool,
) -> IdentifySettings {
    let default = if non_periodic {
        VelocityName::CentralDifference
    } else {
        VelocityName::HarmonicProjection
    };
    let velocity = match spec.velocity.unwrap_or(default) {
        VelocityName::Measured => VelocitySource::Measured,
        VelocityName::CentralDifference => VelocitySource::CentralDifference,
        VelocityName::Spectral => VelocitySource::Spectral {
            harmonics: spec.harmonics,
        },
        VelocityName::HarmonicProjection => VelocitySource::HarmonicProjection {
            harmonics: spec.harmonics,
        },
    };
    let mut settings = IdentifySettings {
        regressor: RegressorSettings {
            windows: Windows::Cycles(WindowSpec {
                skip: spec.skip,
                cycles: spec.cycles,
                count: spec.windows,
            }),
            quadrature: spec.quadrature,
            velocity,
            noise: spec.noise,
            work_form: spec.work_form,
        },
        ..IdentifySettings::default()
    };
    settings.fit.weighting = spec.weighting;
    settings.fit.accept_negative_work = spec.accept_negative_work;
    settings.fit.constraints = Constraints {
        nonnegative: spec.nonnegative,
        bounds: spec
            .bounds
            .iter()
            .map(|(name, b)| Bound {
                name: name.clone(),
                lower: b.lower,
                upper: b.upper,
            })
            .collect(),
        fixed: spec
            .fixed
            .iter()
            .map(|(name, value)| Fixed {
                name: name.clone(),
                value: *value,
            })
            .collect(),
        linear: spec
            .constraints
            .iter()
            .map(|c| LinearConstraint {
                terms: c
                    .terms
                    .iter()
                    .map(|(name, coefficient)| LinearTerm {
                        name: name.clone(),
                        coefficient: *coefficient,
                    })
                    .collect(),
                relation: c.relation,
                value: c.value,
            })
            .collect(),
    };
    settings
}

/// `[design]` against the number of `[simulation]` experiments (none without one).
pub(super) fn design_settings(
    spec: &DesignSpec,
    experiments: Option<usize>,
) -> Result<DesignSettings> {
    let Some(count) = experiments else {
        return Err(Error::Empty {
            what: "[simulation] experiments: a [design] chooses among them, so it needs a [simulation] section".into(),
        });
    };
    let start = spec
        .start
        .iter()
        .map(|&k| {
            k.checked_sub(1).filter(|k| *k < count).ok_or_else(|| {
                Error::invalid(
                    "design start",
                    k as f64,
                    &format!("experiments are numbered 1..{count}"),
                )
            })
        })
        .collect::<Result<Vec<_>>>()?;
    if spec.picks == Some(0) {
        return Err(Error::invalid(
            "picks",
            0.0,
            "[design] adds at least one experiment: give picks ≥ 1, or leave it out (3)",
        ));
    }
    let settings = DesignSettings {
        criterion: spec.criterion,
        picks: spec.picks.unwrap_or(DesignSettings::default().picks),
        start,
        target_condition: spec.target_condition,
        ..DesignSettings::default()
    };
    settings.validate(count)?;
    Ok(settings)
}

/// `[non_periodic]`: fixed spans with the stored-energy unknowns, with the quadrature,
/// velocity, work form and skip of `[identification]`.
pub(super) fn span_settings(
    spec: &NonPeriodicSpec,
    identification: &RegressorSettings,
    n: usize,
    matrix: &dyn Fn(&MatrixRef) -> Result<Mat<f64>>,
) -> Result<RegressorSettings> {
    let kinetic = match &spec.mass {
        None => Kinetic::LumpedPerDof,
        Some(StorageSpec::Elements(ElementsSpec::Named(name))) if name == "each_dof" => {
            Kinetic::LumpedPerDof
        }
        Some(StorageSpec::Elements(ElementsSpec::Named(name))) if name == "none" => {
            Kinetic::Neglected
        }
        Some(StorageSpec::Known { known }) => Kinetic::Known(matrix(known)?),
        Some(StorageSpec::Elements(other)) => {
            return Err(Error::UnknownName {
                what: "mass".into(),
                name: match other {
                    ElementsSpec::Named(name) => name.clone(),
                    ElementsSpec::Pairs(_) => "a list of DOF pairs".into(),
                },
                known: "\"each_dof\", \"none\", { known = <matrix> }".into(),
            });
        }
    };
    let potential = match &spec.stiffness {
        None => Potential::Neglected,
        Some(StorageSpec::Elements(ElementsSpec::Named(name))) if name == "none" => {
            Potential::Neglected
        }
        Some(StorageSpec::Elements(elements)) => Potential::Elements(build_elements(elements, n)?),
        Some(StorageSpec::Known { known }) => Potential::Known(matrix(known)?),
    };
    let offsets = match &spec.offsets {
        None => Vec::new(),
        Some(OffsetsSpec::Named(name)) if name == "none" => Vec::new(),
        Some(OffsetsSpec::Named(name)) if name == "each_dof" => (0..n).collect(),
        Some(OffsetsSpec::Named(name)) => {
            return Err(Error::UnknownName {
                what: "offsets".into(),
                name: name.clone(),
                known: "\"each_dof\", \"none\", a list of 1-based DOFs".into(),
            });
        }
        Some(OffsetsSpec::Dofs(dofs)) => dofs
            .iter()
            .map(|&d| one_based(d, n, "offset"))
            .collect::<Result<_>>()?,
    };
    let skip = identification.windows.cycles().map_or(0, |w| w.skip);
    let storage = StorageModel {
        kinetic,
        potential,
        offsets,
    };
    let settings = RegressorSettings {
        windows: Windows::Spans(SpanWindows {
            length: spec.window,
            skip,
            storage,
        }),
        ..identification.clone()
    };
    settings.validate()?;
    if let Some(spans) = settings.windows.spans() {
        spans.storage.validate(n)?;
    }
    Ok(settings)
}

/// M, K and cubic springs from a model file's matrices (DOFs 1-based in the file).
pub(super) fn stored_energy(
    mass: &MatrixRef,
    stiffness: &MatrixRef,
    cubic: &[CubicSpec],
    n: usize,
    matrix: &dyn Fn(&MatrixRef) -> Result<Mat<f64>>,
) -> Result<StoredEnergy> {
    let cubic_springs = cubic
        .iter()
        .map(|c| Ok((one_based(c.dof, n, "cubic spring")?, c.coefficient)))
        .collect::<Result<_>>()?;
    Ok(StoredEnergy {
        mass: matrix(mass)?,
        stiffness: matrix(stiffness)?,
        cubic_springs,
    })
}

/// A 1-based model-file DOF as a 0-based index.
pub(super) fn one_based(dof: usize, n: usize, what: &str) -> Result<usize> {
    dof.checked_sub(1)
        .filter(|d| *d < n)
        .ok_or_else(|| Error::DofOutOfRange {
            what: what.to_string(),
            dof,
            dofs: n,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> toml::Table {
        toml::from_str(text).unwrap()
    }

    #[test]
    fn the_key_list_is_the_deserializers() {
        // serde lists the fields it expects when it meets an unknown one.
        let message = IdentificationSpec::deserialize(table("not_a_key = 0"))
            .unwrap_err()
            .message()
            .to_string();
        let expected: Vec<&str> = message
            .split("expected one of ")
            .nth(1)
            .unwrap()
            .split(", ")
            .map(|k| k.trim_matches('`'))
            .collect();
        assert_eq!(expected, IDENTIFICATION_KEYS);
    }

    #[test]
    fn keys_translate_as_in_model_files() {
        let given = identification(&table(
            "cycles = 2\nnonnegative = true\nvelocity = \"central_difference\"\naccept_transient = true",
        ))
        .unwrap();
        let spec = IdentificationSpec {
            cycles: 2,
            nonnegative: true,
            velocity: Some(VelocityName::CentralDifference),
            accept_transient: true,
            ..IdentificationSpec::default()
        };
        let steady = given.steady_state.unwrap();
        assert!(steady.accept_transient);
        assert_eq!(
            IdentifySettings {
                steady_state: None,
                ..given.clone()
            },
            identification_settings(&spec, false)
        );
        assert_eq!(given.regressor.windows.cycles().unwrap().cycles, 2);
        let none = identification(&toml::Table::new()).unwrap();
        assert_eq!(
            IdentifySettings {
                steady_state: None,
                ..none.clone()
            },
            identification_settings(&IdentificationSpec::default(), false)
        );
        assert_eq!(none.steady_state, Some(SteadyStateSettings::default()));
    }

    #[test]
    fn an_unknown_key_lists_the_known_ones() {
        let e = identification(&table("cycle = 2")).unwrap_err();
        assert_eq!(e.kind(), "unknown_name");
        let text = e.to_string();
        assert!(
            text.contains("'cycle'") && text.contains("cycles, windows"),
            "{text}"
        );
    }

    #[test]
    fn a_bad_value_names_its_key() {
        let e = identification(&table("quadrature = \"simpson\"")).unwrap_err();
        assert_eq!(e.kind(), "invalid_choice");
        assert!(e.to_string().contains("quadrature"), "{e}");
        let e = identification(&table("max_state_mismatch = -1.0")).unwrap_err();
        assert!(e.to_string().contains("max_state_mismatch"), "{e}");
    }
}
