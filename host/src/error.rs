//! What can go wrong on the host: [`HostError`], re-exported at the crate root.
//! Every path and name it shows passes through [`crate::escape`].

use crate::desc;
use crate::text::escape;
use std::fmt;

/// What can go wrong on the host.
#[derive(Debug)]
pub enum HostError {
    /// The core refused the scene, camera or settings.
    Core(tessera_core::Error),
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

impl From<tessera_core::Error> for HostError {
    fn from(e: tessera_core::Error) -> Self {
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
    fn messages_escape_the_paths_they_show() {
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
