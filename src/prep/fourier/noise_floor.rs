//! Noise floor and automatic harmonic selection ([`select_harmonics`]). Fit every
//! harmonic 1..K_max (K_max the default count, 45% of Nyquist, at most 100) over the m samples of the
//! window's P whole periods. For white noise of variance σ² each coefficient has
//! variance ≈ 2σ²/m, so a bin that carries noise only has power P = a² + b² ~
//! exponential with mean 4σ²/m, whose median is (4σ²/m)·ln 2. The noise bins are:
//!
//! - with P ≥ 2, the bins of the fit's residual at the frequencies jω/P that are not
//!   harmonics of ω (j not a multiple of P, jω/P below K_max ω; at most
//!   [`MAX_NOISE_BINS`], evenly strided), plus the harmonics in the upper half of the
//!   band (K_max/2 < k ≤ K_max). The residual has no periodic content left, so a
//!   transient or a strong harmonic cannot leak into these bins;
//! - with P = 1 (no bins between harmonics), the harmonics 2..K_max.
//!
//! Per channel the per-bin noise power is estimated robustly as
//!
//!   P̂_noise = median over the noise bins of P / ln 2,   σ̂_A = √P̂_noise,
//!
//! (a median ignores the minority of bins that carry signal or leakage), floored at
//! 10⁻¹² max_k A_k for round-off. The per-sample noise standard deviation follows as
//! σ̂ = σ̂_A √m / 2. Harmonic k is kept when A_k > 3.5 σ̂_A in any channel; the
//! fundamental is always kept. A noise-only bin passes with probability
//! exp(−3.5²) ≈ 5·10⁻⁶.
//!
//! When the window holds a whole number of samples per period the fit and the residual
//! bins are read off one real FFT per channel ([`WholeSampleDft`], whose module doc
//! derives why they equal the least-squares ones); otherwise by least squares. A
//! record's harmonics and noise (`record_noise.rs`) are this rule on a few of its spans.

use faer::MatRef;

use super::dft::WholeSampleDft;
use super::{HarmonicBasis, default_harmonics, first_orders};
use crate::error::Result;
use crate::terms::simd::{self, Kernel};

/// Amplitude over the per-bin noise amplitude above which a harmonic is kept.
pub(crate) const NOISE_THRESHOLD: f64 = 3.5;

/// Round-off floor of the noise amplitude, relative to a channel's largest harmonic.
const ROUND_OFF: f64 = 1e-12;

/// Most harmonics the noise-floor selection fits (K_max = min(45% of Nyquist, 100)):
/// structural responses rarely carry measurable content above the 100th harmonic of
/// the drive, and the fit's cost grows with K_max³.
pub(crate) const MAX_SELECTED_HARMONICS: usize = 100;

/// Most residual bins between harmonics read for the noise floor (a median over 256
/// exponential powers has a relative standard error of about 9%).
pub(crate) const MAX_NOISE_BINS: usize = 256;

/// Which harmonics stand above the noise floor of a window, and the evidence.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct HarmonicSelection {
    /// Whole driving periods in the window.
    pub periods: usize,
    /// Samples fitted (those inside the whole periods).
    pub samples: usize,
    /// Harmonic orders kept, ascending; always starts with 1.
    pub kept: Vec<usize>,
    /// Per channel, the estimated per-bin noise amplitude σ̂_A.
    pub noise_amplitude: Vec<f64>,
    /// Per channel, the estimated noise standard deviation per sample, σ̂ = σ̂_A √m / 2.
    pub noise_std: Vec<f64>,
    /// Per channel, the amplitude A_k of harmonics k = 1..=K_max of the full fit.
    pub amplitudes: Vec<Vec<f64>>,
}

/// Selects the harmonics of ω = 2π/`period` that stand above the noise floor in any
/// column of `x` (m × n samples of `periods` whole periods), by the rule of the module
/// doc: by one real FFT per column when the window holds a whole number of samples per
/// period ([`WholeSampleDft`]), else by least squares.
pub(crate) fn select_harmonics(
    x: MatRef<'_, f64>,
    step: f64,
    period: f64,
    periods: usize,
) -> Result<HarmonicSelection> {
    Ok(select_with_spectrum(x, step, period, periods, 0)?.0)
}

