//! Drawing over rendered tiles: a tile is an embedded-graphics `DrawTarget` in
//! frame coordinates, clipped to the tile (`tessera_core::display::DrawPixel`).
//!
//! The expectation is embedded-graphics' own: the same drawing over the whole
//! frame on its `MockDisplay`, clipped to the frame by its `Clipped` adapter.
//! A drawing that crosses the tiles' edges, drawn tile by tile, must equal it
//! pixel for pixel, in every pixel format a tile holds.

use embedded_graphics::mock_display::MockDisplay;
use embedded_graphics::mono_font::MonoTextStyle;
use embedded_graphics::mono_font::ascii::FONT_6X10;
use embedded_graphics::pixelcolor::raw::{RawData, RawU16};
use embedded_graphics::pixelcolor::{Gray8, Rgb555, Rgb565, Rgb888};
use embedded_graphics::prelude::*;
use embedded_graphics::primitives::{
    Circle, Line, PrimitiveStyle, Rectangle, RoundedRectangle, Triangle,
};
use embedded_graphics::text::Text;
use std::fmt::Debug;
use tessera_core::builtin::Builtin;
use tessera_core::color::Rgb8;
use tessera_core::display::{DrawPixel, Drawing, Rgb565Wire, TileSink};
use tessera_core::tile::TilePixel;
use tessera_core::{Renderer, Tile, TileCoord, Viewport};

/// The frame: 61 x 45 in tiles of 16, so the right column and the bottom row of
/// tiles are partial (13 pixels).
const W: u32 = 61;
const H: u32 = 45;
const N: usize = 16;

fn renderer(b: Builtin, cam: &tessera_core::Camera) -> Renderer {
    Renderer::try_new(cam, Viewport::new(W as u16, H as u16), b.settings()).unwrap()
}

/// A drawing over the frame that crosses tile edges and the frame's edges: a
/// label across the first tile corner, a ring over four tiles, a line across
/// the frame from beyond its left edge, filled shapes beyond its top-left and
/// bottom-right corners, a triangle, single pixels on tile borders.
fn overlay<D>(target: &mut D)
where
    D: DrawTarget,
    D::Color: From<Rgb888>,
    D::Error: Debug,
{
    let c = |r, g, b| D::Color::from(Rgb888::new(r, g, b));
    Text::new(
        "FPS 5",
        Point::new(6, 19),
        MonoTextStyle::new(&FONT_6X10, c(255, 255, 0)),
    )
    .draw(target)
    .unwrap();
    Circle::with_center(Point::new(32, 16), 21)
        .into_styled(PrimitiveStyle::with_stroke(c(255, 0, 255), 3))
        .draw(target)
        .unwrap();
    Line::new(Point::new(-5, 40), Point::new(70, 2))
        .into_styled(PrimitiveStyle::with_stroke(c(0, 255, 255), 1))
        .draw(target)
        .unwrap();
    Rectangle::new(Point::new(-10, -10), Size::new(20, 20))
        .into_styled(PrimitiveStyle::with_fill(c(255, 0, 0)))
        .draw(target)
        .unwrap();
    target
        .fill_solid(
            &Rectangle::new(Point::new(40, 30), Size::new(40, 40)),
            c(0, 0, 255),
        )
        .unwrap();
    RoundedRectangle::with_equal_corners(
        Rectangle::new(Point::new(14, 28), Size::new(22, 9)),
        Size::new(4, 4),
    )
    .into_styled(PrimitiveStyle::with_fill(c(10, 200, 30)))
    .draw(target)
    .unwrap();
    Triangle::new(Point::new(44, 8), Point::new(60, 14), Point::new(47, 26))
        .into_styled(PrimitiveStyle::with_fill(c(255, 255, 255)))
        .draw(target)
        .unwrap();
    target
        .draw_iter(
            [
                (15, 15),
                (16, 16),
                (47, 31),
                (48, 32),
                (60, 44),
                (61, 44),
                (60, 45),
                (-1, 0),
            ]
            .map(|(x, y)| Pixel(Point::new(x, y), c(128, 64, 32))),
        )
        .unwrap();
}

