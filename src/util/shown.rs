//! A name (or any text a scene or a file wrote) as a message echoes it.

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

#[cfg(test)]
mod tests {
    use super::{shown, SHOWN_CHARS};

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
