//! The protocol between the firmware test image and its host-side harness
//! (`tessera_tests::firmware`): one source for both. The firmware compiles it as
//! `mod protocol`; the harness, in the root workspace, includes this same file with
//! `#[path]`. Plain constants (and one `const fn`), so that it builds in both
//! (`no_std` and `std`).
//!
//! The qemu command lines are the harness's (`tessera_tests::firmware::Core`); the
//! runner line in the root `.cargo/config.toml` repeats the Cortex-M4F's for `cargo
//! run`, and a test of the harness checks that the two agree.

/// The run list the firmware reads, in qemu's working directory.
pub const RUNS_FILE: &str = "tessera-fw.runs";

/// The largest run list the firmware reads, bytes.
pub const RUNS_MAX: usize = 4096;

/// Guest instructions per SysTick tick on the Cortex-M4F's board (`mps2-an386`):
/// with `-icount shift=0` one instruction is 1 ns of virtual time, and SysTick,
/// clocked from the 25 MHz processor clock, ticks every 40 ns.
pub const INSTRUCTIONS_PER_TICK: u64 = 40;

/// How many guest instructions a tick of the firmware's clock is on a board:
/// `instructions` every `ticks` ticks (a fraction: on `mps3-an547` a tick is 31.25
/// instructions).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TickRate {
    /// Instructions ...
    pub instructions: u64,
    /// ... every this many ticks.
    pub ticks: u64,
}

impl TickRate {
    /// `ticks` ticks in instructions, rounded down.
    #[must_use]
    pub const fn instructions(self, ticks: u64) -> u64 {
        ticks * self.instructions / self.ticks
    }
}

/// `mps2-an386` (Cortex-M4F): SysTick at 25 MHz, 40 instructions a tick.
pub const MPS2_AN386: TickRate = TickRate {
    instructions: INSTRUCTIONS_PER_TICK,
    ticks: 1,
};

/// `mps2-an385` (the Cortex-M3 that runs the Armv6-M image): SysTick at 25 MHz, 40
/// instructions a tick.
pub const MPS2_AN385: TickRate = TickRate {
    instructions: 40,
    ticks: 1,
};

/// `mps2-an500` (Cortex-M7): SysTick at 25 MHz, 40 instructions a tick.
pub const MPS2_AN500: TickRate = TickRate {
    instructions: 40,
    ticks: 1,
};

/// `mps2-an505` (Cortex-M33): SysTick at 20 MHz, 50 instructions a tick.
pub const MPS2_AN505: TickRate = TickRate {
    instructions: 50,
    ticks: 1,
};

/// `mps3-an547` (Cortex-M55): SysTick at 32 MHz, 125 instructions every 4 ticks.
pub const MPS3_AN547: TickRate = TickRate {
    instructions: 125,
    ticks: 4,
};

/// `virt` (rv32imafc): the `minstret` CSR, which qemu advances by one a guest
/// instruction under `-icount`.
pub const RISCV_VIRT: TickRate = TickRate {
    instructions: 1,
    ticks: 1,
};

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
