//! Stepped-sine tables as measured: points grouped in sweeps (one force or response
//! level each), with the noise of every point's force amplitude a, response
//! amplitudes X_i and phase lags φ_i, given per point or estimated from the scatter
//! along each sweep.
//!
//! **Scatter along a sweep.** Along one sweep, sorted by frequency ω, ln a, ln X_i and
//! the (unwrapped) lag φ_i are smooth functions of ω plus noise. Three neighbouring
//! points give the pseudo-residual of Gasser, Sroka and Jennen-Steinmetz (1986),
//!
//! ```text
//!   ε_k = α_k y_{k−1} + β_k y_{k+1} − y_k,
//!   α_k = (ω_{k+1} − ω_k)/(ω_{k+1} − ω_{k−1}),   β_k = (ω_k − ω_{k−1})/(ω_{k+1} − ω_{k−1}),
//! ```
//!
//! which removes any straight line through the three points, so that for independent
//! noise of standard deviation σ, Var ε_k = (α_k² + β_k² + 1) σ². The estimate is
//! robust (a resonance peak between two points gives a few large ε):
//!
//! ```text
//!   σ = 1.4826 · median_k |ε_k| / √(α_k² + β_k² + 1),
//! ```
//!
//! one σ per quantity and sweep, a relative σ for a and X_i (noise on the logarithm)
//! and an absolute one for φ_i. A sweep needs at least three points for it; a sweep with
//! fewer (two points kept near resonance) takes the pooled scatter of the others,
//! σ² = Σ_s (n_s − 2) σ_s² / Σ_s (n_s − 2) over the sweeps of three points or more
//! (the same instrument measured them), and is named in [`SweptTable::pooled`]. Only a
//! table without any sweep of three points is refused.
//!
//! **Duplicated points.** Two points that agree in every value to the last bit (ω, the
//! force's DOF and amplitude, every X_i and φ_i) are one measurement written twice: a
//! repeated measurement never agrees to 16 digits. Each copy would count as an
//! independent equation (the χ² check's degrees of freedom and every standard error
//! wrong), and copies appended after a sweep wreck its scatter (a table written twice
//! over gave standard errors 30 000 times too large with "χ² check passes"). Such a
//! table is refused, naming the two points.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::prep::harmonic::table::SteppedSineTable;

/// Standard deviations of one point's measured values (in the table's units).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointNoise {
    /// σ of the force amplitude a.
    pub force: f64,
    /// σ of each DOF's response amplitude X_i.
    pub amplitudes: Vec<f64>,
    /// σ of each DOF's phase lag φ_i (rad).
    pub phases: Vec<f64>,
}

/// Where the noise of the points comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum NoiseOrigin {
    /// Given per point in the table.
    Given,
    /// Estimated from the scatter along each sweep (module doc).
    SweepScatter,
}

/// A stepped-sine table with its sweeps and the noise of every point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweptTable {
    /// The points.
    pub table: SteppedSineTable,
    /// The sweep of each point (an index into `sweep_names`).
    pub sweeps: Vec<usize>,
    /// The name of each sweep.
    pub sweep_names: Vec<String>,
    /// The noise of each point.
    pub noise: Vec<PointNoise>,
    /// Where the noise came from.
    pub noise_origin: NoiseOrigin,
    /// The sweeps (indices) too short for their own scatter, given the pooled scatter
    /// of the others (module doc).
    #[serde(default)]
    pub pooled: Vec<usize>,
}

impl SweptTable {
    /// A table whose noise is given per point. Checks the lengths and that every σ is
    /// finite and nonnegative.
    pub fn with_noise(
        table: SteppedSineTable,
        sweeps: Vec<usize>,
        sweep_names: Vec<String>,
        noise: Vec<PointNoise>,
    ) -> Result<Self> {
        check_sweeps(&table, &sweeps, &sweep_names)?;
        if noise.len() != table.points().len() {
            return Err(Error::mismatch(
                "noise entries vs stepped-sine points",
                table.points().len(),
                noise.len(),
            ));
        }
        for (index, n) in noise.iter().enumerate() {
            let label = &table.points()[index].label;
            let values = std::iter::once(n.force)
                .chain(n.amplitudes.iter().copied())
                .chain(n.phases.iter().copied());
            if n.amplitudes.len() != table.dofs() || n.phases.len() != table.dofs() {
                return Err(Error::mismatch(
                    format!("noise DOFs of stepped-sine point {index} ('{label}')"),
                    table.dofs(),
                    n.amplitudes.len().min(n.phases.len()),
                ));
            }
            for value in values {
                if !(value.is_finite() && value >= 0.0) {
                    return Err(Error::invalid(
                        &format!(
                            "noise standard deviation of stepped-sine point {index} ('{label}')"
                        ),
                        value,
                        "must be finite and nonnegative",
                    ));
                }
            }
        }
        Ok(SweptTable {
            table,
            sweeps,
            sweep_names,
            noise,
            noise_origin: NoiseOrigin::Given,
            pooled: Vec::new(),
        })
    }

