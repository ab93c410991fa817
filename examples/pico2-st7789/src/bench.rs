//! The bench (feature `bench`, which brings `defmt` and the core's built-in
//! teapot): before the animation, each built-in scene (`Builtin::ALL`), from
//! the core's baked tables in flash, at [`PICTURE`] (240x240) with the scene's
//! own settings, rendered into RGB tile buffers and drawn nowhere, timed with
//! core 0's DWT cycle counter at the system clock. Printed over defmt/RTT for
//! each scene:
//!
//! - **one core**: core 0 renders the tiles in order, each tile's render timed
//!   alone; the cycles, cycles a pixel, time and frames a second, and the
//!   FNV-1a 64 checksum of the frame's RGB bytes tile after tile (each tile's
//!   rows top to bottom), the host's picture's (docs/bench.md);
//! - **two cores**: both take tiles from the firmware's [`QUEUE`] as the
//!   animation's frames do, timed on core 0 from the frame's start until core 1
//!   has finished its last tile: the same figures, the speed-up over one core
//!   and how many tiles each core rendered. Then the frame again on both cores,
//!   untimed, each tile's FNV-1a 64 (with its place) summed: equal to the one
//!   core frame's sum, the two cores drew the same tiles.
//!
//! The counter is checked first: read, a spin of [`SPIN`] cycles, read again.
//! If it reads zero or does not advance, the bench says so and gives no cycle
//! figure, only the checksums.
//!
//! Core 1 takes part from [`serve`], the first thing it runs: it renders the
//! tiles of each bench frame core 0 publishes ([`JOB`], then its number in
//! [`STARTED`], release) and stores the number in [`DONE`] (release) when the
//! queue is empty; after the last scene core 0 sets [`OVER`] and core 1 goes
//! on to the animation's frames.

use crate::{GRID, PICTURE, QUEUE, TILE};
use core::cell::Cell;
use core::hint::spin_loop;
use core::sync::atomic::{AtomicBool, AtomicU32, Ordering};
use cortex_m::peripheral::{DCB, DWT};
use critical_section::Mutex;
use tessera_core::builtin::{Builtin, baked};
use tessera_core::tile::Loops;
use tessera_core::{Error, Renderer, SceneView, Tile, TileCoord, Viewport};

/// The cycles of the spin that checks the cycle counter.
const SPIN: u32 = 500;
/// FNV-1a 64's offset basis.
const FNV_START: u64 = 0xcbf2_9ce4_8422_2325;
/// The frame's pixels.
const PIXELS: u64 = PICTURE.0 as u64 * PICTURE.1 as u64;
/// The frame's tiles.
const TILES: usize = GRID.0 as usize * GRID.1 as usize;

/// The frame both cores render: core 0 writes it before publishing its number
/// in [`STARTED`]; core 1 copies it out after seeing the number.
static JOB: Mutex<Cell<Option<Job>>> = Mutex::new(Cell::new(None));
/// The number of the last bench frame published (from 1).
static STARTED: AtomicU32 = AtomicU32::new(0);
/// The last bench frame core 1 has finished (its tiles and sum in [`CORE1`]).
static DONE: AtomicU32 = AtomicU32::new(0);
/// Core 1's share of the last frame it finished: its tiles and their sum.
static CORE1: Mutex<Cell<Share>> = Mutex::new(Cell::new(Share::NONE));
/// Set when the bench is over: core 1 leaves [`serve`].
static OVER: AtomicBool = AtomicBool::new(false);

/// A scene's frame as both cores render it: plain `Copy` data (the view reads
/// the core's baked tables, `static`).
#[derive(Clone, Copy)]
struct Job {
    scene: Builtin,
    renderer: Renderer,
    view: SceneView<'static>,
    /// Whether each tile's FNV-1a 64 is summed (the untimed pass).
    sum: bool,
}

/// The tiles a core rendered of a frame and the sum of their hashes.
#[derive(Clone, Copy)]
struct Share {
    tiles: u32,
    sum: u64,
}

impl Share {
    const NONE: Self = Self { tiles: 0, sum: 0 };
}

/// Core 1, before the animation: renders the tiles of each bench frame core 0
/// publishes, until core 0 says the bench is over (it returns at once if core
/// 0 has no bench to run).
pub fn serve() {
    let mut seen = 0;
    while !OVER.load(Ordering::Acquire) {
        let frame = STARTED.load(Ordering::Acquire);
        if frame == seen {
            spin_loop();
            continue;
        }
        seen = frame;
        let share = critical_section::with(|cs| JOB.borrow(cs).get())
            .map_or(Share::NONE, |job| job.take_tiles(1, &mut Lap::None));
        critical_section::with(|cs| CORE1.borrow(cs).set(share));
        DONE.store(frame, Ordering::Release);
    }
}

