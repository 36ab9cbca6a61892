//! One mode of a free decay: a zero-phase band-pass and the integration of one sensor's
//! signal in the frequency domain.
//!
//! A signal s of N samples, step h, from a sensor of order r (displacement r = 0,
//! velocity r = 1, acceleration r = 2) is continued past each end by P samples of its own
//! motion ([`super::extend`]: linear prediction, faded out), so that a record that starts
//! or ends in motion does not ring through the filter as a cut would; the M = N + 2P
//! samples are zero-filled to 2M (no wrap-around) and transformed by one real FFT. Each
//! bin q at f_q = q/(2M h), ω_q = 2π f_q, is weighted by the real window W and
//! integrated:
//!
//! ```text
//!   W(f) = 1 on [f_lo, f_hi],  ½(1 − cos(π (f − (1−τ) f_lo)/(τ f_lo))) on [(1−τ) f_lo, f_lo],
//!          ½(1 + cos(π (f − f_hi)/(τ f_hi))) on [f_hi, (1+τ) f_hi],  0 elsewhere,
//!   X_q = W S_q / (iω_q)^r,    V_q = W S_q (iω_q)^{1−r},
//! ```
//!
//! with τ = [`TAPER`]. W is real and even, so the filter has no phase: the band's x and v
//! stay in step, and the energy balance over a window holds for the band's content as it
//! holds for the whole signal. The DC bin is outside every band, so the unknown
//! integration constants never enter.
//!
//! What it biases: content outside the band is removed (other modes, and the harmonics a
//! nonlinear law puts into the response above (1+τ) f_hi, which carry little energy for
//! light damping), content in the tapers is reduced; near the ends of the record the
//! continuation is only as good as the recurrence's fit, so the first and last cycles
//! may carry an error that decays over about 1/(τ f_lo) ([`super::DecaySettings::edge`]
//! drops them).
//!
//! The noise of the signal is estimated from its second differences,
//! d_i = s_{i+1} − 2 s_i + s_{i−1}: for white noise of standard deviation σ,
//! Var d = 6σ², and a smooth signal sampled at many points per period adds only
//! (ωh)² s to d; the median of |d| is robust to that, σ = median|d| / (0.6745 √6).
//! In the band the noise keeps the share 2(f_hi − f_lo) h of its variance and, as a
//! displacement at the band's centre ω_c, divides by ω_c^r: its amplitude (√2 × its
//! standard deviation) is the floor below which a cycle's amplitude is noise.

use realfft::RealFftPlanner;
use realfft::num_complex::Complex;

use crate::error::{Error, Result};
use crate::record::Sensor;

/// The taper of the band's edges, as a share of each edge frequency.
pub const TAPER: f64 = 0.5;

/// A frequency band [low, high] in cycles per time unit (Hz when time is in seconds).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Band {
    /// Lower edge of the flat pass band.
    pub low: f64,
    /// Upper edge of the flat pass band.
    pub high: f64,
}

impl Band {
    /// The band's centre (geometric mean), rad per time unit.
    pub fn centre(&self) -> f64 {
        2.0 * std::f64::consts::PI * (self.low * self.high).sqrt()
    }

    /// Checks 0 < low < high < Nyquist = 1/(2h); errors name `key` (`band`, `peak_in`).
    pub fn validate(&self, step: f64, key: &str) -> Result<()> {
        let nyquist = 0.5 / step;
        if !(self.low.is_finite() && self.low > 0.0) {
            return Err(Error::invalid(
                key,
                self.low,
                "its lower edge must be finite and positive (cycles per time unit)",
            ));
        }
        if !(self.high.is_finite() && self.high > self.low && self.high < nyquist) {
            return Err(Error::invalid(
                key,
                self.high,
                &format!(
                    "its upper edge must lie above the lower edge {} and below the Nyquist frequency {nyquist} (cycles per time unit)",
                    self.low
                ),
            ));
        }
        Ok(())
    }

