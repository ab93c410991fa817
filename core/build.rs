//! Tells the math module which hardware square root the target has: emits
//! `cfg(tessera_riscv_f)` on RISC-V targets with the F extension (single precision
//! in hardware: `fsqrt.s`). Decided by the target's name (its base ISA letters,
//! `riscv32imafc`, `riscv64gc`), or by `target_feature`s `f`/`d` where rustc sets
//! them: on stable it does not for `riscv32imafc-unknown-none-elf`. Arm needs no
//! build script: `cfg(all(target_arch = "arm", target_abi = "eabihf"))` holds on
//! every Arm target with an FPU.

use std::env;

fn main() {
    println!("cargo::rustc-check-cfg=cfg(tessera_riscv_f)");
    println!("cargo::rerun-if-changed=build.rs");
    let target = env::var("TARGET").unwrap_or_default();
    let arch = target.split('-').next().unwrap_or("");
    let Some(isa) = arch
        .strip_prefix("riscv32")
        .or_else(|| arch.strip_prefix("riscv64"))
    else {
        return;
    };
    // The single-letter extensions come first (`imafc`), multi-letter ones after
    // an underscore; `g` is `imafd`, and D implies F.
    let letters = isa.split('_').next().unwrap_or("");
    let by_name = letters.contains(['f', 'd', 'g']);
    let features = env::var("CARGO_CFG_TARGET_FEATURE").unwrap_or_default();
    let by_feature = features.split(',').any(|f| f == "f" || f == "d");
    if by_name || by_feature {
        println!("cargo::rustc-cfg=tessera_riscv_f");
    }
}
