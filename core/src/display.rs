//! Tiles straight onto a display: any `embedded-graphics` [`DrawTarget`] whose colour
//! converts from `Rgb888` (`Rgb565` panels are the main case).
//!
//! Each tile goes out through one `fill_contiguous` call with the tile's rectangle,
//! so a driver that streams an address window (ST7789, ILI9341, ...) receives a
//! whole tile per window. There is no framebuffer: the RAM is one tile buffer plus
//! the renderer's stack. Errors of the display are returned, never swallowed.
//!
//! The links to `embedded-graphics-core`'s items are to docs.rs: a documentation
//! built with `--no-deps` has no local page for them to resolve to.
//!
//! [`DrawTarget`]: https://docs.rs/embedded-graphics-core/0.4/embedded_graphics_core/draw_target/trait.DrawTarget.html

use crate::color::Rgb8;
use crate::dither::Dither;
use crate::error::Error;
pub use crate::tile::TilePixel;
use crate::tile::{AllLoops, Frame, Loops, Tile, TileCoord};
use crate::view::SceneView;
use core::marker::PhantomData;
use embedded_graphics_core::Drawable;
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{OriginDimensions, Point, Size};
use embedded_graphics_core::pixelcolor::{Gray8, PixelColor, Rgb555, Rgb565, Rgb888};
use embedded_graphics_core::primitives::Rectangle;

/// The rectangle of `w x h` pixels at `(x, y)` of the frame (coordinates beyond
/// `i32` clamp, for a display to clip).
fn rectangle(x: u32, y: u32, w: u32, h: u32) -> Rectangle {
    Rectangle::new(
        Point::new(
            i32::try_from(x).unwrap_or(i32::MAX),
            i32::try_from(y).unwrap_or(i32::MAX),
        ),
        Size::new(w, h),
    )
}

/// Sends a rendered tile to `display` with one `fill_contiguous` over the tile's
/// rectangle (its valid part: edge tiles may be partial). For a firmware that
/// renders and sends the tiles itself, e.g. from a static tile buffer or in an
/// order of its own.
pub fn draw_tile<D, const N: usize>(tile: &Tile<N>, display: &mut D) -> Result<(), D::Error>
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    let (x0, y0) = tile.origin();
    let area = rectangle(x0, y0, u32::from(tile.width()), u32::from(tile.height()));
    display.fill_contiguous(
        &area,
        tile.pixels()
            .map(|p| D::Color::from(Rgb888::new(p.r, p.g, p.b))),
    )
}

/// A frame of a scene as an embedded-graphics [`Drawable`] in the display's colour
/// `C`, rendered in rows of `N x N` tiles: [`Frame::drawable`].
///
/// Its size ([`OriginDimensions`]) is the viewport's, at the origin; draw it through
/// a translated or clipped target to place it, like any other drawable. Drawing
/// renders: the pixel memory is one [`Tile<N>`](Tile) on the stack of `draw`
/// (`3 N^2 + 8` bytes: a tile of 16x16 is 776 bytes), sent with one
/// `fill_contiguous` per tile.
///
/// [`Drawable`]: https://docs.rs/embedded-graphics-core/0.4/embedded_graphics_core/trait.Drawable.html
/// [`OriginDimensions`]: https://docs.rs/embedded-graphics-core/0.4/embedded_graphics_core/geometry/trait.OriginDimensions.html
#[derive(Clone, Copy, Debug)]
pub struct Rendering<'a, C, const N: usize> {
    frame: &'a Frame,
    scene: SceneView<'a>,
    color: PhantomData<C>,
}

