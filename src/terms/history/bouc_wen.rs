//! The Bouc–Wen element: force α z with the hysteretic displacement z,
//!
//! ```text
//!   ż = A v − β |v| |z|^{n−1} z − γ v |z|^n,      f = α z,
//! ```
//!
//! v = ẋ the element's relative velocity. α is the linear coefficient (the term's
//! column); β, γ, n are shape parameters. A and α are not separately identifiable from
//! the force alone (A → kA, z → kz, β → β/kⁿ, γ → γ/kⁿ, α → α/k gives the same f), so
//! A = 1: z is in displacement units, α is a stiffness, and z saturates at
//! z_max = (β + γ)^{−1/n} on a long monotone excursion.
//!
//! Rate independence: dividing by v (dx = v dt),
//!
//! ```text
//!   dz/dx = g(z, σ) = 1 − (β σ sgn z + γ) |z|ⁿ,      σ = sgn(dx),
//! ```
//!
//! so between two samples the state follows the straight displacement path x0 → x1
//! with σ fixed; it is integrated in x by the classical fourth-order Runge–Kutta rule
//! on sub-steps of at most z_max/20 (local error O(δx⁵) per sub-step, fourth order in
//! the sample spacing). Needs n ≥ 1 (g is then continuous at z = 0), β + γ > 0
//! (z bounded on loading) and z_max ≥ 1e-280 (representable sub-steps).
//!
//! Run time does not grow with β: a sample that moves the element by many z_max
//! (β ≫ 1/|dx|ⁿ) would take |dx|/z_max · 20 sub-steps, but z reaches the fixed point of
//! g (dz/dx = 0: z = σ z_max on loading when γ ≤ β, linearised decay length z_max/n)
//! within a few hundred of them, so a step of more than 1000 sub-steps stops at the
//! first sub-step that leaves z unchanged to round-off; the rest would not change it.

use crate::error::Result;

use super::{Hysteresis, require};

/// Bouc–Wen with A = 1: z in displacement units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoucWen {
    beta: f64,
    gamma: f64,
    n: f64,
    /// Largest sub-step in x: z_max / 20.
    max_step: f64,
}

/// Sub-steps per z_max of displacement.
const SUBSTEPS_PER_ZMAX: f64 = 20.0;

/// A step of more sub-steps than this stops once z has settled (`step`).
const SETTLE_AFTER: u64 = 1000;

/// Sub-step counts up to this are uniform partitions of the step.
const MAX_UNIFORM: f64 = 4_294_967_296.0;

/// The smallest saturation displacement z_max integrated: below it the sub-steps
/// z_max / 20 approach the smallest normal f64.
const MIN_Z_MAX: f64 = 1e-280;

impl BoucWen {
    /// Shape parameters β, γ (β + γ > 0) and n ≥ 1.
    pub fn new(beta: f64, gamma: f64, n: f64) -> Result<Self> {
        require("bouc_wen", "beta", beta, true, "a finite number")?;
        require("bouc_wen", "gamma", gamma, true, "a finite number")?;
        require(
            "bouc_wen",
            "beta",
            beta,
            beta + gamma > 0.0,
            &format!(
                "β + γ must be positive (here γ = {gamma}): otherwise z grows without bound on loading"
            ),
        )?;
        require(
            "bouc_wen",
            "n",
            n,
            (1.0..=50.0).contains(&n),
            "the exponent n must be in [1, 50]",
        )?;
        let z_max = (beta + gamma).powf(-1.0 / n);
        require(
            "bouc_wen",
            "beta",
            beta,
            z_max >= MIN_Z_MAX,
            &format!(
                "the saturation displacement z_max = (β + γ)^(−1/n) = {} is below {MIN_Z_MAX:e}, too small to integrate in floating point; express the displacements in smaller units (µm instead of m divides β + γ by 10⁶ⁿ)",
                crate::format::number(z_max)
            ),
        )?;
        Ok(BoucWen {
            beta,
            gamma,
            n,
            max_step: z_max / SUBSTEPS_PER_ZMAX,
        })
    }

    /// β.
    pub fn beta(&self) -> f64 {
        self.beta
    }
    /// γ.
    pub fn gamma(&self) -> f64 {
        self.gamma
    }
    /// n.
    pub fn n(&self) -> f64 {
        self.n
    }

