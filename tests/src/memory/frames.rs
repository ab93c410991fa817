//! The boards' memory paths on the frames of the frame-rate estimates: each
//! run traced on the core of each board ([`measure`]), under each layout the
//! board is offered.

use super::{Image, Layout, MemoryPath, Sink, board};
use crate::firmware::{self, Core, Run};
use crate::profile;
use std::path::Path;

/// A board of the estimates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Board {
    /// STM32F411 Black Pill: the Cortex-M4F's image.
    BlackPill,
    /// RP2350 Pico 2: the Cortex-M33's image.
    Pico2,
    /// i.MX RT1062 Teensy 4.1: the Cortex-M7's image.
    Teensy41,
}

impl Board {
    /// Every board, in the report's order.
    pub const ALL: [Board; 3] = [Board::BlackPill, Board::Pico2, Board::Teensy41];

    /// Its name in reports.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Board::BlackPill => "Black Pill",
            Board::Pico2 => "Pico 2",
            Board::Teensy41 => "Teensy 4.1",
        }
    }

    /// The core whose test image stands for the board's.
    #[must_use]
    pub fn core(self) -> Core {
        match self {
            Board::BlackPill => firmware::CORTEX_M4F,
            Board::Pico2 => firmware::CORTEX_M33,
            Board::Teensy41 => firmware::CORTEX_M7,
        }
    }

    /// The layouts the board is offered, by name: the first is its runtime's
    /// default. The Black Pill's second, the hottest code in RAM, is chosen
    /// from the first's stalls ([`HOT_NAME`], [`measure`]).
    #[must_use]
    pub fn layouts(self, image: &Image) -> Vec<(&'static str, Layout)> {
        match self {
            Board::BlackPill => vec![(FLASH, Layout::Flash)],
            Board::Pico2 => vec![
                (FLASH, Layout::Flash),
                (TESSERA_IN_RAM, Layout::crates(image, RAM_CRATES)),
            ],
            Board::Teensy41 => vec![
                (TEENSY_BSP, Layout::CodeInRam),
                (".rodata in DTCM", Layout::AllInRam),
            ],
        }
    }

    /// The name of the layout the board's example ships (the Teensy 4.1: the
    /// one its BSP links).
    #[must_use]
    pub fn shipped(self) -> &'static str {
        match self {
            Board::BlackPill => FLASH,
            Board::Pico2 => TESSERA_IN_RAM,
            Board::Teensy41 => TEENSY_BSP,
        }
    }

    fn path(self) -> Box<dyn MemoryPath + Send> {
        match self {
            Board::BlackPill => Box::new(board::Stm32f411::new()),
            Board::Pico2 => Box::new(board::Rp2350::new()),
            Board::Teensy41 => Box::new(board::Imxrt1062::new()),
        }
    }

    fn flash(self) -> u64 {
        match self {
            Board::BlackPill => board::Stm32f411::FLASH,
            Board::Pico2 => board::Rp2350::FLASH,
            Board::Teensy41 => board::Imxrt1062::OCRAM,
        }
    }
}

/// The layout cortex-m-rt links: code and read-only data in flash.
pub const FLASH: &str = "flash";

/// The Pico 2 example's layout: tessera's code in RAM ([`RAM_CRATES`]).
pub const TESSERA_IN_RAM: &str = "tessera in RAM";

/// The Teensy 4.1's layout as teensy4-bsp links it.
pub const TEENSY_BSP: &str = "teensy4-bsp: .rodata in OCRAM";

/// The crates whose code the "tessera in RAM" layout copies to RAM: the
/// renderer and the math library it calls (`libm`).
pub const RAM_CRATES: &[&str] = &["tessera_core", "libm"];

/// The SRAM the Black Pill's hottest code may take: half the F411's 128 KiB,
/// the rest left to the statics, the stack and the tiles (tessera's code,
/// about 148 KB in that firmware, does not fit).
pub const HOT_BUDGET: u64 = 64 * 1024;

/// The name of the Black Pill's layout with its hottest code in RAM.
pub const HOT_NAME: &str = "hottest 64 KiB of code in RAM";