/// Where the code runs in this build (src/ram.rs; the feature `flash-only`).
const LAYOUT: &str = if cfg!(feature = "flash-only") {
    "layout flash-only: code and tables in flash through the XIP cache"
} else {
    "layout default: tessera's code in SRAM, the rest and the tables in flash through the XIP cache"
};

/// Core 0: checks the cycle counter, then renders, times and prints each
/// built-in scene on one core and, if core 1 runs, on both (`hz`: the system
/// clock). A scene tessera refuses is logged and skipped. Lets core 1 go on at
/// the end.
pub fn run(two_cores: bool, hz: u32) {
    let counting = cortex_m::Peripherals::take()
        .is_some_and(|mut cp| counter_counts(&mut cp.DCB, &mut cp.DWT));
    defmt::info!(
        "bench: {=usize} built-in scene(s) at {=u16}x{=u16} in {=usize}x{=usize} tiles, each with its own settings, drawn nowhere; {=u32} MHz, {=str}; {=u8} core(s)",
        Builtin::ALL.len(),
        PICTURE.0,
        PICTURE.1,
        TILE,
        TILE,
        hz / 1_000_000,
        LAYOUT,
        if two_cores { 2 } else { 1 }
    );
    if !counting {
        defmt::warn!(
            "bench: cycle counter absent or stopped (DWT CYCCNT did not advance across a spin of {=u32} cycles): no cycle figure is given",
            SPIN
        );
    }
    let mut frame = 0;
    for &scene in Builtin::ALL {
        if let Err(e) = bench(scene, two_cores, counting.then_some(hz), &mut frame) {
            defmt::error!("bench: {=str}: {}", scene.name(), e);
        }
    }
    OVER.store(true, Ordering::Release);
}

/// Enables core 0's cycle counter (DCB's trace enable, DWT CYCCNT) and checks
/// that it counts: read, a spin of [`SPIN`] cycles, read again; counting if it
/// advanced by at least half the spin.
fn counter_counts(dcb: &mut DCB, dwt: &mut DWT) -> bool {
    dcb.enable_trace();
    if !DWT::has_cycle_counter() {
        return false;
    }
    dwt.enable_cycle_counter();
    let before = DWT::cycle_count();
    cortex_m::asm::delay(SPIN);
    DWT::cycle_count().wrapping_sub(before) >= SPIN / 2
}

/// `scene`'s frame on one core, then (if `two_cores`) on both, timed and then
/// summed; prints the figures (the cycles only if `clock`, the system clock in
/// Hz, is given: the counter counts). `frame` numbers the frames both cores
/// render.
fn bench(
    scene: Builtin,
    two_cores: bool,
    clock: Option<u32>,
    frame: &mut u32,
) -> Result<(), Error> {
    let job = scene.with_baked_scene(|view, camera| {
        let renderer = Renderer::try_new(
            camera,
            Viewport::new(PICTURE.0, PICTURE.1),
            scene.settings(),
        )?;
        Ok::<_, Error>(Job {
            scene,
            renderer,
            view: *view,
            sum: false,
        })
    })??;
    let one = job.one_core()?;
    report_one_core(scene, &one, clock);
    if two_cores {
        *frame += 1;
        let (cycles, core0, core1) = job.both_cores(*frame);
        *frame += 1;
        let (_, sum0, sum1) = Job { sum: true, ..job }.both_cores(*frame);
        let both = TwoCores {
            cycles,
            core0,
            core1,
            same: sum0.sum.wrapping_add(sum1.sum) == one.sum,
        };
        report_two_cores(scene, &one, &both, clock);
    }
    Ok(())
}

/// A scene's frame on core 0 alone.
struct OneCore {
    /// The cycles of its tiles' renders.
    cycles: u64,
    /// FNV-1a 64 of its RGB bytes, tile after tile.
    checksum: u64,
    /// The sum of its tiles' hashes ([`tile_hash`]).
    sum: u64,
}

/// A scene's frame on both cores.
struct TwoCores {
    /// The cycles from its start until both cores had finished.
    cycles: u64,
    core0: Share,
    core1: Share,
    /// Whether the tiles' hashes summed to the one-core frame's.
    same: bool,
}

