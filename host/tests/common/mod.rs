//! Helpers shared by the CLI tests: the binary, self-cleaning scratch folders.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The `tessera` binary.
pub fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tessera"))
}

/// A fresh, empty folder for one test, removed when dropped (also when the test
/// fails).
pub struct Scratch(tempfile::TempDir);

impl std::ops::Deref for Scratch {
    type Target = Path;
    fn deref(&self) -> &Path {
        self.0.path()
    }
}

impl AsRef<Path> for Scratch {
    fn as_ref(&self) -> &Path {
        self.0.path()
    }
}

/// A [`Scratch`] folder named after the test.
pub fn scratch(name: &str) -> Scratch {
    Scratch(
        tempfile::Builder::new()
            .prefix(&format!("tessera-cli-{name}-"))
            .tempdir()
            .unwrap(),
    )
}

pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

pub fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes")
}

/// The names of the entries of `dir`, sorted.
pub fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(Result::ok)
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The temporary files left in `dir`.
pub fn temps(dir: &Path) -> Vec<String> {
    entries(dir)
        .into_iter()
        .filter(|n| n.ends_with(".tmp") || n.ends_with(".old") || n.starts_with(".tessera-"))
        .collect()
}
