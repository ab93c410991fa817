//! The frame: [`Renderer`], checked once, and a tile's render (which tile loop, its culling lists).

use super::adaptive::NEIGHBOURS;
use super::buffer::{Tile, TileCoord, TilePixel};
use super::pass::{Pass, sparse_columns};
use super::settings::{AllLoops, Loops, RenderSettings, TileLoop, links_any};
use super::sparse::{between_coarse_rows, coarse_fits};
use crate::camera::{Camera, CameraBasis, Viewport};
use crate::color::{Color, Encoding, Rgb8};
use crate::cull::{Picks, TileLists};
use crate::dither::Dither;
use crate::error::Error;
use crate::sample::{Sampler, stratum};
use crate::shade::RayCounter;
use crate::view::SceneView;

/// A checked camera basis and render settings: what every tile of a frame shares.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Renderer {
    pub(super) basis: CameraBasis,
    pub(super) settings: RenderSettings,
    /// Rays per pixel, and the reciprocal by which their sum is averaged.
    pub(super) samples: u32,
    pub(super) inv_count: f32,
    /// `1 / k` for the stratified sampler (`k x k` cells), else 1.
    pub(super) stratum: f32,
    /// The adaptive sampler's threshold (`None` for the other samplers); its
    /// refined pixels are the stratified sampler's (`samples`, `stratum`).
    pub(super) adaptive: Option<u8>,
    /// The sub-pixel offset of a single-sample sampler (`None` for the stratified
    /// and random ones): decided once, not per pixel.
    pub(super) single: Option<(f32, f32)>,
    /// How a tile of a panel's colour ([`TilePixel`]) gets its pixels.
    pub(super) dither: Dither,
}

/// A rectangle of the viewport, `(x0, y0, x1, y1)` in pixel units.
pub(super) type Rect = (f32, f32, f32, f32);

