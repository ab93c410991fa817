//! How deep the stack went. cortex-m-rt's feature `paint-stack` fills the stack,
//! from the top of RAM down to the end of the statics, with
//! `STACK_PAINT_VALUE` at reset; the lowest word that no longer holds it is the
//! deepest the stack reached.

use cortex_m_rt::STACK_PAINT_VALUE;

unsafe extern "C" {
    /// The top of the stack (cortex-m-rt's link.x: the end of RAM).
    static _stack_start: u32;
    /// The lowest address it may reach (the end of the statics).
    static _stack_end: u32;
}

/// Bytes between the end of the statics and the top of RAM.
pub fn available() -> usize {
    (&raw const _stack_start) as usize - (&raw const _stack_end) as usize
}

/// The most bytes of stack used since reset (all of it: [`available`], when the
/// stack reached the statics).
pub fn peak() -> usize {
    let top = (&raw const _stack_start) as usize;
    let mut p = (&raw const _stack_end) as usize;
    // SAFETY: [_stack_end, _stack_start) is RAM, word aligned (link.x checks).
    while p < top && unsafe { core::ptr::read_volatile(p as *const u32) } == STACK_PAINT_VALUE {
        p += 4;
    }
    top - p
}
