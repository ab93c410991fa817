//! Peak stack use: paint the free stack with a pattern, run, find the lowest word
//! that changed.
//!
//! cortex-m-rt puts the stack at the top of RAM (`_stack_start`) growing down to
//! `_stack_end`, the end of `.bss`/`.uninit` (nothing else lives there: no heap).
//! riscv-rt does the same; memory-riscv-virt.x gives its symbols cortex-m-rt's names.

const PATTERN: u32 = 0xDEAD_C0DE;

unsafe extern "C" {
    static _stack_start: u32;
    static _stack_end: u32;
    static _ram_start: u32;
    static _ram_end: u32;
}

/// Bytes of RAM (memory.x's RAM region, from cortex-m-rt's symbols).
pub fn ram() -> usize {
    (&raw const _ram_end) as usize - (&raw const _ram_start) as usize
}

/// The top of the stack (initial SP).
pub fn top() -> usize {
    (&raw const _stack_start) as usize
}

/// The lowest address the stack may reach.
pub fn limit() -> usize {
    (&raw const _stack_end) as usize
}

/// The current stack pointer.
#[cfg(target_arch = "arm")]
#[inline(always)]
pub fn sp() -> usize {
    cortex_m::register::msp::read() as usize
}

/// The current stack pointer.
#[cfg(target_arch = "riscv32")]
#[inline(always)]
pub fn sp() -> usize {
    let sp: usize;
    // SAFETY: copies the stack pointer into a register; touches no memory.
    unsafe { core::arch::asm!("mv {}, sp", out(reg) sp, options(nomem, nostack, preserves_flags)) };
    sp
}

/// Bytes of stack in use now (top minus the current SP).
#[inline(always)]
pub fn in_use() -> usize {
    top() - sp()
}

/// Paints every word between [`limit`] and a little below the current SP.
#[inline(never)]
pub fn paint() {
    let sp = sp();
    // Leave the words this function may still use (it calls nothing).
    let end = sp.saturating_sub(64) & !3;
    let mut p = limit();
    while p < end {
        // SAFETY: [limit, SP - 64) is RAM that no live frame or static uses: the
        // stack grows down from SP and the statics end at `_stack_end`.
        unsafe { core::ptr::write_volatile(p as *mut u32, PATTERN) };
        p += 4;
    }
}

/// The lowest stack address written since the last [`paint`]: the lowest word that
/// no longer holds the pattern. Returns `None` when even the lowest word was
/// overwritten (the stack reached the statics).
pub fn lowest() -> Option<usize> {
    let mut p = limit();
    let top = top();
    while p < top {
        // SAFETY: [limit, top) is RAM, word aligned (checked by cortex-m-rt's link.x).
        if unsafe { core::ptr::read_volatile(p as *const u32) } != PATTERN {
            break;
        }
        p += 4;
    }
    if p == limit() { None } else { Some(p) }
}