    /// A table whose noise is estimated from the scatter along each sweep (module doc).
    pub fn from_scatter(
        table: SteppedSineTable,
        sweeps: Vec<usize>,
        sweep_names: Vec<String>,
    ) -> Result<Self> {
        check_sweeps(&table, &sweeps, &sweep_names)?;
        let points = table.points();
        let dofs = table.dofs();
        let mut noise = vec![
            PointNoise {
                force: 0.0,
                amplitudes: vec![0.0; dofs],
                phases: vec![0.0; dofs],
            };
            points.len()
        ];
        // Each sweep's scatter (relative σ of a, then of each X_j, then σ of each φ_j),
        // None for a sweep of fewer than three points.
        let mut scatters: Vec<Option<(usize, Vec<f64>)>> = Vec::with_capacity(sweep_names.len());
        for s in 0..sweep_names.len() {
            let mut members: Vec<usize> = (0..points.len()).filter(|&i| sweeps[i] == s).collect();
            if members.len() < 3 {
                scatters.push(None);
                continue;
            }
            members.sort_by(|&a, &b| points[a].frequency.total_cmp(&points[b].frequency));
            let omega: Vec<f64> = members.iter().map(|&i| points[i].frequency).collect();
            let log = |value: &dyn Fn(usize) -> f64| -> Vec<f64> {
                members
                    .iter()
                    .map(|&i| value(i).max(f64::MIN_POSITIVE).ln())
                    .collect()
            };
            let mut sigma = vec![scatter(&omega, &log(&|i| points[i].force_amplitude))];
            for j in 0..dofs {
                sigma.push(scatter(&omega, &log(&|i| points[i].amplitudes[j])));
            }
            for j in 0..dofs {
                let phase = unwrap(members.iter().map(|&i| points[i].phases[j]));
                sigma.push(scatter(&omega, &phase));
            }
            scatters.push(Some((members.len() - 2, sigma)));
        }
        // The pooled scatter of the sweeps that have their own.
        let weight: usize = scatters.iter().flatten().map(|(w, _)| w).sum();
        if weight == 0 {
            let name = &sweep_names[0];
            return Err(Error::choice(
                "stepped-sine noise",
                format!(
                    "sweep '{name}' with {} point(s)",
                    sweeps.iter().filter(|&&s| s == 0).count()
                ),
                "the scatter along a sweep needs at least 3 points in one sweep at least (a shorter sweep takes the pooled scatter of the others); give the noise per point (force_std, amplitude_std, phase_std columns)",
            ));
        }
        let pooled: Vec<f64> = (0..1 + 2 * dofs)
            .map(|q| {
                let sum: f64 = scatters
                    .iter()
                    .flatten()
                    .map(|(w, sigma)| *w as f64 * sigma[q] * sigma[q])
                    .sum();
                (sum / weight as f64).sqrt()
            })
            .collect();
        let short: Vec<usize> = (0..sweep_names.len())
            .filter(|&s| scatters[s].is_none())
            .collect();
        for (i, point) in points.iter().enumerate() {
            let sigma = scatters[sweeps[i]].as_ref().map_or(&pooled, |(_, s)| s);
            noise[i].force = sigma[0] * point.force_amplitude;
            for j in 0..dofs {
                noise[i].amplitudes[j] = sigma[1 + j] * point.amplitudes[j];
                noise[i].phases[j] = sigma[1 + dofs + j];
            }
        }
        Ok(SweptTable {
            table,
            sweeps,
            sweep_names,
            noise,
            noise_origin: NoiseOrigin::SweepScatter,
            pooled: short,
        })
    }

