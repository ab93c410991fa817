//! The bench (feature `bench`, which brings `defmt` and the core's built-in
//! teapot): before the firmware draws its scene, each built-in scene
//! (`Builtin::ALL`), from the core's baked tables in flash, at [`FRAME`]
//! (240x240) with the scene's own settings, rendered tile after tile into one
//! RGB tile buffer on the stack and drawn nowhere (the panel is not set up
//! yet), each tile's render timed with the DWT cycle counter at the board's
//! [`SYSCLK_MHZ`](crate::SYSCLK_MHZ). Printed over defmt/RTT a line a scene:
//! its name, size, tiles, cycles, cycles a pixel, time and frames a second, and
//! the FNV-1a 64 checksum of the frame's RGB bytes tile after tile (each
//! tile's rows top to bottom), the host's picture's (docs/bench.md).
//!
//! The counter is checked first: read, a spin of [`SPIN`] cycles, read again.
//! If it reads zero or does not advance, the bench says so and gives no cycle
//! figure, only the checksums.

use cortex_m::peripheral::{DCB, DWT};
use tessera_core::builtin::{Builtin, baked};
use tessera_core::tile::Loops;
use tessera_core::{Error, Renderer, SceneView, Tile, TileCoord, Viewport};

/// The frame: the panel's 240x240 (docs/chip-cost.md's frames a second are at
/// this size).
const FRAME: (u16, u16) = (240, 240);
/// The tile size, the built-in scenes' own: 16x16 pixels.
const TILE: usize = 16;
/// The cycles of the spin that checks the cycle counter.
const SPIN: u32 = 500;
/// FNV-1a 64's offset basis.
const FNV_START: u64 = 0xcbf2_9ce4_8422_2325;

/// Checks the cycle counter, then renders, times and prints each built-in
/// scene; a scene tessera refuses is logged and skipped.
pub fn run(dcb: &mut DCB, dwt: &mut DWT) {
    let counting = counter_counts(dcb, dwt);
    defmt::info!(
        "bench: {=usize} built-in scene(s) at {=u16}x{=u16} in {=usize}x{=usize} tiles, each with its own settings, drawn nowhere; {=u32} MHz, flash wait states and ART as the HAL sets them",
        Builtin::ALL.len(),
        FRAME.0,
        FRAME.1,
        TILE,
        TILE,
        crate::SYSCLK_MHZ
    );
    if !counting {
        defmt::warn!(
            "bench: cycle counter absent or stopped (DWT CYCCNT did not advance across a spin of {=u32} cycles): no cycle figure is given",
            SPIN
        );
    }
    for &scene in Builtin::ALL {
        match bench(scene) {
            Ok(frame) => report(scene, &frame, counting),
            Err(e) => defmt::error!("bench: {=str}: {}", scene.name(), e),
        }
    }
}

/// Enables the cycle counter (DCB's trace enable, DWT CYCCNT) and checks that
/// it counts: read, a spin of [`SPIN`] cycles, read again; counting if it
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

/// One scene's frame: its tiles, the cycles in its render calls, its checksum.
struct Frame {
    tiles: u32,
    cycles: u64,
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
            checksum: FNV_START,
        };
        let (across, down) = renderer.tile_grid(TILE);
        for ty in 0..down {
            for tx in 0..across {
                let start = DWT::cycle_count();
                render(scene, &renderer, view, TileCoord::new(tx, ty), &mut tile)?;
                frame.cycles += u64::from(DWT::cycle_count().wrapping_sub(start));
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

/// Prints a scene's line: with the cycles, time and frames a second if the
/// counter counts, else the checksum alone.
fn report(scene: Builtin, frame: &Frame, counting: bool) {
    let pixels = u64::from(FRAME.0) * u64::from(FRAME.1);
    let hz = u64::from(crate::SYSCLK_MHZ) * 1_000_000;
    if counting {
        let tenths_ms = frame.cycles * 10_000 / hz;
        let hundredths_fps = hz * 100 / frame.cycles.max(1);
        defmt::info!(
            "bench: {=str} {=u16}x{=u16}, {=u32} tiles, one core: {=u64} cycles, {=u64} cycles/px, {=u64}.{=u64} ms, {=u64}.{=u64:02} fps at {=u32} MHz, checksum {=u64:016x}",
            scene.name(),
            FRAME.0,
            FRAME.1,
            frame.tiles,
            frame.cycles,
            frame.cycles / pixels,
            tenths_ms / 10,
            tenths_ms % 10,
            hundredths_fps / 100,
            hundredths_fps % 100,
            crate::SYSCLK_MHZ,
            frame.checksum
        );
    } else {
        defmt::info!(
            "bench: {=str} {=u16}x{=u16}, {=u32} tiles, one core: no cycle figure, checksum {=u64:016x}",
            scene.name(),
            FRAME.0,
            FRAME.1,
            frame.tiles,
            frame.checksum
        );
    }
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

/// FNV-1a 64 of `bytes` continued from `hash`.
fn fnv1a64(hash: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(hash, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    })
}
