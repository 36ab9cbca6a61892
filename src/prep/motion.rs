//! Motion from any sensor: the displacements x and velocities v of a record whose DOFs
//! are sensed by displacement, velocity or acceleration channels ([`Sensor`]), by
//! frequency-domain integration over the record's whole periods.
//!
//! Over the first M = round(P T/h) samples (P = ⌊N h/T⌋ whole periods of the N) the
//! DFT S_q = Σ_i s_i e^{−2πi qi/M} of each channel is integrated bin by bin, with
//! ω_q = 2π q/(M h) for the signed bin −M/2 < q < M/2:
//!
//! ```text
//!   acceleration a:  X_q = −A_q / ω_q²,   V_q = A_q / (i ω_q)
//!   velocity v:      X_q =  V_q / (i ω_q), V_q = V_q
//!   displacement x:  X_q =  X_q,          V_q = i ω_q X_q   (x itself kept as measured)
//! ```
//!
//! The DC bin (q = 0) of x and v is set to zero for velocity and acceleration sensors
//! (the integration constants are unknown: the mean of x and v over the M samples is
//! zero), and so is the Nyquist bin (q = M/2 for even M) of every integrated or
//! differentiated signal (the sign of its ω is undefined). Every other bin is kept, so
//! content that is not harmonic, such as a transient, survives and the steady-state check
//! still sees it. Samples after the M-th repeat the reconstruction with period M h.
//!
//! What it biases:
//! - the means: a true static displacement (a constant force on a spring) or a mean
//!   velocity (a drift) of a velocity or acceleration channel is removed;
//! - when T/h is not an integer, M h differs from P T by less than half a step, the
//!   harmonics fall between bins and leak into their neighbours: a relative error of the
//!   order of the mismatch over M, (|M h − P T|/(P T)), on each harmonic;
//! - a record that is not periodic over its M samples (a transient, a drift) is made
//!   periodic: the jump at the wrap spreads over every bin, and the low bins, divided
//!   by ω_q², amplify it, so x is distorted near the record's ends and by a slow ramp.
//!
//! Records that are not periodic (the non-periodic mode) have no whole periods: there
//! the drift of the integrals is treated by a zero-phase high-pass the user sets
//! ([`Integration::HighPass`], `high_pass` in `[non_periodic]`). The signal, less its
//! mean, is extended evenly (s_{2N−1−i} = s_i, continuous at both ends, so no jump
//! spreads over the spectrum), transformed over 2N samples, and every bin is weighted
//! by G(ω) = 1/(1 + (ω_c/|ω|)⁴) (the gain of a second-order Butterworth high-pass run
//! forward and backward: no phase shift) before integrating as above; the first N
//! samples are kept. A displacement channel is kept as measured and its v is the
//! central difference (one-sided at the ends). What it biases: content below
//! f_c = ω_c/2π is removed (at f_c half of it, G = ½): a slow motion, a static
//! displacement, a mean velocity; between f_c and about 3 f_c the amplitudes are
//! reduced (G(3ω_c) = 0.988) and near the ends of the record the even extension bends
//! the integrals over about 1/f_c. Choose f_c well below the slowest motion of interest
//! and the windows well inside the record.
//!
//! The noise-robust pipeline does not read this reconstruction: it projects the measured
//! signals on the drive's harmonics over each window and integrates per harmonic
//! ([`crate::regressor::robust`]). The other velocity sources, the steady-state check,
//! POD, and the plots read the x and v reconstructed here.

use faer::{Mat, MatRef};
use rustfft::FftPlanner;
use rustfft::num_complex::Complex;

use crate::error::{Error, Result, check_finite};
use crate::record::{Forcing, MeasuredMotion, Record, RecordParts, Sensor};

/// How velocity and acceleration channels are integrated.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub enum Integration {
    /// Over the record's whole periods of the drive (periodic records; see the module doc).
    #[default]
    WholePeriods,
    /// Over the whole record with a zero-phase high-pass of cut-off frequency `cutoff`
    /// (cycles per time unit), for records that are not periodic.
    HighPass {
        /// f_c > 0, below the Nyquist frequency 1/(2h).
        cutoff: f64,
    },
}

