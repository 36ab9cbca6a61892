//! A span's harmonics, noise floor and residual read off the spectra of its periods, so
//! that each period of a record is transformed once however many spans hold it (the
//! steady-state check compares every one-period window with the next period and with
//! the previous one: each period is in two spans).
//!
//! Over a span of P whole periods of N = T/h samples (a whole number, `dft.rs`), m = PN,
//! let Y_j (j < m) be the span's DFT and X_i[k] (k < N) that of its period i. Harmonic
//! k of ω is bin kP of the span and bin k of a period, and
//!
//! ```text
//!   Y_{kP} = Σ_i X_i[k],
//! ```
//!
//! so the span's least-squares coefficients on the harmonics read off the sums
//! (`dft.rs`: a_k = 2 Re Y_{kP}/m, b_k = −2 Im Y_{kP}/m). What lies between the
//! harmonics is what differs from period to period. The Helmert contrasts
//!
//! ```text
//!   H_c[k] = √(P / (c (c + 1))) (Σ_{i<c} X_i[k] − c X_c[k]),   c = 1 … P − 1,
//! ```
//!
//! are √P times an orthonormal transform of (X_0[k], …, X_{P−1}[k]) whose remaining
//! row, (1, …, 1)/√P, gives Y_{kP}/√P; so Σ_c |H_c[k]|² + |Y_{kP}|² = P Σ_i |X_i[k]|²,
//! and Parseval over the span and over each period (Σ_j |Y_j|² = m Σ x²,
//! Σ_k |X_i[k]|² = N Σ x_i²) gives
//!
//! ```text
//!   Σ_{j ≢ 0 (mod P)} |Y_j|² = Σ_{k<N} Σ_c |H_c[k]|²:
//! ```
//!
//! the contrasts carry exactly the power of the bins between the harmonics.
//!
//! **Noise floor.** White noise of variance σ² makes the X_i[k] (0 < k < N/2)
//! independent, with E|X_i[k]|² = Nσ²; the orthogonal contrasts are then independent with
//! E|H_c[k]|² = PNσ² = mσ², the variance of any bin of the span's DFT. So the powers
//! (2/m)² |H_c[k]|², k = 1 … K_max, are distributed as the residual bins between the
//! harmonics that the rule of `noise_floor.rs` reads (exponential, mean 4σ²/m, for
//! Gaussian noise), there are as many ((P − 1) K_max, strided alike to at most
//! [`MAX_NOISE_BINS`]), and periodic content cancels from them exactly, as it does from
//! the residual. [`select_from_periods`] reads them in place of the bins between the
//! harmonics; the rest of the rule is `noise_floor.rs`'s ([`select_from`]). A
//! transient reaches both sets of bins, but not at the same frequencies (the bins
//! between the harmonics sample the contrasts' spectrum half a bin off), so on a record
//! with a transient the two σ̂ differ by how each samples it; on noise they agree in
//! distribution, not bit for bit.
//!
//! **Residual.** The fit on orders S ⊆ 1 … K (K = K_max < N/2) leaves, by Parseval over
//! the half spectrum (weights w_k = 1 at k = 0 and at k = N/2, else 2),
//!
//! ```text
//!   m RSS_S = Σ_{k≤K} w_k Σ_c |H_c[k]|² + P Σ_i Σ_{K<k≤N/2} w_k |X_i[k]|² + Σ_{k≤K, k∉S} 2 |Y_{kP}|²,
//! ```
//!
//! every term a sum of squares, with no cancellation between large ones (above K every
//! bin is residual, so its contrasts and its sum together are P Σ_i |X_i[k]|²). Each
//! period is transformed relative to its first sample x_{i,0}, so that a large offset
//! costs no accuracy; only bin 0 depends on that reference, and the contrasts there take
//! X_i[0] + N (x_{i,0} − x_{0,0}).

use faer::MatRef;
use realfft::num_complex::Complex;

use super::dft::{RelativeFft, WholeSampleDft, transform_length};
use super::noise_floor::{MAX_NOISE_BINS, Selector, most_harmonics};
use super::{HarmonicSelection, first_orders};
use crate::error::{Error, Result};
use crate::record::col;
use crate::terms::simd::{self, Kernel};

