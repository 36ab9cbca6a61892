//! Structural (hysteretic) damping in windows of whole periods: a loss factor η on an
//! element of stiffness k (complex stiffness k(1 + iη)). Per unit η its force is
//!
//! ```text
//!   s(t) = k Σ_n X_n cos(nωt + φ_n + π/2) = −k H[x_e](t),
//! ```
//!
//! the element's deformation x_e(t) = X_0 + Σ_n X_n cos(nωt + φ_n) with every harmonic
//! advanced by a quarter of its own period (H the Hilbert transform, H[cos θ] = sin θ).
//!
//! **Where it comes from.** The complex stiffness acts on each harmonic's phasor
//! X_n e^{iθ_n}, θ_n = nωt + φ_n: Re[k(1 + iη) X_n e^{iθ_n}] = k X_n cos θ_n − ηk X_n sin θ_n.
//! The first part is the elastic force (conservative, in the mass and stiffness the
//! energy balance never needs); the second is η s(t), s = −k Σ_n X_n sin θ_n = −k H\[x_e\].
//!
//! **Its work per window (derived by hand).** With v_e = −Σ_n nω X_n sin θ_n, over the
//! fundamental period T = 2π/ω the cross products of different harmonics vanish and
//! ∫_0^T sin² θ_n dt = T/2, so
//!
//! ```text
//!   ∫_0^T v_e s dt = Σ_n nω k X_n² T/2 = π k Σ_n n X_n²  (> 0: it dissipates).
//! ```
//!
//! Harmonic n alone makes n of its own cycles in T and dissipates π k X_n² in each,
//! whatever its frequency, which is what sets structural damping apart from a viscous
//! dashpot c (π c nω X_n² per cycle of harmonic n). The regressor's column is η's
//! coefficient, Σ_i w_i v_e,i s_i ≈ π k Σ_n n X_n² per period.
//!
//! **How it is computed.** The window's L samples of one run of whole periods (the
//! samples a window closing periodically holds, read as the history terms read them,
//! `regressor/history.rs`) are transformed by one real FFT, X̂_j, j = 0 … ⌊L/2⌋; every
//! bin 0 < j < L/2 is multiplied by +ik (−k H: H multiplies positive frequencies by
//! −i), and the inverse transform gives s_i. As the window holds whole periods, the
//! periodic transform is exact for every harmonic below the Nyquist frequency. Two bins
//! carry no structural force and are set to zero:
//!
//! - the mean (j = 0): a static deformation does no work and H of a constant is 0 (the
//!   complex-stiffness model says nothing at zero frequency);
//! - the Nyquist bin (j = L/2, L even): cos(πi + φ) sampled at the samples i is
//!   cos φ·(−1)^i, whose quarter-period shift sin(πi + φ) vanishes at every sample — the
//!   samples cannot resolve its phase, and its velocity is not resolved either.
//!
//! A window that does not hold L = kT/h whole samples (a period that is not a multiple
//! of the step) is read periodically all the same; its closing jump x_{L−1} → x_0 leaks
//! into the transform, an error that shrinks with the step as the history terms' does.
//!
//! **Where it does not apply.** The force is non-causal in the time domain: H\[x\](t)
//! depends on x at every time of the period, future included, so no time-stepping
//! simulator produces it, and a span that is not whole periods has no harmonics to
//! rotate. The simulator and the non-periodic mode refuse it. The noise-robust rows
//! compute it on the projection instead, as a quadratic form in the element's harmonic
//! coefficients with its expected noise contribution removed
//! (`regressor/robust/structural.rs`).

use crate::terms::on_elements::{Coefficients, OnElements};
use std::cell::RefCell;

use realfft::RealFftPlanner;
use realfft::num_complex::Complex;

use crate::error::{Error, Result};
use crate::terms::element::Element;

thread_local! {
    static PLANNER: RefCell<RealFftPlanner<f64>> = RefCell::new(RealFftPlanner::new());
}

