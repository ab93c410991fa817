//! Puts memory.x where the linker finds it and links the binaries with
//! cortex-m-rt's `link.x` (which includes it); with the feature `defmt`, also
//! with defmt's `defmt.x`, and sets defmt's default log level.

use std::env;
use std::fs;
use std::path::PathBuf;

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::write(out.join("memory.x"), include_bytes!("memory.x")).expect("write memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    // Here rather than in a `.cargo/config.toml`, so that the crate links the same
    // wherever it is built from (a copy outside this repository too). `--nmagic`:
    // no page alignment of the sections (as rp235x-hal's examples link), so no
    // flash is lost to padding.
    println!("cargo:rustc-link-arg-bins=--nmagic");
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
    if env::var_os("CARGO_FEATURE_DEFMT").is_some() {
        // defmt's linker script (its build script puts it on the search path):
        // the sections of the interned log strings.
        println!("cargo:rustc-link-arg-bins=-Tdefmt.x");
        // The log level of this crate's messages when DEFMT_LOG is not set
        // (defmt's own default, `error`, would leave out the start and the
        // frames): the macros read it while this crate compiles, so the image is
        // the same whichever folder cargo runs in.
        println!("cargo:rerun-if-env-changed=DEFMT_LOG");
        if env::var_os("DEFMT_LOG").is_none() {
            println!("cargo:rustc-env=DEFMT_LOG=info");
        }
    }
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
}
