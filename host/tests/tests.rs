//! Integration tests of the host: one binary (linked once), one module per concern.
//!
//! Every module but `lite_deps` runs the `tessera` command or uses what only the
//! `cli` feature brings (`image`, embedded-graphics): built with that feature
//! only. `lite_deps` only asks cargo, and runs with or without it. No test needs a
//! process of its own: each runs the command as a child in its own scratch
//! folder (current directory, signals, resource limits and memory are the
//! child's), and none sets an environment variable of this process.

#[cfg(feature = "cli")]
mod cli;
#[cfg(feature = "cli")]
mod common;
#[cfg(feature = "cli")]
mod diff;
#[cfg(feature = "cli")]
mod display_driver;
#[cfg(feature = "cli")]
mod generated;
#[cfg(feature = "cli")]
mod limits;
mod lite_deps;
#[cfg(feature = "cli")]
mod messages;
#[cfg(feature = "cli")]
mod new;
#[cfg(feature = "cli")]
mod outputs;
#[cfg(feature = "cli")]
mod precision_warnings;

/// Every file of `tests/` (and every folder with a `mod.rs`) is a module of this
/// binary: with `autotests = false` cargo would neither build a file left out nor
/// say so.
#[test]
fn every_file_of_tests_is_a_module() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests");
    let this = include_str!("tests.rs");
    let mut modules = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let module = if path.is_dir() {
            path.join("mod.rs").is_file()
        } else {
            path.extension().is_some_and(|e| e == "rs") && !path.ends_with("tests.rs")
        };
        if module {
            let name = path.file_stem().unwrap().to_string_lossy();
            assert!(
                this.lines().any(|l| l == format!("mod {name};")),
                "{} is not a module of tests/tests.rs",
                path.display()
            );
            modules += 1;
        }
    }
    assert!(modules >= 7, "{modules} modules");
}
