//! The windows' and points' checks: the steady-state verdict of every window of whole
//! periods (judged by the stored-energy mismatch when the energy is known, else by the
//! change of the motion over the window), and the noise-robust pipeline's model check
//! (χ² of the weighted residuals against its degrees of freedom) with, per window or
//! table point, the noise estimated and the residual's propagated standard deviation.
//! Long tables are folded.

use std::fmt::Write as _;

use super::{Equations, HtmlReport, OPEN_ROWS, escape};
use crate::prep::steady_state::ComparedPeriods;
use crate::report::NoiseSummary;

impl HtmlReport<'_> {
    /// The steady-state verdict of every window.
    pub(super) fn steady_state_section(&self) -> String {
        let Some(steady) = self.steady else {
            return if self.equations() == Equations::Points {
                "\n<h2>Steady state</h2>\n<p>A stepped-sine table: each point is a measured steady state, with no time history to check.</p>\n".into()
            } else if self.report.nuisance.is_empty() {
                "\n<h2>Steady state</h2>\n<p>Not checked for this report.</p>\n".into()
            } else {
                "\n<h2>Steady state</h2>\n<p>Non-periodic balance: the stored energy is an unknown, so no window needs to be in steady state.</p>\n".into()
            };
        };
        let rejected = steady.rejected().count();
        let mut out = String::from("\n<h2>Steady state</h2>\n");
        let criterion = if steady.energy_known {
            "the stored-energy mismatch |ΔE| as a share of the window's input work"
        } else {
            "the change of the motion over the window relative to its amplitude (δx, δv)"
        };
        let _ = writeln!(
            out,
            "<p>{} of {} windows steady, judged by {criterion}{}.</p>",
            steady.windows.len() - rejected,
            steady.windows.len(),
            if rejected > 0 {
                if steady.settings.accept_transient {
                    "; the others were accepted although not in steady state"
                } else {
                    ""
                }
            } else {
                ""
            }
        );
        let fold = steady.windows.len() > OPEN_ROWS;
        if fold {
            let _ = writeln!(
                out,
                "<details><summary>Every window ({})</summary>",
                steady.windows.len()
            );
        }
        out.push_str("<table><tr><th>record</th><th>window</th><th>start time</th><th>compared</th><th>δx</th><th>δv</th><th>|ΔE|/|W|</th><th>verdict</th></tr>\n");
        for w in &steady.windows {
            let compared = match w.compared {
                ComparedPeriods::FirstAndLastPeriod => "first/last",
                ComparedPeriods::NextPeriod => "next",
                ComparedPeriods::PreviousPeriod => "previous",
                ComparedPeriods::NotJudged => "–",
            };
            let energy = w
                .energy_mismatch
                .map_or("–".to_string(), |e| format!("{:.3}%", 100.0 * e));
            let verdict = if w.compared == ComparedPeriods::NotJudged {
                "not judged (accepted)"
            } else if w.steady {
                "steady"
            } else {
                "NOT steady (accepted)"
            };
            let _ = writeln!(
                out,
                "<tr{}><td>{}</td><td>{}</td><td>{:.6}</td><td>{compared}</td><td>{:.3}%</td><td>{:.3}%</td><td>{energy}</td><td title=\"{}\">{verdict}</td></tr>",
                if w.steady { "" } else { " class=\"flag\"" },
                escape(&w.record),
                w.window,
                w.start_time,
                100.0 * w.displacement_mismatch,
                100.0 * w.velocity_mismatch,
                escape(&w.reason)
            );
        }
        out.push_str("</table>\n");
        if fold {
            out.push_str("</details>\n");
        }
        out
    }

    /// The noise-robust pipeline's model check and, per window, the harmonics kept and
    /// the estimated noise; per point of a table, its frequency and noise.
    pub(super) fn noise_section(&self, noise: &NoiseSummary) -> String {
        let mut section = String::from("\n<h2>Noise and model check</h2>\n");
        let check = match noise.p_value {
            Some(p) => format!(
                "χ² = {:.3} for {} degrees of freedom (P = {p:.3}){}",
                noise.chi_square,
                noise.degrees_of_freedom,
                if p < crate::report::INADEQUATE_P_VALUE {
                    ": the residuals exceed what the estimated noise explains"
                } else {
                    ": the residuals are as large as the noise explains"
                }
            ),
            None => "no degrees of freedom left for a check".into(),
        };
        let points = self.equations() == Equations::Points;
        let _ = writeln!(
            section,
            "<p>{} weighted by their propagated residual standard deviation. {check}.</p>",
            if points { "Points" } else { "Equations" }
        );
        let fold = noise.windows.len() > OPEN_ROWS;
        if fold {
            let _ = writeln!(
                section,
                "<details><summary>Every {} ({})</summary>",
                if points { "point" } else { "window" },
                noise.windows.len()
            );
        }
        if points {
            let _ = writeln!(
                section,
                "<table><tr><th>sweep</th><th>point</th><th>{}</th><th>amplitude noise σ</th><th>force noise σ</th><th>residual sd</th></tr>",
                escape(&self.frequency_axis())
            );
        } else {
            section.push_str(
                "<table><tr><th>record</th><th>window</th><th>harmonics kept</th><th>displacement noise σ</th><th>residual sd</th></tr>\n",
            );
        }
        let list = |values: &[f64]| -> String {
            let text: Vec<String> = values.iter().map(|s| format!("{s:.2e}")).collect();
            text.join(", ")
        };
        for (i, (w, sd)) in noise.windows.iter().zip(&noise.residual_std).enumerate() {
            if points {
                let hz = self
                    .report
                    .rows
                    .get(i)
                    .and_then(|r| r.frequency)
                    .map_or("–".to_string(), |omega| {
                        format!("{:.3}", omega / std::f64::consts::TAU)
                    });
                let _ = writeln!(
                    section,
                    "<tr><td>{}</td><td>{}</td><td>{hz}</td><td>{}</td><td>{}</td><td>{sd:.3e}</td></tr>",
                    escape(&w.record),
                    w.window + 1,
                    list(&w.displacement_noise),
                    list(&w.force_noise)
                );
            } else {
                let _ = writeln!(
                    section,
                    "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{sd:.3e}</td></tr>",
                    escape(&w.record),
                    w.window,
                    orders_text(&w.harmonics),
                    list(&w.displacement_noise)
                );
            }
        }
        section.push_str("</table>\n");
        if fold {
            section.push_str("</details>\n");
        }
        section
    }
}

