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
//! renderer's stack does not depend on `N` (but for the sparse sampler's two rows
//! of traced pixels, `16 N` bytes): measured on a Cortex-M4F (qemu, stack
//! painting; `docs/chip-cost.md`), `render_tile` needs 1,552 to 2,528 bytes (1.5
//! to 2.5 KiB) below its caller, the tile's culling lists (the primitives that may
//! reach the tile, module `cull`) and the shader's pending-ray stack
//! (`MAX_DEPTH + 1` rays) included.

use crate::camera::{Camera, CameraBasis, Viewport};
use crate::color::{Color, Encoding, Rgb8};
use crate::cull::{Picks, TileLists};
use crate::dither::Dither;
use crate::error::Error;
use crate::error::MAX_DEPTH;
use crate::prefilter::Footprint;
use crate::sample::{PixelHash, Sampler, stratified, stratum};
use crate::shade::{CameraRay, Observer, RayCounter, Signature, trace_with};
use crate::view::SceneView;
use sparse::{Grid, Parents, sparse_blend, sparse_parents};

mod sparse;

/// How a frame is rendered.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderSettings {
    /// Where the rays go in each pixel.
    pub sampler: Sampler,
    /// Reflection/transmission bounces (0 = direct illumination only), at most
    /// [`MAX_DEPTH`].
    pub max_depth: u8,
    /// Seed of the random samplers.
    pub seed: u32,
    /// How the pixels' linear colours become 8 bits (default sRGB, what displays
    /// expect).
    pub encoding: Encoding,
}

impl Default for RenderSettings {
    /// Pixel centres, 3 bounces, seed 0, sRGB.
    fn default() -> Self {
        Self {
            sampler: Sampler::Centre,
            max_depth: 3,
            seed: 0,
            encoding: Encoding::Srgb,
        }
    }
}

impl RenderSettings {
    /// Checks the sampler and the depth.
    pub fn validate(&self) -> Result<(), Error> {
        self.sampler.validate()?;
        if self.max_depth > MAX_DEPTH {
            return Err(Error::DepthTooLarge {
                depth: self.max_depth,
            });
        }
        Ok(())
    }
}

/// One instantiation of a tile's pixel loop: the loop without bounces or with them
/// (mirrors or glass within the frame's depth), in one encoding, or the adaptive
/// or the sparse sampler's loop (which encode each pixel themselves). A frame's tiles all take one
/// ([`Renderer::tile_loop`]); a firmware links those it names ([`Loops`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum TileLoop {
    /// No ray bounces; pixels in this encoding.
    Direct(Encoding),
    /// Rays bounce; pixels in this encoding.
    Bounces(Encoding),
    /// The adaptive sampler, without or with bounces.
    Adaptive {
        /// Whether rays bounce.
        bounces: bool,
    },
    /// The sparse sampler, without or with bounces.
    Sparse {
        /// Whether rays bounce.
        bounces: bool,
    },
}

impl TileLoop {
    /// Every tile loop.
    pub const ALL: [Self; 8] = [
        Self::Direct(Encoding::Srgb),
        Self::Direct(Encoding::Linear),
        Self::Bounces(Encoding::Srgb),
        Self::Bounces(Encoding::Linear),
        Self::Adaptive { bounces: false },
        Self::Adaptive { bounces: true },
        Self::Sparse { bounces: false },
        Self::Sparse { bounces: true },
    ];

    /// The loop a frame's tiles take for `scene` with `settings` (what
    /// [`Renderer::tile_loop`] gives, and what `tessera bake` names in a baked
    /// scene's `SceneLoops`): the adaptive or the sparse sampler's, with bounces
    /// when rays reach a mirror or glass within the settings' depth; else the
    /// loop with bounces or without, in the settings' encoding.
    #[must_use]
    pub fn of(settings: &RenderSettings, scene: &SceneView<'_>) -> Self {
        let bounces = scene.depth(settings.max_depth) > 0;
        match (settings.sampler, bounces) {
            (Sampler::Adaptive { .. }, bounces) => Self::Adaptive { bounces },
            (Sampler::Sparse { .. }, bounces) => Self::Sparse { bounces },
            (_, false) => Self::Direct(settings.encoding),
            (_, true) => Self::Bounces(settings.encoding),
        }
    }
}

/// Which tile loops a firmware links ([`Renderer::render_tile_in`],
/// [`crate::display::Drawing::linking`]). The render settings are values, so
/// [`Renderer::render_tile`] links every [`TileLoop`] ([`AllLoops`]); a firmware
/// whose settings are fixed names the ones it needs and the others are left out
/// of the image (the board example's README, `examples/blackpill-st7789`,
/// measures the flash this saves). A render whose settings need a loop left out
/// is refused ([`Error::NotLinked`]), never drawn wrong: the check
/// ([`Renderer::check_loops`]) and the tile's choice of loop ask the same
/// [`Loops::links`].
///
/// ```
/// use tessera::{builtin, Encoding, tile::Loops, RenderSettings, Tile, TileCoord, tile::TileLoop, Viewport};
///
/// /// Direct light only, sRGB, no adaptive sampling.
/// enum DirectSrgb {}
/// impl Loops for DirectSrgb {
///     fn links(tile_loop: TileLoop) -> bool {
///         tile_loop == TileLoop::Direct(Encoding::Srgb)
///     }
/// }
///
/// let scene = builtin::chapter_direct()?;
/// let settings = RenderSettings { max_depth: 0, ..RenderSettings::default() };
/// let renderer = scene.renderer(Viewport::new(32, 32), settings)?;
/// let mut tile = Tile::<16>::new();
/// renderer.render_tile_in::<DirectSrgb, 16, _, _>(&scene.view(), TileCoord::new(0, 0), &mut tile, &mut ())?;
/// # Ok::<(), tessera::Error>(())
/// ```
pub trait Loops {
    /// Whether this set links `tile_loop`. Asked with constants where the loops
    /// are instantiated, so a loop it refuses is not compiled in: keep it a plain
    /// comparison (`==`, `matches!`).
    fn links(tile_loop: TileLoop) -> bool;
}

/// Every tile loop: what [`Renderer::render_tile`] links.
#[derive(Clone, Copy, Debug)]
pub enum AllLoops {}

impl Loops for AllLoops {
    #[inline(always)]
    fn links(_: TileLoop) -> bool {
        true
    }
}

/// Whether `L` links a loop with bounces (`bounces`) or without, in some form:
/// what the one-ray preview ([`Renderer::preview_color`]) needs.
#[inline(always)]
fn links_any<L: Loops>(bounces: bool) -> bool {
    use Encoding::{Linear, Srgb};
    if bounces {
        L::links(TileLoop::Bounces(Srgb))
            || L::links(TileLoop::Bounces(Linear))
            || L::links(TileLoop::Adaptive { bounces: true })
            || L::links(TileLoop::Sparse { bounces: true })
    } else {
        L::links(TileLoop::Direct(Srgb))
            || L::links(TileLoop::Direct(Linear))
            || L::links(TileLoop::Adaptive { bounces: false })
            || L::links(TileLoop::Sparse { bounces: false })
    }
}

/// Which tile of the frame: tile `(tx, ty)` covers pixels `tx*N .. tx*N + N` by
/// `ty*N .. ty*N + N`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct TileCoord {
    /// Column of tiles, from the left.
    pub tx: u16,
    /// Row of tiles, from the top.
    pub ty: u16,
}

impl TileCoord {
    /// Tile `(tx, ty)`.
    #[must_use]
    pub const fn new(tx: u16, ty: u16) -> Self {
        Self { tx, ty }
    }
}