/// Prints the one-core frame's line (with its cycles if `clock` is given).
fn report_one_core(scene: Builtin, one: &OneCore, clock: Option<u32>) {
    let Some(hz) = clock else {
        defmt::info!(
            "bench: {=str} {=u16}x{=u16}, {=usize} tiles, one core: no cycle figure, checksum {=u64:016x}",
            scene.name(),
            PICTURE.0,
            PICTURE.1,
            TILES,
            one.checksum
        );
        return;
    };
    let f = Figures::of(one.cycles, hz);
    defmt::info!(
        "bench: {=str} {=u16}x{=u16}, {=usize} tiles, one core: {=u64} cycles, {=u64} cycles/px, {=u64}.{=u64} ms, {=u64}.{=u64:02} fps at {=u32} MHz, checksum {=u64:016x}",
        scene.name(),
        PICTURE.0,
        PICTURE.1,
        TILES,
        one.cycles,
        one.cycles / PIXELS,
        f.tenths_ms / 10,
        f.tenths_ms % 10,
        f.hundredths_fps / 100,
        f.hundredths_fps % 100,
        hz / 1_000_000,
        one.checksum
    );
}

/// Prints the two-core frame's line (with its cycles and the speed-up over
/// `one` if `clock` is given).
fn report_two_cores(scene: Builtin, one: &OneCore, both: &TwoCores, clock: Option<u32>) {
    let Some(hz) = clock else {
        defmt::info!(
            "bench: {=str} {=u16}x{=u16}, {=usize} tiles, two cores: no cycle figure, tiles core 0/1 {=u32}/{=u32}, same tiles as one core: {=bool}",
            scene.name(),
            PICTURE.0,
            PICTURE.1,
            TILES,
            both.core0.tiles,
            both.core1.tiles,
            both.same
        );
        return;
    };
    let f = Figures::of(both.cycles, hz);
    let thousandths = one.cycles * 1000 / both.cycles.max(1);
    defmt::info!(
        "bench: {=str} {=u16}x{=u16}, {=usize} tiles, two cores: {=u64} cycles, {=u64} cycles/px, {=u64}.{=u64} ms, {=u64}.{=u64:02} fps at {=u32} MHz, speed-up {=u64}.{=u64:03}, tiles core 0/1 {=u32}/{=u32}, same tiles as one core: {=bool}",
        scene.name(),
        PICTURE.0,
        PICTURE.1,
        TILES,
        both.cycles,
        both.cycles / PIXELS,
        f.tenths_ms / 10,
        f.tenths_ms % 10,
        f.hundredths_fps / 100,
        f.hundredths_fps % 100,
        hz / 1_000_000,
        thousandths / 1000,
        thousandths % 1000,
        both.core0.tiles,
        both.core1.tiles,
        both.same
    );
}

/// A frame's time in tenths of a ms and its rate in hundredths of a frame a
/// second (no float formatting is linked).
struct Figures {
    tenths_ms: u64,
    hundredths_fps: u64,
}

impl Figures {
    /// Of a frame of `cycles` at `hz`.
    fn of(cycles: u64, hz: u32) -> Self {
        let hz = u64::from(hz);
        Self {
            tenths_ms: cycles * 10_000 / hz,
            hundredths_fps: hz * 100 / cycles.max(1),
        }
    }
}

/// Whether a core times the frame as it goes (core 0 reads its cycle counter
/// after each tile and while it waits, so that the 32-bit counter's wrap, 28.6
/// s at 150 MHz, is never missed).
enum Lap {
    /// Core 1: no timing.
    None,
    /// Core 0: the counter's last reading and the cycles since the start.
    Core0 { last: u32, cycles: u64 },
}

impl Lap {
    /// Starts timing now.
    fn start() -> Self {
        Self::Core0 {
            last: DWT::cycle_count(),
            cycles: 0,
        }
    }

    /// Adds the cycles since the last reading.
    fn lap(&mut self) {
        if let Self::Core0 { last, cycles } = self {
            let now = DWT::cycle_count();
            *cycles += u64::from(now.wrapping_sub(*last));
            *last = now;
        }
    }

    /// The cycles since [`Lap::start`] up to the last [`Lap::lap`].
    fn cycles(&self) -> u64 {
        match self {
            Self::None => 0,
            Self::Core0 { cycles, .. } => *cycles,
        }
    }
}

