//! A damping law: the force f(x, v) of one element as a function of its relative
//! displacement x and relative velocity v, and the power it dissipates, v · f(x, v).
//!
//! A law is memoryless: its force at a sample depends on that sample's x and v alone.
//! That is what lets the regressor kernel (`src/regressor/kernel/`) evaluate it block
//! by block, the blocks in parallel and in any order: it calls [`Law::power_sum`] on
//! consecutive runs of samples and adds the results, so a law's sums must be plain sums
//! over the samples they are given. A law whose power has one of the closed forms of
//! [`PowerForm`] says so in [`Law::power_form`], and the kernel then evaluates it in one
//! loop with the other sums of the same velocity column.
//!
//! A new built-in law is one file in `laws/` holding the law, its `impl Law` and its
//! registration (the name model files use, its parameters, its constructor), plus one
//! line in `laws/mod.rs`; a program registers laws of its own at run time
//! (`laws::Registry::with`, then `model_file::parse` with `Options { laws: Some(&registry), .. }`).
//!
//! Where laws end. A force with memory, such as hysteresis and friction with an internal
//! state (Bouc–Wen, Dahl, Iwan/Masing, LuGre), depends on the whole path: a block cannot
//! be evaluated without the state at its first sample. Such a force is not a `Law`, and
//! `Law` gets no state to pretend otherwise: it is a history term
//! ([`crate::terms::history`], [`crate::terms::Term::History`]), whose force per unit
//! coefficient s is computed per window of whole periods on the element's periodic
//! orbit and summed like a force channel, Σ_i w_i v_iᵀ s_i. If f depends on anything
//! but the sample's own x and v, it is a history term.

use std::fmt;

/// A scalar damping law on one element. Coefficients multiply the force; a law has none.
pub trait Law: Send + Sync + fmt::Debug {
    /// A short readable name ("linear", "quadratic", "power(1.5)").
    fn name(&self) -> String;

    /// The damping force per unit coefficient, f(x, v).
    fn force(&self, x: f64, v: f64) -> f64;

    /// Whether f depends on x. When false, [`Law::weighted_power`] receives an empty `x`.
    fn uses_displacement(&self) -> bool {
        false
    }

    /// Σ_i w_i v_i f(x_i, v_i): the window integral of the power per unit coefficient.
    fn weighted_power(&self, x: &[f64], v: &[f64], w: &[f64]) -> f64;

    /// The power p(x, v) = v f(x, v) of one sample.
    fn power(&self, x: f64, v: f64) -> f64 {
        v * self.force(x, v)
    }

    /// Expected change of the power when x and v carry independent zero-mean noise of
    /// variances `var_x` and `var_v`: E[p(x + δx, v + δv)] − p(x, v), to second order.
    /// The default is the three-point Gauss–Hermite rule in each variable,
    /// (p(v + √3σ) − 2 p(v) + p(v − √3σ))/6 (and likewise in x), exact for a power that
    /// is a polynomial of degree ≤ 5 over ±√3σ (v² gives σ², |v|³ gives 3|v|σ² away
    /// from v = 0) and finite across a kink.
    fn noise_bias(&self, x: f64, v: f64, var_x: f64, var_v: f64) -> f64 {
        let p0 = self.power(x, v);
        let mut bias = 0.0;
        if var_v > 0.0 {
            let s = (3.0 * var_v).sqrt();
            bias += (self.power(x, v + s) - 2.0 * p0 + self.power(x, v - s)) / 6.0;
        }
        if var_x > 0.0 && self.uses_displacement() {
            let s = (3.0 * var_x).sqrt();
            bias += (self.power(x + s, v) - 2.0 * p0 + self.power(x - s, v)) / 6.0;
        }
        bias
    }

    /// The slopes (∂p/∂x, ∂p/∂v) of the power, for first-order noise propagation. The
    /// default takes central differences over ±`dx` and ±`dv`, the noise scales, so
    /// that across a kink it averages as the noise does.
    fn power_slope(&self, x: f64, v: f64, dx: f64, dv: f64) -> (f64, f64) {
        let dv = if dv > 0.0 {
            dv
        } else {
            1e-8 * v.abs().max(1e-300)
        };
        let slope_v = (self.power(x, v + dv) - self.power(x, v - dv)) / (2.0 * dv);
        let slope_x = if self.uses_displacement() {
            let dx = if dx > 0.0 {
                dx
            } else {
                1e-8 * x.abs().max(1e-300)
            };
            (self.power(x + dx, v) - self.power(x - dx, v)) / (2.0 * dx)
        } else {
            0.0
        };
        (slope_x, slope_v)
    }

