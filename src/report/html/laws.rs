//! The identified damping laws: one plot per term on elements, θ f(0, v) against the
//! relative velocity v (laws of x drawn at x = 0), solid over the range its elements
//! were measured at and dashed a fifth of the largest speed beyond, with the band
//! (θ ± 1.96 se) f(0, v) over the measured range when the coefficient is determined
//! (with estimated nonlinear parameters: the law at η̂ and the joint standard errors).
//! The measured range is that of the records' velocities, or ± the largest velocity
//! amplitude ω|Z| of a stepped-sine table's points. Numbers in a law's name are rounded
//! ([`crate::format::labels_in`]).

use super::HtmlReport;
use super::plots;
use crate::error::Result;
use crate::format::labels_in;
use crate::record::{Record, col};
use crate::regressor::{Source, SteppedSineSource};
use crate::terms::{Coefficients, OnElements, Term};

/// Curves drawn per term at most (per-element terms may have thousands).
const MAX_CURVES: usize = 8;

/// The law plots extend this fraction of the largest measured speed beyond the measured
/// range on each side, dashed.
const EXTRAPOLATED: f64 = 0.2;

/// Points per law curve (besides the measured range's ends).
const LAW_POINTS: usize = 240;

impl HtmlReport<'_> {
    /// The section: its heading, what the bands are, and the plots.
    pub(super) fn laws_section(&self) -> Result<String> {
        let mut out = String::from("\n<h2>Identified damping laws</h2>\n");
        if self.report.estimation.is_some() {
            out.push_str("<p>Each law at the estimated nonlinear parameters η̂; the bands are ± 1.96 joint standard errors of its coefficient (which include the uncertainty of η̂ in the coefficient, not the change of the curve's shape with η).</p>\n");
        }
        let plotted = self.force_law_plots()?;
        if plotted.is_empty() {
            out.push_str("<p>No law on elements: nothing to draw against velocity.</p>\n");
        }
        for svg in plotted {
            out.push_str(&svg);
            out.push('\n');
        }
        Ok(out)
    }

    /// One plot per element term: θ f(0, v) against relative velocity, solid over the
    /// range its elements were measured at and dashed beyond it (the plot spans the
    /// measured ranges of the term's curves and a fifth of the largest speed more on
    /// each side), with the band (θ ± 1.96 se) f(0, v) over the measured range when the
    /// coefficient is determined. Laws of x are drawn at x = 0.
    fn force_law_plots(&self) -> Result<Vec<String>> {
        // With estimated parameters the bands are of the joint standard errors.
        let joint = self.report.estimation.as_ref();
        let units = self.units();
        let velocity = units.velocity();
        let force = units.force.clone();
        let mut svgs = Vec::new();
        for (term, range) in self.model.term_columns() {
            let Term::Elements(term) = term else { continue };
            let law = term.law();
            let elements = term.elements();
            let shared = matches!(term.coefficients(), Coefficients::Shared(_));
            // The measured range of each drawn coefficient (None: nothing measured).
            let measured: Vec<Option<(f64, f64)>> = (0..range.len().min(MAX_CURVES))
                .map(|j| {
                    let (lo, hi) = if shared {
                        elements
                            .iter()
                            .map(|e| self.velocity_range(e.a, e.b))
                            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), (a, b)| {
                                (l.min(a), h.max(b))
                            })
                    } else {
                        self.velocity_range(elements[j].a, elements[j].b)
                    };
                    (hi > lo).then_some((lo, hi))
                })
                .collect();
            let (lo, hi) = measured
                .iter()
                .flatten()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &(a, b)| {
                    (l.min(a), h.max(b))
                });
            let (lo, hi) = if hi > lo {
                let margin = EXTRAPOLATED * lo.abs().max(hi.abs());
                (lo - margin, hi + margin)
            } else {
                (-1.0, 1.0)
            };
            let curves: Vec<plots::Curve> = range
                .clone()
                .take(MAX_CURVES)
                .enumerate()
                .map(|(j, k)| {
                    let c = &self.report.coefficients[k];
                    // Uniform speeds with the measured range's ends among them, so the
                    // solid part ends exactly there.
                    let mut speeds: Vec<f64> = (0..=LAW_POINTS)
                        .map(|i| lo + (hi - lo) * i as f64 / LAW_POINTS as f64)
                        .chain(measured[j].iter().flat_map(|&(a, b)| [a, b]))
                        .collect();
                    speeds.sort_by(f64::total_cmp);
                    speeds.dedup();
                    let f = |theta: f64, v: f64| theta * law.force(0.0, v);
                    let name = if c.determined {
                        c.name.clone()
                    } else {
                        format!("{} (not determined)", c.name)
                    };
                    let se = match joint {
                        Some(e) => e.coefficients.get(k).and_then(|j| j.std_error),
                        None => c.std_error,
                    };
                    plots::Curve {
                        name,
                        points: speeds.iter().map(|&v| (v, f(c.value, v))).collect(),
                        band: se.filter(|_| c.determined).map(|se| {
                            speeds
                                .iter()
                                .map(|&v| {
                                    let (a, b) =
                                        (f(c.value - 1.96 * se, v), f(c.value + 1.96 * se, v));
                                    (v, a.min(b), a.max(b))
                                })
                                .collect()
                        }),
                        measured: measured[j],
                    }
                })
                .collect();
            let more = range.len().saturating_sub(MAX_CURVES);
            let name = labels_in(&law.name());
            let title = if more > 0 {
                format!(
                    "{name} law (first {MAX_CURVES} of {} coefficients)",
                    range.len()
                )
            } else {
                format!("{name} law")
            };
            svgs.push(plots::force_laws(
                &title,
                &curves,
                (velocity.as_deref(), force.as_deref()),
            )?);
        }
        Ok(svgs)
    }

    /// The smallest and largest relative velocity v_a − v_b (v_a to ground) the
    /// equations saw: in the records (measured velocities, else central differences of
    /// the displacements), or ± the largest ω |Z_a − Z_b| of a table's points (Z = X
    /// e^{−iφ}, the synthesized harmonic motion); empty (∞, −∞) for rows alone.
    fn velocity_range(&self, a: usize, b: Option<usize>) -> (f64, f64) {
        match self.source {
            Source::Records(records) => records_velocity_range(records, a, b),
            Source::Table { table, .. } => table_velocity_range(table, a, b),
            Source::Rows(_) => (f64::INFINITY, f64::NEG_INFINITY),
        }
    }
}