/// The structural-damping force per unit loss factor, s = −k H\[x\], of one period
/// `path` (the samples of a run of whole periods, read periodically) of an element of
/// stiffness `stiffness` (module doc): mean and Nyquist bins give no force.
pub fn force_per_unit_loss(path: &[f64], stiffness: f64) -> Vec<f64> {
    let len = path.len();
    if len < 3 {
        // no bin strictly between the mean and the Nyquist frequency
        return vec![0.0; len];
    }
    let (forward, inverse) = PLANNER.with(|p| {
        let mut p = p.borrow_mut();
        (p.plan_fft_forward(len), p.plan_fft_inverse(len))
    });
    let mut input = path.to_vec();
    let mut spectrum = forward.make_output_vec();
    // cannot fail: realfft errs only on buffer lengths, and these come from the plans
    forward
        .process(&mut input, &mut spectrum)
        .expect("buffers sized by the plan");
    let last = spectrum.len() - 1;
    let scale = stiffness / len as f64;
    for (j, bin) in spectrum.iter_mut().enumerate() {
        let resolved = j > 0 && !(len.is_multiple_of(2) && j == last);
        *bin = if resolved {
            Complex::new(0.0, scale) * *bin
        } else {
            Complex::new(0.0, 0.0)
        };
    }
    let mut out = inverse.make_output_vec();
    // cannot fail: the buffers come from the plan, and the mean and Nyquist bins,
    // whose imaginary parts the inverse requires to be zero, are zero
    inverse
        .process(&mut spectrum, &mut out)
        .expect("buffers sized by the plan");
    out
}

/// Structural damping on elements: a loss factor η (one shared or one per element) on
/// each element of given stiffness, its force per unit η s = −k H\[x_e\] in each window of
/// whole periods (module doc).
#[derive(Debug, Clone)]
pub struct StructuralDamping {
    elements: Vec<Element>,
    stiffness: Vec<f64>,
    coefficients: Coefficients,
}

impl StructuralDamping {
    /// Loss factors on `elements`, element i of stiffness `stiffness[i]`.
    pub fn new(elements: Vec<Element>, stiffness: Vec<f64>, coefficients: Coefficients) -> Self {
        StructuralDamping {
            elements,
            stiffness,
            coefficients,
        }
    }

    /// Each element's stiffness k.
    pub fn stiffness(&self) -> &[f64] {
        &self.stiffness
    }

    pub(crate) fn validate(&self, dofs: usize) -> Result<()> {
        self.validate_elements(dofs, "structural damping term")?;
        if self.stiffness.len() != self.elements.len() {
            return Err(Error::mismatch(
                "structural damping stiffnesses vs elements",
                self.elements.len(),
                self.stiffness.len(),
            ));
        }
        for (element, &k) in self.elements.iter().zip(&self.stiffness) {
            if !(k.is_finite() && k > 0.0) {
                return Err(Error::invalid(
                    &format!("stiffness of structural damping element {}", element.label),
                    k,
                    "a finite stiffness > 0",
                ));
            }
        }
        Ok(())
    }
}

impl OnElements for StructuralDamping {
    fn elements(&self) -> &[Element] {
        &self.elements
    }

    fn coefficients(&self) -> &Coefficients {
        &self.coefficients
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One harmonic: s = −k H[X cos θ] = −k X sin θ, at every sample.
    #[test]
    fn one_harmonic_is_rotated_a_quarter_period() {
        let len = 64;
        let (k, x, phi) = (3.0, 0.7, 0.4);
        let theta = |i: usize| 2.0 * std::f64::consts::PI * 5.0 * i as f64 / len as f64 + phi;
        let path: Vec<f64> = (0..len).map(|i| 2.5 + x * theta(i).cos()).collect();
        let s = force_per_unit_loss(&path, k);
        for (i, s) in s.iter().enumerate() {
            assert!((s + k * x * theta(i).sin()).abs() < 1e-12, "sample {i}");
        }
    }

    /// The mean and the Nyquist bin give no force; too short a path none at all.
    #[test]
    fn mean_and_nyquist_give_nothing() {
        let path: Vec<f64> = (0..8)
            .map(|i| 1.0 + if i % 2 == 0 { 0.3 } else { -0.3 })
            .collect();
        assert!(
            force_per_unit_loss(&path, 2.0)
                .iter()
                .all(|s| s.abs() < 1e-15)
        );
        assert_eq!(force_per_unit_loss(&[1.0, 2.0], 2.0), vec![0.0, 0.0]);
    }
}
