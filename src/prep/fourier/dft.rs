//! The harmonic projection of a window with a whole number of samples per period, by
//! one real FFT per channel: the same coefficients as the least-squares fit of
//! [`super::HarmonicBasis`], in O(L log L) per channel instead of O(L p).
//!
//! **When.** T/h = N is a whole number (to [`WHOLE_SAMPLES`] relative), the window holds
//! P whole periods, L = P N samples, and the fit reads m = L samples (a window that
//! closes periodically) or m = L + 1 (t_0 .. t_0 + PT, the closing sample included),
//! and every harmonic order k of the fit is below Nyquist, 2kP < L. Otherwise the
//! caller keeps the least-squares fit.
//!
//! **Why they agree (m = L).** On t_n = n h the harmonic k of ω = 2π/T is
//! cos(kω t_n) = cos(2π kP n / L): the DFT bin j = kP of length L. For integers
//! 0 < p, q < L/2,
//!
//! ```text
//!   Σ_{n<L} cos(2πpn/L) cos(2πqn/L) = Σ_{n<L} ½[cos(2π(p−q)n/L) + cos(2π(p+q)n/L)] = L/2 δ_pq,
//!   Σ_{n<L} sin(2πpn/L) sin(2πqn/L) = Σ_{n<L} ½[cos(2π(p−q)n/L) − cos(2π(p+q)n/L)] = L/2 δ_pq,
//!   Σ_{n<L} cos(2πpn/L) sin(2πqn/L) = Σ_{n<L} ½[sin(2π(p+q)n/L) − sin(2π(p−q)n/L)] = 0,
//!   Σ_{n<L} cos(2πpn/L) = Σ_{n<L} sin(2πpn/L) = 0,
//! ```
//!
//! because Σ_{n<L} e^{2πi r n/L} = 0 for every integer r ≢ 0 (mod L), and 0 < p + q < L,
//! |p − q| < L, so only p = q leaves a term (the constant ½ · L). The design B of the
//! basis [1, cos k₁ωt, sin k₁ωt, …] therefore has the diagonal Gram matrix
//! D = BᵀB = diag(L, L/2, …, L/2), and the least-squares coefficients c = D⁻¹Bᵀx read
//! straight off the DFT X_j = Σ_{n<L} x_n e^{−2πijn/L}:
//!
//! ```text
//!   a_0 = Re X_0 / L,   a_k = 2 Re X_{kP} / L,   b_k = −2 Im X_{kP} / L.
//! ```
//!
//! **m = L + 1.** The extra sample at t_0 + PT has the design row of t_0,
//! u = [1, 1, 0, 1, 0, …] (cos 2πkP = 1, sin 2πkP = 0), so BᵀB = D + uuᵀ and
//! Bᵀx = y_L + u x_L (y_L the sums over the first L samples, above). Sherman–Morrison
//! gives the same least-squares solution exactly:
//!
//! ```text
//!   c = D⁻¹y − D⁻¹u (uᵀD⁻¹y) / (1 + uᵀD⁻¹u),   y = y_L + u x_L,   uᵀD⁻¹u = (1 + 2|S|)/L.
//! ```
//!
//! **Noise floor.** [`super::select_harmonics`] reads the residual r = x − Bc of the fit
//! on 1..K at the frequencies jω/P between the harmonics, Σ_{n<m} r_n (cos, sin)(2πjn/L),
//! 0 < j < PK < L/2, j not a multiple of P. By the same orthogonality every column of B
//! has zero sum against bin j over the first L samples, so those sums are the signal's
//! own bin, (Re X_j, −Im X_j), plus for m = L + 1 the closing residual
//! (r_L, 0) with r_L = x_L − uᵀc (cos 2πj = 1, sin 2πj = 0).
//!
//! As in the least-squares fit, each channel is transformed relative to its first
//! sample (x − x_0, added back to a_0), so that a large offset costs no accuracy.

use std::cell::RefCell;

use faer::{Mat, MatRef};
use realfft::RealFftPlanner;
use realfft::num_complex::Complex;

use crate::record::col;
use crate::terms::simd::{self, Kernel};

/// The largest relative distance of T/h from a whole number for which the samples are
/// taken as whole per period. Below it the least-squares basis (which uses the exact
/// ω) and the DFT bins differ in phase by at most 2π k P · 10⁻¹² at harmonic k over P
/// periods, the order of the round-off of the least-squares fit itself.
pub(crate) const WHOLE_SAMPLES: f64 = 1e-12;

