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
use crate::shade::RayCounter;
pub use crate::tile::TilePixel;
use crate::tile::{AllLoops, Loops, Renderer, Tile, TileCoord};
use crate::view::SceneView;
use core::convert::Infallible;
use core::marker::PhantomData;
use embedded_graphics_core::Drawable;
use embedded_graphics_core::Pixel;
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Dimensions, OriginDimensions, Point, Size};
use embedded_graphics_core::pixelcolor::raw::{RawData, RawU16};
use embedded_graphics_core::pixelcolor::{Gray8, PixelColor, Rgb555, Rgb565, Rgb888, RgbColor};
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

/// The rectangle of the frame a rendered tile covers: its origin and its valid
/// size (an edge tile's is partial). The window a panel's driver opens for it.
#[must_use]
pub fn tile_area<const N: usize, P: TilePixel>(tile: &Tile<N, P>) -> Rectangle {
    let (x0, y0) = tile.origin();
    rectangle(x0, y0, u32::from(tile.width()), u32::from(tile.height()))
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
    let area = tile_area(tile);
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

/// A tile pixel that embedded-graphics draws on: the colour a drawing over a
/// tile is made of ([`DrawPixel::Color`]) and its conversion to the pixel. A
/// `Tile<N, P>` of such pixels is a `DrawTarget` of that colour, in frame
/// coordinates, clipped to the tile: text, shapes and images drawn over each
/// tile after it is rendered and before it is sent make one picture over the
/// whole frame, with no second buffer.
///
/// | tile pixel | colour drawn |
/// |---|---|
/// | [`Rgb8`] | `Rgb888` |
/// | `Rgb888`, `Rgb565`, `Rgb555`, `Gray8` | the same |
/// | [`Rgb565Wire`] | `Rgb565` (stored high byte first) |
///
/// A drawn colour is stored as it is, not dithered: a label's flat colour
/// stays flat.
pub trait DrawPixel: TilePixel {
    /// The embedded-graphics colour drawn on a tile of this pixel.
    type Color: PixelColor;
    /// The pixel of colour `c`.
    fn from_color(c: Self::Color) -> Self;
    /// The colour of this pixel.
    fn to_color(self) -> Self::Color;
}

impl DrawPixel for Rgb8 {
    type Color = Rgb888;
    #[inline]
    fn from_color(c: Rgb888) -> Self {
        Self::new(c.r(), c.g(), c.b())
    }
    #[inline]
    fn to_color(self) -> Rgb888 {
        Rgb888::new(self.r, self.g, self.b)
    }
}

macro_rules! draws_itself {
    ($($c:ty),*) => {$(
        impl DrawPixel for $c {
            type Color = $c;
            #[inline]
            fn from_color(c: $c) -> Self {
                c
            }
            #[inline]
            fn to_color(self) -> $c {
                self
            }
        }
    )*};
}
draws_itself!(Rgb888, Rgb565, Rgb555, Gray8);

/// The pixel of tile `tile` at frame point `p`, if the tile holds it.
fn frame_pixel<const N: usize, P: TilePixel>(tile: &mut Tile<N, P>, p: Point) -> Option<&mut P> {
    let (x0, y0) = tile.origin();
    let x = usize::try_from(i64::from(p.x) - i64::from(x0)).ok()?;
    let y = usize::try_from(i64::from(p.y) - i64::from(y0)).ok()?;
    tile.pixel_mut(x, y)
}

/// The frame's rectangle the tile covers (its rendered part; empty before the
/// first render).
impl<const N: usize, P: DrawPixel> Dimensions for Tile<N, P> {
    fn bounding_box(&self) -> Rectangle {
        tile_area(self)
    }
}

/// A rendered tile as a drawing surface in **frame** coordinates: a pixel drawn
/// at `(x, y)` lands on the tile's pixel `(x - x0, y - y0)` if the tile covers
/// it, and is dropped otherwise, so one drawing drawn over every tile of a frame
/// in turn equals the same drawing over the whole frame.
///
/// ```
/// use embedded_graphics_core::{pixelcolor::Rgb565, prelude::*, primitives::Rectangle};
/// use tessera_core::display::Rgb565Wire;
/// use tessera_core::{builtin, RenderSettings, Tile, TileCoord, Viewport};
///
/// let scene = builtin::chapter_direct()?;
/// let renderer = scene.renderer(Viewport::new(40, 30), RenderSettings::default())?;
/// let mut tile = Tile::<16, Rgb565Wire>::blank();
/// renderer.render_tile(&scene.view(), TileCoord::new(1, 0), &mut tile, &mut ())?;
/// // A bar across the frame's top rows: on this tile, columns 16 to 31 of it.
/// tile.fill_solid(&Rectangle::new(Point::new(0, 0), Size::new(40, 2)), Rgb565::WHITE).unwrap();
/// assert_eq!(tile.pixel(0, 1), Some(Rgb565Wire::from(Rgb565::WHITE)));
/// assert_ne!(tile.pixel(0, 2), Some(Rgb565Wire::from(Rgb565::WHITE)));
/// # Ok::<(), tessera_core::Error>(())
/// ```
impl<const N: usize, P: DrawPixel> DrawTarget for Tile<N, P> {
    type Color = P::Color;
    type Error = Infallible;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Infallible>
    where
        I: IntoIterator<Item = Pixel<P::Color>>,
    {
        for Pixel(p, c) in pixels {
            if let Some(px) = frame_pixel(self, p) {
                *px = P::from_color(c);
            }
        }
        Ok(())
    }

    fn fill_solid(&mut self, area: &Rectangle, color: P::Color) -> Result<(), Infallible> {
        // The overlap in i64, offsets from the tile's origin: any rectangle
        // embedded-graphics can hold (up to `u32::MAX` wide, anywhere) is cut
        // without overflow.
        let (x0, y0) = self.origin();
        let span = |start: i32, len: u32, origin: u32, live: u16| {
            let from = (i64::from(start) - i64::from(origin)).max(0);
            let to = (i64::from(start) - i64::from(origin) + i64::from(len)).min(i64::from(live));
            let from = usize::try_from(from).unwrap_or(usize::MAX);
            (from, usize::try_from(to).unwrap_or(0))
        };
        let (left, right) = span(area.top_left.x, area.size.width, x0, self.width());
        let (top, bottom) = span(area.top_left.y, area.size.height, y0, self.height());
        if left >= right || top >= bottom {
            return Ok(());
        }
        let px = P::from_color(color);
        let w = usize::from(self.width());
        for row in self
            .as_mut_slice()
            .chunks_mut(w.max(1))
            .take(bottom)
            .skip(top)
        {
            for p in row.iter_mut().take(right).skip(left) {
                *p = px;
            }
        }
        Ok(())
    }
}

/// An RGB565 pixel in the order a display controller takes it on the wire: the
/// high byte (red and the top of green) first, as ST7789, ILI9341 and ST7735
/// panels read 16-bit colour. A `Tile<N, Rgb565Wire>` is filled in that order
/// (dithered as [`Rgb565`] is), so its pixels go to the panel as they lie:
/// [`wire_bytes`] is the tile as one byte slice, what a DMA channel sends, with no
/// conversion and no copy ([`Drawing::send`] overlaps those transfers with the
/// rendering of the next tile).
#[repr(transparent)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Rgb565Wire(pub [u8; 2]);

impl TilePixel for Rgb565Wire {
    const BLACK: Self = Self([0, 0]);
    #[inline]
    fn from_rgb8(p: Rgb8, x: u32, y: u32, dither: Dither) -> Self {
        let (r, g, b) = dither.rgb565(p, x, y);
        Self::from(Rgb565::new(r, g, b))
    }
}

impl DrawPixel for Rgb565Wire {
    type Color = Rgb565;
    #[inline]
    fn from_color(c: Rgb565) -> Self {
        Self::from(c)
    }
    #[inline]
    fn to_color(self) -> Rgb565 {
        Rgb565::from(self)
    }
}

impl From<Rgb565> for Rgb565Wire {
    fn from(c: Rgb565) -> Self {
        Self(RawU16::from(c).into_inner().to_be_bytes())
    }
}

impl From<Rgb565Wire> for Rgb565 {
    fn from(w: Rgb565Wire) -> Self {
        Self::from(RawU16::new(u16::from_be_bytes(w.0)))
    }
}

/// A tile's pixels ([`Tile::as_slice`]: `width x height` of them, row after row)
/// as the bytes a panel takes for the tile's window, two a pixel, high byte
/// first: a view of the tile buffer, not a copy.
#[must_use]
pub fn wire_bytes<const N: usize>(tile: &Tile<N, Rgb565Wire>) -> &[u8] {
    let px = tile.as_slice();
    // SAFETY: `Rgb565Wire` is `repr(transparent)` over `[u8; 2]`: two bytes, of
    // alignment 1, no padding, every byte initialised. So `px.len()` of them are
    // `2 * px.len()` initialised bytes at `px`'s address (at most the tile's
    // `2 N^2`, far below `isize::MAX`), read-only and borrowed as long as `px`.
    #[allow(unsafe_code)]
    unsafe {
        core::slice::from_raw_parts(px.as_ptr().cast::<u8>(), 2 * px.len())
    }
}

/// Where a firmware's tiles go without the CPU waiting: a DMA channel feeding the
/// panel's bus (SPI, 8080 parallel), or any transfer that runs on while the next
/// tile renders. [`Drawing::send`] drives it with two tile buffers: it renders
/// tile `k + 1` into one while the transfer of tile `k` reads the other, then
/// waits for that transfer ([`TileSink::finish`]) before it starts the next.
///
/// What makes a DMA transfer sound is on the caller: [`TileSink::start`] is an
/// `unsafe fn` whose caller promises that `bytes` stay in place and unwritten
/// until the [`TileSink::finish`] that follows has returned ([`Drawing::send`]
/// keeps that promise: the buffer lives on its stack throughout). So an
/// implementation may hand `bytes` to a DMA engine that reads them after `start`
/// returns, as long as the transfer does not outlive `finish`.
pub trait TileSink {
    /// The transfer's error.
    type Error;
    /// Starts sending `bytes` ([`wire_bytes`] of a tile) to the panel's window
    /// `area` (set the window first, then the transfer), without waiting for it.
    ///
    /// # Safety
    /// The caller keeps `bytes` in place and unwritten until the next
    /// [`TileSink::finish`] on this sink has returned (or, if this call fails,
    /// until it has returned): the transfer may read them until then.
    ///
    /// # Errors
    /// The sink's; the drawing stops and returns it.
    #[allow(unsafe_code)] // the declaration: the promise is the caller's
    unsafe fn start(&mut self, area: Rectangle, bytes: &[u8]) -> Result<(), Self::Error>;
    /// Waits until the transfer started last is done.
    ///
    /// # Errors
    /// The sink's; the drawing stops and returns it.
    fn finish(&mut self) -> Result<(), Self::Error>;
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
    let area = tile_area(tile);
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
/// use tessera_core::dither::Dither;
/// use tessera_core::display::Drawing;
/// use tessera_core::{builtin, RenderSettings, Viewport};
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
/// # Ok::<(), tessera_core::Error>(())
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
        self.draw_overlaid(target, |_| ())
    }
}

