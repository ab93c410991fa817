//! The two profiling markers of the firmware images (`tessera-fw` and
//! `tests/dualcore` include this file): empty functions whose first instruction
//! the host's qemu plugins look up by name.

/// Profiling marker: called just before the code to count (each `render_tile` in
/// `tessera-fw`, each CPU's tile loop in `tests/dualcore`). It does nothing; the
/// qemu plugins (`tests/profiler/insn_profile.c`, used by `chip-profile`, and
/// `vcpu_count.c`, per vCPU) start counting when its first instruction executes. The host
/// finds it by name in the ELF's symbol table. Its body is an empty `asm!` (no
/// instruction: the function is a lone `bx lr`, `ret` on RISC-V), which the
/// compiler must assume has effects, so the call is kept; the comment in it
/// differs between the two markers so that they are not merged into one address.
#[inline(never)]
#[unsafe(no_mangle)]
pub extern "C" fn tessera_profile_begin() {
    // SAFETY: an assembler comment, no instruction: touches no register or memory.
    #[cfg(target_arch = "arm")]
    unsafe {
        core::arch::asm!(
            "@ tessera_profile_begin",
            options(nomem, nostack, preserves_flags)
        )
    }
    // SAFETY: as above.
    #[cfg(target_arch = "riscv32")]
    unsafe {
        core::arch::asm!(
            "# tessera_profile_begin",
            options(nomem, nostack, preserves_flags)
        )
    }
}

/// Profiling marker: called just after the code to count (see
/// [`tessera_profile_begin`]); the plugins stop counting when it executes.
#[inline(never)]
#[unsafe(no_mangle)]
pub extern "C" fn tessera_profile_end() {
    // SAFETY: an assembler comment, no instruction: touches no register or memory.
    #[cfg(target_arch = "arm")]
    unsafe {
        core::arch::asm!(
            "@ tessera_profile_end",
            options(nomem, nostack, preserves_flags)
        )
    }
    // SAFETY: as above.
    #[cfg(target_arch = "riscv32")]
    unsafe {
        core::arch::asm!(
            "# tessera_profile_end",
            options(nomem, nostack, preserves_flags)
        )
    }
}
