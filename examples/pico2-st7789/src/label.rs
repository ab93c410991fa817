//! The frame-rate label: "FPS 5.2", the rate of the frame before, in white on a
//! black box at the frame's top left corner, drawn with embedded-graphics over
//! each tile it crosses after the tile is rendered and before it is sent (a
//! rendered `Tile<N, Rgb565Wire>` is a `DrawTarget` of `Rgb565` in frame
//! coordinates, clipped to the tile: tessera's `DrawPixel`).
//!
//! Core 0 makes the frame's [`Label`] once, before its tiles, and hands it to
//! core 1 with the frame's renderer (`crate::FrameJob`): every tile of a frame
//! shows the same text. Without the feature `fps-label`, [`Label`] is empty and
//! draws nothing.

use crate::TILE;
use tessera_core::Tile;
use tessera_core::display::Rgb565Wire;

#[cfg(feature = "fps-label")]
use core::fmt::Write;
#[cfg(feature = "fps-label")]
use embedded_graphics::{
    mono_font::{MonoTextStyle, ascii::FONT_6X10},
    pixelcolor::Rgb565,
    prelude::*,
    primitives::PrimitiveStyle,
    text::{Baseline, Text},
};

/// The longest text: "FPS " and a rate of up to 7 digits, a point, a digit.
#[cfg(feature = "fps-label")]
const CAPACITY: usize = 16;
/// Where the text starts in the frame (its top left corner).
#[cfg(feature = "fps-label")]
const AT: Point = Point::new(4, 4);
/// The black box's margin around the text, in pixels.
#[cfg(feature = "fps-label")]
const MARGIN: u32 = 2;

/// The frame-rate text of one frame: plain `Copy` bytes (so that it travels to
/// core 1 with the renderer in a `Cell`), made once a frame.
#[cfg(feature = "fps-label")]
#[derive(Clone, Copy)]
pub struct Label {
    bytes: [u8; CAPACITY],
    len: u8,
}

#[cfg(feature = "fps-label")]
impl Label {
    /// The label for a frame after one that took `period_us` microseconds
    /// (`None` for the first frame: "FPS -"): the rate to one decimal, rounded,
    /// written with `core::fmt::Write` into a `heapless::String`, in integers
    /// (no float formatting code in the image).
    pub fn new(period_us: Option<u64>) -> Self {
        let mut text = heapless::String::<CAPACITY>::new();
        // A full string only cuts the text short: never reached at these lengths.
        let _ = match period_us {
            Some(us) if us > 0 => {
                let us = u32::try_from(us).unwrap_or(u32::MAX);
                // Tenths of a frame a second, rounded: 10^7 / us.
                let tenths = (10_000_000 + us / 2) / us;
                write!(text, "FPS {}.{}", tenths / 10, tenths % 10)
            }
            _ => text.push_str("FPS -").map_err(|_| core::fmt::Error),
        };
        let mut bytes = [0; CAPACITY];
        for (to, from) in bytes.iter_mut().zip(text.as_bytes()) {
            *to = *from;
        }
        Self {
            bytes,
            // At most CAPACITY, 16.
            len: text.len().min(CAPACITY) as u8,
        }
    }

    /// The text.
    pub fn as_str(&self) -> &str {
        let bytes = self.bytes.get(..usize::from(self.len)).unwrap_or(&[]);
        core::str::from_utf8(bytes).unwrap_or("")
    }

    /// Draws the label over `tile` where the two overlap (a tile away from the
    /// label is left alone, without going through its pixels).
    pub fn draw(&self, tile: &mut Tile<TILE, Rgb565Wire>) {
        let style = MonoTextStyle::new(&FONT_6X10, Rgb565::WHITE);
        let text = Text::with_baseline(self.as_str(), AT, style, Baseline::Top);
        let area = text.bounding_box().offset(MARGIN as i32);
        if area.intersection(&tile.bounding_box()).is_zero_sized() {
            return;
        }
        // Drawing on a tile cannot fail (its error type is `Infallible`).
        let _ = area
            .into_styled(PrimitiveStyle::with_fill(Rgb565::BLACK))
            .draw(tile);
        let _ = text.draw(tile);
    }
}

/// No label (the feature `fps-label` is off): nothing is drawn.
#[cfg(not(feature = "fps-label"))]
#[derive(Clone, Copy)]
pub struct Label;

#[cfg(not(feature = "fps-label"))]
impl Label {
    /// No label.
    pub fn new(_: Option<u64>) -> Self {
        Self
    }

    /// Nothing to draw.
    pub fn draw(&self, _: &mut Tile<TILE, Rgb565Wire>) {}
}