/// A tile buffer of `N x N` pixels, owned by the caller. Tiles on the right and
/// bottom edges of a frame may be partial: [`Tile::width`] and [`Tile::height`] say
/// how much of the buffer holds pixels; the rest is black.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Tile<const N: usize, P = Rgb8> {
    coord: TileCoord,
    width: u16,
    height: u16,
    pixels: [[P; N]; N],
}

/// A pixel a [`Tile`] holds: the 8-bit [`Rgb8`] (3 bytes), or a panel's own colour
/// (`embedded-graphics`' `Rgb565` and `Rgb555`, 2 bytes; `Gray8`, 1; `Rgb888`, 3),
/// made from the 8-bit pixel at its position in the frame with the frame's
/// [`Dither`] ([`Renderer::with_dither`]), so a tile is filled straight in the
/// display's format: a 16x16 `Rgb565` tile is 520 bytes instead of 776.
pub trait TilePixel: Copy {
    /// The colour of the buffer beyond the frame's edge.
    const BLACK: Self;
    /// The pixel of the 8-bit colour `p` at the frame's pixel `(x, y)`.
    fn from_rgb8(p: Rgb8, x: u32, y: u32, dither: Dither) -> Self;
}

impl TilePixel for Rgb8 {
    const BLACK: Self = Self::new(0, 0, 0);
    #[inline(always)]
    fn from_rgb8(p: Rgb8, _: u32, _: u32, _: Dither) -> Self {
        p
    }
}

impl<const N: usize> Default for Tile<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Tile<N> {
    /// An empty (black, 0 x 0) tile buffer of 8-bit pixels. `N` must be 1 to 256:
    /// any other size fails to compile.
    #[must_use]
    pub const fn new() -> Self {
        Self::blank()
    }
}

impl<const N: usize, P: TilePixel> Tile<N, P> {
    /// An empty (black, 0 x 0) tile buffer of pixels `P`:
    /// `Tile::<16, Rgb565>::blank()` (512 bytes of pixels). `N` must be 1 to 256.
    #[must_use]
    pub const fn blank() -> Self {
        const { assert!(N >= 1 && N <= 256, "tile size must be 1 to 256") };
        Self {
            coord: TileCoord::new(0, 0),
            width: 0,
            height: 0,
            pixels: [[P::BLACK; N]; N],
        }
    }

    /// The tile's coordinate in the frame (of the last render).
    #[must_use]
    pub fn coord(&self) -> TileCoord {
        self.coord
    }
    /// Columns of the buffer that hold pixels.
    #[must_use]
    pub fn width(&self) -> u16 {
        self.width
    }
    /// Rows of the buffer that hold pixels.
    #[must_use]
    pub fn height(&self) -> u16 {
        self.height
    }
    /// The frame coordinates of the tile's top-left pixel.
    #[must_use]
    pub fn origin(&self) -> (u32, u32) {
        (
            u32::from(self.coord.tx) * N as u32,
            u32::from(self.coord.ty) * N as u32,
        )
    }
    /// Pixel `(x, y)` of the tile, if it holds one.
    #[must_use]
    pub fn pixel(&self, x: usize, y: usize) -> Option<P> {
        if x < usize::from(self.width) && y < usize::from(self.height) {
            self.as_slice()
                .get(y * usize::from(self.width) + x)
                .copied()
        } else {
            None
        }
    }
    /// The pixels that hold the tile's picture, row after row with no gap
    /// (`width x height` of them, at the start of the buffer: an edge tile's rows
    /// are `width` long, not `N`), ready for one transfer to a display window of
    /// the tile's size (a panel's pixels in its wire order:
    /// [`crate::display::Rgb565Wire`], [`crate::display::wire_bytes`]).
    #[must_use]
    pub fn as_slice(&self) -> &[P] {
        let live = usize::from(self.width) * usize::from(self.height);
        self.pixels.as_flattened().get(..live).unwrap_or(&[])
    }
    /// The rows that hold pixels, each `width` long, top to bottom.
    pub fn rows(&self) -> impl Iterator<Item = &[P]> {
        self.as_slice().chunks(usize::from(self.width).max(1))
    }
    /// The pixels row by row (what `fill_contiguous` wants).
    pub fn pixels(&self) -> impl Iterator<Item = P> + '_ {
        self.rows().flat_map(|r| r.iter().copied())
    }
}

/// Hands out a frame's tiles to several cores, each tile once: each core loops
/// `while let Some(c) = queue.next() { renderer.render_tile(.., c, &mut its_tile,
/// ..)?; /* send it */ }` with its own tile buffer, and a core that finishes its
/// tile early takes the next one, so the cores stay busy to the end of the frame
/// whatever each tile costs. Which core renders a tile changes none of its pixels
/// (a tile is a function of the scene, the renderer and its coordinate), so the
/// image is the one core's, byte for byte. Tiles go out row after row of tiles.
///
/// One load and one `fetch_add` a tile on an `AtomicU32` (cores with atomic read-modify-write:
/// Armv7-M, Armv8-M Mainline, RISC-V with the A extension); on cores without it
/// (Armv6-M, rv32imc) use [`Interleave`]. A `static` queue is shared by both
/// cores of a dual-core part (RP2350); [`TileQueue::reset`] starts the next frame
/// once every core has stopped taking tiles.
#[cfg(target_has_atomic = "32")]
#[derive(Debug)]
pub struct TileQueue {
    next: core::sync::atomic::AtomicU32,
    across: u16,
    down: u16,
}

#[cfg(target_has_atomic = "32")]
impl TileQueue {
    /// The queue of a frame of `across x down` tiles ([`Renderer::tile_grid`]).
    #[must_use]
    pub const fn new(across: u16, down: u16) -> Self {
        Self {
            next: core::sync::atomic::AtomicU32::new(0),
            across,
            down,
        }
    }

    /// The next tile nobody has taken, or `None` when every tile is taken (and
    /// ever after, however often it is asked).
    pub fn next(&self) -> Option<TileCoord> {
        use core::sync::atomic::Ordering;
        let total = u32::from(self.across) * u32::from(self.down);
        // Relaxed: the counter orders nothing else; the pixels a core writes are
        // its own until it hands them over by other means. Once past the end it
        // is left there (a load first, so that it cannot wrap after 2^32 asks).
        if self.next.load(Ordering::Relaxed) >= total {
            return None;
        }
        let k = self.next.fetch_add(1, Ordering::Relaxed);
        (k < total).then(|| tile_at(k, self.across))
    }

    /// Starts the frame over: every tile is handed out again. Call it when no core
    /// is taking tiles. The store is relaxed: the other cores see it once the
    /// caller hands them the new frame with a release that they acquire (the
    /// handshake that tells them a frame is ready); a core that looks earlier
    /// finds the queue empty, which costs it the frame's tiles, not pixels.
    pub fn reset(&self) {
        self.next.store(0, core::sync::atomic::Ordering::Relaxed);
    }
}

/// Tile `k` of a frame `across` tiles wide, row after row.
fn tile_at(k: u32, across: u16) -> TileCoord {
    let across = u32::from(across).max(1);
    // Both fit in u16: k < across * down, each at most u16::MAX.
    TileCoord::new(
        u16::try_from(k % across).unwrap_or(u16::MAX),
        u16::try_from(k / across).unwrap_or(u16::MAX),
    )
}

/// A frame's tiles shared by `cores` cores without atomics: core `core` takes
/// tiles `core`, `core + cores`, `core + 2 cores`, ... row after row (for cores
/// without atomic read-modify-write, where [`TileQueue`] is not available). Each
/// tile goes to one core; the image is one core's, byte for byte. The split is
/// fixed, so a core whose tiles cost more finishes later.
#[derive(Clone, Debug)]
pub struct Interleave {
    k: u32,
    step: u32,
    total: u32,
    across: u16,
}

