//! The firmware's log: defmt over RTT with the feature `defmt` (on by default),
//! nothing without it (each function below is then empty and its calls leave
//! nothing in the image, nor does the clock that times the picture).
//!
//! Messages of level `info` and above are compiled in: `build.rs` sets
//! `DEFMT_LOG=info` for this crate unless the environment sets `DEFMT_LOG`.
//! With the feature, panic-probe's panic handler prints a panic's message here.

use crate::Failure;
use cortex_m::peripheral::{DCB, DWT};
use tessera_core::Renderer;

#[cfg(feature = "defmt")]
use defmt_rtt as _;
#[cfg(feature = "defmt")]
use panic_probe as _;

/// A value the log shows: `defmt::Format` with the feature `defmt`, any type
/// without it.
#[cfg(feature = "defmt")]
pub trait Value: defmt::Format {}
#[cfg(feature = "defmt")]
impl<T: defmt::Format + ?Sized> Value for T {}
/// A value the log shows: `defmt::Format` with the feature `defmt`, any type
/// without it.
#[cfg(not(feature = "defmt"))]
pub trait Value {}
#[cfg(not(feature = "defmt"))]
impl<T: ?Sized> Value for T {}

/// Starts the core's cycle counter (DWT CYCCNT, enabled through DCB's trace
/// enable), which times the picture. Without the feature, leaves it off.
#[cfg_attr(not(feature = "defmt"), allow(unused_variables))]
pub fn start_clock(dcb: &mut DCB, dwt: &mut DWT) {
    #[cfg(feature = "defmt")]
    {
        dcb.enable_trace();
        dwt.enable_cycle_counter();
    }
}

/// The cycle counter (0 without the feature): it wraps after 2^32 cycles,
/// 42.9 s at 100 MHz.
pub fn now() -> u32 {
    #[cfg(feature = "defmt")]
    {
        DWT::cycle_count()
    }
    #[cfg(not(feature = "defmt"))]
    {
        0
    }
}

/// Logs what is about to be drawn: the scene file's name (as `TESSERA_SCENE`
/// gave it), the frame's and the tiles' sizes,
/// the preview's block, the settings (`RenderSettings`' `defmt::Format`).
#[cfg_attr(not(feature = "defmt"), allow(unused_variables))]
pub fn drawing(renderer: &Renderer, tile: usize, block: u32) {
    #[cfg(feature = "defmt")]
    defmt::info!(
        "blackpill-st7789: {=str} at {=u16}x{=u16}, {=usize}x{=usize} tiles after a preview of {=u32}x{=u32} blocks, {=u32} MHz; {}",
        env!("TESSERA_SCENE_NAME"),
        crate::PICTURE.0,
        crate::PICTURE.1,
        tile,
        tile,
        block,
        block,
        crate::SYSCLK_MHZ,
        renderer.settings()
    );
}

/// Logs the scene file's name and the time from `started` ([`now`]) to now: the
/// whole picture, preview, tiles and their SPI transfers.
#[cfg_attr(not(feature = "defmt"), allow(unused_variables))]
pub fn drawn(started: u32) {
    #[cfg(feature = "defmt")]
    {
        let cycles = now().wrapping_sub(started);
        defmt::info!(
            "{=str} drawn in {=u32} ms ({=u32} cycles)",
            env!("TESSERA_SCENE_NAME"),
            cycles / (crate::SYSCLK_MHZ * 1000),
            cycles
        );
    }
}

/// Logs the panel's error `e` as the cause of `failure`, and returns `failure`.
#[cfg_attr(not(feature = "defmt"), allow(unused_variables))]
pub fn panel_error<E: Value>(failure: Failure, e: &E) -> Failure {
    #[cfg(feature = "defmt")]
    defmt::error!("{}: {}", failure, e);
    failure
}

/// Logs the failure that stops the firmware and the LED's code for it.
#[cfg_attr(not(feature = "defmt"), allow(unused_variables))]
pub fn failed(failure: &Failure) {
    #[cfg(feature = "defmt")]
    defmt::error!(
        "stopped: {}; the LED blinks it {=u32} times",
        failure,
        failure.blinks()
    );
}
