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
use crate::tile::{AllLoops, Loops, Renderer, Tile, TileCoord};
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

/// A frame of a scene as an embedded-graphics [`Drawable`]: the one way to draw a
/// whole frame. Tiles of `N x N` in the display's colour `C` (a [`TilePixel`]:
/// `Rgb888`, or a panel's `Rgb565`, `Rgb555`, `Gray8`, each pixel dithered at its
/// position in the frame by the frame's [`Dither`] ([`Renderer::with_dither`]) unless
/// [`Drawing::dithered`] says otherwise), each rendered straight into a buffer of
/// the panel's colour and sent with one `fill_contiguous` ([`draw_panel_tile`]).
/// Options: [`Drawing::dithered`], [`Drawing::progressive`] (a one-ray-per-block
/// preview first), [`Drawing::linking`] (only the tile loops `L` a firmware
/// needs). For tiles a firmware renders and sends itself: [`draw_tile`],
/// [`draw_panel_tile`].
///
/// Its size ([`OriginDimensions`]) is the viewport's, at the origin; draw it
/// through a translated or clipped target to place it, like any other drawable.
/// Drawing renders: the pixel memory is one [`Tile<N, C>`](Tile) on the stack of
/// `draw` (`N^2` pixels of `C` and 8 bytes: a tile of 16x16 is 776 bytes in
/// `Rgb888`, and a tile of 16x16 `Rgb565` is 520
/// bytes).
///
/// ```
/// use embedded_graphics_core::{pixelcolor::Rgb565, prelude::*};
/// use tessera::dither::Dither;
/// use tessera::display::Drawing;
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
/// let renderer = scene.renderer(Viewport::new(40, 30), RenderSettings::default())?;
/// let picture = Drawing::<Rgb565, 16>::new(&renderer, &scene.view()).dithered(Dither::Bayer4);
/// assert_eq!(picture.size(), Size::new(40, 30));
/// let mut display = Count(0);
/// picture.draw(&mut display).unwrap();
/// assert_eq!(display.0, 40 * 30);
/// # Ok::<(), tessera::Error>(())
/// ```
///
/// [`Drawable`]: https://docs.rs/embedded-graphics-core/0.4/embedded_graphics_core/trait.Drawable.html
/// [`OriginDimensions`]: https://docs.rs/embedded-graphics-core/0.4/embedded_graphics_core/geometry/trait.OriginDimensions.html
pub struct Drawing<'a, C, const N: usize, L = AllLoops> {
    renderer: Renderer,
    scene: SceneView<'a>,
    /// The preview's block size (0: no preview).
    block: u32,
    // `fn() -> _`: no bounds on `C` and `L` for the traits below, none stored.
    kinds: PhantomData<fn() -> (C, L)>,
}

// By hand: derived, they would ask `C` and `L` (a firmware's `enum` of constants)
// to be `Clone`, `Copy` and `Debug` too.
impl<C, const N: usize, L> Clone for Drawing<'_, C, N, L> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<C, const N: usize, L> Copy for Drawing<'_, C, N, L> {}

impl<C, const N: usize, L> core::fmt::Debug for Drawing<'_, C, N, L> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Drawing")
            .field("renderer", &self.renderer)
            .field("block", &self.block)
            .finish_non_exhaustive()
    }
}

impl<'a, C, const N: usize> Drawing<'a, C, N> {
    /// `frame` of `scene`, every tile loop linked, no preview.
    #[must_use]
    pub fn new(renderer: &Renderer, scene: &SceneView<'a>) -> Self {
        Self {
            renderer: *renderer,
            scene: *scene,
            block: 0,
            kinds: PhantomData,
        }
    }
}

impl<'a, C, const N: usize, L> Drawing<'a, C, N, L> {
    /// The same drawing with its pixels dithered by `dither` (for a panel of
    /// fewer bits than the tiles' 8 per channel: no banding).
    #[must_use]
    pub fn dithered(self, dither: Dither) -> Self {
        Self {
            renderer: self.renderer.with_dither(dither),
            ..self
        }
    }

