//! Small regressors written out by hand, for tests of the fits and diagnostics.

use dampid::prelude::*;
use dampid::regressor::RowLabel;
use faer::Mat;

/// Labels r0, r1, … for `count` rows, each one window of one cycle of its own record.
pub fn row_labels(count: usize) -> Vec<RowLabel> {
    (0..count)
        .map(|i| RowLabel {
            frequency: None,
            record: format!("r{i}"),
            record_index: i,
            window: 0,
            start_time: 0.0,
            cycles: 1,
        })
        .collect()
}

/// The regressor with rows `rows`, right-hand side `b` and coefficients t0, t1, ….
pub fn from_rows(rows: &[&[f64]], b: &[f64]) -> Regressor {
    let p = rows[0].len();
    let a = Mat::from_fn(rows.len(), p, |i, j| rows[i][j]);
    let names = (0..p).map(|j| format!("t{j}")).collect();
    Regressor::from_parts(a, b.to_vec(), names, row_labels(rows.len())).unwrap()
}
