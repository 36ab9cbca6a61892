//! A window's harmonic fit, the first half of its projection
//! (`regressor/robust/projected.rs`): the harmonic orders S that stand above the
//! window's noise floor (`noise_floor.rs`), or S = 1..K when K is given, each channel's
//! noise σ̂, and, when the window holds a whole number of samples per period, the
//! least-squares coefficients on S read off its spectrum (`dft.rs`):
//!
//! ```text
//!   c = (BᵀB)⁻¹ Bᵀ x,   a_0 = Re X_0 / L + x_0,   a_k = 2 Re X_kP / L,   b_k = −2 Im X_kP / L,
//! ```
//!
//! with the Sherman–Morrison correction when the fit also reads the closing sample
//! (m = L + 1). Elsewhere the caller fits by least squares on its own basis.
//!
//! **Made once.** A window of one period is also a period of the steady-state check,
//! which transforms every period of a record once (`periods.rs`). The check reads the
//! window's spectrum off that transform ([`WindowFit::from_period`]) and hands its fits
//! to the rows ([`WindowFits`]), so that the default pipeline transforms each such
//! period once instead of twice. Both ways give the same bits: the same real FFT of the
//! same N samples less the same x_0, then the same selection and the same fit.
//!
//! Memory: a fit holds (2|S| + 2) numbers per channel, against the N samples of the
//! window's period it replaces a second transform of.

use std::collections::HashMap;

use faer::{Mat, MatRef};

use super::noise_floor::{most_harmonics, select_with};
use super::{PeriodSpectrum, WholePeriods, WholeSampleDft, first_orders, select_with_spectrum};
use crate::error::Result;

/// The harmonics and noise of a window and, where its spectrum gives them, its
/// coefficients (module doc).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct WindowFit {
    /// Whole periods P and samples m fitted.
    whole: WholePeriods,
    /// The harmonics asked for: `Some(K)` for 1..K, `None` for the noise floor's.
    harmonics: Option<usize>,
    /// Harmonic orders S, ascending.
    pub(crate) kept: Vec<usize>,
    /// Per channel, the noise standard deviation per sample σ̂.
    pub(crate) noise_std: Vec<f64>,
    /// c = [a_0, a_k, b_k, …] per channel ((2|S| + 1) × n), read off the window's
    /// spectrum; `None` where the caller fits by least squares.
    pub(crate) coefficients: Option<Mat<f64>>,
}

impl WindowFit {
    /// The fit of `x` (m × n samples of `whole.periods` whole periods), transforming it
    /// where it holds a whole number of samples per period.
    pub(crate) fn new(
        x: MatRef<'_, f64>,
        step: f64,
        period: f64,
        whole: WholePeriods,
        harmonics: Option<usize>,
    ) -> Result<Self> {
        let (selection, spectrum) =
            select_with_spectrum(x, step, period, whole.periods, harmonics.unwrap_or(0))?;
        Self::finish(
            selection.kept,
            selection.noise_std,
            spectrum,
            whole,
            harmonics,
        )
    }

    /// [`WindowFit::new`] of the window of one period that starts at `spectrum`'s first
    /// sample (`x` its m = N or N + 1 samples), read off that spectrum: the same bits.
    /// `None` where the window's own spectrum is not this one's (T/h not whole, bins
    /// above those kept) or the fit fails; [`WindowFit::new`] then decides.
    pub(crate) fn from_period(
        spectrum: &PeriodSpectrum,
        x: MatRef<'_, f64>,
        step: f64,
        period: f64,
        harmonics: Option<usize>,
    ) -> Option<Self> {
        let m = x.nrows();
        // the bins `select_with_spectrum` keeps: K_max of the window, or the K asked
        let highest = most_harmonics(m, step, period).max(harmonics.unwrap_or(0));
        let dft = spectrum.one_period_window(x, step, period, highest)?;
        let selection = select_with(x, step, period, 1, Some(&dft)).ok()?;
        let whole = WholePeriods {
            periods: 1,
            samples: m,
        };
        Self::finish(
            selection.kept,
            selection.noise_std,
            Some(dft),
            whole,
            harmonics,
        )
        .ok()
    }

    /// Whether this is the fit of a window over `whole` with `harmonics` (of a window
    /// that starts at its first sample).
    pub(crate) fn is_of(&self, whole: WholePeriods, harmonics: Option<usize>) -> bool {
        self.whole == whole && self.harmonics == harmonics
    }

    /// S (the noise floor's, or 1..K) and the coefficients on it from `spectrum`.
    fn finish(
        mut kept: Vec<usize>,
        noise_std: Vec<f64>,
        spectrum: Option<WholeSampleDft>,
        whole: WholePeriods,
        harmonics: Option<usize>,
    ) -> Result<Self> {
        if let Some(k) = harmonics {
            kept = first_orders(k, whole.samples)?;
        }
        let coefficients = spectrum.filter(|s| s.covers(&kept)).map(|s| s.fit(&kept));
        Ok(WindowFit {
            whole,
            harmonics,
            kept,
            noise_std,
            coefficients,
        })
    }
}