impl Interleave {
    /// The tiles of core `core` (0-based) of `cores` in a frame of `across x
    /// down` tiles; none when `core >= cores`.
    #[must_use]
    pub fn new(core: u32, cores: u32, across: u16, down: u16) -> Self {
        let total = u32::from(across) * u32::from(down);
        Self {
            k: if core < cores { core } else { total },
            step: cores.max(1),
            total,
            across,
        }
    }
}

impl Iterator for Interleave {
    type Item = TileCoord;
    fn next(&mut self) -> Option<TileCoord> {
        if self.k >= self.total {
            return None;
        }
        let c = tile_at(self.k, self.across);
        self.k = self.k.saturating_add(self.step);
        Some(c)
    }
}

/// A checked camera basis and render settings: what every tile of a frame shares.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Renderer {
    basis: CameraBasis,
    settings: RenderSettings,
    /// Rays per pixel, and the reciprocal by which their sum is averaged.
    samples: u32,
    inv_count: f32,
    /// `1 / k` for the stratified sampler (`k x k` cells), else 1.
    stratum: f32,
    /// The adaptive sampler's threshold (`None` for the other samplers); its
    /// refined pixels are the stratified sampler's (`samples`, `stratum`).
    adaptive: Option<u8>,
    /// The sub-pixel offset of a single-sample sampler (`None` for the stratified
    /// and random ones): decided once, not per pixel.
    single: Option<(f32, f32)>,
    /// How a tile of a panel's colour ([`TilePixel`]) gets its pixels.
    dither: Dither,
}

impl Renderer {
    /// The frame of `camera` over `viewport` with `settings` (checked).
    pub fn try_new(
        camera: &Camera,
        viewport: Viewport,
        settings: RenderSettings,
    ) -> Result<Self, Error> {
        settings.validate()?;
        // The adaptive sampler's refined pixels are stratified ones.
        let (sampler, adaptive) = match settings.sampler {
            Sampler::Adaptive { k, threshold } => (Sampler::Stratified(k), Some(threshold)),
            s => (s, None),
        };
        Ok(Self {
            basis: CameraBasis::try_new(camera, viewport)?,
            settings,
            samples: sampler.count(),
            inv_count: 1.0 / sampler.count() as f32,
            stratum: match sampler {
                Sampler::Stratified(k) => stratum(u32::from(k.max(1))),
                _ => 1.0,
            },
            single: match sampler {
                Sampler::Corner => Some((0.0, 0.0)),
                Sampler::Centre | Sampler::Prefiltered | Sampler::Sparse { .. } => Some((0.5, 0.5)),
                Sampler::Offset(o) => Some((o.x(), o.y())),
                Sampler::Stratified(_) | Sampler::Random(_) | Sampler::Adaptive { .. } => None,
            },
            adaptive,
            dither: Dither::Bayer4,
        })
    }

    /// The same frame, its tiles of a panel's colour (`Tile<N, Rgb565>`, ...)
    /// filled with `dither` (default [`Dither::Bayer4`]; tiles of [`Rgb8`] are not
    /// dithered).
    #[must_use]
    pub const fn with_dither(self, dither: Dither) -> Self {
        Self { dither, ..self }
    }

    /// How tiles of a panel's colour are filled ([`Renderer::with_dither`]).
    #[must_use]
    pub fn dither(&self) -> Dither {
        self.dither
    }

