//! Both cores of qemu's `mps2-an521` (SSE-200: two Cortex-M33, CPU 0 given its FPU
//! as on an RP2350) render each built-in scene, sharing the tiles through one
//! queue: the pixels are the host's, byte for byte (and so those of CPU 0 alone),
//! both CPUs render tiles, qemu shares the time evenly between them, and each
//! CPU's instructions are counted (the plugin `tests/profiler/vcpu_count.c`): the
//! speed-up is one CPU's instructions for the frame over the busier CPU's with two.
//!
//! These tests need `qemu-system-arm`, gcc and the `thumbv8m.main-none-eabihf`
//! target; without them they fail and say to run `bash tests/run-all.sh`.

use std::sync::OnceLock;
use tessera_core::builtin::Builtin;
use tessera_tests::dualcore::{self, Output};
use tessera_tests::firmware;

/// The firmware and the plugin, built once for this binary.
fn built() -> (std::path::PathBuf, std::path::PathBuf) {
    static BUILT: OnceLock<Result<(std::path::PathBuf, std::path::PathBuf), String>> =
        OnceLock::new();
    BUILT
        .get_or_init(|| {
            firmware::qemu_version()?;
            Ok((dualcore::build()?, dualcore::build_plugin()?))
        })
        .clone()
        .unwrap_or_else(|e| panic!("{e}"))
}

fn run() -> Output {
    let (elf, plugin) = built();
    dualcore::run(&elf, &plugin).unwrap_or_else(|e| panic!("{e}"))
}

/// One run, shared by the tests that read it.
fn output() -> &'static Output {
    static OUT: OnceLock<Output> = OnceLock::new();
    OUT.get_or_init(run)
}

/// The host build of the core ([`dualcore::host`]).
fn host(b: Builtin) -> image::RgbImage {
    dualcore::host(b).unwrap()
}

#[test]
fn both_cores_render_the_host_pixels_byte_for_byte() {
    let out = output();
    let mut bad = Vec::new();
    for f in &out.frames {
        let want = host(f.scene);
        if want.as_raw() != f.pixels.as_raw() {
            let differ = want
                .pixels()
                .zip(f.pixels.pixels())
                .filter(|(a, b)| a != b)
                .count();
            let dir = tessera_tests::output_dir();
            let name = format!("dualcore-{}-{}", f.scene.name(), f.cores);
            let _ = f.pixels.save(dir.join(format!("{name}-chip.png")));
            let _ = want.save(dir.join(format!("{name}-host.png")));
            bad.push(format!("{name}: {differ} pixels differ"));
        }
        if f.cores == 2 && f.tiles.contains(&0) {
            bad.push(format!(
                "{} on two cores: CPU 0 rendered {} tiles, CPU 1 {}",
                f.scene.name(),
                f.tiles[0],
                f.tiles[1]
            ));
        }
    }
    // Every built-in scene, on one core and on two.
    for &b in Builtin::ALL {
        for cores in [1, 2] {
            let n = out
                .frames
                .iter()
                .filter(|f| f.scene == b && f.cores == cores)
                .count();
            if n != 1 {
                bad.push(format!("{} on {cores} cores: {n} frames", b.name()));
            }
        }
    }
    assert!(
        bad.is_empty(),
        "(images in target/test-images)\n{}\n{}",
        bad.join("\n"),
        out.stdout
    );
}

/// The table of instructions and speed-ups (printed: `cargo test -p tessera-tests
/// --test tests dualcore -- --nocapture`). The speed-up is a measurement; only a
/// floor is checked. What must hold: both CPUs counted, the work of two CPUs that
/// of one plus the queue's few extra calls, and qemu alternating the two CPUs
/// evenly while both render (so that instruction counts stand for time).
#[test]
fn each_core_is_counted_and_two_cores_share_the_frame() {
    let out = output();
    let table = dualcore::table(&out.counts);
    println!(
        "{table}\nquantum {} instructions; CPU 1's stack {} bytes",
        out.quantum, out.core1_stack
    );
    assert_eq!(out.counts.len(), Builtin::ALL.len(), "{table}");
    for c in &out.counts {
        let name = c.scene.name();
        let [d0, d1] = c.dual;
        assert!(
            d0.insns > 0 && d1.insns > 0,
            "{name}: a CPU counted nothing\n{table}"
        );
        // The two CPUs did the one CPU's work: the same tiles, plus one call of the
        // queue each that finds it empty (tens of instructions).
        let both = d0.insns + d1.insns;
        assert!(
            both >= c.one_core && both - c.one_core < 1_000,
            "{name}: {both} instructions on two CPUs, {} on one\n{table}",
            c.one_core
        );
        // While both rendered, qemu gave them the same time, to within two quanta.
        assert!(
            d0.shared.abs_diff(d1.shared) <= 2 * out.quantum,
            "{name}: CPU 0 ran {} instructions while CPU 1 ran {} side by side\n{table}\n{}",
            d0.shared,
            d1.shared,
            out.profile
        );
        assert!(
            c.speedup() > 1.5,
            "{name}: speed-up {:.3}\n{table}",
            c.speedup()
        );
    }
}

/// Under `-icount` qemu runs both vCPUs on one thread, in turns set by the virtual
/// clock alone: a second run renders the same tiles on the same CPUs with the same
/// counts.
#[test]
fn dual_core_counts_repeat_exactly() {
    let (a, b) = (output(), run());
    assert_eq!(a.profile, b.profile);
    assert_eq!(a.stdout, b.stdout);
}
