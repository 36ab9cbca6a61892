//! Where the report came from: dampid's version and git commit, the date, the model
//! file (its text folded) or the Python arrays (each by shape and SHA-256), the data
//! files read (the records' files, or a stepped-sine table's) with their size and
//! SHA-256, the units, and every setting in effect with where its value came from
//! (folded).

use std::fmt::Write as _;

use super::escape;
use crate::report::provenance::Provenance;
use crate::report::units::Units;

/// The provenance section (module doc); `files` names what the data files are ("data
/// file", or "stepped-sine table").
pub(super) fn section(p: &Provenance, units: &Units, files: &str) -> String {
    let mut out = String::from("\n<h2>Provenance</h2>\n");
    let from = if p.arrays.is_empty() {
        format!("the model file <code>{}</code>", escape(&p.model_file))
    } else {
        "records from Python arrays".into()
    };
    let _ = writeln!(
        out,
        "<p>Made {} by dampid {} (git commit <code>{}</code>) from {from}.</p>",
        escape(&p.date),
        escape(&p.version),
        escape(&p.commit),
    );
    if p.arrays.is_empty() || !p.model_text.is_empty() {
        let _ = writeln!(
            out,
            "<details><summary>Model file <code>{}</code></summary><pre>{}</pre></details>",
            escape(&p.model_file),
            escape(&p.model_text)
        );
    }
    if !p.arrays.is_empty() {
        out.push_str("<table><tr><th>record</th><th>array</th><th>shape</th><th>SHA-256 (float64, little-endian, C order)</th></tr>\n");
        for a in &p.arrays {
            let shape: Vec<String> = a.shape.iter().map(|s| s.to_string()).collect();
            let _ = writeln!(
                out,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td><code class=\"hash\">{}</code></td></tr>",
                escape(&a.record),
                escape(&a.name),
                shape.join(" × "),
                a.sha256
            );
        }
        out.push_str("</table>\n");
    } else if p.data_files.is_empty() {
        out.push_str("<p>No data files: the records were simulated from the model file.</p>\n");
    }
    if !p.data_files.is_empty() {
        let _ = writeln!(
            out,
            "<table><tr><th>{}</th><th>bytes</th><th>SHA-256</th></tr>",
            escape(files)
        );
        for f in &p.data_files {
            let _ = writeln!(
                out,
                "<tr><td>{}</td><td>{}</td><td><code class=\"hash\">{}</code></td></tr>",
                escape(&f.path),
                f.bytes,
                f.sha256
            );
        }
        out.push_str("</table>\n");
    }
    if units.is_empty() {
        out.push_str("<p>Units: none given (a <code>[units]</code> section names them).</p>\n");
    } else {
        let given: Vec<String> = [
            ("length", &units.length),
            ("force", &units.force),
            ("time", &units.time),
            ("angle", &units.angle),
            ("mass", &units.mass),
        ]
        .iter()
        .filter_map(|(d, u)| u.as_ref().map(|u| format!("{d} {}", escape(u))))
        .collect();
        let _ = writeln!(out, "<p>Units: {}.</p>", given.join(", "));
    }
    out.push_str("<details><summary>Every setting in effect, defaults included</summary>\n<table><tr><th>section</th><th>key</th><th>value</th><th>source</th></tr>\n");
    for s in &p.settings {
        let _ = writeln!(
            out,
            "<tr><td class=\"left\">{}</td><td class=\"left\"><code>{}</code></td><td class=\"left\"><code>{}</code></td><td class=\"left\">{}</td></tr>",
            escape(&s.section),
            escape(&s.key),
            escape(&s.value),
            s.source.text()
        );
    }
    out.push_str("</table>\n</details>\n");
    out
}