/// One period's spectrum, per channel: the bins X[k], k = 0 … K, of x − x_0 and the power
/// of the half spectrum above K.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PeriodSpectrum {
    /// N, the period's samples.
    length: usize,
    /// K, the highest bin kept.
    highest: usize,
    /// x_0 per channel.
    first: Vec<f64>,
    /// Per channel, X[k] for k = 0 … K.
    bins: Vec<Vec<Complex<f64>>>,
    /// Per channel, Σ_{K<k≤N/2} w_k |X[k]|².
    above: Vec<f64>,
}

/// K_max of a span of at least two periods of `length` samples ([`most_harmonics`] of
/// it, the same for any count of periods ≥ 2): the bins a [`PeriodSpectrum`] keeps.
pub(crate) fn span_harmonics(length: usize, step: f64, period: f64) -> usize {
    most_harmonics(2 * length, step, period)
}

impl PeriodSpectrum {
    /// The spectrum of every column of `x` (N × n, one period) with bins 0 … `highest`
    /// kept (2 `highest` < N).
    pub(crate) fn new(x: MatRef<'_, f64>, highest: usize) -> Self {
        let (length, n) = x.shape();
        debug_assert!(2 * highest < length);
        let mut fft = RelativeFft::new(length);
        let mut first = Vec::with_capacity(n);
        let mut bins = Vec::with_capacity(n);
        let mut above = Vec::with_capacity(n);
        for c in 0..n {
            let (x0, output) = fft.transform(col(x, c));
            first.push(x0);
            bins.push(output[..=highest].to_vec());
            above.push(half_spectrum_power(&output[highest + 1..], length));
        }
        PeriodSpectrum {
            length,
            highest,
            first,
            bins,
            above,
        }
    }

    /// The spectrum of the window of one period that starts at this period's first
    /// sample, `x` its m = N or N + 1 samples (the closing one at t_0 + T), with the bins
    /// of harmonics 0 … `highest` that [`WholeSampleDft::new`]`(x, step, period, 1,
    /// highest, &[])` keeps: its transform is this one (the same N samples less the same
    /// x_0, the same plan), so its bins are these, bit for bit. `None` where that is
    /// `None` (the window fitted by least squares) or `highest` is above the bins kept.
    pub(crate) fn one_period_window(
        &self,
        x: MatRef<'_, f64>,
        step: f64,
        period: f64,
        highest: usize,
    ) -> Option<WholeSampleDft> {
        let length = transform_length(x.nrows(), step, period, 1, highest, &[])?;
        if length != self.length || highest > self.highest || x.ncols() != self.first.len() {
            return None;
        }
        debug_assert!((0..x.ncols()).all(|c| x[(0, c)].to_bits() == self.first[c].to_bits()));
        let closing = (x.nrows() == length + 1).then(|| {
            (0..x.ncols())
                .map(|c| x[(length, c)] - self.first[c])
                .collect()
        });
        let mut harmonics = Vec::with_capacity(self.bins.len() * (highest + 1));
        for bins in &self.bins {
            harmonics.extend_from_slice(&bins[..=highest]);
        }
        Some(WholeSampleDft::of_one_period(
            length,
            highest,
            self.first.clone(),
            closing,
            harmonics,
        ))
    }

    /// X[0 … K] of channel `c`, of x − x_0.
    fn channel(&self, c: usize) -> &[Complex<f64>] {
        &self.bins[c]
    }

    /// X[0] of channel `c` relative to `reference`: Σ (x − reference).
    fn mean_bin(&self, c: usize, reference: f64) -> Complex<f64> {
        self.bins[c][0] + self.length as f64 * (self.first[c] - reference)
    }