/// A tile's pixels: `(x0, y0, width, height)`.
pub(super) type Area = (u32, u32, usize, usize);

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
            let coarse = self.coarse(scene);
            return pass.sparse_pixel(x, y, (threshold, coarse));
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
    pub(super) fn fill_background<P: TilePixel>(
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
    pub(super) fn background_rays(&self) -> u32 {
        if self.adaptive.is_some() {
            1
        } else {
            self.samples
        }
    }

    /// The camera rays the sparse sampler casts for the tile of `tw x th` pixels
    /// at `(x0, y0)` where every ray misses, all alike (every mean is then
    /// taken): the rays [`Pass::fill_sparse`] casts of its grid's rows, and the
    /// tile's pixels with a neighbour beyond the frame.
    pub(super) fn sparse_background_rays(
        &self,
        (x0, y0, tw, th): (u32, u32, usize, usize),
        coarse: bool,
    ) -> u32 {
        let vp = self.viewport();
        let (w, h) = (u32::from(vp.width), u32::from(vp.height));
        let columns = sparse_columns(x0, tw, w, coarse);
        let evens = |a: u32, b: u32| if a > b { 0 } else { (b - a) / 2 + 1 };
        // The even columns of [a, b] that are multiples of 4.
        let fours = |a: u32, b: u32| {
            let a = (a + 3) & !3;
            if a > b { 0 } else { (b - a) / 4 + 1 }
        };
        let needed = evens(columns.first, columns.last);
        // What one grid row casts (`Pass::grid_row`): every needed column's
        // ray at spacing 2 and on a level-1 row with no coarse row below; the
        // coarse columns' on a coarse row, and its level-1 pixels' whose right
        // neighbour lies beyond the frame; on a level-1 row, those whose
        // diagonal neighbours do (never its coarse columns').
        let row_rays = |g: u32| -> u32 {
            let edge = u32::from(columns.last % 4 == 2 && columns.last + 2 >= w);
            if !coarse || g % 4 == 2 && !between_coarse_rows(g, h) {
                needed
            } else if g.is_multiple_of(4) {
                fours(columns.lo, columns.hi) + edge
            } else {
                edge
            }
        };
        // The grid rows the tile's rows take (its even rows, and for an odd
        // row the rows either side), and with spacing 4 the coarse rows
        // either side of a level-1 row.
        let (first, last) = (y0 & !1, (y0 + th as u32).min(h.saturating_sub(1)) & !1);
        let mut rays = 0;
        let mut g = first;
        while g <= last {
            rays += row_rays(g);
            g += 2;
        }
        if coarse {
            // The coarse rows around the level-1 rows at either end.
            if between_coarse_rows(first, h) {
                rays += row_rays(first - 2);
            }
            if between_coarse_rows(last, h) {
                rays += row_rays(last + 2);
            }
        }
        let (x1, y1) = (x0 + tw as u32, y0 + th as u32);
        // The last column and row when they are odd: a neighbour beyond the frame.
        let col = u32::from(x1 == w && w % 2 == 0);
        let row = u32::from(y1 == h && h % 2 == 0);
        rays + col * th as u32 + row * tw as u32 - col * row
    }

    /// What a pixel comes to when every ray misses: the background, averaged over
    /// the samples as [`Pass::pixel`] averages them (for one sample,
    /// `(0 + b) * 1 = b`).
    pub(super) fn background_pixel(&self, scene: &SceneView<'_>) -> Rgb8 {
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
    pub(super) fn sparse(&self) -> Option<u8> {
        match self.settings.sampler {
            Sampler::Sparse { threshold, .. } => Some(threshold),
            _ => None,
        }
    }

    /// The spacing of the sparse sampler's first grid for `scene`: 4 where it
    /// was asked for and every primitive's outline is sure to hold a ray of
    /// that grid ([`crate::Sampler::Sparse`]), else 2; `None` for the other
    /// samplers.
    #[must_use]
    pub fn sparse_spacing(&self, scene: &SceneView<'_>) -> Option<u8> {
        self.sparse()
            .map(|_| if self.coarse(scene) { 4 } else { 2 })
    }

    /// Whether the sparse sampler starts from its grid of spacing 4 in
    /// `scene`: asked for, and sure to hold a ray in every primitive's outline
    /// ([`coarse_fits`]).
    pub(super) fn coarse(&self, scene: &SceneView<'_>) -> bool {
        matches!(self.settings.sampler, Sampler::Sparse { spacing: 4, .. })
            && coarse_fits(&self.basis, scene)
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

    /// The rectangle (pixel units) every sample of tile `coord` of tiles of
    /// `N` lies in, what its lists are culled for, and its area `(x0, y0,
    /// width, height)`; `None` for a tile outside the frame. The samples lie
    /// in `[x0, x0 + tw] x [y0, y0 + th]`; the adaptive and sparse samplers'
    /// also in the one-pixel apron around it, the sparse sampler's from its
    /// coarse grid (`coarse`, [`Renderer::coarse`]) in a three-pixel one.
    pub(super) fn tile_rect<const N: usize>(
        &self,
        coord: TileCoord,
        coarse: bool,
    ) -> Option<(Rect, Area)> {
        let vp = self.viewport();
        let (x0, y0) = (usize::from(coord.tx) * N, usize::from(coord.ty) * N);
        let (w, h) = (usize::from(vp.width), usize::from(vp.height));
        if x0 >= w || y0 >= h {
            return None;
        }
        let (tw, th) = ((w - x0).min(N), (h - y0).min(N));
        let apron = if coarse {
            3
        } else {
            usize::from(self.adaptive.is_some() || self.sparse().is_some())
        };
        let rect = (
            x0.saturating_sub(apron) as f32,
            y0.saturating_sub(apron) as f32,
            (x0 + tw + apron).min(w) as f32,
            (y0 + th + apron).min(h) as f32,
        );
        Some((rect, (x0 as u32, y0 as u32, tw, th)))
    }

    /// The tile loop: the tile's candidate lists first ([`crate::cull`]), then
    /// every pixel, or the background at once when no primitive reaches the tile.
    pub(super) fn render_tile_with<const N: usize, C: RayCounter, P: TilePixel, L: Loops>(
        &self,
        scene: &SceneView<'_>,
        coord: TileCoord,
        tile: &mut Tile<N, P>,
        count: &mut C,
    ) -> Result<(), Error> {
        let coarse = self.coarse(scene);
        let Some((rect, (x0, y0, tw, th))) = self.tile_rect::<N>(coord, coarse) else {
            return Err(Error::TileOutOfFrame);
        };
        tile.coord = coord;
        // Both fit in u16: they are at most N <= 256.
        tile.width = u16::try_from(tw).unwrap_or(0);
        tile.height = u16::try_from(th).unwrap_or(0);
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
                    self.sparse_background_rays(area, coarse)
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
            let sparse = (threshold, coarse);
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
                    run!(TileLoop::Sparse { bounces: false }, 0 => fill_sparse::<N, P, false>(rows, area, sparse))
                }
                TileLoop::Sparse { bounces: true } => {
                    run!(TileLoop::Sparse { bounces: true }, depth => fill_sparse::<N, P, true>(rows, area, sparse))
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