impl Frame {
    /// This frame of `scene` as a [`Drawable`] ([`Rendering`]) with tiles of `N`,
    /// each pixel converted with the display colour's `From<Rgb888>` (the nearest
    /// level; for a 16-bit or grey panel, [`Frame::drawable_dithered`] dithers
    /// instead of banding):
    ///
    /// ```
    /// use embedded_graphics_core::{pixelcolor::Rgb565, prelude::*};
    /// use tessera::{builtin, RenderSettings, Viewport};
    ///
    /// // A display that only counts what it receives.
    /// struct Count(u32);
    /// impl OriginDimensions for Count {
    ///     fn size(&self) -> Size { Size::new(40, 30) }
    /// }
    /// impl DrawTarget for Count {
    ///     type Color = Rgb565;
    ///     type Error = core::convert::Infallible;
    ///     fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(&mut self, px: I) -> Result<(), Self::Error> {
    ///         self.0 += px.into_iter().count() as u32;
    ///         Ok(())
    ///     }
    /// }
    ///
    /// let scene = builtin::chapter_direct()?;
    /// let frame = scene.frame(Viewport::new(40, 30), RenderSettings::default())?;
    /// let picture = frame.drawable::<_, 16>(&scene.view());
    /// assert_eq!(picture.size(), Size::new(40, 30));
    /// let mut display = Count(0);
    /// picture.draw(&mut display).unwrap();
    /// assert_eq!(display.0, 40 * 30);
    /// # Ok::<(), tessera::Error>(())
    /// ```
    ///
    /// [`Drawable`]: https://docs.rs/embedded-graphics-core/0.4/embedded_graphics_core/trait.Drawable.html
    #[must_use]
    pub fn drawable<'a, C, const N: usize>(&'a self, scene: &SceneView<'a>) -> Rendering<'a, C, N> {
        Rendering {
            frame: self,
            scene: *scene,
            color: PhantomData,
        }
    }
}

impl<C: PixelColor + From<Rgb888>, const N: usize> Drawable for Rendering<'_, C, N> {
    type Color = C;
    type Output = ();

    /// Renders the frame tile after tile, in rows, and sends each tile to `target`
    /// as soon as it is rendered. An error of the target stops the drawing and is
    /// returned.
    fn draw<D>(&self, target: &mut D) -> Result<(), D::Error>
    where
        D: DrawTarget<Color = C>,
    {
        let mut tile = Tile::<N>::new();
        let (across, down) = self.frame.tile_grid(N);
        for ty in 0..down {
            for tx in 0..across {
                // Every tile of the grid lies in the frame, the one case in which
                // `render_tile` refuses: there is no render error to report.
                let coord = TileCoord::new(tx, ty);
                if self
                    .frame
                    .render_tile(&self.scene, coord, &mut tile, &mut ())
                    .is_ok()
                {
                    draw_tile(&tile, target)?;
                }
            }
        }
        Ok(())
    }
}

impl TilePixel for Rgb565 {
    const BLACK: Self = Self::new(0, 0, 0);
    #[inline]
    fn from_rgb8(p: Rgb8, x: u32, y: u32, dither: Dither) -> Self {
        let (r, g, b) = dither.rgb565(p, x, y);
        Self::new(r, g, b)
    }
}

impl TilePixel for Rgb555 {
    const BLACK: Self = Self::new(0, 0, 0);
    #[inline]
    fn from_rgb8(p: Rgb8, x: u32, y: u32, dither: Dither) -> Self {
        let (r, g, b) = dither.rgb555(p, x, y);
        Self::new(r, g, b)
    }
}

impl TilePixel for Gray8 {
    const BLACK: Self = Self::new(0);
    #[inline]
    fn from_rgb8(p: Rgb8, x: u32, y: u32, dither: Dither) -> Self {
        Self::new(dither.gray8(p, x, y))
    }
}

impl TilePixel for Rgb888 {
    const BLACK: Self = Self::new(0, 0, 0);
    #[inline]
    fn from_rgb8(p: Rgb8, _: u32, _: u32, _: Dither) -> Self {
        Self::new(p.r, p.g, p.b)
    }
}

