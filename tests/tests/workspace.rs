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

/// What the crate registry and the online documentation read from the two
/// published manifests (tests/run-all.sh packages both with `cargo publish
/// --dry-run` and type-checks each from its packaged files): a licence with both texts in each package, identical to the
/// repository's; a README, description, keywords and categories within the
/// registry's limits; the documentation address and its build of every feature
/// (and the Cortex-M4F for the core); no placeholder repository address; the path
/// dependencies with the version the registry copy needs; the current version in
/// the CHANGELOG.
#[test]
fn the_published_manifests_are_complete() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let read = |rel: &str| std::fs::read_to_string(root.join(rel)).unwrap();
    let workspace: toml::Table = read("Cargo.toml").parse().unwrap();
    let ws_package = &workspace["workspace"]["package"];
    assert_eq!(ws_package["license"].as_str(), Some("MIT OR Apache-2.0"));
    let version = ws_package["version"].as_str().unwrap().to_string();
    let mut wrong = Vec::new();
    for (dir, name) in [("core", "tessera-core"), ("host", "tessera-host")] {
        let manifest: toml::Table = read(&format!("{dir}/Cargo.toml")).parse().unwrap();
        let package = manifest["package"].as_table().unwrap();
        let str_of = |key: &str| package.get(key).and_then(|v| v.as_str()).unwrap_or("");
        let list = |key: &str| -> Vec<String> {
            package
                .get(key)
                .and_then(|v| v.as_array())
                .map(|a| {
                    a.iter()
                        .filter_map(|v| v.as_str())
                        .map(String::from)
                        .collect()
                })
                .unwrap_or_default()
        };
        if str_of("name") != name {
            wrong.push(format!("{dir}: named {:?}", str_of("name")));
        }
        if str_of("description").len() < 20 {
            wrong.push(format!("{name}: no description"));
        }
        for key in ["license", "rust-version", "version"] {
            if package.get(key).is_none() {
                wrong.push(format!("{name}: no {key}"));
            }
        }
        if package.contains_key("repository") || ws_package.get("repository").is_some() {
            wrong.push(format!("{name}: a repository address (none is public yet)"));
        }
        if str_of("documentation") != format!("https://docs.rs/{name}") {
            wrong.push(format!(
                "{name}: documentation {:?}",
                str_of("documentation")
            ));
        }
        let keywords = list("keywords");
        if keywords.is_empty()
            || keywords.len() > 5
            || keywords.iter().any(|k| {
                k.len() > 20
                    || !k
                        .chars()
                        .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
            })
        {
            wrong.push(format!(
                "{name}: keywords {keywords:?} (1 to 5, 20 characters)"
            ));
        }
        let categories = list("categories");
        if categories.is_empty() || categories.len() > 5 {
            wrong.push(format!("{name}: categories {categories:?}"));
        }
        let readme = str_of("readme");
        let include = list("include");
        for file in [readme, "LICENSE-MIT", "LICENSE-APACHE", "CHANGELOG.md"] {
            if !include.iter().any(|i| i == file) {
                wrong.push(format!("{name}: {file} not in the package's `include`"));
            }
            match std::fs::read(root.join(dir).join(file)) {
                Err(e) => wrong.push(format!("{dir}/{file}: {e}")),
                Ok(bytes) if file != readme && bytes != std::fs::read(root.join(file)).unwrap() => {
                    wrong.push(format!("{dir}/{file} differs from the repository's"))
                }
                Ok(_) => {}
            }
        }
        let docs = package
            .get("metadata")
            .and_then(|m| m.get("docs"))
            .and_then(|d| d.get("rs"))
            .and_then(|d| d.as_table());
        // Only docs.rs's own keys: a package key written after the table's
        // heading would fall into it (and be lost to the package).
        let known = [
            "all-features",
            "features",
            "no-default-features",
            "default-target",
            "targets",
            "rustdoc-args",
            "cargo-args",
        ];
        for key in docs
            .map(|d| d.keys().collect::<Vec<_>>())
            .unwrap_or_default()
        {
            if !known.contains(&key.as_str()) {
                wrong.push(format!("{name}: `{key}` in [package.metadata.docs.rs]"));
            }
        }
        match (name, docs) {
            (_, None) => wrong.push(format!("{name}: no [package.metadata.docs.rs]")),
            ("tessera-core", Some(d)) => {
                let targets: Vec<&str> = d
                    .get("targets")
                    .and_then(|t| t.as_array())
                    .map(|a| a.iter().filter_map(|v| v.as_str()).collect())
                    .unwrap_or_default();
                if d.get("all-features").and_then(|v| v.as_bool()) != Some(true)
                    || !targets.contains(&"thumbv7em-none-eabihf")
                {
                    wrong.push(format!("{name}: docs.rs {d:?}"));
                }
            }
            (_, Some(d)) => {
                if d.get("features").is_none() && d.get("all-features").is_none() {
                    wrong.push(format!("{name}: docs.rs builds only the default features"));
                }
            }
        }
    }
    for dep in ["tessera-core", "tessera-host"] {
        let v = workspace["workspace"]["dependencies"][dep]
            .get("version")
            .and_then(|v| v.as_str());
        if v != Some(version.as_str()) {
            wrong.push(format!(
                "workspace dependency {dep}: version {v:?}, not {version}"
            ));
        }
    }
    let changelog = read("CHANGELOG.md");
    for heading in [
        format!("## [{version}]"),
        "## [Unreleased]".into(),
        "## Minimum supported Rust".into(),
    ] {
        if !changelog.contains(&heading) {
            wrong.push(format!("CHANGELOG.md has no `{heading}`"));
        }
    }
    assert!(wrong.is_empty(), "{wrong:#?}");
}
