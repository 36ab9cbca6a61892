//! The "Proper orthogonal modes" section of the HTML report, present when identification
//! ran on records projected onto their leading POMs ([`crate::prep::pod`]). For each basis
//! drawn: a table of the modes (POV λ_k, energy share, cumulative share, retained or
//! not), the retained mode shapes against the DOF (sensor) index, and the energy share of
//! every mode on a log scale with the retained ones marked. With one basis per record the
//! first [`MAX_BASES`] are drawn and a summary table lists every basis.

use std::fmt::Write as _;

use super::{escape, plots};
use crate::error::Result;
use crate::prep::pod::{Pod, Reduction};

/// Bases drawn in full at most (one per record may mean many records).
const MAX_BASES: usize = 3;

/// Mode shapes drawn per basis at most.
const MAX_SHAPES: usize = 8;

/// Modes listed one per row at least (all retained ones always are); the rest share a
/// row.
const MIN_TABLE_ROWS: usize = 12;

/// The section's HTML, headed "Proper orthogonal modes".
pub(crate) fn section(reduction: &Reduction) -> Result<String> {
    let mut html = String::from("\n<h2>Proper orthogonal modes</h2>\n");
    let bases = &reduction.bases;
    let records = reduction.records.len();
    let shown = bases.len().min(MAX_BASES);
    let which = match (bases.len(), records) {
        (0, _) => {
            html.push_str("<p>No POD basis was computed.</p>\n");
            return Ok(html);
        }
        (1, 0 | 1) => "One basis, from the record's displacements".to_string(),
        (1, _) => {
            format!("One basis shared by all {records} records, from their stacked displacements")
        }
        (n, _) if n == shown => {
            format!("One basis per record ({n} bases), each from its record's displacements")
        }
        (n, _) => format!(
            "One basis per record ({n} bases), each from its record's displacements; the first {shown} are drawn"
        ),
    };
    let _ = writeln!(
        html,
        "<p>{which}. Identification ran on the records projected onto the retained modes (x ≈ x̄ + U<sub>m</sub> U<sub>m</sub>ᵀ (x − x̄)). Shapes are unit length, largest component positive.</p>"
    );
    if bases.len() > 1 {
        html.push_str(&summary_table(reduction));
    }
    for (index, pod) in bases.iter().take(shown).enumerate() {
        let label = basis_label(reduction, index);
        let _ = writeln!(html, "<h3>{}</h3>", escape(&label));
        html.push_str(&basis_section(pod, &label)?);
    }
    Ok(html)
}

/// Which records basis `index` came from.
fn basis_label(reduction: &Reduction, index: usize) -> String {
    if reduction.bases.len() == 1 && reduction.records.len() > 1 {
        return format!("All {} records (stacked)", reduction.records.len());
    }
    match (reduction.records.get(index), reduction.bases.get(index)) {
        (Some(record), Some(pod)) => {
            // The projection appended " [m POMs]" to the source record's label.
            let suffix = format!(" [{} POMs]", pod.retained());
            let label = record.label();
            let source = label.strip_suffix(&suffix).unwrap_or(label);
            format!("Record {} ({source})", index + 1)
        }
        _ => format!("Basis {}", index + 1),
    }
}

/// One row per basis: samples, modes retained, their share and the leading mode's.
fn summary_table(reduction: &Reduction) -> String {
    let mut table = String::from(
        "<table><tr><th>basis</th><th>DOFs</th><th>samples</th><th>retained modes</th><th>retained share</th><th>POM 1 share</th></tr>\n",
    );
    for (index, pod) in reduction.bases.iter().enumerate() {
        let shares = pod.energy_shares();
        let _ = writeln!(
            table,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(&basis_label(reduction, index)),
            pod.dofs(),
            pod.samples(),
            pod.retained(),
            percent(retained_share(pod)),
            percent(shares.first().copied().unwrap_or(f64::NAN)),
        );
    }
    table.push_str("</table>\n");
    table
}

/// One basis: the counts, the table of modes and the two plots.
fn basis_section(pod: &Pod, label: &str) -> Result<String> {
    let mut html = String::new();
    let _ = writeln!(
        html,
        "<p>{} DOFs (sensors), {} samples, mean {}; {} of {} modes retained, carrying {} of the energy.</p>",
        pod.dofs(),
        pod.samples(),
        if pod.mean_removed() {
            "removed"
        } else {
            "not removed"
        },
        pod.retained(),
        pod.dofs(),
        percent(retained_share(pod)),
    );
    html.push_str(&mode_table(pod));
    let shares = pod.energy_shares();
    let drawn = pod.retained().min(MAX_SHAPES);
    let shapes: Vec<plots::Curve> = (0..drawn)
        .filter_map(|k| {
            let shape = pod.mode(k)?;
            Some(plots::Curve {
                name: format!("POM {} ({})", k + 1, percent(shares[k])),
                points: shape
                    .iter()
                    .enumerate()
                    .map(|(dof, &amplitude)| ((dof + 1) as f64, amplitude))
                    .collect(),
                band: None,
                measured: None,
            })
        })
        .collect();
    if drawn < pod.retained() {
        let _ = writeln!(
            html,
            "<p>The first {drawn} of the {} retained shapes are drawn.</p>",
            pod.retained()
        );
    }
    html.push_str(&plots::mode_shapes(
        &format!("Retained POM shapes: {label}"),
        &shapes,
    )?);
    html.push('\n');
    html.push_str(&plots::energy_shares(
        &format!("Energy share per POM: {label}"),
        &shares,
        pod.retained(),
    )?);
    html.push('\n');
    Ok(html)
}

