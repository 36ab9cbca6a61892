//! The projections of every compared span of a check, each piece computed once:
//!
//! ```text
//!   span (record, origin, k')            → harmonics S, σ̂_j, non-harmonic RMS   (steps 1, 3)
//!   period (record, first, samples, S)   → c_x, c_v, Cov/σ̂², ½ ranges          (step 2)
//! ```
//!
//! A one-period window is compared with the next period and with the previous one, so
//! each period of a record takes part in two spans; both usually keep the same
//! harmonics, and then its fit (which depends on its samples and S alone, not on the
//! span's noise) is done once and shared. A span's projection is then its steps 1 and 3
//! with its periods' fits and σ̂_j² (`projection::assemble`): the same values bit for
//! bit as [`projection::project_periods`] of the span. The periods of a record with the
//! same number of samples and the same harmonics share one basis, its factor and its
//! covariances (`projection::PeriodBasis`).

use std::collections::HashMap;

use rayon::prelude::*;

use crate::error::Result;
use crate::record::Record;

use super::projection::{self, StateProjection};

/// A compared span: (record, origin in samples, periods k').
pub(super) type SpanKey<'a> = (&'a Record, usize, f64, usize);

/// The projection of each span of `spans` ((record, record index, origin, k')), its
/// first and last periods projected; one result per span, in order.
pub(super) fn project_spans(spans: &[SpanKey<'_>]) -> Result<Vec<Result<StateProjection>>> {
    let fits = spans
        .par_iter()
        .map(|&(record, _, origin, periods)| {
            crate::cancel::check("the steady-state check")?;
            Ok(projection::fit_span(record, origin, periods))
        })
        .collect::<Result<Vec<_>>>()?;
    // The distinct (record, first sample, samples, S) of the periods the spans project.
    let mut known = HashMap::new();
    let mut periods: Vec<(&Record, usize, usize, usize, &[usize])> = Vec::new();
    let ids: Vec<Vec<usize>> = spans
        .iter()
        .zip(&fits)
        .map(|(&(record, index, origin, count), fit)| {
            let Ok(fit) = fit else { return Vec::new() };
            [0, count - 1]
                .iter()
                .map(|&k| {
                    let (first, rows) = projection::period_samples(record, origin, k);
                    *known
                        .entry((index, first, rows, fit.orders.as_slice()))
                        .or_insert_with(|| {
                            periods.push((record, index, first, rows, fit.orders.as_slice()));
                            periods.len() - 1
                        })
                })
                .collect()
        })
        .collect();
    // Periods of one record with the same samples and harmonics share their basis, its
    // factor and its covariances (t is measured from each period's first sample).
    let mut bases = HashMap::new();
    let mut distinct: Vec<(&Record, usize, &[usize])> = Vec::new();
    let basis_ids: Vec<usize> = periods
        .iter()
        .map(|&(record, index, _, rows, orders)| {
            *bases.entry((index, rows, orders)).or_insert_with(|| {
                distinct.push((record, rows, orders));
                distinct.len() - 1
            })
        })
        .collect();
    let shared: Vec<Result<projection::PeriodBasis>> = distinct
        .par_iter()
        .map(|&(record, rows, orders)| projection::period_basis(record, rows, orders))
        .collect();
    let period_fits = periods
        .par_iter()
        .zip(&basis_ids)
        .map(|(&(record, _, first, _, _), &id)| {
            crate::cancel::check("the steady-state check")?;
            Ok(match &shared[id] {
                Ok(basis) => projection::fit_period_with(record, basis, first),
                Err(e) => Err(e.clone()),
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(spans
        .par_iter()
        .zip(&fits)
        .zip(&ids)
        .map(|((&(record, ..), fit), ids)| {
            let fits: Vec<_> = ids.iter().map(|&i| &period_fits[i]).collect();
            projection::assemble(record, fit, &fits)
        })
        .collect())
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
    /// (each period in two spans; T/h not whole) and three-period ones, with and
    /// without noise.
    #[test]
    fn shared_period_fits_are_the_spans_own() {
        let period = 2.0 * std::f64::consts::PI / 0.618;
        let settings = SimSettings {
            transient_steps: 3000,
            recorded_steps: (6.0 * period / 0.1).ceil() as usize + 4,
            ..SimSettings::default()
        };
        let clean = four_mass_records_with(false, &settings).unwrap();
        let noisy = with_displacement_noise(&clean, 0.01, 7).unwrap();
        for records in [&clean, &noisy] {
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
                let shared = project_spans(&spans).unwrap();
                for (&(_, _, origin, periods), projection) in spans.iter().zip(&shared) {
                    let alone =
                        projection::project_periods(record, origin, periods, &[0, periods - 1]);
                    assert_eq!(projection, &alone, "span at {origin}, {periods} periods");
                }
            }
        }
    }
}