/// A frame on embedded-graphics' mock display, from tiles of pixel `P`.
fn frame<P: DrawPixel>() -> MockDisplay<P::Color> {
    let mut d = MockDisplay::new();
    d.set_allow_overdraw(true);
    d
}

/// Copies a tile's pixels onto the mock display at their frame position.
fn put<P: DrawPixel>(d: &mut MockDisplay<P::Color>, tile: &Tile<N, P>) {
    let (x0, y0) = tile.origin();
    for y in 0..usize::from(tile.height()) {
        for x in 0..usize::from(tile.width()) {
            let p = tile.pixel(x, y).unwrap().to_color();
            d.set_pixel(
                Point::new((x0 as usize + x) as i32, (y0 as usize + y) as i32),
                Some(p),
            );
        }
    }
}

/// The drawing over the frame, tile by tile and over the whole frame, in tiles
/// of pixel `P`, on built-in scene `b`: equal pixel for pixel, and different from
/// the plain render (the drawing is there).
fn tile_by_tile_is_the_whole_frame<P>(b: Builtin)
where
    P: DrawPixel + PartialEq + Debug,
    P::Color: From<Rgb888> + Debug + embedded_graphics::mock_display::ColorMapping,
{
    b.with_scene(|view, cam| {
        let r = renderer(b, cam);
        let (across, down) = r.tile_grid(N);
        let (mut plain, mut tiled, mut whole) = (frame::<P>(), frame::<P>(), frame::<P>());
        let mut tile = Tile::<N, P>::blank();
        for ty in 0..down {
            for tx in 0..across {
                r.render_tile(view, TileCoord::new(tx, ty), &mut tile, &mut ())
                    .unwrap();
                put(&mut plain, &tile);
                put(&mut whole, &tile);
                overlay(&mut tile);
                put(&mut tiled, &tile);
            }
        }
        let area = Rectangle::new(Point::zero(), Size::new(W, H));
        overlay(&mut whole.clipped(&area));
        tiled.assert_eq(&whole);
        let changed = area
            .points()
            .filter(|&p| plain.get_pixel(p) != whole.get_pixel(p))
            .count();
        assert!(changed > 400, "{b:?}: the drawing changed {changed} pixels");
        // Nothing beyond the frame: the mock holds only the frame's pixels.
        assert_eq!(tiled.affected_area(), area);
    })
    .unwrap();
}

#[test]
fn a_drawing_over_the_tiles_is_the_drawing_over_the_frame_in_every_pixel_format() {
    let b = Builtin::Showcase;
    tile_by_tile_is_the_whole_frame::<Rgb8>(b);
    tile_by_tile_is_the_whole_frame::<Rgb888>(b);
    tile_by_tile_is_the_whole_frame::<Rgb565>(b);
    tile_by_tile_is_the_whole_frame::<Rgb555>(b);
    tile_by_tile_is_the_whole_frame::<Gray8>(b);
    tile_by_tile_is_the_whole_frame::<Rgb565Wire>(b);
    tile_by_tile_is_the_whole_frame::<Rgb565Wire>(Builtin::ChapterReflect);
}