/// The parts of a record sensed by any sensors. Pass to [`record_from_sensors`].
#[derive(Debug, Clone)]
pub struct SensorParts {
    /// A label for reports and errors.
    pub label: String,
    /// Sampling step h > 0.
    pub step: f64,
    /// Time of the first sample.
    pub start_time: f64,
    /// N × n measured motion, column j in the units of `sensors[j]`.
    pub motion: Mat<f64>,
    /// What each DOF's channel measures.
    pub sensors: Vec<Sensor>,
    /// Applied force channels.
    pub forcing: Forcing,
    /// Driving period T > 0 (for a non-periodic record, any positive value).
    pub period: f64,
    /// How velocity and acceleration channels are integrated.
    pub integration: Integration,
}

/// `records` integrated again as `integration` says, where they were built from velocity
/// or acceleration sensors ([`Record::measured_motion`]); `None` when none was (every
/// record is then as it is). A program that built its records for whole periods
/// identifies them over fixed spans this way (the zero-phase high-pass of the
/// non-periodic mode; a model file's `[non_periodic] high_pass`).
pub fn reintegrated(records: &[Record], integration: Integration) -> Result<Option<Vec<Record>>> {
    if records.iter().all(|r| r.measured_motion().is_none()) {
        return Ok(None);
    }
    records
        .iter()
        .map(|r| match r.measured_motion() {
            None => Ok(r.clone()),
            Some(motion) => record_from_sensors(SensorParts {
                label: r.label().to_string(),
                step: r.step(),
                start_time: r.start_time(),
                motion: motion.signals.clone(),
                sensors: motion.sensors.clone(),
                forcing: r.forcing().clone(),
                period: r.period(),
                integration,
            }),
        })
        .collect::<Result<Vec<_>>>()
        .map(Some)
}

/// A record from any sensors: a plain [`Record::new`] when every sensor is a
/// displacement (bit for bit), else displacements and velocities reconstructed by
/// [`integrate`] with the measured signals kept ([`Record::measured_motion`]).
pub fn record_from_sensors(parts: SensorParts) -> Result<Record> {
    let SensorParts {
        label,
        step,
        start_time,
        motion,
        sensors,
        forcing,
        period,
        integration,
    } = parts;
    if sensors.len() != motion.ncols() {
        return Err(Error::mismatch(
            "sensors vs motion columns",
            motion.ncols(),
            sensors.len(),
        ));
    }
    let build = |displacements, velocities| {
        Record::new(RecordParts {
            label: label.clone(),
            step,
            start_time,
            displacements,
            velocities,
            forcing: forcing.clone(),
            period,
        })
    };
    if sensors.iter().all(|s| *s == Sensor::Displacement) {
        return build(motion, None);
    }
    if !(step.is_finite() && step > 0.0) {
        return Err(Error::invalid("step", step, "must be finite and positive"));
    }
    if !(period.is_finite() && period > 0.0) {
        return Err(Error::invalid(
            "period",
            period,
            "must be finite and positive",
        ));
    }
    check_finite("measured motion", motion.as_ref())?;
    let (x, v) = match integration {
        Integration::WholePeriods => integrate(motion.as_ref(), &sensors, step, period, &label)?,
        Integration::HighPass { cutoff } => {
            if !(cutoff.is_finite() && cutoff > 0.0 && cutoff < 0.5 / step) {
                return Err(Error::invalid(
                    "high_pass",
                    cutoff,
                    &format!(
                        "the cut-off frequency must be positive and below the Nyquist frequency {}",
                        0.5 / step
                    ),
                ));
            }
            integrate_high_pass(motion.as_ref(), &sensors, step, cutoff)
        }
    };
    build(x, Some(v))?.with_measured_motion(MeasuredMotion {
        sensors,
        signals: motion,
    })
}

/// The samples M = round(P T/h) of the P = ⌊N h/T⌋ whole periods of N samples (at most
/// N); a record shorter than one period is too short.
pub fn whole_period_samples(samples: usize, step: f64, period: f64, label: &str) -> Result<usize> {
    let per_period = period / step;
    let periods = ((samples as f64 + 1e-9) / per_period).floor();
    if periods < 1.0 {
        return Err(Error::RecordTooShort {
            record: label.to_string(),
            needed: per_period.ceil() as usize,
            available: samples,
        });
    }
    Ok(((periods * per_period).round() as usize).clamp(3, samples))
}