/// Sends a tile already in the display's colour (`Tile<N, Rgb565>`, rendered with
/// the frame's [`Dither`]) with one `fill_contiguous` over its rectangle: no
/// conversion on the way.
pub fn draw_panel_tile<D, const N: usize>(
    tile: &Tile<N, D::Color>,
    display: &mut D,
) -> Result<(), D::Error>
where
    D: DrawTarget,
    D::Color: TilePixel,
{
    let (x0, y0) = tile.origin();
    let area = rectangle(x0, y0, u32::from(tile.width()), u32::from(tile.height()));
    display.fill_contiguous(&area, tile.pixels())
}

/// [`draw_tile`] for a panel of fewer bits: each pixel dithered ([`Dither`]) at
/// its position in the frame, so that the pattern is the same for every tile size
/// and order.
pub fn draw_tile_dithered<D, const N: usize>(
    tile: &Tile<N>,
    display: &mut D,
    dither: Dither,
) -> Result<(), D::Error>
where
    D: DrawTarget,
    D::Color: TilePixel,
{
    let (x0, y0) = tile.origin();
    let area = rectangle(x0, y0, u32::from(tile.width()), u32::from(tile.height()));
    let w = usize::from(tile.width()).max(1);
    display.fill_contiguous(
        &area,
        tile.pixels().enumerate().map(|(i, p)| {
            let (dx, dy) = ((i % w) as u32, (i / w) as u32);
            D::Color::from_rgb8(p, x0.wrapping_add(dx), y0.wrapping_add(dy), dither)
        }),
    )
}

/// A frame as a [`Drawable`] on a panel of fewer bits, dithered:
/// [`Frame::drawable_dithered`].
///
/// `L` is the set of tile loops it links ([`Loops`]): every one unless
/// [`DitheredRendering::linking`] says fewer.
///
/// [`Drawable`]: https://docs.rs/embedded-graphics-core/0.4/embedded_graphics_core/trait.Drawable.html
pub struct DitheredRendering<'a, C, const N: usize, L = AllLoops> {
    rendering: Rendering<'a, C, N>,
    dither: Dither,
    // `fn() -> L`: no bounds on `L` for the traits below, and no `L` stored.
    loops: PhantomData<fn() -> L>,
}

// By hand: derived, they would ask `L` (a firmware's `enum` of constants) to be
// `Clone`, `Copy` and `Debug` too (the panel colour `C` still is).
impl<C: Copy, const N: usize, L> Clone for DitheredRendering<'_, C, N, L> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<C: Copy, const N: usize, L> Copy for DitheredRendering<'_, C, N, L> {}

impl<C: core::fmt::Debug, const N: usize, L> core::fmt::Debug for DitheredRendering<'_, C, N, L> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("DitheredRendering")
            .field("rendering", &self.rendering)
            .field("dither", &self.dither)
            .finish_non_exhaustive()
    }
}

impl<'a, C, const N: usize, L> DitheredRendering<'a, C, N, L> {
    /// The same drawing linking only the tile loops of `M` (a firmware with fixed
    /// settings leaves the others out of its image: [`Loops`]).
    ///
    /// # Errors
    /// [`Error::NotLinked`] if the frame's settings and scene need a loop `M`
    /// leaves out ([`Frame::check_loops`]): checked here, once, so the drawing
    /// itself never meets it.
    pub fn linking<M: Loops>(self) -> Result<DitheredRendering<'a, C, N, M>, Error> {
        let r = &self.rendering;
        r.frame.check_loops::<M>(&r.scene)?;
        Ok(DitheredRendering {
            rendering: self.rendering,
            dither: self.dither,
            loops: PhantomData,
        })
    }
}

impl Frame {
    /// [`Frame::drawable`] for a panel colour of fewer bits than the tiles'
    /// (`Rgb565`, `Rgb555`, `Gray8`): each tile rendered into a buffer of the
    /// panel's colour, each pixel dithered by `dither` at its position in the frame
    /// (the same pixels as [`draw_tile_dithered`] of an 8-bit tile).
    #[must_use]
    pub fn drawable_dithered<'a, C, const N: usize>(
        &'a self,
        scene: &SceneView<'a>,
        dither: Dither,
    ) -> DitheredRendering<'a, C, N> {
        DitheredRendering {
            rendering: Rendering {
                frame: self,
                scene: *scene,
                color: PhantomData,
            },
            dither,
            loops: PhantomData,
        }
    }
}