    /// The camera basis.
    #[must_use]
    pub fn basis(&self) -> &CameraBasis {
        &self.basis
    }
    /// The settings.
    #[must_use]
    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }
    /// The viewport.
    #[must_use]
    pub fn viewport(&self) -> Viewport {
        self.basis.viewport()
    }

    /// How many tiles of `n x n` pixels cover the frame, across and down.
    #[must_use]
    pub fn tile_grid(&self, n: usize) -> (u16, u16) {
        let vp = self.viewport();
        let n = n.max(1);
        let across = usize::from(vp.width).div_ceil(n);
        let down = usize::from(vp.height).div_ceil(n);
        (
            u16::try_from(across).unwrap_or(u16::MAX),
            u16::try_from(down).unwrap_or(u16::MAX),
        )
    }

    /// The quick preview of block `(bx, by)` of `block x block` pixels: one ray,
    /// through the centre of the pixel at the block's middle (clamped to the frame),
    /// with the frame's depth; every primitive is a candidate. A firmware draws a
    /// first picture of the frame this way (`block` 4: a sixteenth of the camera
    /// rays) before it renders the tiles ([`crate::display::Drawing::progressive`]).
    pub fn preview_color<C: RayCounter>(
        &self,
        scene: &SceneView<'_>,
        block_at: (u32, u32),
        block: u32,
        count: &mut C,
    ) -> Color {
        self.preview_color_in::<AllLoops, C>(scene, block_at, block, count)
    }

    /// [`Renderer::preview_color`] with the pixel loops of `L` only (the one with
    /// bounces where the scene has them within the frame's depth, else the one
    /// without); black if `L` has not the one needed, which
    /// [`Renderer::check_loops`] rules out beforehand.
    pub(crate) fn preview_color_in<L: Loops, C: RayCounter>(
        &self,
        scene: &SceneView<'_>,
        (bx, by): (u32, u32),
        block: u32,
        count: &mut C,
    ) -> Color {
        let vp = self.viewport();
        let at = |b: u32, size: u16| {
            b.saturating_mul(block)
                .saturating_add(block / 2)
                .min(u32::from(size).saturating_sub(1))
        };
        let centre = Self {
            samples: 1,
            inv_count: 1.0,
            stratum: 1.0,
            adaptive: None,
            single: Some((0.5, 0.5)),
            settings: RenderSettings {
                sampler: Sampler::Centre,
                ..self.settings
            },
            ..*self
        };
        let depth = scene.depth(self.settings.max_depth);
        let (x, y, picks) = (at(bx, vp.width), at(by, vp.height), &Picks::default());
        if depth > 0 && links_any::<L>(true) {
            Pass::new(&centre, scene, picks, depth, count).pixel::<true>(x, y)
        } else if depth == 0 && links_any::<L>(false) {
            Pass::new(&centre, scene, picks, 0, count).pixel::<false>(x, y)
        } else {
            Color::BLACK
        }
    }

    /// The linear colour of pixel `(x, y)`: the mean of its samples, the rays cast
    /// added to `count` (`&mut ()` not to count). Every primitive is a candidate (no
    /// tile, no culling): the same colour as [`Renderer::render_tile`] gives, which the
    /// tests check; its [`Encoding::encode`] with the settings' encoding is the
    /// tile's pixel. (A pixel the sparse sampler interpolates is a mean of 8-bit
    /// pixels: its colour here is [`Encoding::decode`] of it.)
    pub fn pixel_color<C: RayCounter>(
        &self,
        scene: &SceneView<'_>,
        x: u32,
        y: u32,
        count: &mut C,
    ) -> Color {
        let depth = scene.depth(self.settings.max_depth);
        let picks = Picks::default();
        let mut pass = Pass::new(self, scene, &picks, depth, count);
        if let Some(threshold) = self.sparse() {
            return pass.sparse_pixel(x, y, threshold);
        }
        let Some(threshold) = self.adaptive else {
            return pass.pixel::<true>(x, y);
        };
        // The rule of `Pass::fill_adaptive`, for one pixel.
        // The centre rays of the pixel and of its neighbours in the frame.
        let vp = self.viewport();
        let own = pass.centre::<true>(x, y);
        let mut refine = false;
        for (dx, dy) in NEIGHBOURS {
            let (nx, ny) = (x.wrapping_add_signed(dx), y.wrapping_add_signed(dy));
            if nx < u32::from(vp.width) && ny < u32::from(vp.height) {
                let n = pass.centre::<true>(nx, ny);
                let e = self.settings.encoding;
                refine |= own.encoded(e).differs(n.encoded(e), threshold);
            }
        }
        if refine {
            pass.pixel::<true>(x, y)
        } else {
            own.color
        }
    }

    /// Fills a tile buffer as [`Pass::fill`] does where every ray misses: its
    /// first `th` rows of `tw` pixels (`(x0, y0)` to `(x0 + tw, y0 + th)` of the
    /// frame) the background ([`Renderer::background_pixel`]), the rest black. Generic
    /// over the pixel type only: one copy whatever the tile size and counter.
    #[inline(never)]
    fn fill_background<P: TilePixel>(
        &self,
        scene: &SceneView<'_>,
        pixels: &mut [P],
        (x0, y0, tw, th): (u32, u32, usize, usize),
    ) {
        let rgb = self.background_pixel(scene);
        for (j, row) in pixels.chunks_mut(tw.max(1)).enumerate() {
            let live = if j < th { tw } else { 0 };
            let Some((live, rest)) = row.split_at_mut_checked(live) else {
                continue;
            };
            for (i, px) in live.iter_mut().enumerate() {
                *px = P::from_rgb8(rgb, x0 + i as u32, y0 + j as u32, self.dither);
            }
            rest.fill(P::BLACK);
        }
    }

    /// The camera rays a pixel counts where every ray misses (the background is
    /// filled in without tracing them): the adaptive sampler's centre ray, or the
    /// other samplers' samples.
    fn background_rays(&self) -> u32 {
        if self.adaptive.is_some() {
            1
        } else {
            self.samples
        }
    }

    /// The camera rays the sparse sampler casts for the tile of `tw x th` pixels
    /// at `(x0, y0)` where every ray misses: its traced pixels of the tile and of
    /// its apron (the grid of even pixels over them) and the tile's pixels with a
    /// neighbour beyond the frame (every other pixel is interpolated).
    fn sparse_background_rays(&self, (x0, y0, tw, th): (u32, u32, usize, usize)) -> u32 {
        let vp = self.viewport();
        let (w, h) = (u32::from(vp.width), u32::from(vp.height));
        // The even coordinates of [a - 1, a + n] within the frame.
        let evens = |a: u32, n: usize, size: u32| {
            let lo = a & !1;
            let hi = (a + n as u32).min(size - 1);
            (hi - lo) / 2 + 1
        };
        let grid = evens(x0, tw, w) * evens(y0, th, h);
        let (x1, y1) = (x0 + tw as u32, y0 + th as u32);
        // The last column and row when they are odd: a neighbour beyond the frame.
        let col = u32::from(x1 == w && w % 2 == 0);
        let row = u32::from(y1 == h && h % 2 == 0);
        grid + col * th as u32 + row * tw as u32 - col * row
    }

    /// What a pixel comes to when every ray misses: the background, averaged over
    /// the samples as [`Pass::pixel`] averages them (for one sample,
    /// `(0 + b) * 1 = b`).
    fn background_pixel(&self, scene: &SceneView<'_>) -> Rgb8 {
        if self.adaptive.is_some() || self.sparse().is_some() {
            // Every centre ray misses alike: no pixel is refined.
            return self.settings.encoding.encode(scene.background);
        }
        let mut sum = Color::BLACK;
        for _ in 0..self.samples {
            sum += scene.background;
        }
        self.settings.encoding.encode(sum * self.inv_count)
    }

    /// Renders tile `coord` into `tile`, adding the rays cast to `count` (`&mut ()`
    /// not to count: that compiles to nothing). Pixels of the buffer beyond the
    /// frame's right or bottom edge are set to black and excluded from
    /// `width`/`height`.
    ///
    /// Returns [`Error::TileOutOfFrame`] (and leaves `tile` untouched) when the tile
    /// lies entirely outside the frame.
    pub fn render_tile<const N: usize, C: RayCounter, P: TilePixel>(
        &self,
        scene: &SceneView<'_>,
        coord: TileCoord,
        tile: &mut Tile<N, P>,
        count: &mut C,
    ) -> Result<(), Error> {
        self.render_tile_with::<N, C, P, AllLoops>(scene, coord, tile, count)
    }

    /// [`Renderer::render_tile`] linking only the tile loops of `L` ([`Loops`]): the
    /// same pixels, or [`Error::NotLinked`] when the settings and the scene need
    /// a loop that `L` leaves out ([`Renderer::check_loops`]).
    ///
    /// # Errors
    /// As [`Renderer::render_tile`], and [`Error::NotLinked`].
    pub fn render_tile_in<L: Loops, const N: usize, C: RayCounter, P: TilePixel>(
        &self,
        scene: &SceneView<'_>,
        coord: TileCoord,
        tile: &mut Tile<N, P>,
        count: &mut C,
    ) -> Result<(), Error> {
        self.check_loops::<L>(scene)?;
        self.render_tile_with::<N, C, P, L>(scene, coord, tile, count)
    }

    /// The loop this frame's tiles take for `scene` (each tile takes it, but a
    /// tile no primitive reaches, which is filled with the background at once).
    #[must_use]
    pub fn tile_loop(&self, scene: &SceneView<'_>) -> TileLoop {
        TileLoop::of(&self.settings, scene)
    }

    /// The sparse sampler's threshold (`None` for the other samplers).
    fn sparse(&self) -> Option<u8> {
        match self.settings.sampler {
            Sampler::Sparse { threshold } => Some(threshold),
            _ => None,
        }
    }

    /// Whether `L` links the loop this frame's tiles take for `scene`
    /// ([`Renderer::tile_loop`]).
    ///
    /// # Errors
    /// [`Error::NotLinked`] naming none in particular: the settings decide.
    pub fn check_loops<L: Loops>(&self, scene: &SceneView<'_>) -> Result<(), Error> {
        if L::links(self.tile_loop(scene)) {
            Ok(())
        } else {
            Err(Error::NotLinked)
        }
    }

    /// The tile loop: the tile's candidate lists first ([`crate::cull`]), then
    /// every pixel, or the background at once when no primitive reaches the tile.
    fn render_tile_with<const N: usize, C: RayCounter, P: TilePixel, L: Loops>(
        &self,
        scene: &SceneView<'_>,
        coord: TileCoord,
        tile: &mut Tile<N, P>,
        count: &mut C,
    ) -> Result<(), Error> {
        let vp = self.viewport();
        let (x0, y0) = (usize::from(coord.tx) * N, usize::from(coord.ty) * N);
        let (w, h) = (usize::from(vp.width), usize::from(vp.height));
        if x0 >= w || y0 >= h {
            return Err(Error::TileOutOfFrame);
        }
        let (tw, th) = ((w - x0).min(N), (h - y0).min(N));
        tile.coord = coord;
        // Both fit in u16: they are at most N <= 256.
        tile.width = u16::try_from(tw).unwrap_or(0);
        tile.height = u16::try_from(th).unwrap_or(0);
        // Every sample of the tile lies in [x0, x0 + tw] x [y0, y0 + th]; the
        // adaptive and sparse samplers' also in the one-pixel apron around it.
        let apron = usize::from(self.adaptive.is_some() || self.sparse().is_some());
        let rect = (
            x0.saturating_sub(apron) as f32,
            y0.saturating_sub(apron) as f32,
            (x0 + tw + apron).min(w) as f32,
            (y0 + th + apron).min(h) as f32,
        );
        let (x0, y0) = (x0 as u32, y0 as u32);
        let tile_loop = self.tile_loop(scene);
        if !L::links(tile_loop) {
            return Err(Error::NotLinked);
        }
        let mut body = |lists: Option<&mut TileLists<'_>>| {
            let picks = match lists {
                Some(l) => l.build(&self.basis, scene, rect),
                None => Picks::default(),
            };
            let area = (x0, y0, tw, th);
            if picks.camera.is_some_and(|c| c.iter().all(|l| l.is_empty())) {
                // No primitive reaches the tile: every ray misses alike. Its rays
                // are counted, not traced.
                let rays = if self.sparse().is_some() {
                    self.sparse_background_rays(area)
                } else {
                    (tw * th) as u32 * self.background_rays()
                };
                for _ in 0..rays {
                    count.primary();
                }
                return self.fill_background(scene, tile.pixels.as_flattened_mut(), area);
            }
            let depth = scene.depth(self.settings.max_depth);
            let threshold = self.adaptive.or(self.sparse()).unwrap_or(0);
            // The tile's pixels are packed: rows of `tw` (see `Tile::as_slice`).
            let rows = tile.pixels.as_flattened_mut();
            // The loop's instantiations, one per tile loop: with bounces or without
            // (no ray-tree bookkeeping per sample where no ray is reflected or
            // refracted), in each encoding (decided once a tile, not per pixel);
            // the adaptive loop encodes per pixel (its pixels cost far more than
            // the branch). Each where `L` links it: `L::links` of a constant, so
            // the others compile away.
            use Encoding::{Linear, Srgb};
            macro_rules! run {
                ($loop:expr, $depth:expr => $fill:ident $(::<$($g:tt),*>)? ($($arg:expr),*)) => {
                    if L::links($loop) {
                        Pass::new(self, scene, &picks, $depth, count)
                            .$fill$(::<$($g),*>)?($($arg),*)
                    }
                };
            }
            match tile_loop {
                TileLoop::Direct(Srgb) => {
                    run!(TileLoop::Direct(Srgb), 0 => fill::<P, false, true>(rows, area))
                }
                TileLoop::Direct(Linear) => {
                    run!(TileLoop::Direct(Linear), 0 => fill::<P, false, false>(rows, area))
                }
                TileLoop::Bounces(Srgb) => {
                    run!(TileLoop::Bounces(Srgb), depth => fill::<P, true, true>(rows, area))
                }
                TileLoop::Bounces(Linear) => {
                    run!(TileLoop::Bounces(Linear), depth => fill::<P, true, false>(rows, area))
                }
                TileLoop::Adaptive { bounces: false } => {
                    run!(TileLoop::Adaptive { bounces: false }, 0 => fill_adaptive::<N, P, false>(rows, area, threshold))
                }
                TileLoop::Adaptive { bounces: true } => {
                    run!(TileLoop::Adaptive { bounces: true }, depth => fill_adaptive::<N, P, true>(rows, area, threshold))
                }
                TileLoop::Sparse { bounces: false } => {
                    run!(TileLoop::Sparse { bounces: false }, 0 => fill_sparse::<N, P, false>(rows, area, threshold))
                }
                TileLoop::Sparse { bounces: true } => {
                    run!(TileLoop::Sparse { bounces: true }, depth => fill_sparse::<N, P, true>(rows, area, threshold))
                }
            }
        };
        // The tile's candidate lists live on this stack frame, for this tile only:
        // the scene lends their storage (sized by what it holds, see
        // `cull::TileStorage::lend`) and runs the loop above with them.
        (scene.tile_storage)(scene.culled_lists(), &mut body);
        Ok(())
    }
}