/// Displacements and velocities (N × n each) of the signals `motion` measured by
/// `sensors`, integrated over the record's whole periods (see the module doc).
pub fn integrate(
    motion: MatRef<'_, f64>,
    sensors: &[Sensor],
    step: f64,
    period: f64,
    label: &str,
) -> Result<(Mat<f64>, Mat<f64>)> {
    let (samples, n) = motion.shape();
    let m = whole_period_samples(samples, step, period, label)?;
    let mut planner = FftPlanner::<f64>::new();
    let forward = planner.plan_fft_forward(m);
    let inverse = planner.plan_fft_inverse(m);
    let mut x = Mat::zeros(samples, n);
    let mut v = Mat::zeros(samples, n);
    let mut spectrum = vec![Complex::new(0.0, 0.0); m];
    let mut xs = vec![Complex::new(0.0, 0.0); m];
    let mut vs = vec![Complex::new(0.0, 0.0); m];
    let base = 2.0 * std::f64::consts::PI / (m as f64 * step);
    let zero = Complex::new(0.0, 0.0);
    for (j, sensor) in sensors.iter().enumerate().take(n) {
        for (i, s) in spectrum.iter_mut().enumerate() {
            *s = Complex::new(motion[(i, j)], 0.0);
        }
        forward.process(&mut spectrum);
        for q in 0..m {
            let signed = signed_bin(q, m);
            let nyquist = 2 * q == m;
            let s = spectrum[q];
            let i_omega = Complex::new(0.0, base * signed);
            (xs[q], vs[q]) = match sensor {
                _ if q == 0 && *sensor != Sensor::Displacement => (zero, zero),
                Sensor::Displacement if q == 0 || nyquist => (s, zero),
                Sensor::Displacement => (s, i_omega * s),
                _ if nyquist => (zero, zero),
                Sensor::Velocity => (s / i_omega, s),
                Sensor::Acceleration => (s / (i_omega * i_omega), s / i_omega),
            };
        }
        inverse.process(&mut xs);
        inverse.process(&mut vs);
        let scale = 1.0 / m as f64;
        for i in 0..samples {
            x[(i, j)] = if *sensor == Sensor::Displacement {
                motion[(i, j)]
            } else {
                xs[i % m].re * scale
            };
            v[(i, j)] = vs[i % m].re * scale;
        }
    }
    Ok((x, v))
}

/// Displacements and velocities (N × n each) of `motion` measured by `sensors`, over the
/// whole record with a zero-phase high-pass of cut-off `cutoff` (see the module doc).
pub fn integrate_high_pass(
    motion: MatRef<'_, f64>,
    sensors: &[Sensor],
    step: f64,
    cutoff: f64,
) -> (Mat<f64>, Mat<f64>) {
    let (samples, n) = motion.shape();
    let m = 2 * samples;
    let mut planner = FftPlanner::<f64>::new();
    let forward = planner.plan_fft_forward(m);
    let inverse = planner.plan_fft_inverse(m);
    let mut x = Mat::zeros(samples, n);
    let mut v = Mat::zeros(samples, n);
    let zero = Complex::new(0.0, 0.0);
    let mut spectrum = vec![zero; m];
    let mut xs = vec![zero; m];
    let mut vs = vec![zero; m];
    let base = 2.0 * std::f64::consts::PI / (m as f64 * step);
    let omega_c = 2.0 * std::f64::consts::PI * cutoff;
    for (j, sensor) in sensors.iter().enumerate().take(n) {
        if *sensor == Sensor::Displacement {
            for i in 0..samples {
                x[(i, j)] = motion[(i, j)];
                let (a, b) = (i.saturating_sub(1), (i + 1).min(samples - 1));
                v[(i, j)] = (motion[(b, j)] - motion[(a, j)]) / ((b - a) as f64 * step);
            }
            continue;
        }
        let mean = (0..samples).map(|i| motion[(i, j)]).sum::<f64>() / samples as f64;
        for i in 0..samples {
            let s = Complex::new(motion[(i, j)] - mean, 0.0);
            spectrum[i] = s;
            spectrum[m - 1 - i] = s;
        }
        forward.process(&mut spectrum);
        for q in 0..m {
            let signed = signed_bin(q, m);
            if q == 0 || 2 * q == m {
                (xs[q], vs[q]) = (zero, zero);
                continue;
            }
            let omega = base * signed;
            let gain = 1.0 / (1.0 + (omega_c / omega).powi(4));
            let s = spectrum[q] * gain;
            let i_omega = Complex::new(0.0, omega);
            (xs[q], vs[q]) = match sensor {
                Sensor::Velocity => (s / i_omega, s),
                _ => (s / (i_omega * i_omega), s / i_omega),
            };
        }
        inverse.process(&mut xs);
        inverse.process(&mut vs);
        for i in 0..samples {
            x[(i, j)] = xs[i].re / m as f64;
            v[(i, j)] = vs[i].re / m as f64;
        }
    }
    (x, v)
}

