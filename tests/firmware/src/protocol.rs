//! The protocol between the firmware test image and its host-side harness
//! (`tessera_tests::firmware`): one source for both. The firmware compiles it as
//! `mod protocol`; the harness, in the root workspace, includes this same file with
//! `#[path]`. Plain constants only, so that it builds in both (`no_std` and `std`).
//!
//! The qemu command line is the harness's (`tessera_tests::firmware::QEMU_ARGS`);
//! the runner line in the root `.cargo/config.toml` repeats it for `cargo run`, and a
//! test of the harness checks that the two agree.

/// The run list the firmware reads, in qemu's working directory.
pub const RUNS_FILE: &str = "tessera-fw.runs";

/// The largest run list the firmware reads, bytes.
pub const RUNS_MAX: usize = 4096;

/// Guest instructions per SysTick tick: with `-icount shift=0` one instruction is
/// 1 ns of virtual time, and SysTick, clocked from the 25 MHz processor clock, ticks
/// every 40 ns.
pub const INSTRUCTIONS_PER_TICK: u64 = 40;

// The frame file name's two parts, as literals so that `concat!` can join them.
macro_rules! frame_prefix {
    () => {
        "tessera-fw-"
    };
}
macro_rules! frame_suffix {
    () => {
        ".rgb"
    };
}

/// Run `i`'s frame is written to `{FRAME_PREFIX}{i}{FRAME_SUFFIX}`
/// (`tessera-fw-<i>.rgb`): the pixels in row-major image order, 3 bytes (R, G, B)
/// each, no header.
pub const FRAME_PREFIX: &str = frame_prefix!();

/// See [`FRAME_PREFIX`].
pub const FRAME_SUFFIX: &str = frame_suffix!();

/// The frame files' name in messages, built from the same two literals.
pub const FRAME_PATTERN: &str = concat!(frame_prefix!(), "<i>", frame_suffix!());
