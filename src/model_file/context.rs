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
        self.error_at_offset(Some(spanned.span().start), message)
    }

    /// An error at byte `offset` of the file, or about the file as a whole without one.
    fn error_at_offset(&self, offset: Option<usize>, message: impl std::fmt::Display) -> Error {
        let (line, column) = offset.map_or((0, 0), |offset| self.position(offset));
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
        // At the key the error names when it is inside this table, else the table.
        let span = spanned.span();
        let offset = super::locate::key_of(&error)
            .and_then(|key| super::locate::find_key_within(self.text, span.clone(), &key))
            .unwrap_or(span.start);
        let (line, column) = self.position(offset);
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

    /// The typed error `error` about a section as a whole, after `prefix` (the section,
    /// `[identification]`): at the key of that section the error names, if it has one
    /// ([`Context::located`]).
    pub(super) fn whole_file_typed_error(&self, prefix: &str, error: Error) -> Error {
        let section = prefix.trim_matches(|c| c == '[' || c == ']');
        let wrapped = Error::ModelFile {
            file: self.file.to_string(),
            line: 0,
            column: 0,
            message: format!("{prefix}: {error}"),
            cause: Some(Box::new(error)),
        };
        self.located(wrapped, Some(section))
    }

    /// An error at the offset of `key` (searched as [`super::locate::find_key`] does),
    /// or about the file as a whole when the key is not in it.
    pub(super) fn error_at_key(
        &self,
        section: Option<&str>,
        key: &str,
        message: impl std::fmt::Display,
    ) -> Error {
        self.error_at_offset(super::locate::find_key(self.text, section, key), message)
    }

    /// `error` with the line and column of the key it concerns (`locate.rs`), searched
    /// in `section` first: a model-file error that has a position keeps it, any other
    /// error becomes a model-file error of this file (without a position when its key
    /// is not in the file), its typed error kept as the cause.
    pub(super) fn located(&self, error: Error, section: Option<&str>) -> Error {
        if matches!(&error, Error::ModelFile { line, file, .. } if *line > 0 || file != self.file) {
            return error;
        }
        let offset = super::locate::key_of(&error)
            .and_then(|key| super::locate::find_key(self.text, section, &key));
        let (line, column) = offset.map_or((0, 0), |o| self.position(o));
        match error {
            Error::ModelFile {
                file,
                message,
                cause,
                ..
            } => Error::ModelFile {
                file,
                line,
                column,
                message,
                cause,
            },
            other => Error::ModelFile {
                file: self.file.to_string(),
                line,
                column,
                message: other.to_string(),
                cause: Some(Box::new(other)),
            },
        }
    }
}