/// The signed frequency index of FFT bin `q` of `m`: q below m/2, q − m above.
fn signed_bin(q: usize, m: usize) -> f64 {
    if 2 * q < m {
        q as f64
    } else {
        q as f64 - m as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// x = cos ωt + 0.3 sin 3ωt sampled at T/h = 64 over 5 periods; its velocity and
    /// acceleration integrate back to x (no mean) and v exactly, to round-off, since
    /// each harmonic sits on a bin.
    #[test]
    fn harmonics_on_bins_integrate_exactly() {
        let (h, per) = (0.05, 64usize);
        let period = h * per as f64;
        let omega = 2.0 * std::f64::consts::PI / period;
        let samples = 5 * per + 10;
        let t = |i: usize| i as f64 * h;
        let x = |t: f64| (omega * t).cos() + 0.3 * (3.0 * omega * t).sin();
        let v = |t: f64| -omega * (omega * t).sin() + 0.9 * omega * (3.0 * omega * t).cos();
        let a = |t: f64| {
            -omega * omega * (omega * t).cos() - 2.7 * omega * omega * (3.0 * omega * t).sin()
        };
        let motion = Mat::from_fn(samples, 3, |i, j| match j {
            0 => x(t(i)) + 2.0,
            1 => v(t(i)) + 0.5,
            _ => a(t(i)) - 0.1,
        });
        let sensors = [Sensor::Displacement, Sensor::Velocity, Sensor::Acceleration];
        let (xr, vr) = integrate(motion.as_ref(), &sensors, h, period, "test").unwrap();
        for i in 0..samples {
            // the displacement channel keeps its mean; the others lose theirs
            assert!((xr[(i, 0)] - x(t(i)) - 2.0).abs() < 1e-12);
            for j in 0..3 {
                assert!((vr[(i, j)] - v(t(i))).abs() < 1e-11, "v {i} {j}");
            }
            for j in 1..3 {
                assert!((xr[(i, j)] - x(t(i))).abs() < 1e-12, "x {i} {j}");
            }
        }
    }

    /// A burst that is not periodic over the record: a(t) = ẍ of x = e^{−((t−10)/2)²}
    /// over 20 time units. With f_c = 0.01 (ten times below the burst's content) the
    /// high-passed integrals match x − mean and ẋ to a few 10⁻³ of their peak away from
    /// the ends.
    #[test]
    fn high_pass_integration_recovers_a_burst() {
        let h = 0.01;
        let samples = 2001;
        let t = |i: usize| i as f64 * h;
        let x = |t: f64| (-((t - 10.0) / 2.0).powi(2)).exp();
        let v = |t: f64| -2.0 * (t - 10.0) / 4.0 * x(t);
        let a = |t: f64| {
            let u = (t - 10.0) / 2.0;
            (4.0 * u * u - 2.0) / 4.0 * x(t)
        };
        let motion = Mat::from_fn(samples, 2, |i, j| if j == 0 { v(t(i)) } else { a(t(i)) });
        let (xr, vr) = integrate_high_pass(
            motion.as_ref(),
            &[Sensor::Velocity, Sensor::Acceleration],
            h,
            0.01,
        );
        for j in 0..2 {
            let offset = (500..1500).map(|i| xr[(i, j)] - x(t(i))).sum::<f64>() / 1000.0;
            for i in 500..1500 {
                assert!((vr[(i, j)] - v(t(i))).abs() < 3e-3, "v {i} {j}");
                assert!((xr[(i, j)] - x(t(i)) - offset).abs() < 1e-2, "x {i} {j}");
            }
        }
    }

    #[test]
    fn a_record_shorter_than_a_period_is_too_short() {
        let motion = Mat::<f64>::zeros(50, 1);
        let err = integrate(motion.as_ref(), &[Sensor::Acceleration], 0.1, 6.0, "r").unwrap_err();
        assert!(matches!(
            err,
            Error::RecordTooShort {
                needed: 60,
                available: 50,
                ..
            }
        ));
    }
}
