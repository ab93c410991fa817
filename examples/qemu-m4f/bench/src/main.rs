//! A bench for any Cortex-M with a cycle counter: each built-in scene the build
//! has (`Builtin::ALL`: the teapot with the feature `teapot`), from the core's
//! baked tables, at 240x240 with the scene's own settings, rendered tile after
//! tile into one RGB tile buffer and drawn nowhere. Each tile's render is timed
//! with the DWT cycle counter (CYCCNT); the firmware prints, over semihosting,
//! each scene's size, tiles, cycles, cycles a pixel, time and frames a second at
//! [`CLOCK_HZ`], and the FNV-1a 64 checksum of the frame's RGB bytes in the
//! order the qemu example sums them (tile after tile, each tile's rows top to
//! bottom): the host's picture has the same (docs/bench.md).
//!
//! The firmware sets no clock up: the core runs at its reset clock, which
//! [`CLOCK_HZ`] must name for the time and the frames a second to be right
//! (the cycles do not depend on it).
//!
//! The counter is checked before it is believed: enabled (DCB trace, DWT
//! CYCCNT), read, a spin of [`SPIN`] cycles, read again. Where it reads zero
//! or does not advance (qemu 7.2 has no DWT; a core built without one), the
//! firmware says so and gives no cycle figure, only the checksum and SysTick's
//! count, which is the render's instructions under qemu's `-icount shift=0`
//! (this folder's runner).
#![no_std]
#![no_main]

#[path = "../../src/clock.rs"]
mod clock;

use core::fmt;
use cortex_m::peripheral::{DCB, DWT};
use cortex_m_rt::{ExceptionFrame, entry, exception};
use cortex_m_semihosting::debug::{self, EXIT_FAILURE, EXIT_SUCCESS};
use cortex_m_semihosting::hprintln;
use tessera_core::builtin::{Builtin, baked};
use tessera_core::tile::Loops;
use tessera_core::{Error, Renderer, SceneView, Tile, TileCoord, Viewport};

/// The frame: the 240x240 of the boards' panels (docs/chip-cost.md's frames a
/// second are at this size).
const FRAME: (u16, u16) = (240, 240);
/// The tile size, the built-in scenes' own: 16x16 pixels.
const TILE: usize = 16;
/// The core's clock in Hz, for the time and the frames a second: qemu's
/// mps2-an386 runs its Cortex-M4 at 25 MHz. On a board, its reset clock (an
/// STM32F411's internal oscillator: 16 MHz).
const CLOCK_HZ: u32 = 25_000_000;
/// The cycles of the spin that checks the cycle counter.
const SPIN: u32 = 500;

#[entry]
fn main() -> ! {
    let status = match run() {
        Ok(()) => EXIT_SUCCESS,
        Err(e) => {
            hprintln!("error: {}", e);
            EXIT_FAILURE
        }
    };
    debug::exit(status);
    loop {
        cortex_m::asm::bkpt();
    }
}

fn run() -> Result<(), Failure> {
    let mut cp = cortex_m::Peripherals::take().ok_or(Failure::Taken)?;
    clock::start(cp.SYST);
    let counting = start_cycle_counter(&mut cp.DCB, &mut cp.DWT);
    hprintln!(
        "bench: {} built-in scene(s) at {}x{} in {}x{} tiles, each with its own settings, drawn nowhere; clock {} MHz",
        Builtin::ALL.len(),
        FRAME.0,
        FRAME.1,
        TILE,
        TILE,
        CLOCK_HZ / 1_000_000
    );
    match counting {
        Counter::Counting => hprintln!("cycle counter: DWT CYCCNT counts"),
        Counter::Stopped { before, after } => hprintln!(
            "cycle counter: absent or stopped (DWT CYCCNT read {} then {} across a spin of {} cycles): no cycle figure is given; instructions are SysTick's, 40 a tick under qemu's -icount shift=0",
            before,
            after,
            SPIN
        ),
    }
    for &scene in Builtin::ALL {
        report(scene, &bench(scene)?, counting);
    }
    Ok(())
}

/// Prints a scene's line: its cycles, time and frames a second if the counter
/// counts, else SysTick's instructions; its checksum.
fn report(scene: Builtin, frame: &Frame, counting: Counter) {
    let pixels = u64::from(FRAME.0) * u64::from(FRAME.1);
    if counting == Counter::Counting {
        hprintln!(
            "{}: {}x{}, {} tiles, one core: cycles={} ({} a pixel), {} ms, {} fps at {} MHz, checksum={:016x}",
            scene.name(),
            FRAME.0,
            FRAME.1,
            frame.tiles,
            frame.cycles,
            frame.cycles / pixels,
            Decimal::ms(frame.cycles),
            Decimal::fps(frame.cycles),
            CLOCK_HZ / 1_000_000,
            frame.checksum
        );
    } else {
        let instructions = frame.ticks * clock::INSTRUCTIONS_PER_TICK;
        hprintln!(
            "{}: {}x{}, {} tiles, one core: no cycle figure, instructions={} ({} a pixel), checksum={:016x}",
            scene.name(),
            FRAME.0,
            FRAME.1,
            frame.tiles,
            instructions,
            instructions / pixels,
            frame.checksum
        );
    }
}

/// What the check of the cycle counter found.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Counter {
    /// It advanced across the spin.
    Counting,
    /// It read these two values across the spin: zero, or not advancing.
    Stopped { before: u32, after: u32 },
}

