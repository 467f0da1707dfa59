//! Scene errors: each names the file, and the line and column or the field at fault.

use thiserror::Error;

/// A scene file that cannot be used.
#[derive(Debug, Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("{file}: cannot read the scene file: {reason}")]
    Io {
        /// The file.
        file: String,
        /// Why (kept out of the error chain so it is said once).
        reason: std::io::Error,
    },
    /// Malformed TOML or a field of the wrong type or name.
    #[error("{file}:{line}:{column}: {message}")]
    Syntax {
        /// The file.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// A well-formed file whose content is not admissible.
    #[error("{file}: {field}: {message}")]
    Invalid {
        /// The file.
        file: String,
        /// The field, e.g. `constraint "press" (constraint[1]).where`.
        field: String,
        /// What is wrong.
        message: String,
    },
}

impl SceneError {
    /// From a TOML deserialisation error, with its position turned into line and column.
    pub fn syntax(file: &str, text: &str, e: &toml::de::Error) -> Self {
        let (line, column) = match e.span() {
            Some(span) => {
                let before = &text[..span.start.min(text.len())];
                let line = before.matches('\n').count() + 1;
                let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
                (line, column)
            }
            None => (1, 1),
        };
        SceneError::Syntax {
            file: file.to_string(),
            line,
            column,
            message: e.message().trim().to_string(),
        }
    }

    /// An invalid field.
    pub fn invalid(file: &str, field: impl Into<String>, message: impl Into<String>) -> Self {
        SceneError::Invalid {
            file: file.to_string(),
            field: field.into(),
            message: message.into(),
        }
    }
}
