//! The firmware template: a crate for the Cortex-M4F under qemu with a scene file
//! baked into flash by its `build.rs` (`host/template/`, which
//! `examples/qemu-m4f` is made from). `tessera new` writes it; it is also a
//! cargo-generate template (its `cargo-generate.toml`).
//!
//! Two files hold placeholders, `Cargo.toml.liquid` and `README.md.liquid`
//! (written without the `.liquid`): `{{project-name}}`, the crate's name, and
//! `{{tessera_version}}`, the version of `tessera-core` and `tessera-host` it
//! depends on. Every other file is copied as it is.

use std::fmt;
use std::path::{Component, Path, PathBuf};

/// A file of the template: its path in the new crate (with `.liquid` for the
/// files that hold placeholders) and its bytes.
struct TemplateFile {
    path: &'static str,
    bytes: &'static [u8],
}

macro_rules! files {
    ($($path:literal),* $(,)?) => {
        &[$(TemplateFile { path: $path, bytes: include_bytes!(concat!("../template/", $path)) }),*]
    };
}

/// Every file of `host/template/` but `cargo-generate.toml` (a unit test checks
/// the list against the folder).
const FILES: &[TemplateFile] = files![
    ".cargo/config.toml",
    ".gitignore",
    "Cargo.toml.liquid",
    "README.md.liquid",
    "build.rs",
    "memory.x",
    "scene.toml",
    "icosahedron.obj",
    "src/main.rs",
    "src/clock.rs",
    "src/ppm.rs",
    "src/stack.rs",
    "src/animation.rs",
];

/// Where the new crate takes `tessera-core` and `tessera-host` from.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Source {
    /// The crate registry, at this version.
    Registry(String),
    /// A checkout of tessera's repository: the path from the new crate's folder
    /// to it (relative, or absolute), with the version of this build.
    Checkout(PathBuf),
}

/// What is wrong with a crate's name or a checkout's path.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TemplateError(String);

impl fmt::Display for TemplateError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for TemplateError {}

/// The version of tessera this host crate is (what a new crate depends on).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");

/// Checks `name` as Cargo checks a package's name (ASCII letters, digits, `-`
/// and `_`, starting with a letter, at most 64 characters) and that it is not a
/// name the template's own dependencies or Rust already take.
///
/// # Errors
/// What is wrong, naming `name`.
pub fn check_name(name: &str) -> Result<(), TemplateError> {
    let bad = |why: &str| {
        Err(TemplateError(format!(
            "{name:?} is not a crate name: {why}"
        )))
    };
    let Some(first) = name.chars().next() else {
        return bad("it is empty");
    };
    if !first.is_ascii_alphabetic() {
        return bad("it must start with an ASCII letter");
    }
    if let Some(c) = name
        .chars()
        .find(|c| !(c.is_ascii_alphanumeric() || *c == '-' || *c == '_'))
    {
        return bad(&format!("{c:?} is not an ASCII letter, digit, `-` or `_`"));
    }
    if name.len() > 64 {
        return bad("it is longer than 64 characters");
    }
    let taken = [
        "tessera-core",
        "tessera-host",
        "tessera_core",
        "tessera_host",
        "cortex-m",
        "cortex-m-rt",
        "cortex-m-semihosting",
        "core",
        "std",
        "alloc",
        "test",
        "proc_macro",
    ];
    if taken
        .iter()
        .any(|t| t.replace('_', "-") == name.replace('_', "-"))
    {
        return bad("a crate of that name is already among its dependencies or Rust's own");
    }
    Ok(())
}

/// The dependency table's value for `krate` (`core` or `host`) from `source`.
fn dependency(krate: &str, source: &Source) -> Result<String, TemplateError> {
    Ok(match source {
        Source::Registry(version) => format!("version = \"{version}\""),
        Source::Checkout(path) => {
            let path = path.join(krate);
            let path = path.to_str().ok_or_else(|| {
                TemplateError(format!("the checkout's path {path:?} is not UTF-8"))
            })?;
            // A TOML basic string: `\` and `"` escaped, no control character.
            if path.chars().any(char::is_control) {
                return Err(TemplateError(format!(
                    "the checkout's path {path:?} holds a control character"
                )));
            }
            let escaped = path.replace('\\', "\\\\").replace('"', "\\\"");
            format!("version = \"{VERSION}\", path = \"{escaped}\"")
        }
    })
}

/// The files of a new crate named `name` that depends on tessera from `source`:
/// each path (relative to the crate's folder) and its bytes.
///
/// # Errors
/// A bad name ([`check_name`]), or a checkout's path that TOML cannot hold.
pub fn files(name: &str, source: &Source) -> Result<Vec<(PathBuf, Vec<u8>)>, TemplateError> {
    check_name(name)?;
    let (core, host) = (dependency("core", source)?, dependency("host", source)?);
    let mut out = Vec::with_capacity(FILES.len());
    for f in FILES {
        let Some(path) = f.path.strip_suffix(".liquid") else {
            out.push((PathBuf::from(f.path), f.bytes.to_vec()));
            continue;
        };
        let text = String::from_utf8_lossy(f.bytes)
            .replace(
                "tessera-core = { version = \"{{tessera_version}}\"",
                &format!("tessera-core = {{ {core}"),
            )
            .replace(
                "tessera-host = { version = \"{{tessera_version}}\"",
                &format!("tessera-host = {{ {host}"),
            )
            .replace("{{tessera_version}}", VERSION)
            .replace("{{project-name}}", name);
        out.push((PathBuf::from(path), text.into_bytes()));
    }
    Ok(out)
}

