//! A model of a board's memory path, driven by the address streams of the
//! firmware under qemu.
//!
//! The cycle model ([`crate::cycles`]) assumes zero-wait memory. No board has
//! it: the RP2350 executes from QSPI flash through a cache, the STM32F411's
//! flash has wait states behind its ART accelerator, the i.MX RT1062 has
//! tightly coupled memories beside cached flash. This module adds the cycles
//! each board's memory path would cost to the same run:
//!
//! - the qemu plugin `tests/profiler/mem_trace.c` streams, while the firmware
//!   renders a tile, every instruction fetch and data access (cut to 8-byte
//!   granules) through a FIFO ([`trace`]);
//! - [`Image`] tells, from the firmware's ELF, whether an address is code,
//!   read-only data or RAM, and which symbol holds it;
//! - a [`Layout`] says where the board keeps code and read-only data (flash,
//!   or copied to RAM), whole or symbol by symbol;
//! - each board's model ([`board`]) takes the events in order and returns the
//!   stall cycles each one costs, from its caches ([`cache`]) and the
//!   parameters of its vendor's documents (cited there).
//!
//! What the stream loses: an access to the granule its stream (fetch or
//! data) used last, with nothing but accesses to one other granule between, is
//! merged with the one before. It is a hit in any cache of whole granules
//! (nothing was filled between the two), so the hits and misses are the
//! chip's, but the recency order it leaves may differ in a cache that both
//! streams share (the RP2350's XIP cache). Each qemu image is
//! the test firmware built for the board's core, not the board example: its
//! code is laid out with every built-in scene linked, so the sets its hot code
//! falls in are those of that image, not of a board's (a cache's conflicts
//! move with the layout; its capacity misses do not).

pub mod board;
pub mod cache;
pub mod frames;

use crate::firmware::{Core, Run, RunResult, TempDir};
use crate::profile::{self, Markers};
use std::io::{BufReader, Read};
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// The plugin's source, relative to the repository root.
pub const PLUGIN_SOURCE: &str = "tests/profiler/mem_trace.c";

/// What an event is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Instructions fetched from one granule, `n` of them in a row.
    Fetch,
    /// A data load.
    Load,
    /// A data store.
    Store,
}

/// One event of the stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Event {
    /// The 8-byte granule's address in the qemu image.
    pub addr: u32,
    /// Fetch, load or store.
    pub kind: Kind,
    /// For a fetch, the instructions executed in a row from the granule (at
    /// least 1); for a load or store, the access's size in bytes.
    pub n: u32,
}

/// Reads the plugin's records from `r`, calls `f` with each event in order, and
/// returns how often the plugin was armed (the count of its last record).
///
/// # Errors
/// When the stream is cut short (no last record) or holds an unknown record.
pub fn read_events(r: impl Read, mut f: impl FnMut(Event)) -> Result<u64, String> {
    let mut r = BufReader::with_capacity(1 << 20, r);
    let mut rec = [0u8; 8];
    let mut spans = 0u64;
    loop {
        r.read_exact(&mut rec)
            .map_err(|e| format!("the address stream ended without its last record: {e}"))?;
        let w0 = u32::from_le_bytes([rec[0], rec[1], rec[2], rec[3]]);
        let w1 = u32::from_le_bytes([rec[4], rec[5], rec[6], rec[7]]);
        if w0 == u32::MAX {
            if u64::from(w1) != spans {
                return Err(format!(
                    "the plugin was armed {w1} times but closed {spans} spans"
                ));
            }
            return Ok(u64::from(w1));
        }
        let kind = match w0 & 3 {
            0 => Kind::Fetch,
            1 => Kind::Load,
            2 => Kind::Store,
            _ => {
                spans += 1;
                continue;
            }
        };
        f(Event {
            addr: w0 & !7,
            kind,
            n: w1,
        });
    }
}

