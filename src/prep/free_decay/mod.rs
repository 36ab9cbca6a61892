//! Free decay: one mode's ringdown, from a record with no force (or a force that ends,
//! as a hammer's does) to the whole cycles that become equations.
//!
//! Over a window [t_a, t_b] of a free decay no force does work, and the energy balance
//! of the non-periodic mode keeps its stored-energy terms:
//!
//! ```text
//!   E(t_a) − E(t_b) = Σ_k θ_k ∫ v g_k(x, v) dt,     E = ½ m v² + V(x),
//! ```
//!
//! With whole cycles between upward zero crossings of the displacement (x ≈ 0 at both
//! ends) the potential energy is a small correction, ½ m ω² x² with the cycle's own
//! frequency ([`cycles`]), and with the modal mass m known (given, or 1 for a unit modal
//! mass: coefficients per unit mass, ζ exact) every term is known but the damping. A
//! stiffness estimated beside the damping cannot work here: over cycles with their ends
//! at the same phase, ½k\[x²\] and the damping work both follow the decay of the
//! amplitude, so k and θ trade off (an SDOF ringdown gave a stiffness of 8.8 for a truth
//! of 2.5·10⁵ that way).
//!
//! The steps, per record (a record of several sensors is first projected onto the mode
//! by a [`modal_filter`]):
//! 1. **Start**: after the force has ended (the last sample where any force channel
//!    exceeds 5 % of its peak) or at a given time; a record with no force starts at once.
//! 2. **Mode isolation** ([`band`]): a zero-phase band-pass around the mode (a band
//!    given in cycles per time unit, or the largest spectral peak in a range, or in the
//!    whole record, with the band [f_p/2, 2 f_p]) and integration of velocity and
//!    acceleration signals in the frequency domain.
//! 3. **Cycles** ([`cycles`]): windows of whole cycles with their frequency, amplitude
//!    and energy decrement; cycles within [`DecaySettings::edge`] cycles of the decay's
//!    start or of the record's end are dropped (an impact's broadband force, a record
//!    that starts in motion or a cut at the end ring through the band-pass for about
//!    1/(τ f_lo)), and so is every cycle from the first whose amplitude is below
//!    [`DecaySettings::floor`] times the band's noise amplitude on.
//! 4. The **mode's record**: x and v of the band over the kept cycles (one DOF, the
//!    velocities as measured, no force), one sample before the first crossing on, so that
//!    [`cycles::windows`] finds the same cycles in it.

pub mod band;
pub mod cycles;
pub mod extend;
pub mod modal_filter;

use faer::Mat;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::record::{Forcing, Record, RecordParts, Sensor};
pub use band::Band;
pub use cycles::DecayCycle;
pub use modal_filter::ModalFilter;

/// Samples a decay needs at least after its start (a few cycles at the coarsest
/// sampling a band-pass can use).
const MIN_SAMPLES: usize = 64;

/// Where each record's free decay starts.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Start {
    /// After the force has ended (a hammer's impact), or at the first sample when the
    /// record has no force.
    Auto,
    /// At this time (the record's time axis).
    At(f64),
}

/// How the mode's band is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BandChoice {
    /// This band (cycles per time unit).
    Given(Band),
    /// [f_p/2, 2 f_p] around the largest displacement-spectrum peak f_p in this range.
    PeakIn(Band),
    /// [f_p/2, 2 f_p] around the largest displacement-spectrum peak of the record.
    Auto,
}

/// Free-decay settings.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DecaySettings {
    /// The mode's band.
    pub band: BandChoice,
    /// Modal mass m (1: a unit modal mass, coefficients per unit mass).
    pub mass: f64,
    /// Where each record's decay starts.
    pub start: Start,
    /// Whole cycles per equation (k ≥ 1).
    pub cycles: usize,
    /// Cycles of the mode dropped after the decay's start and before the record's end.
    pub edge: usize,
    /// A cycle is kept while its amplitude is at least `floor` times the band's noise
    /// amplitude.
    pub floor: f64,
}

impl DecaySettings {
    /// A unit modal mass, the band around the record's largest peak, automatic start,
    /// one cycle per equation, 4 edge cycles, floor 10.
    pub fn unit_mass() -> Self {
        DecaySettings {
            band: BandChoice::Auto,
            mass: 1.0,
            start: Start::Auto,
            cycles: 1,
            edge: 4,
            floor: 10.0,
        }
    }

    /// Checks the mass, cycles and floor.
    pub fn validate(&self) -> Result<()> {
        if !(self.mass.is_finite() && self.mass > 0.0) {
            return Err(Error::invalid(
                "mass",
                self.mass,
                "the modal mass of a free decay must be finite and positive (1 for a unit modal mass: coefficients per unit mass)",
            ));
        }
        if self.cycles == 0 {
            return Err(Error::invalid(
                "cycles",
                0.0,
                "a free-decay equation spans at least one whole cycle",
            ));
        }
        if !(self.floor.is_finite() && self.floor >= 0.0) {
            return Err(Error::invalid(
                "floor",
                self.floor,
                "must be finite and nonnegative (a multiple of the noise amplitude)",
            ));
        }
        Ok(())
    }
}

