//! `dampid identify --report DIR` writes a self-contained HTML report with the plots.

mod support;
use dampid::progress::silent;
use support::cli::{dampid_json, dampid_ok};

#[test]
fn identify_writes_an_html_report_with_plots() {
    let folder = std::env::temp_dir().join(format!("dampid-html-{}", std::process::id()));
    std::fs::remove_dir_all(&folder).ok(); // a stale folder of an earlier run
    // stdout stays pure JSON.
    let json = dampid_json(&[
        "identify",
        "models/measured_chain.toml",
        "--json",
        "--report",
        folder.to_str().unwrap(),
    ]);
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
    // No [pod] in the model file: no POM section.
    assert!(!page.contains("Proper orthogonal modes"));
    assert!(!page.contains("POM"));
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

/// A model file with `[pod]` (one basis per record) adds the POM section: a summary of
/// every basis, and for the first three a table of the modes, the retained shapes and the
/// energy shares.
#[test]
fn pod_report_shows_the_proper_orthogonal_modes() {
    let folder = std::env::temp_dir().join(format!("dampid-html-pod-{}", std::process::id()));
    std::fs::remove_dir_all(&folder).ok(); // a stale folder of an earlier run
    dampid_ok(&[
        "identify",
        "models/four_mass_pod.toml",
        "--report",
        folder.to_str().unwrap(),
    ]);
    let page = std::fs::read_to_string(folder.join("report.html")).unwrap();
    let (fit, pom) = page
        .split_once("<h2>Proper orthogonal modes</h2>")
        .expect("a POM section");
    assert_eq!(
        fit.matches("<svg").count(),
        3,
        "balance, residuals, the quadratic law"
    );
    assert_eq!(
        pom.matches("<svg").count(),
        6,
        "shapes and energy shares of the first three of four bases"
    );
    for needle in [
        "One basis per record (4 bases)",
        "the first 3 are drawn",
        // The summary lists all four amplitudes' bases; the paper's dominant shares.
        "Record 4 (a=1 ω=0.618 on DOF 4)",
        "98.8196%",
        "97.0052%",
        "2 of 4 modes retained",
        "<th>cumulative share</th>",
        "Retained POM shapes: Record 1 (a=0.25 ω=0.618 on DOF 4)",
        "POM 1 (98.8196%)",
        "POM 2 (",
        "DOF (sensor)",
        "Energy share per POM: Record 3 (a=0.75 ω=0.618 on DOF 4)",
        "retained: 2 mode(s)",
        "discarded: 2 mode(s)",
    ] {
        assert!(pom.contains(needle), "missing {needle}");
    }
    // Only the retained modes are drawn as shapes.
    assert!(!pom.contains("POM 3 ("));
    for fetch in ["<script", "<link", "src=", "href=", "url("] {
        assert!(!page.contains(fetch), "the report must not load {fetch}");
    }
    std::fs::remove_dir_all(&folder).ok();
}

/// With the noise-robust pipeline the page also shows the model check and, per window,
/// the harmonics kept and the estimated noise.
#[test]
fn noise_robust_report_shows_the_noise_and_the_model_check() {
    use dampid::identify::identify;
    use dampid::report::html::HtmlReport;
    let text = std::fs::read_to_string("models/measured_chain.toml")
        .unwrap()
        .replace(
            "velocity = \"spectral\"       # derivative of a Fourier series in harmonics of the drive",
            "velocity = \"harmonic_projection\"",
        );
    let job = dampid::model_file::parse(
        &text,
        "test.toml",
        std::path::Path::new("models"),
        Default::default(),
    )
    .unwrap();
    let (regressor, report) = identify(&job.problem(), &job.settings, &silent)
        .map(|i| (i.regressor, i.report))
        .unwrap();
    assert!(report.noise.is_some());
    let page = HtmlReport {
        title: &job.title,
        model: &job.model,
        source: (&job.records).into(),
        regressor: &regressor,
        report: &report,
        truth: None,
        pod: None,
        steady: None,
        equivalent: None,
        backbone: None,
        provenance: None,
        units: None,
    }
    .render()
    .unwrap();
    for needle in ["Noise and model check", "χ² =", "harmonics kept"] {
        assert!(page.contains(needle), "missing {needle}");
    }
    // the harmonic orders, from the fundamental, as a list or as runs ("1–9, 11–43 odd")
    assert!(
        page.contains("<td>1, ") || page.contains("<td>1–"),
        "no harmonic orders"
    );
}
