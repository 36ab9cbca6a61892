//! Structural damping ([`crate::terms::structural`]) in the noise-robust rows: a
//! quadratic form in the element's projection coefficients, its expected noise
//! contribution subtracted, its gradient fed to the row's noise model.
//!
//! **The column.** On the projection the element's deformation is x̂_e = B c and its
//! velocity v̂_e = D c, c = c_a − c_b its relative displacement coefficients (c_b = 0 for
//! an element to ground) in the basis [1, cos k₁ωt, sin k₁ωt, …]. The Hilbert transform
//! of the series is exact and linear: H[x̂_e] = B H c, H rotating every kept harmonic
//! (cos nωt → sin nωt, sin nωt → −cos nωt, the mean → 0), i.e. (Hc)_cos = −c_sin,
//! (Hc)_sin = c_cos, (Hc)_0 = 0. The force per unit loss factor is s_i = −k b_iᵀ H c, so
//!
//! ```text
//!   A_e = Σ_i w_i v̂_e,i s_e,i = −k cᵀ (Σ_i w_i d_i b_iᵀ) H c = k cᵀ N c,
//!   N = −G H,   G = Dᵀ W B = Σ_i w_i d_i b_iᵀ   (p × p, one per window for every element).
//! ```
//!
//! **Its value (by hand).** With exact quadrature over a span T of whole periods, for
//! harmonic n with x = a cos θ + b sin θ (θ = nωt): d = nω(−sin θ, cos θ), so G's 2 × 2
//! block of harmonic n is nωT/2 [[0, −1], [1, 0]] (rows: d of cos, d of sin; columns:
//! cos, sin; ∫ sin² = ∫ cos² = T/2, ∫ sin cos = 0) and zero across harmonics and with the
//! mean; H's block is [[0, −1], [1, 0]] (new cos = −b, new sin = a); their product is
//! −nωT/2 I₂, so N = diag(0, …, nωT/2 I₂, …) and
//!
//! ```text
//!   A_e = k Σ_n (nωT/2)(a_n² + b_n²) = π k Σ_n n (a_n² + b_n²)  per period (ωT = 2π),
//! ```
//!
//! the work [`crate::terms::structural`] derives from the complex stiffness, and what
//! the plain rows' FFT gives on the same (noise-free, band-limited) motion.
//!
//! **Its noise contribution.** Noise on the channels gives c + δc with E δc = 0 and
//! Cov δc = Σ_e = σ_a² C_a + σ_b² C_b, C_j = S_j (RᵀR)⁻¹ S_jᵀ the unit covariance of
//! channel j's displacement coefficients (S_j = I for a displacement sensor; the two
//! ends' noises independent). Then
//!
//! ```text
//!   E[k (c + δc)ᵀ N (c + δc)] = k cᵀ N c + k E[δcᵀ N δc] = A_e + k tr(N_sym Σ_e),
//! ```
//!
//! (the cross term has zero mean; tr(N Σ) = tr(N_sym Σ), N_sym = (N + Nᵀ)/2, for
//! symmetric Σ), and the column is k cᵀ N c − k tr(N Σ_e), as the laws subtract
//! [`crate::terms::Law::noise_bias`]. On whole periods with (RᵀR)⁻¹ = diag(1/m, 2/m, …)
//! (m samples, h = T/m) the bias is k σ² Σ_n (nωT/2)(2 · 2/m) = 2kωh σ² Σ_n n: per
//! harmonic (4/m) σ²/(a_n² + b_n²) of that harmonic's column, small on long windows and
//! exactly what the mean over many noise draws shows (tests/structural_noise.rs).
//!
//! **Its gradient.** ∂A_e/∂c = k (N + Nᵀ) c, so ∂A_e/∂c_a = k (N + Nᵀ) c and
//! ∂A_e/∂c_b = −k (N + Nᵀ) c, the sensitivities the row's first-order noise model whitens
//! (module doc of [`crate::regressor::robust`]).
//!
//! Cost: G is one p × p product over the window's samples (O(m p²)), then O(p²) per
//! element for the value and gradient, and O(p³) for C_j once per sensor kind (p = 2K + 1).

use crate::terms::OnElements;
use faer::Mat;

use crate::regressor::robust::gradients::Gradients;
use crate::regressor::robust::projected::{ProjectedWindow, signed_ends};
use crate::terms::StructuralDamping;

/// N = −(Σ_i w_i d_i b_iᵀ) H of the window (module doc): p × p.
fn rotated_gram(projected: &ProjectedWindow, weights: &[f64]) -> Mat<f64> {
    let p = projected.columns();
    let g = projected.weighted_gram(weights, false);
    // (G H)_{j,cos} = G_{j,sin}, (G H)_{j,sin} = −G_{j,cos}, (G H)_{j,0} = 0; N = −G H
    let mut n = Mat::<f64>::zeros(p, p);
    for j in 0..p {
        for q in 0..(p - 1) / 2 {
            let (cos, sin) = (2 * q + 1, 2 * q + 2);
            n[(j, cos)] = -g[(j, sin)];
            n[(j, sin)] = g[(j, cos)];
        }
    }
    n
}

/// Adds the columns of structural-damping term `term` (its first column `first`) of
/// the window `projected`, read with `weights`, to `columns`, less their expected noise
/// contribution (channel noise `sigma`), and their gradients to `gradients`.
pub(super) fn add_columns(
    term: &StructuralDamping,
    projected: &ProjectedWindow,
    weights: &[f64],
    sigma: &[f64],
    first: usize,
    columns: &mut [f64],
    gradients: &mut Gradients,
) {
    let n = rotated_gram(projected, weights);
    let p = n.nrows();
    let mut c = vec![0.0; p];
    // tr(N C_j) per sensor kind, N being the window's
    let mut traces = [None; 3];
    for (index, (element, &k)) in term.elements().iter().zip(term.stiffness()).enumerate() {
        let column = first + term.column_of(index);
        let ends = signed_ends(element);
        projected.combination_into(&ends, &mut c);
        // (N + Nᵀ) c and cᵀ N c
        let mut sym_c = vec![0.0; p];
        let mut value = 0.0;
        for j in 0..p {
            let mut row = 0.0;
            for l in 0..p {
                row += n[(j, l)] * c[l];
                sym_c[j] += (n[(j, l)] + n[(l, j)]) * c[l];
            }
            value += c[j] * row;
        }
        // tr(N Σ_e), Σ_e = Σ over the ends of σ_j² C_j
        let mut bias = 0.0;
        for &(j, _) in &ends {
            let variance = sigma[j] * sigma[j];
            if variance == 0.0 {
                continue;
            }
            bias += variance * projected.covariance_trace_in(&mut traces, &n, j);
        }
        columns[column] += k * (value - bias);
        for &(j, sign) in &ends {
            gradients.add(j, column + 1, &sym_c, sign * k);
        }
    }
}
