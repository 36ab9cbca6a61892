//! Text the user writes: an expression law with an unknown identifier is `Expression`
//! (naming the identifier), a malformed model file is `ModelFile` with file, line and
//! column. The model file's own spellings and rejections are in `tests/model_file.rs`.

use dampid::prelude::*;

use crate::fixtures::parse_model;

#[test]
fn expression_with_unknown_identifier_names_it() {
    match dampid::terms::laws::Expression::parse("x^2*vel") {
        Err(Error::Expression {
            expression,
            message,
        }) => {
            assert_eq!(expression, "x^2*vel");
            assert!(message.contains("'vel'"), "{message}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn malformed_model_file_names_file_line_and_column() {
    match parse_model("dofs = 2\nterms = 3\n", "m.toml") {
        Err(Error::ModelFile {
            file,
            line,
            column,
            message,
            ..
        }) => {
            assert_eq!((file.as_str(), line), ("m.toml", 2));
            assert!(column >= 1);
            assert!(!message.is_empty());
        }
        other => panic!("{other:?}"),
    }
}

/// A model with two `[[terms]]` blocks and the simulation that gives them records; the
/// second block is `second`.
fn two_blocks(second: &str) -> String {
    format!(
        "dofs = 2

[[terms]]
kind = \"viscous\"
coefficient = \"c\"
matrix = \"identity\"

[[terms]]
{second}

[simulation]
mass = \"identity\"
stiffness = \"chain\"
coefficients = {{ c = 0.1, d = 0.1 }}
step = 0.1
transient_steps = 10
recorded_steps = 100
experiments = [{{ force_dof = 1, amplitude = 1.0, frequency = 1.0 }}]
"
    )
}

/// An error in the second `[[terms]]` block is reported at the second block's line
/// (line 8), not the first block's (line 3): a DOF out of range, numbered from 1 as in
/// the file, and a coefficient name that the first block already uses.
#[test]
fn an_error_in_the_second_terms_block_points_at_it() {
    let out_of_range =
        two_blocks("kind = \"law\"\nlaw = \"quadratic\"\nelements = [[1, 3]]\ncoefficient = \"d\"");
    let error = parse_model(&out_of_range, "two.toml").unwrap_err();
    match &error {
        Error::ModelFile { line, message, .. } => {
            assert_eq!(*line, 8, "{message}");
            assert!(
                message.contains("DOF 3") && message.contains("1..2"),
                "{message}"
            );
        }
        other => panic!("{other:?}"),
    }
    assert!(
        matches!(
            error.innermost(),
            Error::DofOutOfRange {
                dof: 3,
                dofs: 2,
                ..
            }
        ),
        "{error:?}"
    );
    let repeated = two_blocks(
        "kind = \"law\"\nlaw = \"linear\"\nelements = \"each_dof\"\ncoefficient = \"c\"",
    );
    let error = parse_model(&repeated, "two.toml").unwrap_err();
    assert!(
        matches!(&error, Error::ModelFile { line: 8, .. }),
        "{error:?}"
    );
    assert!(
        matches!(error.innermost(), Error::DuplicateCoefficient { name } if name == "c"),
        "{error:?}"
    );
}

/// A model-file error keeps the typed error it wraps (`cause`), so a program can match
/// on it; TOML syntax errors have none.
#[test]
fn model_file_errors_keep_their_typed_cause() {
    let error = parse_model(
        &two_blocks(
            "kind = \"law\"\nlaw = \"power\"\nelements = \"each_dof\"\ncoefficient = \"d\"",
        ),
        "two.toml",
    )
    .unwrap_err();
    match &error {
        Error::ModelFile {
            cause: Some(cause), ..
        } => assert!(
            matches!(&**cause, Error::Missing { name, .. } if name == "exponent"),
            "{cause:?}"
        ),
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        parse_model("dofs = ", "bad.toml"),
        Err(Error::ModelFile { cause: None, .. })
    ));
}

/// An estimated law parameter needs `initial`, `lower` and `upper`, ordered bounds and
/// the initial value within them; each fault is reported at the `exponent` key's line
/// (the block's, for an expression's unused constant)
/// with its typed cause (`Missing`, `InvalidParameter`), never a fit that wanders off.
#[test]
fn estimated_parameters_need_bounds_and_an_initial_value_within_them() {
    let block = |exponent: &str| {
        two_blocks(&format!(
            "kind = \"law\"\nlaw = \"power\"\nexponent = {exponent}\nelements = \"each_dof\"\ncoefficient = \"d\""
        ))
    };
    let cause = |text: &str| {
        let error = parse_model(text, "estimated.toml").unwrap_err();
        assert!(
            matches!(&error, Error::ModelFile { line: 8 | 11, .. }),
            "{error:?}"
        );
        error.innermost().clone()
    };
    match cause(&block("{ estimate = true, initial = 1.5, lower = 0.5 }")) {
        Error::Missing { name, .. } => assert!(name.contains("upper"), "{name}"),
        other => panic!("{other:?}"),
    }
    match cause(&block("{ estimate = true, lower = 0.5, upper = 4.0 }")) {
        Error::Missing { name, .. } => assert!(name.contains("initial"), "{name}"),
        other => panic!("{other:?}"),
    }
    match cause(&block(
        "{ estimate = true, initial = 5.0, lower = 0.5, upper = 4.0 }",
    )) {
        Error::InvalidParameter { name, value, .. } => {
            assert!(
                name.contains("initial") && name.contains("d.exponent"),
                "{name}"
            );
            assert_eq!(value, 5.0);
        }
        other => panic!("{other:?}"),
    }
    match cause(&block(
        "{ estimate = true, initial = 1.0, lower = 4.0, upper = 0.5 }",
    )) {
        Error::InvalidParameter { name, value, .. } => {
            assert!(name.contains("lower"), "{name}");
            assert_eq!(value, 4.0);
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        cause(&block(
            "{ estimate = false, initial = 1.0, lower = 0.5, upper = 4.0 }"
        )),
        Error::InvalidChoice { .. }
    ));
    // a named constant an expression does not use
    let unused = two_blocks(
        "kind = \"law\"\nlaw = \"expression\"\nexpression = \"tanh(v)\"\nparameters = { vs = { estimate = true, initial = 0.1, lower = 0.01, upper = 1.0 } }\nelements = \"each_dof\"\ncoefficient = \"d\"",
    );
    assert!(matches!(cause(&unused), Error::Expression { .. }));
}

/// `[simulation] noise` must be a finite fraction ≥ 0 of each channel's RMS: a negative
/// one is `InvalidParameter`, naming the key and its value, at the key's line.
#[test]
fn negative_simulation_noise_is_refused_at_its_table() {
    let text = two_blocks(
        "kind = \"law\"\nlaw = \"quadratic\"\nelements = \"each_dof\"\ncoefficient = \"d\"",
    )
    .replace("[simulation]\n", "[simulation]\nnoise = -0.01\n");
    let error = parse_model(&text, "noisy.toml").unwrap_err();
    match &error {
        Error::ModelFile { file, line, .. } => {
            assert_eq!((file.as_str(), *line), ("noisy.toml", 15), "{error}");
        }
        other => panic!("{other:?}"),
    }
    match error.innermost() {
        Error::InvalidParameter { name, value, .. } => {
            assert_eq!(name, "noise");
            assert_eq!(*value, -0.01);
        }
        other => panic!("{other:?}"),
    }
}

/// A `[units]` entry that is not a known dimension is `UnknownName` listing the known
/// ones, at the line of the entry.
#[test]
fn unknown_unit_dimension_names_the_line() {
    let text = "dofs = 1\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = [[1, 0]]\ncoefficient = \"c\"\n[units]\nlength = \"m\"\nlenght = \"mm\"\n";
    match parse_model(text, "u.toml") {
        Err(Error::ModelFile {
            file, line, cause, ..
        }) => {
            assert_eq!((file.as_str(), line), ("u.toml", 9));
            match cause.as_deref() {
                Some(Error::UnknownName { what, name, known }) => {
                    assert_eq!(name, "lenght");
                    assert!(what.contains("[units]"), "{what}");
                    assert!(
                        known.contains("length") && known.contains("force"),
                        "{known}"
                    );
                }
                other => panic!("{other:?}"),
            }
        }
        other => panic!("{other:?}"),
    }
}

/// `model_file::parse_model` (the Python package's `Model.from_toml`) builds the terms
/// alone: a file without records is a model, and a bad term is the error `parse` gives,
/// at its line.
#[test]
fn model_alone_needs_no_records_and_keeps_the_term_errors() {
    use dampid::model_file::parse_model as model_only;
    let terms = "dofs = 2\n[[terms]]\nkind = \"law\"\nlaw = \"linear\"\nelements = \"each_dof\"\ncoefficient = \"c\"\n";
    let model = model_only(terms, "terms.toml").unwrap();
    assert_eq!(model.coefficient_names(), ["c"]);
    let bad = terms.replace("\"linear\"", "\"lineer\"");
    let error = model_only(&bad, "terms.toml").unwrap_err();
    assert!(
        matches!(&error, Error::ModelFile { file, line: 2, .. } if file == "terms.toml"),
        "{error:?}"
    );
    assert!(error.to_string().contains("lineer"), "{error}");
    let empty = model_only("dofs = 2\nterms = []\n", "empty.toml").unwrap_err();
    assert!(
        matches!(empty.innermost(), Error::Empty { .. }),
        "{empty:?}"
    );
}

/// `[identification]` and `[non_periodic]` given as tables (the Python package's keyword
/// settings) translate as the model file's sections do: the settings of
/// models/drive_nonperiodic.toml from its own tables are the job's, and the errors name
/// the key (a periodic-only key beside `[non_periodic]`, an unknown or missing
/// `[non_periodic]` key, an offset DOF beyond `dofs`, a matrix the model does not name).
#[test]
fn non_periodic_sections_as_tables_translate_as_the_model_file() {
    use dampid::model_file::{load, non_periodic_identification};
    let path =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models/drive_nonperiodic.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let file: toml::Table = toml::from_str(&text).unwrap();
    let table = |name: &str| file[name].as_table().unwrap().clone();
    let (identification, high_pass) = non_periodic_identification(
        &table("identification"),
        &table("non_periodic"),
        &text,
        "drive",
    )
    .unwrap();
    let job = load(&path, Default::default()).unwrap();
    assert_eq!(identification, job.settings);
    assert_eq!(high_pass, None);
    let np = |extra: &str| -> toml::Table {
        toml::from_str(&format!("window = 0.25\n{extra}")).unwrap()
    };
    let with_high_pass =
        non_periodic_identification(&toml::Table::new(), &np("high_pass = 0.05"), &text, "drive");
    assert_eq!(with_high_pass.unwrap().1, Some(0.05));

    let error = |identification: &str, non_periodic: toml::Table| {
        let identification: toml::Table = toml::from_str(identification).unwrap();
        non_periodic_identification(&identification, &non_periodic, &text, "drive").unwrap_err()
    };
    match error("cycles = 2", np("")) {
        Error::InvalidChoice { name, reason, .. } => {
            assert_eq!(name, "cycles");
            assert!(
                reason.contains("does not apply beside [non_periodic]"),
                "{reason}"
            );
        }
        other => panic!("{other:?}"),
    }
    match error("", np("windw = 1.0")) {
        Error::InvalidChoice { name, reason, .. } => {
            assert_eq!(name, "[non_periodic]");
            assert!(reason.contains("windw"), "{reason}");
        }
        other => panic!("{other:?}"),
    }
    match error("", toml::from_str("offsets = [1]").unwrap()) {
        Error::InvalidChoice { reason, .. } => assert!(reason.contains("window"), "{reason}"),
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        error("", np("offsets = [2]")),
        Error::DofOutOfRange {
            dof: 2,
            dofs: 1,
            ..
        }
    ));
    match error("", np("mass = { known = \"heavy\" }")) {
        Error::UnknownName { name, known, .. } => {
            assert_eq!(name, "heavy");
            assert!(known.contains("identity"), "{known}");
        }
        other => panic!("{other:?}"),
    }
    match error("quadrature = \"simpson\"", np("")) {
        Error::InvalidChoice { name, .. } => assert_eq!(name, "quadrature"),
        other => panic!("{other:?}"),
    }
}