impl<C: TilePixel + PixelColor, const N: usize, L: Loops> Drawing<'_, C, N, L> {
    /// [`Drawable::draw`], with `overlay` called on each tile after it is
    /// rendered and before it is sent: a tile is a `DrawTarget` in frame
    /// coordinates ([`DrawPixel`]), so a label or a shape drawn in `overlay`
    /// lands where it belongs in the frame, cut along the tiles' edges. The
    /// preview of [`Drawing::progressive`] is sent without it.
    ///
    /// ```
    /// use embedded_graphics_core::{pixelcolor::Rgb565, prelude::*, primitives::Rectangle};
    /// # use tessera_core::display::Drawing;
    /// # use tessera_core::{builtin, RenderSettings, Viewport};
    /// # struct Panel;
    /// # impl OriginDimensions for Panel { fn size(&self) -> Size { Size::new(40, 30) } }
    /// # impl DrawTarget for Panel {
    /// #     type Color = Rgb565;
    /// #     type Error = core::convert::Infallible;
    /// #     fn draw_iter<I: IntoIterator<Item = Pixel<Rgb565>>>(&mut self, _: I) -> Result<(), Self::Error> { Ok(()) }
    /// # }
    /// let scene = builtin::chapter_direct()?;
    /// let renderer = scene.renderer(Viewport::new(40, 30), RenderSettings::default())?;
    /// let frame = Drawing::<Rgb565, 16>::new(&renderer, &scene.view());
    /// // A white bar across the frame, drawn over whichever tiles it crosses.
    /// let bar = Rectangle::new(Point::new(0, 12), Size::new(40, 4));
    /// frame.draw_overlaid(&mut Panel, |tile| {
    ///     let _ = tile.fill_solid(&bar, Rgb565::WHITE);
    /// }).unwrap();
    /// # Ok::<(), tessera_core::Error>(())
    /// ```
    ///
    /// # Errors
    /// The target's.
    ///
    /// [`Drawable::draw`]: https://docs.rs/embedded-graphics-core/0.4/embedded_graphics_core/trait.Drawable.html#tymethod.draw
    pub fn draw_overlaid<D, F>(&self, target: &mut D, mut overlay: F) -> Result<(), D::Error>
    where
        D: DrawTarget<Color = C>,
        F: FnMut(&mut Tile<N, C>),
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
                    overlay(&mut tile);
                    draw_panel_tile(&tile, target)?;
                }
            }
        }
        Ok(())
    }
}

