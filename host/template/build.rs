//! Bakes the scene file into the firmware and sets up the link.
//!
//! The scene is the file named by `TESSERA_SCENE` (relative to this folder), or
//! `scene.toml`. It is read as `tessera render` reads it (OBJ meshes relative to
//! it) and written to `OUT_DIR/scene.rs` as Rust statics, which `src/main.rs`
//! includes: the scene lies in flash and takes no RAM. A scene file that is wrong
//! fails the build with the reader's message (file, line, what is wrong).

use std::env;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

fn main() -> ExitCode {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    match bake(&out) {
        Ok(()) => {
            link(&out);
            ExitCode::SUCCESS
        }
        Err(message) => {
            println!("cargo::error={message}");
            ExitCode::FAILURE
        }
    }
}

/// Writes the scene named by `TESSERA_SCENE` to `out/scene.rs`.
fn bake(out: &Path) -> Result<(), String> {
    println!("cargo::rerun-if-env-changed=TESSERA_SCENE");
    let scene = env::var("TESSERA_SCENE").unwrap_or_else(|_| "scene.toml".into());
    // Cargo runs this script in the crate's folder: the path is taken from there,
    // and the messages name the file as the user gave it.
    println!("cargo::rerun-if-changed={scene}");
    let path = Path::new(&scene);
    let desc = tessera_host::file::load(path).map_err(|e| e.to_string())?;
    for w in tessera_host::file::warnings(&desc) {
        println!("cargo::warning={scene}: {w}");
    }
    let base = path.parent().unwrap_or(Path::new(""));
    for mesh in &desc.meshes {
        if let Some(obj) = tessera_host::mesh::obj_file(mesh, base) {
            println!("cargo::rerun-if-changed={}", obj.display());
        }
    }
    let source = tessera_host::bake::scene_source(&desc, &scene, "tessera_core")
        .map_err(|e| format!("{scene}: {e}"))?;
    // The baked hierarchies are of the core's feature `bvh`.
    if source.contains("BakedBvh") && env::var_os("CARGO_FEATURE_BVH").is_none() {
        return Err(format!(
            "{scene} has meshes or 100 triangles or more: it needs the feature `bvh` \
             (on by default; build without --no-default-features)"
        ));
    }
    // The kinds (and image textures, and the sun) the core compiles only with
    // a feature of its own (the example forwards each: `--features
    // cylinder,disk,image,sun`).
    let missing: Vec<&str> = tessera_host::bake::kind_features(&desc)
        .into_iter()
        .filter(|f| {
            // Cargo's variable for feature `a-b` is `CARGO_FEATURE_A_B`.
            let var = format!("CARGO_FEATURE_{}", f.to_uppercase().replace('-', "_"));
            env::var_os(var).is_none()
        })
        .collect();
    if !missing.is_empty() {
        return Err(format!(
            "{scene} needs the core's optional features `{}` \
             (build with --features {})",
            missing.join("`, `"),
            missing.join(",")
        ));
    }
    // The scene's name, for the firmware to print.
    println!("cargo::rustc-env=TESSERA_SCENE_NAME={scene}");
    fs::write(out.join("scene.rs"), source).map_err(|e| format!("cannot write scene.rs: {e}"))
}

/// Puts memory.x where the linker finds it and links with cortex-m-rt's `link.x`
/// (which includes it). Here rather than in `.cargo/config.toml`, so that the
/// crate links the same wherever it is built from.
fn link(out: &Path) {
    fs::write(out.join("memory.x"), include_bytes!("memory.x")).expect("write memory.x");
    println!("cargo::rustc-link-search={}", out.display());
    println!("cargo::rustc-link-arg-bins=-Tlink.x");
    println!("cargo::rerun-if-changed=memory.x");
    println!("cargo::rerun-if-changed=build.rs");
}