    /// W(f) of the module doc.
    fn weight(&self, f: f64) -> f64 {
        let pi = std::f64::consts::PI;
        let (low_start, high_end) = ((1.0 - TAPER) * self.low, (1.0 + TAPER) * self.high);
        if f <= low_start || f >= high_end {
            0.0
        } else if f < self.low {
            0.5 * (1.0 - (pi * (f - low_start) / (TAPER * self.low)).cos())
        } else if f <= self.high {
            1.0
        } else {
            0.5 * (1.0 + (pi * (f - self.high) / (TAPER * self.high)).cos())
        }
    }
}

/// The order r of a sensor: how many times its signal is differentiated from x.
fn order(sensor: Sensor) -> i32 {
    match sensor {
        Sensor::Displacement => 0,
        Sensor::Velocity => 1,
        Sensor::Acceleration => 2,
    }
}

/// The band's displacement x and velocity v of `signal` (module doc), continued by
/// `pad` samples at each end, the recurrence fitted over `span` samples.
pub fn isolate(
    signal: &[f64],
    sensor: Sensor,
    step: f64,
    band: Band,
    pad: usize,
    span: usize,
) -> Result<(Vec<f64>, Vec<f64>)> {
    band.validate(step, "band")?;
    let n = signal.len();
    if n < 3 {
        return Err(Error::Empty {
            what: "free-decay signal (fewer than 3 samples)".into(),
        });
    }
    let m = n + 2 * pad;
    let length = 2 * m;
    let mut padded = vec![0.0; length];
    for (i, s) in super::extend::backward(signal, span, pad)
        .into_iter()
        .enumerate()
    {
        padded[pad - 1 - i] = s;
    }
    padded[pad..pad + n].copy_from_slice(signal);
    let ahead = super::extend::forward(signal, span, pad);
    padded[pad + n..pad + n + pad].copy_from_slice(&ahead);
    let mut planner = RealFftPlanner::<f64>::new();
    let forward = planner.plan_fft_forward(length);
    let inverse = planner.plan_fft_inverse(length);
    let mut spectrum = forward.make_output_vec();
    forward
        .process(&mut padded, &mut spectrum)
        .map_err(|e| Error::invalid("free-decay FFT", length as f64, &e.to_string()))?;
    let r = order(sensor);
    let df = 1.0 / (length as f64 * step);
    let zero = Complex::new(0.0, 0.0);
    let mut xs = vec![zero; spectrum.len()];
    let mut vs = vec![zero; spectrum.len()];
    let scale = 1.0 / length as f64;
    for (q, s) in spectrum.iter().enumerate() {
        let f = q as f64 * df;
        let w = band.weight(f);
        if w == 0.0 {
            continue;
        }
        let i_omega = Complex::new(0.0, 2.0 * std::f64::consts::PI * f);
        let s = *s * (w * scale);
        (xs[q], vs[q]) = match r {
            0 => (s, s * i_omega),
            1 => (s / i_omega, s),
            _ => (s / (i_omega * i_omega), s / i_omega),
        };
    }
    // A real inverse needs the DC and Nyquist bins real: neither is in a band.
    for bin in [0, xs.len() - 1] {
        (xs[bin], vs[bin]) = (zero, zero);
    }
    let mut x = inverse.make_output_vec();
    let mut v = inverse.make_output_vec();
    inverse
        .process(&mut xs, &mut x)
        .map_err(|e| Error::invalid("free-decay FFT", length as f64, &e.to_string()))?;
    inverse
        .process(&mut vs, &mut v)
        .map_err(|e| Error::invalid("free-decay FFT", length as f64, &e.to_string()))?;
    x.truncate(pad + n);
    v.truncate(pad + n);
    Ok((x.split_off(pad), v.split_off(pad)))
}

/// σ of white noise on `signal` from its second differences (module doc).
pub fn noise_std(signal: &[f64]) -> f64 {
    if signal.len() < 3 {
        return 0.0;
    }
    let mut d: Vec<f64> = signal
        .windows(3)
        .map(|w| (w[2] - 2.0 * w[1] + w[0]).abs())
        .collect();
    let middle = d.len() / 2;
    let (_, median, _) = d.select_nth_unstable_by(middle, f64::total_cmp);
    *median / (0.674_489_750_196_081_7 * 6f64.sqrt())
}

