//! Record diagnostics: how much of the fit's residual each record holds.
//!
//! With ẽ_i the residual of equation i as the fit weighed it (e_i = b_i − A_iθ for an
//! unweighted fit, e_i / s_i with s_i the propagated standard deviation for a weighted
//! one), R_r the equations of record r (m_r of the m), and ν = m − (free coefficients):
//!
//! - the residual share of record r is  share_r = Σ_{i∈R_r} ẽ_i² / Σ_i ẽ_i²;
//! - its standardised residual is  z_r = √(Σ_{i∈R_r} ẽ_i² / m_r) / s,  s = √(Σ_i ẽ_i² / ν),
//!   the record's RMS residual in units of the fit's residual standard deviation (about 1
//!   for a record that fits like the rest; `None` without redundancy, ν = 0).
//!
//! - its ratio to the others is  q_r = √(Σ_{i∈R_r} ẽ_i² / m_r) / √(Σ_{i∉R_r} ẽ_i² / (m − m_r)),
//!   its RMS residual over the RMS residual of every other record's equations.
//!
//! - its outlier test is the F test of "this record's equations have the same residual
//!   variance as the others'":  F_r = (Σ_{i∈R_r} ẽ_i² / m_r) / (Σ_{i∉R_r} ẽ_i² / d_r),
//!   d_r = m − m_r − (free coefficients), with p_r = P(F(m_r, d_r) > F_r) (`None` when
//!   d_r < 1: the other records leave no residual degrees of freedom to compare with).
//!
//! A record *dominates* when it holds at least [`DOMINANT_SHARE`] of the squared residual,
//! at least [`DOMINANCE_RATIO`] times its share of the equations m_r / m, and its outlier
//! test rejects at [`OUTLIER_LEVEL`] / (number of records) (Bonferroni over the records),
//! with two or more records (with residuals of one size everywhere share_r = m_r / m and
//! q_r = 1). The test is what keeps few equations from raising a false alarm: the clean
//! four-mass POD fit (4 records of one equation, 2 coefficients) has a record holding 75 %
//! of the residual by chance (q_r ≈ 3, F_r ≈ 3 on (1, 1) degrees of freedom, p ≈ 0.33),
//! while a force on the wrong DOF gives p below 1e-10. The report then warns
//! ([`crate::report::Warning::RecordDominates`]) with the likely causes.

use serde::{Deserialize, Serialize};

use crate::regressor::RowLabel;

/// Share of the squared residual from which a record can dominate.
pub const DOMINANT_SHARE: f64 = 0.5;

/// How many times its share of the equations a dominating record's residual share is.
pub const DOMINANCE_RATIO: f64 = 3.0;

/// Family-wise level of the records' outlier tests (divided by the number of records).
pub use crate::report::outliers::OUTLIER_LEVEL;

/// The residual of one record's equations.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecordResidual {
    /// The record's label.
    pub record: String,
    /// The record's index in the list identified from.
    pub record_index: usize,
    /// How many equations (windows) it gave.
    pub equations: usize,
    /// Its share of the (weighted) squared residual, Σ_{i∈R_r} ẽ_i² / Σ ẽ_i² (0 when the
    /// fit is exact).
    pub residual_share: f64,
    /// Its RMS (weighted) residual over the fit's residual standard deviation (`None`
    /// without redundancy).
    pub standardised_residual: Option<f64>,
    /// The mean of its unweighted residuals b − Aθ (a sign tells a force on the wrong
    /// DOF or with the wrong sign from noise).
    pub mean_residual: f64,
    /// Its RMS (weighted) residual over that of the other records' equations (`None`
    /// when it is the only record, or the others fit exactly).
    #[serde(default)]
    pub ratio_to_others: Option<f64>,
    /// P(F(m_r, d_r) > F_r) of its outlier test (module doc; `None` without residual
    /// degrees of freedom outside the record).
    #[serde(default)]
    pub outlier_p_value: Option<f64>,
    /// The fit without this record ([`crate::report::outliers`]), when it was made.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub left_out: Option<crate::report::outliers::LeftOut>,
}

impl RecordResidual {
    /// True when this record dominates the residual of a fit on `records` records with
    /// `total_equations` equations (module doc).
    pub fn dominates(&self, records: usize, total_equations: usize) -> bool {
        let fair = self.equations as f64 / total_equations.max(1) as f64;
        records >= 2
            && self.residual_share >= DOMINANT_SHARE
            && self.residual_share >= DOMINANCE_RATIO * fair
            && self
                .outlier_p_value
                .is_some_and(|p| p < OUTLIER_LEVEL / records as f64)
    }
}

