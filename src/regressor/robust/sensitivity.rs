//! First-order noise sensitivity of one equation. With whitened vectors
//! z_{j,0} = σ_j R⁻ᵀ ∂b/∂c_j and z_{j,k} = σ_j R⁻ᵀ ∂A_k/∂c_j for channel j,
//!
//! ```text
//!   Var e(θ) = Σ_j ‖z_{j,0} − Σ_k θ_k z_{j,k}‖² + (force noise term),
//! ```
//!
//! with e = b − Σ θ_k A_k the equation's residual.

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
    /// Variance of the input work from force-channel noise.
    pub force_variance: f64,
}

impl RowNoise {
    /// Var e(θ), the residual's variance at coefficients `theta`.
    pub fn variance(&self, theta: &[f64]) -> f64 {
        let mut total = self.force_variance;
        let mut acc = Vec::new();
        for channel in &self.channels {
            let p = channel
                .input
                .len()
                .max(channel.columns.first().map_or(0, |(_, z)| z.len()));
            acc.clear();
            acc.resize(p, 0.0);
            for (a, z) in acc.iter_mut().zip(&channel.input) {
                *a += z;
            }
            for (k, z) in &channel.columns {
                for (a, z) in acc.iter_mut().zip(z) {
                    *a -= theta[*k] * z;
                }
            }
            total += acc.iter().map(|a| a * a).sum::<f64>();
        }
        total
    }
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
            force_variance: 0.25,
        };
        assert!((row.variance(&[0.5, 2.0]) - (1.0 + 9.0 + 0.25)).abs() < 1e-15);
    }
}