/// One record's free decay, isolated and cut into cycles.
#[derive(Debug, Clone)]
pub struct Decay {
    /// The mode's record: x and v of the band over the kept cycles.
    pub record: Record,
    /// The band the mode was isolated in.
    pub band: Band,
    /// The sample of the source record where the decay starts.
    pub start: usize,
    /// The band's noise amplitude (a displacement).
    pub noise_amplitude: f64,
    /// The kept windows of whole cycles, in samples of [`Decay::record`].
    pub cycles: Vec<DecayCycle>,
    /// Cycles dropped at a record end that cuts through motion.
    pub dropped_at_edges: usize,
    /// Cycles dropped at the noise floor.
    pub dropped_at_floor: usize,
}

impl Decay {
    /// What the isolation found, without the mode's samples.
    pub fn summary(&self, source: &Record) -> DecaySummary {
        let amplitudes = self.cycles.iter().map(|c| c.amplitude);
        DecaySummary {
            record: source.label().to_string(),
            band: self.band,
            start_time: source.start_time() + self.start as f64 * source.step(),
            noise_amplitude: self.noise_amplitude,
            cycles: self.cycles.len(),
            dropped_at_edges: self.dropped_at_edges,
            dropped_at_floor: self.dropped_at_floor,
            largest: amplitudes.clone().fold(0.0, f64::max),
            smallest: amplitudes.fold(f64::INFINITY, f64::min),
        }
    }
}

/// What isolating one record's decay found (for the text, the JSON and `dampid check`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DecaySummary {
    /// The record's label.
    pub record: String,
    /// The band the mode was isolated in (cycles per time unit).
    pub band: Band,
    /// Where the decay starts (the record's time axis).
    pub start_time: f64,
    /// The band's noise amplitude (a displacement).
    pub noise_amplitude: f64,
    /// Windows kept.
    pub cycles: usize,
    /// Cycles dropped at a record end that cuts through motion.
    pub dropped_at_edges: usize,
    /// Cycles dropped at the noise floor.
    pub dropped_at_floor: usize,
    /// The largest amplitude of a kept window.
    pub largest: f64,
    /// The smallest amplitude of a kept window.
    pub smallest: f64,
}

impl std::fmt::Display for DecaySummary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use crate::format::label;
        writeln!(
            f,
            "free decay '{}': band {}–{} cycles per time unit, from time {}; {} windows, amplitude {} down to {} ({:.1}×); dropped {} at the record's ends and {} at the noise floor (amplitude {})",
            self.record,
            label(self.band.low),
            label(self.band.high),
            label(self.start_time),
            self.cycles,
            label(self.largest),
            label(self.smallest),
            self.largest / self.smallest,
            self.dropped_at_edges,
            self.dropped_at_floor,
            label(self.noise_amplitude)
        )
    }
}

/// The sample where `record`'s decay starts (module doc, step 1).
fn start_sample(record: &Record, start: Start) -> Result<usize> {
    let n = record.samples();
    match start {
        Start::At(t) => {
            let at = ((t - record.start_time()) / record.step()).ceil();
            if !(at.is_finite() && at >= 0.0 && (at as usize) < n) {
                return Err(Error::invalid(
                    "start",
                    t,
                    &format!(
                        "must lie within record '{}' (time {} to {})",
                        record.label(),
                        record.start_time(),
                        record.start_time() + (n - 1) as f64 * record.step()
                    ),
                ));
            }
            Ok(at as usize)
        }
        Start::Auto => {
            let signals = &record.forcing().signals;
            let mut end = 0;
            for &k in record.active_channels() {
                let column = signals.col_as_slice(k);
                let peak = column.iter().fold(0.0_f64, |m, f| m.max(f.abs()));
                if let Some(last) = column.iter().rposition(|f| f.abs() > 0.05 * peak) {
                    end = end.max(last + 1);
                }
            }
            Ok(end)
        }
    }
}

/// The measured signal of `record`'s one channel and its sensor.
fn channel(record: &Record) -> Result<(Vec<f64>, Sensor)> {
    if record.dofs() != 1 {
        return Err(Error::invalid(
            "free-decay record",
            record.dofs() as f64,
            &format!(
                "record '{}' has {} motion channels; a free decay is read from one sensor of the mode, or from several through a modal filter (`[free_decay] mode_shape = [..]`, one value per sensor, or `modal_filter = \"pod\"`)",
                record.label(),
                record.dofs()
            ),
        ));
    }
    Ok(match record.measured_motion() {
        Some(m) => (m.signals.col_as_slice(0).to_vec(), m.sensors[0]),
        None => (
            record.displacements().col(0).iter().copied().collect(),
            Sensor::Displacement,
        ),
    })
}

/// Isolates the mode of `record` and cuts its decay into whole cycles (module doc).
pub fn isolate(record: &Record, settings: &DecaySettings) -> Result<Decay> {
    isolate_with(record, None, settings)
}

