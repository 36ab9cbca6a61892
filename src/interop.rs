//! Conversions between nalgebra and faer matrices, for users who hold their data in
//! nalgebra (dampid computes with faer). Both are column-major, so each conversion is
//! one copy.

use faer::{Mat, MatRef};
use nalgebra::DMatrix;

/// A faer matrix from a nalgebra one (e.g. N × n displacements for a `RecordParts`).
pub fn from_nalgebra(m: &DMatrix<f64>) -> Mat<f64> {
    Mat::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)])
}

/// A nalgebra matrix from a faer one (e.g. a regressor or a POD basis).
pub fn to_nalgebra(m: MatRef<'_, f64>) -> DMatrix<f64> {
    DMatrix::from_fn(m.nrows(), m.ncols(), |i, j| m[(i, j)])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_keeps_every_entry() {
        let a = DMatrix::from_fn(3, 2, |i, j| (10 * i + j) as f64);
        let b = from_nalgebra(&a);
        assert_eq!(b[(2, 1)], 21.0);
        assert_eq!(to_nalgebra(b.as_ref()), a);
    }
}
