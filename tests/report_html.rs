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

/// With the noise-robust pipeline the page also shows the model check and, per window,
/// the harmonics kept and the estimated noise.
#[test]
fn noise_robust_report_shows_the_noise_and_the_model_check() {
    use dampid::identify::identify_with_regressor;
    use dampid::report_html::HtmlReport;
    let text = std::fs::read_to_string("models/measured_chain.toml")
        .unwrap()
        .replace(
            "velocity = \"spectral\"       # derivative of a Fourier series in harmonics of the drive",
            "velocity = \"harmonic_projection\"",
        );
    let job =
        dampid::model_file::parse(&text, "test.toml", std::path::Path::new("models")).unwrap();
    let (regressor, report) =
        identify_with_regressor(&job.model, &job.records, &job.settings).unwrap();
    assert!(report.noise.is_some());
    let page = HtmlReport {
        title: &job.title,
        model: &job.model,
        records: &job.records,
        regressor: &regressor,
        report: &report,
        truth: None,
        pod: None,
    }
    .render()
    .unwrap();
    for needle in ["Noise and model check", "χ² =", "harmonics kept", "<td>1, "] {
        assert!(page.contains(needle), "missing {needle}");
    }
}