    /// The least-squares coefficients [a₀, a_k, b_k, …] of channel `c` over the period
    /// on `orders` (ascending, distinct, each ≥ 1), read off the bins (`dft.rs`:
    /// a₀ = X[0]/N + x₀, a_k = 2 Re X[k]/N, b_k = −2 Im X[k]/N), or `None` when an order
    /// is above the bins kept.
    pub(crate) fn coefficients(&self, c: usize, orders: &[usize]) -> Option<Vec<f64>> {
        if orders.last().is_some_and(|&k| k > self.highest) {
            return None;
        }
        let bins = self.channel(c);
        let n = self.length as f64;
        let mut coefficients = Vec::with_capacity(2 * orders.len() + 1);
        coefficients.push(bins[0].re / n + self.first[c]);
        for &k in orders {
            coefficients.push(2.0 * bins[k].re / n);
            coefficients.push(-2.0 * bins[k].im / n);
        }
        Some(coefficients)
    }
}

/// Σ w_k |X[k]|² over the tail `bins` of a half spectrum of `length` samples (the last
/// bin is N/2, of weight 1, when N is even; every other weight is 2).
fn half_spectrum_power(bins: &[Complex<f64>], length: usize) -> f64 {
    let (body, nyquist) = match bins.split_last() {
        Some((last, body)) if length.is_multiple_of(2) => (body, last.norm_sqr()),
        _ => (bins, 0.0),
    };
    2.0 * body.iter().map(|b| b.norm_sqr()).sum::<f64>() + nyquist
}

/// The contrast bins (k, c) the noise floor reads are k = 1 … K, c = 1 … P − 1 in that
/// order, every `stride`-th of them, at most [`MAX_NOISE_BINS`]: as many as the bins
/// between the harmonics ([`super::noise_floor::between_bins`]). Returns (stride, count).
fn contrast_stride(periods: usize, most: usize) -> (usize, usize) {
    let all = most * periods.saturating_sub(1);
    let stride = all.div_ceil(MAX_NOISE_BINS).max(1);
    (stride, all.div_ceil(stride))
}

/// A span read off its periods' spectra: what its residual on any kept harmonics needs.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct SpanSpectrum {
    /// m = PN.
    samples: usize,
    /// Per channel, |Y_{kP}|² for k = 1 … K (at k − 1).
    harmonic_power: Vec<Vec<f64>>,
    /// Per channel, the residual power of every bin but the harmonics 1 … K (module doc).
    non_harmonic: Vec<f64>,
}

impl SpanSpectrum {
    /// RSS_S of channel `channel` for the fit on `orders` (ascending, each at most K;
    /// the constant always fitted), by Parseval (module doc).
    pub(crate) fn residual_sum_of_squares(&self, orders: &[usize], channel: usize) -> f64 {
        // the harmonics 1..=K not in `orders` (both ascending: one merge)
        let mut kept = orders.iter().copied().peekable();
        let mut sum = 0.0;
        for (k, power) in (1..).zip(&self.harmonic_power[channel]) {
            if kept.next_if_eq(&k).is_none() {
                sum += power;
            }
        }
        (self.non_harmonic[channel] + 2.0 * sum) / self.samples as f64
    }
}

