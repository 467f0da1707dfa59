//! The names a scene gives its bodies, materials, constraints, loads, obstacles, probes and
//! cameras: what keyframes, loads, selections and the report refer to them by; and how a name
//! the scene wrote is echoed in a message.

/// The most characters of a name [`shown`] echoes (escapes counted as written).
pub const SHOWN_CHARS: usize = 60;

/// A name (or any text the scene wrote) as a message echoes it, between the message's quotes:
/// control and other invisible characters escaped as Rust writes them (`\u{1b}`, `\0`, `\n`),
/// `"` and `\` escaped, and cut after [`SHOWN_CHARS`] characters with "…" (a reference of
/// 500 kB with ESC and NUL in it was echoed whole, raw, into the terminal).
pub fn shown(name: &str) -> String {
    let mut out = String::new();
    let mut count = 0;
    for (i, c) in name.chars().enumerate() {
        let piece: String = match c {
            // As written: the message quotes with `"`.
            '\'' => c.to_string(),
            // A grapheme extender (an accent) is escaped only at the start, as `str::escape_debug`
            // does: after a letter it is that letter's.
            _ if i > 0 => format!(" {c}").escape_debug().skip(1).collect(),
            _ => c.escape_debug().collect(),
        };
        count += piece.chars().count();
        if count > SHOWN_CHARS {
            out.push('…');
            break;
        }
        out.push_str(&piece);
    }
    out
}

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
    use super::{named, shown, SHOWN_CHARS};

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

    #[test]
    fn a_shown_name_is_escaped_and_cut() {
        assert_eq!(shown("rubber"), "rubber");
        assert_eq!(shown("it's é ν 漢"), "it's é ν 漢");
        assert_eq!(shown("a\u{1b}[31m\0\"\\"), "a\\u{1b}[31m\\0\\\"\\\\");
        let long = "ß".repeat(500_000);
        assert_eq!(shown(&long), format!("{}…", "ß".repeat(SHOWN_CHARS)));
        // An escape is never cut in two.
        let escapes = "\u{1b}".repeat(100);
        assert_eq!(shown(&escapes), format!("{}…", "\\u{1b}".repeat(10)));
        assert_eq!(shown(&"x".repeat(SHOWN_CHARS)), "x".repeat(SHOWN_CHARS));
    }
}
