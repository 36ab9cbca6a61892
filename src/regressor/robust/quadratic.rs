//! Viscous elements (power v², [`PowerForm::Square`]) of the noise-robust rows in the
//! projection coefficients, without a pass over the window's samples per element.
//!
//! **The column.** An element's relative velocity is the series v̂_e = D c with
//! c = c_a − c_b (c_a alone to ground), so its weighted power over the window is a
//! quadratic form in c:
//!
//! ```text
//!   Σ_i w_i v̂_{e,i}² = cᵀ M c,   M = Σ_i w_i d_i d_iᵀ = Dᵀ W D   (p × p, once per window),
//! ```
//!
//! and its expected noise contribution, Σ_i w_i Var v̂_{e,i} (the linear law's bias is σ_v²
//! exactly), is Σ over the ends j of σ_j² Σ_i w_i ‖R⁻ᵀ S_jᵀ d_i‖² = σ_j² tr(M C_j), with
//! C_j = S_j (RᵀR)⁻¹ S_jᵀ the unit covariance of the channel's displacement coefficients
//! (one per sensor kind, [`ProjectedWindow::unit_covariance`]). The column is
//! cᵀ M c − Σ_j σ_j² tr(M C_j): the sum the sample path forms, term for term, with the
//! sums over samples taken once per window instead of once per element.
//!
//! **Its gradient.** ∂(cᵀ M c)/∂c_a = 2 M c and ∂/∂c_b = −2 M c, the sensitivities the
//! row's noise model whitens (what the sample path gathers as Dᵀ (2 W v̂_e)).
//!
//! Cost: M is one p × p product over the window's samples (O(m p²)); then O(p²) per
//! element, where the sample path took O(m) per element in the column, its slopes and
//! their gather, and needed every channel's x̂ and v̂ formed (O(m p) per channel). On a
//! 100-DOF chain of 201 viscous elements (m = 401, p = 5) that was about a third of the
//! rows' instructions. The structural-damping column (`structural.rs`) is the same
//! construction with the rotated Gram matrix.

use crate::regressor::robust::gradients::Gradients;
use crate::regressor::robust::projected::{ProjectedWindow, signed_ends};
use crate::terms::{ElementTerm, OnElements, PowerForm};

/// Whether `term`'s columns are quadratic forms in the projection coefficients: a law
/// of power v² that does not read the displacement.
pub(super) fn applies(term: &ElementTerm) -> bool {
    let law = term.law();
    law.power_form() == Some(PowerForm::Square) && !law.uses_displacement()
}

/// Adds the columns of the viscous element term `term` (its first column `first`,
/// [`applies`]) of the window `projected`, read with `weights`, to `columns`, less their
/// expected noise contribution (channel noise `sigma`), and their gradients to
/// `gradients`.
pub(super) fn add_columns(
    term: &ElementTerm,
    projected: &ProjectedWindow,
    weights: &[f64],
    sigma: &[f64],
    first: usize,
    columns: &mut [f64],
    gradients: &mut Gradients,
) {
    let m = projected.weighted_gram(weights, true);
    let p = m.nrows();
    let mut slope = vec![0.0; p];
    let mut c = vec![0.0; p];
    // tr(M C_j) per sensor kind, M being the window's
    let mut traces = [None; 3];
    for (e, element) in term.elements().iter().enumerate() {
        let weight = term.weights().map_or(1.0, |w| w[e]);
        let column = first + term.coefficients().column_of(e);
        let ends = signed_ends(element);
        projected.combination_into(&ends, &mut c);
        // 2 M c and cᵀ M c
        let mut value = 0.0;
        for (j, s) in slope.iter_mut().enumerate() {
            let row: f64 = (0..p).map(|l| m[(j, l)] * c[l]).sum();
            value += c[j] * row;
            *s = 2.0 * row;
        }
        let mut bias = 0.0;
        for &(j, _) in &ends {
            let variance = sigma[j] * sigma[j];
            if variance != 0.0 {
                bias += variance * projected.covariance_trace_in(&mut traces, &m, j);
            }
        }
        columns[column] += weight * (value - bias);
        for &(j, sign) in &ends {
            gradients.add(j, column + 1, &slope, sign * weight);
        }
    }
}
