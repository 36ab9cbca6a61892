//! The fused window kernel: every term's columns and the input work of one window in a
//! single pass over its samples,
//!
//! ```text
//!   A_k = Σ_i w_i v(t_i)ᵀ f_k(x(t_i), v(t_i)),     b = Σ_i w_i v(t_i)ᵀ r(t_i),
//! ```
//!
//! instead of one pass per term. `plan.rs` lists the weighted sums the row needs (one
//! per element, per Gram entry of a sparse matrix term, per force channel) in the order
//! that reads each velocity column once; `pass.rs` evaluates them block by block in
//! parallel with a fixed reduction order, the sums of one column in one loop
//! (`fused.rs`); `gram.rs` forms G = Vᵀ W V for dense matrix
//! terms. Force channels that are zero over the whole record are never read.

mod fused;
mod gram;
mod log_speed;
mod pass;
mod plan;

use faer::MatRef;

use crate::prep::quadrature::WindowWeights;
use crate::record::Record;

pub(crate) use log_speed::log_speed;
pub(crate) use plan::Plan;

/// The samples of one window that the kernel reads: displacements and velocities
/// (m × n), the force signals (m × c), all column-major, and the quadrature weights (m).
pub(crate) struct WindowSamples<'a> {
    pub(crate) x: MatRef<'a, f64>,
    pub(crate) v: MatRef<'a, f64>,
    pub(crate) signals: MatRef<'a, f64>,
    pub(crate) weights: &'a WindowWeights,
}

/// Whether building the rows of `records` with `columns` coefficients is worth spreading
/// over rayon's pool (see [`pass::worth_parallel`]); small builds run on the calling
/// thread.
pub(crate) fn build_in_parallel(records: &[Record], columns: usize) -> bool {
    let sample_sums = records
        .iter()
        .map(|r| {
            r.samples()
                .saturating_mul(columns + r.forcing().signals.ncols())
        })
        .fold(0usize, usize::saturating_add);
    pass::worth_parallel(sample_sums)
}

impl Plan<'_> {
    /// The regressor row (one value per coefficient) and the input work of one window.
    pub(crate) fn row(&self, samples: &WindowSamples<'_>) -> (Vec<f64>, f64) {
        let sums = pass::window_sums(self, samples);
        let gram = self
            .needs_gram()
            .then(|| gram::weighted_gram(samples.v, samples.weights));
        self.combine(&sums, gram.as_ref())
    }
}