/// Enables the cycle counter (DWT's software lock opened, as a Cortex-M7 needs;
/// DCB's trace enable; CYCCNT) and checks that it counts: read, a spin of
/// [`SPIN`] cycles, read again; counting only if it advanced by at least half
/// the spin.
fn start_cycle_counter(dcb: &mut DCB, dwt: &mut DWT) -> Counter {
    DWT::unlock();
    dcb.enable_trace();
    if DWT::has_cycle_counter() {
        dwt.enable_cycle_counter();
    }
    let before = DWT::cycle_count();
    cortex_m::asm::delay(SPIN);
    let after = DWT::cycle_count();
    if after.wrapping_sub(before) >= SPIN / 2 {
        Counter::Counting
    } else {
        Counter::Stopped { before, after }
    }
}

/// One scene's frame: its tiles, the cycles and SysTick ticks in its render
/// calls, and its checksum.
struct Frame {
    tiles: u32,
    cycles: u64,
    ticks: u64,
    checksum: u64,
}

/// Renders `scene` at [`FRAME`] with its own settings, tile after tile, timing
/// each tile's render alone (not the checksum's sums between them).
fn bench(scene: Builtin) -> Result<Frame, Error> {
    scene.with_baked_scene(|view, camera| {
        let renderer =
            Renderer::try_new(camera, Viewport::new(FRAME.0, FRAME.1), scene.settings())?;
        let mut tile = Tile::<TILE>::new();
        let mut frame = Frame {
            tiles: 0,
            cycles: 0,
            ticks: 0,
            checksum: FNV_START,
        };
        let (across, down) = renderer.tile_grid(TILE);
        for ty in 0..down {
            for tx in 0..across {
                let (c0, t0) = (DWT::cycle_count(), clock::ticks());
                render(scene, &renderer, view, TileCoord::new(tx, ty), &mut tile)?;
                let (c1, t1) = (DWT::cycle_count(), clock::ticks());
                frame.cycles += u64::from(c1.wrapping_sub(c0));
                frame.ticks += t1 - t0;
                frame.tiles += 1;
                for row in tile.rows() {
                    for p in row {
                        frame.checksum = fnv1a64(frame.checksum, &[p.r, p.g, p.b]);
                    }
                }
            }
        }
        Ok(frame)
    })?
}

/// Renders tile `coord` of `scene` with the tile loops its baked module names
/// (`SceneLoops`: what a firmware of that scene alone links). A built-in scene
/// this bench does not know: [`Error::NotLinked`].
fn render(
    scene: Builtin,
    renderer: &Renderer,
    view: &SceneView<'_>,
    coord: TileCoord,
    tile: &mut Tile<TILE>,
) -> Result<(), Error> {
    use baked::{chapter_direct, chapter_reflect, interference, showcase};
    let (r, v) = (renderer, view);
    match scene {
        Builtin::ChapterDirect => render_in::<chapter_direct::SceneLoops>(r, v, coord, tile),
        Builtin::ChapterReflect => render_in::<chapter_reflect::SceneLoops>(r, v, coord, tile),
        Builtin::Interference => render_in::<interference::SceneLoops>(r, v, coord, tile),
        Builtin::Showcase => render_in::<showcase::SceneLoops>(r, v, coord, tile),
        #[cfg(feature = "teapot")]
        Builtin::Teapot => render_in::<baked::teapot::SceneLoops>(r, v, coord, tile),
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

/// FNV-1a 64's offset basis.
const FNV_START: u64 = 0xcbf2_9ce4_8422_2325;

/// FNV-1a 64 of `bytes` continued from `hash`.
fn fnv1a64(hash: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(hash, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}

/// A number of `places` decimal places, held as an integer of that many
/// more digits (no float formatting is linked).
struct Decimal {
    value: u64,
    places: u32,
}

impl Decimal {
    /// A frame of `cycles` in ms at [`CLOCK_HZ`], to a tenth.
    fn ms(cycles: u64) -> Self {
        let value = cycles * 10_000 / u64::from(CLOCK_HZ);
        Self { value, places: 1 }
    }

    /// Frames a second at [`CLOCK_HZ`] for a frame of `cycles`, to a hundredth.
    fn fps(cycles: u64) -> Self {
        let value = u64::from(CLOCK_HZ) * 100 / cycles.max(1);
        Self { value, places: 2 }
    }
}

impl fmt::Display for Decimal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let unit = 10_u64.pow(self.places);
        let width = self.places as usize;
        write!(f, "{}.{:0width$}", self.value / unit, self.value % unit)
    }
}

/// What stops the bench.
enum Failure {
    /// tessera refused a scene or a tile.
    Tessera(Error),
    /// The core peripherals were taken already.
    Taken,
}

impl From<Error> for Failure {
    fn from(e: Error) -> Self {
        Self::Tessera(e)
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Tessera(e) => write!(f, "tessera: {e}"),
            Self::Taken => f.write_str("the core peripherals were taken already"),
        }
    }
}

/// A fault (a bad memory access, say): reported, and qemu exits with a failure.
#[exception]
unsafe fn HardFault(frame: &ExceptionFrame) -> ! {
    hprintln!("hard fault: {:?}", frame);
    debug::exit(EXIT_FAILURE);
    loop {
        cortex_m::asm::bkpt();
    }
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo<'_>) -> ! {
    cortex_m::interrupt::disable();
    hprintln!("panic: {}", info);
    debug::exit(EXIT_FAILURE);
    loop {
        cortex_m::asm::bkpt();
    }
}