    /// The same drawing with a quick first picture: one ray per `block x block`
    /// pixels ([`Renderer::preview_color`]), each block drawn with one `fill_solid`
    /// as soon as it is traced, then the tiles, which replace every preview
    /// pixel. On a slow chip the picture appears in about `1 / block^2` of a
    /// direct render's rays (`block` 0 is taken as 1).
    #[must_use]
    pub fn progressive(self, block: u32) -> Self {
        Self {
            block: block.max(1),
            ..self
        }
    }

    /// The same drawing linking only the tile loops of `M` (a firmware with fixed
    /// settings leaves the others out of its image: [`Loops`]).
    ///
    /// # Errors
    /// [`Error::NotLinked`] if the frame's settings and scene need a loop `M`
    /// leaves out ([`Renderer::check_loops`]): checked here, once, so the drawing
    /// itself never meets it.
    pub fn linking<M: Loops>(self) -> Result<Drawing<'a, C, N, M>, Error> {
        self.renderer.check_loops::<M>(&self.scene)?;
        Ok(Drawing {
            renderer: self.renderer,
            scene: self.scene,
            block: self.block,
            kinds: PhantomData,
        })
    }
}

impl<C: TilePixel + PixelColor, const N: usize, L: Loops> Drawing<'_, C, N, L> {
    /// The preview pass alone (block 1 without [`Drawing::progressive`]): each
    /// block's colour sent to `target` with one `fill_solid`.
    ///
    /// # Errors
    /// The target's.
    pub fn draw_preview<D: DrawTarget<Color = C>>(&self, target: &mut D) -> Result<(), D::Error> {
        let renderer = &self.renderer;
        let block = self.block.max(1);
        let vp = renderer.viewport();
        let (w, h) = (u32::from(vp.width), u32::from(vp.height));
        for by in 0..h.div_ceil(block) {
            for bx in 0..w.div_ceil(block) {
                let c = renderer.preview_color_in::<L, _>(&self.scene, (bx, by), block, &mut ());
                let (x, y) = (bx * block, by * block);
                let rgb = renderer.settings().encoding.encode(c);
                let color = C::from_rgb8(rgb, x, y, renderer.dither());
                let area = rectangle(x, y, block.min(w - x), block.min(h - y));
                target.fill_solid(&area, color)?;
            }
        }
        Ok(())
    }
}

impl<C: TilePixel + PixelColor, const N: usize, L: Loops> Drawable for Drawing<'_, C, N, L> {
    type Color = C;
    type Output = ();

    /// The preview (with [`Drawing::progressive`]), then the frame tile after
    /// tile, in rows, each tile sent to `target` as soon as it is rendered. An
    /// error of the target stops the drawing and is returned.
    fn draw<D>(&self, target: &mut D) -> Result<(), D::Error>
    where
        D: DrawTarget<Color = C>,
    {
        if self.block > 0 {
            self.draw_preview(target)?;
        }
        let mut tile = Tile::<N, C>::blank();
        let (across, down) = self.renderer.tile_grid(N);
        for ty in 0..down {
            for tx in 0..across {
                // Every tile of the grid lies in the frame, and `L` was checked
                // when linked: there is no render error to report.
                let coord = TileCoord::new(tx, ty);
                if self
                    .renderer
                    .render_tile_in::<L, N, _, _>(&self.scene, coord, &mut tile, &mut ())
                    .is_ok()
                {
                    draw_panel_tile(&tile, target)?;
                }
            }
        }
        Ok(())
    }
}

