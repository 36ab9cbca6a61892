//! A record's noise and harmonics, estimated once for every window of it.
//!
//! The sensors' noise and the harmonics the motion carries are properties of a record
//! (one drive, one set of sensors), not of a window: estimating them per window from
//! one or two periods gives every window its own random error (a median over ≈ 90–250
//! noise bins, 9–13 % on σ̂) and its own harmonic set. Here they are estimated once per
//! record from up to [`MAX_SPANS`] spans of [`SPAN_PERIODS`] whole periods, evenly
//! spread over the record (non-overlapping, from its first sample; a record of fewer
//! than two periods gives one span of one period):
//!
//! ```text
//!   per span s:   S_s, σ̂_{j,s}        (noise_floor.rs: out-of-band median, A_k > 3.5 σ̂_A)
//!   S   = {1} ∪ {q : q ∈ S_s for at least MIN_SPANS_ABOVE spans s}   (any one span when
//!                                      fewer than three are sampled)
//!   σ̂_j = median_s σ̂_{j,s}            (per motion channel, and per force channel)
//! ```
//!
//! A harmonic on noise alone stands above the floor of a span in some channel with
//! probability ≈ n · 5·10⁻⁶ (n channels): of 16 spans and K_max = 90 orders, one of
//! them would (0.7 for n = 100), each adding two coefficients to every window's fit,
//! while two spans in the same order happen about once in 400 records. A harmonic
//! that the motion carries stands above the noise in most spans, or in those a
//! transient reaches, two at least unless it lasts less than two of the sampled spans.
//! The median over spans ignores the minority whose out-of-band bins a transient
//! reached. The cost is that of the selection on 2 · MAX_SPANS periods, whatever the
//! record's length.
//!
//! Motion channels are taken as measured ([`Record::measured_motion`], where their
//! noise is white), so σ̂_j is in the units of channel j's sensor.

use faer::MatRef;
use rayon::prelude::*;

use super::noise_floor::{HarmonicSelection, select_harmonics};
use crate::error::{Error, Result};
use crate::record::Record;

/// Periods of each span the record's noise is estimated on.
pub(crate) const SPAN_PERIODS: usize = 2;
/// Most spans the record's noise is estimated on.
pub(crate) const MAX_SPANS: usize = 16;
/// Sampled spans in which a harmonic must stand above the noise to be kept, when
/// three or more are sampled.
pub(crate) const MIN_SPANS_ABOVE: usize = 2;

/// The harmonics and the noise of one record (module doc).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct RecordNoise {
    /// Harmonic orders S that stand above the noise in [`MIN_SPANS_ABOVE`] sampled spans
    /// (in one when fewer than three are sampled), ascending, starting with 1.
    pub(crate) kept: Vec<usize>,
    /// Per motion channel, σ̂_j per sample (in its sensor's units).
    pub(crate) motion_std: Vec<f64>,
    /// Per force channel, σ̂ per sample.
    pub(crate) force_std: Vec<f64>,
    /// Spans sampled.
    pub(crate) spans: usize,
}

/// The samples [first, first + m) of each sampled span of `record`, and the whole
/// periods P each holds.
fn sampled_spans(record: &Record) -> Result<(Vec<(usize, usize)>, usize)> {
    let length = record.period() / record.step();
    let available = record.samples();
    // whole periods the record holds (a position within round-off of a whole number
    // of samples is that number)
    let held = available as f64 / length;
    let whole = (held.round() - held).abs() <= 1e-9 * held.max(1.0);
    let periods = if whole { held.round() } else { held.floor() } as usize;
    let per_span = SPAN_PERIODS.min(periods);
    // a span needs a mean and the fundamental: 3 samples
    if periods == 0 || (per_span as f64 * length).ceil() < 3.0 {
        return Err(Error::invalid(
            "samples per record",
            available as f64,
            &format!(
                "estimating the record's noise needs a whole period, and 3 samples in spans of up to {SPAN_PERIODS} periods; {} holds {available} samples of a period of {length:.3} samples",
                record.label()
            ),
        ));
    }
    let count = periods / per_span;
    let chosen = count.min(MAX_SPANS);
    let bound = |position: f64| {
        let snapped = position.round();
        let position = if (position - snapped).abs() <= 1e-9 * position.max(1.0) {
            snapped
        } else {
            position
        };
        (position.ceil() as usize).min(available)
    };
    let spans = (0..chosen)
        .map(|s| {
            // evenly spread: span indices 0 and count − 1 are both sampled
            let index = if chosen == 1 {
                0
            } else {
                (s * (count - 1) + (chosen - 1) / 2) / (chosen - 1)
            };
            let origin = (index * per_span) as f64 * length;
            let first = bound(origin);
            let end = bound(origin + per_span as f64 * length);
            (first, end - first)
        })
        .collect();
    Ok((spans, per_span))
}