    /// The noise-robust row's sums of one element over a window
    /// (`src/regressor/robust/row.rs`): Σ_i w_i (p(x_i, v_i) − bias_i), bias_i =
    /// [`Law::noise_bias`] at the sample's variances, and the weighted slopes
    /// w_i ∂p/∂x, w_i ∂p/∂v ([`Law::power_slope`] with steps σ_x, σ_v) into `g_x`, `g_v`,
    /// over the samples of `w`. A law need not override it: as a provided method it is
    /// compiled for each law with the per-sample methods called directly (not through
    /// the `dyn Law`), so a law whose bias or slope ignores an argument costs no square
    /// root for it.
    #[allow(clippy::too_many_arguments)]
    fn robust_sums(
        &self,
        x: &[f64],
        v: &[f64],
        var_x: &[f64],
        var_v: &[f64],
        w: &[f64],
        g_x: &mut [f64],
        g_v: &mut [f64],
    ) -> f64 {
        // Two passes over the same samples: the sum (sequential, in sample order) and
        // the slopes (independent per sample, so the compiler can pack them), each
        // sample's arithmetic as in one pass; slices cut to the window's length, so no
        // bounds checks inside the loops.
        let n = w.len();
        let (x, v, var_x, var_v) = (&x[..n], &v[..n], &var_x[..n], &var_v[..n]);
        let mut value = 0.0;
        for (((x, v), (var_x, var_v)), w) in x.iter().zip(v).zip(var_x.iter().zip(var_v)).zip(w) {
            let p = self.power(*x, *v);
            let bias = self.noise_bias(*x, *v, *var_x, *var_v);
            value += w * (p - bias);
        }
        for ((((x, v), (var_x, var_v)), w), (g_x, g_v)) in x
            .iter()
            .zip(v)
            .zip(var_x.iter().zip(var_v))
            .zip(w)
            .zip(g_x[..n].iter_mut().zip(&mut g_v[..n]))
        {
            let (sx, sv) = self.power_slope(*x, *v, var_x.sqrt(), var_v.sqrt());
            *g_v = w * sv;
            *g_x = w * sx;
        }
        value
    }

    /// True when the power is |v| (Coulomb friction): its window integral is then the
    /// total variation of the displacement, a form that needs no velocity.
    fn is_total_variation(&self) -> bool {
        false
    }

    /// The power v f(v) as one of the closed forms the regressor kernel knows, when the
    /// law depends on the velocity alone and has one. The kernel then evaluates the law
    /// together with the other sums that read the same velocity column, in one loop,
    /// instead of calling [`Law::power_sum`] (`src/regressor/kernel/fused.rs`); the default,
    /// `None`, keeps the call. A law that returns `Some` must have
    /// [`Law::uses_displacement`] false and a `power_sum` that is the same sum.
    fn power_form(&self) -> Option<PowerForm> {
        None
    }

    /// Σ_i w_i v_i f(x_i, v_i) over one run of samples of one element, for relative
    /// motion given as the element's DOF motions (x = x_a − x_b, v = v_a − v_b between
    /// two DOFs) and weights given per sample or as one value for the run.
    ///
    /// The default forms the relative motion and the weights in short chunks on the
    /// stack and calls [`Law::weighted_power`], so every law works unchanged. A law can
    /// override it to work on the DOF motions directly and to skip the weights when they
    /// are uniform (the built-in laws do, with [`crate::terms::lanes`]); the result must
    /// be the same sum up to round-off.
    fn power_sum(&self, motion: ElementMotion<'_>, weights: Weights<'_>) -> f64 {
        const CHUNK: usize = 256;
        let v_len = match motion {
            ElementMotion::Ground { v, .. } => v.len(),
            ElementMotion::Between { v_a, .. } => v_a.len(),
        };
        let mut dx = [0.0; CHUNK];
        let mut dv = [0.0; CHUNK];
        let mut uniform = [0.0; CHUNK];
        if let Weights::Uniform(w) = weights {
            uniform.fill(w);
        }
        let mut total = 0.0;
        for start in (0..v_len).step_by(CHUNK) {
            let end = (start + CHUNK).min(v_len);
            let len = end - start;
            let (x, v): (&[f64], &[f64]) = match motion {
                ElementMotion::Ground { x, v } => (
                    if x.is_empty() { x } else { &x[start..end] },
                    &v[start..end],
                ),
                ElementMotion::Between { x_a, x_b, v_a, v_b } => {
                    for (d, (a, b)) in dv
                        .iter_mut()
                        .zip(v_a[start..end].iter().zip(&v_b[start..end]))
                    {
                        *d = a - b;
                    }
                    let x: &[f64] = if x_a.is_empty() {
                        &[]
                    } else {
                        for (d, (a, b)) in dx
                            .iter_mut()
                            .zip(x_a[start..end].iter().zip(&x_b[start..end]))
                        {
                            *d = a - b;
                        }
                        &dx[..len]
                    };
                    (x, &dv[..len])
                }
            };
            let w = match weights {
                Weights::Uniform(_) => &uniform[..len],
                Weights::PerSample(w) => &w[start..end],
            };
            total += self.weighted_power(x, v, w);
        }
        total
    }
}