/// What the pixels of one tile share: the renderer, the scene, the tile's
/// candidates (`picks`), the depth rays bounce to and the counter. Its methods
/// are the pixel loop in plain form: a pixel's samples ([`Pass::pixel`]), each a
/// camera ray ([`CameraBasis::ray`]) traced and shaded ([`Pass::sample`]), their
/// mean encoded into the tile's pixel type ([`Pass::fill`]); the loop's
/// instantiations are made in one place, [`Renderer::render_tile_in`]'s `run!`.
struct Pass<'a, C> {
    renderer: &'a Renderer,
    scene: &'a SceneView<'a>,
    picks: &'a Picks<'a>,
    depth: u8,
    count: &'a mut C,
}

impl<'a, C: Observer> Pass<'a, C> {
    #[inline(always)]
    fn new(
        renderer: &'a Renderer,
        scene: &'a SceneView<'a>,
        picks: &'a Picks<'a>,
        depth: u8,
        count: &'a mut C,
    ) -> Self {
        Self {
            renderer,
            scene,
            picks,
            depth,
            count,
        }
    }

    /// Fills a tile buffer's first `th` rows of `tw` pixels (`(x0, y0)` to `(x0 +
    /// tw, y0 + th)` of the frame) with each pixel's colour, encoded (`SRGB`); the
    /// rest of the buffer black. Out of line: the loops with and without bounces then each
    /// have their own stack frame, and the larger one (the inlined shader of
    /// the loop without bounces) does not add to the stack of the other. The
    /// rows are a slice: one copy whatever the tile size.
    #[inline(never)]
    fn fill<P: TilePixel, const BOUNCES: bool, const SRGB: bool>(
        mut self,
        pixels: &mut [P],
        (x0, y0, tw, th): (u32, u32, usize, usize),
    ) {
        let dither = self.renderer.dither;
        for (j, row) in pixels.chunks_mut(tw.max(1)).enumerate() {
            let live = if j < th { tw } else { 0 };
            let Some((live, rest)) = row.split_at_mut_checked(live) else {
                continue;
            };
            for (i, px) in live.iter_mut().enumerate() {
                let (x, y) = (x0 + i as u32, y0 + j as u32);
                let rgb = encode::<SRGB>(self.pixel::<BOUNCES>(x, y));
                *px = P::from_rgb8(rgb, x, y, dither);
            }
            rest.fill(P::BLACK);
        }
    }

    /// [`Pass::fill`] for the adaptive sampler: the centre rays of the tile and of
    /// a one-pixel apron around it (where the frame has pixels), row after row,
    /// then each pixel either its centre colour or, where it differs from a
    /// neighbour's ([`CentrePixel::differs`]), its stratified samples. Rows are decided
    /// as soon as the row below them is traced: three rows of centre samples are
    /// kept ([`Window`]), not the tile's.
    #[inline(never)]
    fn fill_adaptive<const N: usize, P: TilePixel, const BOUNCES: bool>(
        mut self,
        pixels: &mut [P],
        (x0, y0, tw, th): (u32, u32, usize, usize),
        threshold: u8,
    ) where
        C: RayCounter,
    {
        let (vp, settings, dither) = (
            self.renderer.viewport(),
            self.renderer.settings,
            self.renderer.dither,
        );
        let (w, h) = (i64::from(vp.width), i64::from(vp.height));
        let (x0i, y0i) = (i64::from(x0), i64::from(y0));
        let mut window = Window::<N>::new();
        // Row `r` of the tile (-1 and `th`: the apron) into the window.
        let trace_row = |pass: &mut Self, r: i64, window: &mut Window<N>| {
            let y = y0i + r;
            if !(0..h).contains(&y) {
                return;
            }
            for i in -1..=tw as i64 {
                let x = x0i + i;
                if (0..w).contains(&x) {
                    let c = pass.centre::<BOUNCES>(x as u32, y as u32);
                    window.set(r, i, c.encoded(settings.encoding));
                }
            }
        };
        trace_row(&mut self, -1, &mut window);
        trace_row(&mut self, 0, &mut window);
        for (j, row) in pixels.chunks_mut(tw.max(1)).enumerate() {
            let live = if j < th { tw } else { 0 };
            let Some((live, rest)) = row.split_at_mut_checked(live) else {
                continue;
            };
            let r = j as i64;
            if !live.is_empty() {
                trace_row(&mut self, r + 1, &mut window);
            }
            for (i, px) in live.iter_mut().enumerate() {
                let (x, y) = (x0i + i as i64, y0i + r);
                let own = window.get(r, i as i64);
                let mut refine = false;
                for (dx, dy) in NEIGHBOURS {
                    let (nx, ny) = (x + i64::from(dx), y + i64::from(dy));
                    if (0..w).contains(&nx) && (0..h).contains(&ny) {
                        let n = window.get(r + i64::from(dy), i as i64 + i64::from(dx));
                        refine |= own.differs(n, threshold);
                    }
                }
                let rgb = if refine {
                    settings
                        .encoding
                        .encode(self.pixel::<BOUNCES>(x as u32, y as u32))
                } else {
                    own.color
                };
                *px = P::from_rgb8(rgb, x as u32, y as u32, dither);
            }
            rest.fill(P::BLACK);
        }
    }

