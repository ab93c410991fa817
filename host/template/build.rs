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
    // The scene file, read, checked against the core's features this build
    // enables, and baked to `OUT_DIR/scene.rs`.
    match tessera_host::bake::build_script("scene.toml") {
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