/// The amplitude, as a displacement, of the band's share of white noise σ on a sensor
/// of `sensor`'s kind (module doc).
pub fn noise_amplitude(sigma: f64, sensor: Sensor, step: f64, band: Band) -> f64 {
    let share = (2.0 * (band.high - band.low) * step).min(1.0);
    std::f64::consts::SQRT_2 * sigma * share.sqrt() / band.centre().powi(order(sensor))
}

/// The displacement spectrum |S_q| / ω_q^r of a signal measured by a sensor of order r
/// (0 displacement, 1 velocity, 2 acceleration), by one real FFT of the mean-free signal
/// with a Hann window, and the frequency range to search: `range`, or everything above
/// 4/(N h) up to the Nyquist frequency.
pub(crate) struct DisplacementSpectrum {
    /// |S_q| / ω_q^r for every bin q (ω_q = 2π q Δf).
    pub(crate) magnitudes: Vec<f64>,
    /// Δf = 1/(N h).
    pub(crate) df: f64,
    /// The range's lower end.
    pub(crate) low: f64,
    /// The range's upper end.
    pub(crate) high: f64,
}

impl DisplacementSpectrum {
    pub(crate) fn new(
        signal: &[f64],
        sensor: Sensor,
        step: f64,
        range: Option<Band>,
    ) -> Result<Self> {
        let n = signal.len();
        let mean = signal.iter().sum::<f64>() / n.max(1) as f64;
        let pi = std::f64::consts::PI;
        let mut windowed: Vec<f64> = signal
            .iter()
            .enumerate()
            .map(|(i, s)| (s - mean) * 0.5 * (1.0 - (2.0 * pi * i as f64 / n as f64).cos()))
            .collect();
        let mut planner = RealFftPlanner::<f64>::new();
        let forward = planner.plan_fft_forward(n);
        let mut spectrum = forward.make_output_vec();
        forward
            .process(&mut windowed, &mut spectrum)
            .map_err(|e| Error::invalid("free-decay FFT", n as f64, &e.to_string()))?;
        let df = 1.0 / (n as f64 * step);
        let (low, high) = range.map_or((4.0 * df, 0.5 / step), |b| (b.low, b.high));
        let r = order(sensor);
        let magnitudes = (0..spectrum.len())
            .map(|q| spectrum[q].norm() / (2.0 * pi * q as f64 * df).powi(r))
            .collect();
        Ok(DisplacementSpectrum {
            magnitudes,
            df,
            low,
            high,
        })
    }
}

