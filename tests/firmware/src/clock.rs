//! Instruction counting with SysTick.
//!
//! qemu runs with `-icount shift=0`: one guest instruction advances virtual time by
//! 1 ns. SysTick, clocked from the processor clock, then decrements at a fixed
//! rate in instructions, whatever the host does: once every 40 on mps2-an386
//! (25 MHz), and [`RATE`] on each board. The counter is 24 bits; the SysTick
//! exception counts its wraps, so [`now`] is a 64-bit tick count.

use core::sync::atomic::{AtomicU32, Ordering};
use cortex_m::peripheral::SYST;
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_rt::exception;

use crate::protocol::{self, TickRate};

const RELOAD: u32 = 0x00FF_FFFF;

/// Guest instructions per tick on this board (build.rs sets `board`; the harness
/// checks the rate against the calibration loop).
#[cfg(board = "mps2-an386")]
pub const RATE: TickRate = protocol::MPS2_AN386;
/// See above.
#[cfg(board = "mps2-an385")]
pub const RATE: TickRate = protocol::MPS2_AN385;
/// See above.
#[cfg(board = "mps2-an500")]
pub const RATE: TickRate = protocol::MPS2_AN500;
/// See above.
#[cfg(board = "mps2-an505")]
pub const RATE: TickRate = protocol::MPS2_AN505;
/// See above.
#[cfg(board = "mps3-an547")]
pub const RATE: TickRate = protocol::MPS3_AN547;

static WRAPS: AtomicU32 = AtomicU32::new(0);

#[exception]
fn SysTick() {
    // Armv6-M has no read-modify-write atomics; this handler is the only writer, so
    // a load and a store count the same there.
    #[cfg(target_has_atomic = "32")]
    WRAPS.fetch_add(1, Ordering::Relaxed);
    #[cfg(not(target_has_atomic = "32"))]
    WRAPS.store(
        WRAPS.load(Ordering::Relaxed).wrapping_add(1),
        Ordering::Relaxed,
    );
}

/// Starts SysTick: processor clock, reload 2^24 - 1, exception on each wrap.
pub fn start(mut syst: SYST) {
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(RELOAD);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
}

/// Ticks since [`start`].
///
/// The counter goes `RELOAD, ..., 1, 0, RELOAD, ...` and the exception fires as it
/// reaches 0, so `(RELOAD + 1 - value) mod 2^24` is the position in the current
/// period (0 when the wrap was just counted). The wrap count is read on both sides
/// of the counter so that a wrap between the two reads is never half-counted.
pub fn now() -> u64 {
    loop {
        let w = WRAPS.load(Ordering::SeqCst);
        let v = SYST::get_current();
        if WRAPS.load(Ordering::SeqCst) == w {
            let pos = RELOAD.wrapping_add(1).wrapping_sub(v) & RELOAD;
            return (u64::from(w) << 24) | u64::from(pos);
        }
    }
}

/// Runs a loop of exactly `2 * iterations` instructions (`subs` + `bne`) and
/// returns the ticks it took, to check
/// [`RATE`].
pub fn calibrate(iterations: u32) -> u64 {
    let t0 = now();
    let mut n = iterations.max(1);
    // SAFETY: a register-only countdown loop; touches no memory and no stack.
    unsafe {
        core::arch::asm!(
            "2:",
            "subs {n}, {n}, #1",
            "bne 2b",
            n = inout(reg) n,
            options(nomem, nostack),
        );
    }
    let _ = n;
    now() - t0
}
