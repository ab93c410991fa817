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
    /// default.
    #[must_use]
    pub fn layouts(self, image: &Image) -> Vec<(&'static str, Layout)> {
        match self {
            Board::BlackPill | Board::Pico2 => vec![
                ("flash", Layout::Flash),
                ("tessera in RAM", Layout::crates(image, RAM_CRATES)),
            ],
            Board::Teensy41 => vec![
                ("teensy4-bsp: .rodata in OCRAM", Layout::CodeInRam),
                (".rodata in DTCM", Layout::AllInRam),
            ],
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

/// The crates whose code the "tessera in RAM" layout copies to RAM: the
/// renderer and the math library it calls (`libm`).
pub const RAM_CRATES: &[&str] = &["tessera_core", "libm"];

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
    /// Of those, of instruction fetches.
    pub fetch_px: f64,
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
    let markers = profile::markers(elf)?;
    let layouts = b.layouts(&image);
    let mut out = Vec::new();
    for run in runs {
        let mut sinks: Vec<Sink<'_>> = layouts
            .iter()
            .map(|(_, l)| Sink::new(&image, l.clone(), b.flash(), b.path()))
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
                fetch_px: t.fetch_stalls as f64 / px,
                shared_px: t.shared_bus as f64 / px,
                code_in_ram: layout.code_bytes(&image),
            });
        }
    }
    Ok(out)
}
