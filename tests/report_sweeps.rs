//! The HTML page of a stepped-sine table fit, organised by sweep, and what every page
//! shares (issue 28, items 7 and 8): one row per sweep, plots coloured by sweep with
//! legends of at most 20 entries (more sweeps gathered), axes in the table's words, the
//! table file's SHA-256 in the provenance, equivalent damping on linear and estimated
//! fits alike with a ζ_eq(X) plot, and rounded numbers in the law plots' labels.
//!
//! The ζ_eq(X) plot is read back from its SVG: the tick labels give the map from data
//! to drawn pixels, and the drawn curve and markers, mapped back, must be the
//! closed-form ζ_eq(X) = E_d(X)/(2π k X²) of the generating law (viscous c plus
//! d|v|^1.5, E_d = π c ω_n X² + d ω_n^1.5 X^2.5 ∫|sin|^2.5) and each point's own
//! ζ_p = E_p/(2π k X_p²) = ω_p c_eq(X_p)/(2k) (the harmonic balance of the table's
//! generator, c_eq = c + d √(ωX) ∫|sin|^2.5 / π), within two drawn pixels.

mod support;
#[path = "support/stepped_sine_table.rs"]
mod table;

use std::f64::consts::PI;
use std::path::PathBuf;

use dampid::command::identify::{Identified, IdentifyOptions, run};
use dampid::identify::Equivalent;
use dampid::progress::silent;
use sha2::Digest;
use support::cli::dampid_ok;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("dampid_report_sweeps_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// `n` force levels log-spaced from 0.05 to 3 (the generator's range).
fn levels(n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| 0.05 * 60f64.powf(k as f64 / (n - 1).max(1) as f64))
        .collect()
}

/// A table of the viscous + power-law oscillator at `levels`, `points` frequencies per
/// sweep over ±3 % of 50 Hz (with the generator's noise when `noisy`), and its model
/// file (`extra` appended): (model file, table file).
fn table_job(
    name: &str,
    levels: &[f64],
    points: usize,
    noisy: bool,
    extra: &str,
) -> (PathBuf, PathBuf) {
    let csv = scratch(&format!("{name}.csv"));
    let noise = noisy.then_some((20, 0.005, 0.3f64.to_radians()));
    let columns = table::residual_columns_at(levels, points, 0.0, 0.0, 1.0, noise);
    support::write_scratch_csv(&csv, &table::headers(), &columns);
    let model = scratch(&format!("{name}.toml"));
    std::fs::write(&model, table::model_text(&csv, extra)).unwrap();
    (model, csv)
}

