//! A firmware that renders only the built-in teapot, as a firmware engineer would
//! write it: the whole scene baked in flash (`tessera_core::builtin::baked::teapot`,
//! what `tessera bake scenes/teapot.toml` writes: no byte of the scene in RAM), one
//! 16x16 tile buffer in `.bss`. It renders
//! 64x64 tile after tile and prints
//!
//! `teapot pixels=<n> checksum=<fnv-1a of the RGB bytes, row-major> stack=<bytes>
//! preview=<instructions> render=<instructions>`
//!
//! where `stack` is the peak stack of the whole program from the top of RAM (painted
//! before rendering), so that the host can state the RAM it takes beyond the tile
//! buffer: its statics (from the ELF) plus this stack; `preview` the instructions
//! (the clock under `-icount shift=0`: SysTick, 40 a tick on mps2-an386) of a
//! progressive first picture (one ray per 4x4 block, `Renderer::preview_color`) and
//! `render` those of the tiles.
#![no_std]
#![no_main]

// The harness's stack painting; this firmware uses only part of it.
#[path = "stack.rs"]
#[allow(dead_code)]
mod stack;

// The test image's fault and panic handlers.
#[cfg_attr(target_arch = "arm", path = "faults.rs")]
#[cfg_attr(target_arch = "riscv32", path = "riscv/faults.rs")]
mod faults;

// The clocks' tick rates.
#[path = "protocol.rs"]
#[allow(dead_code)]
mod protocol;

// Instruction counting, as the test image's.
#[cfg_attr(target_arch = "arm", path = "clock.rs")]
#[cfg_attr(target_arch = "riscv32", path = "riscv/clock.rs")]
#[allow(dead_code)]
mod clock;

#[cfg(target_arch = "arm")]
use cortex_m_rt::entry;
#[cfg(target_arch = "arm")]
use cortex_m_semihosting::{
    debug::{self, EXIT_FAILURE, EXIT_SUCCESS},
    hprintln,
};
#[cfg(target_arch = "riscv32")]
use riscv_rt::entry;
#[cfg(target_arch = "riscv32")]
use riscv_semihosting::{
    debug::{self, EXIT_FAILURE, EXIT_SUCCESS},
    hprintln,
};
use tessera_core::builtin::baked::teapot::SCENE;
use tessera_core::{Tile, TileCoord, Viewport};

/// The image: 64x64 in 16x16 tiles.
const SIZE: u16 = 64;
const N: usize = 16;

#[cfg(target_arch = "arm")]
#[entry]
fn main() -> ! {
    let peripherals = cortex_m::Peripherals::take();
    let status = match (cortex_m::singleton!(: Tile<N> = Tile::new()), peripherals) {
        (Some(tile), Some(p)) => {
            clock::start(p.SYST);
            stack::paint();
            let drawn = draw(tile);
            match (drawn, stack::lowest()) {
                (Ok((sum, preview, render)), Some(lowest)) => {
                    hprintln!(
                        "teapot pixels={} checksum={:08x} stack={} preview={} render={}",
                        u32::from(SIZE) * u32::from(SIZE),
                        sum,
                        stack::top() - lowest,
                        clock::RATE.instructions(preview),
                        clock::RATE.instructions(render)
                    );
                    EXIT_SUCCESS
                }
                (Err(e), _) => {
                    hprintln!("error: tessera: {}", e);
                    EXIT_FAILURE
                }
                (_, None) => {
                    hprintln!("error: the stack reached the statics");
                    EXIT_FAILURE
                }
            }
        }
        _ => EXIT_FAILURE,
    };
    debug::exit(status);
    loop {
        cortex_m::asm::bkpt();
    }
}

#[cfg(target_arch = "riscv32")]
#[entry]
fn main() -> ! {
    let status = match riscv::singleton!(: Tile<N> = Tile::new()) {
        Some(tile) => {
            clock::start();
            stack::paint();
            let drawn = draw(tile);
            match (drawn, stack::lowest()) {
                (Ok((sum, preview, render)), Some(lowest)) => {
                    hprintln!(
                        "teapot pixels={} checksum={:08x} stack={} preview={} render={}",
                        u32::from(SIZE) * u32::from(SIZE),
                        sum,
                        stack::top() - lowest,
                        clock::RATE.instructions(preview),
                        clock::RATE.instructions(render)
                    );
                    EXIT_SUCCESS
                }
                (Err(e), _) => {
                    hprintln!("error: tessera: {}", e);
                    EXIT_FAILURE
                }
                (_, None) => {
                    hprintln!("error: the stack reached the statics");
                    EXIT_FAILURE
                }
            }
        }
        None => EXIT_FAILURE,
    };
    debug::exit(status);
    loop {
        riscv::asm::wfi();
    }
}

/// A progressive first picture (one ray per 4x4 block), then the teapot into
/// `tile`, tile after tile (row-major); returns the FNV-1a hash of every tile's
/// pixels in that order, each tile's row-major (the order the tiles reach a
/// display: no frame buffer to hash the image's rows), and the SysTick ticks of
/// the preview and of the tiles.
#[inline(never)]
fn draw(tile: &mut Tile<N>) -> Result<(u32, u64, u64), tessera_core::Error> {
    // The scene's tables where they lie (checked once), at its own settings.
    let view = SCENE.view()?;
    let renderer = SCENE.renderer_at(Viewport::new(SIZE, SIZE), SCENE.settings())?;
    let t0 = clock::now();
    let mut blocks = 0u32;
    for by in 0..u32::from(SIZE).div_ceil(4) {
        for bx in 0..u32::from(SIZE).div_ceil(4) {
            let c = renderer.preview_color(&view, (bx, by), 4, &mut ());
            let c = renderer.settings().encoding.encode(c);
            // Kept (a display would get it): the work cannot be optimised away.
            blocks = blocks.wrapping_add(u32::from(c.r) + u32::from(c.g) + u32::from(c.b));
        }
    }
    let preview = clock::now() - t0;
    core::hint::black_box(blocks);
    let t0 = clock::now();
    let (across, down) = renderer.tile_grid(N);
    let mut hash = 0x811c_9dc5_u32;
    for ty in 0..down {
        for tx in 0..across {
            renderer.render_tile(&view, TileCoord::new(tx, ty), tile, &mut ())?;
            for p in tile.pixels() {
                for byte in [p.r, p.g, p.b] {
                    hash = (hash ^ u32::from(byte)).wrapping_mul(0x0100_0193);
                }
            }
        }
    }
    Ok((hash, preview, clock::now() - t0))
}
