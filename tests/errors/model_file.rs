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
        }) => {
            assert_eq!((file.as_str(), line), ("m.toml", 2));
            assert!(column >= 1);
            assert!(!message.is_empty());
        }
        other => panic!("{other:?}"),
    }
}
