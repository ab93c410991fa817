//! # tessera: a ray tracer for microcontrollers
//!
//! `tessera` renders a ray-traced scene one fixed-size **tile** at a time, with `f32`
//! math and fixed-capacity scene lists, so that a chip with a few KiB of RAM and no
//! framebuffer can draw straight onto its display. There is no allocator, no `std`,
//! no panicking path and two audited `unsafe` spots (the FPU square roots, Arm's
//! `vsqrt.f32` and RISC-V's `fsqrt.s`).
//!
//! Why this shape: a 240x240 RGB framebuffer is 169 KiB, more than most small MCUs
//! have. A tile of 16x16 pixels is 776 bytes; the caller owns it, renders tile
//! `(tx, ty)` into it and sends it to the display before rendering the next one. A
//! pixel depends only on the scene, the camera, the settings and its coordinates, so
//! tiles may be rendered in any order, at any size, on any number of cores.
//!
//! The model is the course chapter "Le ray tracer en infographie": camera, viewport
//! (`N_L x N_H` pixels), view frustum (near/far planes, vertical opening angle), the
//! ray equation `r = r0 + v t`, geometries, materials, primitives, lights and a
//! Whitted-style shader with reflection and transmission.
//!
//! ```
//! use tessera::{builtin, RenderSettings, Tile, TileCoord, Viewport};
//!
//! let scene = builtin::chapter_direct()?;
//! let frame = scene.frame(Viewport::new(40, 30), RenderSettings::default())?;
//! let mut tile = Tile::<16>::new();
//! frame.render_tile(&scene.view(), TileCoord::new(2, 1), &mut tile, &mut ())?;
//! // The last tile of a 40-pixel-wide frame holds 8 columns and 14 rows.
//! assert_eq!((tile.width(), tile.height()), (8, 14));
//! # Ok::<(), tessera::Error>(())
//! ```
#![no_std]
#![deny(missing_docs)]
#![deny(unsafe_code)]
#![cfg_attr(
    not(test),
    deny(
        clippy::unwrap_used,
        clippy::expect_used,
        clippy::panic,
        clippy::indexing_slicing,
        clippy::unreachable,
        clippy::todo,
        clippy::unimplemented,
    )
)]

// The public API is the re-exports below (and the built-in scenes): the modules
// are private, so what a firmware author sees in `tessera::` is what they use.
mod baked;
pub mod builtin;
#[cfg(feature = "bvh")]
mod bvh;
mod camera;
mod color;
mod cull;
mod display;
mod dither;
mod error;
#[cfg(feature = "testing")]
mod extreme;
mod geometry;
mod hit;
mod light;
mod material;
mod math;
#[cfg(feature = "bvh")]
mod mesh;
mod prefilter;
mod primitive;
mod ray;
mod sample;
mod scene;
mod search;
mod shade;
mod texture;
mod tile;
mod vec;
mod view;

pub use baked::{BakedCamera, BakedScene};
#[cfg(feature = "bvh")]
pub use bvh::{
    BakedBvh, Bounded, Bvh, BvhNode, CROSSOVER as BVH_CROSSOVER,
    SPHERE_CROSSOVER as BVH_SPHERE_CROSSOVER,
};
pub use camera::{Camera, CameraBasis, Viewport};
pub use color::{Color, Encoding, Rgb8, UnknownEncoding};
pub use display::{
    DitheredRendering, ProgressiveRendering, Rendering, draw_panel_tile, draw_tile,
    draw_tile_dithered,
};
pub use dither::{Dither, UnknownDither};
pub use error::{Error, Field, List, MAX_COLOR, MAX_DEPTH, MAX_EXTENT, MIN_LENGTH};
pub use geometry::{Aabb, Plane, Sphere, Triangle};
pub use light::PointLight;
pub use material::{Material, MaterialId};
#[cfg(feature = "bvh")]
pub use mesh::{MAX_MESHES, Mesh};
pub use primitive::Primitive;
pub use ray::Ray;
pub use sample::{Sampler, SubPixel};
pub use scene::Scene;
pub use shade::{RayCount, RayCounter};
pub use texture::Texture;
pub use tile::{AllLoops, Frame, Loops, RenderSettings, Tile, TileCoord, TileLoop, TilePixel};
pub use vec::Vec3;
pub use view::SceneView;

/// One ray at a time, outside the tile loop: what a ray hits first, and the colour
/// it brings back (with every primitive a candidate: no tile lists).
pub mod trace {
    pub use crate::ray::Ray;
    pub use crate::search::first_hit;
    pub use crate::shade::{RayCount, RayCounter, trace};
}

/// The Rust examples of the repository's README.md, compiled by `cargo test -p
/// tessera --doc`: under `cfg(doctest)` only, so not part of the API (and
/// README.md, outside this package, is read only by the doctests).
#[cfg(doctest)]
#[doc = include_str!("../../README.md")]
pub struct ReadmeExamples;

/// Internals that the test crates check on their own (the extremes battery, the
/// benchmarks, the firmware test image's scaled scenes), with the feature `testing`
/// only: not part of the API, and not kept stable.
#[cfg(feature = "testing")]
#[doc(hidden)]
pub mod testing {
    /// How many BVH nodes the searches have tested so far, and how many searches
    /// went through a BVH (the BVH's cost per ray; counted only with this feature).
    #[cfg(feature = "bvh")]
    pub use crate::bvh::visits;
    pub use crate::extreme::Extreme;
    pub use crate::geometry::{Candidate, Shape, Surface};
    /// The square root of every per-pixel path (`math::sqrt`): the firmware test
    /// image checks on each core that it is correctly rounded.
    pub use crate::math::sqrt;
    pub use crate::ray::offset_origin;
    pub use crate::shade::refract;
}
