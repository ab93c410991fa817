//! Puts memory.x where the linker finds it and links the binaries with
//! cortex-m-rt's `link.x` (which includes it).

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
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
}
