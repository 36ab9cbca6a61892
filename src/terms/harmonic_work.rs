//! The work per cycle of a term under single-harmonic motion, in closed form: the
//! stepped-sine rows of the laws that have one, without synthesizing a period
//! (`regressor/stepped_sine.rs`).
//!
//! DOF j moves as x_j = Re(Z_j e^{iωt}), Z_j = X_j e^{−iψ_j}, so an element's deformation
//! is Z_e = Z_a − Z_b (Z_a alone to ground), x_e = |Z_e| cos(ωt − ψ_e) and
//! v_e = −ω |Z_e| sin(ωt − ψ_e). Per unit coefficient, over one period T = 2π/ω:
//!
//! - **matrix term** θ C₀ (viscous, stiffness- or mass-proportional): with
//!   ∮ v_j v_k dt = (T/2) Re(iωZ_j · conj(iωZ_k)) = π ω Re(Z_j Z̄_k),
//!
//!   ```text
//!     W = ∮ vᵀ C₀ v dt = π ω Σ_jk (C₀)_jk Re(Z_j Z̄_k)   (a dashpot: π c ω |Z_e|²);
//!   ```
//!
//! - **a law whose power is |v|^q** ([`PowerForm`]: linear q = 2, quadratic q = 3,
//!   Coulomb q = 1, power law |v|^p sign v with q = p + 1): with θ = ωt − ψ_e,
//!   dt = dθ/ω and Wallis' integral ∫₀^{π/2} sin^q θ dθ = (√π/2) Γ((q+1)/2)/Γ(q/2 + 1),
//!
//!   ```text
//!     W = ∫₀^{2π} |ω |Z_e| sin θ|^q dθ/ω = ω^p |Z_e|^{p+1} G(p),
//!     G(p) = 4 ∫₀^{π/2} sin^{p+1} θ dθ = 2√π Γ(p/2 + 1) / Γ(p/2 + 3/2),
//!   ```
//!
//!   G(0) = 4 (Coulomb: W = 4|Z_e|, the distance travelled), G(1) = π (linear:
//!   π ω |Z_e|²), G(2) = 8/3 (quadratic: (8/3) ω² |Z_e|³); these three are taken exactly.
//!   Its derivatives: ∂W/∂|Z_e| = (p + 1) W/|Z_e|, and in the exponent
//!
//!   ```text
//!     ∂W/∂p = W (ln ω + ln |Z_e| + ½ ψ(p/2 + 1) − ½ ψ(p/2 + 3/2)),   ψ the digamma function.
//!   ```
//!
//! An element term's column is Σ_e w_e W_e over its elements for a shared coefficient,
//! w_e W_e for one per element (w_e the element weight, 1 by default). Laws without such
//! a form (expressions, custom closures), forces with memory and structural damping
//! terms of the model have no closed form here ([`Term::harmonic_columns`] is `None`):
//! their rows keep the synthesis. A matrix term whose symmetric part is not positive
//! semidefinite has none either: its power can change sign within a period, and the
//! synthesized rows' round-off check (`regressor/round_off.rs`, which compares the net
//! work with the gross) must then see it; for a semidefinite one net and gross work are
//! the same, and so is the check's outcome.

use std::f64::consts::PI;

use crate::terms::law::PowerForm;
use crate::terms::on_elements::{Coefficients, OnElements};
use crate::terms::{MatrixTerm, Term};

/// A complex amplitude (real part, imaginary part).
pub type Phasor = (f64, f64);

/// G(p) = 4 ∫₀^{π/2} sin^{p+1} θ dθ = 2√π Γ(p/2 + 1)/Γ(p/2 + 3/2) (module doc), exact
/// at p = 0, 1, 2.
pub fn cycle_factor(p: f64) -> f64 {
    if p == 0.0 {
        4.0
    } else if p == 1.0 {
        PI
    } else if p == 2.0 {
        8.0 / 3.0
    } else {
        // the last p asked for and its G (every row of a build asks for the same p)
        thread_local! {
            static LAST: std::cell::Cell<(u64, f64)> = const { std::cell::Cell::new((0, 4.0)) };
        }
        LAST.with(|last| {
            let (bits, g) = last.get();
            if bits == p.to_bits() {
                return g;
            }
            use statrs::function::gamma::ln_gamma;
            let g = 2.0 * PI.sqrt() * (ln_gamma(p / 2.0 + 1.0) - ln_gamma(p / 2.0 + 1.5)).exp();
            last.set((p.to_bits(), g));
            g
        })
    }
}

