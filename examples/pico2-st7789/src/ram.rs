//! tessera's code in SRAM: the copy at start-up of the section `.ram_text`
//! (`ram.x`, which build.rs appends to memory.x unless the feature
//! `flash-only` is on).
//!
//! From flash, the renderer runs through the RP2350's 16 KiB XIP cache, which
//! its hot code does not fit: the memory model (`tests/src/memory/`, its
//! figures in docs/chip-cost.md, "Frames per second with the memory model")
//! estimates a miss at 114 cycles (QSPI at 50 MHz, as the bootrom sets it up)
//! and the teapot's frame at almost three times its zero-wait cycles. From
//! SRAM, which has no wait state, what is left is the read-only data's misses
//! (the scene's tables stay in flash).
//!
//! cortex-m-rt's reset handler calls `__pre_init` first, before it initialises
//! `.data` and `.bss`: nothing here may touch a static, so it is assembly.
//! The copy is word by word (the section starts and ends 4-byte aligned); the
//! barriers make the core fetch the copied code, not what it held before.

core::arch::global_asm!(
    ".pushsection .text.__pre_init,\"ax\",%progbits",
    ".global __pre_init",
    ".type __pre_init,%function",
    ".thumb_func",
    "__pre_init:",
    "    ldr r0, =__sram_text",
    "    ldr r1, =__eram_text",
    "    ldr r2, =__siram_text",
    "1:  cmp r0, r1",
    "    bhs 2f",
    "    ldr r3, [r2], #4",
    "    str r3, [r0], #4",
    "    b 1b",
    "2:  dsb",
    "    isb",
    "    bx lr",
    ".ltorg",
    ".size __pre_init, . - __pre_init",
    ".popsection",
);
