//! System matrices the reference systems and model files build by name.

use faer::Mat;

/// K = tridiag(−1, 2, −1) for a chain of n unit springs fixed at both ends.
pub fn chain_stiffness(n: usize) -> Mat<f64> {
    Mat::from_fn(n, n, |i, j| {
        if i == j {
            2.0
        } else if i.abs_diff(j) == 1 {
            -1.0
        } else {
            0.0
        }
    })
}
