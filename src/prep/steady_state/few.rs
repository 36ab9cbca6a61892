//! Products of one channel's few coefficients (p = 2K + 1 of them, K the harmonics
//! kept), which the check forms for every channel of every period and span:
//!
//! ```text
//!   aᵀb = Σ_k a_k b_k,        ‖R v‖² = Σ_i (Σ_{k ≥ i} R_ik v_k)²   (R upper triangular),
//! ```
//!
//! unrolled for p = 3, 5, 7, 9 and 11 (one to five harmonics: a loop of five turns
//! costs more in its setup than in its products), a loop otherwise. Each sum is added
//! term by term in the order of k from −0.0, as `Iterator::sum` adds, so the results
//! are the same bits as the plain loops.

/// aᵀb (a and b of one length).
#[inline]
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    match a.len() {
        3 => dot_of::<3>(a, b),
        5 => dot_of::<5>(a, b),
        7 => dot_of::<7>(a, b),
        9 => dot_of::<9>(a, b),
        11 => dot_of::<11>(a, b),
        _ => a.iter().zip(b).map(|(a, b)| a * b).sum(),
    }
}

#[inline(always)]
fn dot_of<const P: usize>(a: &[f64], b: &[f64]) -> f64 {
    let (a, b) = (&a[..P], &b[..P]);
    let mut sum = -0.0;
    for k in 0..P {
        sum += a[k] * b[k];
    }
    sum
}

/// ‖R v‖², R's upper triangle given row by row from its diagonal (`upper`, p(p + 1)/2
/// values for the p of `v`).
#[inline]
pub(super) fn triangle_norm(upper: &[f64], v: &[f64]) -> f64 {
    match v.len() {
        3 => triangle_norm_of::<3>(upper, v),
        5 => triangle_norm_of::<5>(upper, v),
        7 => triangle_norm_of::<7>(upper, v),
        9 => triangle_norm_of::<9>(upper, v),
        11 => triangle_norm_of::<11>(upper, v),
        p => {
            let mut sum = -0.0;
            let mut rows = upper;
            for i in 0..p {
                let (row, rest) = rows.split_at(p - i);
                rows = rest;
                let dot: f64 = row.iter().zip(&v[i..]).map(|(r, v)| r * v).sum();
                sum += dot * dot;
            }
            sum
        }
    }
}

#[inline(always)]
fn triangle_norm_of<const P: usize>(upper: &[f64], v: &[f64]) -> f64 {
    let (upper, v) = (&upper[..P * (P + 1) / 2], &v[..P]);
    let mut sum = -0.0;
    let mut at = 0;
    for i in 0..P {
        let mut dot = -0.0;
        for k in i..P {
            dot += upper[at + k - i] * v[k];
        }
        at += P - i;
        sum += dot * dot;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unrolled products are bit for bit the plain loops, for p = 1 to 13 (the
    /// unrolled sizes and the others), on values over forty decades with signed zeros.
    #[test]
    fn the_unrolled_products_are_the_loops() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand::rngs::StdRng::seed_from_u64(3);
        let mut next = || {
            let value = 10f64.powf(rng.random_range(-20.0..20.0));
            match rng.random_range(0..5) {
                0 => -0.0,
                1 => -value,
                _ => value,
            }
        };
        for p in 1..=13 {
            for _ in 0..50 {
                let a: Vec<f64> = (0..p).map(|_| next()).collect();
                let b: Vec<f64> = (0..p).map(|_| next()).collect();
                let plain: f64 = a.iter().zip(&b).map(|(a, b)| a * b).sum();
                assert_eq!(dot(&a, &b).to_bits(), plain.to_bits(), "p = {p}");
                let upper: Vec<f64> = (0..p * (p + 1) / 2).map(|_| next()).collect();
                let mut plain = -0.0;
                let mut at = 0;
                for i in 0..p {
                    let dot: f64 = upper[at..at + p - i]
                        .iter()
                        .zip(&b[i..])
                        .map(|(r, v)| r * v)
                        .sum();
                    at += p - i;
                    plain += dot * dot;
                }
                assert_eq!(
                    triangle_norm(&upper, &b).to_bits(),
                    plain.to_bits(),
                    "p = {p}"
                );
            }
        }
    }
}
