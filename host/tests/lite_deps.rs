//! The library without its `cli` feature (`default-features = false`, what a
//! firmware's `build.rs` takes to read and bake scene files) keeps none of the
//! command's dependencies: `cargo tree` of that build lists none of them. (It
//! reads PNG and JPEG files for image textures, so `image` with those two
//! codecs is the library's.) Runs with and without `cli` (it only asks cargo).

use std::path::Path;
use std::process::Command;

/// The crates only the command needs (and with them their own crates:
/// `rayon-core`, `clap_builder`, `signal-hook-registry`, ...).
const CLI_ONLY: [&str; 7] = [
    "gif",
    "rayon",
    "clap",
    "indicatif",
    "flip-rs",
    "embedded-graphics-simulator",
    "signal-hook",
];

/// The names of the crates in the normal (not dev, not build) dependencies of
/// `tessera-host` built with `features` (cargo tree's arguments).
fn crates(features: &[&str]) -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let out = Command::new(env!("CARGO"))
        .current_dir(&root)
        .args(["tree", "-p", "tessera-host", "-e", "normal"])
        .args(["--prefix", "none", "--offline"])
        .args(features)
        .output()
        .expect("cargo runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "cargo tree {features:?} failed: {}\n{stdout}",
        String::from_utf8_lossy(&out.stderr)
    );
    let mut names: Vec<String> = stdout
        .lines()
        .filter_map(|l| l.split_whitespace().next())
        .map(str::to_owned)
        .collect();
    names.sort();
    names.dedup();
    names
}

#[test]
fn without_cli_the_library_has_none_of_the_command_s_dependencies() {
    let lite = crates(&["--no-default-features"]);
    // What the scene reader and the baker need is there (the list is read right).
    for name in ["tessera-host", "tessera-core", "toml", "serde", "tobj"] {
        assert!(lite.iter().any(|c| c == name), "{name} missing: {lite:?}");
    }
    let found: Vec<&str> = CLI_ONLY
        .into_iter()
        .filter(|name| {
            lite.iter().any(|c| {
                c.strip_prefix(name)
                    .is_some_and(|rest| rest.is_empty() || rest.starts_with(['-', '_']))
            })
        })
        .collect();
    assert!(
        found.is_empty(),
        "the build without `cli` depends on {found:?} (all: {lite:?})"
    );
    // The default build has them: the check above can see them.
    let full = crates(&[]);
    for name in CLI_ONLY {
        assert!(
            full.iter().any(|c| c == name),
            "{name} not found in {full:?}"
        );
    }
}
