//! What each command may be asked for, checked before any work starts; a
//! request beyond a limit is refused with the figure it would need.
//!
//! - Render threads: at most [`MAX_THREADS`] (0 = one per core).
//! - `render`: no size limit: it streams the PNG a row of tiles at a time, in
//!   memory proportional to the width (see [`crate::render_png`]).
//! - `compare` and `trade`: at most [`flip_pixels`] pixels (about 28.5 million,
//!   e.g. 5,300 x 5,300): FLIP refuses more than 2^34 filter operations at its
//!   default 67 pixels per degree. They keep whole images (about 120 bytes a
//!   pixel: 3.4 GB at that size). `trade` runs at most [`MAX_RUNS`] timed runs.
//! - `simulate`: the simulated panel keeps whole frames: at most
//!   [`MEMORY_LIMIT`] bytes, counted as [`SIMULATE_BYTES_PER_PIXEL`] per pixel
//!   for the frame being drawn and 3 more per pixel of each frame kept for
//!   `--window`; an orbit has at most [`MAX_ORBIT_FRAMES`] frames, its GIF at
//!   most [`MAX_GIF_DELAY_MS`] between frames.

use crate::HostError;
use tessera::Viewport;

/// The most render threads.
pub const MAX_THREADS: usize = 256;
/// The most memory a command may plan to take (4 GiB).
pub const MEMORY_LIMIT: u64 = 4 << 30;
/// Memory per pixel of the frame `simulate` draws: the panel's buffer, its RGB
/// picture, the copy handed back, and the GIF encoder's RGBA copy and indices.
pub const SIMULATE_BYTES_PER_PIXEL: u64 = 16;
/// The most frames of an orbit (one per tenth of a degree).
pub const MAX_ORBIT_FRAMES: u32 = 3600;
/// The most timed runs per setting of `trade`.
pub const MAX_RUNS: usize = 1000;
/// The longest delay between the frames of an orbit's GIF, in milliseconds: a
/// GIF counts delays in hundredths of a second, in 16 bits (65,535).
pub const MAX_GIF_DELAY_MS: u32 = 655_350;

/// `n` with thousands separators.
#[must_use]
pub fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A byte count for people: `1.5 GiB`, `300.0 MiB`, `12 bytes`.
#[must_use]
pub fn bytes(n: u64) -> String {
    const UNITS: [(&str, u64); 4] = [
        ("TiB", 1 << 40),
        ("GiB", 1 << 30),
        ("MiB", 1 << 20),
        ("KiB", 1 << 10),
    ];
    UNITS.iter().find(|(_, u)| n >= *u).map_or_else(
        || format!("{n} bytes"),
        |(name, u)| format!("{:.1} {name}", n as f64 / *u as f64),
    )
}

/// Checks a thread count (0 = one per core).
pub fn threads(n: usize) -> Result<usize, String> {
    if n > MAX_THREADS {
        return Err(format!(
            "{n} render threads is more than the {MAX_THREADS} allowed (0 = one per core, {} here)",
            std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
        ));
    }
    Ok(n)
}

/// The most pixels FLIP measures at the default pixels per degree: its filter
/// work, `pixels x (16 x spatial taps + 14 x feature taps)`, is at most 2^34
/// (flip-rs computes the taps in f32 as here).
#[must_use]
pub fn flip_pixels() -> u64 {
    use std::f32::consts::PI;
    let ppd = flip_rs::DEFAULT_PPD;
    let radius = (3.0 * (0.04 / (2.0 * (PI * PI))).sqrt() * ppd).ceil();
    let feature_radius = (3.0 * (0.5 * 0.082 * ppd)).ceil();
    let spatial = 2 * radius as u64 + 1;
    let feature = 2 * feature_radius as u64 + 1;
    (1u64 << 34) / (16 * spatial + 14 * feature)
}

fn pixels(vp: Viewport) -> u64 {
    u64::from(vp.width) * u64::from(vp.height)
}

/// Checks that `command` (compare, trade) can measure a `vp` image with FLIP.
pub fn measured(command: &str, vp: Viewport) -> Result<(), HostError> {
    let (n, max) = (pixels(vp), flip_pixels());
    if n > max {
        let side = (max as f64).sqrt().floor() as u64;
        return Err(HostError::Limit(format!(
            "{command} at {}x{}: {} pixels is more than the {} that FLIP can measure (2^34 filter operations at {:.0} pixels per degree), e.g. {side}x{side}: choose a smaller --size",
            vp.width,
            vp.height,
            thousands(n),
            thousands(max),
            flip_rs::DEFAULT_PPD,
        )));
    }
    Ok(())
}

/// Checks the memory of `simulate`: `frames` frames of `vp`, all kept when
/// `keep` (for the window).
pub fn simulated(vp: Viewport, frames: u32, keep: bool) -> Result<(), HostError> {
    if frames == 0 || frames > MAX_ORBIT_FRAMES {
        return Err(HostError::Limit(format!(
            "--orbit {frames}: an orbit has 1 to {MAX_ORBIT_FRAMES} frames"
        )));
    }
    let kept = if keep { u64::from(frames) * 3 } else { 0 };
    let need = pixels(vp) * (SIMULATE_BYTES_PER_PIXEL + kept);
    if need > MEMORY_LIMIT {
        return Err(HostError::Limit(format!(
            "simulate at {}x{}{}: the simulated panel would need {} ({} bytes), more than the limit of {}: choose a smaller --size{}",
            vp.width,
            vp.height,
            if keep {
                format!(", {frames} frame(s) kept for the window")
            } else {
                String::new()
            },
            bytes(need),
            thousands(need),
            bytes(MEMORY_LIMIT),
            if keep { " or fewer frames" } else { "" }
        )));
    }
    Ok(())
}

/// Checks a delay between GIF frames, in milliseconds (see [`MAX_GIF_DELAY_MS`]).
pub fn gif_delay(ms: u32) -> Result<u32, String> {
    if ms > MAX_GIF_DELAY_MS {
        return Err(format!(
            "expected a delay from 0 to {MAX_GIF_DELAY_MS} ms (a GIF frame lasts at most \
             65535 hundredths of a second), got {ms}"
        ));
    }
    Ok(ms)
}

/// Checks the runs of `trade`.
pub fn runs(n: usize) -> Result<usize, HostError> {
    if n > MAX_RUNS {
        return Err(HostError::Limit(format!(
            "--runs {n}: at most {MAX_RUNS} timed runs per setting"
        )));
    }
    Ok(n)
}
