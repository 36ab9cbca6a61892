//! The projections of every compared span of a check, each piece computed once:
//!
//! ```text
//!   record                               → harmonics S, σ̂_j        (step 1, `prep/fourier/record_noise.rs`)
//!   period (record, first, samples)      → c_x, c_v, Cov/σ̂², RSS_p, ½ ranges   (step 2)
//!   span (record, origin, k')            → non-harmonic RMS        (step 3, from its periods when T/h = N is whole)
//! ```
//!
//! A one-period window is compared with the next period and with the previous one, so
//! each period of a record takes part in two spans. Consecutive spans are projected
//! together, [`SPANS_PER_TASK`] to a task (the tasks in parallel), and within a task
//! each period is fitted once on its record's harmonics, and the periods with the same
//! number of samples share one basis, its factor and its covariances
//! (`projection::PeriodBasis`). With N whole, every period of a span is fitted and the
//! span's residual comes from their fits; otherwise the span is fitted whole for it.
//!
//! A span's projection is then its steps 1 and 3 with its first and last periods' fits
//! and σ̂_j² (`projection::assemble`): the same values as
//! [`projection::project_periods`] of the span, at any thread count.

use std::collections::HashMap;

use rayon::prelude::*;

use crate::error::Result;
use crate::prep::fourier::{RecordNoise, RecordNoises};
use crate::record::Record;

use super::projection::{self, PeriodBasis, PeriodFit, StateProjection};

/// Consecutive spans one task projects, sharing its periods' bases and fits: at task
/// boundaries one period in this many + 1 is fitted twice.
const SPANS_PER_TASK: usize = 64;

/// A compared span: (record, record index, origin in samples, periods k').
pub(super) type SpanKey<'a> = (&'a Record, usize, f64, usize);