/// Points just outside a tile's rectangle, on every side and corner, and far
/// away (the extremes of `i32`): drawing them changes nothing of the tile, so a
/// point left of the tile does not wrap onto the row above. Each point inside
/// changes exactly its own pixel.
#[test]
fn nothing_is_drawn_outside_the_tile_and_each_point_lands_on_its_pixel() {
    let b = Builtin::Showcase;
    b.with_scene(|view, cam| {
        let r = renderer(b, cam);
        let (across, down) = r.tile_grid(N);
        let mut tile = Tile::<N, Rgb565Wire>::blank();
        let white = Rgb565::WHITE;
        for (tx, ty) in [(0, 0), (1, 1), (across - 1, 0), (across - 1, down - 1)] {
            r.render_tile(view, TileCoord::new(tx, ty), &mut tile, &mut ())
                .unwrap();
            let before = tile.clone();
            let (x0, y0) = tile.origin();
            let (x0, y0) = (x0 as i32, y0 as i32);
            let (w, h) = (i32::from(tile.width()), i32::from(tile.height()));
            let mut outside = Vec::new();
            for x in x0 - 1..=x0 + w {
                outside.push(Point::new(x, y0 - 1));
                outside.push(Point::new(x, y0 + h));
            }
            for y in y0 - 1..=y0 + h {
                outside.push(Point::new(x0 - 1, y));
                outside.push(Point::new(x0 + w, y));
            }
            for (x, y) in [
                (i32::MIN, i32::MIN),
                (i32::MAX, i32::MAX),
                (i32::MIN, y0),
                (x0, i32::MAX),
            ] {
                outside.push(Point::new(x, y));
            }
            tile.draw_iter(outside.iter().map(|&p| Pixel(p, white)))
                .unwrap();
            for area in [
                Rectangle::new(Point::new(x0 - 50, y0), Size::new(50, h as u32)),
                Rectangle::new(Point::new(x0, y0 + h), Size::new(w as u32, 50)),
                Rectangle::new(Point::new(x0 + w, y0 - 5), Size::new(3, 100)),
            ] {
                tile.fill_solid(&area, white).unwrap();
                tile.fill_contiguous(&area, std::iter::repeat(white))
                    .unwrap();
            }
            // The largest rectangles embedded-graphics holds, around the tile.
            for area in [
                Rectangle::new(Point::new(i32::MIN, i32::MIN), Size::new(u32::MAX, 10)),
                Rectangle::new(Point::new(i32::MIN, y0 + h), Size::new(u32::MAX, u32::MAX)),
                Rectangle::new(Point::new(x0 + w, i32::MIN), Size::new(u32::MAX, u32::MAX)),
                Rectangle::new(
                    Point::new(i32::MAX, i32::MAX),
                    Size::new(u32::MAX, u32::MAX),
                ),
            ] {
                tile.fill_solid(&area, white).unwrap();
            }
            assert_eq!(tile, before, "tile ({tx}, {ty}): drawn outside");
            for (x, y) in [
                (0, 0),
                (w - 1, 0),
                (0, h - 1),
                (w - 1, h - 1),
                (w / 2, h / 3),
            ] {
                let mut one = before.clone();
                one.draw_iter([Pixel(Point::new(x0 + x, y0 + y), white)])
                    .unwrap();
                let (xu, yu) = (x as usize, y as usize);
                for (i, (a, b)) in one.as_slice().iter().zip(before.as_slice()).enumerate() {
                    let at = (i % w as usize, i / w as usize);
                    if at == (xu, yu) {
                        assert_eq!(*a, Rgb565Wire::from(white), "({x}, {y})");
                    } else {
                        assert_eq!(a, b, "drawing ({x}, {y}) changed {at:?}");
                    }
                }
            }
        }
        // A rectangle from the far corner over the whole tile fills all of it.
        let huge = Rectangle::new(
            Point::new(i32::MIN, i32::MIN),
            Size::new(u32::MAX, u32::MAX),
        );
        tile.fill_solid(&huge, white).unwrap();
        assert!(
            tile.as_slice()
                .iter()
                .all(|&p| p == Rgb565Wire::from(white))
        );
        // A tile never rendered covers no pixel: nothing to draw on.
        let mut empty = Tile::<N, Rgb565>::blank();
        empty
            .fill_solid(&Rectangle::new(Point::zero(), Size::new(99, 99)), white)
            .unwrap();
        assert!(empty.as_slice().is_empty());
        assert_eq!(empty.bounding_box().size, Size::zero());
    })
    .unwrap();
}

/// Copies each tile's bytes into a frame as they are handed over (no DMA: the
/// copy is done before `start` returns).
struct FrameSink {
    bytes: Vec<u8>,
}

