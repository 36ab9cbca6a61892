//! `dampid identify --report DIR` writes a self-contained HTML report with the plots.

use std::process::Command;

#[test]
fn identify_writes_an_html_report_with_plots() {
    let folder = std::env::temp_dir().join(format!("dampid-html-{}", std::process::id()));
    let output = Command::new(env!("CARGO_BIN_EXE_dampid"))
        .args([
            "identify",
            "models/measured_chain.toml",
            "--json",
            "--report",
        ])
        .arg(&folder)
        .output()
        .unwrap();
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    // stdout stays pure JSON.
    let json: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    assert_eq!(json["report"]["status"], "solved");

    let page = std::fs::read_to_string(folder.join("report.html")).unwrap();
    assert!(page.starts_with("<!DOCTYPE html>"));
    assert_eq!(
        page.matches("<svg").count(),
        4,
        "balance, residuals, one law plot per element term"
    );
    for needle in [
        "Energy balance per window",
        "Residuals b − Aθ per equation",
        "linear law",
        "coulomb law",
        "dashpot[2-3]",
        "friction",
        "95% interval",
    ] {
        assert!(page.contains(needle), "missing {needle}");
    }
    // Self-contained: no scripts, stylesheets or images fetched from anywhere (the only
    // URL is the SVG namespace, which is a name, not a fetch).
    for fetch in ["<script", "<link", "src=", "href=", "url("] {
        assert!(
            !page.contains(fetch),
            "the report must not load anything: found {fetch}"
        );
    }
    std::fs::remove_dir_all(&folder).ok();
}