    /// The points of sweep `s`, in table order.
    pub fn members(&self, s: usize) -> Vec<usize> {
        (0..self.sweeps.len())
            .filter(|&i| self.sweeps[i] == s)
            .collect()
    }
}

/// One sweep index per point, each below the number of names, every sweep non-empty,
/// and no point written twice (module doc).
fn check_sweeps(table: &SteppedSineTable, sweeps: &[usize], names: &[String]) -> Result<()> {
    let mut seen = std::collections::HashMap::new();
    for (i, p) in table.points().iter().enumerate() {
        let key: Vec<u64> = [p.frequency, p.force_amplitude, p.force_dof as f64]
            .iter()
            .chain(&p.amplitudes)
            .chain(&p.phases)
            .map(|x| x.to_bits())
            .collect();
        if let Some(first) = seen.insert(key, i) {
            let points = table.points();
            return Err(Error::choice(
                "stepped-sine points",
                format!(
                    "'{}' and '{}' (points {} and {})",
                    points[first].label,
                    p.label,
                    first + 1,
                    i + 1
                ),
                "the two points agree in every value (frequency, force, amplitudes, phases) to the last digit: one measurement written twice, which would count as two independent equations (wrong degrees of freedom and standard errors); remove the copy",
            ));
        }
    }
    if sweeps.len() != table.points().len() {
        return Err(Error::mismatch(
            "sweep indices vs stepped-sine points",
            table.points().len(),
            sweeps.len(),
        ));
    }
    for (s, name) in names.iter().enumerate() {
        if !sweeps.contains(&s) {
            return Err(Error::Empty {
                what: format!("sweep '{name}'"),
            });
        }
    }
    if let Some(&bad) = sweeps.iter().find(|&&s| s >= names.len()) {
        return Err(Error::invalid(
            "sweep index",
            bad as f64,
            &format!("there are {} sweeps", names.len()),
        ));
    }
    Ok(())
}

/// Lags unwrapped along the sweep (each within π of the previous one).
fn unwrap(phases: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for phi in phases {
        let value = match out.last() {
            Some(&previous) => previous + crate::prep::fourier::wrap_phase(phi - previous),
            None => phi,
        };
        out.push(value);
    }
    out
}

/// The robust pseudo-residual σ of `y` over `x` (sorted ascending), module doc.
pub(crate) fn scatter(x: &[f64], y: &[f64]) -> f64 {
    let mut normalised: Vec<f64> = (1..x.len().saturating_sub(1))
        .map(|k| {
            let span = x[k + 1] - x[k - 1];
            let (alpha, beta) = if span > 0.0 {
                ((x[k + 1] - x[k]) / span, (x[k] - x[k - 1]) / span)
            } else {
                (0.5, 0.5)
            };
            let e = alpha * y[k - 1] + beta * y[k + 1] - y[k];
            e.abs() / (alpha * alpha + beta * beta + 1.0).sqrt()
        })
        .collect();
    if normalised.is_empty() {
        return 0.0;
    }
    normalised.sort_by(f64::total_cmp);
    let n = normalised.len();
    let median = if n.is_multiple_of(2) {
        0.5 * (normalised[n / 2 - 1] + normalised[n / 2])
    } else {
        normalised[n / 2]
    };
    1.4826 * median
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A straight line has no scatter: every pseudo-residual is exactly zero.
    #[test]
    fn a_line_has_no_scatter() {
        let x = [1.0, 1.5, 3.0, 3.5, 5.0];
        let y: Vec<f64> = x.iter().map(|x| 2.0 - 0.7 * x).collect();
        assert!(scatter(&x, &y) < 1e-15);
    }

    /// Alternating ±δ on equally spaced points: ε = ±(δ + δ) ... every |ε| = 2δ·(…)
    /// by hand: y = (δ, −δ, δ, …), α = β = ½, ε = ½δ + ½δ + δ = 2δ in magnitude,
    /// c = √(¼ + ¼ + 1) = √1.5, so σ = 1.4826 · 2δ/√1.5.
    #[test]
    fn alternating_noise_by_hand() {
        let delta = 0.01;
        let x: Vec<f64> = (0..9).map(|k| k as f64).collect();
        let y: Vec<f64> = (0..9)
            .map(|k| if k % 2 == 0 { delta } else { -delta })
            .collect();
        let expected = 1.4826 * 2.0 * delta / 1.5f64.sqrt();
        assert!((scatter(&x, &y) - expected).abs() < 1e-15);
    }
}