impl<C: TilePixel + PixelColor, const N: usize, L: Loops> Drawable
    for DitheredRendering<'_, C, N, L>
{
    type Color = C;
    type Output = ();

    /// As [`Rendering`]'s `draw`, each tile rendered straight into a buffer of the
    /// panel's colour (`N x N` of `C`: 512 bytes for 16x16 `Rgb565`) with the
    /// dithering, and sent as it is ([`draw_panel_tile`]).
    fn draw<D>(&self, target: &mut D) -> Result<(), D::Error>
    where
        D: DrawTarget<Color = C>,
    {
        let r = &self.rendering;
        let frame = r.frame.with_dither(self.dither);
        let mut tile = Tile::<N, C>::blank();
        let (across, down) = frame.tile_grid(N);
        for ty in 0..down {
            for tx in 0..across {
                let coord = TileCoord::new(tx, ty);
                if frame
                    .render_tile_in::<L, N, _, _>(&r.scene, coord, &mut tile, &mut ())
                    .is_ok()
                {
                    draw_panel_tile(&tile, target)?;
                }
            }
        }
        Ok(())
    }
}

/// A frame drawn progressively: a preview of one ray per `block x block` block,
/// each block filled in one colour, then the tiles as [`DitheredRendering`] draws
/// them, which replace every preview pixel: the final picture is the direct
/// render's. [`Frame::drawable_progressive`].
pub struct ProgressiveRendering<'a, C, const N: usize, L = AllLoops> {
    tiles: DitheredRendering<'a, C, N, L>,
    block: u32,
}

// By hand, as [`DitheredRendering`]'s.
impl<C: Copy, const N: usize, L> Clone for ProgressiveRendering<'_, C, N, L> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<C: Copy, const N: usize, L> Copy for ProgressiveRendering<'_, C, N, L> {}

impl<C: core::fmt::Debug, const N: usize, L> core::fmt::Debug
    for ProgressiveRendering<'_, C, N, L>
{
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("ProgressiveRendering")
            .field("tiles", &self.tiles)
            .field("block", &self.block)
            .finish()
    }
}

impl<'a, C, const N: usize, L> ProgressiveRendering<'a, C, N, L> {
    /// The same drawing linking only the tile loops of `M`
    /// ([`DitheredRendering::linking`]).
    ///
    /// # Errors
    /// [`Error::NotLinked`] if the frame's settings and scene need a loop `M`
    /// leaves out.
    pub fn linking<M: Loops>(self) -> Result<ProgressiveRendering<'a, C, N, M>, Error> {
        Ok(ProgressiveRendering {
            tiles: self.tiles.linking::<M>()?,
            block: self.block,
        })
    }
}

impl Frame {
    /// [`Frame::drawable_dithered`] with a quick first picture: one ray per
    /// `block x block` pixels ([`Frame::preview_color`]), each block drawn with
    /// one `fill_solid` as soon as it is traced, then the tiles. On a slow chip
    /// the picture appears in about `1 / block^2` of a direct render's rays
    /// (`block` 0 is taken as 1).
    #[must_use]
    pub fn drawable_progressive<'a, C, const N: usize>(
        &'a self,
        scene: &SceneView<'a>,
        dither: Dither,
        block: u32,
    ) -> ProgressiveRendering<'a, C, N> {
        ProgressiveRendering {
            tiles: self.drawable_dithered(scene, dither),
            block: block.max(1),
        }
    }

    /// The preview pass of [`Frame::drawable_progressive`] alone: each block's
    /// colour sent to `target` with one `fill_solid`.
    ///
    /// # Errors
    /// The target's.
    pub fn draw_preview<D>(
        &self,
        scene: &SceneView<'_>,
        dither: Dither,
        block: u32,
        target: &mut D,
    ) -> Result<(), D::Error>
    where
        D: DrawTarget,
        D::Color: TilePixel,
    {
        self.draw_preview_in::<AllLoops, D>(scene, dither, block, target)
    }

    /// [`Frame::draw_preview`] with the pixel loops of `L` only.
    fn draw_preview_in<L: Loops, D>(
        &self,
        scene: &SceneView<'_>,
        dither: Dither,
        block: u32,
        target: &mut D,
    ) -> Result<(), D::Error>
    where
        D: DrawTarget,
        D::Color: TilePixel,
    {
        let block = block.max(1);
        let vp = self.viewport();
        let (w, h) = (u32::from(vp.width), u32::from(vp.height));
        for by in 0..h.div_ceil(block) {
            for bx in 0..w.div_ceil(block) {
                let c = self.preview_color_in::<L, _>(scene, (bx, by), block, &mut ());
                let (x, y) = (bx * block, by * block);
                let color = D::Color::from_rgb8(self.settings().encoding.encode(c), x, y, dither);
                let area = rectangle(x, y, block.min(w - x), block.min(h - y));
                target.fill_solid(&area, color)?;
            }
        }
        Ok(())
    }
}