/// Mode, POV, share, cumulative share, retained: every retained mode and at least
/// [`MIN_TABLE_ROWS`] rows, the remaining modes summed in one last row.
fn mode_table(pod: &Pod) -> String {
    let mut table = String::from(
        "<table><tr><th>mode</th><th>POV λ</th><th>energy share</th><th>cumulative share</th><th>retained</th></tr>\n",
    );
    let values = pod.values();
    let shares = pod.energy_shares();
    let cumulative = pod.cumulative_shares();
    let rows = values.len().min(pod.retained().max(MIN_TABLE_ROWS));
    for k in 0..rows {
        let _ = writeln!(
            table,
            "<tr><td>{}</td><td>{:.4e}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            k + 1,
            values[k],
            percent(shares[k]),
            percent(cumulative[k]),
            if k < pod.retained() { "yes" } else { "no" }
        );
    }
    if rows < values.len() {
        let rest: f64 = values[rows..].iter().sum();
        let rest_share: f64 = shares[rows..].iter().sum();
        let _ = writeln!(
            table,
            "<tr><td>{}–{}</td><td>{rest:.4e} (sum)</td><td>{} (sum)</td><td>{}</td><td>no</td></tr>",
            rows + 1,
            values.len(),
            percent(rest_share),
            percent(cumulative.last().copied().unwrap_or(f64::NAN)),
        );
    }
    table.push_str("</table>\n");
    table
}

/// Cumulative energy share of the retained modes.
fn retained_share(pod: &Pod) -> f64 {
    pod.retained()
        .checked_sub(1)
        .and_then(|last| pod.cumulative_shares().get(last).copied())
        .unwrap_or(0.0)
}

/// A share as a percentage with enough digits to tell 99.9% from 99.99%, and tiny
/// shares in exponent form rather than as 0.0000%.
fn percent(share: f64) -> String {
    let value = 100.0 * share;
    if !value.is_finite() {
        "–".into()
    } else if value != 0.0 && value.abs() < 1e-3 {
        format!("{value:.2e}%")
    } else {
        format!("{value:.4}%")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::prep::pod::{PodBasis, PodSettings, Retain, reduce};

    #[test]
    fn percent_keeps_tiny_shares_readable() {
        assert_eq!(percent(0.988196), "98.8196%");
        assert_eq!(percent(1.0), "100.0000%");
        assert_eq!(percent(0.0), "0.0000%");
        assert_eq!(percent(4.3256e-8), "4.33e-6%");
        assert_eq!(percent(f64::NAN), "–");
    }

    fn record(label: &str, dofs: usize) -> crate::record::Record {
        use crate::record::{Forcing, Record, RecordParts};
        use faer::Mat;
        let samples = 64;
        let displacements = Mat::from_fn(samples, dofs, |i, j| {
            let t = i as f64 * 0.1;
            (j + 1) as f64 * t.sin() + 0.01 * (3.0 * t + j as f64).cos()
        });
        Record::new(RecordParts {
            label: label.into(),
            step: 0.1,
            start_time: 0.0,
            forcing: Forcing::generalized(Mat::from_fn(samples, dofs, |i, _| {
                (i as f64 * 0.1).cos()
            })),
            displacements,
            velocities: None,
            period: std::f64::consts::TAU,
        })
        .unwrap()
    }

    fn reduction(records: &[crate::record::Record], basis: PodBasis) -> Reduction {
        let settings = PodSettings {
            retain: Retain::Count(1),
            basis,
            ..Default::default()
        };
        reduce(records, &settings).unwrap()
    }

    #[test]
    fn one_dof_gives_one_mode_and_both_plots() {
        let html = section(&reduction(&[record("single", 1)], PodBasis::PerRecord)).unwrap();
        assert!(html.contains("One basis, from the record's displacements"));
        assert!(html.contains("Record 1 (single)"));
        assert!(html.contains("1 of 1 modes retained"));
        assert_eq!(html.matches("<svg").count(), 2);
        assert!(!html.contains("discarded"));
    }

    #[test]
    fn a_shared_basis_is_drawn_once_and_labelled_as_stacked() {
        let records = [record("a", 3), record("b", 3)];
        let html = section(&reduction(&records, PodBasis::Shared)).unwrap();
        assert!(html.contains("One basis shared by all 2 records"));
        assert!(html.contains("All 2 records (stacked)"));
        assert_eq!(html.matches("<svg").count(), 2);
        // One basis: no summary table of bases.
        assert!(!html.contains("<th>basis</th>"));
    }

    #[test]
    fn per_record_bases_beyond_the_first_few_are_listed_not_drawn() {
        let records: Vec<_> = (0..MAX_BASES + 1)
            .map(|k| record(&format!("<run {k}> & co"), 2))
            .collect();
        let html = section(&reduction(&records, PodBasis::PerRecord)).unwrap();
        assert!(html.contains(&format!("the first {MAX_BASES} are drawn")));
        assert_eq!(html.matches("<svg").count(), 2 * MAX_BASES);
        assert_eq!(html.matches("<h3>").count(), MAX_BASES);
        // Every basis in the summary, labels escaped, the POM suffix dropped.
        assert!(html.contains(&format!(
            "Record {} (&lt;run {MAX_BASES}&gt; &amp; co)",
            MAX_BASES + 1
        )));
        assert!(!html.contains("<run"));
        assert!(!html.contains("POMs]"));
    }

    #[test]
    fn an_empty_reduction_says_so() {
        let empty = Reduction {
            records: Vec::new(),
            bases: Vec::new(),
        };
        let html = section(&empty).unwrap();
        assert!(html.contains("Proper orthogonal modes"));
        assert!(html.contains("No POD basis"));
        assert!(!html.contains("<svg"));
    }
}
