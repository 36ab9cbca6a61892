//! Velocities for a window's samples: measured, or estimated from displacements.
//!
//! - **Central differences**: v_i = (x_{i+1} − x_{i−1}) / 2h, second order, using the
//!   record's samples just outside the window when they exist and the one-sided
//!   second-order forms (∓3x_i ± 4x_{i±1} ∓ x_{i±2}) / 2h at the record's ends. The
//!   error on a harmonic of frequency kω is a relative −(kωh)²/6.
//! - **Spectral**: the derivative of the least-squares Fourier series in the harmonics
//!   of the driving frequency fitted over the window (see `src/prep/fourier/`). Exact for
//!   periodic, band-limited motion whether or not the period is a whole number of
//!   samples; with K below the default it also low-pass filters sensor noise.
//! - **Harmonic projection**: the window's whole periods t_0 .. t_0 + kT (k = the
//!   periods the quadrature rule spans, ⌊kT/h⌋ + 1 samples) are projected by least
//!   squares onto a Fourier series in harmonics of ω = 2π/T,
//!
//!   ```text
//!     x(t) ≈ a_0 + Σ_{q ∈ S} (a_q cos qωt + b_q sin qωt),
//!     v(t) = Σ_{q ∈ S} qω (b_q cos qωt − a_q sin qωt),
//!   ```
//!
//!   and the series' derivative is evaluated at every sample the rule reads. When the
//!   window holds a whole number of samples per period the projection (and the noise
//!   floor) is read off one real FFT per channel, the same coefficients to round-off
//!   (`src/prep/fourier/dft.rs` derives why). With
//!   `harmonics: Some(K)`, S = {1..K}. With `harmonics: None`, S is chosen from the
//!   noise floor of the window ([`harmonic_selection`]): fit every harmonic up to
//!   K_max = 45% of Nyquist; per displacement channel, estimate the per-bin noise
//!   amplitude σ̂_A from the median power of the out-of-band harmonics 2..K_max,
//!   σ̂_A² = median P_q / ln 2 (the median of an exponential is its mean times ln 2;
//!   the few harmonics that carry signal do not move a median), floored at 10⁻¹² of the
//!   channel's largest harmonic for round-off; keep harmonic q when its amplitude
//!   A_q = √(a_q² + b_q²) exceeds 3.5 σ̂_A in any channel, and always keep the
//!   fundamental. A noise-only harmonic passes with probability e^{−3.5²} ≈ 5·10⁻⁶, so
//!   S holds the harmonics the motion really has, and noise in the others is dropped:
//!   for white displacement noise σ the velocity noise is σ ω √(Σ_{q∈S} q² · 2/m)
//!   instead of ≈ σ/(h√2) for central differences. `docs/velocities.md` compares the
//!   three estimators on noisy data.
//!
//! A window that closes periodically ([`crate::prep::window::periodic_closure`]: its
//! L = kT/h samples end with the record, and the sample at t_0 + kT is the one at t_0)
//! is read through [`VelocitySource::velocities_of`]:
//!
//! - central differences wrap around at both ends of the window,
//!   v_i = (x_{(i+1) mod L} − x_{(i−1) mod L}) / 2h (window indices), so v_0 reads
//!   x_{L−1} for the sample before t_0 and v_{L−1} reads x_0 for the one at kT: the
//!   periodic central difference, second order everywhere with the same −(kωh)²/6 and
//!   no one-sided end;
//! - spectral and harmonic projection fit their series over exactly the L samples of
//!   the k periods, where the harmonic basis is discretely orthogonal (the truncated
//!   DFT), instead of the ⌊kT/h⌋ + 1 samples that hold the closing one twice;
//! - measured velocities are read as they are.

use faer::{Mat, MatRef};
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::prep::fourier::{
    HarmonicBasis, WholePeriods, WholeSampleDft, default_harmonics, first_orders, select_harmonics,
    select_with_spectrum,
};
use crate::prep::window::Window;
use crate::record::{Record, col};