/// Where an address of the qemu image lies.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Area {
    /// The vector table and `.text`: code, and the literal pools in it.
    Code,
    /// `.rodata`: the scene tables, the sRGB table, constants.
    Rodata,
    /// `.data`, `.bss`, the stack, peripherals: RAM on every board.
    Ram,
}

/// Which memory an access goes to on the board.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mem {
    /// The board's flash path (through its caches, with its wait states).
    Flash,
    /// The board's SRAM (or tightly coupled memory, where the board has it).
    Ram,
}

/// A symbol's span in the image.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Span {
    /// Its name, demangled without the hash.
    pub name: String,
    /// Its first address (the Thumb bit cleared).
    pub start: u64,
    /// One past its last byte.
    pub end: u64,
    /// Its area.
    pub area: Area,
}

/// The qemu image's layout: its code and read-only data, and its symbols.
#[derive(Clone, Debug, Default)]
pub struct Image {
    code: Vec<(u64, u64)>,
    rodata: Vec<(u64, u64)>,
    /// Code's and rodata's lowest address: where the board's flash starts.
    pub flash_base: u64,
    /// Function and data symbols in flash, by address, without overlaps.
    pub spans: Vec<Span>,
}

impl Image {
    /// Reads the layout of `elf`.
    ///
    /// # Errors
    /// When the file cannot be read or parsed, or has no `.text`.
    pub fn of(elf: &Path) -> Result<Self, String> {
        use object::{Object, ObjectSection};
        let bytes =
            std::fs::read(elf).map_err(|e| format!("cannot read {}: {e}", elf.display()))?;
        let file = object::File::parse(&*bytes)
            .map_err(|e| format!("{} is not an object file: {e}", elf.display()))?;
        let mut image = Image::default();
        for sec in file.sections() {
            let range = (sec.address(), sec.address() + sec.size());
            match sec.name().unwrap_or("") {
                ".vector_table" | ".text" => image.code.push(range),
                ".rodata" => image.rodata.push(range),
                _ => {}
            }
        }
        if image.code.is_empty() {
            return Err(format!("{} has no .text", elf.display()));
        }
        image.flash_base = image
            .code
            .iter()
            .chain(&image.rodata)
            .map(|r| r.0)
            .min()
            .unwrap_or(0);
        let mut spans: Vec<Span> = crate::firmware::symbols(elf)?
            .into_iter()
            .filter(|s| s.size > 0)
            .filter_map(|s| {
                let start = s.address & !1;
                let area = image.area(start);
                (area != Area::Ram).then(|| Span {
                    name: s.name,
                    start,
                    end: start + s.size,
                    area,
                })
            })
            .collect();
        spans.sort_by_key(|s| (s.start, std::cmp::Reverse(s.end)));
        spans.dedup_by(|b, a| b.start < a.end);
        image.spans = spans;
        Ok(image)
    }

    /// The area of `addr`.
    #[must_use]
    pub fn area(&self, addr: u64) -> Area {
        let inside = |rs: &[(u64, u64)]| rs.iter().any(|&(a, b)| (a..b).contains(&addr));
        if inside(&self.code) {
            Area::Code
        } else if inside(&self.rodata) {
            Area::Rodata
        } else {
            Area::Ram
        }
    }

    /// The index in [`Image::spans`] of the symbol holding `addr`.
    #[must_use]
    pub fn span_of(&self, addr: u64) -> Option<usize> {
        let i = self.spans.partition_point(|s| s.start <= addr);
        (i > 0 && addr < self.spans[i - 1].end).then(|| i - 1)
    }

    /// Bytes of code and of read-only data.
    #[must_use]
    pub fn sizes(&self) -> (u64, u64) {
        let sum = |rs: &[(u64, u64)]| rs.iter().map(|r| r.1 - r.0).sum();
        (sum(&self.code), sum(&self.rodata))
    }
}