/// The path from folder `from` to `to`, both absolute and without `..`: `../..`
/// from `/a/b/c` to `/a`. Falls back to `to` when they share no root (another
/// drive).
#[must_use]
pub fn relative(from: &Path, to: &Path) -> PathBuf {
    let (a, b): (Vec<Component<'_>>, Vec<Component<'_>>) =
        (from.components().collect(), to.components().collect());
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    if common == 0 {
        return to.to_path_buf();
    }
    let mut out = PathBuf::new();
    for _ in common..a.len() {
        out.push("..");
    }
    for c in b.iter().skip(common) {
        out.push(c);
    }
    if out.as_os_str().is_empty() {
        out.push(".");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn template_dir() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("template")
    }

    /// Every file under `dir`, as paths relative to `root`.
    fn walk(root: &Path, dir: &Path, out: &mut Vec<String>) {
        for entry in std::fs::read_dir(dir).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                walk(root, &path, out);
            } else {
                out.push(
                    path.strip_prefix(root)
                        .unwrap()
                        .to_str()
                        .unwrap()
                        .to_string(),
                );
            }
        }
    }

    #[test]
    fn the_list_is_the_template_folder() {
        let mut on_disk = Vec::new();
        walk(&template_dir(), &template_dir(), &mut on_disk);
        on_disk.retain(|p| p != "cargo-generate.toml");
        on_disk.sort();
        let mut listed: Vec<String> = FILES.iter().map(|f| f.path.to_string()).collect();
        listed.sort();
        assert_eq!(listed, on_disk);
    }

    #[test]
    fn placeholders_are_filled_and_only_in_the_liquid_files() {
        let files = files("my-fw", &Source::Registry("0.7.1".into())).unwrap();
        let cargo = files
            .iter()
            .find(|(p, _)| p == Path::new("Cargo.toml"))
            .unwrap();
        let cargo = String::from_utf8(cargo.1.clone()).unwrap();
        assert!(cargo.contains("name = \"my-fw\"\n"), "{cargo}");
        assert!(
            cargo.contains("tessera-core = { version = \"0.7.1\", default-features = false }"),
            "{cargo}"
        );
        assert!(
            cargo.contains("tessera-host = { version = \"0.7.1\", default-features = false }"),
            "{cargo}"
        );
        for (path, bytes) in &files {
            let text = String::from_utf8_lossy(bytes);
            assert!(!path.to_str().unwrap().ends_with(".liquid"), "{path:?}");
            if matches!(path.to_str(), Some("Cargo.toml" | "README.md")) {
                assert!(!text.contains("{{"), "{path:?}: {text}");
            }
        }
        // The Rust sources are copied as they are.
        let main = files
            .iter()
            .find(|(p, _)| p == Path::new("src/main.rs"))
            .unwrap();
        assert_eq!(main.1, include_bytes!("../template/src/main.rs"));
        // The cargo-generate placeholders are the ones filled here, and its
        // configuration names the two templated files.
        let config = std::fs::read_to_string(template_dir().join("cargo-generate.toml")).unwrap();
        assert!(config.contains("[placeholders.tessera_version]"));
        assert!(config.contains("include = [\"Cargo.toml.liquid\", \"README.md.liquid\"]"));
    }

    #[test]
    fn a_checkout_is_a_path_dependency_with_this_version() {
        let out = files("fw", &Source::Checkout(PathBuf::from("../a \"b\\c"))).unwrap();
        let cargo = out
            .iter()
            .find(|(p, _)| p == Path::new("Cargo.toml"))
            .unwrap();
        let cargo = String::from_utf8(cargo.1.clone()).unwrap();
        let want = format!(
            "tessera-core = {{ version = \"{VERSION}\", path = \"../a \\\"b\\\\c/core\", default-features = false }}"
        );
        assert!(cargo.contains(&want), "{cargo}");
        let parsed: toml::Table = cargo.parse().unwrap();
        assert_eq!(
            parsed["build-dependencies"]["tessera-host"]["path"].as_str(),
            Some("../a \"b\\c/host")
        );
        assert!(
            files("fw", &Source::Checkout(PathBuf::from("a\nb")))
                .unwrap_err()
                .to_string()
                .contains("control character")
        );
    }

    #[test]
    fn bad_names_are_refused_with_the_reason() {
        for (name, why) in [
            ("", "empty"),
            ("1fw", "start with an ASCII letter"),
            ("my fw", "' ' is not"),
            ("fw/../x", "'/' is not"),
            ("é", "start with an ASCII letter"),
            ("tessera_core", "already among"),
            ("cortex_m", "already among"),
            ("std", "already among"),
        ] {
            let e = check_name(name).unwrap_err().to_string();
            assert!(e.contains(why), "{name:?}: {e}");
        }
        assert!(check_name(&"a".repeat(65)).is_err());
        for ok in ["fw", "my-firmware", "Fw_2", &"a".repeat(64)] {
            check_name(ok).unwrap();
        }
    }

    #[test]
    fn relative_paths_climb_then_descend() {
        let r = |a: &str, b: &str| relative(Path::new(a), Path::new(b));
        assert_eq!(
            r("/w/main/examples/qemu-m4f", "/w/main"),
            Path::new("../..")
        );
        assert_eq!(r("/tmp/x/fw", "/w/main"), Path::new("../../../w/main"));
        assert_eq!(r("/w/main", "/w/main"), Path::new("."));
        assert_eq!(r("/w", "/w/main/sub"), Path::new("main/sub"));
    }
}
