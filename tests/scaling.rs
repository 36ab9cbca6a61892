//! Diagnostics that scale: models/chain100.toml, a 100-DOF chain with a linear dashpot
//! per link and a quadratic damper per mass (201 coefficients) identified from 100
//! one-period windows, so that at least 101 directions are not determined. Its text
//! reports summarise (under 200 lines: counts by term, the largest contributors and
//! "+ N more", VIFs as a top list and histogram) while the JSON keeps every direction
//! as a whole coefficient vector.

mod support;
use support::cli::{dampid_json, dampid_ok};

const MODEL: &str = "models/chain100.toml";

fn lines(bytes: &[u8]) -> Vec<String> {
    String::from_utf8_lossy(bytes)
        .lines()
        .map(str::to_string)
        .collect()
}

#[test]
fn the_201_coefficient_chain_reads_in_under_200_lines_and_the_json_keeps_everything() {
    let check = lines(&dampid_ok(&["check", MODEL]).stdout);
    let identify = lines(&dampid_ok(&["identify", MODEL]).stdout);
    for (command, text) in [("check", &check), ("identify", &identify)] {
        let all = text.join("\n");
        assert!(text.len() < 200, "{command}: {} lines\n{all}", text.len());
        // No line runs over every coefficient: the longest stays readable.
        let longest = text.iter().map(|l| l.chars().count()).max().unwrap();
        assert!(
            longest < 600,
            "{command}: a line of {longest} characters\n{all}"
        );
        assert!(all.contains("more"), "{command}: nothing summarised\n{all}");
        assert!(
            all.contains("by term: dashpot"),
            "{command}: no counts by term\n{all}"
        );
    }
    let all = identify.join("\n");
    assert!(all.contains("not determined:"), "{all}");

    let json = dampid_json(&["check", MODEL, "--json"]);
    let identifiability = &json["identifiability"];
    let names = identifiability["names"].as_array().unwrap();
    assert_eq!(names.len(), 201);
    let nulls = identifiability["null_directions"].as_array().unwrap();
    let determined = identifiability["determined"].as_array().unwrap();
    // 100 equations for 201 unknowns: at most 100 singular values are not zero.
    assert!(nulls.len() >= 101, "{} null directions", nulls.len());
    assert_eq!(
        nulls.len() + determined.len(),
        201,
        "every right singular vector is a null direction or a determined combination"
    );
    for d in nulls {
        let weights = d["direction"]["weights"].as_array().unwrap();
        assert_eq!(weights.len(), 201);
        // Normalised to a largest component of 1.
        let largest = weights
            .iter()
            .map(|w| w.as_f64().unwrap().abs())
            .fold(0.0, f64::max);
        assert!((largest - 1.0).abs() < 1e-12, "{largest}");
        // The kept terms are the weights at or above 5% of the largest.
        let kept = weights
            .iter()
            .filter(|w| w.as_f64().unwrap().abs() >= 0.05)
            .count();
        assert_eq!(d["direction"]["terms"].as_array().unwrap().len(), kept);
    }
    // The text and the JSON agree on the counts.
    let check_text = check.join("\n");
    assert!(
        check_text.contains(&format!("{} direction(s) not determined", nulls.len())),
        "{check_text}"
    );
}

/// The HTML report of the 201-coefficient chain summarises as the text report does: the
/// undetermined coefficients counted by term with every row folded, the determined
/// combinations grouped by term, the 10 smallest undetermined directions and "+ N
/// more", the 10 largest VIFs sorted and a histogram by decade, the most correlated
/// pairs instead of the 201 × 201 matrix; the page before its folded JSON stays small.
#[test]
fn the_html_report_of_the_201_coefficient_chain_summarises() {
    let folder = std::env::temp_dir().join(format!("dampid-scaling-html-{}", std::process::id()));
    std::fs::remove_dir_all(&folder).ok();
    dampid_ok(&["identify", MODEL, "--report", folder.to_str().unwrap()]);
    let page = std::fs::read_to_string(folder.join("report.html")).unwrap();
    let visible = &page[..page.find("<summary>Report JSON").unwrap()];
    for needle in [
        "<b>not determined</b>: ",
        "of 201 coefficients (by term: dashpot",
        "<summary>Every coefficient (201)</summary>",
        "<h3>Determined combinations</h3>",
        "<th>term</th><th>combinations</th>",
        "the 10 smallest, each by its 5 largest components",
        "(<code>identifiability.null_directions</code> in the JSON)",
        "The 10 largest of 201, sorted:",
        "Histogram of the VIFs by decade:",
        "most correlated of 20100 pairs",
    ] {
        assert!(visible.contains(needle), "missing {needle}");
    }
    // The largest VIFs are listed in decreasing order.
    let start = visible.find("The 10 largest of 201, sorted:").unwrap();
    let table = &visible[start..start + visible[start..].find("</table>").unwrap()];
    let vifs: Vec<f64> = table
        .split("<tr><td>")
        .skip(1)
        .map(|row| {
            let cell = row.split("</td><td>").nth(1).unwrap();
            cell.trim_end_matches("</td></tr>\n").parse().unwrap()
        })
        .collect();
    assert_eq!(vifs.len(), 10);
    assert!(vifs.windows(2).all(|w| w[0] >= w[1]), "{vifs:?}");
    // No table row per pair of coefficients: the correlation matrix is not drawn.
    let rows = visible.matches("<tr>").count();
    assert!(rows < 1500, "{rows} table rows");
    assert!(
        visible.len() < 1_000_000,
        "{} bytes before the JSON",
        visible.len()
    );
    std::fs::remove_dir_all(&folder).ok();
}