/// The fits the steady-state check made of the one-period windows of a list of
/// records, by (record index, first sample), for the harmonics the rows ask for.
#[derive(Default)]
pub(crate) struct WindowFits {
    /// The records' address and count, to tell whether a build reads the same ones.
    source: (usize, usize),
    fits: HashMap<(usize, usize), WindowFit>,
}

impl std::fmt::Debug for WindowFits {
    /// How many, not the fits themselves (a record's worth of coefficients).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "WindowFits({} windows)", self.fits.len())
    }
}

impl WindowFits {
    /// The fits of windows of `records` (address and count), each by (record index,
    /// first sample); of two fits of one window the first is kept (they are equal).
    pub(crate) fn new(
        records: &[crate::record::Record],
        fits: impl IntoIterator<Item = ((usize, usize), WindowFit)>,
    ) -> Self {
        let mut map = HashMap::new();
        for (key, fit) in fits {
            map.entry(key).or_insert(fit);
        }
        WindowFits {
            source: (records.as_ptr() as usize, records.len()),
            fits: map,
        }
    }

    /// The fit made of the window of `records[record]` from sample `start`, if any
    /// (and if these are the records it was made of); the caller checks that it is of
    /// its window's samples ([`WindowFit::is_of`]).
    pub(crate) fn get(
        &self,
        records: &[crate::record::Record],
        record: usize,
        start: usize,
    ) -> Option<&WindowFit> {
        if self.source != (records.as_ptr() as usize, records.len()) {
            return None;
        }
        self.fits.get(&(record, start))
    }

    /// How many windows have a fit.
    #[cfg(test)]
    pub(crate) fn len(&self) -> usize {
        self.fits.len()
    }
}

#[cfg(test)]
mod tests {
    use super::super::periods::tests::signal;
    use super::super::span_harmonics;
    use super::*;

    /// A one-period window's fit read off its period's spectrum (the one the
    /// steady-state check makes, with the bins a span of two periods reads) is the
    /// window's own fit bit for bit: with and without the closing sample, even and odd
    /// N, with and without noise, on the noise floor's harmonics and on 1..K. Where the
    /// window's own spectrum is not that one (T/h not whole, K above the bins kept) it
    /// gives none, and the window fits itself.
    #[test]
    fn a_windows_fit_off_its_periods_spectrum_is_its_own() {
        for per_period in [64usize, 101, 400] {
            for noise in [0.0, 1e-3] {
                // two periods, of which the window reads one and the closing sample
                let (x, step, period) = signal(per_period, 2, 4, noise, 0.0, 3);
                let kept = span_harmonics(per_period, step, period);
                let spectrum = PeriodSpectrum::new(x.as_ref().subrows(0, per_period), kept);
                for m in [per_period, per_period + 1] {
                    let window = x.as_ref().subrows(0, m);
                    let whole = WholePeriods {
                        periods: 1,
                        samples: m,
                    };
                    for harmonics in [None, Some(1), Some(7), Some(kept)] {
                        let read =
                            WindowFit::from_period(&spectrum, window, step, period, harmonics)
                                .expect("the period's bins cover the window's");
                        let own = WindowFit::new(window, step, period, whole, harmonics).unwrap();
                        assert!(own.coefficients.is_some(), "N {per_period}: the FFT path");
                        assert_eq!(read, own, "N {per_period}, m {m}, σ {noise}, {harmonics:?}");
                        assert!(read.is_of(whole, harmonics));
                        assert!(!read.is_of(whole, harmonics.map_or(Some(2), |_| None)));
                    }
                    if noise > 0.0 && per_period == 400 {
                        let own = WindowFit::new(window, step, period, whole, None).unwrap();
                        assert_eq!(own.kept, vec![1, 2, 3, 5], "the noise floor's harmonics");
                    }
                    let above = Some(kept + 1);
                    assert!(
                        WindowFit::from_period(&spectrum, window, step, period, above).is_none()
                    );
                }
                // T/h not whole: the window's own fit is by least squares
                let off = period * (1.0 + 1e-6);
                let window = x.as_ref().subrows(0, per_period);
                assert!(WindowFit::from_period(&spectrum, window, step, off, None).is_none());
            }
        }
    }

    /// A set of fits answers for the records it was made of, by record and first
    /// sample, and for no other list of records.
    #[test]
    fn fits_answer_for_their_own_records_only() {
        let (x, step, period) = signal(64, 2, 4, 1e-3, 0.0, 9);
        let x = x.subrows(0, 65);
        let whole = WholePeriods {
            periods: 1,
            samples: 65,
        };
        let fit = WindowFit::new(x, step, period, whole, None).unwrap();
        let records = crate::reference::four_mass_records(false, 3).unwrap();
        let fits = WindowFits::new(&records, [((1, 130), fit.clone()), ((1, 130), fit)]);
        assert_eq!(fits.len(), 1);
        assert!(fits.get(&records, 1, 130).is_some());
        assert!(fits.get(&records, 0, 130).is_none());
        assert!(fits.get(&records, 1, 131).is_none());
        let copy = records.clone();
        assert!(fits.get(&copy, 1, 130).is_none());
        assert!(fits.get(&records[..1], 1, 130).is_none());
    }
}