impl<const N: usize, L: Loops> Drawing<'_, Rgb565Wire, N, L> {
    /// The frame tile after tile, in rows, each tile's bytes ([`wire_bytes`])
    /// handed to `sink` as soon as it is rendered while the next tile renders into
    /// a second buffer: the transfers overlap the rendering, and the time a frame
    /// takes is about the larger of the two, not their sum. Two tile buffers on
    /// the stack (`2 N^2 + 8` bytes each). The preview of
    /// [`Drawing::progressive`] is not sent: draw it first with
    /// [`Drawing::draw_preview`] on a target if wanted.
    ///
    /// # Errors
    /// The sink's: the drawing stops at the first (every transfer but a failed
    /// one has finished by then).
    pub fn send<S: TileSink>(&self, sink: &mut S) -> Result<(), S::Error> {
        self.send_counting(sink, &mut ())
    }

    /// [`Drawing::send`], with `overlay` called on each tile after it is
    /// rendered and before its transfer starts (as [`Drawing::draw_overlaid`]):
    /// a label drawn over the frame on its way to the panel.
    ///
    /// # Errors
    /// As [`Drawing::send`].
    pub fn send_overlaid<S: TileSink, F: FnMut(&mut Tile<N, Rgb565Wire>)>(
        &self,
        sink: &mut S,
        overlay: F,
    ) -> Result<(), S::Error> {
        self.send_with(sink, &mut (), overlay)
    }

    /// [`Drawing::send`], the rays cast added to `count`.
    ///
    /// # Errors
    /// As [`Drawing::send`].
    pub fn send_counting<S: TileSink, R: RayCounter>(
        &self,
        sink: &mut S,
        count: &mut R,
    ) -> Result<(), S::Error> {
        self.send_with(sink, count, |_| ())
    }

    fn send_with<S: TileSink, R: RayCounter, F: FnMut(&mut Tile<N, Rgb565Wire>)>(
        &self,
        sink: &mut S,
        count: &mut R,
        mut overlay: F,
    ) -> Result<(), S::Error> {
        let mut tiles = [Tile::<N, Rgb565Wire>::blank(), Tile::blank()];
        let mut in_flight = false;
        let (across, down) = self.renderer.tile_grid(N);
        let coords = (0..down).flat_map(|ty| (0..across).map(move |tx| TileCoord::new(tx, ty)));
        for (k, coord) in coords.enumerate() {
            let [a, b] = &mut tiles;
            let tile = if k % 2 == 0 { a } else { b };
            // Every tile of the grid lies in the frame, and `L` was checked when
            // linked: there is no render error to report.
            let rendered = self
                .renderer
                .render_tile_in::<L, N, _, _>(&self.scene, coord, tile, count)
                .is_ok();
            // Drawn while the other buffer's transfer runs.
            if rendered {
                overlay(tile);
            }
            // The other buffer's transfer is done before this one starts (and
            // before that buffer is rendered into again, next turn).
            if in_flight {
                in_flight = false;
                sink.finish()?;
            }
            if rendered {
                // SAFETY: this buffer is written again (rendered into) only after
                // the `finish` at the top of the turn after next, and both
                // buffers live on this stack frame until the last `finish` below.
                #[allow(unsafe_code)]
                unsafe {
                    sink.start(tile_area(tile), wire_bytes(tile))?;
                }
                in_flight = true;
            }
        }
        if in_flight {
            sink.finish()?;
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

    #[test]
    fn wire_pixels_are_rgb565_high_byte_first() {
        for (c, bytes) in [
            (Rgb565::new(31, 0, 0), [0xf8, 0x00]),
            (Rgb565::new(0, 63, 0), [0x07, 0xe0]),
            (Rgb565::new(0, 0, 31), [0x00, 0x1f]),
            (Rgb565::new(1, 2, 3), [0x08, 0x43]),
        ] {
            assert_eq!(Rgb565Wire::from(c).0, bytes);
            assert_eq!(Rgb565::from(Rgb565Wire(bytes)), c);
        }
        let p = Rgb8::new(200, 100, 50);
        for d in Dither::ALL {
            for (x, y) in [(0, 0), (3, 1), (2, 7)] {
                let want = Rgb565Wire::from(Rgb565::from_rgb8(p, x, y, d));
                assert_eq!(Rgb565Wire::from_rgb8(p, x, y, d), want);
            }
        }
    }

    #[test]
    fn wire_bytes_are_the_tile_as_a_panel_takes_it() {
        let b = builtin::Builtin::Showcase;
        b.with_scene(|view, cam| {
            // 37 x 21 in tiles of 16: full, right-edge and bottom-edge tiles.
            let r = Renderer::try_new(cam, Viewport::new(37, 21), b.settings()).unwrap();
            let (mut wire, mut panel) =
                (Tile::<16, Rgb565Wire>::blank(), Tile::<16, Rgb565>::blank());
            for c in [
                TileCoord::new(0, 0),
                TileCoord::new(2, 0),
                TileCoord::new(1, 1),
            ] {
                r.render_tile(view, c, &mut wire, &mut ()).unwrap();
                r.render_tile(view, c, &mut panel, &mut ()).unwrap();
                let bytes = wire_bytes(&wire);
                let n = usize::from(wire.width()) * usize::from(wire.height());
                assert_eq!(bytes.len(), 2 * n, "{c:?}");
                let want: std::vec::Vec<u8> =
                    panel.pixels().flat_map(|p| Rgb565Wire::from(p).0).collect();
                assert_eq!(bytes, &want[..], "{c:?}");
            }
        })
        .unwrap();
    }

    /// Counts rays on a clock a [`MockBus`] shares: one tick a ray, the time of
    /// this model.
    struct Ticks<'c>(&'c core::cell::Cell<u64>);

    impl crate::shade::sealed::Sealed for Ticks<'_> {}

    impl RayCounter for Ticks<'_> {
        fn primary(&mut self) {
            self.0.set(self.0.get() + 1);
        }
        fn secondary(&mut self) {
            self.0.set(self.0.get() + 1);
        }
        fn shadow(&mut self) {
            self.0.set(self.0.get() + 1);
        }
    }

    /// A panel behind a DMA-like bus: a transfer takes `delay` ticks from its
    /// start, reads the tile's bytes only when it completes (as a DMA engine
    /// reads the buffer while it runs: bytes changed before `finish` would show),
    /// and `finish` before then waits (the clock jumps to the completion).
    struct MockBus<'c> {
        clock: &'c core::cell::Cell<u64>,
        delay: u64,
        width: usize,
        panel: std::vec::Vec<Option<[u8; 2]>>,
        /// The transfer in flight: its window, its bytes, when it completes.
        flight: Option<(Rectangle, *const u8, usize, u64)>,
        /// Per transfer: the clock at its start and when `finish` was called.
        log: std::vec::Vec<(u64, u64)>,
        fail_at: usize,
    }

    impl TileSink for MockBus<'_> {
        type Error = &'static str;
        #[allow(unsafe_code)]
        unsafe fn start(&mut self, area: Rectangle, bytes: &[u8]) -> Result<(), Self::Error> {
            if self.flight.is_some() {
                return Err("a transfer started while another is in flight");
            }
            if self.log.len() == self.fail_at {
                return Err("bus fault");
            }
            let now = self.clock.get();
            self.flight = Some((area, bytes.as_ptr(), bytes.len(), now + self.delay));
            self.log.push((now, 0));
            Ok(())
        }
        fn finish(&mut self) -> Result<(), Self::Error> {
            let (area, ptr, len, done) = self.flight.take().ok_or("finish with no transfer")?;
            if let Some(last) = self.log.last_mut() {
                last.1 = self.clock.get();
            }
            self.clock.set(self.clock.get().max(done));
            // SAFETY: `TileSink`'s contract: the bytes given to `start` stay in
            // place, unwritten, until this `finish` returns.
            #[allow(unsafe_code)]
            let bytes = unsafe { core::slice::from_raw_parts(ptr, len) };
            let (x0, y0) = (area.top_left.x as usize, area.top_left.y as usize);
            let w = area.size.width as usize;
            for (i, px) in bytes.chunks(2).enumerate() {
                let at = (y0 + i / w) * self.width + x0 + i % w;
                self.panel[at] = Some([px[0], px[1]]);
            }
            Ok(())
        }
    }

    #[test]
    fn send_renders_the_next_tile_while_the_bus_sends_the_last() {
        let b = builtin::Builtin::ChapterReflect;
        b.with_scene(|view, cam| {
            let (w, h) = (45u16, 38u16);
            let r = Renderer::try_new(cam, Viewport::new(w, h), b.settings()).unwrap();
            let clock = core::cell::Cell::new(0);
            // A transfer as long as rendering about 100 pixels' rays: less than a
            // tile's, so the bus never holds the renderer up here.
            let mut bus = MockBus {
                clock: &clock,
                delay: 150,
                width: usize::from(w),
                panel: std::vec![None; usize::from(w) * usize::from(h)],
                flight: None,
                log: std::vec::Vec::new(),
                fail_at: usize::MAX,
            };
            Drawing::<Rgb565Wire, 16>::new(&r, view)
                .send_counting(&mut bus, &mut Ticks(&clock))
                .unwrap();
            assert_eq!(bus.log.len(), 9, "3 x 3 tiles, one transfer each");
            // Rays were traced between each transfer's start and its finish
            // (the next tile rendered while it was in flight), but the last's.
            let (last, rest) = bus.log.split_last().unwrap();
            for (k, (start, finish)) in rest.iter().enumerate() {
                assert!(
                    finish > start,
                    "tile {k}: nothing rendered during its transfer"
                );
                assert!(
                    finish - start >= bus.delay,
                    "tile {k}: the bus waited on the renderer"
                );
            }
            assert_eq!(last.1, last.0, "nothing is left to render during the last");
            // Every pixel arrived, as the tiles render it for an Rgb565 panel.
            let mut rays = ();
            for y in 0..u32::from(h) {
                for x in 0..u32::from(w) {
                    let c = r.pixel_color(view, x, y, &mut rays);
                    let want = Rgb565Wire::from_rgb8(c.to_srgb8(), x, y, r.dither());
                    let at = y as usize * usize::from(w) + x as usize;
                    assert_eq!(bus.panel[at], Some(want.0), "({x}, {y})");
                }
            }
            // The whole frame: the rays plus the last transfer, not plus all nine.
            let rays_traced = clock.get() - bus.delay;
            let mut count = crate::trace::RayCount::default();
            Drawing::<Rgb565Wire, 16>::new(&r, view)
                .send_counting(&mut NullSink, &mut count)
                .unwrap();
            assert_eq!(rays_traced, count.total());
        })
        .unwrap();
    }

    #[test]
    fn a_sink_error_stops_the_drawing() {
        let b = builtin::Builtin::ChapterDirect;
        b.with_scene(|view, cam| {
            let r = Renderer::try_new(cam, Viewport::new(40, 40), b.settings()).unwrap();
            let clock = core::cell::Cell::new(0);
            let mut bus = MockBus {
                clock: &clock,
                delay: 10,
                width: 40,
                panel: std::vec![None; 1600],
                flight: None,
                log: std::vec::Vec::new(),
                fail_at: 4,
            };
            let e = Drawing::<Rgb565Wire, 16>::new(&r, view)
                .send_counting(&mut bus, &mut Ticks(&clock));
            assert_eq!(e, Err("bus fault"));
            assert_eq!(bus.log.len(), 4);
            assert!(
                bus.flight.is_none(),
                "the transfer before the fault was finished"
            );
        })
        .unwrap();
    }

    /// A sink that sends nothing.
    struct NullSink;

    impl TileSink for NullSink {
        type Error = core::convert::Infallible;
        #[allow(unsafe_code)]
        unsafe fn start(&mut self, _: Rectangle, _: &[u8]) -> Result<(), Self::Error> {
            Ok(())
        }
        fn finish(&mut self) -> Result<(), Self::Error> {
            Ok(())
        }
    }

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
    /// adaptive and sparse ones included, tiles of 8 and 16), and takes 2 bytes a
    /// pixel.
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
                Sampler::sparse(),
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
