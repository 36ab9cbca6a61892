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
        }
    }

    /// Runs `f`, turning its error into a model-file error at `spanned`.
    pub(super) fn at<S, T>(
        &self,
        spanned: &Spanned<S>,
        f: impl FnOnce(&S) -> Result<T>,
    ) -> Result<T> {
        f(spanned.get_ref()).map_err(|e| self.error_at(spanned, e))
    }

    pub(super) fn whole_file_error(&self, message: impl Into<String>) -> Error {
        Error::ModelFile {
            file: self.file.to_string(),
            line: 0,
            column: 0,
            message: message.into(),
        }
    }
}