/// The frequency (cycles per time unit) of the largest prominent peak (over 10 times
/// the median of the bins within a factor 1.3 in frequency; the largest bin when none
/// is) of the displacement spectrum |S_q| / ω_q^r of `signal` within `range` (the whole
/// spectrum above 4/(N h) when `None`), by one real FFT of the mean-free signal with a
/// Hann window and the parabola through the peak bin's log magnitudes.
pub fn peak_frequency(
    signal: &[f64],
    sensor: Sensor,
    step: f64,
    range: Option<Band>,
) -> Result<f64> {
    let DisplacementSpectrum {
        magnitudes,
        df,
        low,
        high,
    } = DisplacementSpectrum::new(signal, sensor, step, range)?;
    let magnitude = |q: usize| magnitudes[q];
    let first = ((low / df).ceil() as usize).max(1);
    let last = ((high / df).floor() as usize).min(magnitudes.len() - 2);
    // A mode stands out of its neighbourhood; noise divided by ω^r only rises smoothly
    // towards low frequencies. Prominence: the magnitude over the median of the bins
    // within a factor 1.3 in frequency.
    let prominent = |q: usize| {
        let (a, b) = (
            (q as f64 / 1.3) as usize,
            ((q as f64 * 1.3) as usize).min(magnitudes.len() - 1),
        );
        let mut around: Vec<f64> = (a.max(1)..=b).map(magnitude).collect();
        let middle = around.len() / 2;
        let (_, median, _) = around.select_nth_unstable_by(middle, f64::total_cmp);
        magnitude(q) > 10.0 * *median
    };
    // The local maxima, largest first; the first prominent one of the 64 largest is the
    // peak.
    let mut maxima: Vec<usize> = (first..=last)
        .filter(|&q| magnitude(q) >= magnitude(q - 1) && magnitude(q) >= magnitude(q + 1))
        .collect();
    maxima.sort_by(|&a, &b| magnitude(b).total_cmp(&magnitude(a)));
    let peak = maxima
        .iter()
        .copied()
        .take(64)
        .find(|&q| prominent(q))
        .or_else(|| maxima.first().copied())
        .filter(|&q| magnitude(q) > 0.0)
        .ok_or_else(|| {
            Error::invalid(
                "free-decay band",
                low,
                &format!(
                    "no spectral peak between {low} and {high} cycles per time unit: the signal has no content there; give the mode's `band`"
                ),
            )
        })?;
    let (a, b, c) = (
        magnitude(peak - 1).max(f64::MIN_POSITIVE).ln(),
        magnitude(peak).ln(),
        magnitude(peak + 1).max(f64::MIN_POSITIVE).ln(),
    );
    let denominator = a - 2.0 * b + c;
    let shift = if denominator < 0.0 {
        (0.5 * (a - c) / denominator).clamp(-0.5, 0.5)
    } else {
        0.0
    };
    Ok((peak as f64 + shift) * df)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A decaying sine measured as an acceleration: the band's x and v are the closed
    /// forms X e^{−σt} sin ω_d t and its derivative, away from the ends.
    #[test]
    fn integrates_a_decaying_acceleration() {
        let (h, n) = (1.0 / 12_800.0, 25_600);
        let (omega, sigma) = (2.0 * std::f64::consts::PI * 80.0, 2.0);
        let x = |t: f64| (-sigma * t).exp() * (omega * t).sin();
        let v =
            |t: f64| (-sigma * t).exp() * (omega * (omega * t).cos() - sigma * (omega * t).sin());
        let a = |t: f64| {
            (-sigma * t).exp()
                * ((sigma * sigma - omega * omega) * (omega * t).sin()
                    - 2.0 * sigma * omega * (omega * t).cos())
        };
        let signal: Vec<f64> = (0..n).map(|i| a(i as f64 * h)).collect();
        let band = Band {
            low: 40.0,
            high: 160.0,
        };
        let (xs, vs) = isolate(&signal, Sensor::Acceleration, h, band, 1000, 2000).unwrap();
        let mut worst: f64 = 0.0;
        for i in 2000..n - 2000 {
            let t = i as f64 * h;
            let scale = (-sigma * t).exp();
            worst = worst
                .max((xs[i] - x(t)).abs() / scale)
                .max((vs[i] - v(t)).abs() / (omega * scale));
        }
        assert!(worst < 1e-4, "worst relative error {worst}");
    }

    #[test]
    fn estimates_white_noise_beside_a_smooth_signal() {
        use rand::SeedableRng;
        use rand_distr::{Distribution, Normal};
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let noise = Normal::new(0.0, 0.01).unwrap();
        let signal: Vec<f64> = (0..20_000)
            .map(|i| (i as f64 * 0.04).sin() + noise.sample(&mut rng))
            .collect();
        let sigma = noise_std(&signal);
        assert!((sigma / 0.01 - 1.0).abs() < 0.05, "σ = {sigma}");
    }

    #[test]
    fn finds_the_peak_between_bins() {
        let h = 1e-3;
        let signal: Vec<f64> = (0..5000)
            .map(|i| (2.0 * std::f64::consts::PI * 37.3 * i as f64 * h).sin())
            .collect();
        let f = peak_frequency(&signal, Sensor::Displacement, h, None).unwrap();
        assert!((f - 37.3).abs() < 0.05, "{f}");
    }
}
