//! Windows of one record are replicates. In steady state every window of whole periods
//! of a record repeats the same experiment, so its rows of A differ only by noise and by
//! the quadrature and velocity errors of each window (central differences at the
//! record's ends, leakage), never by information. Those differences still give the
//! column-scaled regressor singular values above round-off, and when the equations are
//! nearly exact (the differences enter A and b consistently, so the residual hides
//! them) the identifiability analysis would call coefficients determined that one
//! experiment cannot separate: one record of a 2-mass chain with central differences
//! (four windows, three dashpots) gave "every coefficient is determined" with standard
//! errors of 10⁻¹² and c = 0.93 for a truth of 0.125.
//!
//! With ã_i the column-scaled row i (A_s = A S⁻¹, the matrix the analysis factors; the
//! rows weighted by their propagated noise for a weighted fit) and u_R the direction of
//! the mean of the rows of record R (windows of whole periods only; spans of the
//! non-periodic mode legitimately differ),
//!
//! ```text
//!   s_w = √( Σ_R Σ_{i∈R} ‖ã_i − (ã_iᵀu_R) u_R‖² / Σ_R (m_R − 1) ),
//! ```
//!
//! over the records with two windows or more: the size of one row's scatter between
//! replicates, across their common direction. Rows that differ only in scale (windows
//! weighted differently) lie on one line and span one direction, so scale is not
//! counted. A singular value below κ·s_w could be made by that scatter alone
//! (Weyl: the singular values of A_s beyond the rank of its record means are at most
//! ‖A_s − Ā_s‖₂, of the size of s_w times a few), so the analysis takes
//! max(s, s_w) as the noise level of its threshold
//! ([`crate::analysis::identifiability`]).
//!
//! The points of a stepped-sine table are not replicates: each is a steady state at its
//! own frequency (and force), so each point counts as an experiment of its own and its
//! row is left out of s_w, although a sweep's points share a record index.
//!
//! And however the windows scatter, the records are the experiments: R records whose
//! windows are replicates give at most R independent equations, so at most R
//! combinations of the coefficients are determined ([`experiments`]; each window of
//! the non-periodic mode counts as one). A 100-DOF chain driven in 5 experiments of 50
//! windows each (models/chain100.toml) was said to determine 93 combinations of its 201
//! coefficients; it determines at most 5.
//!
//! **Experiments that nothing checks** ([`unchecked`]). With ā_g the mean scaled row of
//! experiment g (a record's windows averaged; a stepped-sine point or a span alone) over
//! the free columns, and Ā = U Σ Vᵀ (the singular values above 10⁻¹⁰ σ₁ kept), the
//! leverage of g among the experiments is
//!
//! ```text
//!   h_g = ‖U_g‖² = ā_gᵀ (ĀᵀĀ)⁺ ā_g,   0 ≤ h_g ≤ 1,   Σ_g h_g = rank Ā.
//! ```
//!
//! An error δ in experiment g's equations leaves a residual (1 − h_g) δ there: at
//! h_g = 1 the experiment alone determines a combination of the coefficients, and the
//! fit absorbs whatever it holds (wrong units, sign, force DOF), with χ² = 0 however many
//! windows it has. Every experiment has h_g = 1 when there are no more experiments than
//! free coefficients; two records at one frequency and forcing point differ only in
//! amplitude for a linear law, so they count once in rank Ā and the third, fourth …
//! other record can still be alone (the physics fuzz target found both). Experiments
//! with h_g ≥ [`UNCHECKED_LEVERAGE`] are named ([`crate::report::Warning::NoRecordRedundancy`]).

use faer::Mat;

use crate::fit::scaling::Scaling;
use crate::regressor::{Regressor, RowLabel};

/// Leverage at or above which an experiment's error would show at most √(1 − h) ≈ 3 %
/// in its residual: the experiment is not checked by the others (module doc).
pub const UNCHECKED_LEVERAGE: f64 = 0.999;

/// Whether the row of `label` repeats the other windows of its record: windows of whole
/// periods do; spans of the non-periodic mode and stepped-sine points do not.
fn replicated(label: &RowLabel) -> bool {
    label.cycles > 0 && label.frequency.is_none()
}

