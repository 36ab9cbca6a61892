//! `[free_decay]`: every record of `[data]` is a ringdown of one mode. The section's keys
//! become [`DecaySettings`]; each record's mode is isolated and cut into whole cycles
//! ([`crate::prep::free_decay::isolate`]) before the job's one `identify` reads it,
//! with windows [`Windows::Decay`] and the mode's own velocity.

use toml::Spanned;

use super::context::Context;
use super::spec::{FreeDecaySpec, StartSpec};
use crate::error::{Error, Result};
use crate::prep::free_decay::{
    Band, BandChoice, Decay, DecaySettings, ModalFilter, Start, isolate_with,
};
use crate::prep::quadrature::Quadrature;
use crate::prep::velocity::VelocitySource;
use crate::record::Record;
use crate::regressor::{RegressorSettings, Windows};

/// The keys of `[identification]` that a free decay does not read, and why.
pub(super) const NOT_FOR_FREE_DECAY: &[(&str, &str)] = &[
    ("cycles", "[free_decay] sets the whole cycles per window"),
    (
        "windows",
        "a free decay's windows are its whole cycles above the noise floor",
    ),
    ("skip", "[free_decay] `start` sets where each decay starts"),
    (
        "velocity",
        "a free decay's velocity is its mode's, integrated with its displacement",
    ),
    ("harmonics", "a decay has no drive and no harmonics"),
    (
        "noise",
        "the noise-robust rows project whole periods of a drive; a decay has none",
    ),
    (
        "max_energy_mismatch",
        "a decay is not in steady state: the stored energy it loses is the equation",
    ),
    (
        "max_state_mismatch",
        "a decay is not in steady state: the stored energy it loses is the equation",
    ),
    (
        "accept_transient",
        "a decay is not in steady state: no steady-state check runs",
    ),
];

