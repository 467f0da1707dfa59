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
    #[error("{file}:{line}:{column}: {field}{message}\n{line:>6} | {source_line}")]
    Syntax {
        /// The file.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The field's path followed by ": " (e.g. `body[0].pose.index.pip: `), or empty where
        /// the file could not be parsed at all.
        field: String,
        /// What is wrong.
        message: String,
        /// The text of the line at fault, so a duplicate key or a stray character is seen.
        source_line: String,
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
    /// From a TOML deserialisation error, with its position turned into line and column;
    /// `field` is the path of the field at fault where it is known (empty otherwise).
    pub fn syntax(file: &str, text: &str, field: &str, e: &toml::de::Error) -> Self {
        let (line, column) = match e.span() {
            Some(span) => {
                let before = text.get(..span.start).unwrap_or(text);
                let line = before.matches('\n').count() + 1;
                let column = before.len() - before.rfind('\n').map_or(0, |i| i + 1) + 1;
                (line, column)
            }
            None => (1, 1),
        };
        let source_line: String = text
            .lines()
            .nth(line - 1)
            .unwrap_or("")
            .trim_end()
            .chars()
            .take(160)
            .collect();
        SceneError::Syntax {
            file: file.to_string(),
            line,
            column,
            field: if field.is_empty() {
                String::new()
            } else {
                format!("{field}: ")
            },
            message: plain_message(e.message().trim()),
            source_line,
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

/// A deserialiser's message told in the scene's terms: the program's own type names (`expected
/// struct MaterialDef`, `struct variant Shape::Box`, `untagged enum PreshapeDef`) replaced by
/// what the file is to hold there (a table, an array, one of the names).
pub fn plain_message(message: &str) -> String {
    // Longest first: "struct variant" before "struct".
    const KINDS: [(&str, &str); 8] = [
        (
            "data did not match any variant of untagged enum ",
            "the value has none of the forms this field accepts",
        ),
        ("expected struct variant ", "expected a table"),
        ("expected tuple variant ", "expected an array"),
        ("expected newtype variant ", "expected a value"),
        ("expected unit variant ", "expected a name"),
        ("expected struct ", "expected a table"),
        ("expected tuple struct ", "expected an array"),
        (
            "expected enum ",
            "expected one of the names or tables this field accepts",
        ),
    ];
    let mut out = String::with_capacity(message.len());
    let mut rest = message;
    'scan: while !rest.is_empty() {
        for (kind, plain) in KINDS {
            if let Some(after) = rest.strip_prefix(kind) {
                let name = after
                    .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == ':'))
                    .unwrap_or(after.len());
                if name > 0 {
                    out.push_str(plain);
                    rest = &after[name..];
                    continue 'scan;
                }
            }
        }
        let c = rest.chars().next().expect("not empty");
        out.push(c);
        rest = &rest[c.len_utf8()..];
    }
    // The primitive types a number is read into.
    const NUMBERS: [(&str, &str); 12] = [
        ("usize", "a whole number, 0 or more"),
        ("u64", "a whole number, 0 or more"),
        ("u32", "a whole number, 0 or more"),
        ("u16", "a whole number, 0 or more"),
        ("u8", "a whole number, 0 or more"),
        ("isize", "a whole number"),
        ("i64", "a whole number"),
        ("i32", "a whole number"),
        ("f64", "a number"),
        ("f32", "a number"),
        ("bool", "true or false"),
        ("char", "a single character"),
    ];
    for (ty, plain) in NUMBERS {
        let pattern = format!("expected {ty}");
        let mut told = String::with_capacity(out.len());
        let mut rest = out.as_str();
        while let Some(at) = rest.find(&pattern) {
            let after = &rest[at + pattern.len()..];
            told.push_str(&rest[..at]);
            if after.starts_with(|c: char| c.is_ascii_alphanumeric() || c == '_') {
                told.push_str(&pattern);
            } else {
                told.push_str("expected ");
                told.push_str(plain);
            }
            rest = after;
        }
        told.push_str(rest);
        out = told;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::plain_message;

    #[test]
    fn the_programs_type_names_are_told_as_what_the_file_holds() {
        assert_eq!(
            plain_message("invalid type: integer `3`, expected struct MaterialDef"),
            "invalid type: integer `3`, expected a table"
        );
        assert_eq!(
            plain_message("invalid type: integer `3`, expected struct variant Shape::Box"),
            "invalid type: integer `3`, expected a table"
        );
        assert_eq!(
            plain_message("data did not match any variant of untagged enum PreshapeDef"),
            "the value has none of the forms this field accepts"
        );
        assert_eq!(
            plain_message("invalid type: floating point `10.5`, expected usize"),
            "invalid type: floating point `10.5`, expected a whole number, 0 or more"
        );
        assert_eq!(
            plain_message("invalid type: string \"1e6\", expected f64"),
            "invalid type: string \"1e6\", expected a number"
        );
        assert_eq!(
            plain_message("invalid type: integer `1`, expected bool"),
            "invalid type: integer `1`, expected true or false"
        );
        assert_eq!(
            plain_message("unknown field `yung`, expected one of `name`, `young`"),
            "unknown field `yung`, expected one of `name`, `young`"
        );
    }
}
