//! Upper-tail probabilities of the test statistics dampid reports, from statrs:
//!
//! - the F distribution with (d₁, d₂) degrees of freedom, P(F > f) (nested model
//!   comparison, [`crate::analysis::compare`]);
//! - the χ² distribution with ν degrees of freedom, P(χ²_ν > x) (model adequacy of a fit
//!   weighted by propagated variances, [`crate::analysis::diagnostics`]).
//!
//! Degenerate arguments get the limit a user expects: a statistic ≤ 0 has tail 1, an
//! infinite one 0, NaN or no degrees of freedom NaN.

use statrs::distribution::{ChiSquared, ContinuousCDF, FisherSnedecor};

/// P(F > f) for F with (d1, d2) degrees of freedom.
pub(crate) fn f_upper_tail(f: f64, d1: f64, d2: f64) -> f64 {
    tail(f, || FisherSnedecor::new(d1, d2).ok().map(|d| d.sf(f)))
}

/// P(χ²_ν > x) for ν = `dof` degrees of freedom.
pub(crate) fn chi_square_upper_tail(x: f64, dof: f64) -> f64 {
    tail(x, || ChiSquared::new(dof).ok().map(|d| d.sf(x)))
}

fn tail(statistic: f64, sf: impl Fn() -> Option<f64>) -> f64 {
    if statistic.is_nan() {
        f64::NAN
    } else if statistic <= 0.0 {
        1.0
    } else if statistic.is_infinite() {
        0.0
    } else {
        sf().unwrap_or(f64::NAN)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// With d₁ = 2 the F tail is (1 + 2f/d₂)^(−d₂/2).
    #[test]
    fn f_tail_with_two_numerator_degrees() {
        for d2 in [1.0, 5.0, 17.0, 120.0] {
            for f in [0.1, 1.0, 3.0, 25.0] {
                let exact = (1.0f64 + 2.0 * f / d2).powf(-d2 / 2.0);
                let tail = f_upper_tail(f, 2.0, d2);
                assert!((tail - exact).abs() < 1e-12 * exact.max(1e-3), "{f} {d2}");
            }
        }
    }

    /// With d₁ = d₂ = 1 (a squared Cauchy variable), P(F > f) = 1 − (2/π) atan √f.
    #[test]
    fn f_tail_with_one_and_one_degree() {
        for f in [0.5, 1.0, 4.0, 100.0] {
            let exact = 1.0 - 2.0 / std::f64::consts::PI * f64::sqrt(f).atan();
            assert!((f_upper_tail(f, 1.0, 1.0) - exact).abs() < 1e-12);
        }
    }

    /// χ² with 2 degrees of freedom is exponential with mean 2: P(χ² > x) = e^{−x/2};
    /// and the tail at the mean of a large ν is near ½.
    #[test]
    fn chi_square_tails() {
        for x in [0.1, 1.0, 4.0, 30.0] {
            let exact = (-x / 2.0f64).exp();
            assert!((chi_square_upper_tail(x, 2.0) - exact).abs() < 1e-12 * exact.max(1e-3));
        }
        let half = chi_square_upper_tail(1000.0, 1000.0);
        assert!((half - 0.5).abs() < 0.01, "{half}");
        assert_eq!(chi_square_upper_tail(0.0, 3.0), 1.0);
        assert!(chi_square_upper_tail(1.0, 0.0).is_nan());
    }
}
