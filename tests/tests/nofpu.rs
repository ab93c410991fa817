//! The core on chips without an FPU (`tessera_tests::firmware::NOFPU_CORES`): the
//! firmware test image built for `thumbv6m-none-eabi` (a Cortex-M0/M0+, run on
//! `mps2-an385`'s Cortex-M3) and for `riscv32imc-unknown-none-elf` (qemu's `virt`
//! with F and D switched off), floating point in software, renders each built-in
//! scene at its own settings, one with stratified:2 and one baked scene byte for
//! byte like the host; its clock ticks at the rate the harness counts with; and
//! the core's square root there (libm's `sqrtf`, in software) is correctly
//! rounded (`tessera-sqrt`).
//!
//! The renders are small (48x36): software floating point takes some 25 to 45
//! times the Cortex-M4F's instructions per pixel (docs/chip-nofpu.md).
//!
//! These tests need `qemu-system-arm`, `qemu-system-riscv32` and the targets
//! `thumbv6m-none-eabi` and `riscv32imc-unknown-none-elf`; without them they fail
//! and say to run `bash tests/run-all.sh`, which installs them.

use crate::firmware::{assert_clock, differences};
use tessera_core::Sampler;
use tessera_core::builtin::Builtin;
use tessera_tests::firmware::{self, Core, Run, SceneRef, SqrtReport};

/// The renders checked on each core without an FPU: every built-in scene at its
/// own settings, chapter-reflect with stratified:2 (four rays a pixel) and the
/// baked teapot (its tables in flash), 48x36 in tiles of 16 (partial tiles at the
/// bottom edge).
fn nofpu_runs() -> Vec<Run> {
    let mut runs: Vec<Run> = Builtin::ALL.iter().map(|&b| Run::of(b, 48, 36)).collect();
    runs.push(Run {
        sampler: Sampler::Stratified(2),
        seed: 3,
        ..Run::of(Builtin::ChapterReflect, 48, 36)
    });
    runs.push(Run::of(SceneRef::Baked(Builtin::Teapot), 48, 36));
    runs
}

/// Builds the image for `core`, runs the renders and the square root's check, and
/// checks both against the host.
fn renders_like_the_host(core: &Core) {
    let fail = |e: String| -> ! { panic!("{}: {e}", core.title) };
    core.qemu_version().unwrap_or_else(|e| fail(e));
    let elf = core.build(&[]).unwrap_or_else(|e| fail(e));

    let runs = nofpu_runs();
    let out = core.run(&elf, &runs).unwrap_or_else(|e| fail(e));
    assert_clock(core, &out);
    // No F or D extension on the RISC-V CPU (qemu's `f=false,d=false` in force):
    // an F instruction would trap.
    if core.target.starts_with("riscv") {
        let misa = out
            .stdout
            .lines()
            .find_map(|l| l.strip_prefix("misa=0x"))
            .and_then(|v| u32::from_str_radix(v.trim(), 16).ok())
            .unwrap_or_else(|| fail(format!("no misa= line:\n{}", out.stdout)));
        let (f, d) = (1 << (b'F' - b'A'), 1 << (b'D' - b'A'));
        assert_eq!(misa & (f | d), 0, "{}: misa={misa:#x}", core.title);
    }
    let bad = differences(core.name, &runs, &out);
    assert!(
        bad.is_empty(),
        "{}: chip and host differ (images in target/test-images):\n{}",
        core.title,
        bad.join("\n")
    );

    let sqrt = firmware::check_sqrt(core, &elf).unwrap_or_else(|e| fail(e));
    assert_eq!(sqrt, SqrtReport::host(), "{}: sqrt", core.title);
}

#[test]
fn cortex_m0_renders_like_the_host() {
    renders_like_the_host(&firmware::CORTEX_M0_ON_M3);
}

#[test]
fn rv32imc_renders_like_the_host() {
    renders_like_the_host(&firmware::RV32IMC);
}