/// [`isolate`] of a record of several sensors, projected onto the mode by `filter`
/// first ([`modal_filter`]); with `None`, of a record of one sensor.
pub fn isolate_with(
    record: &Record,
    filter: Option<&ModalFilter>,
    settings: &DecaySettings,
) -> Result<Decay> {
    settings.validate()?;
    let start = start_sample(record, settings.start)?;
    let (signal, sensor) = match filter {
        None => channel(record)?,
        Some(filter) => {
            let range = match settings.band {
                BandChoice::Given(b) | BandChoice::PeakIn(b) => Some(b),
                BandChoice::Auto => None,
            };
            modal_filter::project(record, filter, range, start)?
        }
    };
    let step = record.step();
    let decay = &signal[start.min(signal.len())..];
    if decay.len() < MIN_SAMPLES {
        return Err(Error::RecordTooShort {
            record: format!(
                "{} (its free decay, from sample {} where the force has ended or `start` says)",
                record.label(),
                start + 1
            ),
            needed: MIN_SAMPLES,
            available: decay.len(),
        });
    }
    let around = |f: f64| Band {
        low: 0.5 * f,
        high: (2.0 * f).min(0.45 / step),
    };
    let band = match settings.band {
        BandChoice::Given(band) => band,
        BandChoice::PeakIn(range) => {
            range.validate(step, "peak_in")?;
            around(band::peak_frequency(decay, sensor, step, Some(range))?)
        }
        BandChoice::Auto => around(band::peak_frequency(decay, sensor, step, None)?),
    };
    band.validate(step, "band")?;
    let period = 2.0 * std::f64::consts::PI / band.centre() / step;
    let pad = (4.0 * period / band::TAPER).ceil() as usize;
    let span = ((16.0 * period).ceil() as usize).min(signal.len());
    let (x, v) = band::isolate(&signal, sensor, step, band, pad, span)?;
    let noise_amplitude = band::noise_amplitude(band::noise_std(decay), sensor, step, band);
    let all = cycles::windows(&x, &v, step, settings.mass, 1);
    let n = signal.len();
    let edge = (settings.edge as f64 * period).ceil() as usize;
    // The decay's start (a record that starts in motion, or the end of an impact, whose
    // broadband force the band-pass spreads over about 1/(τ f_lo)) and a record end that
    // cuts through motion ring through the filter: their first and last cycles go.
    let mut dropped_at_edges = 0;
    let mut kept: Vec<DecayCycle> = Vec::new();
    let mut dropped_at_floor = 0;
    for w in all.iter().filter(|w| w.start > start) {
        if w.start < start + edge || w.end + edge >= n {
            dropped_at_edges += 1;
            continue;
        }
        if dropped_at_floor > 0 || w.amplitude < settings.floor * noise_amplitude {
            dropped_at_floor += 1;
            continue;
        }
        kept.push(*w);
    }
    let (Some(first), Some(last)) = (kept.first(), kept.last()) else {
        // Named by the key that would change it: the floor when cycles fell below it.
        let (key, value) = if dropped_at_floor > 0 {
            ("floor", settings.floor)
        } else {
            ("edge", settings.edge as f64)
        };
        return Err(Error::invalid(
            key,
            value,
            &format!(
                "record '{}' has no whole cycle of the mode (band {:.4}–{:.4} cycles per time unit) between its start and its noise floor (amplitude {:.3e}): {} cycles in the band, {} before the decay's start, {} at the record's ends, {} below {} × the noise amplitude",
                record.label(),
                band.low,
                band.high,
                noise_amplitude,
                all.len(),
                all.iter().filter(|w| w.start <= start).count(),
                dropped_at_edges,
                dropped_at_floor,
                settings.floor
            ),
        ));
    };
    let (from, to) = (first.start - 1, last.end);
    let length = to - from + 1;
    let column = |s: &[f64]| Mat::from_fn(length, 1, |i, _| s[from + i]);
    let mean_frequency = kept.iter().map(|w| w.frequency).sum::<f64>() / kept.len() as f64;
    let mode = Record::new(RecordParts {
        label: record.label().to_string(),
        step,
        start_time: record.start_time() + from as f64 * step,
        displacements: column(&x),
        velocities: Some(column(&v)),
        forcing: Forcing::on_dofs(Mat::zeros(length, 0), Vec::new()),
        period: 2.0 * std::f64::consts::PI / mean_frequency,
    })?;
    let cycles = of_record(&mode, settings);
    Ok(Decay {
        record: mode,
        band,
        start,
        noise_amplitude,
        cycles,
        dropped_at_edges,
        dropped_at_floor,
    })
}

/// The windows of `settings.cycles` whole cycles of a mode's record (as [`isolate`]
/// returns it): the one place the regressor and the backbone cut them.
pub fn of_record(record: &Record, settings: &DecaySettings) -> Vec<DecayCycle> {
    let x: Vec<f64> = record.displacements().col(0).iter().copied().collect();
    let v: Vec<f64> = match record.velocities() {
        Some(v) => v.col(0).iter().copied().collect(),
        None => vec![0.0; x.len()],
    };
    cycles::windows(&x, &v, record.step(), settings.mass, settings.cycles)
}
