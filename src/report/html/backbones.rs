//! The page of `dampid backbones` ([`crate::analysis::backbones`]): a table of the
//! jobs, ζ(X) and f(X) on a log-X axis with each job's measured points and fitted law in
//! its own colour, each later job's fitted ζ against the first's at common amplitudes
//! (a table, with 95 % intervals where a job has them), the text outcome and the JSON.

use std::fmt::Write as _;

use super::plots::backbones::{JobSeries, by_job};
use super::{STYLE, escape};
use crate::analysis::backbones::{Backbones, TestKind, ZetaPoint};
use crate::error::Result;

/// The whole page of `backbones`.
pub fn page(backbones: &Backbones) -> Result<String> {
    let title = "Backbones of one mode: ringdown and stepped sine";
    let mut page = format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width, initial-scale=1\"><title>{title}</title>\n<style>{STYLE}</style></head><body>\n<h1>{title}</h1>\n"
    );
    page.push_str("<p>Each job identified once by its own model file; ζ is a ratio, independent of the modal mass, but the amplitudes must be the same displacement (same sensor, or the same mode-shape normalisation) in every job.</p>\n");
    page.push_str("<table><tr><th>job</th><th class=\"left\">model file</th><th class=\"left\">title</th><th class=\"left\">test</th><th>measured points</th><th>fitted amplitudes</th><th>modal mass</th></tr>\n");
    for (k, job) in backbones.jobs.iter().enumerate() {
        let range = job.fitted_range().map_or("–".to_string(), |(lo, hi)| {
            format!(
                "{} to {}",
                crate::format::label(lo),
                crate::format::label(hi)
            )
        });
        let _ = writeln!(
            page,
            "<tr><td>{}</td><td class=\"left\">{}</td><td class=\"left\">{}</td><td class=\"left\">{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            k + 1,
            escape(&job.label.file),
            escape(&job.label.title),
            job.kind,
            job.measured.len(),
            range,
            job.modal_mass
        );
    }
    page.push_str("</table>\n");
    let name = |k: usize| format!("[{}] {}", k + 1, backbones.jobs[k].kind);
    // `lines`: whether a free decay's fitted curve is drawn (its frequencies are the
    // windows' own, which the markers show already).
    let series = |y: fn(&ZetaPoint) -> (f64, Option<f64>), lines: bool| {
        backbones
            .jobs
            .iter()
            .enumerate()
            .map(|(k, job)| JobSeries {
                name: name(k),
                measured: job.measured.iter().map(|p| (p.amplitude, y(p).0)).collect(),
                fitted: job
                    .fitted
                    .iter()
                    .filter(|_| lines || job.kind != TestKind::FreeDecay)
                    .map(|p| {
                        let (v, s) = y(p);
                        (p.amplitude, v, s)
                    })
                    .collect(),
            })
            .collect::<Vec<_>>()
    };
    page.push_str("<h2>Damping ratio ζ(X)</h2>\n<p>Markers: a free decay's energy decrement over the windows around each; a stepped-sine table's phase slope at each sweep's π/2 crossing. Lines: each job's fitted law (a free decay's at each window's frequency, a table's at ω<sub>n</sub>).</p>\n");
    let _ = writeln!(
        page,
        "{}",
        by_job(
            "Damping ratio ζ(X) of each job",
            "damping ratio ζ",
            &series(|p| (p.damping_ratio, p.std), true)
        )?
    );
    page.push_str("<h2>Frequency f(X)</h2>\n<p>Markers: a free decay's window frequencies, a table's π/2 crossings. Lines: the natural frequency a table's fitted ζ is evaluated at (a free decay's fitted ζ is evaluated at each window's own frequency, the markers).</p>\n");
    let _ = writeln!(
        page,
        "{}",
        by_job(
            "Frequency f(X) of each job",
            "frequency f (cycles per time unit)",
            &series(|p| (p.frequency, None), false)
        )?
    );
    page.push_str("<h2>Fitted ζ against the first job's</h2>\n");
    for pair in &backbones.pairs {
        let _ = writeln!(
            page,
            "<h3>{} against {}</h3>",
            escape(&name(pair.second)),
            escape(&name(pair.first))
        );
        if pair.points.is_empty() {
            page.push_str("<p>No common amplitudes: the fitted curves do not overlap.</p>\n");
            continue;
        }
        let _ = writeln!(
            page,
            "<table><tr><th>amplitude</th><th>ζ [{}]</th><th>ζ [{}]</th><th>ratio</th><th>95 % interval</th></tr>",
            pair.first + 1,
            pair.second + 1
        );
        for p in &pair.points {
            let interval = p.ratio_std.map_or("–".to_string(), |s| {
                format!("{:.4} … {:.4}", p.ratio - 1.96 * s, p.ratio + 1.96 * s)
            });
            let _ = writeln!(
                page,
                "<tr><td>{}</td><td>{:.4e}</td><td>{:.4e}</td><td>{:.4}</td><td>{interval}</td></tr>",
                crate::format::label(p.amplitude),
                p.first,
                p.second,
                p.ratio
            );
        }
        page.push_str("</table>\n");
    }
    let _ = write!(
        page,
        "<h2>Text</h2>\n<pre>{}</pre>\n",
        escape(&backbones.to_string())
    );
    let json = serde_json::to_string_pretty(backbones).unwrap_or_default();
    let _ = write!(
        page,
        "<details><summary>JSON</summary><pre>{}</pre></details>\n</body></html>\n",
        escape(&json)
    );
    Ok(page)
}
