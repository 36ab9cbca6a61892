//! `dampid backbones` refuses jobs whose backbones cannot be put side by side
//! ([`dampid::Error::Incomparable`]), naming the files: different length or time units,
//! a job that is not one mode (forced records), fewer than two jobs.

use std::path::Path;

use dampid::Error;
use dampid::command::backbones::run;
use dampid::model_file::{Job, Options, load, parse};
use dampid::progress::silent;

fn shipped(file: &str) -> (String, Job) {
    (
        file.to_string(),
        load(Path::new(file), Options::default()).unwrap(),
    )
}

/// The shipped table with `from` replaced by `to` in its model file, named `name`.
fn edited(from: &str, to: &str, name: &str) -> (String, Job) {
    let text = std::fs::read_to_string("models/backbones_stepped.toml").unwrap();
    assert!(text.contains(from), "{from}");
    let job = parse(
        &text.replacen(from, to, 1),
        name,
        Path::new("models"),
        Options::default(),
    )
    .unwrap();
    (name.to_string(), job)
}

#[test]
fn different_units_are_refused_naming_both_files() {
    for (from, to, what) in [
        (
            "length = \"m\"",
            "length = \"mm\"",
            "[units] length 'm' and 'mm'",
        ),
        ("time = \"s\"", "time = \"ms\"", "[units] time 's' and 'ms'"),
    ] {
        let jobs = [
            shipped("models/backbones_ringdown.toml"),
            edited(from, to, "stepped_in_other_units.toml"),
        ];
        let error = run(&jobs, &silent).unwrap_err();
        assert!(matches!(error, Error::Incomparable { .. }), "{error:?}");
        let text = error.to_string();
        assert!(
            text.contains("models/backbones_ringdown.toml and stepped_in_other_units.toml"),
            "{text}"
        );
        assert!(text.contains(what), "{text}");
    }
}

#[test]
fn a_job_of_forced_records_is_refused_naming_its_file() {
    let jobs = [
        shipped("models/backbones_ringdown.toml"),
        shipped("models/walkthrough.toml"),
    ];
    let error = run(&jobs, &silent).unwrap_err();
    assert!(matches!(error, Error::Incomparable { .. }), "{error:?}");
    let text = error.to_string();
    assert!(text.contains("models/walkthrough.toml"), "{text}");
    assert!(text.contains("records of forced vibration"), "{text}");
    assert!(text.contains("[free_decay]"), "{text}");
}

#[test]
fn one_job_is_not_a_comparison() {
    let error = run(&[shipped("models/backbones_stepped.toml")], &silent).unwrap_err();
    assert_eq!(error.kind(), "empty", "{error}");
}