/// The harmonics that stand above the noise floor of the span made of the periods
/// `spectra` (in time order, each of N = T/h samples, keeping the bins up to
/// [`span_harmonics`]), by the rule of `noise_floor.rs` with the contrast bins in place
/// of the bins between the harmonics (module doc), and the span's spectrum for its
/// residual.
pub(crate) fn select_from_periods(
    spectra: &[&PeriodSpectrum],
    step: f64,
    period: f64,
) -> Result<(HarmonicSelection, SpanSpectrum)> {
    let periods = spectra.len();
    let Some(head) = spectra.first() else {
        return Err(Error::invalid("periods", 0.0, "a span needs at least one"));
    };
    let (length, n) = (head.length, head.first.len());
    let m = periods * length;
    let most = most_harmonics(m, step, period);
    // the checks of the least-squares rule: overdetermined, below Nyquist
    first_orders(most, m)?;
    if spectra
        .iter()
        .any(|s| s.length != length || s.highest < most || s.first.len() != n)
    {
        return Err(Error::Numerical {
            stage: "noise floor".into(),
            detail: format!(
                "the periods of a span must have {length} samples and {n} channels with bins up to {most}"
            ),
        });
    }
    let (stride, count) = contrast_stride(periods, most);
    let scale = 2.0 / m as f64;
    // √(P / (c (c + 1))) for c = 1 … P − 1
    let weights: Vec<f64> = (1..periods)
        .map(|c| (periods as f64 / (c * (c + 1)) as f64).sqrt())
        .collect();
    let mut selector = Selector::new(m, periods, most, n);
    let mut harmonic_power = Vec::with_capacity(n);
    let mut non_harmonic = Vec::with_capacity(n);
    // one channel at a time: its coefficients, noise bins and rows of bins
    let mut coefficients = vec![0.0; 2 * most + 1];
    let mut noise = vec![0.0; count];
    let mut rows: Vec<&[Complex<f64>]> = Vec::with_capacity(periods);
    for channel in 0..n {
        rows.clear();
        rows.extend(spectra.iter().map(|s| s.channel(channel)));
        let reference = head.first[channel];
        // bin 0: the periods' means against one reference (contrasts of weight 1)
        let mut prefix = head.mean_bin(channel, reference);
        let mut power = 0.0;
        for (c, (spectrum, weight)) in (1..).zip(spectra[1..].iter().zip(&weights)) {
            let x = spectrum.mean_bin(channel, reference);
            power += ((prefix - x * c as f64) * *weight).norm_sqr();
            prefix += x;
        }
        coefficients[0] = prefix.re / m as f64 + reference;
        // bins 1 … K (contrasts of weight 2), every `stride`-th contrast a noise bin
        let mut powers = Vec::with_capacity(most);
        let bins = BinsOut {
            coefficients: &mut coefficients[1..],
            noise: &mut noise,
            powers: &mut powers,
        };
        let between = harmonic_bins(&rows, &weights, most, stride, scale, bins);
        selector.channel(&coefficients, (periods >= 2).then_some(noise.as_slice()));
        let above: f64 = spectra.iter().map(|s| s.above[channel]).sum();
        non_harmonic.push(power + 2.0 * between + periods as f64 * above);
        harmonic_power.push(powers);
    }
    Ok((
        selector.finish(),
        SpanSpectrum {
            samples: m,
            harmonic_power,
            non_harmonic,
        },
    ))
}

/// Where [`harmonic_bins`] writes one channel's bins 1 … K.
struct BinsOut<'a> {
    /// a_k, b_k of the sums for k = 1 … K (2K values).
    coefficients: &'a mut [f64],
    /// The noise bins' powers (2/m)² |H_c[k]|².
    noise: &'a mut [f64],
    /// |Y_{kP}|², pushed for k = 1 … K.
    powers: &'a mut Vec<f64>,
}

/// One channel's bins 1 … K from its periods' `rows` of bins: the sums' coefficients
/// (scaled by `scale` = 2/m) and powers, every `stride`-th contrast's power as a noise
/// bin, and Σ_k Σ_c |H_c[k]|², returned. Two periods (every contrast a noise bin, the
/// usual check) take a loop of their own, with the same operations.
fn harmonic_bins(
    rows: &[&[Complex<f64>]],
    weights: &[f64],
    most: usize,
    stride: usize,
    scale: f64,
    out: BinsOut<'_>,
) -> f64 {
    if let ([first, second], 1) = (rows, stride) {
        return simd::dispatch(TwoPeriods {
            first: &first[1..=most],
            second: &second[1..=most],
            scale,
            out,
        });
    }
    let mut between = 0.0;
    let pairs = out.coefficients.chunks_exact_mut(2);
    let (mut until, mut next) = (0, 0);
    for (k, pair) in (1..=most).zip(pairs) {
        let mut prefix = rows[0][k];
        for (c, (row, weight)) in (1..).zip(rows[1..].iter().zip(weights)) {
            let x = row[k];
            let h2 = ((prefix - x * c as f64) * *weight).norm_sqr();
            between += h2;
            if until == 0 {
                out.noise[next] = scale * scale * h2;
                (until, next) = (stride - 1, next + 1);
            } else {
                until -= 1;
            }
            prefix += x;
        }
        out.powers.push(prefix.norm_sqr());
        pair[0] = scale * prefix.re;
        pair[1] = -scale * prefix.im;
    }
    between
}