/// The motion of one element over a run of samples. Displacement slices are empty when
/// the law does not use displacement ([`Law::uses_displacement`]).
#[derive(Debug, Clone, Copy)]
pub enum ElementMotion<'a> {
    /// A DOF to ground: x and v are the DOF's own.
    Ground {
        /// Displacements (or empty).
        x: &'a [f64],
        /// Velocities.
        v: &'a [f64],
    },
    /// A dashpot between DOFs a and b, acting on x_a − x_b and v_a − v_b.
    Between {
        /// Displacements of DOF a (or empty).
        x_a: &'a [f64],
        /// Displacements of DOF b (or empty).
        x_b: &'a [f64],
        /// Velocities of DOF a.
        v_a: &'a [f64],
        /// Velocities of DOF b.
        v_b: &'a [f64],
    },
}

/// The power g(v) = v f(v) of a velocity-only law in a closed form
/// ([`Law::power_form`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum PowerForm {
    /// g = v² (linear viscous).
    Square,
    /// g = v² |v| (quadratic, f = v |v|).
    AbsCube,
    /// g = |v| (Coulomb, f = sign v).
    Abs,
    /// g = |v|^q (power law f = |v|^(q−1) sign v).
    AbsPow(f64),
}

impl PowerForm {
    /// g(v).
    #[inline(always)]
    pub fn power(self, v: f64) -> f64 {
        match self {
            PowerForm::Square => v * v,
            PowerForm::AbsCube => v * v * v.abs(),
            PowerForm::Abs => v.abs(),
            PowerForm::AbsPow(q) => v.abs().powf(q),
        }
    }
}

/// Quadrature weights over a run of samples.
#[derive(Debug, Clone, Copy)]
pub enum Weights<'a> {
    /// The same weight for every sample of the run (the interior of the rectangular and
    /// trapezoid rules).
    Uniform(f64),
    /// One weight per sample.
    PerSample(&'a [f64]),
}

/// sign(v) with sign(0) = 0 (unlike `f64::signum`), so that Coulomb friction at rest
/// exerts no force in the simulator and dissipates nothing.
pub fn sign(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::terms::laws::{Linear, PowerLaw, Quadratic};

    /// A law that uses x and keeps every provided method: the default bias and slopes.
    #[derive(Debug)]
    struct Stiffened;

    impl Law for Stiffened {
        fn name(&self) -> String {
            "stiffened".into()
        }
        fn force(&self, x: f64, v: f64) -> f64 {
            v * (1.0 + x * x)
        }
        fn uses_displacement(&self) -> bool {
            true
        }
        fn weighted_power(&self, x: &[f64], v: &[f64], w: &[f64]) -> f64 {
            (0..w.len()).map(|i| w[i] * self.power(x[i], v[i])).sum()
        }
    }

    /// `robust_sums` is bitwise the one-pass loop over the samples it replaced (the sum
    /// in sample order, each sample's bias and slopes as alone), for the built-in laws
    /// that override the per-sample methods and for one that keeps the defaults; zero
    /// variances included.
    #[test]
    fn robust_sums_are_the_one_pass_sums() {
        let laws: Vec<Box<dyn Law>> = vec![
            Box::new(Linear),
            Box::new(Quadratic),
            Box::new(PowerLaw::new(0.7).expect("a valid exponent")),
            Box::new(Stiffened),
        ];
        let n = 203;
        let x: Vec<f64> = (0..n).map(|i| (0.37 * i as f64).sin()).collect();
        let v: Vec<f64> = (0..n).map(|i| (0.61 * i as f64).cos() - 0.2).collect();
        let var_x: Vec<f64> = (0..n).map(|i| 1e-4 * (i % 7) as f64).collect();
        let var_v: Vec<f64> = (0..n).map(|i| 3e-4 * (i % 5) as f64).collect();
        let w: Vec<f64> = (0..n).map(|i| 0.01 + 1e-3 * (i % 3) as f64).collect();
        for law in &laws {
            let mut expected = (0.0, vec![0.0; n], vec![0.0; n]);
            for i in 0..n {
                let p = law.power(x[i], v[i]);
                let bias = law.noise_bias(x[i], v[i], var_x[i], var_v[i]);
                expected.0 += w[i] * (p - bias);
                let (sx, sv) = law.power_slope(x[i], v[i], var_x[i].sqrt(), var_v[i].sqrt());
                expected.2[i] = w[i] * sv;
                expected.1[i] = w[i] * sx;
            }
            let (mut g_x, mut g_v) = (vec![f64::NAN; n + 3], vec![f64::NAN; n + 3]);
            let value = law.robust_sums(&x, &v, &var_x, &var_v, &w, &mut g_x, &mut g_v);
            assert_eq!(value.to_bits(), expected.0.to_bits(), "{}", law.name());
            for i in 0..n {
                assert_eq!(
                    g_x[i].to_bits(),
                    expected.1[i].to_bits(),
                    "{} x {i}",
                    law.name()
                );
                assert_eq!(
                    g_v[i].to_bits(),
                    expected.2[i].to_bits(),
                    "{} v {i}",
                    law.name()
                );
            }
        }
    }
}
