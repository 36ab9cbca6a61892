//! The projections of every compared span of a check, each piece computed once:
//!
//! ```text
//!   period (record, first)               → its spectrum, when T/h = N is whole   (steps 1, 2)
//!   span (record, origin, k')            → harmonics S, σ̂_j, non-harmonic RMS   (steps 1, 3)
//!   period (record, first, samples, S)   → c_x, c_v, Cov/σ̂², ½ ranges          (step 2)
//! ```
//!
//! A one-period window is compared with the next period and with the previous one, so
//! each period of a record takes part in two spans. Consecutive spans are projected
//! together, [`SPANS_PER_TASK`] to a task (the tasks in parallel), and within a task:
//!
//! - with N whole, each period is transformed once (`prep::fourier::periods`), and the
//!   spans' steps 1 and 3 and the periods' coefficients are read off the spectra;
//!   otherwise each span is fitted whole and each period by least squares;
//! - a period kept on the same harmonics by both its spans (the usual case) is fitted
//!   once (the fit depends on its samples and S alone, not on the span's noise), and
//!   the periods with the same number of samples and the same harmonics share one
//!   basis, its factor and its covariances (`projection::PeriodBasis`).
//!
//! A span's projection is then its steps 1 and 3 with its periods' fits and σ̂_j²
//! (`projection::assemble`): the same values bit for bit as
//! [`projection::project_periods`] of the span, at any thread count.
//!
//! Before noise-robust rows ([`FitRequests`]), the first span a one-period window
//! compares also makes the window's harmonic fit from its period's spectrum
//! (`prep/fourier/window_fit.rs`), so that the rows do not transform the period again.

use std::collections::HashMap;

use rayon::prelude::*;

use crate::error::Result;
use crate::prep::fourier::{PeriodSpectrum, WindowFit};
use crate::record::Record;

use super::projection::{self, PeriodBasis, PeriodFit, StateProjection};

/// Consecutive spans one task projects, sharing its periods' spectra, bases and fits:
/// at task boundaries one period in this many + 1 is transformed and fitted twice.
const SPANS_PER_TASK: usize = 16;

/// A compared span: (record, origin in samples, periods k').
pub(super) type SpanKey<'a> = (&'a Record, usize, f64, usize);

/// The one-period windows whose harmonic fit the check makes for the noise-robust
/// rows (`prep/fourier/window_fit.rs`), from the spectrum of their period.
pub(super) struct FitRequests {
    /// The harmonics the rows fit on (`None`: the noise floor's).
    pub(super) harmonics: Option<usize>,
    /// Per span, the windows it makes the fit of: (first sample, samples m).
    pub(super) per_span: Vec<Vec<(usize, usize)>>,
}

/// A window's fit, by (record index, first sample).
pub(super) type MadeFit = ((usize, usize), WindowFit);

/// The projection of each span of `spans` ((record, record index, origin, k')), its
/// first and last periods projected; one result per span, in order. With `requests`,
/// also the fits of the windows each span makes (on spans whose periods are
/// transformed; in span order).
pub(super) fn project_spans(
    spans: &[SpanKey<'_>],
    requests: Option<&FitRequests>,
) -> Result<(Vec<Result<StateProjection>>, Vec<MadeFit>)> {
    let tasks = spans
        .par_chunks(SPANS_PER_TASK)
        .enumerate()
        .map(|(t, task)| project_task(task, requests, t * SPANS_PER_TASK))
        .collect::<Result<Vec<_>>>()?;
    let mut projections = Vec::with_capacity(spans.len());
    let mut fits = Vec::new();
    for (p, f) in tasks {
        projections.extend(p);
        fits.extend(f);
    }
    Ok((projections, fits))
}

/// The periods of one record: (record index, first sample).
type PeriodKey = (usize, usize);

/// The projections of the consecutive spans `task`: each period's spectrum, each basis
/// (record, samples, S) and each period's fit on S made once for the task; with
/// `requests` (of every span; the task's first is span `offset`), the windows' fits.
fn project_task(
    task: &[SpanKey<'_>],
    requests: Option<&FitRequests>,
    offset: usize,
) -> Result<(Vec<Result<StateProjection>>, Vec<MadeFit>)> {
    let mut spectra: HashMap<PeriodKey, PeriodSpectrum> = HashMap::new();
    let mut bases: HashMap<(usize, usize, Vec<usize>), Result<PeriodBasis>> = HashMap::new();
    let mut fits: HashMap<(PeriodKey, usize, Vec<usize>), Result<PeriodFit>> = HashMap::new();
    let mut made = Vec::new();
    let projections = task
        .iter()
        .enumerate()
        .map(|(s, &(record, index, origin, count))| {
            crate::cancel::check("the steady-state check")?;
            let whole = projection::span_periods(record, origin, count);
            let span = match &whole {
                Some((firsts, n)) => {
                    for &first in firsts {
                        spectra
                            .entry((index, first))
                            .or_insert_with(|| projection::period_spectrum(record, first, *n));
                    }
                    if let Some(FitRequests {
                        harmonics,
                        per_span,
                    }) = requests
                    {
                        for &(first, m) in &per_span[offset + s] {
                            if let Some(spectrum) = spectra.get(&(index, first)) {
                                made.extend(
                                    projection::window_fit(record, spectrum, first, m, *harmonics)
                                        .map(|fit| ((index, first), fit)),
                                );
                            }
                        }
                    }
                    let own: Vec<&PeriodSpectrum> = firsts
                        .iter()
                        .filter_map(|&f| spectra.get(&(index, f)))
                        .collect();
                    projection::fit_span_from(record, &own)
                }
                None => projection::fit_span(record, origin, count),
            };
            let Ok(fit) = &span else {
                return Ok(projection::assemble(record, &span, &[]));
            };
            let mut keys = Vec::with_capacity(2);
            for k in [0, count - 1] {
                let (first, rows) = projection::period_samples(record, origin, k);
                let key = ((index, first), rows, fit.orders.clone());
                if !fits.contains_key(&key) {
                    let basis = bases
                        .entry((index, rows, fit.orders.clone()))
                        .or_insert_with(|| projection::period_basis(record, rows, &fit.orders));
                    // a period of N whole samples is read off its spectrum, as in
                    // `projection::fit_period`
                    let spectrum = projection::whole_period(record, rows).then(|| {
                        &*spectra
                            .entry((index, first))
                            .or_insert_with(|| projection::period_spectrum(record, first, rows))
                    });
                    let period = match (basis, spectrum) {
                        (Ok(basis), Some(spectrum)) => {
                            projection::fit_period_from(record, basis, first, spectrum)
                        }
                        (Ok(basis), None) => projection::fit_period_with(record, basis, first),
                        (Err(e), _) => Err(e.clone()),
                    };
                    fits.insert(key.clone(), period);
                }
                keys.push(key);
            }
            let periods: Vec<&Result<PeriodFit>> =
                keys.iter().filter_map(|key| fits.get(key)).collect();
            let projection = projection::assemble(record, &span, &periods);
            // The next span of the task starts at this one's last period at the
            // earliest: what lies before it is not read again (and if it were, it
            // would be made again, the same), so its memory is reused at once.
            let last = keys.last().map_or(0, |((_, first), ..)| *first);
            spectra.retain(|&(i, first), _| i == index && first >= last);
            fits.retain(|((i, first), ..), _| *i == index && *first >= last);
            Ok(projection)
        })
        .collect::<Result<Vec<_>>>()?;
    Ok((projections, made))
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
            let whole = projection::span_periods(&clean[0], 0.0, 2).is_some();
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
                let shared = project_spans(&spans, None).unwrap().0;
                for (&(_, _, origin, periods), projection) in spans.iter().zip(&shared) {
                    let alone =
                        projection::project_periods(record, origin, periods, &[0, periods - 1]);
                    assert_eq!(projection, &alone, "span at {origin}, {periods} periods");
                }
            }
        }
    }
}