/// Harmonic orders (ascending) as runs: three or more consecutive orders as "a–b", three
/// or more every other order as "a–b odd" (or "even"), the others one by one, so that a
/// record's set reads "1–9, 11–43 odd" and keeps its table inside the page.
fn orders_text(orders: &[usize]) -> String {
    let mut parts = Vec::new();
    let mut i = 0;
    while i < orders.len() {
        // the last index of the run of `step` from i
        let run = |step: usize| {
            let mut j = i;
            while j + 1 < orders.len() && orders[j + 1] == orders[j] + step {
                j += 1;
            }
            j
        };
        let (one, two) = (run(1), run(2));
        if one >= i + 2 && one >= two {
            parts.push(format!("{}–{}", orders[i], orders[one]));
            i = one + 1;
        } else if two >= i + 2 {
            let parity = if orders[i] % 2 == 1 { "odd" } else { "even" };
            parts.push(format!("{}–{} {parity}", orders[i], orders[two]));
            i = two + 1;
        } else {
            parts.push(orders[i].to_string());
            i += 1;
        }
    }
    parts.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Orders read as runs: consecutive, every other (odd or even), and single ones.
    #[test]
    fn harmonic_orders_read_as_runs() {
        let mut record = vec![1, 2, 3, 4, 5, 6, 7, 8, 9];
        record.extend((11..=43).step_by(2));
        assert_eq!(orders_text(&record), "1–9, 11–43 odd");
        assert_eq!(orders_text(&[1, 3]), "1, 3");
        assert_eq!(orders_text(&[1, 2, 4, 6, 8, 9]), "1, 2–8 even, 9");
        assert_eq!(orders_text(&[1, 2, 3, 5]), "1–3, 5");
        assert_eq!(orders_text(&[1]), "1");
        assert_eq!(orders_text(&[]), "");
    }
}
