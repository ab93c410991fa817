//! tessera on a Cortex-M4F, under qemu (board mps2-an386): the scene file baked
//! into flash by build.rs is rendered tile by tile into one tile buffer, each tile
//! written to the host as part of a PPM picture (`tessera.ppm`, in qemu's working
//! folder), and the firmware prints the picture's size, its checksum, the
//! instructions the render took and the stack it needed.
//!
//! On a real board the tiles go to a display instead of the file: see
//! [`show`]. Everything else stays as it is.
#![no_std]
#![no_main]

mod clock;
mod ppm;
mod stack;

/// The scene: its tables (`SCENE`, `MATERIALS`, the meshes...) are statics in
/// flash, written by build.rs from the scene file.
mod scene {
    include!(concat!(env!("OUT_DIR"), "/scene.rs"));
}

use core::fmt;
use cortex_m_rt::{ExceptionFrame, entry, exception};
use cortex_m_semihosting::debug::{self, EXIT_FAILURE, EXIT_SUCCESS};
use cortex_m_semihosting::hprintln;
use tessera_core::{Tile, TileCoord};

/// The tile size: the scene file's `tile` (8, 16 or 32).
const N: usize = scene::TILE;

/// The picture's file on the host.
const PICTURE: &core::ffi::CStr = c"tessera.ppm";

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

fn run() -> Result<(), Error> {
    let peripherals = cortex_m::Peripherals::take().ok_or(Error::Taken)?;
    clock::start(peripherals.SYST);
    // The tile buffer, in RAM (.bss): the only pixels the firmware holds.
    let tile = cortex_m::singleton!(: Tile<N> = Tile::new()).ok_or(Error::Taken)?;

    // The scene, checked once and read where it lies, and its frame: the camera,
    // the size and the settings of the scene file.
    let view = scene::SCENE.view()?;
    let renderer = scene::SCENE.renderer()?;
    let (width, height) = (scene::WIDTH, scene::HEIGHT);
    hprintln!(
        "tessera: {}, {}x{} in {}x{} tiles",
        env!("TESSERA_SCENE_NAME"),
        width,
        height,
        N,
        N
    );

    let mut out = ppm::Ppm::create(PICTURE, width, height)?;
    let mut checksum = Fnv1a64::new();
    let mut ticks = 0;
    let (across, down) = renderer.tile_grid(N);
    for ty in 0..down {
        for tx in 0..across {
            let start = clock::ticks();
            // SceneLoops: only the tile loops this scene needs are linked.
            renderer.render_tile_in::<scene::SceneLoops, N, _, _>(
                &view,
                TileCoord::new(tx, ty),
                tile,
                &mut (),
            )?;
            ticks += clock::ticks() - start;
            show(tile, &mut out, &mut checksum)?;
        }
    }
    drop(out);

    let pixels = u64::from(width) * u64::from(height);
    let instructions = ticks * clock::INSTRUCTIONS_PER_TICK;
    let (peak, available) = (stack::peak(), stack::available());
    if peak >= available {
        return Err(Error::StackOverflow);
    }
    hprintln!("wrote {}", PICTURE.to_str().unwrap_or("the picture"));
    hprintln!("size={}x{}", width, height);
    hprintln!(
        "checksum={:016x} (FNV-1a 64 of the RGB bytes, tile after tile)",
        checksum.0
    );
    hprintln!(
        "instructions={} ({} a pixel)",
        instructions,
        instructions / pixels
    );
    hprintln!("stack={} bytes (peak, of {} free)", peak, available);
    #[cfg(feature = "instances")]
    move_an_instance(&view)?;
    Ok(())
}

/// What a frame that moves one mesh instance sets up (with the feature
/// `instances`, for a scene with `[[instance]]`s): the scene's instances
/// copied into RAM (`Instances::of`), the first one moved (`set`: its
/// transforms and its box in the world alone worked out again) and handed
/// back to the view (`with_instances`); the next frame renders through that
/// view. Prints the instructions of each step.
#[cfg(feature = "instances")]
fn move_an_instance(view: &tessera_core::SceneView<'_>) -> Result<(), Error> {
    use tessera_core::instance::{Instances, Placement};
    if view.instance_count() == 0 {
        return Ok(());
    }
    let t0 = clock::ticks();
    let mut placed: Instances<'_, 16> = Instances::of(view)?;
    let t1 = clock::ticks();
    if let Some(first) = placed.get(0) {
        let p = first.placement;
        let [x, y, z] = p.translation;
        placed.set(0, Placement::new(p.rotation, p.scale, [x + 0.1, y, z]))?;
    }
    let t2 = clock::ticks();
    let frame = view.with_instances(&placed)?;
    let t3 = clock::ticks();
    core::hint::black_box(&frame);
    let k = clock::INSTRUCTIONS_PER_TICK;
    hprintln!(
        "moving an instance: instances={} copy={} set={} view={} (instructions)",
        placed.len(),
        (t1 - t0) * k,
        (t2 - t1) * k,
        (t3 - t2) * k
    );
    Ok(())
}

/// Where a rendered tile goes: here, its rows into the PPM file at their place,
/// and into the checksum.
///
/// On a real board, send it to the display instead: the tile's rectangle
/// (`tile.origin()`, `tile.width()` x `tile.height()`) as the panel's address
/// window, then `tile.pixels()` in the panel's colours (with embedded-graphics,
/// one `display.fill_contiguous(&rectangle, colours)`; a `Tile<N, Rgb565>`
/// holds a 16-bit panel's colours already). examples/blackpill-st7789 draws on
/// an ST7789 so, through `tessera_core::display::Drawing`.
fn show(tile: &Tile<N>, out: &mut ppm::Ppm, checksum: &mut Fnv1a64) -> Result<(), Error> {
    let (x, y) = tile.origin();
    let mut bytes = [0u8; 3 * N];
    for (j, row) in tile.rows().enumerate() {
        let rgb = bytes.get_mut(..3 * row.len()).unwrap_or_default();
        for (dst, p) in rgb.chunks_exact_mut(3).zip(row) {
            dst.copy_from_slice(&[p.r, p.g, p.b]);
        }
        checksum.add(rgb);
        out.write_at(x as usize, y as usize + j, rgb)?;
    }
    Ok(())
}

/// The FNV-1a 64-bit hash.
struct Fnv1a64(u64);

impl Fnv1a64 {
    fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }

    fn add(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
        }
    }
}

enum Error {
    Tessera(tessera_core::Error),
    Io(ppm::IoError),
    Taken,
    StackOverflow,
}

impl From<tessera_core::Error> for Error {
    fn from(e: tessera_core::Error) -> Self {
        Self::Tessera(e)
    }
}

impl From<ppm::IoError> for Error {
    fn from(e: ppm::IoError) -> Self {
        Self::Io(e)
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Tessera(e) => write!(f, "tessera: {e}"),
            Self::Io(e) => write!(f, "{e} on {}", PICTURE.to_str().unwrap_or("the picture")),
            Self::Taken => f.write_str("the peripherals or the tile buffer were taken already"),
            Self::StackOverflow => f.write_str("the stack reached the statics"),
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
