//! The fault and panic handlers of the firmware images (`tessera-fw`,
//! `tessera-teapot`, `tessera-sqrt` and, for its CPU 0, `tests/dualcore` include
//! this file): each reports over semihosting (a `hard fault` or `panic` line) and
//! exits qemu with a failure, which the host-side harness turns into an error.

use cortex_m_rt::{ExceptionFrame, exception};
use cortex_m_semihosting::debug::{self, EXIT_FAILURE};
use cortex_m_semihosting::{heprintln, hprintln};

#[exception]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    hprintln!("hard fault: {:?}", frame);
    debug::exit(EXIT_FAILURE);
    loop {
        cortex_m::asm::bkpt();
    }
}

#[exception]
unsafe fn DefaultHandler(irq: i16) {
    hprintln!("hard fault: unexpected exception {}", irq);
    debug::exit(EXIT_FAILURE);
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
    cortex_m::interrupt::disable();
    hprintln!("panic: {}", info);
    heprintln!("panic: {}", info);
    debug::exit(EXIT_FAILURE);
    loop {
        cortex_m::asm::bkpt();
    }
}
