//! # tessera: a ray tracer for microcontrollers
//!
//! `tessera` renders a ray-traced scene one fixed-size **tile** at a time, with `f32`
//! math and fixed-capacity scene lists, so that a chip with a few KiB of RAM and no
//! framebuffer can draw straight onto its display. There is no allocator, no `std`,
//! no panicking path and four audited `unsafe` spots (the FPU square roots, Arm's
//! `vsqrt.f32` and RISC-V's `fsqrt.s`; a panel tile's pixels seen as bytes,
//! `display::wire_bytes`; and `Drawing::send` lending those bytes to a DMA
//! transfer, `display::TileSink::start`).
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
//! use tessera_core::{builtin, RenderSettings, Tile, TileCoord, Viewport};
//!
//! let scene = builtin::chapter_direct()?;
//! let renderer = scene.renderer(Viewport::new(40, 30), RenderSettings::default())?;
//! let mut tile = Tile::<16>::new();
//! renderer.render_tile(&scene.view(), TileCoord::new(2, 1), &mut tile, &mut ())?;
//! // The last tile of a 40-pixel-wide frame holds 8 columns and 14 rows.
//! assert_eq!((tile.width(), tile.height()), (8, 14));
//! # Ok::<(), tessera_core::Error>(())
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

// The public API: a small root for the firmware author (the scene and its view,
// the frame and its tiles, the camera and viewport, the settings, the errors, the
// built-in scenes) and one public module per concept; the other modules are the
// renderer's internals.
#[cfg(feature = "animation")]
pub mod animation;
mod baked;
pub mod builtin;
#[cfg(feature = "bvh")]
pub mod bvh;
pub mod camera;
pub mod color;
mod cull;
pub mod display;
pub mod dither;
pub mod error;
#[cfg(feature = "testing")]
mod extreme;
pub mod geometry;
mod hit;
#[cfg(feature = "image")]
pub mod image;
#[cfg(feature = "instances")]
pub mod instance;
pub mod kind;
pub mod light;
pub mod material;
mod math;
#[cfg(feature = "bvh")]
pub mod mesh;
mod prefilter;
mod primitive;
mod ray;
pub mod sample;
mod scene;
mod search;
mod shade;
pub mod texture;
pub mod tile;
mod vec;
mod view;

pub use baked::{BakedCamera, BakedScene};
pub use camera::{Camera, Viewport};
pub use color::{Color, Encoding};
pub use error::Error;
pub use kind::{Capacities, Geometry, Primitives};
pub use primitive::Primitive;
pub use sample::Sampler;
pub use scene::Scene;
#[cfg(feature = "instances")]
pub use tile::{Moved, moved_instances};
pub use tile::{RenderSettings, Renderer, Tile, TileCoord};
pub use vec::Vec3;
pub use view::SceneView;

/// One ray at a time, outside the tile loop: what a ray hits first, and the colour
/// it brings back (with every primitive a candidate: no tile lists).
pub mod trace {
    pub use crate::ray::Ray;
    pub use crate::search::first_hit;
    pub use crate::shade::{RayCount, RayCounter, trace};
}

/// Internals that the test crates check on their own (the extremes battery, the
/// benchmarks, the firmware test image's scaled scenes), with the feature `testing`
/// only: not part of the API, and not kept stable. The hooks on scenes and views
/// are traits here ([`testing::SceneHooks`], [`testing::BuiltinHooks`],
/// [`testing::ViewHooks`]), so the feature adds no method to a public type.
#[cfg(feature = "testing")]
#[doc(hidden)]
pub mod testing {
    /// How many BVH nodes the searches have tested so far, and how many searches
    /// went through a BVH (the BVH's cost per ray; counted only with the feature
    /// `visit-count`).
    #[cfg(feature = "visit-count")]
    pub use crate::bvh::visits;
    pub use crate::extreme::Extreme;
    pub use crate::geometry::shape::{Candidate, Shape, Surface};
    /// The square root of every per-pixel path (`math::sqrt`): the firmware test
    /// image checks on each core that it is correctly rounded.
    pub use crate::math::sqrt;
    use crate::{Camera, Error, Scene, SceneView, builtin::Builtin};

