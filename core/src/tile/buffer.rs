//! A tile and its place in the frame: [`TileCoord`], [`Tile`] and its pixel types ([`TilePixel`]).

#[cfg(doc)]
use super::Renderer;
use crate::color::Rgb8;
use crate::dither::Dither;

/// Which tile of the frame: tile `(tx, ty)` covers pixels `tx*N .. tx*N + N` by
/// `ty*N .. ty*N + N`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
    pub(super) coord: TileCoord,
    pub(super) width: u16,
    pub(super) height: u16,
    pub(super) pixels: [[P; N]; N],
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
    /// Pixel `(x, y)` of the tile to change, if it holds one (a firmware's own
    /// marks over the picture; [`crate::display`] makes the tile an
    /// embedded-graphics `DrawTarget` in frame coordinates).
    #[must_use]
    pub fn pixel_mut(&mut self, x: usize, y: usize) -> Option<&mut P> {
        if x < usize::from(self.width) && y < usize::from(self.height) {
            let w = usize::from(self.width);
            self.as_mut_slice().get_mut(y * w + x)
        } else {
            None
        }
    }
    /// [`Tile::as_slice`], to change: the `width x height` pixels of the
    /// picture, row after row. The rest of the buffer stays black.
    #[must_use]
    pub fn as_mut_slice(&mut self) -> &mut [P] {
        let live = usize::from(self.width) * usize::from(self.height);
        self.pixels
            .as_flattened_mut()
            .get_mut(..live)
            .unwrap_or(&mut [])
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
