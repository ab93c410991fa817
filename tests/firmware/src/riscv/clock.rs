//! Instruction counting on the rv32imafc core of qemu's `virt` board: the
//! `minstret` CSR (instructions retired, 64 bits as `minstreth:minstret`).
//!
//! With `-icount shift=0` qemu 7.2 returns its instruction count for `minstret`
//! (and for `mcycle`): one count per guest instruction, so a tick here is one
//! instruction (the calibration loop checks it). The `time` CSR, from the board's
//! 10 MHz timer, would tick once every 100 instructions.

use crate::protocol::{self, TickRate};
use riscv::register::minstret;

/// Guest instructions per tick: one (the harness checks it against the
/// calibration loop).
pub const RATE: TickRate = protocol::RISCV_VIRT;

/// Nothing to start: the counter runs from reset.
pub fn start() {}

/// Instructions retired since reset.
pub fn now() -> u64 {
    minstret::read64()
}

/// Runs a loop of exactly `2 * iterations` instructions (`addi` + `bnez`) and
/// returns the ticks it took, to check
/// [`RATE`].
pub fn calibrate(iterations: u32) -> u64 {
    let t0 = now();
    let mut n = iterations.max(1);
    // SAFETY: a register-only countdown loop; touches no memory and no stack.
    unsafe {
        core::arch::asm!(
            "2:",
            "addi {n}, {n}, -1",
            "bnez {n}, 2b",
            n = inout(reg) n,
            options(nomem, nostack),
        );
    }
    let _ = n;
    now() - t0
}
