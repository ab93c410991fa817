//! tessera on a Cortex-M4F, under qemu (board mps2-an386): the scene file baked
//! into flash by build.rs is rendered tile by tile into one tile buffer, each tile
//! written to the host as part of a PPM picture (`tessera.ppm`, in qemu's working
//! folder), and the firmware prints the picture's size, its checksum, the
//! instructions the render took and the stack it needed.
//!
//! A scene with an animation (`[[keyframes]]`) also has a few of its frames
//! written, `frame-NNN.ppm`, each with its checksum and counts ([`animation`]).
//!
//! On a real board the tiles go to a display instead of the file: see
//! [`show`]. Everything else stays as it is.
#![no_std]
#![no_main]

#[cfg(tessera_animation)]
mod animation;
mod clock;
mod ppm;
mod stack;

/// The scene: its tables (`SCENE`, `MATERIALS`, the meshes...) are statics in
/// flash, written by build.rs from the scene file.
mod scene {
    include!(concat!(env!("OUT_DIR"), "/scene.rs"));
}

use core::ffi::CStr;
use core::fmt;
use cortex_m_rt::{ExceptionFrame, entry, exception};
use cortex_m_semihosting::debug::{self, EXIT_FAILURE, EXIT_SUCCESS};
use cortex_m_semihosting::hprintln;
use tessera_core::{Renderer, SceneView, Tile, TileCoord};

/// The tile size: the scene file's `tile` (8, 16 or 32).
const N: usize = scene::TILE;

/// The picture's file on the host.
const PICTURE: &CStr = c"tessera.ppm";

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

    let (checksum, instructions) = render_picture(&view, &renderer, tile, Picture::Still)?;
    let pixels = u64::from(width) * u64::from(height);
    let (peak, available) = (stack::peak(), stack::available());
    if peak >= available {
        return Err(Error::StackOverflow);
    }
    hprintln!("wrote {}", PICTURE.to_str().unwrap_or("the picture"));
    hprintln!("size={}x{}", width, height);
    hprintln!(
        "checksum={:016x} (FNV-1a 64 of the RGB bytes, tile after tile)",
        checksum
    );
    hprintln!(
        "instructions={} ({} a pixel)",
        instructions,
        instructions / pixels
    );
    hprintln!("stack={} bytes (peak, of {} free)", peak, available);
    #[cfg(feature = "instances")]
    move_an_instance(&view)?;
    #[cfg(tessera_animation)]
    animation::play(&view, &renderer, tile)?;
    Ok(())
}

/// A picture file the firmware writes on the host.
#[derive(Clone, Copy, Debug)]
enum Picture {
    /// The scene's picture, [`PICTURE`].
    Still,
    /// Frame `n` of its animation, `frame-NNN.ppm` (at least three digits).
    #[cfg_attr(not(tessera_animation), allow(dead_code))]
    Frame(u32),
}

impl fmt::Display for Picture {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Still => f.write_str(PICTURE.to_str().unwrap_or("the picture")),
            Self::Frame(n) => write!(f, "frame-{n:03}.ppm"),
        }
    }
}

/// Renders the frame of `renderer` through `view`, tile after tile into `tile`,
/// each tile written to the file `picture` ([`show`]). Returns the picture's
/// checksum and the instructions the render took.
fn render_picture(
    view: &SceneView<'_>,
    renderer: &Renderer,
    tile: &mut Tile<N>,
    picture: Picture,
) -> Result<(u64, u64), Error> {
    let vp = renderer.viewport();
    // The name, NUL-terminated, as semihosting takes it.
    let mut name = Name::default();
    fmt::write(&mut name, format_args!("{picture}\0")).map_err(|_| Error::Name(picture))?;
    let name = CStr::from_bytes_with_nul(name.bytes()).map_err(|_| Error::Name(picture))?;
    let io = |e| Error::Io(e, picture);
    let mut out = ppm::Ppm::create(name, vp.width, vp.height).map_err(io)?;
    let mut checksum = Fnv1a64::new();
    let mut ticks = 0;
    let (across, down) = renderer.tile_grid(N);
    for ty in 0..down {
        for tx in 0..across {
            let start = clock::ticks();
            // SceneLoops: only the tile loops this scene needs are linked.
            renderer.render_tile_in::<scene::SceneLoops, N, _, _>(
                view,
                TileCoord::new(tx, ty),
                tile,
                &mut (),
            )?;
            ticks += clock::ticks() - start;
            show(tile, &mut out, &mut checksum).map_err(io)?;
        }
    }
    Ok((checksum.0, ticks * clock::INSTRUCTIONS_PER_TICK))
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
fn show(tile: &Tile<N>, out: &mut ppm::Ppm, checksum: &mut Fnv1a64) -> Result<(), ppm::IoError> {
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

/// A file name, formatted in place (at most 32 bytes).
#[derive(Default)]
struct Name {
    bytes: [u8; 32],
    len: usize,
}

impl Name {
    fn bytes(&self) -> &[u8] {
        self.bytes.get(..self.len).unwrap_or_default()
    }
}

impl fmt::Write for Name {
    fn write_str(&mut self, s: &str) -> fmt::Result {
        let end = self.len + s.len();
        let room = self.bytes.get_mut(self.len..end).ok_or(fmt::Error)?;
        room.copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
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
    /// A semihosting call failed on this file.
    Io(ppm::IoError, Picture),
    /// This file's name did not fit its buffer.
    Name(Picture),
    Taken,
    StackOverflow,
}

impl From<tessera_core::Error> for Error {
    fn from(e: tessera_core::Error) -> Self {
        Self::Tessera(e)
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Tessera(e) => write!(f, "tessera: {e}"),
            Self::Io(e, picture) => write!(f, "{e} on {picture}"),
            Self::Name(picture) => write!(f, "the file name {picture} is too long"),
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
