//! The names a scene gives its bodies, materials, constraints, loads, obstacles, probes and
//! cameras: what keyframes, loads, selections and the report refer to them by; and how a name
//! the scene wrote is echoed in a message.

pub use crate::util::shown::shown;

/// `name` refused when it is empty or only spaces (`name = ""` was accepted, and its body then
/// reported as `""`), or when it holds a control character (ESC, NUL, a line break: echoed in
/// messages and written into the report and file names): the error to give with the entry's
/// field.
pub(super) fn named(kind: &str, name: &str) -> Result<(), String> {
    if name.trim().is_empty() {
        return Err(format!(
            "has no name: give the {kind} a name (`name = \"…\"`), which the scene and the \
             report refer to it by"
        ));
    }
    if let Some(c) = name.chars().find(|c| c.is_control()) {
        return Err(format!(
            "the name holds a control character ({}): a {kind}'s name is plain text on one \
             line, which the messages and the report show",
            c.escape_debug()
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::named;

    #[test]
    fn an_empty_or_blank_name_is_refused() {
        assert!(named("body", "")
            .unwrap_err()
            .contains("give the body a name"));
        assert!(named("probe", "  ").is_err());
        assert!(named("body", "ball").is_ok());
    }

    #[test]
    fn a_name_with_a_control_character_is_refused() {
        assert_eq!(
            named("load", "air\u{1b}[31m").unwrap_err(),
            "the name holds a control character (\\u{1b}): a load's name is plain text on one \
             line, which the messages and the report show"
        );
        assert!(named("camera", "a\0b").unwrap_err().contains("(\\0)"));
        assert!(named("body", "two\nlines").is_err());
        assert!(named("material", "caoutchouc naturel é ν 漢").is_ok());
    }
}
