//! The core on every core with an FPU beside the Cortex-M4F
//! (`tessera_tests::firmware::FPU_CORES`: Cortex-M7 on `mps2-an500`, Cortex-M33 on
//! `mps2-an505`, Cortex-M55 on `mps3-an547`, rv32imafc on `virt`): the firmware test
//! image, built once per core, renders what the Cortex-M4F's renders
//! (`firmware::identity_runs`: every built-in scene with four samplers, every tile
//! size, both encodings, the baked scenes, the extremes battery) byte for byte like
//! the host; its clock ticks at the rate the harness counts with; the guarded runs'
//! instruction counts stay within 2% of `tests/chip-baseline-cores.txt`; and the
//! core's square root is correctly rounded on the chip (`tessera-sqrt`), as on the
//! Cortex-M4F (`firmware::sqrt_is_correctly_rounded_on_the_chip`).
//!
//! These tests need `qemu-system-arm`, `qemu-system-riscv32` and the targets
//! `thumbv7em-none-eabihf`, `thumbv8m.main-none-eabihf` and
//! `riscv32imafc-unknown-none-elf`; without them they fail and say to run `bash
//! tests/run-all.sh`, which installs them.

use crate::firmware::{assert_clock, differences, identity_runs};
use tessera_tests::baseline;
use tessera_tests::firmware::{self, Core, SqrtReport};

/// Builds the image for `core`, runs the renders (and the guarded ones) and the
/// square root's check, and checks them against the host and the baseline.
fn renders_like_the_host(core: &Core) {
    let fail = |e: String| -> ! { panic!("{}: {e}", core.title) };
    let qemu = core.qemu_version().unwrap_or_else(|e| fail(e));
    let elf = core.build(&[]).unwrap_or_else(|e| fail(e));

    let mut runs = identity_runs();
    let identity = runs.len();
    runs.extend(baseline::runs());
    let out = core.run(&elf, &runs).unwrap_or_else(|e| fail(e));
    assert_clock(core, &out);
    let bad = differences(core.name, &runs[..identity], &out);
    assert!(
        bad.is_empty(),
        "{}: chip and host differ (images in target/test-images):\n{}",
        core.title,
        bad.join("\n")
    );

    let path = baseline::cores_path();
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    baseline::same_qemu(baseline::CORES_FILE, &text, &qemu).unwrap_or_else(|e| fail(e));
    let base = baseline::parse(&text).unwrap_or_else(|e| panic!("{e}"));
    let now: Vec<(String, u64)> = runs[identity..]
        .iter()
        .zip(&out.runs[identity..])
        .map(|(r, res)| (baseline::key(core, r), res.instructions))
        .collect();
    let cmp = baseline::Comparison::new(&base, &now);
    let table = cmp.table();
    println!(
        "{}: instruction counts against {}:\n{table}",
        core.title,
        baseline::CORES_FILE
    );
    assert!(
        cmp.failures().is_empty(),
        "{}: instruction counts rose over {}:\n{table}",
        core.title,
        baseline::CORES_FILE
    );

    let sqrt = firmware::check_sqrt(core, &elf).unwrap_or_else(|e| fail(e));
    assert_eq!(sqrt, SqrtReport::host(), "{}: sqrt", core.title);
}

#[test]
fn cortex_m7_renders_like_the_host() {
    renders_like_the_host(&firmware::CORTEX_M7);
}

#[test]
fn cortex_m33_renders_like_the_host() {
    renders_like_the_host(&firmware::CORTEX_M33);
}

#[test]
fn cortex_m55_renders_like_the_host() {
    renders_like_the_host(&firmware::CORTEX_M55);
}

#[test]
fn rv32imafc_renders_like_the_host() {
    renders_like_the_host(&firmware::RV32IMAFC);
}
