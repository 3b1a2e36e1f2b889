//! [`SceneError`]: every error names the file, the line and column and the field path.

use std::io;
use std::ops::Range;

use thiserror::Error;

use crate::shorten::{short_field, short_message};

/// The class of a [`SceneError`], for callers (and tests) that branch on it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ErrorKind {
    /// The scene file itself could not be read.
    Io,
    /// The text is not valid TOML.
    Syntax,
    /// A value has the wrong type, a key is missing or unknown, or a `type` string is unknown.
    Schema,
    /// A number is NaN or infinite.
    NonFinite,
    /// A number is outside its allowed range.
    OutOfRange,
    /// Keys that contradict each other, are missing for the chosen `type`, or do not apply to it.
    Conflict,
    /// A shape refers to a material that is not defined.
    UnknownMaterial,
    /// A referenced file (mesh, environment map) is missing, unreadable or invalid.
    File,
    /// Degenerate geometry: a zero-area light, a camera that looks nowhere, a transform that
    /// overflows.
    Degenerate,
    /// The scene is over one of the [`crate::Limits`] (file size, triangles, memory); the
    /// message names the limit and the `ggx` flag that raises it.
    Limit,
}

/// An error while loading a scene.
#[derive(Debug, Error)]
pub enum SceneError {
    /// The scene file could not be read (missing, unreadable, not UTF-8).
    #[error("{path}: cannot read scene file: {source}")]
    Read {
        /// The scene file as given.
        path: String,
        /// The underlying I/O error.
        #[source]
        source: io::Error,
    },
    /// The scene file is not a regular file (a directory, FIFO or device) or is larger than
    /// [`crate::Limits::max_scene_bytes`]; `kind` is [`ErrorKind::Io`] or [`ErrorKind::Limit`].
    #[error("{message}")]
    Unreadable {
        /// The scene file as given.
        path: String,
        /// What class of error this is.
        kind: ErrorKind,
        /// What is wrong, starting with the path.
        message: String,
    },
    /// An error at a position in the scene file.
    #[error("{file}:{line}:{column}: {}{message}", field_prefix(.field))]
    At {
        /// The scene file name as given to the loader.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column, in characters.
        column: usize,
        /// Dotted field path such as `materials.gold.roughness` or `shapes[2].transform.scale`;
        /// empty when the error is not inside a field (e.g. some syntax errors).
        field: String,
        /// What class of error this is.
        kind: ErrorKind,
        /// What is wrong.
        message: String,
    },
}

fn field_prefix(field: &str) -> String {
    if field.is_empty() { String::new() } else { format!("{field}: ") }
}

impl SceneError {
    /// The class of the error.
    pub fn kind(&self) -> ErrorKind {
        match self {
            Self::Read { .. } => ErrorKind::Io,
            Self::Unreadable { kind, .. } => *kind,
            Self::At { kind, .. } => *kind,
        }
    }

    /// The field path, empty for errors reading the file and errors outside any field.
    pub fn field(&self) -> &str {
        match self {
            Self::Read { .. } | Self::Unreadable { .. } => "",
            Self::At { field, .. } => field,
        }
    }

    /// `(line, column)`, both 1-based, or `None` for errors reading the file.
    pub fn line_column(&self) -> Option<(usize, usize)> {
        match self {
            Self::Read { .. } | Self::Unreadable { .. } => None,
            Self::At { line, column, .. } => Some((*line, *column)),
        }
    }
}

/// 1-based line and column (in characters) of byte `offset` in `text`.
pub(crate) fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let line = before.matches('\n').count() + 1;
    (line, before[line_start..].chars().count() + 1)
}

/// Where errors are reported: the scene text and the name it is shown under.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Source<'a> {
    /// The scene text; spans index into it.
    pub text: &'a str,
    /// The file name shown in messages.
    pub file: &'a str,
}

impl Source<'_> {
    /// An error at `span` in field `field`. User text in `field` and in `message` (quoted
    /// with backticks or double quotes) is shortened ([`crate::shorten`]).
    pub fn error(&self, span: Range<usize>, field: &str, kind: ErrorKind, message: impl Into<String>) -> SceneError {
        let (line, column) = line_column(self.text, span.start);
        SceneError::At {
            file: self.file.to_owned(),
            line,
            column,
            field: short_field(field),
            kind,
            message: short_message(&message.into()),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::line_column;

    #[test]
    fn line_column_counts_characters() {
        let text = "a = 1\nbé = 2\n";
        assert_eq!(line_column(text, 0), (1, 1));
        assert_eq!(line_column(text, 6), (2, 1));
        assert_eq!(line_column(text, 9), (2, 3));
        assert_eq!(line_column(text, 8), (2, 2));
        assert_eq!(line_column(text, 999), (3, 1));
    }
}