/// ω^p, kept for the last (ω, p) asked for: a stepped-sine point's perturbed copies
/// (noise model, ∂A/∂R) share its ω and are computed one after the other, so all but
/// the first read it (the same bits: `powf` is a function of its arguments).
fn frequency_power(omega: f64, p: f64) -> f64 {
    thread_local! {
        static LAST: std::cell::Cell<(u64, u64, f64)> = const { std::cell::Cell::new((0, 0, 1.0)) };
    }
    LAST.with(|last| {
        let (w, q, value) = last.get();
        if w == omega.to_bits() && q == p.to_bits() {
            return value;
        }
        let value = omega.powf(p);
        last.set((omega.to_bits(), p.to_bits(), value));
        value
    })
}

impl PowerForm {
    /// The exponent p of the force |v|^p sign v whose power this is (q − 1).
    pub fn force_exponent(self) -> f64 {
        match self {
            PowerForm::Square => 1.0,
            PowerForm::AbsCube => 2.0,
            PowerForm::Abs => 0.0,
            PowerForm::AbsPow(q) => q - 1.0,
        }
    }

    /// W = ω^p X^{p+1} G(p): the work per cycle of the power |v|^{p+1} when the element
    /// moves as X cos(ωt − ψ) (module doc).
    pub fn cycle_work(self, omega: f64, amplitude: f64) -> f64 {
        let p = self.force_exponent();
        let x = amplitude.abs();
        match self {
            PowerForm::Square => PI * omega * x * x,
            PowerForm::AbsCube => 8.0 / 3.0 * omega * omega * x * x * x,
            PowerForm::Abs => 4.0 * x,
            PowerForm::AbsPow(_) => frequency_power(omega, p) * x.powf(p + 1.0) * cycle_factor(p),
        }
    }

    /// ∂W/∂X = (p + 1) ω^p X^p G(p).
    pub fn cycle_work_slope(self, omega: f64, amplitude: f64) -> f64 {
        let p = self.force_exponent();
        let x = amplitude.abs();
        (p + 1.0) * omega.powf(p) * x.powf(p) * cycle_factor(p)
    }

    /// ∂W/∂p = W (ln ω + ln X + ½ ψ(p/2 + 1) − ½ ψ(p/2 + 3/2)) (module doc): the
    /// derivative in an estimated exponent.
    pub fn cycle_work_exponent_derivative(self, omega: f64, amplitude: f64) -> f64 {
        use statrs::function::gamma::digamma;
        let p = self.force_exponent();
        let x = amplitude.abs();
        let w = self.cycle_work(omega, x);
        if w == 0.0 {
            return 0.0;
        }
        w * (omega.ln() + x.ln() + 0.5 * digamma(p / 2.0 + 1.0) - 0.5 * digamma(p / 2.0 + 1.5))
    }
}

/// Z_a − Z_b of an element (Z_b = 0 to ground).
fn deformation(z: &[Phasor], a: usize, b: Option<usize>) -> Phasor {
    match b {
        None => z[a],
        Some(b) => (z[a].0 - z[b].0, z[a].1 - z[b].1),
    }
}

/// Whether the symmetric part of `m` is positive semidefinite (its smallest eigenvalue
/// at least −10⁻¹² of its largest magnitude, for round-off).
fn semidefinite(m: &MatrixTerm) -> bool {
    let c = m.matrix();
    let n = c.nrows();
    if n == 0 || c.ncols() != n {
        return false;
    }
    let sym = nalgebra::DMatrix::from_fn(n, n, |i, j| 0.5 * (c[(i, j)] + c[(j, i)]));
    if sym.iter().any(|v| !v.is_finite()) {
        return false;
    }
    let eig = sym.symmetric_eigenvalues();
    let largest = eig.iter().fold(0.0f64, |m, e| m.max(e.abs()));
    eig.iter().all(|&e| e >= -1e-12 * largest)
}