/// Where a board keeps code and read-only data.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Layout {
    /// Both in flash, as cortex-m-rt links a firmware: the default.
    Flash,
    /// Code copied to RAM at start, read-only data in flash.
    CodeInRam,
    /// Both copied to RAM at start.
    AllInRam,
    /// Flash, but for these spans of the image, copied to RAM (by symbol).
    Some(Spans),
}

/// Address ranges of the image, sorted and merged where they touch, so that
/// finding the one holding an address is a binary search: [`Layout::mem`]
/// asks it for every event of a stream.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Spans(Vec<(u64, u64)>);

impl Spans {
    /// The ranges `[start, end)` of `spans`, in any order.
    #[must_use]
    pub fn new(mut spans: Vec<(u64, u64)>) -> Self {
        spans.sort_unstable();
        let mut merged: Vec<(u64, u64)> = Vec::with_capacity(spans.len());
        for (a, b) in spans {
            match merged.last_mut() {
                Some(last) if a <= last.1 => last.1 = last.1.max(b),
                _ => merged.push((a, b)),
            }
        }
        Self(merged)
    }

    /// Whether `addr` lies in one of the ranges.
    #[must_use]
    pub fn contains(&self, addr: u64) -> bool {
        let i = self.0.partition_point(|&(a, _)| a <= addr);
        i > 0 && addr < self.0[i - 1].1
    }

    /// The ranges, sorted and disjoint.
    #[must_use]
    pub fn ranges(&self) -> &[(u64, u64)] {
        &self.0
    }
}

impl Layout {
    /// The memory `addr` (of area `area`) lies in under this layout.
    #[must_use]
    pub fn mem(&self, area: Area, addr: u64) -> Mem {
        match (self, area) {
            (_, Area::Ram) | (Layout::AllInRam, _) | (Layout::CodeInRam, Area::Code) => Mem::Ram,
            (Layout::Some(spans), _) if spans.contains(addr) => Mem::Ram,
            _ => Mem::Flash,
        }
    }

    /// Flash, but for the code of the crates `crates` (the symbols whose names
    /// hold one of them: their functions, their generic functions made for
    /// other crates' types and their closures), copied to RAM: what a linker
    /// script does with the input sections `.text.*<crate>*`.
    #[must_use]
    pub fn crates(image: &Image, crates: &[&str]) -> Self {
        Layout::Some(Spans::new(
            image
                .spans
                .iter()
                .filter(|s| s.area == Area::Code && crates.iter().any(|c| s.name.contains(c)))
                .map(|s| (s.start, s.end))
                .collect(),
        ))
    }

    /// Bytes of the image's code this layout copies to RAM.
    #[must_use]
    pub fn code_bytes(&self, image: &Image) -> u64 {
        match self {
            Layout::Flash => 0,
            Layout::CodeInRam | Layout::AllInRam => image.sizes().0,
            Layout::Some(spans) => spans
                .ranges()
                .iter()
                .filter(|&&(a, _)| image.area(a) == Area::Code)
                .map(|&(a, b)| b - a)
                .sum(),
        }
    }
}

/// A board's memory path: the stall cycles of each event.
pub trait MemoryPath {
    /// The cycles `e` stalls the core beyond a zero-wait access, when it goes to
    /// `mem` at the board's address `addr` (the image's address carried to the
    /// board's flash when `mem` is flash).
    fn stall(&mut self, e: &Event, mem: Mem, addr: u64) -> u64;
}

/// What one model made of a stream.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tally {
    /// Stall cycles in all.
    pub stalls: u64,
    /// Stall cycles of instruction fetches.
    pub fetch_stalls: u64,
    /// Stall cycles of loads.
    pub load_stalls: u64,
    /// Instructions seen (the fetch events' counts).
    pub instructions: u64,
    /// Events that went to flash.
    pub flash_events: u64,
    /// Loads and stores to RAM while the code ran from RAM: on a core whose
    /// code and data share a bus port there (the Cortex-M4's S-bus, the
    /// Cortex-M33's S-AHB), each may delay a fetch by a cycle; the fetch
    /// buffer hides most of it. A bound, not part of the stalls.
    pub shared_bus: u64,
    /// Stall cycles by the symbol ([`Image::spans`]) the access fell in; the
    /// last entry gathers those in no symbol.
    pub by_span: Vec<u64>,
}

