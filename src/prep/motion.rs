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
//! The noise-robust pipeline does not read this reconstruction: it projects the measured
//! signals on the drive's harmonics over each window and integrates per harmonic
//! ([`crate::regressor::robust`]). The other velocity sources, the steady-state check,
//! POD, and the plots read the x and v reconstructed here.

use faer::{Mat, MatRef};
use rustfft::FftPlanner;
use rustfft::num_complex::Complex;

use crate::error::{Error, Result, check_finite};
use crate::record::{Forcing, MeasuredMotion, Record, RecordParts, Sensor};

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
    /// Driving period T > 0.
    pub period: f64,
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
    let (x, v) = integrate(motion.as_ref(), &sensors, step, period, &label)?;
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
            let signed = if 2 * q < m {
                q as f64
            } else {
                q as f64 - m as f64
            };
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
