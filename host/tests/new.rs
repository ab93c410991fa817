//! `tessera new`: the crate it writes, and what it refuses without writing
//! anything. (Building and running the crate under qemu:
//! tests/tests/examples/qemu.rs in the workspace's test crate.)

use crate::common::{bin, entries, scratch, text};
use std::path::Path;

fn checkout() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

#[test]
fn new_writes_the_template_with_the_crate_s_name_and_its_source() {
    let dir = scratch("new");
    let out = bin()
        .current_dir(&dir)
        .args(["new", "my-fw"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let said = text(&out.stdout);
    assert!(
        said.starts_with("created my-fw (13 files, tessera 0.1.0 from the crate registry)"),
        "{said}"
    );
    assert_eq!(entries(&dir), ["my-fw"], "no staging folder left");
    let manifest = std::fs::read_to_string(dir.join("my-fw/Cargo.toml")).unwrap();
    let parsed: toml::Table = manifest.parse().unwrap();
    assert_eq!(parsed["package"]["name"].as_str(), Some("my-fw"));
    assert_eq!(parsed["bin"][0]["name"].as_str(), Some("my-fw"));
    let core = &parsed["dependencies"]["tessera-core"];
    assert_eq!(core["version"].as_str(), Some(env!("CARGO_PKG_VERSION")));
    assert!(core.get("path").is_none());
    for file in [
        ".cargo/config.toml",
        "build.rs",
        "memory.x",
        "scene.toml",
        "src/main.rs",
        "src/animation.rs",
        "README.md",
    ] {
        assert!(dir.join("my-fw").join(file).is_file(), "{file}");
    }
    let readme = std::fs::read_to_string(dir.join("my-fw/README.md")).unwrap();
    assert!(
        readme.starts_with("# my-fw\n") && !readme.contains("{{"),
        "{readme}"
    );

    // A checkout: path dependencies, relative to the new crate.
    let in_sub = || {
        bin()
            .current_dir(&dir)
            .args(["new", "sub/fw2", "--path"])
            .arg(checkout())
            .output()
            .unwrap()
    };
    assert!(
        !in_sub().status.success(),
        "the folder it goes in must exist"
    );
    std::fs::create_dir(dir.join("sub")).unwrap();
    let out = in_sub();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let manifest: toml::Table = std::fs::read_to_string(dir.join("sub/fw2/Cargo.toml"))
        .unwrap()
        .parse()
        .unwrap();
    let path = manifest["build-dependencies"]["tessera-host"]["path"]
        .as_str()
        .unwrap();
    let resolved = dir.join("sub/fw2").join(path).canonicalize().unwrap();
    assert_eq!(resolved, checkout().join("host").canonicalize().unwrap());
    assert!(Path::new(path).is_relative(), "{path}");
}

#[test]
fn new_refuses_without_writing_anything() {
    let dir = scratch("new-refused");
    std::fs::create_dir(dir.join("taken")).unwrap();
    std::fs::write(dir.join("taken/keep.txt"), "the user's work").unwrap();
    std::fs::write(dir.join("file"), "a file").unwrap();
    for (args, message) in [
        (
            vec!["new", "taken"],
            "taken: already exists: nothing was written",
        ),
        (vec!["new", "file"], "file: already exists"),
        (vec!["new", "9lives"], "must start with an ASCII letter"),
        (vec!["new", "my fw"], "' ' is not an ASCII letter"),
        (
            vec!["new", "tessera-core"],
            "already among its dependencies",
        ),
        (
            vec!["new", "fw", "--path", "."],
            "not a checkout of tessera",
        ),
        (
            vec!["new", "fw", "--path", "nowhere"],
            "nowhere: cannot read the checkout",
        ),
    ] {
        let out = bin().current_dir(&dir).args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        let e = text(&out.stderr);
        assert!(
            e.starts_with("tessera: error: ") && e.contains(message),
            "{args:?}: {e}"
        );
    }
    assert_eq!(entries(&dir), ["file", "taken"]);
    assert_eq!(entries(&dir.join("taken")), ["keep.txt"]);
    assert_eq!(std::fs::read_to_string(dir.join("file")).unwrap(), "a file");
}
