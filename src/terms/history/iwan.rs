//! The four-parameter Iwan joint of Segalman (2005, "A four-parameter Iwan model for
//! lap-type joints", J. Appl. Mech. 72, 752–760): a parallel set of Jenkins elements
//! (a unit spring in series with a slider of strength φ) with the slip-strength density
//!
//! ```text
//!   ρ(φ) = R φ^χ [H(φ) − H(φ − φ_max)] + S δ(φ − φ_max),      F(u) = ∫ ρ(φ) (u − p(φ)) dφ,
//! ```
//!
//! p(φ) the slider positions, |u − p(φ)| ≤ φ. Segalman's parameters follow from the
//! density's moments: K_T = ∫ρ = R φ_max^{χ+1}/(χ+1) + S (the joint's stiffness),
//! β = S / (R φ_max^{χ+1}/(χ+1)), F_S = ∫ρ φ = φ_max K_T (β + (χ+1)/(χ+2))/(1 + β) (the
//! force of macroslip). The force scales with K_T at fixed (φ_max, χ, β), so K_T is the
//! term's linear coefficient and φ_max, χ, β are shape parameters (F_S is reported
//! through [`Iwan::slip_force`]).
//!
//! Discretisation. [0, φ_max] is cut into [`SEGMENTS`] geometric intervals
//! [φ_max q^{k+1}, φ_max q^k], q = [`SMALLEST`]^{1/SEGMENTS}, plus [0, φ_max·SMALLEST];
//! each interval is one Jenkins element carrying its exact mass ∫ρ and placed at its
//! centroid ∫ρφ/∫ρ, and S is one more element at φ_max. K_T and F_S are therefore exact.
//! The state is every slider position, advanced exactly by clipping (a Jenkins element
//! on a monotone path u0 → u1 ends at p1 = clamp(p0, u1 − φ, u1 + φ)); no ODE.
//!
//! Error. One Jenkins element of strength φ under a symmetric cycle of amplitude A > φ
//! dissipates 4φ(A − φ) (its loop is a parallelogram of height 2φ and slip 2(A − φ)).
//! Integrated over the density, for A ≤ φ_max (microslip; Segalman's eq. for D):
//!
//! ```text
//!   D(A) = ∫_0^A R φ^χ 4φ(A − φ) dφ = 4R [A·A^{χ+2}/(χ+2) − A^{χ+3}/(χ+3)] = 4R A^{χ+3}/((χ+2)(χ+3)),
//! ```
//!
//! and for A > φ_max, D = 4R[A φ_max^{χ+2}/(χ+2) − φ_max^{χ+3}/(χ+3)] + 4Sφ_max(A − φ_max)
//! ([`Iwan::dissipation`]). The centroid rule makes each fully slipping interval's
//! dissipation 4m(Aφ̄ − φ̄²), short of the exact 4m(Aφ̄ − E\[φ²\]) by 4m·Var(φ) ≤ m(Δφ)²:
//! a relative error O((1 − q)²) ≈ 10⁻³ for every amplitude in [10 SMALLEST, 1]·φ_max;
//! tests/hysteresis.rs checks the discrete loop against D(A) within 1 %.

use crate::error::Result;

use super::{Hysteresis, require};

/// Geometric intervals of the continuous part of the density.
pub const SEGMENTS: usize = 120;

/// The smallest interval edge, as a fraction of φ_max.
pub const SMALLEST: f64 = 1e-3;

/// Segalman's four-parameter Iwan joint per unit K_T.
#[derive(Debug, Clone, PartialEq)]
pub struct Iwan {
    phi_max: f64,
    chi: f64,
    beta: f64,
    /// Slip strength of each Jenkins element (the last is S's, at φ_max).
    strengths: Vec<f64>,
    /// Stiffness of each (sums to 1).
    masses: Vec<f64>,
}