pub use crate::prep::fourier::HarmonicSelection;

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
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum VelocitySource {
    /// The record's measured (or simulated) velocities.
    Measured,
    /// Central differences of the displacements.
    CentralDifference,
    /// Derivative of a least-squares Fourier series in harmonics of the drive.
    /// `harmonics: None` uses 45% of the Nyquist count for the period.
    Spectral {
        /// Number of harmonics K.
        harmonics: Option<usize>,
    },
    /// Derivative of the least-squares projection of the window's whole periods on
    /// harmonics of the drive (the default: with `NoiseTreatment::Auto` it runs the
    /// noise-robust pipeline, see [`crate::regressor::robust`]). `harmonics: None` keeps the harmonics that stand above
    /// the noise floor (see the module doc); `Some(K)` keeps 1..K.
    HarmonicProjection {
        /// Number of harmonics K, or `None` to choose them from the noise floor.
        harmonics: Option<usize>,
    },
}

impl Default for VelocitySource {
    /// Harmonic projection on the harmonics above the noise floor.
    fn default() -> Self {
        VelocitySource::HarmonicProjection { harmonics: None }
    }
}

impl VelocitySource {
    /// The name model files give this source (`velocity = "..."`).
    pub fn name(&self) -> &'static str {
        match self {
            VelocitySource::Measured => "measured",
            VelocitySource::CentralDifference => "central_difference",
            VelocitySource::Spectral { .. } => "spectral",
            VelocitySource::HarmonicProjection { .. } => "harmonic_projection",
        }
    }

    /// Velocities (count × n) for the first `count` samples window `w` of `record` reads
    /// (`count` at most [`Window::samples`] of its rule): those of
    /// [`VelocitySource::window_velocities`], except that central differences wrap around
    /// at both ends of a window that closes periodically (see the module doc).
    pub fn velocities_of<'a>(
        &self,
        record: &'a Record,
        w: &Window,
        count: usize,
    ) -> Result<WindowVelocities<'a>> {
        match (self, w.closed_length(record.step())) {
            (VelocitySource::CentralDifference, Some(length)) => {
                Ok(WindowVelocities::Estimated(periodic_central_differences(
                    record,
                    w.start,
                    length,
                    count,
                    &every_dof(record.dofs()),
                )))
            }
            _ => self.window_velocities(record, w.start, count),
        }
    }

    /// The velocities of the DOFs `dofs` only (count × `dofs.len()`, column q that of
    /// DOF `dofs[q]`, 0-based): bitwise those columns of
    /// [`VelocitySource::velocities_of`]. Central differences (each DOF on its own) are
    /// formed for those DOFs alone, so a check that reads the velocities of the loaded
    /// DOFs of a 100-DOF record differences one column per window, not 100; the other
    /// sources' columns are copied out of theirs.
    pub fn velocities_of_dofs(
        &self,
        record: &Record,
        w: &Window,
        count: usize,
        dofs: &[usize],
    ) -> Result<Mat<f64>> {
        match (self, w.closed_length(record.step())) {
            (VelocitySource::CentralDifference, Some(length)) => Ok(periodic_central_differences(
                record, w.start, length, count, dofs,
            )),
            (VelocitySource::CentralDifference, None) => {
                Ok(central_differences(record, w.start, count, dofs))
            }
            _ => {
                let all = self.velocities_of(record, w, count)?;
                let all = all.as_ref();
                Ok(Mat::from_fn(all.nrows(), dofs.len(), |i, q| {
                    all[(i, dofs[q])]
                }))
            }
        }
    }

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
            VelocitySource::CentralDifference => Ok(WindowVelocities::Estimated(
                central_differences(record, start, count, &every_dof(n)),
            )),
            VelocitySource::Spectral { harmonics } => {
                let omega = 2.0 * std::f64::consts::PI / record.period();
                let k =
                    harmonics.unwrap_or_else(|| default_harmonics(record.period() / record.step()));
                let basis = HarmonicBasis::new(omega, k, record.step(), count)?;
                let v = basis.differentiate(record.displacements().subrows(start, count));
                Ok(WindowVelocities::Estimated(without_round_off(
                    v,
                    record,
                    start,
                    &every_dof(n),
                )))
            }
            VelocitySource::HarmonicProjection { harmonics } => {
                let whole = whole_periods(record, start, count)?;
                let x = record.displacements().subrows(start, whole.samples);
                let (step, period) = (record.step(), record.period());
                let (orders, spectrum) = match harmonics {
                    Some(k) => {
                        let orders = first_orders(k, whole.samples)?;
                        let spectrum = WholeSampleDft::new(x, step, period, whole.periods, k, &[]);
                        (orders, spectrum)
                    }
                    None => {
                        let (selection, spectrum) =
                            select_with_spectrum(x, step, period, whole.periods, 0)?;
                        (selection.kept, spectrum)
                    }
                };
                let omega = 2.0 * std::f64::consts::PI / period;
                let basis = HarmonicBasis::with_orders(omega, orders, step, whole.samples)?;
                let coefficients = match spectrum.filter(|s| s.covers(basis.orders())) {
                    Some(spectrum) => spectrum.fit(basis.orders()),
                    None => basis.fit(x),
                };
                let v = basis.derivative(&coefficients, count);
                Ok(WindowVelocities::Estimated(without_round_off(
                    v,
                    record,
                    start,
                    &every_dof(n),
                )))
            }
        }
    }
}