/// [`select_harmonics`], also returning the window's spectrum when it holds a whole
/// number of samples per period, with the bins of harmonics up to max(K_max,
/// `highest`), so that the caller projects on the kept harmonics (or on 1..`highest`)
/// without a second transform.
pub(crate) fn select_with_spectrum(
    x: MatRef<'_, f64>,
    step: f64,
    period: f64,
    periods: usize,
    highest: usize,
) -> Result<(HarmonicSelection, Option<WholeSampleDft>)> {
    let most = most_harmonics(x.nrows(), step, period);
    let bins = if periods >= 2 {
        between_bins(periods, most)
    } else {
        Vec::new()
    };
    let spectrum = WholeSampleDft::new(x, step, period, periods, most.max(highest), &bins);
    let selection = select_with(x, step, period, periods, spectrum.as_ref())?;
    Ok((selection, spectrum))
}

/// K_max for a window of `samples` samples: 45% of the Nyquist count, at most
/// [`MAX_SELECTED_HARMONICS`] and at most (m − 1)/2.
pub(crate) fn most_harmonics(samples: usize, step: f64, period: f64) -> usize {
    default_harmonics(period / step)
        .min(MAX_SELECTED_HARMONICS)
        .min((samples.saturating_sub(1)) / 2)
}

/// [`select_harmonics`] from the window's spectrum when given (it must hold the bins of
/// harmonics 1..K_max and of [`between_bins`]), else by least squares.
pub(super) fn select_with(
    x: MatRef<'_, f64>,
    step: f64,
    period: f64,
    periods: usize,
    spectrum: Option<&WholeSampleDft>,
) -> Result<HarmonicSelection> {
    let m = x.nrows();
    let omega = 2.0 * std::f64::consts::PI / period;
    let most = most_harmonics(m, step, period);
    // The least-squares basis (and its checks: the memory of its dense design, the
    // Nyquist limit) only where the spectrum does not answer.
    let basis = || HarmonicBasis::new(omega, most, step, m);
    let orders = first_orders(most, m)?;
    let bins = if periods >= 2 {
        between_bins(periods, most)
    } else {
        Vec::new()
    };
    let spectrum = spectrum.filter(|s| s.covers(&orders) && s.covers_between(&bins));
    // By least squares with bins between the harmonics: the design once, for the fit
    // and its residual.
    let (coefficients, design) = match spectrum {
        Some(spectrum) => (spectrum.fit(&orders), None),
        None if periods >= 2 => {
            let (c, design) = basis()?.fit_and_design(x);
            (c, Some(design))
        }
        None => (basis()?.fit(x), None),
    };
    let between = if periods >= 2 {
        Some(match (spectrum, design) {
            (Some(spectrum), _) => spectrum.between_powers(&coefficients),
            (None, design) => {
                let design = match design {
                    Some(design) => design,
                    None => basis()?.design(m),
                };
                let residual = x - design * &coefficients;
                between_harmonics(residual.as_ref(), step, omega, periods, &bins)
            }
        })
    } else {
        None
    };
    // per channel, its powers at the bins in order
    let between = between.map(|bins| {
        (0..x.ncols())
            .map(|channel| bins.iter().map(|powers| powers[channel]).collect())
            .collect::<Vec<Vec<f64>>>()
    });
    Ok(select_from(
        &coefficients,
        between.as_deref(),
        m,
        periods,
        most,
    ))
}

/// The rule of the module doc on a window's coefficients (a_0, then a_k, b_k for
/// k = 1..=`most`, per channel) and, with P ≥ 2, the noise bins other than the upper
/// half of the band (`noise_bins[channel][b]`, powers a² + b² on the coefficients'
/// scale): the harmonics kept and each channel's noise.
pub(super) fn select_from(
    coefficients: &faer::Mat<f64>,
    noise_bins: Option<&[Vec<f64>]>,
    m: usize,
    periods: usize,
    most: usize,
) -> HarmonicSelection {
    let mut selector = Selector::new(m, periods, most, coefficients.ncols());
    for channel in 0..coefficients.ncols() {
        selector.channel(
            coefficients.col_as_slice(channel),
            noise_bins.map(|bins| bins[channel].as_slice()),
        );
    }
    selector.finish()
}

/// The rule of the module doc, one channel at a time: each channel's amplitudes and
/// noise, and the harmonics that stand above the noise in any channel.
pub(super) struct Selector {
    /// m, the samples of the window.
    samples: usize,
    /// P, its whole periods.
    periods: usize,
    /// K_max.
    most: usize,
    /// Whether harmonic k stands above the noise in a channel so far.
    above: Vec<bool>,
    noise_amplitude: Vec<f64>,
    amplitudes: Vec<Vec<f64>>,
    /// The order keys of a channel's noise bins (scratch).
    keys: Vec<i64>,
}