impl Context<'_> {
    /// The free-decay settings of `[free_decay]`, and the regressor settings of the job
    /// (the quadrature and work form of `[identification]`).
    pub(super) fn free_decay_settings(
        &self,
        spec: &Spanned<FreeDecaySpec>,
        identification: &RegressorSettings,
    ) -> Result<(DecaySettings, RegressorSettings)> {
        let s = spec.get_ref();
        let mass = s.mass.as_ref().ok_or_else(|| {
            self.error_at(
                spec,
                "[free_decay] needs the modal mass: `mass = 1.0` for a unit modal mass (coefficients per unit mass, and ζ exact), or the mode's modal mass in the model's units (then the coefficients are in those units); a decay loses stored energy, and only a mass says how much",
            )
        })?;
        let band = |b: &Spanned<[f64; 2]>| Band {
            low: b.get_ref()[0],
            high: b.get_ref()[1],
        };
        let choice = match (&s.band, &s.peak_in) {
            (Some(_), Some(p)) => {
                return Err(self.error_at(
                    p,
                    "give `band` (the mode's band) or `peak_in` (a range to find its peak in), not both",
                ));
            }
            (Some(b), None) => BandChoice::Given(band(b)),
            (None, Some(p)) => BandChoice::PeakIn(band(p)),
            (None, None) => BandChoice::Auto,
        };
        for b in s.band.iter().chain(&s.peak_in) {
            let value = band(b);
            if !(value.low.is_finite()
                && value.low > 0.0
                && value.high.is_finite()
                && value.high > value.low)
            {
                return Err(self.typed_error_at(
                    b,
                    Error::invalid(
                        "band",
                        value.low,
                        &format!(
                            "[{}, {}] is not a band: give [low, high] with 0 < low < high, in cycles per time unit",
                            value.low, value.high
                        ),
                    ),
                ));
            }
        }
        let start = match s.start.as_ref().map(|s| (s, s.get_ref())) {
            None => Start::Auto,
            Some((_, StartSpec::Named(name))) if name == "auto" => Start::Auto,
            Some((at, StartSpec::Named(name))) => {
                return Err(self.typed_error_at(
                    at,
                    Error::UnknownName {
                        what: "start".into(),
                        name: name.clone(),
                        known: "\"auto\" (after the force has ended), or a time".into(),
                    },
                ));
            }
            Some((_, StartSpec::Time(t))) => Start::At(*t),
        };
        let settings = DecaySettings {
            band: choice,
            mass: *mass.get_ref(),
            start,
            cycles: s.cycles.unwrap_or(1),
            edge: s.edge.unwrap_or(4),
            floor: s.floor.as_ref().map_or(10.0, |f| *f.get_ref()),
        };
        self.at(spec, |_| settings.validate())?;
        if identification.quadrature == Quadrature::Spectral {
            return Err(self.error_at(
                spec,
                "[identification] quadrature = \"spectral\" integrates whole periods of a drive; a free decay takes \"trapezoid\" or \"rectangular\"",
            ));
        }
        let regressor = RegressorSettings {
            windows: Windows::Decay(settings),
            velocity: VelocitySource::Measured,
            ..identification.clone()
        };
        Ok((settings, regressor))
    }

    /// The first `[identification]` key of the file that a free decay does not read, as
    /// an error at its line.
    pub(super) fn refuse_periodic_keys_beside_free_decay(&self) -> Result<()> {
        #[derive(serde::Deserialize)]
        struct Raw {
            #[serde(default)]
            identification: std::collections::BTreeMap<String, Spanned<toml::Value>>,
        }
        let Ok(raw) = toml::from_str::<Raw>(self.text) else {
            return Ok(());
        };
        for (key, reason) in NOT_FOR_FREE_DECAY {
            if let Some(value) = raw.identification.get(*key) {
                return Err(self.typed_error_at(
                    value,
                    Error::choice(
                        key,
                        value.get_ref(),
                        &format!(
                            "[identification] {key} does not apply beside [free_decay]: {reason}; remove it"
                        ),
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Each record's mode, isolated (through `filter` when given) and cut into cycles; the
/// error names the record.
pub(super) fn isolated(
    records: &[Record],
    filter: Option<&ModalFilter>,
    settings: &DecaySettings,
) -> Result<Vec<Decay>> {
    records
        .iter()
        .map(|r| isolate_with(r, filter, settings))
        .collect()
}

impl Context<'_> {
    /// The modal filter of `[free_decay]` (`mode_shape` or `modal_filter = "pod"`), if
    /// any; errors at the key's line.
    pub(super) fn modal_filter(&self, spec: &FreeDecaySpec) -> Result<Option<ModalFilter>> {
        match (&spec.mode_shape, &spec.modal_filter) {
            (Some(_), Some(named)) => Err(self.error_at(
                named,
                "give `mode_shape` (the mode's shape at the sensors) or `modal_filter = \"pod\"` (the record's own POD), not both",
            )),
            (Some(shape), None) => {
                let filter = ModalFilter::Shape(shape.get_ref().clone());
                filter
                    .validate()
                    .map_err(|e| self.typed_error_at(shape, e))?;
                Ok(Some(filter))
            }
            (None, Some(named)) if named.get_ref() == "pod" => Ok(Some(ModalFilter::Pod)),
            (None, Some(named)) => Err(self.typed_error_at(
                named,
                Error::UnknownName {
                    what: "modal_filter".into(),
                    name: named.get_ref().clone(),
                    known: "\"pod\" (the record's own proper orthogonal modes), or give `mode_shape`".into(),
                },
            )),
            (None, None) => Ok(None),
        }
    }

    /// Every record's motion channels against the length of `mode_shape`: an error at
    /// the key's line naming the first record whose count differs.
    pub(super) fn check_mode_shape(&self, spec: &FreeDecaySpec, records: &[Record]) -> Result<()> {
        let Some(shape) = &spec.mode_shape else {
            return Ok(());
        };
        match records.iter().find(|r| r.dofs() != shape.get_ref().len()) {
            Some(record) => Err(self.typed_error_at(
                shape,
                Error::mismatch(
                    format!(
                        "mode_shape entries vs motion channels of record '{}' (one value per sensor, in the record's order)",
                        record.label()
                    ),
                    record.dofs(),
                    shape.get_ref().len(),
                ),
            )),
            None => Ok(()),
        }
    }
}

/// The motion channels a record of `[data]` lists (its largest DOF index): the DOFs to
/// read it with when a modal filter reduces it to one mode.
pub(super) fn listed_channels(spec: &super::spec::RecordSpec) -> usize {
    [&spec.displacements, &spec.velocities, &spec.accelerations]
        .iter()
        .flat_map(|list| {
            list.iter()
                .enumerate()
                .map(|(position, c)| c.get_ref().dof.unwrap_or(position + 1))
        })
        .max()
        .unwrap_or(1)
}

/// `[identification]` and `[free_decay]` given as tables rather than in a model file
/// (the Python package's `identify(model, records, free_decay={"mass": 1.0})`), read by
/// the model file's own translation: same keys, same defaults, same errors (the typed
/// error itself, without a position in a file the user did not write), and the modal
/// filter of several sensors (`mode_shape` or `modal_filter = "pod"`) when given, for
/// [`isolate_with`].
pub fn free_decay_identification(
    identification_table: &toml::Table,
    free_decay: &toml::Table,
) -> Result<(
    crate::identify::IdentifySettings,
    DecaySettings,
    Option<ModalFilter>,
)> {
    let mut document = toml::Table::new();
    document.insert(
        "identification".into(),
        toml::Value::Table(identification_table.clone()),
    );
    document.insert("free_decay".into(), toml::Value::Table(free_decay.clone()));
    let text = toml::to_string(&document)
        .map_err(|e| Error::choice("free_decay", free_decay, &e.to_string()))?;
    let unwrapped = |e: Error| match e {
        Error::ModelFile {
            cause: Some(cause), ..
        } => *cause,
        other => other,
    };
    let context = Context {
        file: "free_decay",
        text: &text,
    };
    context
        .refuse_periodic_keys_beside_free_decay()
        .map_err(unwrapped)?;
    #[derive(serde::Deserialize)]
    struct Section {
        free_decay: Spanned<FreeDecaySpec>,
    }
    let section = toml::from_str::<Section>(&text)
        .map_err(|e| Error::choice("free_decay", free_decay, e.message()))?;
    let filter = context
        .modal_filter(section.free_decay.get_ref())
        .map_err(unwrapped)?;
    let mut settings = super::identification(identification_table)?;
    let (decay, regressor) = context
        .free_decay_settings(&section.free_decay, &settings.regressor)
        .map_err(unwrapped)?;
    settings.regressor = regressor;
    settings.steady_state = None;
    Ok((settings, decay, filter))
}
