//! How messages show what the user named: text escaped so that it cannot drive
//! the terminal or end a line ([`escape`], [`must_escape`], also for the strings
//! `tessera bake` writes into Rust), and the kind of a file that is not a regular
//! one. A leaf: it imports nothing of the crate.

use std::path::Path;

/// `s` with every character that could move the cursor, end a line or reorder
/// the text around it written as `\u{1b}` (Rust's notation), so that a path or
/// a name shown in a message cannot forge a line or drive the terminal: the
/// control characters (C0, DEL and C1, U+0085 NEXT LINE among them), the line
/// and paragraph separators U+2028 and U+2029, and the bidirectional-text
/// controls (U+061C, U+200E, U+200F, U+202A to U+202E, U+2066 to U+2069), and
/// every other whitespace but the space (`must_escape`).
/// Other text, backslashes included, is unchanged, so escaping twice changes
/// nothing more.
#[must_use]
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        if must_escape(c) {
            out.push_str(&format!("\\u{{{:x}}}", u32::from(c)));
        } else {
            out.push(c);
        }
    }
    out
}

/// Whether `c` could end a line or reorder the text around it, for a terminal,
/// a reader or the compiler's lints (in generated Rust, `tessera bake`): a
/// control character, a whitespace other than the space, a bidirectional-text
/// control. Decided here, whatever the Unicode tables of `escape_debug` (which
/// change between Rust versions) say.
#[must_use]
pub(crate) fn must_escape(c: char) -> bool {
    c.is_control()
        || (c.is_whitespace() && c != ' ')
        || matches!(
            c,
            '\u{61c}' | '\u{200e}' | '\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}'
        )
}

/// A path as a message shows it: [`Path::display`] through [`escape`].
#[must_use]
pub fn escape_path(p: &Path) -> String {
    escape(&p.display().to_string())
}

/// What a file that is not a regular file is, for a message about an output
/// ([`crate::output`]) or an input ([`crate::file`]).
pub(crate) fn file_kind(t: &std::fs::FileType) -> &'static str {
    #[cfg(unix)]
    {
        use std::os::unix::fs::FileTypeExt;
        if t.is_char_device() {
            return "a character device";
        }
        if t.is_block_device() {
            return "a block device";
        }
        if t.is_fifo() {
            return "a FIFO (named pipe)";
        }
        if t.is_socket() {
            return "a socket";
        }
    }
    if t.is_dir() {
        "a folder"
    } else {
        "not a regular file"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn escape_shows_what_could_drive_the_terminal_and_nothing_else() {
        assert_eq!(
            escape("a\u{1b}[2J\tb\r\n\u{7f}\u{85}\u{9b}\u{2028}\u{2029}\u{61c}\u{202e}\u{2066}"),
            "a\\u{1b}[2J\\u{9}b\\u{d}\\u{a}\\u{7f}\\u{85}\\u{9b}\\u{2028}\\u{2029}\\u{61c}\\u{202e}\\u{2066}"
        );
        let plain = "scène 2: got \"é\\n\" [0.1, -1] 日本 \u{200b}";
        assert_eq!(escape(plain), plain);
        let once = escape("x\ny\u{2028}");
        assert_eq!(escape(&once), once);
    }
}