impl<C, const N: usize, L> OriginDimensions for Drawing<'_, C, N, L> {
    fn size(&self) -> Size {
        let vp = self.renderer.viewport();
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
        let renderer = scene
            .renderer(Viewport::new(40, 20), RenderSettings::default())
            .unwrap();
        let mut d = Recorder {
            fills: heapless::Vec::new(),
            fail_after: usize::MAX,
        };
        Drawing::<_, 16>::new(&renderer, &scene.view())
            .draw(&mut d)
            .unwrap();
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
        let renderer = scene
            .renderer(Viewport::new(40, 20), RenderSettings::default())
            .unwrap();
        let mut d = Recorder {
            fills: heapless::Vec::new(),
            fail_after: 2,
        };
        let r = Drawing::<_, 16>::new(&renderer, &scene.view()).draw(&mut d);
        assert_eq!(r, Err("bus error"));
        assert_eq!(d.fills.len(), 2);
    }

    /// The sizes of panel tiles the docs give (`TilePixel`, `Tile::blank`,
    /// `Drawing`'s `draw`) and docs/firmware.md's: `2 N^2 + 8` bytes in
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
            renderer: &Renderer,
            dither: Dither,
        ) {
            let renderer = renderer.with_dither(dither);
            let (across, down) = renderer.tile_grid(N);
            for ty in 0..down {
                for tx in 0..across {
                    let c = TileCoord::new(tx, ty);
                    let mut rgb = Tile::<N>::new();
                    let mut panel = Tile::<N, P>::blank();
                    renderer.render_tile(view, c, &mut rgb, &mut ()).unwrap();
                    renderer.render_tile(view, c, &mut panel, &mut ()).unwrap();
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
                    let renderer =
                        Renderer::try_new(cam, crate::Viewport::new(37, 29), settings).unwrap();
                    check::<Rgb565, 16>(view, &renderer, Dither::Bayer4);
                    check::<Rgb565, 8>(view, &renderer, Dither::Bayer8);
                    check::<Rgb555, 16>(view, &renderer, Dither::None);
                    check::<Gray8, 8>(view, &renderer, Dither::Bayer4);
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
                let renderer =
                    Renderer::try_new(cam, crate::Viewport::new(w, h), b.settings()).unwrap();
                let fb = || Fb {
                    w: u32::from(w),
                    h: u32::from(h),
                    px: std::vec![Rgb565::new(0, 0, 0); usize::from(w) * usize::from(h)],
                    writes: 0,
                };
                let mut direct = fb();
                Drawing::<Rgb565, 16>::new(&renderer, view)
                    .dithered(Dither::Bayer4)
                    .draw(&mut direct)
                    .unwrap();
                let mut progressive = fb();
                Drawing::<Rgb565, 16>::new(&renderer, view)
                    .dithered(Dither::Bayer4)
                    .progressive(4)
                    .draw(&mut progressive)
                    .unwrap();
                assert!(progressive.px == direct.px, "{}", b.name());
                let mut preview = fb();
                Drawing::<_, 16>::new(&renderer, view)
                    .dithered(Dither::Bayer4)
                    .progressive(4)
                    .draw_preview(&mut preview)
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
                let _ = renderer.preview_color(view, (0, 0), 4, &mut rays);
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
                let renderer =
                    Renderer::try_new(cam, crate::Viewport::new(w, h), b.settings()).unwrap();
                let fb = || Fb {
                    w: u32::from(w),
                    h: u32::from(h),
                    px: std::vec![Rgb565::new(0, 0, 0); usize::from(w) * usize::from(h)],
                    writes: 0,
                };
                let mut all = fb();
                let drawing = Drawing::<Rgb565, 16>::new(&renderer, view)
                    .dithered(Dither::Bayer4)
                    .progressive(4);
                drawing.draw(&mut all).unwrap();
                let direct = view.depth(b.settings().max_depth) == 0;
                match drawing.linking::<DirectSrgb>() {
                    Ok(fewer) => {
                        assert!(direct, "{}", b.name());
                        // Copy and Debug although `DirectSrgb` is neither.
                        let copy = fewer;
                        assert!(std::format!("{copy:?}").starts_with("Drawing"));
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
                    let renderer =
                        Renderer::try_new(cam, crate::Viewport::new(w, h), settings).unwrap();
                    let fb = || Fb {
                        w: u32::from(w),
                        h: u32::from(h),
                        px: std::vec![Rgb888::new(0, 0, 0); usize::from(w) * usize::from(h)],
                        writes: 0,
                    };
                    let mut direct = fb();
                    Drawing::<Rgb888, 16>::new(&renderer, view)
                        .dithered(Dither::Bayer4)
                        .draw(&mut direct)
                        .unwrap();
                    let mut preview = fb();
                    Drawing::<_, 16>::new(&renderer, view)
                        .dithered(Dither::Bayer4)
                        .progressive(4)
                        .draw_preview(&mut preview)
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
