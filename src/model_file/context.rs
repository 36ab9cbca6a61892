//! Model-file errors with the file, line and column of the table or key they concern:
//! toml gives byte spans, this turns them into 1-based lines and columns.

use toml::Spanned;

use crate::error::{Error, Result};

/// The model file being read: its name and text, to turn spans into line and column.
pub(super) struct Context<'a> {
    pub(super) file: &'a str,
    pub(super) text: &'a str,
}

impl Context<'_> {
    /// 1-based line and column of byte `offset`.
    pub(super) fn position(&self, offset: usize) -> (usize, usize) {
        let before = &self.text[..offset.min(self.text.len())];
        let line = before.matches('\n').count() + 1;
        let column = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
        (line, column)
    }

    pub(super) fn error_at<T>(
        &self,
        spanned: &Spanned<T>,
        message: impl std::fmt::Display,
    ) -> Error {
        let (line, column) = self.position(spanned.span().start);
        Error::ModelFile {
            file: self.file.to_string(),
            line,
            column,
            message: message.to_string(),
            cause: None,
        }
    }

    /// The typed error `error` at `spanned`, kept as the model-file error's cause (an
    /// error that already has a position in this file keeps it).
    pub(super) fn typed_error_at<T>(&self, spanned: &Spanned<T>, error: Error) -> Error {
        if matches!(error, Error::ModelFile { .. }) {
            return error;
        }
        let (line, column) = self.position(spanned.span().start);
        Error::ModelFile {
            file: self.file.to_string(),
            line,
            column,
            message: error.to_string(),
            cause: Some(Box::new(error)),
        }
    }

    /// Runs `f`, turning its error into a model-file error at `spanned`.
    pub(super) fn at<S, T>(
        &self,
        spanned: &Spanned<S>,
        f: impl FnOnce(&S) -> Result<T>,
    ) -> Result<T> {
        f(spanned.get_ref()).map_err(|e| self.typed_error_at(spanned, e))
    }

    pub(super) fn whole_file_error(&self, message: impl Into<String>) -> Error {
        Error::ModelFile {
            file: self.file.to_string(),
            line: 0,
            column: 0,
            message: message.into(),
            cause: None,
        }
    }

    /// The typed error `error` about the file as a whole, after `prefix` (a section).
    pub(super) fn whole_file_typed_error(&self, prefix: &str, error: Error) -> Error {
        Error::ModelFile {
            file: self.file.to_string(),
            line: 0,
            column: 0,
            message: format!("{prefix}: {error}"),
            cause: Some(Box::new(error)),
        }
    }
}
