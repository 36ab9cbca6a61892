//! docs/model-file.md documents every key the model-file parser accepts, with its type,
//! default, unit and an example.
//!
//! The key lists come from the parser itself: each probe is a document with an unknown
//! key in one table; the schema rejects unknown keys (`deny_unknown_fields`) and its
//! error lists the keys that table accepts ("unknown field `…`, expected one of `a`,
//! `b`"). A key added to src/model_file/spec.rs appears in its table's list, and this
//! test fails until docs/model-file.md has a row for it in that table's section. A new
//! table is a new key of its parent, so it fails the same way until documented (and
//! then wants a probe of its own here).

const UNKNOWN: &str = "zz_not_a_key";

/// (the section's heading in docs/model-file.md, a document whose first key in that
/// table is unknown).
fn probes() -> Vec<(&'static str, String)> {
    let k = UNKNOWN;
    vec![
        ("## Top level", format!("{k} = 1\n")),
        (
            "## [[terms]]",
            format!("[[terms]]\nkind = \"law\"\n{k} = 1\n"),
        ),
        (
            "## [[terms]]",
            format!("[[terms]]\nkind = \"viscous\"\n{k} = 1\n"),
        ),
        (
            "## [[terms]]",
            format!("[[terms]]\nkind = \"stiffness_proportional\"\n{k} = 1\n"),
        ),
        (
            "## [[terms]]",
            format!("[[terms]]\nkind = \"mass_proportional\"\n{k} = 1\n"),
        ),
        (
            "## [[terms]]",
            format!("[[terms]]\nkind = \"bouc_wen\"\n{k} = 1\n"),
        ),
        (
            "## [[terms]]",
            format!("[[terms]]\nkind = \"dahl\"\n{k} = 1\n"),
        ),
        (
            "## [[terms]]",
            format!("[[terms]]\nkind = \"iwan\"\n{k} = 1\n"),
        ),
        (
            "## [[terms]]",
            format!("[[terms]]\nkind = \"structural\"\n{k} = 1\n"),
        ),
        (
            "## [identification]",
            format!("[identification]\n{k} = 1\n"),
        ),
        (
            "## [identification]",
            format!("[identification]\nbounds = {{ c = {{ {k} = 1 }} }}\n"),
        ),
        (
            "## [identification]",
            format!("[identification]\nconstraints = [{{ {k} = 1 }}]\n"),
        ),
        ("## [simulation]", format!("[simulation]\n{k} = 1\n")),
        (
            "## [simulation]",
            format!("[simulation]\ncubic_springs = [{{ {k} = 1 }}]\n"),
        ),
        (
            "### [[simulation.experiments]]",
            format!("[[simulation.experiments]]\n{k} = 1\n"),
        ),
        ("## [[data.records]]", format!("[data]\n{k} = 1\n")),
        (
            "## [[data.records]]",
            format!("[[data.records]]\n{k} = 1\n"),
        ),
        (
            "## [[data.records]]",
            format!("[[data.records]]\ndisplacements = [{{ {k} = 1 }}]\n"),
        ),
        (
            "## [[data.records]]",
            format!("[[data.records]]\nforces = [{{ {k} = 1 }}]\n"),
        ),
        ("## [design]", format!("[design]\n{k} = 1\n")),
        (
            "## [string_simulation]",
            format!("[string_simulation]\n{k} = 1\n"),
        ),
        ("## [system]", format!("[system]\n{k} = 1\n")),
        (
            "## [system]",
            format!("[system]\ncubic_springs = [{{ {k} = 1 }}]\n"),
        ),
        ("## [pod]", format!("[pod]\n{k} = 1\n")),
        ("## [stepped_sine]", format!("[stepped_sine]\n{k} = 1\n")),
        (
            "## [stepped_sine]",
            format!("[stepped_sine]\nstructural = [{{ {k} = 1 }}]\n"),
        ),
        (
            "## [stepped_sine]",
            format!("[stepped_sine]\nkeep = {{ {k} = 1 }}\n"),
        ),
        (
            "## [harmonic_approximation]",
            format!("[harmonic_approximation]\n{k} = 1\n"),
        ),
        ("## [non_periodic]", format!("[non_periodic]\n{k} = 1\n")),
    ]
}