impl Selector {
    /// A selection over `m` samples of `periods` periods on harmonics 1..=`most`, for
    /// `channels` channels.
    pub(super) fn new(m: usize, periods: usize, most: usize, channels: usize) -> Self {
        Selector {
            samples: m,
            periods,
            most,
            above: vec![false; most + 1],
            noise_amplitude: Vec::with_capacity(channels),
            amplitudes: Vec::with_capacity(channels),
            keys: Vec::new(),
        }
    }

    /// The next channel, from its coefficients [a_0, a_1, b_1, …] (harmonics up to K_max
    /// at least) and, with P ≥ 2, its powers at the noise bins between the harmonics.
    /// The passes over the harmonics are compiled for the widest instruction set the CPU
    /// has ([`simd::dispatch`]): element by element the same operations, and maxima
    /// (exact) in lanes, so the same bits at every level.
    pub(super) fn channel(&mut self, coefficients: &[f64], noise_bins: Option<&[f64]>) {
        simd::dispatch(NextChannel {
            selector: self,
            coefficients,
            noise_bins,
        })
    }

    /// [`Selector::channel`] at the level it is compiled for.
    #[inline(always)]
    fn channel_at_level(&mut self, coefficients: &[f64], noise_bins: Option<&[f64]>) {
        let most = self.most;
        let amps = amplitudes_of(coefficients, most);
        self.keys.clear();
        match noise_bins {
            // the upper half of the band, then the noise bins between harmonics
            Some(bins) => self.keys.extend(
                amps[most / 2..]
                    .iter()
                    .map(|a| order_key(a * a))
                    .chain(bins.iter().map(|&power| order_key(power))),
            ),
            None => self.keys.extend(amps[1..].iter().map(|a| order_key(a * a))),
        }
        let floor = ROUND_OFF * largest_magnitude(&amps);
        let noise = median(&mut self.keys).map_or(floor, |median| {
            (median / std::f64::consts::LN_2).sqrt().max(floor)
        });
        let threshold = NOISE_THRESHOLD * noise;
        for (above, a) in self.above[2..].iter_mut().zip(&amps[1..]) {
            *above |= *a > threshold;
        }
        self.noise_amplitude.push(noise);
        self.amplitudes.push(amps);
    }

    /// The selection over the channels given.
    pub(super) fn finish(self) -> HarmonicSelection {
        let mut kept = vec![1];
        kept.extend((2..=self.most).filter(|&k| self.above[k]));
        let noise_std = self
            .noise_amplitude
            .iter()
            .map(|a| a * (self.samples as f64).sqrt() / 2.0)
            .collect();
        HarmonicSelection {
            periods: self.periods,
            samples: self.samples,
            kept,
            noise_amplitude: self.noise_amplitude,
            noise_std,
            amplitudes: self.amplitudes,
        }
    }
}

/// [`Selector::channel`] as a [`Kernel`].
struct NextChannel<'a> {
    selector: &'a mut Selector,
    coefficients: &'a [f64],
    noise_bins: Option<&'a [f64]>,
}

impl Kernel for NextChannel<'_> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        self.selector
            .channel_at_level(self.coefficients, self.noise_bins)
    }
}

/// Lanes of [`largest_magnitude`].
const LANES: usize = 8;

/// The largest of |v| over `values` and 0, NaN ignored: `f64::max` folded in [`LANES`]
/// lanes and then across them, the same value as one fold in order (the maximum of
/// numbers is exact, |v| has no negative zero, and `f64::max` ignores NaN either way).
#[inline(always)]
fn largest_magnitude(values: &[f64]) -> f64 {
    let mut lanes = [0.0f64; LANES];
    let mut chunks = values.chunks_exact(LANES);
    for chunk in &mut chunks {
        for (m, v) in lanes.iter_mut().zip(chunk) {
            *m = m.max(v.abs());
        }
    }
    lanes
        .iter()
        .chain(chunks.remainder())
        .fold(0.0, |m, &v| m.max(v.abs()))
}