impl Term {
    /// Whether this term has a closed-form work per cycle under single-harmonic motion
    /// ([`Term::harmonic_columns`] is `Some`).
    pub fn has_harmonic_work(&self) -> bool {
        match self {
            Term::Matrix(m) => semidefinite(m),
            Term::Elements(t) => t.law().power_form().is_some(),
            Term::History(_) | Term::Structural(_) => false,
        }
    }

    /// The term's columns (work per cycle per unit coefficient) when every DOF moves as
    /// Re(z_j e^{iωt}), in closed form (module doc); `None` when the term has none.
    /// `z` holds one phasor per DOF of a validated model.
    pub fn harmonic_columns(&self, omega: f64, z: &[Phasor]) -> Option<Vec<f64>> {
        let mut columns = Vec::new();
        self.harmonic_columns_into(omega, z, &mut columns)
            .then_some(columns)
    }

    /// [`Term::harmonic_columns`] appended to `out` (the same numbers, no allocation
    /// of their own); false, with `out` as it was, when the term has none.
    pub fn harmonic_columns_into(&self, omega: f64, z: &[Phasor], out: &mut Vec<f64>) -> bool {
        self.columns_into::<false>(omega, z, &[], out, &mut Vec::new())
    }

    /// [`Term::harmonic_columns_into`], and the columns' derivative along the phasors'
    /// direction `dz` (one per DOF) appended to `slope`:
    ///
    /// ```text
    ///   matrix term:  dW = π ω Σ_jk (C₀)_jk Re(dZ_j Z̄_k + Z_j dZ̄_k),
    ///   |v|^q law:    dW = w_e (p + 1) (W_e/|Z_e|) Re(Z_e dZ̄_e)/|Z_e|,
    /// ```
    ///
    /// (∂W/∂|Z_e| = (p + 1) W/|Z_e|, module doc). An element that does not move
    /// (|Z_e| = 0) has derivative 0 for p > 0 and none for Coulomb friction (NaN: the
    /// caller then differences). The columns are those of
    /// [`Term::harmonic_columns_into`] to the last bit.
    pub fn harmonic_columns_and_slope_into(
        &self,
        omega: f64,
        z: &[Phasor],
        dz: &[Phasor],
        out: &mut Vec<f64>,
        slope: &mut Vec<f64>,
    ) -> bool {
        self.columns_into::<true>(omega, z, dz, out, slope)
    }

