//! The weighted velocity Gram matrix of a window,
//!
//! ```text
//!   G = Vᵀ W V = Σ_i w_i v_i v_iᵀ     (n × n, symmetric),
//! ```
//!
//! for matrix terms with a dense C₀ (each column is then tr(C₀ᵀ G)). Formed block by
//! block, G += V_bᵀ (W_b V_b), by faer's matrix product on its lower triangle only, with
//! one scratch block of weighted velocities: no copy of the whole window. The product is
//! sequential (`Par::Seq`): windows already run in parallel, and faer's own split follows
//! the thread count and would change the rounding.

use faer::linalg::matmul::triangular::{BlockStructure, matmul};
use faer::{Accum, Mat, MatRef, Par};

use crate::prep::quadrature::WindowWeights;
use crate::record::col;
use crate::terms::Weights;

/// Scratch size in f64 for the weighted block W_b V_b (8 MiB).
const SCRATCH: usize = 1 << 20;

/// G = Vᵀ W V for the window's velocities `v` (m × n) and weights `w` (m); only the
/// lower triangle (row ≥ column) is filled.
pub(crate) fn weighted_gram(v: MatRef<'_, f64>, w: &WindowWeights) -> Mat<f64> {
    let (m, n) = v.shape();
    let mut gram = Mat::<f64>::zeros(n, n);
    let block = (SCRATCH / n.max(1)).clamp(64, m.max(1));
    let mut weighted = Mat::<f64>::zeros(block, n);
    for start in (0..m).step_by(block) {
        let rows = block.min(m - start);
        for j in 0..n {
            let source = col(v, j);
            let target = weighted.col_as_slice_mut(j);
            for piece in w.pieces(start..start + rows) {
                let (from, to) = (piece.rows.start, piece.rows.end);
                let target = &mut target[from - start..to - start];
                match piece.weights {
                    Weights::Uniform(w) => {
                        for (t, s) in target.iter_mut().zip(&source[from..to]) {
                            *t = w * s;
                        }
                    }
                    Weights::PerSample(w) => {
                        for ((t, s), w) in target.iter_mut().zip(&source[from..to]).zip(w) {
                            *t = w * s;
                        }
                    }
                }
            }
        }
        matmul(
            gram.as_mut(),
            BlockStructure::TriangularLower,
            Accum::Add,
            v.subrows(start, rows).transpose(),
            BlockStructure::Rectangular,
            weighted.as_ref().subrows(0, rows),
            BlockStructure::Rectangular,
            1.0,
            Par::Seq,
        );
    }
    gram
}
