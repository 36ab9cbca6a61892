//! A window's sums with every power law on a DOF to ground read from the logarithm of
//! the speed, computed once per record, instead of from the speed:
//!
//! ```text
//!   Σ_i w_i |v_i|^q  =  Σ_i w_i exp(q ℓ_i),     ℓ_i = ln|v_i|   (exp(q · −∞) = 0 at rest, q > 0),
//! ```
//!
//! for the law's power form g(v) = |v|^q ([`PowerForm::AbsPow`], a power law
//! f = |v|^(q−1) sgn v). When the exponent is estimated, variable projection rebuilds
//! the regressor at every trial exponent over the same samples: `powf` (a logarithm and
//! an exponential per sample) becomes one exponential per sample, the logarithms made
//! once. The sum differs from the kernel's `powf` sum by round-off only (the relative
//! error of exp(q ℓ) is about |q ℓ| ε, a few ε).
//!
//! Every other sum (a closed form other than `AbsPow`, a law that reads x, a dashpot
//! between DOFs, a Gram entry, a force's work) is the kernel's own, block by block as
//! [`super::pass::window_sums`] adds them, so its value is bitwise the one
//! [`Plan::row`] gives.

use std::ops::Range;

use crate::regressor::kernel::plan::{Plan, Sum};
use crate::regressor::kernel::{WindowSamples, pass};
use crate::terms::PowerForm;
use crate::terms::lanes;

/// ln|v| of every sample of one velocity column (−∞ where v = 0).
pub(crate) fn log_speed(v: &[f64]) -> Vec<f64> {
    v.iter().map(|v| v.abs().ln()).collect()
}

impl Plan<'_> {
    /// The regressor row and input work of one window, as [`Plan::row`] gives them,
    /// with the power laws on a DOF to ground summed from `logs[j]` = ln|v_j| over the
    /// window's rows (`logs` one column per DOF, each as long as the window, or empty for
    /// a DOF that no such law reads).
    pub(crate) fn row_from_logs(
        &self,
        samples: &WindowSamples<'_>,
        logs: &[&[f64]],
    ) -> (Vec<f64>, f64) {
        debug_assert!(
            !self.needs_gram(),
            "a mode's record has one DOF, no Gram path"
        );
        let m = samples.weights.len();
        let block_len = *pass::BLOCK_SIZE;
        let sums: Vec<f64> = self
            .sums
            .iter()
            .map(|sum| {
                let mut total = 0.0;
                for start in (0..m).step_by(block_len) {
                    let rows = start..(start + block_len).min(m);
                    total += match power_of_log(sum, logs) {
                        Some((q, log)) => log_sum(q, log, samples, rows),
                        None => pass::block_sum(sum, samples, rows),
                    };
                }
                total
            })
            .collect();
        self.combine(&sums, None)
    }
}

/// The exponent q and the log column of a sum that is |v_a|^q on a DOF to ground.
fn power_of_log<'l>(sum: &Sum<'_>, logs: &[&'l [f64]]) -> Option<(f64, &'l [f64])> {
    match *sum {
        Sum::Power { law, a, b: None } => match law.power_form() {
            Some(PowerForm::AbsPow(q)) if q > 0.0 => {
                logs.get(a).filter(|l| !l.is_empty()).map(|l| (q, *l))
            }
            _ => None,
        },
        _ => None,
    }
}

/// Σ_{i ∈ rows} w_i exp(q ℓ_i), piece by piece of the weights, the pieces added as the
/// kernel adds them.
fn log_sum(q: f64, log: &[f64], samples: &WindowSamples<'_>, rows: Range<usize>) -> f64 {
    samples
        .weights
        .pieces(rows)
        .map(|piece| lanes::sum(piece.weights, &log[piece.rows], |l| (q * l).exp()))
        .sum()
}
