//! Puts the memory map of the board (`memory/<board>.x`) where the linker finds it,
//! as `memory.x`, and links the binaries with the runtime's `link.x`: cortex-m-rt's
//! on Arm (it includes `memory.x`), riscv-rt's on RISC-V (after `-Tmemory.x`).
//!
//! The board is the target's, or the one a board feature names:
//! - `thumbv7em-none-eabihf`: `mps2-an386` (Cortex-M4F); `mps2-an500` (Cortex-M7)
//!   with the feature `mps2-an500`;
//! - `thumbv8m.main-none-eabihf`: `mps2-an505` (Cortex-M33); `mps3-an547`
//!   (Cortex-M55) with the feature `mps3-an547`;
//! - `riscv32imafc-unknown-none-elf`: qemu's `virt`;
//! - `thumbv6m-none-eabi` (no FPU): `mps2-an385` (a Cortex-M3, which runs the
//!   Armv6-M code of a Cortex-M0/M0+);
//! - `riscv32imc-unknown-none-elf` (no FPU): qemu's `virt`, its CPU without F and D.
//!
//! No file named `memory.x` lies in the package's folder: the linker, which runs
//! there, would find it before the one in `OUT_DIR`.

use std::env;
use std::fs;
use std::path::PathBuf;

fn main() {
    let target = env::var("TARGET").expect("cargo sets TARGET");
    let feature = |name: &str| env::var_os(format!("CARGO_FEATURE_{name}")).is_some();
    let (an500, an547) = (feature("MPS2_AN500"), feature("MPS3_AN547"));
    let board = match (target.as_str(), an500, an547) {
        ("thumbv7em-none-eabihf", false, false) => "mps2-an386",
        ("thumbv7em-none-eabihf", true, false) => "mps2-an500",
        ("thumbv8m.main-none-eabihf", false, false) => "mps2-an505",
        ("thumbv8m.main-none-eabihf", false, true) => "mps3-an547",
        ("riscv32imafc-unknown-none-elf", false, false) => "riscv-virt",
        ("thumbv6m-none-eabi", false, false) => "mps2-an385",
        ("riscv32imc-unknown-none-elf", false, false) => "riscv-virt",
        _ => panic!(
            "tessera-fw builds for thumbv7em-none-eabihf (mps2-an386; mps2-an500 with the \
             feature mps2-an500), thumbv8m.main-none-eabihf (mps2-an505; mps3-an547 with \
             the feature mps3-an547), riscv32imafc-unknown-none-elf (virt), \
             thumbv6m-none-eabi (mps2-an385) and riscv32imc-unknown-none-elf (virt): not \
             {target} with mps2-an500 {an500}, mps3-an547 {an547}"
        ),
    };
    // The board for the code: `clock` takes its tick rate by it.
    println!(
        "cargo::rustc-check-cfg=cfg(board, values(\"mps2-an385\", \"mps2-an386\", \
         \"mps2-an500\", \"mps2-an505\", \"mps3-an547\", \"riscv-virt\"))"
    );
    println!("cargo::rustc-cfg=board=\"{board}\"");
    // A target without an FPU (floating point in software): `main` reports the
    // RISC-V CPU's extensions there.
    println!("cargo::rustc-check-cfg=cfg(nofpu)");
    if matches!(
        target.as_str(),
        "thumbv6m-none-eabi" | "riscv32imc-unknown-none-elf"
    ) {
        println!("cargo::rustc-cfg=nofpu");
    }
    let map = PathBuf::from("memory").join(format!("{board}.x"));
    let text = fs::read(&map).unwrap_or_else(|e| panic!("cannot read {}: {e}", map.display()));
    let out = PathBuf::from(env::var_os("OUT_DIR").expect("cargo sets OUT_DIR"));
    fs::write(out.join("memory.x"), text).expect("write memory.x");
    println!("cargo:rustc-link-search={}", out.display());
    // Here rather than in a `.cargo/config.toml`, so that the crate links the same
    // wherever it is built from (a copy outside this repository too).
    if target.starts_with("riscv") {
        println!("cargo:rustc-link-arg-bins=-Tmemory.x");
    }
    println!("cargo:rustc-link-arg-bins=-Tlink.x");
    println!("cargo:rerun-if-changed=memory");
    println!("cargo:rerun-if-changed=build.rs");
}