impl Job {
    /// The frame on core 0 alone, tiles in order, each tile's render timed
    /// alone.
    fn one_core(&self) -> Result<OneCore, Error> {
        let mut tile = Tile::<TILE>::new();
        let (mut cycles, mut checksum, mut sum) = (0, FNV_START, 0_u64);
        for ty in 0..GRID.1 {
            for tx in 0..GRID.0 {
                let start = DWT::cycle_count();
                render(self, TileCoord::new(tx, ty), &mut tile)?;
                cycles += u64::from(DWT::cycle_count().wrapping_sub(start));
                for row in tile.rows() {
                    for p in row {
                        checksum = fnv1a64(checksum, &[p.r, p.g, p.b]);
                    }
                }
                sum = sum.wrapping_add(tile_hash(&tile));
            }
        }
        Ok(OneCore {
            cycles,
            checksum,
            sum,
        })
    }

    /// The frame on both cores from [`QUEUE`], numbered `frame`: the cycles
    /// from its start until core 1 has finished, and each core's share.
    fn both_cores(&self, frame: u32) -> (u64, Share, Share) {
        // Core 1 has finished the frame before (DONE, acquire): it takes no
        // tile until it sees this frame's number.
        QUEUE.reset();
        critical_section::with(|cs| JOB.borrow(cs).set(Some(*self)));
        let mut lap = Lap::start();
        STARTED.store(frame, Ordering::Release);
        let core0 = self.take_tiles(0, &mut lap);
        while DONE.load(Ordering::Acquire) != frame {
            lap.lap();
            spin_loop();
        }
        lap.lap();
        let core1 = critical_section::with(|cs| CORE1.borrow(cs).get());
        (lap.cycles(), core0, core1)
    }

    /// Renders tiles from [`QUEUE`] until it is empty (`core` names the core
    /// in the log of a tile tessera refuses); sums their hashes if the job
    /// says so; `lap` after each tile.
    fn take_tiles(&self, core: u8, lap: &mut Lap) -> Share {
        let mut tile = Tile::<TILE>::new();
        let mut share = Share::NONE;
        while let Some(coord) = QUEUE.next() {
            match render(self, coord, &mut tile) {
                Ok(()) => {
                    share.tiles += 1;
                    if self.sum {
                        share.sum = share.sum.wrapping_add(tile_hash(&tile));
                    }
                }
                Err(e) => crate::log::tile_failed(core, coord, e),
            }
            lap.lap();
        }
        share
    }
}

/// Renders tile `coord` of the job's scene with the tile loops its baked
/// module names (`SceneLoops`: what a firmware of that scene alone links). A
/// built-in scene this bench does not know: [`Error::NotLinked`].
fn render(job: &Job, coord: TileCoord, tile: &mut Tile<TILE>) -> Result<(), Error> {
    use baked::{chapter_direct, chapter_reflect, interference, showcase, teapot};
    let (r, v) = (&job.renderer, &job.view);
    match job.scene {
        Builtin::ChapterDirect => render_in::<chapter_direct::SceneLoops>(r, v, coord, tile),
        Builtin::ChapterReflect => render_in::<chapter_reflect::SceneLoops>(r, v, coord, tile),
        Builtin::Interference => render_in::<interference::SceneLoops>(r, v, coord, tile),
        Builtin::Showcase => render_in::<showcase::SceneLoops>(r, v, coord, tile),
        Builtin::Teapot => render_in::<teapot::SceneLoops>(r, v, coord, tile),
        _ => Err(Error::NotLinked),
    }
}

/// Renders tile `coord` through `renderer` linking the tile loops of `L`.
fn render_in<L: Loops>(
    renderer: &Renderer,
    view: &SceneView<'_>,
    coord: TileCoord,
    tile: &mut Tile<TILE>,
) -> Result<(), Error> {
    renderer.render_tile_in::<L, TILE, _, _>(view, coord, tile, &mut ())
}

/// A tile's FNV-1a 64: its origin's coordinates (little-endian), then its RGB
/// bytes; summed over a frame's tiles in any order.
fn tile_hash(tile: &Tile<TILE>) -> u64 {
    let (x, y) = tile.origin();
    let mut hash = fnv1a64(FNV_START, &x.to_le_bytes());
    hash = fnv1a64(hash, &y.to_le_bytes());
    for row in tile.rows() {
        for p in row {
            hash = fnv1a64(hash, &[p.r, p.g, p.b]);
        }
    }
    hash
}

/// FNV-1a 64 of `bytes` continued from `hash`.
fn fnv1a64(hash: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(hash, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}
