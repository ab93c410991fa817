//! Host side of tessera: renders frames tile by tile with the core, assembles the
//! tiles into an [`image::RgbImage`] or streams them into a PNG a row of tiles at a
//! time ([`render_png`]), and writes files without ever leaving a half-written file
//! behind ([`output`]). What each command may ask for is bounded ([`limits`]).
//!
//! All of that is the `cli` feature's (on by default). Without it
//! (`default-features = false`, e.g. as a firmware's build-dependency) the crate
//! is the scene reader and baker alone: scene files ([`mod@file`], [`desc`],
//! [`mesh`]), the core scene they build, their warnings ([`precision`]) and
//! [`bake`], with none of the command's dependencies (image encoders, threads,
//! argument parsing, FLIP, the simulator).

// Without `cli` the links to its items (in the docs above, of limits, ...) stay
// plain text.
#![cfg_attr(not(feature = "cli"), allow(rustdoc::broken_intra_doc_links))]

/// Runs `$body` with `$n` a `const` tile size (8, 16 or 32, see [`TILE_SIZES`])
/// equal to the run-time `$tile`; another size is [`HostError::TileSize`]. The
/// one place where a tile size chosen at run time becomes the core's const
/// generic: `with_tile_size!(tile, |N| render_tiles::<N>(view, &renderer, None))`.
#[cfg(feature = "cli")]
macro_rules! with_tile_size {
    ($tile:expr, |$n:ident| $body:expr) => {
        match $tile {
            8 => {
                const $n: usize = 8;
                $body
            }
            16 => {
                const $n: usize = 16;
                $body
            }
            32 => {
                const $n: usize = 32;
                $body
            }
            n => Err($crate::HostError::TileSize(n)),
        }
    };
}

pub mod animation;
pub mod arr3;
pub mod bake;
#[cfg(feature = "cli")]
pub mod compare;
pub mod desc;
mod error;
pub mod file;
pub mod gltf;
#[cfg(feature = "cli")]
mod images;
pub mod kinds;
pub mod limits;
pub mod material_rule;
pub mod mesh;
#[cfg(feature = "cli")]
pub mod output;
#[cfg(feature = "cli")]
pub mod png;
pub mod precision;
#[cfg(feature = "cli")]
pub mod reference;
#[cfg(feature = "cli")]
pub mod simulate;
pub mod teapot;
pub mod template;
mod text;
pub mod texture_image;
#[cfg(feature = "cli")]
pub mod trade;

pub use error::{HostError, TempStep};
#[cfg(feature = "cli")]
pub use images::{
    encode_png, place, render, render_parallel, render_png, render_tiles, render_with,
    write_atomic, write_png,
};
pub use text::{escape, escape_path};

/// The tile sizes the host can render with (the core fixes the size at compile
/// time; the host instantiates these three).
pub const TILE_SIZES: [usize; 3] = [8, 16, 32];