/// A board's path under a layout, fed event by event.
pub struct Sink<'a> {
    image: &'a Image,
    layout: Layout,
    /// Where the board's flash starts.
    flash_base: u64,
    path: Box<dyn MemoryPath + Send + 'a>,
    /// Whether the last fetch came from RAM.
    fetching_ram: bool,
    /// What it counted.
    pub tally: Tally,
}

impl<'a> Sink<'a> {
    /// `path` under `layout`, for the image `image`, with the board's flash at
    /// `flash_base`.
    pub fn new(
        image: &'a Image,
        layout: Layout,
        flash_base: u64,
        path: Box<dyn MemoryPath + Send + 'a>,
    ) -> Self {
        Self {
            image,
            layout,
            flash_base,
            path,
            fetching_ram: false,
            tally: Tally {
                by_span: vec![0; image.spans.len() + 1],
                ..Tally::default()
            },
        }
    }

    /// Takes one event.
    pub fn event(&mut self, e: &Event) {
        let addr = u64::from(e.addr);
        let area = self.image.area(addr);
        let mem = self.layout.mem(area, addr);
        match e.kind {
            Kind::Fetch => {
                self.tally.instructions += u64::from(e.n);
                self.fetching_ram = mem == Mem::Ram;
            }
            Kind::Load | Kind::Store if mem == Mem::Ram && self.fetching_ram => {
                self.tally.shared_bus += 1;
            }
            _ => {}
        }
        let board_addr = match mem {
            Mem::Flash => {
                self.tally.flash_events += 1;
                addr - self.image.flash_base + self.flash_base
            }
            Mem::Ram => addr,
        };
        let stall = self.path.stall(e, mem, board_addr);
        if stall > 0 {
            self.tally.stalls += stall;
            match e.kind {
                Kind::Fetch => self.tally.fetch_stalls += stall,
                Kind::Load => self.tally.load_stalls += stall,
                Kind::Store => {}
            }
            let i = self.image.span_of(addr).unwrap_or(self.image.spans.len());
            self.tally.by_span[i] += stall;
        }
    }
}

/// Compiles the plugin, as [`profile::build_plugin_from`] does.
///
/// # Errors
/// When the C compiler fails.
pub fn build_plugin() -> Result<std::path::PathBuf, String> {
    profile::build_plugin_from(PLUGIN_SOURCE)
}