    /// The columns into `out`, and with `SLOPE` their derivative along `dz` into
    /// `slope` (see [`Term::harmonic_columns_and_slope_into`]; without it neither is
    /// read, and the columns cost what they cost before the slope existed).
    fn columns_into<const SLOPE: bool>(
        &self,
        omega: f64,
        z: &[Phasor],
        dz: &[Phasor],
        out: &mut Vec<f64>,
        slope: &mut Vec<f64>,
    ) -> bool {
        match self {
            Term::Matrix(m) => {
                if !semidefinite(m) {
                    return false;
                }
                let c = m.matrix();
                let mut sum = 0.0;
                for (j, zj) in z.iter().enumerate() {
                    for (k, zk) in z.iter().enumerate() {
                        sum += c[(j, k)] * (zj.0 * zk.0 + zj.1 * zk.1);
                    }
                }
                out.push(PI * omega * sum);
                if SLOPE {
                    let mut d = 0.0;
                    for (j, (zj, dj)) in z.iter().zip(dz).enumerate() {
                        for (k, (zk, dk)) in z.iter().zip(dz).enumerate() {
                            d +=
                                c[(j, k)] * (dj.0 * zk.0 + dj.1 * zk.1 + zj.0 * dk.0 + zj.1 * dk.1);
                        }
                    }
                    slope.push(PI * omega * d);
                }
                true
            }
            Term::Elements(t) => {
                let Some(form) = t.law().power_form() else {
                    return false;
                };
                let start = out.len();
                out.resize(start + t.coefficient_count(), 0.0);
                let columns = &mut out[start..];
                let from = slope.len();
                if SLOPE {
                    slope.resize(from + t.coefficient_count(), 0.0);
                }
                for (e, element) in t.elements().iter().enumerate() {
                    let (re, im) = deformation(z, element.a, element.b);
                    let weight = t.weights().map_or(1.0, |w| w[e]);
                    let x = re.hypot(im);
                    let cycle = form.cycle_work(omega, x);
                    let work = weight * cycle;
                    let column = match t.coefficients() {
                        Coefficients::Shared(_) => 0,
                        Coefficients::PerElement(_) => e,
                    };
                    columns[column] += work;
                    if SLOPE {
                        let p = form.force_exponent();
                        let (dre, dim) = deformation(dz, element.a, element.b);
                        slope[from + column] += if x > 0.0 {
                            weight * (p + 1.0) * (cycle / x) * ((re * dre + im * dim) / x)
                        } else if p > 0.0 {
                            0.0
                        } else {
                            f64::NAN
                        };
                    }
                }
                true
            }
            Term::History(_) | Term::Structural(_) => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::terms::Element;
    use crate::terms::laws::{Coulomb, Expression, Linear, PowerLaw, Quadratic};

    /// The periodic trapezoid (the spectral rule's weights on whole periods) of
    /// ∮ |v|^q dt with N samples of v = −ωX sin(ωt − ψ).
    fn quadrature(form: PowerForm, omega: f64, x: f64, psi: f64, n: usize) -> f64 {
        let h = 2.0 * PI / omega / n as f64;
        (0..n)
            .map(|j| {
                let t = j as f64 * h;
                h * form.power(-omega * x * (omega * t - psi).sin())
            })
            .sum()
    }

    /// Viscous, quadratic, Coulomb and the power law against the 512-sample quadrature
    /// of the synthesis, worst over where the samples fall in one sample interval: v²
    /// is a trigonometric polynomial and integrates exactly; |v|^q has a kink of order q
    /// at each zero crossing, so the trapezoid converges as N^{−(q+1)}: measured worst
    /// relative differences at N = 512 are 1.25e-5 (Coulomb, q = 1), 2.4e-9 (the power
    /// law with p = 1.5, q = 2.5) and 2.8e-10 (quadratic, q = 3), each halving of N
    /// multiplying them by 2^{q+1}.
    #[test]
    fn closed_forms_match_the_synthesized_quadrature() {
        let (omega, x) = (37.7, 2.3e-3);
        let worst = |form: PowerForm, n: usize| {
            let exact = form.cycle_work(omega, x);
            (0..=40)
                .map(|k| {
                    let psi = 1.1 + 2.0 * PI / n as f64 * k as f64 / 40.0;
                    (quadrature(form, omega, x, psi, n) - exact).abs() / exact
                })
                .fold(0.0f64, f64::max)
        };
        let e = worst(PowerForm::Square, 512);
        assert!(e < 1e-14, "{e}");
        for (form, q, bound) in [
            (PowerForm::Abs, 1.0, 2e-5),
            (PowerForm::AbsPow(2.5), 2.5, 4e-9),
            (PowerForm::AbsCube, 3.0, 5e-10),
        ] {
            let (e256, e512) = (worst(form, 256), worst(form, 512));
            assert!(e512 < bound, "q = {q}: {e512}");
            let order = (e256 / e512).log2();
            assert!((order - (q + 1.0)).abs() < 0.3, "q = {q}: order {order}");
        }
        // The general formula at the exact exponents.
        for (p, form) in [
            (0.0, PowerForm::Abs),
            (1.0, PowerForm::Square),
            (2.0, PowerForm::AbsCube),
        ] {
            let general = omega.powf(p)
                * x.powf(p + 1.0)
                * 2.0
                * PI.sqrt()
                * (statrs::function::gamma::ln_gamma(p / 2.0 + 1.0)
                    - statrs::function::gamma::ln_gamma(p / 2.0 + 1.5))
                .exp();
            let exact = form.cycle_work(omega, x);
            assert!((general - exact).abs() < 1e-13 * exact, "p = {p}");
            let pow = PowerForm::AbsPow(p + 1.0).cycle_work(omega, x);
            assert!((pow - exact).abs() < 1e-13 * exact, "p = {p}");
        }
    }

    /// ∂W/∂X and ∂W/∂p against central differences.
    #[test]
    fn derivatives_match_differences() {
        let (omega, x) = (40.0, 1.5e-3);
        for p in [0.3, 1.5, 2.7] {
            let form = PowerForm::AbsPow(p + 1.0);
            let h = 1e-6 * x;
            let fd = (form.cycle_work(omega, x + h) - form.cycle_work(omega, x - h)) / (2.0 * h);
            let slope = form.cycle_work_slope(omega, x);
            assert!((fd - slope).abs() < 1e-7 * slope.abs(), "p = {p}");
            let h = 1e-5;
            let fd = (PowerForm::AbsPow(p + 1.0 + h).cycle_work(omega, x)
                - PowerForm::AbsPow(p + 1.0 - h).cycle_work(omega, x))
                / (2.0 * h);
            let d = form.cycle_work_exponent_derivative(omega, x);
            assert!((fd - d).abs() < 1e-7 * d.abs(), "p = {p}: {fd} vs {d}");
        }
    }

    /// The columns' derivative along a direction of the phasors against central
    /// differences of the columns (every closed-form kind, two DOFs, per-element and
    /// shared coefficients, weights), and the columns themselves bit for bit those of
    /// `harmonic_columns`.
    #[test]
    fn slope_matches_central_differences() {
        let omega = 12.0;
        let z = [(1.0e-2, -0.4e-2), (0.3e-2, 0.8e-2)];
        let dz = [(-0.7, 0.2), (0.4, -1.1)];
        let elements = vec![Element::to_ground(0), Element::between(0, 1)];
        let terms = [
            Term::weighted(
                PowerLaw::new(1.5).unwrap(),
                elements.clone(),
                vec![1.0, 0.5],
                Coefficients::PerElement("d".into()),
            ),
            Term::on_elements(
                Quadratic,
                elements.clone(),
                Coefficients::Shared("q".into()),
            ),
            Term::on_elements(Coulomb, elements.clone(), Coefficients::Shared("f".into())),
            Term::on_elements(Linear, elements, Coefficients::Shared("c".into())),
            Term::viscous("m", faer::mat![[2.0, -1.0], [-1.0, 1.0]]),
        ];
        let along = |t: f64| -> Vec<Phasor> {
            z.iter()
                .zip(&dz)
                .map(|(a, d)| (a.0 + t * d.0, a.1 + t * d.1))
                .collect()
        };
        for term in &terms {
            let (mut columns, mut slope) = (Vec::new(), Vec::new());
            assert!(term.harmonic_columns_and_slope_into(omega, &z, &dz, &mut columns, &mut slope));
            let plain = term.harmonic_columns(omega, &z).unwrap();
            assert_eq!(
                columns.iter().map(|c| c.to_bits()).collect::<Vec<_>>(),
                plain.iter().map(|c| c.to_bits()).collect::<Vec<_>>()
            );
            let h = 1e-7;
            let (up, down) = (
                term.harmonic_columns(omega, &along(h)).unwrap(),
                term.harmonic_columns(omega, &along(-h)).unwrap(),
            );
            assert_eq!(slope.len(), plain.len());
            for k in 0..slope.len() {
                let central = (up[k] - down[k]) / (2.0 * h);
                assert!(
                    (slope[k] - central).abs() < 1e-7 * central.abs(),
                    "{k}: {} vs {central}",
                    slope[k]
                );
            }
        }
        // An element that does not move: 0 for p > 0, none for Coulomb friction.
        let still = [(0.0, 0.0)];
        let one = [(1.0, 0.0)];
        let grounded = |law: Term| {
            let (mut c, mut s) = (Vec::new(), Vec::new());
            law.harmonic_columns_and_slope_into(omega, &still, &one, &mut c, &mut s);
            s[0]
        };
        let ground = vec![Element::to_ground(0)];
        assert_eq!(
            grounded(Term::on_elements(
                Linear,
                ground.clone(),
                Coefficients::Shared("c".into())
            )),
            0.0
        );
        assert!(
            grounded(Term::on_elements(
                Coulomb,
                ground,
                Coefficients::Shared("f".into())
            ))
            .is_nan()
        );
    }

    /// A term's columns: shared and per-element coefficients, element weights, a dashpot
    /// between two DOFs with different phases, and a viscous matrix, against the
    /// quadrature of the synthesized motion; an expression law has none.
    #[test]
    fn term_columns_match_the_quadrature() {
        let omega = 12.0;
        let z = [(1.0e-2, -0.4e-2), (0.3e-2, 0.8e-2)];
        let n = 512;
        let h = 2.0 * PI / omega / n as f64;
        let v = |j: usize, t: f64| {
            let (re, im) = z[j];
            // Re(iω Z e^{iωt})
            -omega * (re * (omega * t).sin() + im * (omega * t).cos())
        };
        let sum = |f: &dyn Fn(f64) -> f64| (0..n).map(|i| h * f(i as f64 * h)).sum::<f64>();
        let elements = vec![Element::to_ground(0), Element::between(0, 1)];
        let term = Term::weighted(
            PowerLaw::new(1.5).unwrap(),
            elements.clone(),
            vec![1.0, 0.5],
            Coefficients::PerElement("d".into()),
        );
        let cols = term.harmonic_columns(omega, &z).unwrap();
        let g0 = sum(&|t| v(0, t).abs().powf(2.5));
        let g1 = 0.5 * sum(&|t| (v(0, t) - v(1, t)).abs().powf(2.5));
        assert!((cols[0] - g0).abs() < 1e-8 * g0);
        assert!((cols[1] - g1).abs() < 1e-8 * g1);
        let shared = Term::on_elements(
            Quadratic,
            elements.clone(),
            Coefficients::Shared("q".into()),
        );
        let q = shared.harmonic_columns(omega, &z).unwrap();
        let expect = sum(&|t| v(0, t).abs().powi(3) + (v(0, t) - v(1, t)).abs().powi(3));
        assert!((q[0] - expect).abs() < 1e-9 * expect);
        let coulomb =
            Term::on_elements(Coulomb, elements.clone(), Coefficients::Shared("f".into()));
        let f = coulomb.harmonic_columns(omega, &z).unwrap();
        let expect = sum(&|t| v(0, t).abs() + (v(0, t) - v(1, t)).abs());
        assert!((f[0] - expect).abs() < 1e-4 * expect);
        let linear = Term::on_elements(Linear, elements, Coefficients::Shared("c".into()));
        let c = linear.harmonic_columns(omega, &z).unwrap();
        let expect = sum(&|t| v(0, t).powi(2) + (v(0, t) - v(1, t)).powi(2));
        assert!((c[0] - expect).abs() < 1e-13 * expect);
        // The same dashpots as a matrix: [[2, −1], [−1, 1]].
        let matrix = Term::viscous("c", faer::mat![[2.0, -1.0], [-1.0, 1.0]]);
        let m = matrix.harmonic_columns(omega, &z).unwrap();
        assert!((m[0] - c[0]).abs() < 1e-13 * c[0]);
        // An indefinite matrix keeps the synthesis, and so does an expression law.
        let indefinite = Term::viscous("k", faer::mat![[1.0, 0.0], [0.0, -1.0]]);
        assert!(indefinite.harmonic_columns(omega, &z).is_none());
        assert!(!indefinite.has_harmonic_work());
        let expression = Term::per_dof(
            Expression::parse("v*abs(v)").unwrap(),
            2,
            Coefficients::Shared("e".into()),
        );
        assert!(expression.harmonic_columns(omega, &z).is_none());
    }
}