/// The smallest and largest relative velocity of `records` (see
/// [`HtmlReport::velocity_range`]).
fn records_velocity_range(records: &[Record], a: usize, b: Option<usize>) -> (f64, f64) {
    let mut range = (f64::INFINITY, f64::NEG_INFINITY);
    for record in records {
        if a >= record.dofs() || b.is_some_and(|b| b >= record.dofs()) {
            continue;
        }
        let h2 = 2.0 * record.step();
        let velocity = |j: usize| -> Vec<f64> {
            match record.velocities() {
                Some(v) => col(v, j).to_vec(),
                None => col(record.displacements(), j)
                    .windows(3)
                    .map(|w| (w[2] - w[0]) / h2)
                    .collect(),
            }
        };
        let va = velocity(a);
        let vb = b.map(velocity);
        for (i, v) in va.iter().enumerate() {
            let relative = v - vb.as_ref().map_or(0.0, |vb| vb[i]);
            if relative.is_finite() {
                range = (range.0.min(relative), range.1.max(relative));
            }
        }
    }
    range
}

/// ± the largest relative velocity amplitude ω |Z_a − Z_b| of `table`'s points (see
/// [`HtmlReport::velocity_range`]).
fn table_velocity_range(table: &SteppedSineSource, a: usize, b: Option<usize>) -> (f64, f64) {
    let phasor = |p: &crate::prep::harmonic::SteppedSinePoint, j: usize| -> Option<(f64, f64)> {
        let (x, phi) = (*p.amplitudes.get(j)?, *p.phases.get(j)?);
        Some((x * phi.cos(), -x * phi.sin()))
    };
    let largest = table
        .table
        .table
        .points()
        .iter()
        .filter_map(|p| {
            let za = phasor(p, a)?;
            let zb = match b {
                Some(b) => phasor(p, b)?,
                None => (0.0, 0.0),
            };
            Some(p.frequency * (za.0 - zb.0).hypot(za.1 - zb.1))
        })
        .filter(|v| v.is_finite())
        .fold(f64::NEG_INFINITY, f64::max);
    if largest > 0.0 {
        (-largest, largest)
    } else {
        (f64::INFINITY, f64::NEG_INFINITY)
    }
}
