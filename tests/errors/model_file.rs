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