/// Per record (in order of first appearance in `rows`): the residual share and the
/// standardised residual of `residuals`, weighted by `residual_std` when given, with
/// `free` free coefficients.
pub fn per_record(
    rows: &[RowLabel],
    residuals: &[f64],
    residual_std: Option<&[f64]>,
    free: usize,
) -> Vec<RecordResidual> {
    let weighted: Vec<f64> = residuals
        .iter()
        .enumerate()
        .map(|(i, e)| match residual_std.and_then(|s| s.get(i)) {
            Some(s) if *s > 0.0 && s.is_finite() => e / s,
            _ => *e,
        })
        .collect();
    let total: f64 = weighted.iter().map(|e| e * e).sum();
    let dof = rows.len().saturating_sub(free);
    let s = (dof > 0 && total > 0.0).then(|| (total / dof as f64).sqrt());
    let mut out: Vec<RecordResidual> = Vec::new();
    let mut sums: Vec<(f64, f64)> = Vec::new();
    for ((row, e), w) in rows.iter().zip(residuals).zip(&weighted) {
        let k = match out.iter().position(|r| r.record_index == row.record_index) {
            Some(k) => k,
            None => {
                out.push(RecordResidual {
                    record: row.record.clone(),
                    record_index: row.record_index,
                    equations: 0,
                    residual_share: 0.0,
                    standardised_residual: None,
                    mean_residual: 0.0,
                    ratio_to_others: None,
                    outlier_p_value: None,
                    left_out: None,
                });
                sums.push((0.0, 0.0));
                out.len() - 1
            }
        };
        out[k].equations += 1;
        sums[k].0 += w * w;
        sums[k].1 += e;
    }
    for (r, (squares, sum)) in out.iter_mut().zip(sums) {
        let m = r.equations as f64;
        r.residual_share = if total > 0.0 { squares / total } else { 0.0 };
        r.standardised_residual = s.map(|s| (squares / m).sqrt() / s);
        r.mean_residual = sum / m;
        let others = rows.len() - r.equations;
        let rest = total - squares;
        r.ratio_to_others = (others > 0 && rest > 0.0)
            .then(|| (squares / m).sqrt() / (rest / others as f64).sqrt());
        let rest_dof = others.saturating_sub(free);
        r.outlier_p_value = (rest_dof >= 1 && squares > 0.0).then(|| {
            if rest > 0.0 {
                let f = (squares / m) / (rest / rest_dof as f64);
                crate::analysis::stats::f_upper_tail(f, m, rest_dof as f64)
            } else {
                0.0
            }
        });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(record: usize, window: usize) -> RowLabel {
        RowLabel {
            record: format!("r{record}"),
            record_index: record,
            window,
            start_time: 0.0,
            cycles: 1,
            frequency: None,
        }
    }

    /// Four records of two equations; residuals (by hand) 0.1, −0.1 | 0.1, −0.1 | 2, 2 |
    /// 0.1, −0.1: Σe² = 6 · 0.01 + 8 = 8.06, so record 3 holds 8/8.06 = 0.9926 of it
    /// (fair share 0.25); with one free coefficient ν = 7, s = √(8.06/7), z_3 = √(8/2)/s;
    /// the others' RMS is √(0.06/6) = 0.1, so q_3 = 2/0.1 = 20; F_3 = (8/2)/(0.06/5) = 333.3
    /// on (2, 5) degrees of freedom, whose tail is (1 + 2F/5)^(−5/2) = 4.82e-6.
    #[test]
    fn shares_and_standardised_residuals_by_hand() {
        let rows = [
            row(0, 0),
            row(0, 1),
            row(1, 0),
            row(1, 1),
            row(2, 0),
            row(2, 1),
            row(3, 0),
            row(3, 1),
        ];
        let e = [0.1, -0.1, 0.1, -0.1, 2.0, 2.0, 0.1, -0.1];
        let records = per_record(&rows, &e, None, 1);
        assert_eq!(records.len(), 4);
        assert!((records[2].residual_share - 8.0 / 8.06).abs() < 1e-12);
        assert!((records[0].residual_share - 0.02 / 8.06).abs() < 1e-12);
        let s = (8.06f64 / 7.0).sqrt();
        assert!((records[2].standardised_residual.unwrap() - 2.0 / s).abs() < 1e-12);
        assert_eq!(records[2].mean_residual, 2.0);
        assert!((records[2].ratio_to_others.unwrap() - 20.0).abs() < 1e-9);
        let p = (1.0 + 2.0 * (4.0 / 0.012) / 5.0f64).powf(-2.5);
        assert!((records[2].outlier_p_value.unwrap() / p - 1.0).abs() < 1e-9);
        assert!(records[2].dominates(4, 8));
        assert!(!records[0].dominates(4, 8));
        let shares: f64 = records.iter().map(|r| r.residual_share).sum();
        assert!((shares - 1.0).abs() < 1e-12);
    }

    /// Equal residuals everywhere: every share is the fair one, nobody dominates; one
    /// record alone never dominates; weights divide the residuals.
    #[test]
    fn fair_residuals_and_weights() {
        let rows = [row(0, 0), row(1, 0), row(1, 1)];
        let records = per_record(&rows, &[1.0, -1.0, 1.0], None, 1);
        assert!((records[1].residual_share - 2.0 / 3.0).abs() < 1e-12);
        assert!(!records[1].dominates(2, 3));
        let one = per_record(&rows[..1], &[5.0], None, 0);
        assert!(!one[0].dominates(1, 1));
        // Weighted: the second record's residuals are 10 sd each, the first 1 sd.
        let weighted = per_record(&rows, &[1.0, 10.0, 10.0], Some(&[1.0, 1.0, 1.0]), 0);
        assert!((weighted[1].residual_share - 200.0 / 201.0).abs() < 1e-12);
        let scaled = per_record(&rows, &[1.0, 10.0, 10.0], Some(&[1.0, 10.0, 10.0]), 0);
        assert!((scaled[1].residual_share - 2.0 / 3.0).abs() < 1e-12);
        // One equation per record, one residual degree of freedom left outside the record:
        // however large its share, a record is not called dominant (the POD case).
        let rows4 = [row(0, 0), row(1, 0), row(2, 0), row(3, 0)];
        let pod = per_record(&rows4, &[0.1, 0.4, 0.1, 0.1], None, 2);
        assert!(pod[1].residual_share > 0.8 && !pod[1].dominates(4, 4));
        // No redundancy: no standardised residual.
        assert!(
            per_record(&rows, &[1.0, 1.0, 1.0], None, 3)[0]
                .standardised_residual
                .is_none()
        );
    }
}