    /// dz/dx at z moving in direction σ.
    fn slope(&self, z: f64, sigma: f64) -> f64 {
        let power = z.abs().powf(self.n);
        let sign = if z > 0.0 {
            1.0
        } else if z < 0.0 {
            -1.0
        } else {
            0.0
        };
        1.0 - (self.beta * sigma * sign + self.gamma) * power
    }
}

impl Hysteresis for BoucWen {
    fn kind(&self) -> &'static str {
        "bouc_wen"
    }

    fn name(&self) -> String {
        format!("bouc_wen(β={}, γ={}, n={})", self.beta, self.gamma, self.n)
    }

    fn state_len(&self) -> usize {
        1
    }

    fn start(&self, _x: f64, state: &mut [f64]) {
        state[0] = 0.0;
    }

    fn step(&self, state: &mut [f64], x0: f64, x1: f64) {
        let dx = x1 - x0;
        if dx == 0.0 {
            return;
        }
        let sigma = dx.signum();
        let substeps = (dx.abs() / self.max_step).ceil().max(1.0);
        // Beyond SETTLE_AFTER sub-steps a sample moves the element many z_max: z
        // settles on the fixed point of g within a few hundred sub-steps (module doc),
        // after which the remaining ones (β large: up to 10²⁹⁸) change nothing; the
        // loop stops once a sub-step leaves z unchanged to round-off. Uniform sub-steps
        // of dx / substeps while that is a representable count, else of z_max / 20.
        let (h, count) = if substeps <= MAX_UNIFORM {
            (dx / substeps, substeps as u64)
        } else {
            (sigma * self.max_step, u64::MAX)
        };
        let settle = count > SETTLE_AFTER;
        let mut z = state[0];
        for _ in 0..count {
            let k1 = self.slope(z, sigma);
            let k2 = self.slope(z + 0.5 * h * k1, sigma);
            let k3 = self.slope(z + 0.5 * h * k2, sigma);
            let k4 = self.slope(z + h * k3, sigma);
            let next = z + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            let still = (next - z).abs() <= f64::EPSILON * next.abs();
            z = next;
            if settle && still {
                break;
            }
        }
        state[0] = z;
    }

    fn force(&self, state: &[f64], _x: f64) -> f64 {
        state[0]
    }

    fn state_scale(&self, amplitude: f64) -> f64 {
        amplitude
            .min(SUBSTEPS_PER_ZMAX * self.max_step)
            .max(f64::MIN_POSITIVE)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With β = 0 the loading branch from z = 0 solves dz/dx = 1 − γ zⁿ; for n = 1,
    /// z(x) = (1 − e^{−γx})/γ (separable ODE).
    #[test]
    fn loading_branch_matches_the_closed_form() {
        let element = BoucWen::new(0.0, 2.0, 1.0).unwrap();
        let mut state = [0.0];
        let mut x = 0.0;
        for _ in 0..50 {
            element.step(&mut state, x, x + 0.02);
            x += 0.02;
        }
        let exact = (1.0 - (-2.0 * x).exp()) / 2.0;
        assert!((state[0] - exact).abs() < 1e-8, "{} vs {exact}", state[0]);
    }

    /// A huge β (z_max ≪ the step) settles on z_max in bounded work: β = 1e270 with
    /// n = 1 would otherwise take 10²⁷¹ sub-steps per sample. Beyond z_max = 1e-280 the
    /// element is refused with the unit advice.
    #[test]
    fn a_huge_beta_saturates_quickly() {
        for beta in [1e6, 1e12, 1e270] {
            let element = BoucWen::new(beta, 0.0, 1.0).unwrap();
            let z_max = 1.0 / beta;
            let mut state = [0.0];
            element.step(&mut state, 0.0, 0.5);
            assert!(
                (state[0] - z_max).abs() <= 1e-12 * z_max,
                "{beta}: {}",
                state[0]
            );
            element.step(&mut state, 0.5, -0.5);
            assert!(
                (state[0] + z_max).abs() <= 1e-12 * z_max,
                "{beta}: {}",
                state[0]
            );
        }
        assert!(BoucWen::new(f64::MAX, 0.0, 1.0).is_err());
        let e = BoucWen::new(1e300, 0.0, 1.0).unwrap_err();
        assert!(e.to_string().contains("smaller units"), "{e}");
    }

    #[test]
    fn refuses_unbounded_shapes() {
        assert!(BoucWen::new(0.5, -0.5, 1.0).is_err());
        assert!(BoucWen::new(1.0, 0.0, 0.5).is_err());
        assert!(BoucWen::new(f64::NAN, 0.0, 1.0).is_err());
    }
}