    /// [`Pass::fill`] for the sparse sampler: row after row, the traced pixels
    /// (both coordinates even, [`Sampler::Sparse`]) of the rows the row needs
    /// (its own when even, the one above and the one below when odd), over the
    /// tile's columns and the apron's, kept two rows at a time ([`Grid`]); then
    /// each pixel its traced colour, the mean of its traced neighbours
    /// ([`sparse_blend`]), or its own ray.
    ///
    /// Out of line and small: its cells are on its own frame, not on that of
    /// the tile loop that calls it, whose other loops then do not carry them.
    #[inline(never)]
    fn fill_sparse<const N: usize, P: TilePixel, const BOUNCES: bool>(
        self,
        pixels: &mut [P],
        area: (u32, u32, usize, usize),
        threshold: u8,
    ) where
        C: RayCounter,
    {
        // A row of the grid holds at most N / 2 + 2 traced pixels: N of them
        // from 4 on, 4 below.
        let mut big = [[CentrePixel::default(); N]; 2];
        let mut small = [[CentrePixel::default(); 4]; 2];
        let ([b0, b1], [s0, s1]) = (&mut big, &mut small);
        let cells: [&mut [CentrePixel]; 2] = if N >= 4 { [b0, b1] } else { [s0, s1] };
        self.fill_sparse_in::<P, BOUNCES>(pixels, area, threshold, Grid::new(cells));
    }

    /// [`Pass::fill_sparse`] in the rows of `grid`: one copy whatever the tile
    /// size.
    #[inline(never)]
    fn fill_sparse_in<P: TilePixel, const BOUNCES: bool>(
        mut self,
        pixels: &mut [P],
        (x0, y0, tw, th): (u32, u32, usize, usize),
        threshold: u8,
        mut grid: Grid<'_>,
    ) where
        C: RayCounter,
    {
        let (vp, encoding, dither) = (
            self.renderer.viewport(),
            self.renderer.settings.encoding,
            self.renderer.dither,
        );
        let frame = (u32::from(vp.width), u32::from(vp.height));
        // The even columns of [x0 - 1, x0 + tw] within the frame.
        let columns = (x0 & !1, (x0 + tw as u32).min(frame.0.saturating_sub(1)));
        for (j, row) in pixels.chunks_mut(tw.max(1)).enumerate() {
            let live = if j < th { tw } else { 0 };
            let Some((live, rest)) = row.split_at_mut_checked(live) else {
                continue;
            };
            let y = y0 + j as u32;
            if !live.is_empty() {
                for g in [y & !1, (y | 1) + 1] {
                    if g < frame.1 && (g == y || y % 2 == 1) && !grid.holds(g) {
                        let slot = grid.slot_for(g);
                        for (k, gx) in (columns.0..=columns.1).step_by(2).enumerate() {
                            let c = self.centre::<BOUNCES>(gx, g);
                            slot.set(k, c.encoded(encoding));
                        }
                    }
                }
            }
            // The traced rows this row takes its pixels from: its own (even), or
            // the one above and, but on the frame's last row, the one below (odd).
            let odd_y = y % 2 == 1;
            let rows = match (grid.row(y & !1), grid.row(y + 1)) {
                (Some(u), _) if !odd_y => Some((u, u)),
                (Some(u), Some(l)) => Some((u, l)),
                // The frame's last row, odd: no row below.
                _ => None,
            };
            for (i, px) in live.iter_mut().enumerate() {
                let x = x0 + i as u32;
                let k = ((x - columns.0) / 2) as usize;
                let odd_x = x % 2 == 1;
                let mean = match rows {
                    // A neighbour beyond the frame.
                    _ if odd_x && x + 1 >= frame.0 => None,
                    None => None,
                    Some((u, l)) => match (odd_x, odd_y) {
                        (false, false) => Some(u.at(k).color),
                        (true, false) => sparse_blend([u.at(k), u.at(k + 1)], threshold),
                        (false, true) => sparse_blend([u.at(k), l.at(k)], threshold),
                        (true, true) => {
                            sparse_blend([u.at(k), u.at(k + 1), l.at(k), l.at(k + 1)], threshold)
                        }
                    },
                };
                let rgb = match mean {
                    Some(rgb) => rgb,
                    // Its own ray, the prefiltered one (no signature needed).
                    None => encoding.encode(self.pixel::<BOUNCES>(x, y)),
                };
                *px = P::from_rgb8(rgb, x, y, dither);
            }
            rest.fill(P::BLACK);
        }
    }

    /// The sparse sampler's linear colour of pixel `(x, y)` on its own: the rule
    /// of [`Pass::fill_sparse`], its traced neighbours traced here.
    fn sparse_pixel(&mut self, x: u32, y: u32, threshold: u8) -> Color
    where
        C: RayCounter,
    {
        let vp = self.renderer.viewport();
        let frame = (u32::from(vp.width), u32::from(vp.height));
        let encoding = self.renderer.settings.encoding;
        let traced =
            |pass: &mut Self, (gx, gy): (u32, u32)| pass.centre::<true>(gx, gy).encoded(encoding);
        let blended = match sparse_parents((x, y), frame) {
            Parents::Own => None,
            Parents::Two(at) => sparse_blend(at.map(|a| traced(self, a)).each_ref(), threshold),
            Parents::Four(at) => sparse_blend(at.map(|a| traced(self, a)).each_ref(), threshold),
        };
        match blended {
            Some(rgb) => encoding.decode(rgb),
            None => self.pixel::<true>(x, y),
        }
    }

    /// The colour of pixel `(x, y)`: the mean of its samples, each one call of
    /// [`Renderer::sample`]. The single-sample samplers trace one ray and return
    /// its colour (`(0 + c) * 1 = c`); the stratified and random samplers hash the
    /// pixel once and the sample index per sample.
    #[inline(always)]
    fn pixel<const BOUNCES: bool>(&mut self, x: u32, y: u32) -> Color {
        let r = self.renderer;
        let (px, py) = (x as f32, y as f32);
        // One ray: no loop, no average (`(0 + c) * 1 = c`).
        if let Some((dx, dy)) = r.single {
            let footprint = matches!(
                r.settings.sampler,
                Sampler::Prefiltered | Sampler::Sparse { .. }
            )
            .then(|| Footprint::new(&r.basis, px, py));
            let (at, footprint) = ((px + dx, py + dy), footprint.as_ref());
            return r.sample::<C, BOUNCES>(
                self.scene, self.picks, self.depth, at, footprint, self.count,
            );
        }
        let hash = PixelHash::new(x, y, r.settings.seed);
        let mut sum = Color::BLACK;
        // The stratified sampler's cell (cx, cy) of sample i = cy k + cx.
        let (mut cx, mut cy) = (0u32, 0u32);
        for i in 0..r.samples {
            let (dx, dy) = match r.settings.sampler {
                Sampler::Stratified(k) | Sampler::Adaptive { k, .. } => {
                    let d = stratified(hash, i, (cx, cy), r.stratum);
                    cx += 1;
                    if cx == u32::from(k) {
                        (cx, cy) = (0, cy + 1);
                    }
                    d
                }
                _ => hash.pair(i),
            };
            let at = (px + dx, py + dy);
            sum += r.sample::<C, BOUNCES>(self.scene, self.picks, self.depth, at, None, self.count);
        }
        sum * r.inv_count
    }