    /// A scene's test hook: [`SceneHooks::scaled_pow2`].
    pub trait SceneHooks: Sized {
        /// The same scene with every length multiplied by `2^k` and every light
        /// intensity by `4^k`, so that the image is unchanged in exact arithmetic
        /// (each value checked again).
        ///
        /// # Errors
        /// A scaled value out of the supported range.
        fn scaled_pow2(&self, k: i32) -> Result<Self, Error>;
    }

    impl<C: crate::Capacities> SceneHooks for Scene<C> {
        fn scaled_pow2(&self, k: i32) -> Result<Self, Error> {
            self.scaled_pow2_hook(k)
        }
    }

    /// A built-in scene's test hook: [`BuiltinHooks::with_scaled_scene`].
    pub trait BuiltinHooks {
        /// [`Builtin::with_scene`] with the scene scaled by `2^k`
        /// ([`SceneHooks::scaled_pow2`]).
        ///
        /// # Errors
        /// As [`Builtin::with_scene`], and a scale out of range.
        fn with_scaled_scene<R>(
            self,
            k: i32,
            f: impl FnOnce(&SceneView<'_>, &Camera) -> R,
        ) -> Result<R, Error>;
    }

    impl BuiltinHooks for Builtin {
        fn with_scaled_scene<R>(
            self,
            k: i32,
            f: impl FnOnce(&SceneView<'_>, &Camera) -> R,
        ) -> Result<R, Error> {
            self.with_scaled_scene_hook(k, f)
        }
    }

    /// A scene view's test hooks: its searches with the culling bounds off and
    /// with or without hierarchies whatever their size.
    pub trait ViewHooks<'a>: Sized {
        /// The same view with every culling bound off (no tile lists, no list
        /// hull): the same bytes, slower.
        fn without_culling(&self) -> Self;
        /// `with_bvh` whatever the number of triangles.
        ///
        /// # Errors
        /// As `SceneView::with_bvh`.
        #[cfg(feature = "bvh")]
        fn with_bvh_always<const N: usize, const T: usize>(
            &self,
            bvh: &'a crate::bvh::Bvh<N, T>,
        ) -> Result<Self, Error>;
        /// The same view without its hierarchies.
        #[cfg(feature = "bvh")]
        fn without_bvh(&self) -> Self;
        /// `with_sphere_bvh` whatever the number of spheres.
        ///
        /// # Errors
        /// As `SceneView::with_sphere_bvh`.
        #[cfg(feature = "bvh")]
        fn with_sphere_bvh_always<const N: usize, const T: usize>(
            &self,
            bvh: &'a crate::bvh::Bvh<N, T>,
        ) -> Result<Self, Error>;
    }

    impl<'a> ViewHooks<'a> for SceneView<'a> {
        fn without_culling(&self) -> Self {
            self.without_culling_hook()
        }
        #[cfg(feature = "bvh")]
        fn with_bvh_always<const N: usize, const T: usize>(
            &self,
            bvh: &'a crate::bvh::Bvh<N, T>,
        ) -> Result<Self, Error> {
            self.with_bvh_always_hook(bvh)
        }
        #[cfg(feature = "bvh")]
        fn without_bvh(&self) -> Self {
            self.without_bvh_hook()
        }
        #[cfg(feature = "bvh")]
        fn with_sphere_bvh_always<const N: usize, const T: usize>(
            &self,
            bvh: &'a crate::bvh::Bvh<N, T>,
        ) -> Result<Self, Error> {
            self.with_sphere_bvh_always_hook(bvh)
        }
    }

    pub use crate::ray::offset_origin;
    pub use crate::shade::refract;
}
