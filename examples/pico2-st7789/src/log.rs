//! The firmware's log: defmt over RTT with the feature `defmt` (on by default),
//! nothing without it (each function below is then empty and its calls leave
//! nothing in the image).
//!
//! Both cores log: defmt-rtt takes the `critical-section` lock, which rp235x-hal
//! implements with a hardware spinlock shared by the cores. Messages of level
//! `info` and above are compiled in: `build.rs` sets `DEFMT_LOG=info` for this
//! crate unless the environment sets `DEFMT_LOG`. With the feature, panic-probe's
//! panic handler prints a panic's message here.

use crate::Failure;
use tessera_core::TileCoord;

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

/// Logs what the firmware animates: the scene file, the frame's and the tiles'
/// sizes, the instances, the frames of a pass through the animation and its
/// frames a second, the settings (`RenderSettings`' `defmt::Format`) and how
/// many cores render.
#[cfg_attr(not(feature = "defmt"), allow(unused_variables))]
pub fn started(two_cores: bool, frames_per_loop: u32) {
    #[cfg(feature = "defmt")]
    defmt::info!(
        "pico2-st7789: {=str} at {=u16}x{=u16} in {=usize}x{=usize} tiles, {=usize} instance(s), {=u32} frames a loop at {=f32} frames a second, on {=u8} core(s), fps label {=bool}; {}",
        env!("TESSERA_SCENE_NAME"),
        crate::PICTURE.0,
        crate::PICTURE.1,
        crate::TILE,
        crate::TILE,
        crate::INSTANCE_COUNT,
        frames_per_loop,
        crate::scene::FPS,
        if two_cores { 2 } else { 1 },
        cfg!(feature = "fps-label"),
        crate::scene::SCENE.settings()
    );
}

/// Logs frame `frame`'s time, `period_us` (from its start to the next frame's),
/// its rate, and how many of its `tiles` core 0 rendered (core 1 the others).
#[cfg_attr(not(feature = "defmt"), allow(unused_variables))]
pub fn frame(frame: u32, period_us: u64, core0_tiles: u32, tiles: u32) {
    #[cfg(feature = "defmt")]
    defmt::info!(
        "frame {=u32}: {=u64} us, {=f32} fps; core 0 rendered {=u32} of {=u32} tiles",
        frame,
        period_us,
        1e6 / period_us.max(1) as f32,
        core0_tiles,
        tiles
    );
}

/// Logs core 1's failure to start (rp235x-hal's error): core 0 renders alone.
#[cfg_attr(not(feature = "defmt"), allow(unused_variables))]
pub fn core1_not_started<E: Value>(e: &E) {
    #[cfg(feature = "defmt")]
    defmt::warn!("core 1 did not start ({}): core 0 renders alone", e);
}

/// Logs tessera's refusal of tile `coord` on core `core` (not expected: the
/// loops are checked once a frame); the tile is not sent.
#[cfg_attr(not(feature = "defmt"), allow(unused_variables))]
pub fn tile_failed(core: u8, coord: TileCoord, e: tessera_core::Error) {
    #[cfg(feature = "defmt")]
    defmt::error!("core {=u8}: tile {}: {}", core, coord, e);
}

/// Logs the failure of the clocks' set-up (rp235x-hal's error): the firmware
/// halts before it has an LED.
#[cfg_attr(not(feature = "defmt"), allow(unused_variables))]
pub fn clocks_failed<E: Value>(e: &E) {
    #[cfg(feature = "defmt")]
    defmt::error!("clock set-up failed: {}", e);
}

/// Logs the failure that stops the animation and the LED's code for it.
#[cfg_attr(not(feature = "defmt"), allow(unused_variables))]
pub fn failed(failure: &Failure) {
    #[cfg(feature = "defmt")]
    defmt::error!(
        "stopped: {}; the LED blinks it {=u32} times",
        failure,
        failure.blinks()
    );
}