/// 0, 1, …, n − 1: every DOF of a record of `n`.
fn every_dof(n: usize) -> Vec<usize> {
    (0..n).collect()
}

/// Central differences of the DOFs `dofs` (column q that of DOF `dofs[q]`) for samples
/// `start..start + count` of `record` (module doc), each column on its own.
fn central_differences(record: &Record, start: usize, count: usize, dofs: &[usize]) -> Mat<f64> {
    let x = record.displacements();
    let last = record.samples() - 1;
    let h2 = 2.0 * record.step();
    let mut v = Mat::zeros(count, dofs.len());
    for (q, &j) in dofs.iter().enumerate() {
        let xj = col(x, j);
        let vj = v.col_as_slice_mut(q);
        // The one-sided forms are written in differences, so that a
        // constant signal gives exactly zero (−3a + 4a − a does not).
        for (k, out) in vj.iter_mut().enumerate() {
            let i = start + k;
            *out = if i == 0 {
                (4.0 * (xj[1] - xj[0]) - (xj[2] - xj[0])) / h2
            } else if i == last {
                (4.0 * (xj[last] - xj[last - 1]) - (xj[last] - xj[last - 2])) / h2
            } else {
                (xj[i + 1] - xj[i - 1]) / h2
            };
        }
    }
    without_round_off(v, record, start, dofs)
}

/// Central differences of the DOFs `dofs` over the `length` samples from `start` of
/// `record` closed periodically, v_i = (x_{(i+1) mod L} − x_{(i−1) mod L}) / 2h for
/// i = 0..count.
fn periodic_central_differences(
    record: &Record,
    start: usize,
    length: usize,
    count: usize,
    dofs: &[usize],
) -> Mat<f64> {
    let x = record.displacements();
    let h2 = 2.0 * record.step();
    let mut v = Mat::zeros(count, dofs.len());
    for (q, &j) in dofs.iter().enumerate() {
        let xj = &col(x, j)[start..start + length];
        for (i, out) in v.col_as_slice_mut(q).iter_mut().enumerate() {
            let (next, previous) = ((i + 1) % length, (i + length - 1) % length);
            *out = (xj[next] - xj[previous]) / h2;
        }
    }
    without_round_off(v, record, start, dofs)
}

/// An estimated velocity no larger than this times max|x|/h over the window is the
/// round-off of differentiating a displacement that does not move.
const ROUND_OFF_VELOCITY: f64 = 8.0 * f64::EPSILON;