/// [`harmonic_bins`] of two periods (every contrast a noise bin, the usual check):
/// H_1[k] = X_0[k] − X_1[k] (the weight √(2/2) is 1). Each bin's values are formed
/// element by element, compiled for the widest instruction set the CPU has
/// ([`simd::dispatch`]), with |H_1[k]|² held in the noise bins; Σ_k |H_1[k]|² is then
/// added in the order of k and the noise bins scaled by (2/m)²: the same operations in
/// the same order as one loop, so the same bits at every level.
struct TwoPeriods<'a> {
    first: &'a [Complex<f64>],
    second: &'a [Complex<f64>],
    scale: f64,
    out: BinsOut<'a>,
}

impl Kernel for TwoPeriods<'_> {
    type Output = f64;
    #[inline(always)]
    fn run(self) -> f64 {
        let TwoPeriods {
            first,
            second,
            scale,
            out,
        } = self;
        let start = out.powers.len();
        out.powers.resize(start + first.len(), 0.0);
        let bins = first.iter().zip(second);
        let outputs = out
            .coefficients
            .chunks_exact_mut(2)
            .zip(out.noise.iter_mut());
        for (((&x0, &x1), (pair, noise)), power) in bins.zip(outputs).zip(&mut out.powers[start..])
        {
            *noise = (x0 - x1).norm_sqr();
            let sum = x0 + x1;
            *power = sum.norm_sqr();
            pair[0] = scale * sum.re;
            pair[1] = -scale * sum.im;
        }
        let noise = &mut out.noise[..first.len()];
        let between = noise.iter().fold(0.0, |between, h2| between + h2);
        for h2 in noise {
            *h2 *= scale * scale;
        }
        between
    }
}

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use crate::prep::fourier::{WholeSampleDft, select_with_residuals};
    use faer::Mat;
    use rand::{Rng, SeedableRng};

    /// A periodic response (harmonics 1, 2, 3, 5, an offset), with seeded Gaussian-like
    /// noise (a sum of uniforms) and optionally a decaying transient, on `periods`
    /// periods of `per_period` samples (also `window_fit.rs`'s).
    pub(in crate::prep::fourier) fn signal(
        per_period: usize,
        periods: usize,
        channels: usize,
        noise: f64,
        transient: f64,
        seed: u64,
    ) -> (Mat<f64>, f64, f64) {
        let period = 0.8;
        let step = period / per_period as f64;
        let omega = 2.0 * std::f64::consts::PI / period;
        let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
        let x = Mat::from_fn(per_period * periods, channels, |i, j| {
            let t = i as f64 * step;
            let s = 1.0 + j as f64;
            let gauss: f64 = (0..12).map(|_| rng.random::<f64>()).sum::<f64>() - 6.0;
            40.0 + s * (omega * t - 0.3 * s).cos()
                + 0.2 * (2.0 * omega * t).sin()
                + 0.05 * s * (3.0 * omega * t + 1.0).cos()
                + 0.01 * (5.0 * omega * t).sin()
                + transient * (-t / period).exp() * (1.7 * omega * t).sin()
                + noise * gauss
        });
        (x, step, period)
    }

    fn spectra_of(x: &Mat<f64>, per_period: usize, step: f64, period: f64) -> Vec<PeriodSpectrum> {
        let most = span_harmonics(per_period, step, period);
        (0..x.nrows() / per_period)
            .map(|i| PeriodSpectrum::new(x.as_ref().subrows(i * per_period, per_period), most))
            .collect()
    }

    /// The span's coefficients and its residual on any kept harmonics read off the
    /// periods' spectra equal those of the span's own FFT (and so the least-squares
    /// ones) to round-off, with even and odd N, 2 to 5 periods, with and without noise.
    #[test]
    fn sums_and_residuals_equal_the_spans_own_transform() {
        for (per_period, periods) in [(64usize, 2usize), (101, 3), (400, 2), (77, 5)] {
            for noise in [0.0, 0.01] {
                let (x, step, period) = signal(per_period, periods, 3, noise, 0.3, 11);
                let spectra = spectra_of(&x, per_period, step, period);
                let refs: Vec<&PeriodSpectrum> = spectra.iter().collect();
                let (selection, span) = select_from_periods(&refs, step, period).unwrap();
                let (own, dft) = select_with_residuals(x.as_ref(), step, period, periods).unwrap();
                let dft: WholeSampleDft = dft.expect("whole samples per period");
                for (a, b) in selection
                    .amplitudes
                    .iter()
                    .flatten()
                    .zip(own.amplitudes.iter().flatten())
                {
                    assert!((a - b).abs() <= 1e-12 * (1.0 + b.abs()), "{a} vs {b}");
                }
                for orders in [
                    vec![1],
                    vec![1, 2, 3, 5],
                    (1..=selection.amplitudes[0].len()).collect(),
                ] {
                    for channel in 0..3 {
                        let ours = span.residual_sum_of_squares(&orders, channel);
                        let theirs = dft.residual_sum_of_squares(&orders, channel).unwrap();
                        let total: f64 = x.col(channel).iter().map(|v| (v - 40.0).powi(2)).sum();
                        assert!(
                            (ours - theirs).abs() <= 1e-12 * total,
                            "N {per_period} P {periods} σ {noise} {orders:?}: {ours:e} vs {theirs:e}"
                        );
                    }
                }
            }
        }
    }

    /// On a noisy steady response the noise floor from the contrasts estimates the
    /// noise as the bins between the harmonics do: over 40 channels of independent
    /// noise, the mean σ̂ of each within 4 % of the true σ (the standard error of that
    /// mean is about 1 %), and the same harmonics kept. A periodic response without
    /// noise leaves the contrasts, the noise and the residual at round-off.
    #[test]
    fn contrasts_estimate_the_noise_as_the_bins_between_harmonics_do() {
        let sigma = 0.004;
        for (per_period, periods) in [(400usize, 2usize), (256, 3)] {
            let (x, step, period) = signal(per_period, periods, 40, sigma, 0.0, 5);
            let spectra = spectra_of(&x, per_period, step, period);
            let refs: Vec<&PeriodSpectrum> = spectra.iter().collect();
            let (ours, _) = select_from_periods(&refs, step, period).unwrap();
            let (own, _) = select_with_residuals(x.as_ref(), step, period, periods).unwrap();
            assert_eq!(ours.kept, vec![1, 2, 3, 5]);
            assert_eq!(own.kept, ours.kept);
            for (what, selection) in [("contrasts", &ours), ("between bins", &own)] {
                let mean = selection.noise_std.iter().sum::<f64>() / 40.0;
                assert!(
                    (mean / sigma - 1.0).abs() < 0.04,
                    "N {per_period}, P {periods}, {what}: mean σ̂ {mean} vs σ {sigma}"
                );
            }
        }
        let (x, step, period) = signal(400, 2, 2, 0.0, 0.0, 5);
        let spectra = spectra_of(&x, 400, step, period);
        let refs: Vec<&PeriodSpectrum> = spectra.iter().collect();
        let (clean, span) = select_from_periods(&refs, step, period).unwrap();
        for (j, s) in clean.noise_std.iter().enumerate() {
            let rss = span.residual_sum_of_squares(&clean.kept, j);
            assert!(
                *s < 1e-9 && rss < 1e-18,
                "channel {j}: σ̂ {s:e}, RSS {rss:e}"
            );
        }
    }

    /// The contrast bins are as many as the bins between the harmonics (every one of
    /// them below [`MAX_NOISE_BINS`], strided above).
    #[test]
    fn as_many_contrast_bins_as_bins_between_harmonics() {
        for (periods, most) in [(2, 100), (3, 100), (4, 45), (12, 100), (1, 10)] {
            let between = super::super::noise_floor::between_bins(periods, most);
            let (stride, count) = contrast_stride(periods, most);
            assert_eq!(count, between.len(), "P {periods}, K {most}");
            assert_eq!(stride == 1, between.len() == most * (periods - 1));
        }
    }
}