/// A_k = √(a_k² + b_k²) for k = 1..=`most` of one channel's coefficients
/// [a₀, a₁, b₁, …], the squares formed on the coefficients scaled by a power of two near
/// the largest (exact), so that neither overflows nor loses bits below the normal range
/// at any scale the data check lets through: as accurate as `hypot` (within an ulp of
/// it), at the cost of a square root.
#[inline(always)]
fn amplitudes_of(c: &[f64], most: usize) -> Vec<f64> {
    let largest = largest_magnitude(&c[1..=2 * most]);
    let scale = if largest > 0.0 && largest.is_finite() {
        2f64.powi(-largest.log2().round() as i32)
    } else {
        1.0
    };
    c[1..=2 * most]
        .chunks_exact(2)
        .map(|pair| {
            let (a, b) = (scale * pair[0], scale * pair[1]);
            (a * a + b * b).sqrt() / scale
        })
        .collect()
}

/// The key of `x` in IEEE 754's total order as an integer: `order_key(a) < order_key(b)`
/// exactly when `a.total_cmp(&b)` is `Less` (the bit transform `f64::total_cmp` applies
/// to both sides of every comparison, applied once per value; its own inverse).
#[inline(always)]
fn order_key(x: f64) -> i64 {
    let bits = x.to_bits() as i64;
    bits ^ ((((bits >> 63) as u64) >> 1) as i64)
}

/// The value whose [`order_key`] is `key`.
fn from_order_key(key: i64) -> f64 {
    f64::from_bits((key ^ ((((key >> 63) as u64) >> 1) as i64)) as u64)
}

/// The median of the values whose [`order_key`]s are `keys` (reordered), or None when
/// empty: by selection on the integer keys, O(n), the same values as a sort by
/// `f64::total_cmp` would put in the middle.
fn median(keys: &mut [i64]) -> Option<f64> {
    if keys.is_empty() {
        return None;
    }
    let mid = keys.len() / 2;
    let odd = keys.len() % 2 == 1;
    let (below, &mut upper, _) = keys.select_nth_unstable(mid);
    let upper = from_order_key(upper);
    Some(if odd {
        upper
    } else {
        // even count: the lower middle is the largest of those below
        let lower = below.iter().copied().max().map_or(upper, from_order_key);
        0.5 * (lower + upper)
    })
}

/// The bins j between the harmonics whose residual power the noise floor reads:
/// j = 1..P·K with j not a multiple of P, at most [`MAX_NOISE_BINS`] of them evenly
/// strided (frequency jω/P).
pub(crate) fn between_bins(periods: usize, most: usize) -> Vec<usize> {
    let all: Vec<usize> = (1..periods * most).filter(|j| j % periods != 0).collect();
    let stride = all.len().div_ceil(MAX_NOISE_BINS).max(1);
    all.into_iter().step_by(stride).collect()
}