/// The keys the parser's error for `document` says its table accepts.
fn accepted_keys(document: &str) -> Vec<String> {
    let error = dampid::model_file::parse(
        document,
        "probe.toml",
        std::path::Path::new("."),
        Default::default(),
    )
    .expect_err("a document with an unknown key is refused")
    .to_string();
    assert!(
        error.contains(&format!("unknown field `{UNKNOWN}`")),
        "the probe did not reach the table's key check:\n{document}\n{error}"
    );
    let listed = error
        .split_once("expected")
        .map(|(_, rest)| rest)
        .unwrap_or_else(|| panic!("no list of keys in: {error}"));
    let keys: Vec<String> = listed
        .split('`')
        .skip(1)
        .step_by(2)
        .map(str::to_string)
        .collect();
    assert!(!keys.is_empty(), "no keys listed in: {error}");
    keys
}

/// The text of the section under `heading`, up to the next heading.
fn section<'a>(doc: &'a str, heading: &str) -> &'a str {
    let start = doc
        .lines()
        .position(|l| l.trim_end() == heading)
        .unwrap_or_else(|| panic!("docs/model-file.md has no heading '{heading}'"));
    let lines: Vec<&str> = doc.lines().collect();
    let end = (start + 1..lines.len())
        .find(|&i| lines[i].starts_with("## ") || lines[i].starts_with("### "))
        .unwrap_or(lines.len());
    let from = lines[..start].iter().map(|l| l.len() + 1).sum::<usize>();
    let to = lines[..end].iter().map(|l| l.len() + 1).sum::<usize>();
    &doc[from..to.min(doc.len())]
}

/// The row `| `key` | type | default | unit | example |` of `key` in `section`, split
/// into its cells.
fn row<'a>(section: &'a str, key: &str) -> Option<Vec<&'a str>> {
    let start = format!("| `{key}` |");
    section.lines().find(|l| l.starts_with(&start)).map(|l| {
        l.trim()
            .trim_matches('|')
            .split(" | ")
            .map(str::trim)
            .collect()
    })
}

#[test]
fn every_key_the_parser_accepts_is_documented_with_type_default_unit_and_example() {
    let doc = std::fs::read_to_string("docs/model-file.md").unwrap();
    let mut missing = Vec::new();
    let mut checked = 0;
    for (heading, document) in probes() {
        let text = section(&doc, heading);
        for key in accepted_keys(&document) {
            checked += 1;
            match row(text, &key) {
                None => missing.push(format!("{heading}: `{key}`")),
                Some(cells) => assert!(
                    cells.len() >= 5 && cells[1..5].iter().all(|c| !c.is_empty()),
                    "{heading}: `{key}` needs a type, a default, a unit (– for none) and an example: {cells:?}"
                ),
            }
        }
    }
    assert!(
        missing.is_empty(),
        "keys the parser accepts but docs/model-file.md does not document:\n{}",
        missing.join("\n")
    );
    // The probes reach the tables: the schema has well over a hundred keys.
    assert!(checked > 100, "only {checked} keys probed");
}

/// The probe itself can fail: a key that is not in the docs is reported.
#[test]
fn an_undocumented_key_would_be_found() {
    let doc = std::fs::read_to_string("docs/model-file.md").unwrap();
    let text = section(&doc, "## [pod]");
    assert!(row(text, "modes").is_some());
    assert!(row(text, "not_documented").is_none());
    let keys = accepted_keys(&format!("[pod]\n{UNKNOWN} = 1\n"));
    assert_eq!(keys, ["modes", "energy", "basis", "remove_mean"]);
}

/// Each documented example row names a key of its section that the parser accepts:
/// a documented key that no longer exists is found too.
#[test]
fn every_documented_key_exists() {
    let doc = std::fs::read_to_string("docs/model-file.md").unwrap();
    let mut accepted: std::collections::BTreeMap<&str, Vec<String>> = Default::default();
    for (heading, document) in probes() {
        accepted
            .entry(heading)
            .or_default()
            .extend(accepted_keys(&document));
    }
    for (heading, keys) in &accepted {
        for line in section(&doc, heading).lines() {
            let Some(rest) = line.strip_prefix("| `") else {
                continue;
            };
            let key = rest.split('`').next().unwrap();
            // `known` is the one key of an untagged table the errors cannot list, `kind`
            // the tag that chooses a [[terms]] variant (its error lists the variant's keys).
            assert!(
                keys.iter().any(|k| k == key) || key == "known" || key == "kind",
                "{heading} documents `{key}`, which the parser does not accept"
            );
        }
    }
}
