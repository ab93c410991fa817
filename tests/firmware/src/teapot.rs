//! A firmware that renders only the built-in teapot, as a firmware engineer would
//! write it: the scene's few lists on the stack, its mesh and BVH in flash
//! (`tessera::builtin::TEAPOT_MESHES`), one 16x16 tile buffer in `.bss`. It renders
//! 64x64 tile after tile and prints
//!
//! `teapot pixels=<n> checksum=<fnv-1a of the RGB bytes, row-major> stack=<bytes>`
//!
//! where `stack` is the peak stack of the whole program from the top of RAM (painted
//! before rendering), so that the host can state the RAM it takes beyond the tile
//! buffer: its statics (from the ELF) plus this stack.
#![no_std]
#![no_main]

// The harness's stack painting; this firmware uses only part of it.
#[path = "stack.rs"]
#[allow(dead_code)]
mod stack;

use cortex_m_rt::{ExceptionFrame, entry, exception};
use cortex_m_semihosting::debug::{self, EXIT_FAILURE, EXIT_SUCCESS};
use cortex_m_semihosting::hprintln;
use tessera::builtin::{self, Builtin};
use tessera::{Frame, Tile, TileCoord, Viewport};

/// The image: 64x64 in 16x16 tiles.
const SIZE: u16 = 64;
const N: usize = 16;

#[entry]
fn main() -> ! {
    let status = match cortex_m::singleton!(: Tile<N> = Tile::new()) {
        Some(tile) => {
            stack::paint();
            let drawn = draw(tile);
            match (drawn, stack::lowest()) {
                (Ok(sum), Some(lowest)) => {
                    hprintln!(
                        "teapot pixels={} checksum={:08x} stack={}",
                        u32::from(SIZE) * u32::from(SIZE),
                        sum,
                        stack::top() - lowest
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
        cortex_m::asm::bkpt();
    }
}

/// Renders the teapot into `tile`, tile after tile (row-major); returns the FNV-1a
/// hash of every tile's pixels in that order, each tile's row-major (the order the
/// tiles reach a display: no frame buffer to hash the image's rows).
#[inline(never)]
fn draw(tile: &mut Tile<N>) -> Result<u32, tessera::Error> {
    let scene = builtin::teapot()?;
    let view = scene.view().with_meshes(builtin::TEAPOT_MESHES)?;
    let frame = Frame::try_new(
        scene.camera(),
        Viewport::new(SIZE, SIZE),
        Builtin::Teapot.settings(),
    )?;
    let (across, down) = frame.tile_grid(N);
    let mut hash = 0x811c_9dc5_u32;
    for ty in 0..down {
        for tx in 0..across {
            frame.render_tile(&view, TileCoord::new(tx, ty), tile, &mut ())?;
            for p in tile.pixels() {
                for byte in [p.r, p.g, p.b] {
                    hash = (hash ^ u32::from(byte)).wrapping_mul(0x0100_0193);
                }
            }
        }
    }
    Ok(hash)
}

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
