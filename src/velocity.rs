//! Velocities for a window's samples: measured, or estimated from displacements.
//!
//! - **Central differences**: v_i = (x_{i+1} − x_{i−1}) / 2h, second order, using the
//!   record's samples just outside the window when they exist and the one-sided
//!   second-order forms (∓3x_i ± 4x_{i±1} ∓ x_{i±2}) / 2h at the record's ends. The
//!   error on a harmonic of frequency kω is a relative −(kωh)²/6.
//! - **Spectral**: the derivative of the least-squares Fourier series in the harmonics
//!   of the driving frequency fitted over the window (see [`crate::fourier`]). Exact for
//!   periodic, band-limited motion whether or not the period is a whole number of
//!   samples; with K below the default it also low-pass filters sensor noise.

use faer::{Mat, MatRef};
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::fourier::{HarmonicBasis, default_harmonics};
use crate::record::{Record, col};

/// A window's velocities: borrowed from the record when measured, else estimated.
pub enum WindowVelocities<'a> {
    /// A view into the record's measured velocities.
    Measured(MatRef<'a, f64>),
    /// Velocities estimated for this window.
    Estimated(Mat<f64>),
}

impl WindowVelocities<'_> {
    /// The velocities as a view (samples × DOFs).
    pub fn as_ref(&self) -> MatRef<'_, f64> {
        match self {
            WindowVelocities::Measured(v) => *v,
            WindowVelocities::Estimated(v) => v.as_ref(),
        }
    }
}

/// Where the velocities come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VelocitySource {
    /// The record's measured (or simulated) velocities.
    Measured,
    /// Central differences of the displacements.
    #[default]
    CentralDifference,
    /// Derivative of a least-squares Fourier series in harmonics of the drive.
    /// `harmonics: None` uses 45% of the Nyquist count for the period.
    Spectral {
        /// Number of harmonics K.
        harmonics: Option<usize>,
    },
}

impl VelocitySource {
    /// Velocities (count × n) for samples `start..start + count` of `record`.
    pub fn window_velocities<'a>(
        &self,
        record: &'a Record,
        start: usize,
        count: usize,
    ) -> Result<WindowVelocities<'a>> {
        let n = record.dofs();
        match *self {
            VelocitySource::Measured => {
                let v = record
                    .velocities()
                    .ok_or_else(|| Error::MissingVelocities {
                        record: record.label().to_string(),
                    })?;
                Ok(WindowVelocities::Measured(v.subrows(start, count)))
            }
            VelocitySource::CentralDifference => {
                let x = record.displacements();
                let last = record.samples() - 1;
                let h2 = 2.0 * record.step();
                let mut v = Mat::zeros(count, n);
                for j in 0..n {
                    let xj = col(x, j);
                    let vj = v.col_as_slice_mut(j);
                    for (k, out) in vj.iter_mut().enumerate() {
                        let i = start + k;
                        *out = if i == 0 {
                            (-3.0 * xj[0] + 4.0 * xj[1] - xj[2]) / h2
                        } else if i == last {
                            (3.0 * xj[last] - 4.0 * xj[last - 1] + xj[last - 2]) / h2
                        } else {
                            (xj[i + 1] - xj[i - 1]) / h2
                        };
                    }
                }
                Ok(WindowVelocities::Estimated(v))
            }
            VelocitySource::Spectral { harmonics } => {
                let omega = 2.0 * std::f64::consts::PI / record.period();
                let k =
                    harmonics.unwrap_or_else(|| default_harmonics(record.period() / record.step()));
                let basis = HarmonicBasis::new(omega, k, record.step(), count)?;
                Ok(WindowVelocities::Estimated(basis.differentiate(
                    record.displacements().subrows(start, count),
                )))
            }
        }
    }
}