/// The projection of each span of `spans` ((record, record index, origin, k')), its
/// first and last periods projected, on the noise of its record in `noises`; one
/// result per span, in order.
pub(super) fn project_spans(
    spans: &[SpanKey<'_>],
    noises: &RecordNoises,
) -> Result<Vec<Result<StateProjection>>> {
    let tasks = spans
        .par_chunks(SPANS_PER_TASK)
        .map(|task| project_task(task, noises))
        .collect::<Result<Vec<_>>>()?;
    Ok(tasks.into_iter().flatten().collect())
}

/// A period of one record: (record index, first sample, samples).
type PeriodKey = (usize, usize, usize);

/// The projections of the consecutive spans `task`: each basis (record, samples) and
/// each period's fit made once for the task. (Not inlined: `benches/end_to_end/
/// check_instructions.sh` counts the check by its entry points.)
#[inline(never)]
fn project_task(
    task: &[SpanKey<'_>],
    noises: &RecordNoises,
) -> Result<Vec<Result<StateProjection>>> {
    let mut bases: HashMap<(usize, usize), Result<PeriodBasis>> = HashMap::new();
    let mut fits: HashMap<PeriodKey, Result<PeriodFit>> = HashMap::new();
    task.iter()
        .map(|&(record, index, origin, count)| {
            crate::cancel::check("the steady-state check")?;
            let noise = match noises.get(index) {
                Ok(noise) => noise,
                Err(e) => return Ok(projection::assemble(record, &Err(e), &[])),
            };
            let whole = projection::from_periods(record, origin, count);
            // every period of a span whose residual comes from them, else its ends
            let fitted: Vec<usize> = if whole {
                (0..count).collect()
            } else {
                vec![0, count - 1]
            };
            let mut keys = Vec::with_capacity(fitted.len());
            for k in fitted {
                let (first, rows) = projection::period_samples(record, origin, k);
                let key = (index, first, rows);
                fits.entry(key).or_insert_with(|| {
                    let basis = bases
                        .entry((index, rows))
                        .or_insert_with(|| basis_of(record, noise, rows));
                    match basis {
                        Ok(basis) => projection::fit_period(record, basis, first),
                        Err(e) => Err(e.clone()),
                    }
                });
                keys.push(key);
            }
            let periods: Vec<&Result<PeriodFit>> =
                keys.iter().filter_map(|key| fits.get(key)).collect();
            let span = if whole {
                span_from(record, noise, &bases, &keys, &periods)
            } else {
                projection::fit_span(record, noise, origin, count)
            };
            let ends = [periods[0], periods[periods.len() - 1]];
            let projection = projection::assemble(record, &span, &ends);
            // The next span of the task starts at this one's last period at the
            // earliest: what lies before it is not read again (and if it were, it
            // would be made again, the same), so its memory is reused at once.
            let last = keys.last().map_or(0, |&(_, first, _)| first);
            fits.retain(|&(i, first, _), _| i == index && first >= last);
            Ok(projection)
        })
        .collect()
}

/// The basis of `record`'s periods of `rows` samples on its noise's harmonics.
fn basis_of(record: &Record, noise: &RecordNoise, rows: usize) -> Result<PeriodBasis> {
    projection::period_basis(
        record,
        noise,
        rows,
        &projection::period_orders(record, noise, rows)?,
    )
}

/// Step 3 of a span of whole periods from its periods' fits (`keys` and `periods` in
/// time order, all of `rows` samples): the first error of a period, else the span.
fn span_from(
    record: &Record,
    noise: &RecordNoise,
    bases: &HashMap<(usize, usize), Result<PeriodBasis>>,
    keys: &[PeriodKey],
    periods: &[&Result<PeriodFit>],
) -> Result<projection::SpanFit> {
    let (index, _, rows) = keys[0];
    let fits = periods
        .iter()
        .map(|fit| fit.as_ref().map_err(Clone::clone))
        .collect::<Result<Vec<_>>>()?;
    // cannot fail: the periods were fitted on this basis, which is kept for the task
    let basis = bases[&(index, rows)].as_ref().map_err(Clone::clone)?;
    Ok(projection::fit_span_from(record, noise, basis, &fits))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prep::quadrature::Quadrature;
    use crate::prep::steady_state::judge::compared_spans;
    use crate::prep::window::WindowSpec;
    use crate::reference::{four_mass_records_with, with_displacement_noise};
    use crate::simulate::SimSettings;

    /// Each span's projection with its periods fitted once and shared equals
    /// `project_periods` of the span alone, value for value, for one-period windows
    /// (each period in two spans) and three-period ones, with and without noise, with
    /// T/h not whole (spans fitted whole) and whole (spans read off their periods'
    /// spectra, each period's spectrum shared by the spans of a task).
    #[test]
    fn shared_period_fits_are_the_spans_own() {
        let period = 2.0 * std::f64::consts::PI / 0.618;
        for step in [0.1, period / 64.0] {
            let settings = SimSettings {
                step,
                transient_steps: (300.0 / step) as usize,
                recorded_steps: (40.0 * period / step).ceil() as usize + 4,
                ..SimSettings::default()
            };
            let clean = four_mass_records_with(false, &settings).unwrap();
            let noisy = with_displacement_noise(&clean, 0.01, 7).unwrap();
            let whole = projection::from_periods(&clean[0], 0.0, 2);
            assert_eq!(whole, step != 0.1, "h = {step}");
            shared_fits_for(&clean, &noisy);
        }
    }

    fn shared_fits_for(clean: &[Record], noisy: &[Record]) {
        for records in [clean, noisy] {
            for cycles in [1, 3] {
                let record = &records[0];
                let windows = WindowSpec::cycles(cycles)
                    .windows(record, 0, Quadrature::Trapezoid)
                    .unwrap();
                let mut spans: Vec<SpanKey<'_>> = Vec::new();
                for window in &windows {
                    for (origin, periods, _) in compared_spans(record, window).unwrap() {
                        if !spans.iter().any(|s| s.2 == origin && s.3 == periods) {
                            spans.push((record, 0, origin, periods));
                        }
                    }
                }
                assert!(spans.len() >= 2, "{} spans", spans.len());
                let noises = RecordNoises::of(records);
                let shared = project_spans(&spans, &noises).unwrap();
                for (&(_, _, origin, periods), projection) in spans.iter().zip(&shared) {
                    let alone =
                        projection::project_periods(record, origin, periods, &[0, periods - 1]);
                    assert_eq!(projection, &alone, "span at {origin}, {periods} periods");
                }
            }
        }
    }
}