/// The median of `values` (the mean of the two middle ones for an even count).
fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    let n = values.len();
    if n == 0 {
        0.0
    } else if n % 2 == 1 {
        values[n / 2]
    } else {
        0.5 * (values[n / 2 - 1] + values[n / 2])
    }
}

/// σ̂ of each channel: the median over the spans' selections.
fn channel_medians(selections: &[HarmonicSelection]) -> Vec<f64> {
    let channels = selections.first().map_or(0, |s| s.noise_std.len());
    (0..channels)
        .map(|j| median(selections.iter().map(|s| s.noise_std[j]).collect()))
        .collect()
}

impl RecordNoise {
    /// The harmonics and noise of `record` (module doc). (Not inlined:
    /// `benches/end_to_end/check_instructions.sh` counts it by name.)
    #[inline(never)]
    pub(crate) fn of(record: &Record) -> Result<Self> {
        let (spans, periods) = sampled_spans(record)?;
        let (step, period) = (record.step(), record.period());
        let motion: MatRef<'_, f64> = match record.measured_motion() {
            Some(m) => m.signals.as_ref(),
            None => record.displacements(),
        };
        let forces = record.forcing().signals.as_ref();
        let select = |signals: MatRef<'_, f64>| -> Result<Vec<HarmonicSelection>> {
            spans
                .par_iter()
                .map(|&(first, m)| {
                    select_harmonics(signals.subrows(first, m), step, period, periods)
                })
                .collect()
        };
        let moving = select(motion)?;
        // how many spans keep each order
        let mut votes = std::collections::BTreeMap::<usize, usize>::new();
        for selection in &moving {
            for &q in &selection.kept {
                *votes.entry(q).or_default() += 1;
            }
        }
        let needed = if moving.len() >= 3 {
            MIN_SPANS_ABOVE
        } else {
            1
        };
        let kept = votes
            .into_iter()
            .filter(|&(q, n)| q == 1 || n >= needed)
            .map(|(q, _)| q)
            .collect();
        let force_std = if forces.ncols() == 0 {
            Vec::new()
        } else {
            channel_medians(&select(forces)?)
        };
        Ok(RecordNoise {
            kept,
            motion_std: channel_medians(&moving),
            force_std,
            spans: spans.len(),
        })
    }

    /// The harmonic orders a window of `samples` samples fits: S, less the orders its
    /// basis cannot hold below Nyquist (K_max of `samples`), or 1..K when `harmonics`
    /// is `Some(K)`.
    pub(crate) fn orders_for(
        &self,
        samples: usize,
        step: f64,
        period: f64,
        harmonics: Option<usize>,
    ) -> Result<Vec<usize>> {
        match harmonics {
            Some(k) => super::first_orders(k, samples),
            None => {
                let most = super::noise_floor::most_harmonics(samples, step, period).max(1);
                Ok(self.kept.iter().copied().filter(|&q| q <= most).collect())
            }
        }
    }
}

/// The noise of each record of a list, estimated once and shared by every build that
/// reads the same records (variable projection's trials, the steady-state check and the
/// rows), keyed to the records' address as [`crate::regressor::DecayCache`] is.
#[derive(Debug, Default, Clone)]
pub(crate) struct RecordNoises {
    /// The records' address and count.
    source: (usize, usize),
    noises: Vec<Result<RecordNoise>>,
}

impl RecordNoises {
    /// The noise of every record of `records`, in parallel (a record too short for it
    /// keeps its error, returned if a window of it asks).
    pub(crate) fn of(records: &[Record]) -> Self {
        RecordNoises {
            source: (records.as_ptr() as usize, records.len()),
            noises: records.par_iter().map(RecordNoise::of).collect(),
        }
    }

    /// Whether these are the noises of `records`.
    pub(crate) fn are_of(&self, records: &[Record]) -> bool {
        self.source == (records.as_ptr() as usize, records.len())
    }