/// N = T/h when it is a whole number (to [`WHOLE_SAMPLES`] relative) of at least 2.
pub(crate) fn whole_samples(step: f64, period: f64) -> Option<usize> {
    let per_period = period / step;
    let whole = per_period.round();
    (whole.is_finite() && whole >= 2.0 && (per_period - whole).abs() <= WHOLE_SAMPLES * per_period)
        .then_some(whole as usize)
}

/// L = P N, the length of the transform of a window of `samples` samples over `periods`
/// whole periods, when the window's projection reads its bins (module doc, **When**):
/// N = T/h whole, m = L or L + 1, harmonics up to `highest` and `between_bins` below
/// Nyquist. `None` where the caller fits by least squares.
pub(super) fn transform_length(
    samples: usize,
    step: f64,
    period: f64,
    periods: usize,
    highest: usize,
    between_bins: &[usize],
) -> Option<usize> {
    let length = periods.checked_mul(whole_samples(step, period)?)?;
    if periods == 0 || !(samples == length || samples == length + 1) {
        return None;
    }
    if 2 * highest.checked_mul(periods)? >= length
        || between_bins.iter().any(|&j| j == 0 || 2 * j >= length)
    {
        return None;
    }
    Some(length)
}

thread_local! {
    /// One planner per thread: it caches a plan (twiddles, factorisation) per length,
    /// so the windows of a record, which share their length, plan once.
    static PLANNER: RefCell<RealFftPlanner<f64>> = RefCell::new(RealFftPlanner::new());
}

/// A real FFT of one length with its buffers, planned once (per thread, `PLANNER`), that
/// transforms each channel relative to its first sample, so that a large offset costs no
/// accuracy.
pub(super) struct RelativeFft {
    fft: std::sync::Arc<dyn realfft::RealToComplex<f64>>,
    input: Vec<f64>,
    output: Vec<Complex<f64>>,
    scratch: Vec<Complex<f64>>,
}

impl RelativeFft {
    /// The transform of `length` samples.
    pub(super) fn new(length: usize) -> Self {
        let fft = PLANNER.with(|p| p.borrow_mut().plan_fft_forward(length));
        RelativeFft {
            input: vec![0.0; length],
            output: fft.make_output_vec(),
            scratch: fft.make_scratch_vec(),
            fft,
        }
    }

    /// x_0 and the half spectrum X_0 … X_⌊L/2⌋ of x_n − x_0 over the first L samples of
    /// `x` (at least L of them).
    pub(super) fn transform(&mut self, x: &[f64]) -> (f64, &[Complex<f64>]) {
        let x0 = x[0];
        for (slot, value) in self.input.iter_mut().zip(x) {
            *slot = value - x0;
        }
        // cannot fail: realfft errs only on buffer lengths, and these come from the plan
        self.fft
            .process_with_scratch(&mut self.input, &mut self.output, &mut self.scratch)
            .expect("buffers made by the plan have its lengths");
        (x0, &self.output)
    }
}

/// [`WholeSampleDft::fit`]'s harmonic coefficients of one channel on orders 1..=K:
/// a_k = 2 (Re X_k + x_L − x_0)/L, b_k = −2 Im X_k / L into `out` (2K values).
struct Harmonics<'a> {
    out: &'a mut [f64],
    bins: &'a [Complex<f64>],
    extra: f64,
    l: f64,
}

impl Kernel for Harmonics<'_> {
    type Output = ();
    #[inline(always)]
    fn run(self) {
        for (pair, bin) in self.out.chunks_exact_mut(2).zip(self.bins) {
            pair.copy_from_slice(&harmonic_pair(bin, self.extra, self.l));
        }
    }
}

/// (a_k, b_k) = (2 (Re X_k + x_L − x_0)/L, −2 Im X_k / L) from bin X_k, `extra` = x_L − x_0
/// (0 without a closing sample).
#[inline(always)]
fn harmonic_pair(bin: &Complex<f64>, extra: f64, l: f64) -> [f64; 2] {
    [2.0 * (bin.re + extra) / l, -2.0 * bin.im / l]
}

