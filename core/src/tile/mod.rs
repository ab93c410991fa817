//! Frames and tiles: the contract between the renderer and whoever owns the pixels.
//!
//! A [`Renderer`] is the camera basis and the render settings, checked once. The caller
//! owns a [`Tile<N>`] buffer (`N x N` pixels, `N` fixed at compile time) and asks the
//! frame to render tile `(tx, ty)` into it, in any order. No allocation, no
//! framebuffer: the RAM is one tile buffer plus the renderer's stack.
//!
//! | tile  | buffer (`size_of::<Tile<N>>()`) |
//! |-------|---------------------------------|
//! | 8x8   | 200 bytes                       |
//! | 16x16 | 776 bytes                       |
//! | 32x32 | 3,080 bytes                     |
//!
//! (3 bytes a pixel plus 8 bytes of coordinates; a unit test checks these sizes
//! and `tests/tests/docs.rs` checks them against `docs/chip-cost.md`.) The
//! renderer's stack does not depend on `N` (but for the sparse sampler's three
//! rows of traced pixels: `16 N` bytes from tiles of 30, `24 N` below):
//! measured on a Cortex-M4F (qemu, stack painting; `docs/chip-cost.md` has
//! each scene's), `render_tile` needs under 3
//! KiB below its caller, the tile's culling lists (the primitives that may
//! reach the tile, module `cull`) and the shader's pending-ray stack
//! (`MAX_DEPTH + 1` rays) included.

mod adaptive;
mod buffer;
#[cfg(feature = "instances")]
mod changes;
mod pass;
mod queue;
mod renderer;
mod settings;
mod sparse;
#[cfg(test)]
mod tests;

pub use buffer::{Tile, TileCoord, TilePixel};
#[cfg(feature = "instances")]
pub use changes::{Moved, moved_instances};
pub use queue::Interleave;
#[cfg(target_has_atomic = "32")]
pub use queue::TileQueue;
pub use renderer::Renderer;
pub use settings::{AllLoops, Loops, RenderSettings, TileLoop};
