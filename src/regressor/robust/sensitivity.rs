//! First-order noise sensitivity of one equation. With whitened vectors
//! z_{j,0} = σ_j R⁻ᵀ ∂b/∂c_j and z_{j,k} = σ_j R⁻ᵀ ∂A_k/∂c_j for channel j,
//!
//! ```text
//!   Var e(θ) = Σ_j ‖z_{j,0} − Σ_k θ_k z_{j,k}‖² + (force noise term),
//! ```
//!
//! with e = b − Σ θ_k A_k the equation's residual.
//!
//! **Scale.** Every entry of a whitened vector is of the size of (noise of x) × (force),
//! s_x s_f, so their squares are of size (s_x s_f)²: data in units that put s_x s_f near
//! 1e-160 (a force and a displacement of 1e-80 each) would square to below the smallest
//! f64 and the variance would read 0, and above 1e154 to infinity. The force term is kept
//! as a standard deviation and [`RowNoise::std`] forms the norm after dividing by the
//! largest entry (as `hypot` does), so the standard deviation of a residual is right
//! wherever it is itself a finite f64: the weighted fit, its χ² and its standard errors
//! are then the same at any data scale.

use serde::{Deserialize, Serialize};

/// The whitened sensitivities of one equation to the noise of one displacement channel.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ChannelSensitivity {
    /// The displacement channel (DOF).
    pub channel: usize,
    /// σ_j R⁻ᵀ ∂b/∂c_j (empty when the input work does not read this channel).
    pub input: Vec<f64>,
    /// (column k, σ_j R⁻ᵀ ∂A_k/∂c_j) for the columns that read this channel.
    pub columns: Vec<(usize, Vec<f64>)>,
}

/// First-order noise sensitivity of one equation's residual.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct RowNoise {
    /// Per displacement channel.
    pub channels: Vec<ChannelSensitivity>,
    /// Standard deviation of the input work from force-channel noise.
    pub force_std: f64,
}

impl RowNoise {
    /// √Var e(θ), the residual's standard deviation at coefficients `theta`, formed
    /// without squaring an entry of the data's size (module doc).
    pub fn std(&self, theta: &[f64]) -> f64 {
        self.std_with(theta, &mut Vec::new())
    }

    /// [`RowNoise::std`] with `buffer` as its scratch (cleared first): the same numbers,
    /// in the same order, without an allocation per row when one buffer serves many rows
    /// ([`crate::regressor::robust::NoiseModel::residual_std`]).
    pub(crate) fn std_with(&self, theta: &[f64], buffer: &mut Vec<f64>) -> f64 {
        buffer.clear();
        for channel in &self.channels {
            let p = channel
                .input
                .len()
                .max(channel.columns.first().map_or(0, |(_, z)| z.len()));
            let start = buffer.len();
            buffer.resize(start + p, 0.0);
            let acc = &mut buffer[start..];
            for (a, z) in acc.iter_mut().zip(&channel.input) {
                *a += z;
            }
            for (k, z) in &channel.columns {
                for (a, z) in acc.iter_mut().zip(z) {
                    *a -= theta[*k] * z;
                }
            }
        }
        buffer.push(self.force_std);
        norm(buffer)
    }

    /// Var e(θ) = [`RowNoise::std`]², for sums of variances over rows of one size.
    pub fn variance(&self, theta: &[f64]) -> f64 {
        self.std(theta).powi(2)
    }
}

/// ‖values‖₂ without overflow or underflow of the squares: the largest magnitude m
/// times √Σ (v/m)².
pub(crate) fn norm(values: &[f64]) -> f64 {
    let largest = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if largest == 0.0 || !largest.is_finite() {
        return largest;
    }
    largest
        * values
            .iter()
            .map(|v| (v / largest).powi(2))
            .sum::<f64>()
            .sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One channel, b-sensitivity (1, 0), column 0 sensitivity (0, 2), column 1 (1, 1):
    /// at θ = (0.5, 2), the residual's whitened vector is (1 − 2, 0 − 1 − 2) = (−1, −3).
    #[test]
    fn variance_is_the_squared_norm_of_the_combined_sensitivity() {
        let row = RowNoise {
            channels: vec![ChannelSensitivity {
                channel: 0,
                input: vec![1.0, 0.0],
                columns: vec![(0, vec![0.0, 2.0]), (1, vec![1.0, 1.0])],
            }],
            force_std: 0.5,
        };
        assert!((row.variance(&[0.5, 2.0]) - (1.0 + 9.0 + 0.25)).abs() < 1e-14);
        // The same row at the data scales 1e-160 and 1e160: its standard deviation
        // scales exactly where the squares would underflow or overflow.
        for scale in [1e-160, 1e160] {
            let scaled = RowNoise {
                channels: vec![ChannelSensitivity {
                    channel: 0,
                    input: vec![scale, 0.0],
                    columns: vec![(0, vec![0.0, 2.0 * scale]), (1, vec![scale, scale])],
                }],
                force_std: 0.5 * scale,
            };
            let std = scaled.std(&[0.5, 2.0]) / scale;
            assert!((std - 10.25f64.sqrt()).abs() < 1e-14, "{scale}: {std}");
        }
    }
}