/// The DFT bins of a window's channels that the harmonic projection and the noise floor
/// read: bins kP for k = 0..=K and a list of bins between the harmonics.
pub(crate) struct WholeSampleDft {
    /// L = P N.
    length: usize,
    /// Samples fitted, L or L + 1.
    samples: usize,
    /// Highest harmonic order K whose bin is kept.
    highest: usize,
    /// x_0 per channel.
    first: Vec<f64>,
    /// x_L − x_0 per channel when m = L + 1.
    closing: Option<Vec<f64>>,
    /// Per channel, X_{kP} of x − x_0 for k = 0..=K (channel c at c (K + 1) + k).
    harmonics: Vec<Complex<f64>>,
    /// The bins between the harmonics that were kept, ascending.
    between_bins: Vec<usize>,
    /// Per channel, X_j at `between_bins` (channel c at c · bins + b).
    between: Vec<Complex<f64>>,
}

impl WholeSampleDft {
    /// The bins of every column of `x` (m × n samples of `periods` whole periods of
    /// `period`, sampled every `step`) for harmonics 0..=`highest` and the bins
    /// `between_bins`, or `None` when the window does not hold a whole number of samples
    /// per period (module doc), where the caller fits by least squares.
    pub(crate) fn new(
        x: MatRef<'_, f64>,
        step: f64,
        period: f64,
        periods: usize,
        highest: usize,
        between_bins: &[usize],
    ) -> Option<Self> {
        let samples = x.nrows();
        let length = transform_length(samples, step, period, periods, highest, between_bins)?;
        let n = x.ncols();
        let mut fft = RelativeFft::new(length);
        let mut first = Vec::with_capacity(n);
        let mut closing = (samples == length + 1).then(|| Vec::with_capacity(n));
        let mut harmonics = Vec::with_capacity(n * (highest + 1));
        let mut between = Vec::with_capacity(n * between_bins.len());
        for c in 0..n {
            let xc = col(x, c);
            let (x0, output) = fft.transform(xc);
            first.push(x0);
            if let Some(closing) = closing.as_mut() {
                closing.push(xc[length] - x0);
            }
            harmonics.extend((0..=highest).map(|k| output[k * periods]));
            between.extend(between_bins.iter().map(|&j| output[j]));
        }
        Some(WholeSampleDft {
            length,
            samples,
            highest,
            first,
            closing,
            harmonics,
            between_bins: between_bins.to_vec(),
            between,
        })
    }

    /// Whether the bins of every order of `orders` were kept.
    pub(crate) fn covers(&self, orders: &[usize]) -> bool {
        orders.iter().all(|&k| k <= self.highest)
    }

    /// Whether the bins `bins` between harmonics were kept.
    pub(crate) fn covers_between(&self, bins: &[usize]) -> bool {
        self.between_bins == bins
    }

    /// The least-squares coefficients ((2|S| + 1) × n: a_0, then a_k, b_k per order of
    /// `orders`, ascending and distinct, each at most the `highest` given to
    /// [`WholeSampleDft::new`]) of every channel: those of
    /// [`super::HarmonicBasis::fit`] on the same samples (module doc).
    pub(crate) fn fit(&self, orders: &[usize]) -> Mat<f64> {
        debug_assert!(self.covers(orders));
        let n = self.first.len();
        let p = 2 * orders.len() + 1;
        let l = self.length as f64;
        let mut c = Mat::zeros(p, n);
        let contiguous = orders.iter().enumerate().all(|(i, &k)| k == i + 1);
        for j in 0..n {
            let bins = &self.harmonics[j * (self.highest + 1)..(j + 1) * (self.highest + 1)];
            let extra = self.closing.as_ref().map_or(0.0, |x| x[j]);
            // one channel's column as a slice: the same arithmetic without a bounds
            // check of (row, column) per value
            let cj = c.col_as_slice_mut(j);
            // y = Bᵀx over the m samples, then D⁻¹y
            cj[0] = (bins[0].re + extra) / l;
            if contiguous {
                // orders 1..=K (the noise floor's): the bins in order, at the widest
                // instruction set
                simd::dispatch(Harmonics {
                    out: &mut cj[1..],
                    bins: &bins[1..=orders.len()],
                    extra,
                    l,
                });
            } else {
                for (pair, &k) in cj[1..].chunks_exact_mut(2).zip(orders) {
                    pair.copy_from_slice(&harmonic_pair(&bins[k], extra, l));
                }
            }
            if self.closing.is_some() {
                // Sherman–Morrison for BᵀB = D + uuᵀ, u = [1, 1, 0, 1, 0, …]:
                // D⁻¹u = [1, 2, 0, 2, 0, …]/L, uᵀD⁻¹y = Σ of the cosine rows of D⁻¹y.
                let projection = cj[0] + cj[1..].iter().step_by(2).sum::<f64>();
                let scale = projection / (1.0 + p as f64 / l);
                cj[0] -= scale / l;
                for cosine in cj[1..].iter_mut().step_by(2) {
                    *cosine -= 2.0 * scale / l;
                }
            }
            cj[0] += self.first[j];
        }
        c
    }

