//! What can go wrong on the host: [`HostError`], re-exported at the crate root,
//! and [`escape`], which every message passes the paths and names it shows
//! through.

use crate::desc;
use std::fmt;
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

/// What can go wrong on the host.
#[derive(Debug)]
pub enum HostError {
    /// The core refused the scene, camera or settings.
    Core(tessera::Error),
    /// A tile size other than 8, 16 or 32.
    TileSize(usize),
    /// Writing the output failed.
    Io {
        /// The file.
        path: String,
        /// Why.
        source: std::io::Error,
    },
    /// A step with an output's temporary file failed (see [`crate::output`]).
    Temp {
        /// The output file, as the user named it.
        target: String,
        /// The file that could not be created, written or renamed.
        temp: String,
        /// What was being done.
        step: TempStep,
        /// Why.
        source: std::io::Error,
    },
    /// An output that must not be written: not a regular file, the input, ...
    Refused {
        /// The output, as the user named it.
        path: String,
        /// Why.
        reason: String,
    },
    /// A request beyond a documented limit (see [`crate::limits`]), refused before any work.
    Limit(String),
    /// A file could not be read (not a regular file, ...).
    Read {
        /// The file.
        path: String,
        /// Why, e.g. `cannot read the cached reference: it is a FIFO (named
        /// pipe), not a regular file`.
        message: String,
    },
    /// Writing failed on a stream that does not know its file's name (the caller
    /// names it: [`crate::output::Pending::error`]).
    Write(std::io::Error),
    /// Several steps failed (an all-or-nothing write that could not be undone).
    Files(String),
    /// Encoding the PNG failed.
    Encode(String),
    /// The thread pool could not be built.
    Threads(String),
    /// A scene description was refused (the item and why).
    Scene(desc::DescError),
    /// Two images could not be measured against each other (sizes differ, FLIP
    /// refused them).
    Measure(String),
}

/// The step of writing an output through its temporary file that failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TempStep {
    /// Creating the temporary file (next to the output).
    Create,
    /// Writing it (or flushing it to the disk).
    Write,
    /// Renaming it onto the output.
    Rename,
    /// Keeping a copy of the old output while several files are replaced.
    Backup,
}

/// Paths, names and quoted texts are shown through [`escape`].
impl fmt::Display for HostError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let e = |s: &str| escape(s);
        let io = |s: &std::io::Error| escape(&s.to_string());
        match self {
            Self::Core(e) => write!(f, "{e}"),
            Self::TileSize(n) => write!(f, "tile size {n} is not one of 8, 16, 32"),
            Self::Io { path, source } => write!(f, "cannot write {}: {}", e(path), io(source)),
            Self::Temp {
                target,
                temp,
                step,
                source,
            } => {
                let what = match step {
                    TempStep::Create => "creating the temporary file",
                    TempStep::Write => "writing the temporary file",
                    TempStep::Rename => "renaming onto it the temporary file",
                    TempStep::Backup => "keeping a copy of the old file as",
                };
                write!(
                    f,
                    "cannot write {}: {what} {} failed: {}",
                    e(target),
                    e(temp),
                    io(source)
                )
            }
            Self::Refused { path, reason } => {
                write!(f, "refusing to write {}: {}", e(path), e(reason))
            }
            Self::Read { path, message } => write!(f, "{}: {}", e(path), e(message)),
            Self::Limit(s) | Self::Files(s) | Self::Measure(s) => f.write_str(&e(s)),
            Self::Write(s) => write!(f, "cannot write the output: {}", io(s)),
            Self::Encode(s) => write!(f, "cannot encode the PNG: {}", e(s)),
            Self::Threads(s) => write!(f, "cannot start the render threads: {}", e(s)),
            Self::Scene(d) => write!(f, "{d}"),
        }
    }
}

impl std::error::Error for HostError {}

impl From<tessera::Error> for HostError {
    fn from(e: tessera::Error) -> Self {
        Self::Core(e)
    }
}

impl From<desc::DescError> for HostError {
    fn from(e: desc::DescError) -> Self {
        Self::Scene(e)
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
        let e = HostError::Temp {
            target: "a\nb.png".into(),
            temp: "d/\u{1b}.tmp".into(),
            step: TempStep::Create,
            source: std::io::Error::other("no\u{2029}way"),
        };
        assert_eq!(
            e.to_string(),
            "cannot write a\\u{a}b.png: creating the temporary file d/\\u{1b}.tmp failed: \
             no\\u{2029}way"
        );
    }
}