/// Runs `run` on `core`'s firmware `elf` under qemu with the plugin `plugin`
/// armed around each tile by `markers`, and feeds the stream to each of
/// `sinks` while qemu runs (through a FIFO: a frame's stream is gigabytes).
/// Returns the firmware's result.
///
/// # Errors
/// When qemu or the firmware fails, or the stream is cut short or was not armed
/// once per tile.
pub fn trace(
    core: &Core,
    elf: &Path,
    plugin: &Path,
    markers: Markers,
    run: &Run,
    sinks: &mut [Sink<'_>],
) -> Result<RunResult, String> {
    let dir = TempDir::new()?;
    let fifo = dir.path().join("trace.fifo");
    crate::firmware::checked(
        std::process::Command::new("mkfifo").arg(&fifo),
        "mkfifo",
        "mkfifo failed",
    )?;
    let arg = profile::plugin_arg(plugin, markers, &fifo)?;
    let opened = AtomicBool::new(false);
    let (result, arms) = std::thread::scope(|s| {
        let reader = s.spawn(|| {
            let file = std::fs::File::open(&fifo)
                .map_err(|e| format!("cannot open {}: {e}", fifo.display()));
            opened.store(true, Ordering::SeqCst);
            read_events(file?, |e| {
                for sink in sinks.iter_mut() {
                    sink.event(&e);
                }
            })
        });
        let result = core.run_with(elf, std::slice::from_ref(run), &["-plugin".into(), arg]);
        if !opened.load(Ordering::SeqCst) {
            // qemu never opened the FIFO: open it once so that the reader's
            // open returns, and sees an empty stream.
            let _ = std::fs::OpenOptions::new().write(true).open(&fifo);
        }
        let arms = reader
            .join()
            .map_err(|_| "the address stream's reader panicked".to_string())?;
        Ok::<_, String>((result, arms))
    })?;
    let result = result?;
    let arms = arms.map_err(|e| format!("{run}: {e}"))?;
    if arms != profile::tiles(run) {
        return Err(format!(
            "{run}: the plugin was armed {arms} times for {} tiles",
            profile::tiles(run)
        ));
    }
    result
        .runs
        .into_iter()
        .next()
        .ok_or_else(|| format!("{run}: no result"))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(w0: u32, w1: u32) -> [u8; 8] {
        let mut r = [0u8; 8];
        r[..4].copy_from_slice(&w0.to_le_bytes());
        r[4..].copy_from_slice(&w1.to_le_bytes());
        r
    }

    #[test]
    fn reads_the_plugin_records() {
        let mut bytes = Vec::new();
        for (w0, w1) in [
            (0x1000, 3),
            (0x2000_0009, 4),
            (0x1008, 1),
            (0x2000_0012, 2),
            (3, 0),
            (u32::MAX, 1),
        ] {
            bytes.extend_from_slice(&record(w0, w1));
        }
        let mut events = Vec::new();
        let arms = read_events(&bytes[..], |e| events.push(e)).unwrap();
        assert_eq!(arms, 1);
        assert_eq!(
            events,
            [
                Event {
                    addr: 0x1000,
                    kind: Kind::Fetch,
                    n: 3
                },
                Event {
                    addr: 0x2000_0008,
                    kind: Kind::Load,
                    n: 4
                },
                Event {
                    addr: 0x1008,
                    kind: Kind::Fetch,
                    n: 1
                },
                Event {
                    addr: 0x2000_0010,
                    kind: Kind::Store,
                    n: 2
                },
            ]
        );
        // Cut short, or armed more often than it closed spans: refused.
        assert!(read_events(&bytes[..bytes.len() - 8], |_| {}).is_err());
        assert!(read_events(&bytes[..bytes.len() - 3], |_| {}).is_err());
        let mut two = bytes[..bytes.len() - 8].to_vec();
        two.extend_from_slice(&record(u32::MAX, 2));
        assert!(read_events(&two[..], |_| {}).is_err());
    }

    #[test]
    fn layouts_place_areas() {
        let hot = Layout::Some(Spans::new(vec![
            (0x200, 0x210),
            (0x100, 0x140),
            (0x130, 0x150),
        ]));
        assert_eq!(Layout::Flash.mem(Area::Code, 0x100), Mem::Flash);
        assert_eq!(Layout::Flash.mem(Area::Ram, 0x2000_0000), Mem::Ram);
        assert_eq!(Layout::CodeInRam.mem(Area::Code, 0x100), Mem::Ram);
        assert_eq!(Layout::CodeInRam.mem(Area::Rodata, 0x9000), Mem::Flash);
        assert_eq!(Layout::AllInRam.mem(Area::Rodata, 0x9000), Mem::Ram);
        assert_eq!(hot.mem(Area::Code, 0x13c), Mem::Ram);
        assert_eq!(hot.mem(Area::Code, 0x14f), Mem::Ram);
        assert_eq!(hot.mem(Area::Code, 0x150), Mem::Flash);
        assert_eq!(hot.mem(Area::Code, 0xff), Mem::Flash);
        assert_eq!(hot.mem(Area::Code, 0x208), Mem::Ram);
        assert_eq!(hot.mem(Area::Code, 0x210), Mem::Flash);
    }
}