/// s_w of `regressor` (module doc); `None` when no record has two windows of whole
/// periods.
pub fn window_scatter(regressor: &Regressor) -> Option<f64> {
    let a = regressor.matrix();
    let (m, p) = a.shape();
    if m == 0 || p == 0 {
        return None;
    }
    let scaling = Scaling::of(a, regressor.rhs());
    let groups: Vec<Vec<usize>> = grouped(regressor)
        .into_iter()
        .filter(|g| g.replicated)
        .map(|g| g.rows)
        .collect();
    let (mut squares, mut dof) = (0.0, 0usize);
    for rows in groups.iter().filter(|rows| rows.len() >= 2) {
        let columns = &scaling.columns;
        let row = |i: usize| (0..p).map(move |j| a[(i, j)] / columns[j]);
        let mut mean = vec![0.0; p];
        for &i in rows {
            mean.iter_mut().zip(row(i)).for_each(|(m, x)| *m += x);
        }
        let norm = mean.iter().map(|m| m * m).sum::<f64>().sqrt();
        if norm > 0.0 {
            mean.iter_mut().for_each(|m| *m /= norm);
        }
        for &i in rows {
            let along: f64 = row(i).zip(&mean).map(|(x, u)| x * u).sum();
            squares += row(i)
                .zip(&mean)
                .map(|(x, u)| (x - along * u).powi(2))
                .sum::<f64>();
        }
        dof += rows.len() - 1;
    }
    (dof > 0 && squares.is_finite()).then(|| (squares / dof as f64).sqrt())
}

/// The number of experiments behind the rows of `regressor`: one per record for its
/// windows of whole periods (replicates), one per row otherwise (module doc).
pub fn experiments(regressor: &Regressor) -> usize {
    grouped(regressor).len()
}

/// One experiment's rows: a record's windows of whole periods, or one other row.
pub(crate) struct Experiment {
    /// Whether its rows are replicate windows of one record.
    pub(crate) replicated: bool,
    /// Its rows, in order.
    pub(crate) rows: Vec<usize>,
}

/// The experiments behind the rows of `regressor`, in the order of their first row
/// (module doc).
pub(crate) fn grouped(regressor: &Regressor) -> Vec<Experiment> {
    let mut groups: Vec<Experiment> = Vec::new();
    let mut by_record = std::collections::HashMap::new();
    for (i, label) in regressor.rows().iter().enumerate() {
        if !replicated(label) {
            groups.push(Experiment {
                replicated: false,
                rows: vec![i],
            });
        } else if let Some(&g) = by_record.get(&label.record_index) {
            let group: &mut Experiment = &mut groups[g];
            group.rows.push(i);
        } else {
            by_record.insert(label.record_index, groups.len());
            groups.push(Experiment {
                replicated: true,
                rows: vec![i],
            });
        }
    }
    groups
}

/// The experiments with leverage h_g ≥ [`UNCHECKED_LEVERAGE`] over the `free` columns
/// (module doc), named by their record (a point or span by its row label), in row order.
pub fn unchecked(regressor: &Regressor, free: &[usize]) -> Vec<String> {
    let a = regressor.matrix();
    if a.nrows() == 0 || free.is_empty() {
        return Vec::new();
    }
    let scaling = Scaling::of(a, regressor.rhs());
    let groups = grouped(regressor);
    let (g, f) = (groups.len(), free.len());
    // Padded to at least f rows, as the thin SVD of a wide matrix needs.
    let means = Mat::from_fn(g.max(f), f, |k, j| match groups.get(k) {
        Some(Experiment { rows, .. }) => {
            let column = free[j];
            rows.iter().map(|i| a[(*i, column)]).sum::<f64>()
                / (rows.len() as f64 * scaling.columns[column])
        }
        None => 0.0,
    });
    let Ok(svd) = means.thin_svd() else {
        return Vec::new();
    };
    let sigma = svd.S().column_vector();
    let largest = (0..f).map(|i| sigma[i]).fold(0.0, f64::max);
    if !(largest.is_finite() && largest > 0.0) {
        return Vec::new();
    }
    let kept: Vec<usize> = (0..f).filter(|i| sigma[*i] > 1e-10 * largest).collect();
    let u = svd.U();
    groups
        .into_iter()
        .enumerate()
        .filter(|(k, _)| {
            kept.iter().map(|i| u[(*k, *i)].powi(2)).sum::<f64>() >= UNCHECKED_LEVERAGE
        })
        .map(|(_, group)| {
            let label = &regressor.rows()[group.rows[0]];
            if group.replicated {
                label.record.clone()
            } else {
                label.to_string()
            }
        })
        .collect()
}