    /// `given` where it holds the noises of `records`, else those estimated here.
    pub(crate) fn given_or_of<'a>(
        given: Option<&'a RecordNoises>,
        records: &[Record],
    ) -> std::borrow::Cow<'a, RecordNoises> {
        match given.filter(|n| n.are_of(records)) {
            Some(noises) => std::borrow::Cow::Borrowed(noises),
            None => std::borrow::Cow::Owned(RecordNoises::of(records)),
        }
    }

    /// The noise of `records[index]`.
    pub(crate) fn get(&self, index: usize) -> Result<&RecordNoise> {
        self.noises[index].as_ref().map_err(Clone::clone)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::record::{Forcing, RecordParts};
    use faer::Mat;
    use rand::SeedableRng;
    use rand::rngs::StdRng;
    use rand_distr::{Distribution, Normal};

    /// Two channels of `periods` periods of N = 64 samples: harmonics 1 and 3 (1.0 and
    /// 0.2), white noise σ, and with `burst` = (first, last) periods a decaying
    /// oscillation at 2.5 ω (between harmonics) over those periods only.
    fn record(periods: usize, sigma: f64, burst: Option<(usize, usize)>, seed: u64) -> Record {
        let n = 64;
        let period = 2.0 * std::f64::consts::PI;
        let h = period / n as f64;
        let mut rng = StdRng::seed_from_u64(seed);
        let normal = Normal::new(0.0, sigma.max(f64::MIN_POSITIVE)).unwrap();
        let samples = periods * n + 1;
        let mut x = Mat::from_fn(samples, 2, |i, j| {
            let t = i as f64 * h;
            let a = 1.0 + j as f64;
            let mut value = a * (t + 0.3).cos() + 0.2 * a * (3.0 * t).sin();
            if let Some((first, last)) = burst
                && (first * n..last * n).contains(&i)
            {
                let since = (i - first * n) as f64 * h;
                value += 0.3 * (-0.05 * since).exp() * (2.5 * t).cos();
            }
            value
        });
        if sigma > 0.0 {
            for j in 0..2 {
                for i in 0..samples {
                    x[(i, j)] += normal.sample(&mut rng);
                }
            }
        }
        let force = Mat::from_fn(samples, 1, |i, _| (i as f64 * h).cos());
        Record::new(RecordParts {
            label: "two".into(),
            step: h,
            start_time: 0.0,
            displacements: x,
            velocities: None,
            forcing: Forcing::on_dofs(force, vec![1]),
            period,
        })
        .unwrap()
    }

    /// σ̂ is the noise of the record, within 10 % (a median of 16 span estimates of
    /// 42 noise bins each: ≈ 3 % standard error), and the harmonics kept are those the
    /// motion carries.
    #[test]
    fn a_records_noise_is_its_sensors_noise() {
        for (sigma, seed) in [(1e-3, 1u64), (1e-2, 2), (3e-2, 3)] {
            let noise = RecordNoise::of(&record(40, sigma, None, seed)).unwrap();
            assert_eq!(noise.spans, MAX_SPANS);
            assert_eq!(noise.kept, vec![1, 3], "σ {sigma}");
            for s in &noise.motion_std {
                assert!((s / sigma - 1.0).abs() < 0.1, "σ {sigma}: {s}");
            }
            assert_eq!(noise.force_std.len(), 1);
        }
    }

    /// A transient between the harmonics in one sampled span (its leakage reaches the
    /// harmonics 2 and 4 next to 2.5 ω) moves neither σ̂ (a median) nor S (a harmonic
    /// must stand above the noise in two spans).
    #[test]
    fn a_short_transient_moves_neither_the_noise_nor_the_harmonics() {
        let sigma = 1e-3;
        let quiet = RecordNoise::of(&record(40, sigma, None, 7)).unwrap();
        let burst = RecordNoise::of(&record(40, sigma, Some((0, 2)), 7)).unwrap();
        assert_eq!(burst.kept, quiet.kept);
        for (a, b) in burst.motion_std.iter().zip(&quiet.motion_std) {
            assert!((a / b - 1.0).abs() < 0.05, "{a} vs {b}");
        }
    }

    /// A harmonic that stands above the noise in a single sampled span is not kept; in
    /// two it is.
    #[test]
    fn a_harmonic_needs_two_spans() {
        let record = record(40, 1e-3, None, 5);
        let (spans, periods) = sampled_spans(&record).unwrap();
        assert_eq!((spans.len(), periods), (16, 2));
        // the spans are evenly spread: the first and the last of the record's 20
        assert_eq!(spans[0], (0, 128));
        assert_eq!(spans[15], (19 * 128, 128));
        let votes = |extra: &[usize]| {
            let mut x = record.displacements().to_owned();
            for &s in extra {
                let (first, m) = spans[s];
                for i in first..first + m {
                    x[(i, 0)] += 0.05 * (7.0 * i as f64 * record.step()).cos();
                }
            }
            let mut parts = record.parts().clone();
            parts.displacements = x;
            RecordNoise::of(&Record::new(parts).unwrap()).unwrap().kept
        };
        assert_eq!(votes(&[4]), vec![1, 3]);
        assert_eq!(votes(&[4, 9]), vec![1, 3, 7]);
    }

    /// A record of fewer than two periods gives one span of one period; one of no
    /// whole period is a typed error naming the record.
    #[test]
    fn short_records() {
        let record = record(1, 1e-3, None, 9);
        assert_eq!(sampled_spans(&record).unwrap(), (vec![(0, 64)], 1));
        assert!(RecordNoise::of(&record).is_ok());
        let mut parts = record.parts().clone();
        parts.displacements = parts.displacements.subrows(0, 40).to_owned();
        parts.forcing = Forcing::on_dofs(Mat::from_fn(40, 1, |i, _| i as f64), vec![1]);
        let short = Record::new(parts).unwrap();
        match RecordNoise::of(&short) {
            Err(Error::InvalidParameter { name, reason, .. }) => {
                assert_eq!(name, "samples per record");
                assert!(reason.contains("two"), "{reason}");
            }
            other => panic!("{other:?}"),
        }
    }
}