/// The page `dampid identify MODEL --report` writes, with `extra` arguments.
fn cli_page(model: &std::path::Path, name: &str, extra: &[&str]) -> String {
    let folder = scratch(name);
    std::fs::remove_dir_all(&folder).ok();
    let mut args = vec![
        "identify",
        model.to_str().unwrap(),
        "--report",
        folder.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    dampid_ok(&args);
    std::fs::read_to_string(folder.join("report.html")).unwrap()
}

/// `job` identified as `dampid identify` does, and its page (without provenance).
fn identified(job: &dampid::model_file::Job) -> (dampid::identify::Identification, String) {
    let options = IdentifyOptions::default();
    let found = run(job, &options, &silent).unwrap();
    let page = Identified {
        job,
        options: &options,
        identification: &found,
    }
    .html_with(None)
    .unwrap();
    (found, page)
}

/// Every inline SVG of the page.
fn svgs(page: &str) -> Vec<&str> {
    page.split("<svg")
        .skip(1)
        .map(|s| &s[..s.find("</svg>").unwrap()])
        .collect()
}

/// The value of attribute `name` in `tag`.
fn attr(tag: &str, name: &str) -> Option<f64> {
    let key = format!(" {name}=\"");
    let start = tag.find(&key)? + key.len();
    tag[start..start + tag[start..].find('"')?].parse().ok()
}

/// The text elements of an SVG: (x, y, text-anchor, text).
fn texts(svg: &str) -> Vec<(f64, f64, String, String)> {
    svg.split("<text")
        .skip(1)
        .filter_map(|t| {
            let head = &t[..t.find('>')?];
            let body = t[t.find('>')? + 1..t.find("</text>")?].trim().to_string();
            let anchor = head
                .split("text-anchor=\"")
                .nth(1)?
                .split('"')
                .next()?
                .to_string();
            Some((attr(head, "x")?, attr(head, "y")?, anchor, body))
        })
        .collect()
}

/// The least-squares line value = a + b · pixel through the labelled ticks.
fn axis(ticks: &[(f64, f64)]) -> (f64, f64) {
    assert!(ticks.len() >= 2, "{ticks:?}");
    let n = ticks.len() as f64;
    let (mp, mv) = (
        ticks.iter().map(|t| t.0).sum::<f64>() / n,
        ticks.iter().map(|t| t.1).sum::<f64>() / n,
    );
    let b = ticks.iter().map(|t| (t.0 - mp) * (t.1 - mv)).sum::<f64>()
        / ticks.iter().map(|t| (t.0 - mp).powi(2)).sum::<f64>();
    (mv - b * mp, b)
}

/// The ζ_eq(X) plot read back: (log10 X of a pixel, ζ of a pixel) maps, the drawn
/// curve (log10 X, ζ) and the markers' centres in the plot (log10 X, ζ), and the
/// pixel size in ζ.
struct ZetaPlot {
    curve: Vec<(f64, f64)>,
    markers: Vec<(f64, f64)>,
    pixel: (f64, f64),
}

fn zeta_plot(page: &str) -> ZetaPlot {
    let svg = svgs(page)
        .into_iter()
        .find(|s| s.contains("Equivalent viscous damping ratio ζ_eq(X)"))
        .expect("a ζ_eq(X) plot");
    let labels = texts(svg);
    // x ticks: decade labels "1e-4" (the axis holds log10 X); y ticks: right-aligned.
    let x_ticks: Vec<(f64, f64)> = labels
        .iter()
        .filter(|t| t.2 == "middle")
        .filter_map(|t| Some((t.0, t.3.parse::<f64>().ok()?.log10())))
        .collect();
    let y_ticks: Vec<(f64, f64)> = labels
        .iter()
        .filter(|t| t.2 == "end")
        .filter_map(|t| Some((t.1, t.3.parse::<f64>().ok()?)))
        .collect();
    let (x, y) = (axis(&x_ticks), axis(&y_ticks));
    let at = |px: f64, py: f64| (x.0 + x.1 * px, y.0 + y.1 * py);
    // The plot area ends at the x axis's labels; the legend lies below.
    let bottom = x_ticks.first().map_or(f64::INFINITY, |_| {
        labels
            .iter()
            .filter(|t| t.2 == "middle" && t.3.parse::<f64>().is_ok())
            .map(|t| t.1)
            .fold(f64::INFINITY, f64::min)
    });
    // The fitted curve: the black 2 px polyline with more than two points.
    let curve = svg
        .split("<polyline")
        .skip(1)
        .map(|p| &p[..p.find("/>").unwrap()])
        .filter(|p| p.contains("stroke=\"#000000\"") && p.contains("stroke-width=\"8\""))
        .map(|p| {
            let points = p
                .split("points=\"")
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap();
            points
                .split_whitespace()
                .map(|xy| {
                    let (px, py) = xy.split_once(',').unwrap();
                    at(px.parse().unwrap(), py.parse().unwrap())
                })
                .collect::<Vec<_>>()
        })
        .find(|p| p.len() > 2)
        .expect("the fitted curve");
    let markers = svg
        .split("<circle")
        .skip(1)
        .filter_map(|c| {
            let head = &c[..c.find("/>")?];
            let (px, py) = (attr(head, "cx")?, attr(head, "cy")?);
            (py < bottom && !head.contains("fill=\"none\"")).then(|| at(px, py))
        })
        .collect();
    ZetaPlot {
        curve,
        markers,
        pixel: (x.1.abs(), y.1.abs()),
    }
}

/// ∫₀^{2π} |sin θ|^2.5 dθ.
fn sine_integral() -> f64 {
    table::sine_power_integral(2.5)
}

/// The closed-form ζ_eq(X) of the generating law at ω_n (module doc).
fn true_zeta(x: f64) -> f64 {
    let omega = (table::K / table::M).sqrt();
    let energy =
        PI * table::C * omega * x * x + table::D * (omega * x).powf(1.5) * x * sine_integral();
    energy / (2.0 * PI * table::K * x * x)
}

/// A table of 30 sweeps: one Sweeps row per sweep, legends of at most 20 entries with
/// the sweeps beyond the 17th gathered, the table's words on the axes (no windows), the
/// table file with its SHA-256 and no "simulated" provenance.
#[test]
fn a_table_page_is_organised_by_sweep() {
    let (model, csv) = table_job("thirty", &levels(30), 9, true, "");
    let page = cli_page(&model, "thirty_page", &[]);
    assert!(page.contains("270 points from 30 sweeps"), "header");
    let sweeps = &page[page.find("<h2>Sweeps</h2>").expect("a Sweeps table")..];
    let sweeps = &sweeps[..sweeps.find("</table>").unwrap()];
    assert_eq!(
        sweeps.matches("<tr").count(),
        31,
        "a header and one row per sweep"
    );
    for k in 1..=30 {
        assert!(
            sweeps.contains(&format!("<td>level = {k}</td>")),
            "sweep {k}"
        );
    }
    assert!(!page.contains("<h2>Records</h2>"));
    let plots = svgs(&page);
    assert!(plots.len() >= 5, "{} plots", plots.len());
    let mut gathered = 0;
    for svg in &plots {
        // Legend entries are the left-aligned texts.
        let entries = texts(svg).iter().filter(|t| t.2 == "start").count();
        assert!(entries <= 20, "a legend of {entries} entries");
        // The sweeps beyond those with a marker of their own share one entry.
        let named = |name: &str| texts(svg).iter().any(|t| t.3 == name);
        if let Some(kept) = (1..30).find(|k| named(&format!("{} more sweeps", 30 - k))) {
            gathered += 1;
            assert!(named(&format!("level = {kept}")), "{kept}");
            assert!(!named(&format!("level = {}", kept + 1)), "{kept}");
        }
    }
    // The energy balance, residuals, energy per cycle and ζ_eq(X) colour by sweep.
    assert_eq!(gathered, 4, "plots coloured by sweep");
    for words in [
        "Energy balance per point",
        "input energy per cycle π a X sin φ",
        "Residuals b − Aθ per point",
        "frequency ω/2π [Hz]",
        "Every point (270)",
        "<th>stepped-sine table</th>",
    ] {
        assert!(page.contains(words), "missing {words}");
    }
    for absent in [
        "per window",
        "equation (window)",
        "from 30 records",
        "No data files",
    ] {
        assert!(!page.contains(absent), "the page says {absent}");
    }
    let sha = sha2::Sha256::digest(std::fs::read(&csv).unwrap());
    let hex: String = sha.iter().map(|b| format!("{b:02x}")).collect();
    assert!(page.contains(&hex), "the table file's SHA-256");
}

/// The ζ_eq(X) plot of a linear fit on a noise-free table: its curve is the fit's
/// equivalent damping and the generating law's closed form; its markers are the points
/// within 2 % of ω_n, each at its own ζ_p (module doc), and no other.
#[test]
fn the_zeta_plot_draws_the_equivalent_damping_and_each_points_own_ratio() {
    let (model, _) = table_job("zeta", &[0.1, 0.5, 2.0], 41, false, "");
    let job = dampid::model_file::load(&model, Default::default()).unwrap();
    let (found, page) = identified(&job);
    let Some(Equivalent::Computed(equivalent)) = &found.equivalent else {
        panic!("no equivalent damping: {:?}", found.equivalent)
    };
    let plot = zeta_plot(&page);
    let tolerance = 2.0 * plot.pixel.1;
    assert_eq!(plot.curve.len(), equivalent.points.len());
    for ((x, zeta), p) in plot.curve.iter().zip(&equivalent.points) {
        assert!(
            (x - p.amplitude.log10()).abs() <= 2.0 * plot.pixel.0,
            "{x} vs {}",
            p.amplitude
        );
        assert!(
            (zeta - p.damping_ratio).abs() <= tolerance,
            "{zeta} vs {}",
            p.damping_ratio
        );
        let truth = true_zeta(p.amplitude);
        assert!(
            (zeta - truth).abs() <= tolerance,
            "X = {}: {zeta} vs truth {truth}",
            p.amplitude
        );
    }
    // Each point's own ratio, for those near resonance.
    let omega_n = (table::K / table::M).sqrt();
    let columns = table::residual_columns_at(&[0.1, 0.5, 2.0], 41, 0.0, 0.0, 1.0, None);
    let expected: Vec<(f64, f64)> = (0..columns[0].len())
        .filter_map(|i| {
            let omega = 2.0 * PI * columns[1][i];
            let x = columns[3][i];
            ((omega / omega_n - 1.0).abs() <= 0.02).then(|| {
                let c_eq = table::C + table::D * (omega * x).sqrt() * sine_integral() / PI;
                (x.log10(), omega * c_eq / (2.0 * table::K))
            })
        })
        .collect();
    assert!(expected.len() > 20 && expected.len() < columns[0].len());
    assert_eq!(
        plot.markers.len(),
        expected.len(),
        "one marker per point near resonance"
    );
    for (x, zeta) in &expected {
        assert!(
            plot.markers
                .iter()
                .any(|m| (m.0 - x).abs() <= 2.0 * plot.pixel.0 && (m.1 - zeta).abs() <= tolerance),
            "no marker at log10 X = {x}, ζ = {zeta}"
        );
    }
    assert!(page.contains(&format!(
        "for the {} of 123 points within 2% of ω_n",
        expected.len()
    )));
    // ζ at the measured levels: one open square per sweep on the plot, and a table
    // row per sweep whose fitted ζ_eq(X_c) is the law's at that amplitude.
    assert_eq!(equivalent.levels.len(), 3, "{equivalent}");
    let svg = svgs(&page)
        .into_iter()
        .find(|s| s.contains("Equivalent viscous damping ratio"))
        .unwrap();
    assert!(svg.contains("ζ measured at each sweep"), "no legend entry");
    for level in &equivalent.levels {
        let truth = true_zeta(level.amplitude);
        assert!(
            (level.fitted / truth - 1.0).abs() < 0.01,
            "{level:?} vs {truth}"
        );
        let row = format!(
            "<tr><td>{}</td><td>{:.6e}</td><td>{:.4e}</td>",
            level.sweep,
            level.frequency / (2.0 * PI),
            level.amplitude
        );
        assert!(page.contains(&row), "no row {row}");
    }
}

/// Every fit gets the one page: a linear table fit with a bootstrap says it resampled
/// whole sweeps and shows the equivalent damping; a fit with estimated residual
/// receptances adds its parameter table and joint intervals to the same sections.
#[test]
fn every_fit_gets_the_same_page() {
    let (model, _) = table_job("bootstrap", &levels(6), 11, true, "");
    let page = cli_page(&model, "bootstrap_page", &["--bootstrap", "40"]);
    let bootstrap = &page[page
        .find("<h2>Bootstrap</h2>")
        .expect("a bootstrap section")..];
    let bootstrap = &bootstrap[..bootstrap.find("</table>").unwrap()];
    assert!(
        bootstrap.contains("each drew 6 whole sweeps with replacement"),
        "{bootstrap}"
    );
    assert!(bootstrap.contains("<tr><td>c</td>") && bootstrap.contains("<tr><td>d</td>"));
    assert!(!page.contains("Estimated nonlinear parameters"));
    let residual = cli_page(
        std::path::Path::new("models/bolted_joint_stepped_sine_residual.toml"),
        "residual_page",
        &[],
    );
    for p in [&page, &residual] {
        assert_eq!(p.matches("<h2>Coefficients</h2>").count(), 1);
        for section in [
            "<h2>Sweeps</h2>",
            "<h2>Energy balance</h2>",
            "<h2>Identified damping laws</h2>",
            "<h2>Dissipated energy per cycle</h2>",
            "<h2>Equivalent damping</h2>",
            "Equivalent viscous damping ratio ζ_eq(X)",
            "<th>ζ_eq interval</th>",
        ] {
            assert!(p.contains(section), "missing {section}");
        }
    }
    assert!(residual.contains("Estimated nonlinear parameters"));
    assert!(residual.contains("joint 95% interval"));
    assert!(
        page.contains("from the covariance of the coefficients (the modal mass taken as exact)")
    );
}

/// An estimated exponent reads rounded in the law plot's title and the coefficient's
/// unit, not with all sixteen digits.
#[test]
fn numbers_in_law_labels_are_rounded() {
    let text = std::fs::read_to_string("models/four_mass_power.toml").unwrap()
        + "\n[units]\nlength = \"m\"\nforce = \"N\"\ntime = \"s\"\n";
    let job = dampid::model_file::parse(
        &text,
        "test.toml",
        std::path::Path::new("models"),
        Default::default(),
    )
    .unwrap();
    let (found, page) = identified(&job);
    let exponent = found.report.parameter("d.exponent").unwrap();
    let digits = |text: &str| {
        text.trim_start_matches(['0', '.'])
            .chars()
            .filter(char::is_ascii_digit)
            .count()
    };
    assert!(
        digits(&format!("{exponent}")) > 4,
        "{exponent} needs no rounding"
    );
    let visible = &page[..page.find("<summary>Report JSON").unwrap()];
    for (prefix, end) in [("power(", ')'), ("N·(s/m)^", '<')] {
        let shown: Vec<&str> = visible
            .split(prefix)
            .skip(1)
            .map(|rest| &rest[..rest.find(end).unwrap()])
            .collect();
        assert!(!shown.is_empty(), "no {prefix}");
        for number in shown {
            assert!(digits(number) <= 4, "{prefix}{number}");
            let value: f64 = number.parse().unwrap();
            assert!(
                (value - exponent).abs() <= 5e-4 * exponent,
                "{number} vs {exponent}"
            );
        }
    }
}