/// Zeroes the estimated velocities (window rows from `start`; column q that of DOF
/// `dofs[q]`) of every DOF whose displacement does not move beyond round-off: a
/// constant signal (a still DOF, a stuck sensor) then does exactly zero work, instead
/// of round-off velocities that column scaling would turn into a coefficient of any
/// size.
fn without_round_off(mut v: Mat<f64>, record: &Record, start: usize, dofs: &[usize]) -> Mat<f64> {
    let x = record.displacements();
    for (q, &j) in dofs.iter().enumerate() {
        let xj = col(x, j);
        let end = start.saturating_add(v.nrows()).min(xj.len());
        let largest = xj[start.min(end)..end]
            .iter()
            .fold(0.0f64, |m, a| m.max(a.abs()));
        let floor = ROUND_OFF_VELOCITY * largest / record.step();
        let vj = v.col_as_slice_mut(q);
        if vj.iter().all(|a| a.abs() <= floor) {
            vj.fill(0.0);
        }
    }
    v
}

/// The whole periods of the window of `count` samples from `start` of `record`.
fn whole_periods(record: &Record, start: usize, count: usize) -> Result<WholePeriods> {
    if start.saturating_add(count) > record.samples() {
        return Err(Error::RecordTooShort {
            record: record.label().to_string(),
            needed: start.saturating_add(count),
            available: record.samples(),
        });
    }
    WholePeriods::of_window(
        count,
        record.samples() - start,
        record.step(),
        record.period(),
    )
}

/// The harmonics that [`VelocitySource::HarmonicProjection`] with `harmonics: None`
/// keeps for the window of `count` samples from `start` of `record`, with the noise
/// floor and harmonic amplitudes of every displacement channel (see the module doc).
pub fn harmonic_selection(
    record: &Record,
    start: usize,
    count: usize,
) -> Result<HarmonicSelection> {
    let whole = whole_periods(record, start, count)?;
    select_harmonics(
        record.displacements().subrows(start, whole.samples),
        record.step(),
        record.period(),
        whole.periods,
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prep::quadrature::Quadrature;
    use crate::prep::window::WindowSpec;
    use crate::record::{Forcing, RecordParts};

    /// Five DOFs (one still, so its round-off velocities are zeroed), `samples` of
    /// T/h = 64, measured velocities too.
    fn record(samples: usize) -> Record {
        let h = 2.0 * std::f64::consts::PI / 64.0;
        let x = |i: usize, j: usize| match j {
            2 => 0.75,
            _ => (1.0 + j as f64) * (i as f64 * h + 0.3 * j as f64).sin() + 0.01 * i as f64,
        };
        Record::new(RecordParts {
            label: "five".into(),
            step: h,
            start_time: 0.0,
            displacements: Mat::from_fn(samples, 5, x),
            velocities: Some(Mat::from_fn(samples, 5, |i, j| x(i, j) * 0.5)),
            forcing: Forcing::on_dofs(Mat::from_fn(samples, 1, |i, _| (i as f64).cos()), vec![1]),
            period: 2.0 * std::f64::consts::PI,
        })
        .expect("a valid record")
    }

    /// The velocities of some DOFs are bitwise those columns of every DOF's: windows
    /// at the record's start (one-sided form), ending on its last sample, closing
    /// periodically (wrapped differences), a still DOF, DOFs in any order.
    #[test]
    fn velocities_of_some_dofs_are_those_columns() {
        for samples in [128, 129, 200] {
            let record = record(samples);
            let windows = WindowSpec::cycles(1)
                .windows(&record, 0, Quadrature::Trapezoid)
                .expect("windows");
            for w in &windows {
                let count = w.samples(Quadrature::Trapezoid, record.step());
                for source in [
                    VelocitySource::CentralDifference,
                    VelocitySource::Measured,
                    VelocitySource::HarmonicProjection { harmonics: Some(3) },
                ] {
                    let all = source.velocities_of(&record, w, count).expect("velocities");
                    let all = all.as_ref();
                    for dofs in [vec![1], vec![4, 0], vec![2], vec![0, 1, 2, 3, 4], vec![]] {
                        let some = source
                            .velocities_of_dofs(&record, w, count, &dofs)
                            .expect("velocities");
                        assert_eq!(some.shape(), (count, dofs.len()));
                        for (q, &j) in dofs.iter().enumerate() {
                            for i in 0..count {
                                assert_eq!(
                                    some[(i, q)].to_bits(),
                                    all[(i, j)].to_bits(),
                                    "{source:?}, {samples} samples, window {}, DOF {j}, row {i}",
                                    w.index
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}
