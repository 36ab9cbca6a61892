//! A free decay of several sensors (`[free_decay] mode_shape` or `modal_filter`): each
//! wrong shape is a `ModelFile` error at the key's line with its typed cause — a shape
//! whose length is not the record's number of sensors (`DimensionMismatch`, naming the
//! record), a shape that is zero at every sensor (`InvalidParameter`), an unknown filter
//! (`UnknownName`), both keys at once, and sensors of mixed kinds (`InvalidChoice`).

use dampid::prelude::*;
use dampid::prep::free_decay::ModalFilter;

/// Three sine channels a1, a2, a3 of 4096 samples in a CSV under a fresh directory,
/// and the model text with `[free_decay]` ending in `keys` (line 17 on) and the
/// record's motion columns `motion`.
fn job(name: &str, motion: &str, keys: &str) -> Result<dampid::model_file::Job> {
    let dir = std::env::temp_dir().join(format!("dampid-errors-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut csv = String::from("a1,a2,a3\n");
    for i in 0..4096 {
        let t = i as f64 * 1e-3;
        let decay = (-2.0 * t).exp();
        let a = |k: f64| decay * (2.0 * std::f64::consts::PI * 20.0 * t + k).sin();
        csv.push_str(&format!("{},{},{}\n", a(0.0), 0.5 * a(0.0), a(1.0)));
    }
    std::fs::write(dir.join("r.csv"), csv).unwrap();
    let text = format!(
        "dofs = 1

[[terms]]
kind = \"viscous\"
coefficient = \"c\"
matrix = \"identity\"

[data]
records = [
  {{ file = \"r.csv\", label = \"three\", step = 1e-3, {motion} }},
]

[free_decay]
mass = 1.0
band = [10.0, 40.0]
# the filter:
{keys}
"
    );
    let job = dampid::model_file::parse(&text, "sensors.toml", &dir, Default::default());
    std::fs::remove_dir_all(&dir).ok();
    job
}

const THREE: &str = "accelerations = [\"a1\", \"a2\", \"a3\"]";

/// The error's line, message and typed cause.
fn at(result: Result<dampid::model_file::Job>) -> (usize, String, Option<Error>) {
    match result {
        Err(Error::ModelFile {
            line,
            message,
            cause,
            ..
        }) => (line, message, cause.map(|c| *c)),
        Err(other) => panic!("not a model-file error: {other}"),
        Ok(_) => panic!("accepted"),
    }
}

#[test]
fn a_mode_shape_of_the_wrong_length_names_the_record() {
    let (line, message, cause) = at(job("length", THREE, "mode_shape = [1.0, 0.5]"));
    assert_eq!(line, 17, "{message}");
    assert!(message.contains("mode_shape"), "{message}");
    assert!(message.contains("record 'three'"), "{message}");
    assert!(
        matches!(
            cause,
            Some(Error::DimensionMismatch {
                expected: 3,
                found: 2,
                ..
            })
        ),
        "{cause:?}"
    );
    // The right length is accepted.
    job("length-ok", THREE, "mode_shape = [1.0, 0.5, 0.2]").unwrap();
}

#[test]
fn a_zero_mode_shape_is_refused_at_its_line() {
    let (line, message, cause) = at(job("zero", THREE, "mode_shape = [0.0, 0.0, 0.0]"));
    assert_eq!(line, 17, "{message}");
    assert!(message.contains("zero at every sensor"), "{message}");
    assert!(
        matches!(cause, Some(Error::InvalidParameter { ref name, .. }) if name == "mode_shape"),
        "{cause:?}"
    );
}

#[test]
fn an_unknown_filter_or_both_keys_are_refused() {
    let (line, message, cause) = at(job("unknown", THREE, "modal_filter = \"svd\""));
    assert_eq!(line, 17, "{message}");
    assert!(message.contains("\"pod\""), "{message}");
    assert!(
        matches!(cause, Some(Error::UnknownName { .. })),
        "{cause:?}"
    );
    let (line, message, _) = at(job(
        "both",
        THREE,
        "mode_shape = [1.0, 0.5, 0.2]\nmodal_filter = \"pod\"",
    ));
    assert_eq!(line, 18, "{message}");
    assert!(message.contains("not both"), "{message}");
}

#[test]
fn sensors_of_mixed_kinds_are_refused() {
    let mixed = "accelerations = [\"a1\", \"a2\"], velocities = [{ column = \"a3\", dof = 3 }]";
    let (_, message, cause) = at(job("mixed", mixed, "modal_filter = \"pod\""));
    assert!(
        message.contains("mixes acceleration and velocity"),
        "{message}"
    );
    assert!(
        matches!(cause, Some(Error::InvalidChoice { .. })),
        "{cause:?}"
    );
}

/// The Python package's `free_decay={...}` reads the modal filter's keys as a model file
/// does: `mode_shape` checked (finite, not all zero), not both, an unknown filter named.
#[test]
fn the_tables_of_the_python_package_read_the_modal_filter() {
    let table = |entries: &[(&str, toml::Value)]| {
        let mut section = toml::Table::new();
        section.insert("mass".into(), toml::Value::Float(1.0));
        for (key, value) in entries {
            section.insert((*key).into(), value.clone());
        }
        dampid::model_file::free_decay_identification(&toml::Table::new(), &section)
    };
    let shape = toml::Value::Array(vec![toml::Value::Float(1.0), toml::Value::Float(0.5)]);
    let (_, _, filter) = table(&[("mode_shape", shape.clone())]).unwrap();
    assert_eq!(filter, Some(ModalFilter::Shape(vec![1.0, 0.5])));
    let (_, _, filter) = table(&[("modal_filter", toml::Value::String("pod".into()))]).unwrap();
    assert_eq!(filter, Some(ModalFilter::Pod));
    let both = table(&[
        ("mode_shape", shape),
        ("modal_filter", toml::Value::String("pod".into())),
    ])
    .unwrap_err();
    assert!(both.to_string().contains("not both"), "{both}");
    let zero = toml::Value::Array(vec![toml::Value::Float(0.0), toml::Value::Float(0.0)]);
    let zero = table(&[("mode_shape", zero)]).unwrap_err();
    assert!(zero.to_string().contains("mode_shape"), "{zero}");
    let unknown = table(&[("modal_filter", toml::Value::String("svd".into()))]).unwrap_err();
    assert!(
        matches!(unknown, Error::UnknownName { ref name, .. } if name == "svd"),
        "{unknown}"
    );
}