impl<C: TilePixel + PixelColor, const N: usize, L: Loops> Drawable
    for ProgressiveRendering<'_, C, N, L>
{
    type Color = C;
    type Output = ();

    /// The preview, then the tiles.
    fn draw<D>(&self, target: &mut D) -> Result<(), D::Error>
    where
        D: DrawTarget<Color = C>,
    {
        let r = &self.tiles.rendering;
        r.frame
            .draw_preview_in::<L, D>(&r.scene, self.tiles.dither, self.block, target)?;
        self.tiles.draw(target)
    }
}

impl<C, const N: usize, L> OriginDimensions for ProgressiveRendering<'_, C, N, L> {
    fn size(&self) -> Size {
        self.tiles.size()
    }
}

impl<C, const N: usize, L> OriginDimensions for DitheredRendering<'_, C, N, L> {
    fn size(&self) -> Size {
        self.rendering.size()
    }
}

impl<C, const N: usize> OriginDimensions for Rendering<'_, C, N> {
    fn size(&self) -> Size {
        let vp = self.frame.viewport();
        Size::new(u32::from(vp.width), u32::from(vp.height))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Viewport;
    use crate::builtin;
    use crate::tile::RenderSettings;
    use embedded_graphics_core::Pixel;
    use embedded_graphics_core::geometry::OriginDimensions;
    use embedded_graphics_core::pixelcolor::Rgb565;

    /// Records every fill_contiguous rectangle; fails after `fail_after` fills.
    struct Recorder {
        fills: heapless::Vec<Rectangle, 64>,
        fail_after: usize,
    }

    impl OriginDimensions for Recorder {
        fn size(&self) -> Size {
            Size::new(40, 20)
        }
    }

    impl DrawTarget for Recorder {
        type Color = Rgb565;
        type Error = &'static str;
        fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(
            &mut self,
            _: I,
        ) -> Result<(), Self::Error> {
            Err("draw_iter must not be used: tiles go through fill_contiguous")
        }
        fn fill_contiguous<I: IntoIterator<Item = Rgb565>>(
            &mut self,
            area: &Rectangle,
            colors: I,
        ) -> Result<(), Self::Error> {
            if self.fills.len() == self.fail_after {
                return Err("bus error");
            }
            assert_eq!(
                colors.into_iter().count() as u32,
                area.size.width * area.size.height
            );
            self.fills.push(*area).map_err(|_| "full")
        }
    }

    #[test]
    fn one_fill_per_tile_covering_the_frame_once() {
        let scene = builtin::chapter_direct().unwrap();
        let frame = scene
            .frame(Viewport::new(40, 20), RenderSettings::default())
            .unwrap();
        let mut d = Recorder {
            fills: heapless::Vec::new(),
            fail_after: usize::MAX,
        };
        frame.drawable::<_, 16>(&scene.view()).draw(&mut d).unwrap();
        let want = [
            (0, 0, 16, 16),
            (16, 0, 16, 16),
            (32, 0, 8, 16),
            (0, 16, 16, 4),
            (16, 16, 16, 4),
            (32, 16, 8, 4),
        ];
        assert_eq!(d.fills.len(), want.len());
        for (r, (x, y, w, h)) in d.fills.iter().zip(want) {
            assert_eq!(*r, Rectangle::new(Point::new(x, y), Size::new(w, h)));
        }
    }

    #[test]
    fn display_errors_are_returned() {
        let scene = builtin::chapter_direct().unwrap();
        let frame = scene
            .frame(Viewport::new(40, 20), RenderSettings::default())
            .unwrap();
        let mut d = Recorder {
            fills: heapless::Vec::new(),
            fail_after: 2,
        };
        let r = frame.drawable::<_, 16>(&scene.view()).draw(&mut d);
        assert_eq!(r, Err("bus error"));
        assert_eq!(d.fills.len(), 2);
    }

    /// The sizes of panel tiles the docs give (`TilePixel`, `Tile::blank`,
    /// `DitheredRendering`'s `draw`) and README.md's: `2 N^2 + 8` bytes in
    /// `Rgb565` (`Rgb555` too), `N^2 + 8` in `Gray8`.
    #[test]
    fn panel_tile_sizes_match_the_docs() {
        use core::mem::size_of;
        use embedded_graphics_core::pixelcolor::{Gray8, Rgb555};
        let rgb565 = [
            size_of::<Tile<8, Rgb565>>(),
            size_of::<Tile<16, Rgb565>>(),
            size_of::<Tile<32, Rgb565>>(),
        ];
        assert_eq!(rgb565, [136, 520, 2_056]);
        assert_eq!(size_of::<Tile<16, Rgb555>>(), 520);
        let gray8 = [
            size_of::<Tile<8, Gray8>>(),
            size_of::<Tile<16, Gray8>>(),
            size_of::<Tile<32, Gray8>>(),
        ];
        assert_eq!(gray8, [72, 264, 1_032]);
        // The pixels alone of a 16x16 `Rgb565` tile.
        assert_eq!(size_of::<[[Rgb565; 16]; 16]>(), 512);
    }

    /// A tile rendered in a panel's colour is the 8-bit tile dithered pixel by
    /// pixel at its frame position (every built-in scene, every sampler kind, the
    /// adaptive one included, tiles of 8 and 16), and takes 2 bytes a pixel.
    #[test]
    fn panel_tiles_are_the_8_bit_tiles_dithered() {
        use crate::builtin::Builtin;
        use crate::sample::Sampler;
        use embedded_graphics_core::pixelcolor::{Gray8, Rgb555};
        assert_eq!(core::mem::size_of::<Tile<8, Rgb565>>(), 136);
        assert_eq!(core::mem::size_of::<Tile<16, Rgb565>>(), 520);
        assert_eq!(core::mem::size_of::<Tile<16>>(), 776);
        assert_eq!(core::mem::size_of::<Tile<16, Gray8>>(), 264);
        fn check<P: TilePixel + PartialEq + core::fmt::Debug, const N: usize>(
            view: &SceneView<'_>,
            frame: &Frame,
            dither: Dither,
        ) {
            let frame = frame.with_dither(dither);
            let (across, down) = frame.tile_grid(N);
            for ty in 0..down {
                for tx in 0..across {
                    let c = TileCoord::new(tx, ty);
                    let mut rgb = Tile::<N>::new();
                    let mut panel = Tile::<N, P>::blank();
                    frame.render_tile(view, c, &mut rgb, &mut ()).unwrap();
                    frame.render_tile(view, c, &mut panel, &mut ()).unwrap();
                    let (x0, y0) = rgb.origin();
                    for y in 0..usize::from(rgb.height()) {
                        for x in 0..usize::from(rgb.width()) {
                            let want = P::from_rgb8(
                                rgb.pixel(x, y).unwrap(),
                                x0 + x as u32,
                                y0 + y as u32,
                                dither,
                            );
                            assert_eq!(panel.pixel(x, y), Some(want));
                        }
                    }
                }
            }
        }
        for &b in Builtin::ALL {
            for sampler in [
                Sampler::Centre,
                Sampler::Stratified(2),
                Sampler::Adaptive { k: 2, threshold: 8 },
            ] {
                b.with_scene(|view, cam| {
                    let settings = RenderSettings {
                        sampler,
                        ..b.settings()
                    };
                    let frame =
                        Frame::try_new(cam, crate::Viewport::new(37, 29), settings).unwrap();
                    check::<Rgb565, 16>(view, &frame, Dither::Bayer4);
                    check::<Rgb565, 8>(view, &frame, Dither::Bayer8);
                    check::<Rgb555, 16>(view, &frame, Dither::None);
                    check::<Gray8, 8>(view, &frame, Dither::Bayer4);
                })
                .unwrap();
            }
        }
    }

    /// A frame buffer of `C` (`Rgb565` unless said) that counts the pixel writes.
    struct Fb<C = Rgb565> {
        w: u32,
        h: u32,
        px: std::vec::Vec<C>,
        writes: usize,
    }

    extern crate std;

    impl<C> OriginDimensions for Fb<C> {
        fn size(&self) -> Size {
            Size::new(self.w, self.h)
        }
    }

    impl<C: PixelColor> DrawTarget for Fb<C> {
        type Color = C;
        type Error = core::convert::Infallible;
        fn draw_iter<I: IntoIterator<Item = embedded_graphics_core::Pixel<C>>>(
            &mut self,
            pixels: I,
        ) -> Result<(), Self::Error> {
            for embedded_graphics_core::Pixel(p, c) in pixels {
                let (x, y) = (p.x as u32, p.y as u32);
                assert!(x < self.w && y < self.h, "({x}, {y}) outside");
                self.px[(y * self.w + x) as usize] = c;
                self.writes += 1;
            }
            Ok(())
        }
    }

    /// The progressive drawing ends on the direct render's pixels; its preview
    /// paints every pixel, in uniform blocks, with one ray a block.
    #[test]
    fn progressive_drawing_ends_on_the_direct_render() {
        use crate::builtin::Builtin;
        use crate::shade::RayCount;
        for &b in Builtin::ALL {
            b.with_scene(|view, cam| {
                let (w, h) = (45u16, 34u16);
                let frame = Frame::try_new(cam, crate::Viewport::new(w, h), b.settings()).unwrap();
                let fb = || Fb {
                    w: u32::from(w),
                    h: u32::from(h),
                    px: std::vec![Rgb565::new(0, 0, 0); usize::from(w) * usize::from(h)],
                    writes: 0,
                };
                let mut direct = fb();
                frame
                    .drawable_dithered::<Rgb565, 16>(view, Dither::Bayer4)
                    .draw(&mut direct)
                    .unwrap();
                let mut progressive = fb();
                frame
                    .drawable_progressive::<Rgb565, 16>(view, Dither::Bayer4, 4)
                    .draw(&mut progressive)
                    .unwrap();
                assert!(progressive.px == direct.px, "{}", b.name());
                let mut preview = fb();
                frame
                    .draw_preview(view, Dither::Bayer4, 4, &mut preview)
                    .unwrap();
                assert_eq!(preview.writes, usize::from(w) * usize::from(h));
                for by in 0..usize::from(h).div_ceil(4) {
                    for bx in 0..usize::from(w).div_ceil(4) {
                        let first = preview.px[by * 4 * usize::from(w) + bx * 4];
                        for y in by * 4..(by * 4 + 4).min(usize::from(h)) {
                            for x in bx * 4..(bx * 4 + 4).min(usize::from(w)) {
                                assert_eq!(preview.px[y * usize::from(w) + x], first);
                            }
                        }
                    }
                }
                let mut rays = RayCount::default();
                let _ = frame.preview_color(view, (0, 0), 4, &mut rays);
                assert_eq!(rays.primary, 1);
            })
            .unwrap();
        }
    }

    /// A drawing linking only the loops its settings need draws the same pixels;
    /// one linking too few is refused before it draws.
    #[test]
    fn a_drawing_with_fewer_loops_draws_the_same_or_is_refused() {
        use crate::builtin::Builtin;
        /// Direct light only, sRGB, no adaptive sampler.
        enum DirectSrgb {}
        impl Loops for DirectSrgb {
            fn links(l: crate::tile::TileLoop) -> bool {
                l == crate::tile::TileLoop::Direct(crate::Encoding::Srgb)
            }
        }
        for &b in Builtin::ALL {
            b.with_scene(|view, cam| {
                let (w, h) = (37u16, 29u16);
                let frame = Frame::try_new(cam, crate::Viewport::new(w, h), b.settings()).unwrap();
                let fb = || Fb {
                    w: u32::from(w),
                    h: u32::from(h),
                    px: std::vec![Rgb565::new(0, 0, 0); usize::from(w) * usize::from(h)],
                    writes: 0,
                };
                let mut all = fb();
                let drawing = frame.drawable_progressive::<Rgb565, 16>(view, Dither::Bayer4, 4);
                drawing.draw(&mut all).unwrap();
                let direct = view.depth(b.settings().max_depth) == 0;
                match drawing.linking::<DirectSrgb>() {
                    Ok(fewer) => {
                        assert!(direct, "{}", b.name());
                        // Copy and Debug although `DirectSrgb` is neither.
                        let copy = fewer;
                        assert!(std::format!("{copy:?}").starts_with("ProgressiveRendering"));
                        let mut px = fb();
                        fewer.draw(&mut px).unwrap();
                        assert!(px.px == all.px, "{}", b.name());
                    }
                    Err(e) => assert!(!direct && e == Error::NotLinked, "{}", b.name()),
                }
            })
            .unwrap();
        }
    }

    /// A preview block is the colour of the final picture at the pixel its ray
    /// goes through (the block's middle, clamped to the frame), in the frame's
    /// encoding: with centre sampling the same ray, so the same bytes (8-bit
    /// colour: no dithering to move them).
    #[test]
    fn a_preview_block_is_the_final_pixel_at_its_middle_in_either_encoding() {
        use crate::builtin::Builtin;
        use embedded_graphics_core::pixelcolor::Rgb888;
        for &b in Builtin::ALL {
            for encoding in [crate::Encoding::Srgb, crate::Encoding::Linear] {
                b.with_scene(|view, cam| {
                    let (w, h) = (45u16, 34u16);
                    let settings = RenderSettings {
                        sampler: crate::Sampler::Centre,
                        encoding,
                        ..b.settings()
                    };
                    let frame = Frame::try_new(cam, crate::Viewport::new(w, h), settings).unwrap();
                    let fb = || Fb {
                        w: u32::from(w),
                        h: u32::from(h),
                        px: std::vec![Rgb888::new(0, 0, 0); usize::from(w) * usize::from(h)],
                        writes: 0,
                    };
                    let mut direct = fb();
                    frame
                        .drawable_dithered::<Rgb888, 16>(view, Dither::Bayer4)
                        .draw(&mut direct)
                        .unwrap();
                    let mut preview = fb();
                    frame
                        .draw_preview(view, Dither::Bayer4, 4, &mut preview)
                        .unwrap();
                    let (w, h) = (usize::from(w), usize::from(h));
                    for by in 0..h.div_ceil(4) {
                        for bx in 0..w.div_ceil(4) {
                            let (mx, my) = ((bx * 4 + 2).min(w - 1), (by * 4 + 2).min(h - 1));
                            assert_eq!(
                                preview.px[by * 4 * w + bx * 4],
                                direct.px[my * w + mx],
                                "{} {encoding} block ({bx}, {by})",
                                b.name()
                            );
                        }
                    }
                })
                .unwrap();
            }
        }
    }
}