impl Iwan {
    /// φ_max > 0, χ in (−1, 5], β ≥ 0.
    pub fn new(phi_max: f64, chi: f64, beta: f64) -> Result<Self> {
        require(
            "iwan",
            "phi_max",
            phi_max,
            phi_max > 0.0,
            "φ_max must be positive",
        )?;
        require(
            "iwan",
            "chi",
            chi,
            chi > -1.0 && chi <= 5.0,
            "χ must be in (−1, 5] (the density φ^χ must be integrable at 0)",
        )?;
        require(
            "iwan",
            "beta",
            beta,
            (0.0..=1e6).contains(&beta),
            "β must be zero or positive (S = β R φ_max^{χ+1}/(χ+1) is a mass of sliders)",
        )?;
        // Per unit K_T: R φ_max^{χ+1}/(χ+1) = 1/(1+β), S = β/(1+β). With t = φ/φ_max
        // the mass of [a, b] is (t_b^{χ+1} − t_a^{χ+1})/(1+β) and its first moment
        // φ_max (χ+1)/(χ+2) (t_b^{χ+2} − t_a^{χ+2})/(1+β).
        let q = SMALLEST.powf(1.0 / SEGMENTS as f64);
        let mut edges: Vec<f64> = (0..=SEGMENTS).map(|k| q.powi(k as i32)).collect();
        edges.push(0.0);
        let (c1, c2) = (chi + 1.0, chi + 2.0);
        let mut strengths = Vec::with_capacity(SEGMENTS + 2);
        let mut masses = Vec::with_capacity(SEGMENTS + 2);
        for pair in edges.windows(2) {
            let (b, a) = (pair[0], pair[1]);
            let mass = (b.powf(c1) - a.powf(c1)) / (1.0 + beta);
            let moment = phi_max * c1 / c2 * (b.powf(c2) - a.powf(c2)) / (1.0 + beta);
            strengths.push(moment / mass);
            masses.push(mass);
        }
        if beta > 0.0 {
            strengths.push(phi_max);
            masses.push(beta / (1.0 + beta));
        }
        Ok(Iwan {
            phi_max,
            chi,
            beta,
            strengths,
            masses,
        })
    }

    /// φ_max.
    pub fn phi_max(&self) -> f64 {
        self.phi_max
    }
    /// χ.
    pub fn chi(&self) -> f64 {
        self.chi
    }
    /// β.
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// F_S = φ_max K_T (β + (χ+1)/(χ+2))/(1 + β), the macroslip force of a joint of
    /// stiffness `k_t`.
    pub fn slip_force(&self, k_t: f64) -> f64 {
        self.phi_max * k_t * (self.beta + (self.chi + 1.0) / (self.chi + 2.0)) / (1.0 + self.beta)
    }

    /// Segalman's closed-form dissipation per symmetric cycle of amplitude `amplitude`
    /// of the continuous density with stiffness `k_t` (see the module doc).
    pub fn dissipation(&self, k_t: f64, amplitude: f64) -> f64 {
        let (chi, pm) = (self.chi, self.phi_max);
        let r = k_t * (chi + 1.0) / ((1.0 + self.beta) * pm.powf(chi + 1.0));
        let s = k_t * self.beta / (1.0 + self.beta);
        let a = amplitude.abs();
        if a <= pm {
            4.0 * r * a.powf(chi + 3.0) / ((chi + 2.0) * (chi + 3.0))
        } else {
            4.0 * r * (a * pm.powf(chi + 2.0) / (chi + 2.0) - pm.powf(chi + 3.0) / (chi + 3.0))
                + 4.0 * s * pm * (a - pm)
        }
    }
}

impl Hysteresis for Iwan {
    fn kind(&self) -> &'static str {
        "iwan"
    }

    fn name(&self) -> String {
        format!(
            "iwan(φ_max={}, χ={}, β={})",
            self.phi_max, self.chi, self.beta
        )
    }

    fn state_len(&self) -> usize {
        self.strengths.len()
    }

    fn start(&self, x: f64, state: &mut [f64]) {
        state.fill(x);
    }

    fn step(&self, state: &mut [f64], _x0: f64, x1: f64) {
        for (p, &phi) in state.iter_mut().zip(&self.strengths) {
            *p = p.clamp(x1 - phi, x1 + phi);
        }
    }

    fn force(&self, state: &[f64], x: f64) -> f64 {
        state
            .iter()
            .zip(&self.masses)
            .map(|(p, m)| m * (x - p))
            .sum()
    }

    fn state_scale(&self, amplitude: f64) -> f64 {
        amplitude.max(f64::MIN_POSITIVE)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// K_T = 1 and F_S exact: the masses sum to 1, and far beyond macroslip every
    /// slider carries its strength, Σ m φ = F_S(1).
    #[test]
    fn stiffness_and_slip_force_are_exact() {
        let joint = Iwan::new(2e-3, -0.5, 0.3).unwrap();
        let total: f64 = joint.masses.iter().sum();
        assert!((total - 1.0).abs() < 1e-12);
        let mut state = vec![0.0; joint.state_len()];
        joint.start(0.0, &mut state);
        joint.step(&mut state, 0.0, 1.0);
        let force = joint.force(&state, 1.0);
        assert!((force - joint.slip_force(1.0)).abs() < 1e-12 * force);
    }
}
