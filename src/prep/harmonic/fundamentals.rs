//! The fundamental of every DOF and force channel over k whole periods of a window,
//! by least squares on the harmonics of ω = 2π/T (the series of `src/prep/fourier/`):
//!
//! ```text
//!   y(t) ≈ a_0 + Σ_{q=1..K} (a_q cos qωt + b_q sin qωt),   t = record time,
//!   Y = √(a_1² + b_1²),   φ = atan2(b_1, a_1),   so that y ≈ Y cos(ωt − φ) + …,
//! ```
//!
//! fitted over the ⌊kT/h⌋ + 1 samples inside [t_0, t_0 + kT] (over the L = kT/h
//! samples of a window that closes periodically,
//! [`crate::prep::window::periodic_closure`]: a record of exactly k periods from t_0
//! does not hold the sample at kT, which is the one at t_0), with K the default count
//! (45% of Nyquist) so that the higher harmonics of a nonlinear response and a mean
//! offset do not leak into the fundamental when T/h is not an integer. The phase φ is a
//! lag against the record's clock (t = start_time + i h), wrapped into (−π, π].

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::prep::fourier::{HarmonicBasis, Phasor, default_harmonics, wrap_phase};
use crate::prep::window::periodic_closure;
use crate::record::Record;

/// The fundamentals of one window of a record.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Fundamentals {
    /// Driving frequency ω = 2π/T.
    pub frequency: f64,
    /// Record time of the window's first sample.
    pub start_time: f64,
    /// Whole periods fitted.
    pub periods: usize,
    /// Samples fitted.
    pub samples: usize,
    /// Harmonics in the fit.
    pub harmonics: usize,
    /// Fundamental of each DOF's displacement.
    pub displacements: Vec<Phasor>,
    /// Fundamental of each force channel.
    pub forces: Vec<Phasor>,
}

/// Fits the fundamentals over `periods` whole periods of `record` from sample `start`.
pub fn fundamentals(record: &Record, start: usize, periods: usize) -> Result<Fundamentals> {
    if periods == 0 {
        return Err(Error::invalid(
            "periods",
            0.0,
            "a harmonic fit needs at least one whole period",
        ));
    }
    let per_period = record.period() / record.step();
    let length = periods as f64 * per_period;
    let whole = if (length - length.round()).abs() <= 1e-9 * length.max(1.0) {
        length.round()
    } else {
        length.floor()
    };
    // Saturating: an absurd period or start must end in RecordTooShort. A window that
    // closes periodically holds its L whole samples, not the closing one.
    let closed = periodic_closure(record, start, periods as f64 * record.period());
    let samples = (whole as usize).saturating_add(usize::from(!closed));
    let needed = start.saturating_add(samples);
    if needed > record.samples() {
        return Err(Error::RecordTooShort {
            record: record.label().to_string(),
            needed,
            available: record.samples(),
        });
    }
    if samples < 3 {
        return Err(Error::invalid(
            "samples per window",
            samples as f64,
            "a harmonic fit needs at least 3 samples (a mean and one harmonic)",
        ));
    }
    let harmonics = default_harmonics(per_period).min((samples - 1) / 2);
    let omega = 2.0 * std::f64::consts::PI / record.period();
    let basis = HarmonicBasis::new(omega, harmonics, record.step(), samples)?;
    let start_time = record.start_time() + start as f64 * record.step();
    // The basis clock starts at the window: cos(ω(t − t_0) − φ_0) = cos(ωt − (φ_0 + ωt_0)).
    let shift = omega * start_time;
    let absolute = |phasors: Vec<Phasor>| -> Vec<Phasor> {
        phasors
            .into_iter()
            .map(|p| Phasor {
                amplitude: p.amplitude,
                phase: wrap_phase(p.phase + shift),
            })
            .collect()
    };
    let x = record.displacements().subrows(start, samples);
    let displacements = absolute(basis.phasors(&basis.fit(x), 0));
    let signals = record.forcing().signals.as_ref().subrows(start, samples);
    let forces = if signals.ncols() == 0 {
        Vec::new()
    } else {
        absolute(basis.phasors(&basis.fit(signals), 0))
    };
    Ok(Fundamentals {
        frequency: omega,
        start_time,
        periods,
        samples,
        harmonics,
        displacements,
        forces,
    })
}