    /// Per bin between the harmonics (the `between_bins` given to
    /// [`WholeSampleDft::new`]) and channel, the power (2/m)²(A² + B²) of the residual
    /// of the fit `coefficients` on orders 1..=K (from [`WholeSampleDft::fit`]), with
    /// (A, B) = Σ_{n<m} r_n (cos, sin)(2πjn/L) (module doc).
    pub(crate) fn between_powers(&self, coefficients: &Mat<f64>) -> Vec<Vec<f64>> {
        let n = self.first.len();
        let bins = self.between_bins.len();
        let scale = 2.0 / self.samples as f64;
        // the closing residual r_L = x_L − uᵀc per channel
        let closing: Vec<f64> = (0..n)
            .map(|j| {
                self.closing.as_ref().map_or(0.0, |x| {
                    let fitted = coefficients[(0, j)]
                        + (1..coefficients.nrows())
                            .step_by(2)
                            .map(|k| coefficients[(k, j)])
                            .sum::<f64>();
                    x[j] + self.first[j] - fitted
                })
            })
            .collect();
        (0..bins)
            .map(|b| {
                (0..n)
                    .map(|j| {
                        let bin = self.between[j * bins + b];
                        let a = scale * (bin.re + closing[j]);
                        let s = scale * bin.im;
                        a * a + s * s
                    })
                    .collect()
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::super::noise_floor::{between_bins, select_with};
    use super::super::{HarmonicBasis, select_harmonics};
    use super::*;
    use rand::{Rng, SeedableRng};

    /// A chain-like response with harmonics 1, 2, 3, 5 of ω, an offset and seeded
    /// uniform noise of amplitude `noise` (every channel different), on `m` samples of
    /// step h = T/N.
    fn signal(m: usize, n: usize, per_period: usize, noise: f64, seed: u64) -> (Mat<f64>, f64) {
        let period = 2.5;
        let step = period / per_period as f64;
        let omega = 2.0 * std::f64::consts::PI / period;
        let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
        let x = Mat::from_fn(m, n, |i, j| {
            let t = i as f64 * step;
            let s = 1.0 + j as f64;
            3.0 + s * (omega * t - 0.3 * s).cos()
                + 0.2 * (2.0 * omega * t).sin()
                + 0.05 * s * (3.0 * omega * t + 1.0).cos()
                + 0.01 * (5.0 * omega * t).sin()
                + noise * (rng.random::<f64>() - 0.5)
        });
        (x, step)
    }

    fn relative_difference(a: &Mat<f64>, b: &Mat<f64>) -> f64 {
        let scale = (0..b.ncols())
            .flat_map(|j| (0..b.nrows()).map(move |i| (i, j)))
            .fold(0.0f64, |m, (i, j)| m.max(b[(i, j)].abs()));
        (0..b.ncols())
            .flat_map(|j| (0..b.nrows()).map(move |i| (i, j)))
            .fold(0.0f64, |m, (i, j)| m.max((a[(i, j)] - b[(i, j)]).abs()))
            / scale
    }

    /// The FFT coefficients equal the least-squares ones to round-off, for m = L (a
    /// window that closes periodically) and m = L + 1 (the closing sample read), for
    /// every order up to K_max and for a chosen subset, with even and odd N.
    #[test]
    fn fit_equals_least_squares_on_whole_samples_per_period() {
        for (per_period, periods) in [(64usize, 1usize), (101, 3), (200, 7)] {
            let length = per_period * periods;
            for m in [length, length + 1] {
                let (x, step) = signal(m, 4, per_period, 0.02, m as u64);
                let period = step * per_period as f64;
                let omega = 2.0 * std::f64::consts::PI / period;
                let most = (per_period - 1) / 2;
                let dft = WholeSampleDft::new(x.as_ref(), step, period, periods, most, &[])
                    .expect("whole samples per period");
                let all: Vec<usize> = (1..=most).collect();
                for orders in [all, vec![1, 2, 3, 5], vec![2, most]] {
                    let basis = HarmonicBasis::with_orders(omega, orders.clone(), step, m).unwrap();
                    let difference = relative_difference(&dft.fit(&orders), &basis.fit(x.as_ref()));
                    assert!(
                        difference < 1e-12,
                        "N = {per_period}, P = {periods}, m = {m}, {} orders: {difference:e}",
                        orders.len()
                    );
                }
            }
        }
    }

    /// The noise floor from the FFT equals the least-squares one: the same harmonics
    /// kept, the same amplitudes and noise estimates to round-off, with one period (no
    /// bins between harmonics) and several (m = L and L + 1).
    #[test]
    fn noise_floor_equals_least_squares() {
        for (per_period, periods) in [(90usize, 1usize), (128, 2), (77, 5), (256, 12)] {
            let length = per_period * periods;
            for m in [length, length + 1] {
                let (x, step) = signal(m, 3, per_period, 0.01, 7 + m as u64);
                let period = step * per_period as f64;
                let most = super::super::noise_floor::most_harmonics(m, step, period);
                let bins = if periods >= 2 {
                    between_bins(periods, most)
                } else {
                    Vec::new()
                };
                let dft = WholeSampleDft::new(x.as_ref(), step, period, periods, most, &bins)
                    .expect("whole samples per period");
                let fast = select_with(x.as_ref(), step, period, periods, Some(&dft)).unwrap();
                let slow = select_with(x.as_ref(), step, period, periods, None).unwrap();
                assert_eq!(
                    fast,
                    select_harmonics(x.as_ref(), step, period, periods).unwrap()
                );
                assert_eq!(
                    fast.kept, slow.kept,
                    "N = {per_period}, P = {periods}, m = {m}"
                );
                assert!(
                    fast.kept.len() >= 4 && fast.kept.len() < most / 2,
                    "{:?}",
                    fast.kept
                );
                // Round-off is relative to the signal: the noise bins sit about 10³
                // below the largest harmonic, so their own relative agreement is
                // about 10³ times looser.
                for (channel, (fast_noise, slow_noise)) in fast
                    .noise_amplitude
                    .iter()
                    .zip(&slow.noise_amplitude)
                    .enumerate()
                {
                    let amplitudes = &slow.amplitudes[channel];
                    let largest = amplitudes.iter().cloned().fold(0.0, f64::max);
                    let difference = (fast_noise - slow_noise).abs();
                    assert!(
                        difference < 1e-12 * largest && difference < 1e-10 * slow_noise,
                        "noise of channel {channel}, N = {per_period}, P = {periods}, m = {m}: {:e} of the noise",
                        difference / slow_noise
                    );
                    for (a, b) in fast.amplitudes[channel].iter().zip(amplitudes) {
                        assert!((a - b).abs() < 1e-12 * largest, "amplitude {a} vs {b}");
                    }
                }
            }
        }
    }

    /// Windows the FFT does not serve: T/h not whole, fewer samples than L, an order at
    /// or above Nyquist, a bin outside the band.
    #[test]
    fn declines_what_is_not_whole_samples_per_period() {
        let (x, step) = signal(301, 2, 100, 0.0, 1);
        let period = step * 100.0;
        assert!(WholeSampleDft::new(x.as_ref(), step, period, 3, 10, &[]).is_some());
        assert!(WholeSampleDft::new(x.as_ref(), step, period * (1.0 + 1e-9), 3, 10, &[]).is_none());
        assert!(WholeSampleDft::new(x.subrows(0, 299), step, period, 3, 10, &[]).is_none());
        assert!(WholeSampleDft::new(x.as_ref(), step, period, 3, 50, &[]).is_none());
        assert!(WholeSampleDft::new(x.as_ref(), step, period, 3, 10, &[150]).is_none());
        assert!(WholeSampleDft::new(x.as_ref(), step, period, 3, 10, &[0]).is_none());
    }
}