/// One run of one board under one layout.
#[derive(Clone, Debug, PartialEq)]
pub struct Traced {
    /// The board.
    pub board: Board,
    /// The layout's name ([`Board::layouts`]).
    pub layout: &'static str,
    /// The run.
    pub run: Run,
    /// Instructions a pixel (the stream's count).
    pub instr_px: f64,
    /// Stall cycles a pixel.
    pub stalls_px: f64,
    /// RAM accesses a pixel that may meet a fetch on a shared bus
    /// ([`super::Tally::shared_bus`]).
    pub shared_px: f64,
    /// Bytes of code this layout copies to RAM, in this image.
    pub code_in_ram: u64,
}

/// Traces each of `runs` on each board's image (`elfs`, in [`Board::ALL`]'s
/// order), the three boards on three threads.
///
/// # Errors
/// When a build, a qemu run or a stream fails.
pub fn measure(runs: &[Run], elfs: [&Path; 3]) -> Result<Vec<Traced>, String> {
    let plugin = super::build_plugin()?;
    let per_board: Vec<Result<Vec<Traced>, String>> = std::thread::scope(|s| {
        let handles: Vec<_> = Board::ALL
            .iter()
            .zip(elfs)
            .map(|(&b, elf)| {
                let plugin = &plugin;
                s.spawn(move || measure_board(b, elf, plugin, runs))
            })
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err("a tracing thread panicked".into()))
            })
            .collect()
    });
    let mut all = Vec::new();
    for r in per_board {
        all.extend(r?);
    }
    Ok(all)
}

fn measure_board(b: Board, elf: &Path, plugin: &Path, runs: &[Run]) -> Result<Vec<Traced>, String> {
    let image = Image::of(elf)?;
    let layouts = b.layouts(&image);
    let (mut out, stalls) = trace_runs(b, &image, elf, plugin, runs, &layouts)?;
    if b == Board::BlackPill {
        let hot = vec![(HOT_NAME, hottest(&image, &stalls, HOT_BUDGET))];
        out.extend(trace_runs(b, &image, elf, plugin, runs, &hot)?.0);
    }
    Ok(out)
}

/// The code spans of `image` that waited most in `stalls` (each run's stalls
/// by span under the first layout, each run weighed as much as the others),
/// most first, as long as they fit `budget` bytes together.
fn hottest(image: &Image, stalls: &[Vec<u64>], budget: u64) -> Layout {
    let mut share = vec![0.0f64; image.spans.len()];
    for run in stalls {
        let total = run.iter().sum::<u64>().max(1) as f64;
        for (i, &s) in run.iter().take(share.len()).enumerate() {
            share[i] += s as f64 / total;
        }
    }
    let mut order: Vec<usize> = (0..share.len())
        .filter(|&i| image.spans[i].area == super::Area::Code && share[i] > 0.0)
        .collect();
    order.sort_by(|&a, &b| share[b].total_cmp(&share[a]));
    let (mut taken, mut spans) = (0, Vec::new());
    for i in order {
        let s = &image.spans[i];
        if taken + (s.end - s.start) <= budget {
            taken += s.end - s.start;
            spans.push((s.start, s.end));
        }
    }
    Layout::Some(super::Spans::new(spans))
}

/// Traces each of `runs` under each of `layouts`; returns the rows and, per
/// run, the first layout's stalls by span.
fn trace_runs(
    b: Board,
    image: &Image,
    elf: &Path,
    plugin: &Path,
    runs: &[Run],
    layouts: &[(&'static str, Layout)],
) -> Result<(Vec<Traced>, Vec<Vec<u64>>), String> {
    let markers = profile::markers(elf)?;
    let (mut out, mut stalls) = (Vec::new(), Vec::new());
    for run in runs {
        let mut sinks: Vec<Sink<'_>> = layouts
            .iter()
            .map(|(_, l)| Sink::new(image, l.clone(), b.flash(), b.path()))
            .collect();
        let res = super::trace(&b.core(), elf, plugin, markers, run, &mut sinks)?;
        let px = res.pixels_count.max(1) as f64;
        for ((name, layout), sink) in layouts.iter().zip(&sinks) {
            let t = &sink.tally;
            out.push(Traced {
                board: b,
                layout: name,
                run: *run,
                instr_px: t.instructions as f64 / px,
                stalls_px: t.stalls as f64 / px,
                shared_px: t.shared_bus as f64 / px,
                code_in_ram: layout.code_bytes(image),
            });
        }
        stalls.push(
            sinks
                .first()
                .map(|s| s.tally.by_span.clone())
                .unwrap_or_default(),
        );
    }
    Ok((out, stalls))
}
