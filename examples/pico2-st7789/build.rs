//! Bakes the animated scene into the firmware and sets up the link.
//!
//! The scene is the file named by `TESSERA_SCENE` (relative to this folder), or
//! `../../scenes/examples/animated-pico2.toml` (the repository's animated scene,
//! `scenes/examples/animated.toml`, framed for the square panel). It is read as
//! `tessera render` reads it (mesh files relative to it) and written to
//! `OUT_DIR/scene.rs` as Rust statics, which `src/main.rs` includes: the scene,
//! its meshes, their BVHs and the keyframes lie in flash. A scene file that is
//! wrong fails the build with the reader's message (file, line, what is wrong),
//! and so does one this firmware cannot play: one without `[[keyframes]]`, or one
//! that needs a feature of the core that `Cargo.toml` does not enable.
//!
//! `tessera_host::bake::build_script_for` reads, checks and bakes it, against
//! the core's features this firmware fixes in `Cargo.toml` ([`CORE_FEATURES`]:
//! it always plays an animation) rather than forwards one by one as the other
//! examples do.
//!
//! The link: memory.x and ram.x where the linker finds them, the binaries
//! linked with ram.x (tessera's code in SRAM; not with the feature
//! `flash-only`), then cortex-m-rt's `link.x` (which includes memory.x), the
//! binaries linked with cortex-m-rt's `link.x` (which includes it) and
//! `--nmagic`; with the feature `defmt`, also with defmt's `defmt.x`, and
//! defmt's default log level set.

use std::env;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use tessera_host::bake::{CoreFeatures, build_script_for};

/// The scene file without `TESSERA_SCENE`.
const DEFAULT_SCENE: &str = "../../scenes/examples/animated-pico2.toml";

/// The core's features `Cargo.toml` enables (`animation` implies `instances`,
/// which implies `bvh`).
const CORE_FEATURES: [&str; 3] = ["bvh", "instances", "animation"];

fn main() -> ExitCode {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    match bake() {
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

/// Reads the scene file, checks that this firmware can play it and writes it
/// baked to `OUT_DIR/scene.rs` (`build_script_for`, which also sets
/// `TESSERA_SCENE_NAME`, the file as named, for the log).
fn bake() -> Result<(), String> {
    let desc = build_script_for(DEFAULT_SCENE, CoreFeatures::Fixed(&CORE_FEATURES))?;
    if desc.keyframes.is_empty() {
        return Err(format!(
            "{} has no [[keyframes]]: this firmware plays an animation (a still scene \
             file: examples/blackpill-st7789)",
            std::env::var("TESSERA_SCENE").unwrap_or_else(|_| DEFAULT_SCENE.into())
        ));
    }
    Ok(())
}

/// Puts memory.x and ram.x where the linker finds them and links with `--nmagic`,
/// cortex-m-rt's `link.x` (and defmt's `defmt.x`). Here rather than in a
/// `.cargo/config.toml`, so that the crate links the same wherever it is built
/// from (a copy outside this repository too).
fn link(out: &Path) {
    fs::write(out.join("memory.x"), include_bytes!("memory.x")).expect("write memory.x");
    fs::write(out.join("ram.x"), include_bytes!("ram.x")).expect("write ram.x");
    println!("cargo::rustc-link-search={}", out.display());
    // No page alignment of the sections (as rp235x-hal's examples link), so no
    // flash is lost to padding.
    println!("cargo::rustc-link-arg-bins=--nmagic");
    // tessera's code in SRAM (ram.x, src/ram.rs), unless the feature
    // `flash-only` keeps everything in flash. Before link.x: a linker gives an
    // input section to the first pattern that matches it in the order it reads
    // them.
    if env::var_os("CARGO_FEATURE_FLASH_ONLY").is_none() {
        println!("cargo::rustc-link-arg-bins=-Tram.x");
    }
    println!("cargo::rustc-link-arg-bins=-Tlink.x");
    if env::var_os("CARGO_FEATURE_DEFMT").is_some() {
        // defmt's linker script (its build script puts it on the search path):
        // the sections of the interned log strings.
        println!("cargo::rustc-link-arg-bins=-Tdefmt.x");
        // The log level of this crate's messages when DEFMT_LOG is not set
        // (defmt's own default, `error`, would leave out the start and the
        // frames): the macros read it while this crate compiles, so the image is
        // the same whichever folder cargo runs in.
        println!("cargo::rerun-if-env-changed=DEFMT_LOG");
        if env::var_os("DEFMT_LOG").is_none() {
            println!("cargo::rustc-env=DEFMT_LOG=info");
        }
    }
    println!("cargo::rerun-if-changed=memory.x");
    println!("cargo::rerun-if-changed=ram.x");
    println!("cargo::rerun-if-changed=build.rs");
}