    /// The adaptive sampler's centre sample of pixel `(x, y)`: its colour and the
    /// signature of its ray tree.
    #[inline(always)]
    fn centre<const BOUNCES: bool>(&mut self, x: u32, y: u32) -> CentreSample
    where
        C: RayCounter,
    {
        let mut signed = Signature::new(&mut *self.count);
        let (px, py) = (x as f32, y as f32);
        let footprint = Footprint::new(&self.renderer.basis, px, py);
        let at = (px + 0.5, py + 0.5);
        let (scene, picks, depth) = (self.scene, self.picks, self.depth);
        let color = self.renderer.sample::<_, BOUNCES>(
            scene,
            picks,
            depth,
            at,
            Some(&footprint),
            &mut signed,
        );
        CentreSample {
            color,
            sig: signed.hash,
            textured: signed.textured,
        }
    }
}

impl Renderer {
    /// The colour the camera ray through the viewport point `at` brings back: the
    /// pixel loop's one call per sample. Out of line: inlined, the pixel loop's
    /// registers spill around the shader.
    #[inline(never)]
    fn sample<C: Observer, const BOUNCES: bool>(
        &self,
        scene: &SceneView<'_>,
        picks: &Picks<'_>,
        depth: u8,
        (x, y): (f32, f32),
        footprint: Option<&Footprint<'_>>,
        count: &mut C,
    ) -> Color {
        let (ray, t_max) = self.basis.ray(x, y);
        let cam = CameraRay {
            ray,
            t_max,
            footprint,
        };
        trace_with::<C, BOUNCES>(scene, cam, depth, picks, count)
    }
}

/// `c` in 8 bits, sRGB-encoded or linear (a tile loop's constant).
#[inline(always)]
fn encode<const SRGB: bool>(c: Color) -> Rgb8 {
    if SRGB { c.to_srgb8() } else { c.to_rgb8() }
}

/// The neighbours a pixel is compared with, as `(dx, dy)`: above, left, right,
/// below. (The diagonal ones too would trace many more camera rays for hardly
/// a smaller error: an edge that crosses a pixel crosses the line to one of
/// these four.)
const NEIGHBOURS: [(i32, i32); 4] = [(0, -1), (-1, 0), (1, 0), (0, 1)];

/// A centre sample of the adaptive sampler: the linear colour and the signature
/// of its ray tree (see `shade::Signed`).
#[derive(Clone, Copy)]
struct CentreSample {
    color: Color,
    sig: u32,
    textured: bool,
}

impl CentreSample {
    /// What the decision needs of it.
    #[inline(always)]
    fn encoded(&self, encoding: Encoding) -> CentrePixel {
        CentrePixel {
            color: encoding.encode(self.color),
            sig: self.sig,
            textured: self.textured,
        }
    }
}

/// What the adaptive sampler compares of two neighbouring centre samples: the
/// 8-bit pixel and the signature.
#[derive(Clone, Copy, Default)]
struct CentrePixel {
    color: Rgb8,
    sig: u32,
    textured: bool,
}

impl CentrePixel {
    /// Whether the two pixels straddle an edge: their rays met different things,
    /// or a channel differs by more than `threshold`.
    #[inline(always)]
    fn differs(self, other: Self, threshold: u8) -> bool {
        let (a, b) = (self.color, other.color);
        self.sig != other.sig
            || !self.textured
                && (a.r.abs_diff(b.r) > threshold
                    || a.g.abs_diff(b.g) > threshold
                    || a.b.abs_diff(b.b) > threshold)
    }
}

/// Three rows of centre samples, each `N + 2` wide (the tile's columns and the
/// apron's on either side): row `r` of the tile (`-1` to `N`) is kept in slot
/// `(r + 1) mod 3`, column `i` (`-1` to `N`) in `left`, `mid[i]` or `right`.
struct Window<const N: usize> {
    rows: [Row<N>; 3],
}

/// One row of a [`Window`].
#[derive(Clone, Copy)]
struct Row<const N: usize> {
    left: CentrePixel,
    mid: [CentrePixel; N],
    right: CentrePixel,
}

impl<const N: usize> Window<N> {
    fn new() -> Self {
        let row = Row {
            left: CentrePixel::default(),
            mid: [CentrePixel::default(); N],
            right: CentrePixel::default(),
        };
        Self { rows: [row; 3] }
    }

    /// The place of column `i` of row `r` (always `Some`: the slot is `< 3`).
    #[inline(always)]
    fn at(&mut self, r: i64, i: i64) -> Option<&mut CentrePixel> {
        let row = self.rows.get_mut((r + 1).rem_euclid(3) as usize)?;
        Some(match usize::try_from(i) {
            Err(_) => &mut row.left,
            Ok(i) => match row.mid.get_mut(i) {
                Some(p) => p,
                None => &mut row.right,
            },
        })
    }

    #[inline(always)]
    fn set(&mut self, r: i64, i: i64, p: CentrePixel) {
        if let Some(at) = self.at(r, i) {
            *at = p;
        }
    }

