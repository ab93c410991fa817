//! Counting instructions with SysTick.
//!
//! qemu runs with `-icount shift=0` (.cargo/config.toml): one instruction takes 1
//! ns of virtual time, and SysTick, clocked by the board's 25 MHz processor clock,
//! counts down once every 40 instructions, however fast the host is. On a real
//! chip the same counter counts processor cycles.

use core::sync::atomic::{AtomicU32, Ordering};
use cortex_m::peripheral::SYST;
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_rt::exception;

/// Instructions a SysTick tick under qemu (1 ns an instruction, 25 MHz).
pub const INSTRUCTIONS_PER_TICK: u64 = 40;

/// The counter's 24 bits.
const RELOAD: u32 = 0x00FF_FFFF;

/// How many times the counter wrapped.
static WRAPS: AtomicU32 = AtomicU32::new(0);

#[exception]
fn SysTick() {
    WRAPS.fetch_add(1, Ordering::Relaxed);
}

/// Starts SysTick on the processor clock, an exception at each wrap.
pub fn start(mut syst: SYST) {
    syst.set_clock_source(SystClkSource::Core);
    syst.set_reload(RELOAD);
    syst.clear_current();
    syst.enable_interrupt();
    syst.enable_counter();
}

/// Ticks since [`start`]: the wraps and the position in the current period (the
/// wraps read on both sides of the counter, so that a wrap between the reads is
/// not half counted).
pub fn ticks() -> u64 {
    loop {
        let wraps = WRAPS.load(Ordering::SeqCst);
        let value = SYST::get_current();
        if WRAPS.load(Ordering::SeqCst) == wraps {
            let position = RELOAD.wrapping_add(1).wrapping_sub(value) & RELOAD;
            return (u64::from(wraps) << 24) | u64::from(position);
        }
    }
}
