//! The workspace's own shape: what `cargo test --workspace` builds.

use std::path::Path;

/// The report programs (tests/src/bin) hold no tests: each is declared in
/// tests/Cargo.toml with `test = false`, so the test run links no empty harness
/// for them, and none is left to cargo's automatic discovery (which would build
/// one).
#[test]
fn report_programs_build_no_test_harness() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let manifest = std::fs::read_to_string(root.join("Cargo.toml")).unwrap();
    let mut declared = Vec::new();
    let mut wrong = Vec::new();
    for section in manifest.split("\n[").skip(1) {
        if !section.starts_with("[bin]]") {
            continue;
        }
        let value = |key: &str| {
            section.lines().find_map(|l| {
                let (k, v) = l.split_once('=')?;
                (k.trim() == key).then(|| v.trim().trim_matches('"').to_string())
            })
        };
        let path = value("path").unwrap_or_default();
        if value("test").as_deref() != Some("false") {
            wrong.push(format!("{path}: no `test = false`"));
        }
        declared.push(path);
    }
    for entry in std::fs::read_dir(root.join("src/bin")).unwrap() {
        let name = entry.unwrap().file_name().into_string().unwrap();
        let path = format!("src/bin/{name}");
        if !declared.contains(&path) {
            wrong.push(format!("{path}: not declared as a [[bin]]"));
        }
    }
    assert!(declared.len() >= 8, "the report programs: {declared:?}");
    assert!(wrong.is_empty(), "tests/Cargo.toml: {wrong:#?}");
}

/// The core's package builds from its own files: `cargo package -p tessera`
/// copies the package's folder alone and builds it (its verification step), so
/// a file read from outside `core/` (an `include_str!` of `../../scenes/..`)
/// fails it. Offline: the workspace's build has fetched every dependency.
#[test]
fn the_core_packages_and_builds_from_its_own_files() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let target = root.join("target").join("package-check");
    let out = tessera_tests::firmware::cargo()
        .current_dir(&root)
        .args(["package", "-p", "tessera", "--offline", "--allow-dirty"])
        .arg("--target-dir")
        .arg(&target)
        .output()
        .expect("cargo runs");
    assert!(
        out.status.success(),
        "cargo package -p tessera failed:\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