    #[inline(always)]
    fn get(&mut self, r: i64, i: i64) -> CentrePixel {
        self.at(r, i).map(|p| *p).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::mem::size_of;

    #[test]
    fn a_queue_hands_out_every_tile_once_however_the_cores_interleave() {
        let q = TileQueue::new(5, 3);
        let mut seen = std::vec::Vec::new();
        // Two "cores" asking in turn, then one alone: each tile once, in order.
        while let Some(c) = q.next() {
            seen.push(c);
            if let Some(c) = q.next() {
                seen.push(c);
            }
        }
        let want: std::vec::Vec<_> = (0..3)
            .flat_map(|ty| (0..5).map(move |tx| TileCoord::new(tx, ty)))
            .collect();
        assert_eq!(seen, want);
        assert_eq!(q.next(), None);
        q.reset();
        assert_eq!(q.next(), Some(TileCoord::new(0, 0)));
        assert_eq!(TileQueue::new(0, 7).next(), None);
    }

    #[test]
    fn a_queue_shared_by_threads_gives_each_tile_to_one_of_them() {
        let q = TileQueue::new(37, 29);
        let taken: std::vec::Vec<std::vec::Vec<TileCoord>> = std::thread::scope(|s| {
            let hs: std::vec::Vec<_> = (0..4)
                .map(|_| s.spawn(|| core::iter::from_fn(|| q.next()).collect()))
                .collect();
            hs.into_iter().map(|h| h.join().unwrap()).collect()
        });
        let mut all: std::vec::Vec<_> = taken.concat();
        all.sort_by_key(|c| (c.ty, c.tx));
        all.dedup();
        assert_eq!(all.len(), 37 * 29);
        assert_eq!(taken.iter().map(std::vec::Vec::len).sum::<usize>(), 37 * 29);
    }

    #[test]
    fn interleaved_cores_cover_the_frame_once() {
        for cores in 1..5 {
            let mut all: std::vec::Vec<_> = (0..cores)
                .flat_map(|c| Interleave::new(c, cores, 4, 3))
                .collect();
            assert_eq!(all.len(), 12, "{cores} cores");
            all.sort_by_key(|c| (c.ty, c.tx));
            all.dedup();
            assert_eq!(all.len(), 12, "{cores} cores");
        }
        assert_eq!(Interleave::new(2, 2, 4, 3).count(), 0);
        let second: std::vec::Vec<_> = Interleave::new(1, 2, 3, 2).collect();
        assert_eq!(
            second,
            [
                TileCoord::new(1, 0),
                TileCoord::new(0, 1),
                TileCoord::new(2, 1)
            ]
        );
    }

    #[test]
    fn an_edge_tile_packs_its_rows_and_leaves_the_rest_black() {
        // 20 x 13 with tiles of 8: tile (2, 1) holds 4 x 5 pixels.
        let b = crate::builtin::Builtin::ChapterReflect;
        b.with_scene(|view, cam| {
            let r = Renderer::try_new(cam, crate::Viewport::new(20, 13), b.settings()).unwrap();
            let mut tile = Tile::<8>::new();
            r.render_tile(view, TileCoord::new(2, 1), &mut tile, &mut ())
                .unwrap();
            assert_eq!((tile.width(), tile.height()), (4, 5));
            assert_eq!(tile.as_slice().len(), 20);
            for y in 0..5 {
                for x in 0..4 {
                    let want = r.pixel_color(view, 16 + x, 8 + y, &mut ()).to_srgb8();
                    assert_eq!(tile.as_slice()[(y * 4 + x) as usize], want, "({x}, {y})");
                    assert_eq!(tile.pixel(x as usize, y as usize), Some(want));
                }
            }
            assert!(
                tile.pixels.as_flattened()[20..]
                    .iter()
                    .all(|p| *p == Rgb8::BLACK)
            );
            assert_eq!(
                tile.rows().map(<[Rgb8]>::len).collect::<std::vec::Vec<_>>(),
                [4; 5]
            );
        })
        .unwrap();
    }
    extern crate std;

    /// The module docs' table's and the crate docs' bytes: `3 N^2 + 8`.
    #[test]
    fn tile_buffer_sizes_match_the_docs() {
        assert_eq!(size_of::<Tile<8>>(), 8 * 8 * 3 + 8);
        assert_eq!(size_of::<Tile<16>>(), 16 * 16 * 3 + 8);
        assert_eq!(size_of::<Tile<32>>(), 32 * 32 * 3 + 8);
        assert_eq!(
            [
                size_of::<Tile<8>>(),
                size_of::<Tile<16>>(),
                size_of::<Tile<32>>()
            ],
            [200, 776, 3_080]
        );
    }

    #[test]
    fn settings_are_checked() {
        let mut s = RenderSettings {
            max_depth: MAX_DEPTH + 1,
            ..RenderSettings::default()
        };
        assert_eq!(
            s.validate(),
            Err(Error::DepthTooLarge {
                depth: MAX_DEPTH + 1
            })
        );
        s.max_depth = MAX_DEPTH;
        assert!(s.validate().is_ok());
        s.sampler = Sampler::Random(0);
        assert_eq!(s.validate(), Err(Error::BadSampleCount));
    }

    /// A set of loops by a mask over [`TileLoop::ALL`].
    struct Set<const MASK: u8>;

    impl<const MASK: u8> Loops for Set<MASK> {
        fn links(l: TileLoop) -> bool {
            TileLoop::ALL
                .iter()
                .position(|&x| x == l)
                .is_some_and(|i| MASK >> i & 1 == 1)
        }
    }

    /// Every tile of the frame with the loops of `L`, each tile's pixels in turn;
    /// or the first error. The tile buffer holds another tile's pixels before
    /// each render, so a tile left unfilled would show.
    fn tiles_in<L: Loops>(
        renderer: &Renderer,
        view: &SceneView<'_>,
    ) -> Result<std::vec::Vec<Rgb8>, Error> {
        let mut out = std::vec::Vec::new();
        let mut tile = Tile::<8>::new();
        let (across, down) = renderer.tile_grid(8);
        for ty in 0..down {
            for tx in 0..across {
                for (i, p) in tile.pixels.iter_mut().flatten().enumerate() {
                    *p = Rgb8::new(i as u8, 7, 200);
                }
                renderer.render_tile_in::<L, 8, _, _>(
                    view,
                    TileCoord::new(tx, ty),
                    &mut tile,
                    &mut (),
                )?;
                out.extend(tile.pixels());
            }
        }
        Ok(out)
    }

    /// One frame, its pixels with every loop, and the loop it needs.
    struct Case<'a, 'v> {
        renderer: &'a Renderer,
        view: &'a SceneView<'v>,
        all: &'a [Rgb8],
        need: TileLoop,
    }

    /// The set `L` on `case`: the same bytes when it links the loop needed,
    /// else refused (by `check_loops` too); returns whether it was refused.
    fn one<L: Loops>(case: &Case<'_, '_>) -> bool {
        let enough = L::links(case.need);
        match tiles_in::<L>(case.renderer, case.view) {
            Ok(px) => assert!(enough && px == case.all, "{:?}", case.need),
            Err(e) => assert!(!enough && e == Error::NotLinked, "{:?}: {e}", case.need),
        }
        assert_eq!(case.renderer.check_loops::<L>(case.view).is_ok(), enough);
        !enough
    }

    /// The sets on `case`: each loop alone, every loop but one, all and none;
    /// the number refused.
    fn every_set(case: &Case<'_, '_>) -> usize {
        let alone = [
            one::<Set<0b000001>>(case),
            one::<Set<0b000010>>(case),
            one::<Set<0b000100>>(case),
            one::<Set<0b001000>>(case),
            one::<Set<0b010000>>(case),
            one::<Set<0b100000>>(case),
        ];
        let but = [
            one::<Set<0b111110>>(case),
            one::<Set<0b111101>>(case),
            one::<Set<0b111011>>(case),
            one::<Set<0b110111>>(case),
            one::<Set<0b101111>>(case),
            one::<Set<0b011111>>(case),
        ];
        let ends = [one::<Set<0b111111>>(case), one::<Set<0>>(case)];
        alone
            .iter()
            .chain(&but)
            .chain(&ends)
            .filter(|r| **r)
            .count()
    }

    /// With a set of loops that has what the settings and the scene need, a
    /// render is the same bytes as with every loop; with a set that lacks one of
    /// them, it is refused. All 32 sets on every built-in scene, with and without
    /// bounces, in both encodings, with and without the adaptive sampler (whose
    /// frames have background tiles too).
    #[test]
    fn a_render_with_fewer_loops_is_the_same_or_refused() {
        use crate::builtin::Builtin;
        for &b in Builtin::ALL {
            for (sampler, depth, encoding) in [
                (Sampler::Centre, 0, Encoding::Srgb),
                (Sampler::Stratified(2), 3, Encoding::Linear),
                (Sampler::adaptive(2), 3, Encoding::Srgb),
                (Sampler::adaptive(2), 0, Encoding::Linear),
                (
                    Sampler::Adaptive { k: 2, threshold: 0 },
                    5,
                    Encoding::Linear,
                ),
            ] {
                b.with_scene(|view, cam| {
                    let settings = RenderSettings {
                        sampler,
                        max_depth: depth,
                        seed: 3,
                        encoding,
                    };
                    let renderer =
                        Renderer::try_new(cam, crate::Viewport::new(20, 13), settings).unwrap();
                    let all = tiles_in::<AllLoops>(&renderer, view).unwrap();
                    let bounces = view.depth(depth) > 0;
                    // The loop the settings and the scene need, derived here on its own.
                    let need = match (sampler, bounces) {
                        (Sampler::Adaptive { .. }, bounces) => TileLoop::Adaptive { bounces },
                        (_, false) => TileLoop::Direct(encoding),
                        (_, true) => TileLoop::Bounces(encoding),
                    };
                    assert_eq!(renderer.tile_loop(view), need);
                    let case = Case {
                        renderer: &renderer,
                        view,
                        all: &all,
                        need,
                    };
                    // Refused: the other five alone, the one "every loop but" it,
                    // and none.
                    assert_eq!(every_set(&case), 7);
                })
                .unwrap();
            }
        }
    }
}
