//! Bakes the scene file into the firmware and sets up the link.
//!
//! The scene is the file named by `TESSERA_SCENE` (relative to this folder), or
//! `../../scenes/teapot.toml` (the teapot, which bakes to the core's built-in
//! one). It is read as `tessera render` reads it (mesh files relative to it) and
//! written to `OUT_DIR/scene.rs` as Rust statics, which `src/main.rs` includes:
//! the scene lies in flash and takes no RAM. A scene file that is wrong fails the
//! build with the reader's message (file, line, what is wrong).
//!
//! The link: memory.x where the linker finds it, the binaries linked with
//! cortex-m-rt's `link.x` (which includes it); with the feature `defmt`, also
//! with defmt's `defmt.x`, and defmt's default log level set.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The scene file without `TESSERA_SCENE`.
const DEFAULT_SCENE: &str = "../../scenes/teapot.toml";

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

/// Writes the scene named by `TESSERA_SCENE` to `out/scene.rs` (the same as the
/// qemu example's build.rs, but for the default scene and the `bvh` message).
fn bake(out: &Path) -> Result<(), String> {
    println!("cargo::rerun-if-env-changed=TESSERA_SCENE");
    let scene = env::var("TESSERA_SCENE").unwrap_or_else(|_| DEFAULT_SCENE.into());
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
        if let Some(file) = tessera_host::mesh::obj_file(mesh, base) {
            println!("cargo::rerun-if-changed={}", file.display());
        }
    }
    let source = tessera_host::bake::scene_source(&desc, &scene, "tessera_core")
        .map_err(|e| format!("{scene}: {e}"))?;
    // The baked hierarchies are of the core's feature `bvh`.
    if source.contains("BakedBvh") && env::var_os("CARGO_FEATURE_BVH").is_none() {
        return Err(format!(
            "{scene} has meshes or 100 triangles or more: it needs the feature `bvh` \
             (on by default; with --no-default-features, add --features bvh)"
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
    // The scene's name, for the firmware's log.
    println!("cargo::rustc-env=TESSERA_SCENE_NAME={scene}");
    fs::write(out.join("scene.rs"), source).map_err(|e| format!("cannot write scene.rs: {e}"))
}

/// Puts memory.x where the linker finds it and links with cortex-m-rt's `link.x`
/// (and defmt's `defmt.x`). Here rather than in `.cargo/config.toml`, so that the
/// crate links the same wherever it is built from (a copy outside this
/// repository too).
fn link(out: &Path) {
    fs::write(out.join("memory.x"), include_bytes!("memory.x")).expect("write memory.x");
    println!("cargo::rustc-link-search={}", out.display());
    println!("cargo::rustc-link-arg-bins=-Tlink.x");
    if env::var_os("CARGO_FEATURE_DEFMT").is_some() {
        // defmt's linker script (its build script puts it on the search path):
        // the sections of the interned log strings.
        println!("cargo::rustc-link-arg-bins=-Tdefmt.x");
        // The log level of this crate's messages when DEFMT_LOG is not set
        // (defmt's own default, `error`, would leave out the start and the
        // timing): the macros read it while this crate compiles, so the image is
        // the same whichever folder cargo runs in.
        println!("cargo::rerun-if-env-changed=DEFMT_LOG");
        if env::var_os("DEFMT_LOG").is_none() {
            println!("cargo::rustc-env=DEFMT_LOG=info");
        }
    }
    println!("cargo::rerun-if-changed=memory.x");
    println!("cargo::rerun-if-changed=build.rs");
}