/// Powers a² + b² per channel of the residual (m × n) at the frequencies jω/P between
/// the harmonics, for the bins j of [`between_bins`]; a = (2/m) Σ r_i cos(jωt_i/P), b
/// likewise with sin. The sines and cosines come from powers of the phasor e^{iωt_i/P},
/// one sincos per sample.
fn between_harmonics(
    residual: MatRef<'_, f64>,
    step: f64,
    omega: f64,
    periods: usize,
    bins: &[usize],
) -> Vec<Vec<f64>> {
    let (m, n) = residual.shape();
    let Some(&highest) = bins.last() else {
        return Vec::new();
    };
    // sums[b][c] = (Σ r cos, Σ r sin) for bin b and channel c
    let mut sums = vec![vec![(0.0, 0.0); n]; bins.len()];
    let base = omega / periods as f64 * step;
    let row: Vec<&[f64]> = (0..n).map(|c| crate::record::col(residual, c)).collect();
    // LANES samples' recurrences side by side (each with its own arithmetic, so the
    // same values); the block's cosines and sines at the bins kept, then every sum
    // (bin, channel) takes its terms in sample order, the sums interleaved so that no
    // addition waits on the one before.
    const LANES: usize = 4;
    let count = bins.len();
    let mut flat = vec![0.0; 2 * count * n];
    let mut phasors = vec![(0.0, 0.0); LANES * count];
    let mut values = vec![0.0; n];
    for block in (0..m).step_by(LANES) {
        let lanes = (m - block).min(LANES);
        let (mut s1, mut c1) = ([0.0; LANES], [1.0; LANES]);
        for l in 0..lanes {
            (s1[l], c1[l]) = (base * (block + l) as f64).sin_cos();
        }
        let (mut cos, mut sin) = ([1.0; LANES], [0.0; LANES]);
        let mut b = 0;
        for j in 1..=highest {
            for l in 0..LANES {
                (cos[l], sin[l]) = (
                    cos[l] * c1[l] - sin[l] * s1[l],
                    sin[l] * c1[l] + cos[l] * s1[l],
                );
            }
            if bins[b] == j {
                for l in 0..LANES {
                    phasors[l * count + b] = (cos[l], sin[l]);
                }
                b += 1;
            }
        }
        for l in 0..lanes {
            for (value, r) in values.iter_mut().zip(&row) {
                *value = r[block + l];
            }
            for (sums, &(cos, sin)) in flat
                .chunks_exact_mut(2 * n)
                .zip(&phasors[l * count..(l + 1) * count])
            {
                for (sum, r) in sums.chunks_exact_mut(2).zip(&values) {
                    sum[0] += cos * r;
                    sum[1] += sin * r;
                }
            }
        }
    }
    for (b, per_channel) in sums.iter_mut().enumerate() {
        for (c, sum) in per_channel.iter_mut().enumerate() {
            *sum = (flat[2 * (b * n + c)], flat[2 * (b * n + c) + 1]);
        }
    }
    let scale = 2.0 / m as f64;
    sums.into_iter()
        .map(|per_channel| {
            per_channel
                .into_iter()
                .map(|(a, b)| (scale * a).powi(2) + (scale * b).powi(2))
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::{amplitudes_of, from_order_key, median, order_key};

    /// The amplitudes from scaled squares are within an ulp or two of `hypot`, at the
    /// extremes of scale the data check lets through (2^±505) and where a harmonic is
    /// 10⁻¹⁶ of the largest, whose plain square would sink below the normal range.
    #[test]
    fn amplitudes_are_hypot_at_every_scale() {
        for exponent in [-505, -300, 0, 300, 505] {
            let s = 2f64.powi(exponent);
            let c: Vec<f64> = [0.3, 1.0, -0.75, 1e-16, 3e-17, -2.5e-13, 1e-12]
                .iter()
                .map(|v| s * v)
                .collect();
            let amps = amplitudes_of(&c, 3);
            for (k, a) in amps.iter().enumerate() {
                let reference = c[2 * k + 1].hypot(c[2 * k + 2]);
                assert!(
                    (a - reference).abs() <= 4.0 * f64::EPSILON * reference,
                    "2^{exponent}, harmonic {}: {a:e} vs {reference:e}",
                    k + 1
                );
            }
        }
        assert_eq!(amplitudes_of(&[0.0; 5], 2), vec![0.0, 0.0]);
    }

    /// The median by selection equals the middle of the sorted values (odd and even
    /// counts, ties), bit for bit.
    #[test]
    fn median_by_selection_is_the_sorted_middle() {
        let mut state = 12345u64;
        for len in 1..40 {
            let values: Vec<f64> = (0..len)
                .map(|_| {
                    state = state.wrapping_mul(6364136223846793005).wrapping_add(1);
                    ((state >> 33) % 17) as f64 * 0.37
                })
                .collect();
            let mut sorted = values.clone();
            sorted.sort_by(f64::total_cmp);
            let mid = len / 2;
            let expected = if len % 2 == 1 {
                sorted[mid]
            } else {
                0.5 * (sorted[mid - 1] + sorted[mid])
            };
            let mut keys: Vec<i64> = values.iter().map(|&v| order_key(v)).collect();
            assert_eq!(median(&mut keys), Some(expected), "{values:?}");
        }
        assert_eq!(median(&mut []), None);
    }

    /// The integer keys order values as `f64::total_cmp` does (signed zeros, subnormals,
    /// infinities, NaNs of both signs) and give the values back bit for bit.
    #[test]
    fn order_keys_follow_the_total_order() {
        let values = [
            f64::NEG_INFINITY,
            -f64::NAN,
            -1e300,
            -1.0,
            -f64::MIN_POSITIVE / 4.0,
            -0.0,
            0.0,
            f64::MIN_POSITIVE / 4.0,
            1e-300,
            0.37,
            2.0,
            f64::MAX,
            f64::INFINITY,
            f64::NAN,
        ];
        for a in values {
            assert_eq!(from_order_key(order_key(a)).to_bits(), a.to_bits());
            for b in values {
                assert_eq!(order_key(a).cmp(&order_key(b)), a.total_cmp(&b), "{a} {b}");
            }
        }
    }
}
