//! Puts memory.x where the linker finds it (cortex-m-rt's link.x includes it).
//!
//! `-Tlink.x` itself comes from the repository's `.cargo/config.toml` (target
//! `thumbv7em-none-eabihf`): adding it here too would give it twice.

use std::env;
use std::fs;
use std::path::PathBuf;

fn main() {
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::write(out.join("memory.x"), include_bytes!("memory.x")).expect("write memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    println!("cargo:rerun-if-changed=memory.x");
    println!("cargo:rerun-if-changed=build.rs");
}