#[cfg(test)]
mod window_fits {
    use crate::prep::fourier::{WholePeriods, WindowFit};
    use crate::prep::quadrature::Quadrature;
    use crate::prep::steady_state::{RowHarmonics, SteadyStateSettings, check, check_making_fits};
    use crate::prep::window::WindowSpec;
    use crate::reference::{four_mass_records_with, with_displacement_noise};
    use crate::simulate::SimSettings;

    /// The check made with the rows' fits gives the same report, and a fit for every
    /// one-period window (every rule, with and without the closing sample, a window
    /// that closes periodically among them) that is the window's own, bit for bit, on
    /// the harmonics the rows ask for. Windows of several periods get none (their
    /// spans' periods are not their windows).
    #[test]
    fn the_check_makes_every_one_period_windows_own_fit() {
        let period = 2.0 * std::f64::consts::PI / 0.618;
        let step = period / 64.0;
        let settings = SimSettings {
            step,
            transient_steps: (300.0 / step) as usize,
            recorded_steps: 20 * 64,
            ..SimSettings::default()
        };
        let clean = four_mass_records_with(false, &settings).unwrap();
        let noisy = with_displacement_noise(&clean, 0.01, 7).unwrap();
        let thresholds = SteadyStateSettings::default();
        let mut closed = 0;
        for quadrature in [
            Quadrature::Trapezoid,
            Quadrature::Rectangular,
            Quadrature::Spectral,
        ] {
            for harmonics in [None, Some(3)] {
                let rows = Some(RowHarmonics(harmonics));
                let spec = WindowSpec::cycles(1);
                let (report, fits) =
                    check_making_fits(&noisy, &spec, quadrature, None, &thresholds, rows).unwrap();
                let alone = check(&noisy, &spec, quadrature, None, &thresholds).unwrap();
                assert_eq!(report, alone);
                let fits = fits.expect("fits asked for");
                let mut windows = 0;
                for (index, record) in noisy.iter().enumerate() {
                    for w in spec.windows(record, index, quadrature).unwrap() {
                        let (h, t) = (record.step(), record.period());
                        let count = w.weights(quadrature, h, t).unwrap().len();
                        let available = record.samples() - w.start;
                        let whole = WholePeriods::of_window(count, available, h, t).unwrap();
                        let x = record.displacements().subrows(w.start, whole.samples);
                        let own = WindowFit::new(x, h, t, whole, harmonics).unwrap();
                        let made = fits.get(&noisy, index, w.start).expect("a fit per window");
                        assert!(made.is_of(whole, harmonics));
                        assert_eq!(made, &own, "{quadrature:?}, record {index}, {w:?}");
                        windows += 1;
                        closed += usize::from(w.closed);
                    }
                }
                assert_eq!(fits.len(), windows);
            }
            let spec = WindowSpec::cycles(3);
            let (_, fits) = check_making_fits(
                &noisy,
                &spec,
                quadrature,
                None,
                &thresholds,
                Some(RowHarmonics(None)),
            )
            .unwrap();
            assert_eq!(fits.map(|f| f.len()), Some(0));
        }
        assert!(closed > 0, "a window that closes periodically");
    }
}