impl TileSink for FrameSink {
    type Error = std::convert::Infallible;
    #[allow(unsafe_code)]
    unsafe fn start(&mut self, area: Rectangle, bytes: &[u8]) -> Result<(), Self::Error> {
        let w = area.size.width as usize;
        for (i, px) in bytes.chunks(2).enumerate() {
            let (x, y) = (
                area.top_left.x as usize + i % w,
                area.top_left.y as usize + i / w,
            );
            let at = 2 * (y * W as usize + x);
            self.bytes[at..at + 2].copy_from_slice(px);
        }
        Ok(())
    }
    fn finish(&mut self) -> Result<(), Self::Error> {
        Ok(())
    }
}

/// `Drawing::draw_overlaid` and `Drawing::send_overlaid` (the DMA path, wire
/// order) put the drawing where the tile-by-tile loop does.
#[test]
fn a_drawing_s_overlay_is_on_every_tile_it_sends() {
    let b = Builtin::ChapterDirect;
    b.with_scene(|view, cam| {
        let r = renderer(b, cam);
        let mut want = frame::<Rgb565>();
        let mut tile = Tile::<N, Rgb565>::blank();
        let (across, down) = r.tile_grid(N);
        for ty in 0..down {
            for tx in 0..across {
                r.render_tile(view, TileCoord::new(tx, ty), &mut tile, &mut ())
                    .unwrap();
                overlay(&mut tile);
                put(&mut want, &tile);
            }
        }
        let drawing = Drawing::<Rgb565, N>::new(&r, view);
        let mut drawn = frame::<Rgb565>();
        drawing.draw_overlaid(&mut drawn, overlay).unwrap();
        drawn.assert_eq(&want);

        let mut sink = FrameSink {
            bytes: vec![0; 2 * (W * H) as usize],
        };
        Drawing::<Rgb565Wire, N>::new(&r, view)
            .send_overlaid(&mut sink, overlay)
            .unwrap();
        let mut sent = frame::<Rgb565>();
        for (i, px) in sink.bytes.chunks(2).enumerate() {
            let p = Point::new((i % W as usize) as i32, (i / W as usize) as i32);
            sent.set_pixel(p, Some(Rgb565Wire([px[0], px[1]]).to_color()));
        }
        sent.assert_eq(&want);
    })
    .unwrap();
}

/// A drawn colour is stored as given, not dithered: a flat fill over a tile
/// rendered with Bayer dithering is the same pixel everywhere (its wire bytes
/// the colour's, high byte first), while the renderer's own pixels of one
/// colour differ by position.
#[test]
fn a_drawn_colour_is_stored_undithered() {
    let p = Rgb8::new(200, 100, 50);
    let d = tessera_core::dither::Dither::Bayer4;
    let rendered: Vec<Rgb565> = (0..4).map(|x| Rgb565::from_rgb8(p, x, 0, d)).collect();
    assert!(rendered.windows(2).any(|w| w[0] != w[1]), "{rendered:?}");

    let b = Builtin::ChapterDirect;
    b.with_scene(|view, cam| {
        let r = renderer(b, cam).with_dither(d);
        let mut tile = Tile::<N, Rgb565Wire>::blank();
        r.render_tile(view, TileCoord::new(1, 1), &mut tile, &mut ())
            .unwrap();
        let c = Rgb565::new(25, 25, 6);
        tile.fill_solid(&Rectangle::new(Point::zero(), Size::new(W, H)), c)
            .unwrap();
        let want = RawU16::from(c).into_inner().to_be_bytes();
        assert!(tile.as_slice().iter().all(|px| px.0 == want));
        let mut rgb = Tile::<N>::blank();
        r.render_tile(view, TileCoord::new(1, 1), &mut rgb, &mut ())
            .unwrap();
        rgb.fill_solid(
            &Rectangle::new(Point::zero(), Size::new(W, H)),
            Rgb888::new(200, 100, 50),
        )
        .unwrap();
        assert!(rgb.as_slice().iter().all(|&px| px == p));
    })
    .unwrap();
}
