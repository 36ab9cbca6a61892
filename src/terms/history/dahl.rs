//! The Dahl friction element. Dahl's law dF/dt = σ v (1 − (F/F_c) sgn v)^i, written
//! with F = F_c ẑ and x_c = F_c/σ (the displacement over which the force builds up), is
//!
//! ```text
//!   dẑ/dx = (1 − ẑ σ_x)^i / x_c,      σ_x = sgn(dx),      F = F_c ẑ,
//! ```
//!
//! so F_c (the Coulomb force it tends to) is the linear coefficient and x_c and i
//! (default 1) are shape parameters; |ẑ| ≤ 1.
//!
//! Exact step. Along a monotone path of length L = |x1 − x0| put u = 1 − σ_x ẑ ≥ 0:
//! du/dL = −u^i / x_c, so
//!
//! ```text
//!   i = 1:   u1 = u0 e^{−L/x_c};
//!   i ≠ 1:   u1^{1−i} = u0^{1−i} − (1 − i) L / x_c      (u1 = 0 once the right side ≤ 0, i < 1),
//! ```
//!
//! and ẑ1 = σ_x (1 − u1). No discretisation error beyond the straight path between
//! samples.

use crate::error::Result;

use super::{Hysteresis, require};

/// Dahl's element, force per unit F_c.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dahl {
    x_c: f64,
    exponent: f64,
}

impl Dahl {
    /// x_c = F_c/σ > 0 and the exponent i in (0, 10].
    pub fn new(x_c: f64, exponent: f64) -> Result<Self> {
        require(
            "dahl",
            "x_c",
            x_c,
            x_c > 0.0,
            "x_c = F_c/σ must be positive",
        )?;
        require(
            "dahl",
            "exponent",
            exponent,
            exponent > 0.0 && exponent <= 10.0,
            "the exponent i must be in (0, 10]",
        )?;
        Ok(Dahl { x_c, exponent })
    }

    /// x_c.
    pub fn x_c(&self) -> f64 {
        self.x_c
    }
    /// i.
    pub fn exponent(&self) -> f64 {
        self.exponent
    }
}

impl Hysteresis for Dahl {
    fn kind(&self) -> &'static str {
        "dahl"
    }

    fn name(&self) -> String {
        format!("dahl(x_c={}, i={})", self.x_c, self.exponent)
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
        let length = dx.abs() / self.x_c;
        let u0 = (1.0 - sigma * state[0]).max(0.0);
        let i = self.exponent;
        let u1 = if i == 1.0 {
            u0 * (-length).exp()
        } else if u0 == 0.0 {
            0.0
        } else {
            let power = u0.powf(1.0 - i) - (1.0 - i) * length;
            if power <= 0.0 {
                0.0
            } else {
                power.powf(1.0 / (1.0 - i))
            }
        };
        state[0] = sigma * (1.0 - u1);
    }

    fn force(&self, state: &[f64], _x: f64) -> f64 {
        state[0]
    }

    fn state_scale(&self, _amplitude: f64) -> f64 {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The exact step composes: one step of length 2L equals two of length L, and for
    /// i = 2 the closed form u = 1/(1 + L/x_c) from u0 = 1.
    #[test]
    fn steps_compose_and_match_the_closed_form() {
        for i in [0.5, 1.0, 2.0] {
            let d = Dahl::new(0.1, i).unwrap();
            let (mut one, mut two) = ([0.0], [0.0]);
            d.step(&mut one, 0.0, 0.06);
            d.step(&mut two, 0.0, 0.03);
            d.step(&mut two, 0.03, 0.06);
            assert!((one[0] - two[0]).abs() < 1e-14, "i = {i}");
        }
        let d = Dahl::new(0.1, 2.0).unwrap();
        let mut z = [0.0];
        d.step(&mut z, 0.0, 0.3);
        assert!((z[0] - (1.0 - 1.0 / (1.0 + 3.0))).abs() < 1e-14);
    }
}
