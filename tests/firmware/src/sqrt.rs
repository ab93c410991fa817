//! A firmware that checks the core's square root on the chip: `tessera`'s
//! `math::sqrt` (through `tessera_core::testing::sqrt`: `vsqrt.f32` on an Arm FPU,
//! `fsqrt.s` on RISC-V with F) for every input of [`sqrt_check::inputs`] (hard
//! cases, special values, pseudo-random floats), each result tested exactly by
//! [`sqrt_check::correctly_rounded`]. It prints
//!
//! `sqrt cases=<n> wrong=<k> hash=<fnv-1a of the results' bits>`
//!
//! and a line `sqrt wrong x=<bits> got=<bits>` for each of the first wrong results;
//! the harness checks `wrong=0` and compares the hash with the host's.
#![no_std]
#![no_main]

// The fault and panic handlers.
#[cfg_attr(target_arch = "arm", path = "faults.rs")]
#[cfg_attr(target_arch = "riscv32", path = "riscv/faults.rs")]
mod faults;

mod sqrt_check;

#[cfg(target_arch = "arm")]
use cortex_m_rt::entry;
#[cfg(target_arch = "arm")]
use cortex_m_semihosting::{
    debug::{self, EXIT_SUCCESS},
    hprintln,
};
#[cfg(target_arch = "riscv32")]
use riscv_rt::entry;
#[cfg(target_arch = "riscv32")]
use riscv_semihosting::{
    debug::{self, EXIT_SUCCESS},
    hprintln,
};

/// The wrong results printed, at most.
const SHOWN: u32 = 8;

#[entry]
fn main() -> ! {
    let (mut cases, mut wrong) = (0u32, 0u32);
    let results = sqrt_check::inputs().map(|x| {
        // Opaque to the compiler: the root is computed on the chip.
        let r = tessera_core::testing::sqrt(core::hint::black_box(x));
        cases += 1;
        if !sqrt_check::correctly_rounded(x, r) {
            if wrong < SHOWN {
                hprintln!(
                    "sqrt wrong x={:#010x} got={:#010x}",
                    x.to_bits(),
                    r.to_bits()
                );
            }
            wrong += 1;
        }
        r
    });
    let hash = sqrt_check::hash(results);
    hprintln!("sqrt cases={} wrong={} hash={:08x}", cases, wrong, hash);
    debug::exit(EXIT_SUCCESS);
    loop {
        #[cfg(target_arch = "arm")]
        cortex_m::asm::bkpt();
        #[cfg(target_arch = "riscv32")]
        riscv::asm::wfi();
    }
}
