//! The trap and panic handlers of the firmware images on RISC-V (`tessera-fw` and
//! `tessera-teapot` include this file): each reports over semihosting and exits
//! qemu with a failure, which the host-side harness turns into an error. Without
//! them riscv-rt's default handler would loop (an instruction the core lacks, say,
//! would hang the run until the harness's timeout).

use riscv::register::{mcause, mepc, mtval};
use riscv_semihosting::debug::{self, EXIT_FAILURE};
use riscv_semihosting::{heprintln, hprintln};

/// Every exception (riscv-rt's default for each one it does not find by name).
#[unsafe(export_name = "ExceptionHandler")]
fn exception_handler(frame: &riscv_rt::TrapFrame) -> ! {
    hprintln!(
        "hard fault: mcause={:#x} mepc={:#x} mtval={:#x} {:?}",
        mcause::read().bits(),
        mepc::read(),
        mtval::read(),
        frame
    );
    debug::exit(EXIT_FAILURE);
    loop {
        riscv::asm::wfi();
    }
}

/// Every interrupt (the firmware enables none).
#[unsafe(export_name = "DefaultHandler")]
fn default_handler() {
    hprintln!("unexpected interrupt mcause={:#x}", mcause::read().bits());
    debug::exit(EXIT_FAILURE);
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
    riscv::interrupt::disable();
    hprintln!("panic: {}", info);
    heprintln!("panic: {}", info);
    debug::exit(EXIT_FAILURE);
    loop {
        riscv::asm::wfi();
    }
}
