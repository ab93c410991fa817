//! Tiles straight onto a display: any `embedded-graphics` [`DrawTarget`] whose colour
//! converts from `Rgb888` (`Rgb565` panels are the main case).
//!
//! Each tile goes out through one `fill_contiguous` call with the tile's rectangle,
//! so a driver that streams an address window (ST7789, ILI9341, ...) receives a
//! whole tile per window. There is no framebuffer: the RAM is the caller's tile
//! buffer plus the renderer's stack. Errors of the display are returned, never
//! swallowed.

use crate::error::Error;
use crate::scene::SceneView;
use crate::tile::{Frame, Tile, TileCoord};
use core::fmt;
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::geometry::{Point, Size};
use embedded_graphics_core::pixelcolor::Rgb888;
use embedded_graphics_core::primitives::Rectangle;

/// What can fail while drawing a frame: rendering, or the display itself.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrawError<E> {
    /// The renderer refused (a tile outside the frame).
    Render(Error),
    /// The display returned an error.
    Display(E),
}

impl<E: fmt::Debug> fmt::Display for DrawError<E> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Render(e) => write!(f, "render: {e}"),
            Self::Display(e) => write!(f, "display: {e:?}"),
        }
    }
}

/// Sends a rendered tile to `display` with one `fill_contiguous` over the tile's
/// rectangle (its valid part: edge tiles may be partial).
pub fn draw_tile<D, const N: usize>(tile: &Tile<N>, display: &mut D) -> Result<(), D::Error>
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
{
    let (x0, y0) = tile.origin();
    let area = Rectangle::new(
        Point::new(
            i32::try_from(x0).unwrap_or(i32::MAX),
            i32::try_from(y0).unwrap_or(i32::MAX),
        ),
        Size::new(u32::from(tile.width()), u32::from(tile.height())),
    );
    display.fill_contiguous(
        &area,
        tile.pixels()
            .map(|p| D::Color::from(Rgb888::new(p.r, p.g, p.b))),
    )
}

impl Frame {
    /// Renders the whole frame onto `display`, tile after tile in rows, through the
    /// caller's `tile` buffer: the only pixel memory used.
    ///
    /// ```
    /// use embedded_graphics_core::{pixelcolor::Rgb565, prelude::*, primitives::Rectangle};
    /// use tessera::{builtin, RenderSettings, Tile, Viewport};
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
    /// let mut display = Count(0);
    /// frame.draw(&scene.view(), &mut Tile::<16>::new(), &mut display).unwrap();
    /// assert_eq!(display.0, 40 * 30);
    /// # Ok::<(), tessera::Error>(())
    /// ```
    pub fn draw<D, const N: usize>(
        &self,
        scene: &SceneView<'_>,
        tile: &mut Tile<N>,
        display: &mut D,
    ) -> Result<(), DrawError<D::Error>>
    where
        D: DrawTarget,
        D::Color: From<Rgb888>,
    {
        let (across, down) = self.tile_grid(N);
        for ty in 0..down {
            for tx in 0..across {
                self.render_tile(scene, TileCoord::new(tx, ty), tile)
                    .map_err(DrawError::Render)?;
                draw_tile(tile, display).map_err(DrawError::Display)?;
            }
        }
        Ok(())
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
        frame
            .draw(&scene.view(), &mut Tile::<16>::new(), &mut d)
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
        let frame = scene
            .frame(Viewport::new(40, 20), RenderSettings::default())
            .unwrap();
        let mut d = Recorder {
            fills: heapless::Vec::new(),
            fail_after: 2,
        };
        let r = frame.draw(&scene.view(), &mut Tile::<16>::new(), &mut d);
        assert_eq!(r, Err(DrawError::Display("bus error")));
        assert_eq!(d.fills.len(), 2);
    }
}
