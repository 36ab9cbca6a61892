//! Closed-form steady states of chains with structural (hysteretic) damping, with no
//! time integration (the simulator refuses a loss factor: its force is non-causal).
//!
//! A chain M ẍ + C ẋ + K(η) x = r, the elements' stiffnesses complex, k_e(1 + iη_e),
//! driven by r(t) = Σ_n F_n cos(nωt) on DOF 1, has the steady state
//! x(t) = Σ_n Re[X_n e^{inωt}] with, per harmonic,
//!
//! ```text
//!   (K(η) − M(nω)² + i nω C) X_n = F_n        (SDOF: X_n = F_n/(k − m(nω)² + i nωc + iηk)),
//! ```
//!
//! solved here by complex Gaussian elimination.

use std::f64::consts::PI;

use dampid::prelude::*;
use faer::Mat;
use realfft::num_complex::Complex64;

/// Samples per fundamental period.
pub const SAMPLES: usize = 200;
/// Periods per record (one window each).
pub const PERIODS: usize = 2;

/// A spring (and loss factor) between DOF `a` and DOF `b` (`None`: ground), 0-based.
pub struct Spring {
    pub a: usize,
    pub b: Option<usize>,
    pub k: f64,
    pub eta: f64,
}

/// A chain: masses, springs, a dashpot `c` from every DOF to ground.
pub struct Chain {
    pub mass: Vec<f64>,
    pub springs: Vec<Spring>,
    pub c: f64,
}

impl Chain {
    pub fn sdof(m: f64, k: f64, eta: f64, c: f64) -> Self {
        Chain {
            mass: vec![m],
            springs: vec![Spring {
                a: 0,
                b: None,
                k,
                eta,
            }],
            c,
        }
    }

    /// X_n for a unit-free force vector `f` (on DOF 1) at frequency `omega`.
    pub fn response(&self, omega: f64, force: f64) -> Vec<Complex64> {
        let n = self.mass.len();
        let mut d = vec![vec![Complex64::new(0.0, 0.0); n]; n];
        for (i, m) in self.mass.iter().enumerate() {
            d[i][i] += Complex64::new(-m * omega * omega, omega * self.c);
        }
        for s in &self.springs {
            let k = Complex64::new(s.k, s.k * s.eta);
            d[s.a][s.a] += k;
            if let Some(b) = s.b {
                d[b][b] += k;
                d[s.a][b] -= k;
                d[b][s.a] -= k;
            }
        }
        let mut rhs = vec![Complex64::new(0.0, 0.0); n];
        rhs[0] = Complex64::new(force, 0.0);
        // Gaussian elimination (n ≤ 2, the diagonal dominates: no pivoting needed)
        for p in 0..n {
            for r in p + 1..n {
                let f = d[r][p] / d[p][p];
                let pivot = d[p].clone();
                for (entry, above) in d[r].iter_mut().zip(&pivot).skip(p) {
                    *entry -= f * above;
                }
                let v = rhs[p];
                rhs[r] -= f * v;
            }
        }
        let mut x = vec![Complex64::new(0.0, 0.0); n];
        for p in (0..n).rev() {
            let mut s = rhs[p];
            for c in p + 1..n {
                s -= d[p][c] * x[c];
            }
            x[p] = s / d[p][p];
        }
        x
    }

    /// The steady-state record of the force Σ_n F_n cos(nωt) on DOF 1, `harmonics`
    /// the (n, F_n); the recorded force multiplied by `force_scale` and `extra`(x) added
    /// to it (a force the energy balance must not see).
    pub fn record(
        &self,
        omega: f64,
        harmonics: &[(usize, f64)],
        force_scale: f64,
        extra: &dyn Fn(f64) -> f64,
    ) -> Record {
        self.sampled_record(omega, harmonics, force_scale, extra, SAMPLES, PERIODS)
    }

    /// [`Chain::record`] with `samples` per period over `periods` periods.
    pub fn sampled_record(
        &self,
        omega: f64,
        harmonics: &[(usize, f64)],
        force_scale: f64,
        extra: &dyn Fn(f64) -> f64,
        samples: usize,
        periods: usize,
    ) -> Record {
        let dofs = self.mass.len();
        let period = 2.0 * PI / omega;
        let step = period / samples as f64;
        let m = samples * periods;
        let phasors: Vec<(usize, f64, Vec<Complex64>)> = harmonics
            .iter()
            .map(|&(n, f)| (n, f, self.response(n as f64 * omega, f)))
            .collect();
        let motion = |i: usize, j: usize, derivative: bool| -> f64 {
            let t = i as f64 * step;
            phasors
                .iter()
                .map(|(n, _, x)| {
                    let w = *n as f64 * omega;
                    let e = Complex64::from_polar(1.0, w * t);
                    let factor = if derivative {
                        Complex64::new(0.0, w)
                    } else {
                        Complex64::new(1.0, 0.0)
                    };
                    (factor * x[j] * e).re
                })
                .sum()
        };
        let force = |i: usize| -> f64 {
            let t = i as f64 * step;
            phasors
                .iter()
                .map(|(n, f, _)| f * (*n as f64 * omega * t).cos())
                .sum::<f64>()
        };
        Record::new(RecordParts {
            label: format!("w={omega:.3},{harmonics:?}"),
            step,
            start_time: 0.0,
            displacements: Mat::from_fn(m, dofs, |i, j| motion(i, j, false)),
            velocities: Some(Mat::from_fn(m, dofs, |i, j| motion(i, j, true))),
            forcing: Forcing::on_dofs(
                Mat::from_fn(m, 1, |i, _| {
                    force_scale * force(i) + extra(motion(i, 0, false))
                }),
                vec![0],
            ),
            period,
        })
        .unwrap()
    }

    /// |X_e,n|² of spring `s` for each harmonic.
    pub fn deformation_squared(
        &self,
        s: usize,
        omega: f64,
        harmonics: &[(usize, f64)],
    ) -> Vec<f64> {
        let spring = &self.springs[s];
        harmonics
            .iter()
            .map(|&(n, f)| {
                let x = self.response(n as f64 * omega, f);
                let e = x[spring.a] - spring.b.map_or(Complex64::new(0.0, 0.0), |b| x[b]);
                e.norm_sqr()
            })
            .collect()
    }
}
