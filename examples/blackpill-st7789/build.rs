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
    // The scene file, read, checked against the core's features this build
    // enables, and baked to `OUT_DIR/scene.rs`.
    match tessera_host::bake::build_script(DEFAULT_SCENE) {
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
