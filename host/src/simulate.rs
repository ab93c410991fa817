//! What a panel would show: frames drawn through the core's `DrawTarget` output onto
//! an `embedded-graphics-simulator` display of a chosen colour type (default
//! 240x240 `Rgb565`), saved as PNG, or as an animated GIF of a camera orbit.

use crate::HostError;
use embedded_graphics::mono_font::{MonoTextStyleBuilder, ascii::FONT_6X10};
use embedded_graphics::text::{Baseline, Text};
use embedded_graphics_core::draw_target::DrawTarget;
use embedded_graphics_core::pixelcolor::{Gray8, PixelColor, Rgb555, Rgb565, Rgb888, RgbColor};
use embedded_graphics_core::prelude::{Drawable, Point, Size};
use embedded_graphics_simulator::{OutputSettings, SimulatorDisplay};
use image::RgbImage;
use std::fmt;
use std::io::Write;
use std::str::FromStr;
use tessera_core::display::{DrawPixel, Drawing, TilePixel};
use tessera_core::{Camera, Renderer, SceneView, Vec3, dither::Dither};

/// The colour type of the simulated panel.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PanelColor {
    /// 16-bit 5-6-5, the usual SPI TFT (ST7789, ILI9341).
    #[default]
    Rgb565,
    /// 15-bit 5-5-5.
    Rgb555,
    /// 24-bit.
    Rgb888,
    /// 8-bit grey (luma).
    Gray8,
}

impl FromStr for PanelColor {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "rgb565" => Ok(Self::Rgb565),
            "rgb555" => Ok(Self::Rgb555),
            "rgb888" => Ok(Self::Rgb888),
            "gray8" | "grey8" => Ok(Self::Gray8),
            _ => Err(format!(
                "expected rgb565, rgb555, rgb888 or gray8, got {s:?}"
            )),
        }
    }
}

impl fmt::Display for PanelColor {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Rgb565 => "rgb565",
            Self::Rgb555 => "rgb555",
            Self::Rgb888 => "rgb888",
            Self::Gray8 => "gray8",
        })
    }
}

/// The longest label [`simulate_labelled`] draws, in characters.
pub const MAX_LABEL: usize = 64;

/// Checks a label: at most [`MAX_LABEL`] characters, each printable ASCII (the
/// font's).
///
/// # Errors
/// What is wrong, naming the first character the font lacks.
pub fn check_label(text: &str) -> Result<(), String> {
    if let Some(c) = text.chars().find(|c| !(c.is_ascii_graphic() || *c == ' ')) {
        return Err(format!(
            "the label holds {c:?}, which its font (ASCII, 6x10) cannot draw"
        ));
    }
    if text.len() > MAX_LABEL {
        return Err(format!(
            "the label is {} characters long, more than {MAX_LABEL}",
            text.len()
        ));
    }
    Ok(())
}

/// Draws `text` in white on black in the bottom-left corner of a frame `height`
/// pixels high (6x10 pixels a character, 2 from the edges) onto `target`: a
/// whole panel, or a tile (in frame coordinates, clipped to it).
pub fn draw_label<D: DrawTarget>(target: &mut D, text: &str, height: u32) -> Result<(), D::Error>
where
    D::Color: From<Rgb888>,
{
    let style = MonoTextStyleBuilder::new()
        .font(&FONT_6X10)
        .text_color(D::Color::from(<Rgb888 as RgbColor>::WHITE))
        .background_color(D::Color::from(<Rgb888 as RgbColor>::BLACK))
        .build();
    let bottom = i32::try_from(height).unwrap_or(i32::MAX).saturating_sub(2);
    Text::with_baseline(text, Point::new(2, bottom), style, Baseline::Bottom).draw(target)?;
    Ok(())
}

/// Draws `frame` onto a simulated panel of colour type `C` as the embedded-graphics
/// drawable [`tessera_core::display::Drawing`] (tiles of N x N, one `fill_contiguous`
/// each), `label` drawn over each tile before it is sent, and returns what the
/// panel shows, as 8-bit RGB.
fn panel<C, const N: usize>(
    scene: &SceneView<'_>,
    renderer: &Renderer,
    dither: Option<Dither>,
    label: Option<&str>,
) -> Result<RgbImage, HostError>
where
    C: PixelColor + From<Rgb888> + Into<Rgb888> + TilePixel + DrawPixel<Color = C>,
{
    let vp = renderer.viewport();
    let size = Size::new(u32::from(vp.width), u32::from(vp.height));
    let mut display =
        SimulatorDisplay::<C>::with_default_color(size, C::from(Rgb888::new(0, 0, 0)));
    let drawing = Drawing::<C, N>::new(renderer, scene).dithered(dither.unwrap_or(Dither::None));
    let Ok(()) = drawing.draw_overlaid(&mut display, |tile| {
        if let Some(text) = label {
            let Ok(()) = draw_label(tile, text, size.height);
        }
    });
    let out = display.to_rgb_output_image(&OutputSettings::default());
    let buf = out.as_image_buffer();
    RgbImage::from_raw(buf.width(), buf.height(), buf.as_raw().to_vec())
        .ok_or_else(|| HostError::Encode("simulator image has an unexpected size".into()))
}

/// What a panel of colour type `color` shows for `frame`, drawn in 16x16 tiles with
/// `embedded-graphics`' own conversion from `Rgb888` (the nearest level).
pub fn simulate(
    scene: &SceneView<'_>,
    renderer: &Renderer,
    color: PanelColor,
) -> Result<RgbImage, HostError> {
    simulate_tiled(scene, renderer, color, 16, None)
}

/// [`simulate`] with tiles of `tile` pixels (8, 16 or 32), each pixel converted to
/// the panel's colour with `dither` (`None`: `embedded-graphics`' own conversion;
/// see [`tessera_core::dither::Dither`]).
pub fn simulate_tiled(
    scene: &SceneView<'_>,
    renderer: &Renderer,
    color: PanelColor,
    tile: usize,
    dither: Option<Dither>,
) -> Result<RgbImage, HostError> {
    simulate_labelled(scene, renderer, color, tile, dither, None)
}

/// [`simulate_tiled`] with `label` ([`draw_label`]) drawn over each tile after
/// it is rendered and before it is sent to the panel, as a firmware draws a
/// label over the frame with no framebuffer.
///
/// # Errors
/// A label [`check_label`] refuses, or the panel image's.
pub fn simulate_labelled(
    scene: &SceneView<'_>,
    renderer: &Renderer,
    color: PanelColor,
    tile: usize,
    dither: Option<Dither>,
    label: Option<&str>,
) -> Result<RgbImage, HostError> {
    if let Some(text) = label {
        check_label(text).map_err(HostError::Limit)?;
    }
    with_tile_size!(tile, |N| match color {
        PanelColor::Rgb565 => panel::<Rgb565, N>(scene, renderer, dither, label),
        PanelColor::Rgb555 => panel::<Rgb555, N>(scene, renderer, dither, label),
        PanelColor::Rgb888 => panel::<Rgb888, N>(scene, renderer, dither, label),
        PanelColor::Gray8 => panel::<Gray8, N>(scene, renderer, dither, label),
    })
}

/// The cameras of an orbit of `frames` steps around the vertical (camera up) axis
/// through `pivot`, starting at `camera`: all of them, or the first the core
/// refuses (a position beyond [`tessera_core::error::MAX_EXTENT`]), as a
/// [`HostError::Scene`] whose item is the frame (`orbit frame 3 of 36`, numbered
/// from 0 as the frames' files are) and whose message gives the position.
pub fn orbit(camera: &Camera, pivot: Vec3, frames: u32) -> Result<Vec<Camera>, HostError> {
    let axis = camera.up();
    let arm = camera.position() - pivot;
    let frames = frames.max(1);
    (0..frames)
        .map(|k| {
            let a = std::f32::consts::TAU * k as f32 / frames as f32;
            let (s, c) = a.sin_cos();
            // Rodrigues' rotation of the arm about the axis.
            let rotated = arm * c + axis.cross(arm) * s + axis * (axis.dot(arm) * (1.0 - c));
            let position = pivot + rotated;
            Camera::try_new(
                position,
                pivot - position,
                camera.up(),
                camera.fovy_degrees(),
                camera.near(),
                camera.far(),
            )
            .map_err(|e| {
                HostError::Scene(crate::desc::DescError {
                    item: format!("orbit frame {k} of {frames} (numbered from 0)"),
                    message: format!(
                        "the camera at {} (on a circle of radius {} around {}): {e}",
                        show(position),
                        show_f32(arm.length()),
                        show(pivot)
                    ),
                })
            })
        })
        .collect()
}

/// `x` for a message: the shortest digits that read back to the same `f32`,
/// with an exponent from `1e6` up and below `1e-6` (`1.4142135e18`).
fn show_f32(x: f32) -> String {
    let a = x.abs();
    if x.is_finite() && a != 0.0 && !(1e-6..1e6).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// A point for a message: `[x, y, z]` (see [`show_f32`]).
fn show(v: Vec3) -> String {
    format!("[{}, {}, {}]", show_f32(v.x), show_f32(v.y), show_f32(v.z))
}

/// The point the camera looks at: where its central ray first hits the scene, or,
/// if it hits nothing, the point of its forward line nearest the origin (at least
/// ten near distances ahead).
///
/// # Errors
///
/// The core's error if the camera's position or forward direction is not a ray
/// (not finite): a camera built by [`Camera::try_new`] always is.
pub fn pivot(scene: &SceneView<'_>, camera: &Camera) -> Result<Vec3, HostError> {
    let ray = tessera_core::trace::Ray::new(camera.position(), camera.forward())
        .map_err(HostError::Core)?;
    let t = tessera_core::trace::first_hit(scene, &ray, camera.far())
        .unwrap_or_else(|| (-camera.position()).dot(camera.forward()))
        .max(10.0 * camera.near());
    Ok(ray.at(t))
}

/// An endlessly looping animated GIF written a frame at a time (`delay_ms` per
/// frame): the frames need not all be in memory. The bytes are those of `image`'s
/// `GifEncoder` at speed 10 (the same `gif` encoder, palette and disposal).
pub struct GifStream<W: Write> {
    enc: gif::Encoder<W>,
    size: (u16, u16),
    delay: u16,
}

/// A delay of `ms` milliseconds in the hundredths of a second a GIF counts: the
/// nearest one, but at least one for a delay that is not 0 (a GIF delay of 0 is
/// no delay: viewers show such frames at a pace of their own). Refused above
/// [`crate::limits::MAX_GIF_DELAY_MS`] (16 bits of hundredths).
pub fn gif_delay(ms: u32) -> Result<u16, HostError> {
    crate::limits::gif_delay(ms).map_err(HostError::Limit)?;
    // No overflow: `ms` is at most MAX_GIF_DELAY_MS.
    let hundredths = ((ms + 5) / 10).max(u32::from(ms > 0));
    u16::try_from(hundredths).map_err(|_| HostError::Limit(format!("a GIF delay of {ms} ms")))
}

fn gif_error(e: gif::EncodingError) -> HostError {
    match e {
        gif::EncodingError::Io(e) => HostError::Write(e),
        e => HostError::Encode(e.to_string()),
    }
}

impl<W: Write> GifStream<W> {
    /// Writes the header of a GIF of `width x height` frames, `delay_ms` apart
    /// (see [`gif_delay`]; at most [`crate::limits::MAX_GIF_DELAY_MS`]).
    pub fn new(out: W, width: u16, height: u16, delay_ms: u32) -> Result<Self, HostError> {
        let delay = gif_delay(delay_ms)?;
        let mut enc = gif::Encoder::new(out, width, height, &[]).map_err(gif_error)?;
        enc.set_repeat(gif::Repeat::Infinite).map_err(gif_error)?;
        Ok(Self {
            enc,
            size: (width, height),
            delay,
        })
    }

    /// Quantises and writes the next frame (of the size given to [`GifStream::new`]).
    pub fn add(&mut self, img: &RgbImage) -> Result<(), HostError> {
        let (w, h) = self.size;
        if img.dimensions() != (u32::from(w), u32::from(h)) {
            return Err(HostError::Encode(format!(
                "a {}x{} frame in a {w}x{h} GIF",
                img.width(),
                img.height()
            )));
        }
        let mut rgba = image::DynamicImage::ImageRgb8(img.clone()).to_rgba8();
        let mut frame = gif::Frame::from_rgba_speed(w, h, &mut rgba, 10);
        frame.delay = self.delay;
        frame.dispose = gif::DisposalMethod::Background;
        self.enc.write_frame(&frame).map_err(gif_error)
    }

    /// The output.
    pub fn writer(&mut self) -> &mut W {
        self.enc.get_mut()
    }

    /// Writes the trailer and returns the output.
    pub fn finish(self) -> Result<W, HostError> {
        self.enc.into_inner().map_err(gif_error)
    }
}

/// Encodes frames as an endlessly looping animated GIF (`delay_ms` per frame).
pub fn gif(frames: &[RgbImage], delay_ms: u32) -> Result<Vec<u8>, HostError> {
    let Some(first) = frames.first() else {
        return Err(HostError::Encode("a GIF without frames".into()));
    };
    let size = |n: u32| {
        u16::try_from(n).map_err(|_| HostError::Encode(format!("a GIF {n} pixels across")))
    };
    let mut g = GifStream::new(
        Vec::new(),
        size(first.width())?,
        size(first.height())?,
        delay_ms,
    )?;
    for f in frames {
        g.add(f)?;
    }
    g.finish()
}

#[cfg(test)]
mod tests {
    use super::*;
    use tessera_core::builtin::Builtin;
    use tessera_core::{RenderSettings, Viewport};

    #[test]
    fn rgb565_panel_shows_the_tiles_quantised_to_565() {
        let b = Builtin::ChapterReflect;
        b.with_scene(|view, cam| {
            let renderer = Renderer::try_new(cam, Viewport::new(50, 30), b.settings()).unwrap();
            let shown = simulate(view, &renderer, PanelColor::Rgb565).unwrap();
            let host = crate::render_tiles::<16>(view, &renderer, None).unwrap();
            for (a, h) in shown.pixels().zip(host.pixels()) {
                let want: Rgb888 = Rgb565::from(Rgb888::new(h[0], h[1], h[2])).into();
                use embedded_graphics_core::pixelcolor::RgbColor;
                assert_eq!(a.0, [want.r(), want.g(), want.b()]);
            }
            let exact = simulate(view, &renderer, PanelColor::Rgb888).unwrap();
            assert_eq!(exact.as_raw(), host.as_raw());
        })
        .unwrap();
    }

    /// An `RgbImage` as a whole-frame target: the drawing a label makes over
    /// the finished picture, for comparison.
    struct Picture(RgbImage);

    impl embedded_graphics_core::geometry::OriginDimensions for Picture {
        fn size(&self) -> Size {
            Size::new(self.0.width(), self.0.height())
        }
    }

    impl DrawTarget for Picture {
        type Color = Rgb888;
        type Error = core::convert::Infallible;
        fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Self::Error>
        where
            I: IntoIterator<Item = embedded_graphics_core::Pixel<Rgb888>>,
        {
            for embedded_graphics_core::Pixel(p, c) in pixels {
                let (Ok(x), Ok(y)) = (u32::try_from(p.x), u32::try_from(p.y)) else {
                    continue;
                };
                if x < self.0.width() && y < self.0.height() {
                    self.0.put_pixel(x, y, image::Rgb([c.r(), c.g(), c.b()]));
                }
            }
            Ok(())
        }
    }

    /// The label drawn over each tile (crossing tile columns and a tile row)
    /// is the label drawn over the finished frame, for every tile size.
    #[test]
    fn a_label_over_the_tiles_is_the_label_over_the_frame() {
        let b = Builtin::ChapterReflect;
        b.with_scene(|view, cam| {
            let renderer = Renderer::try_new(cam, Viewport::new(150, 40), b.settings()).unwrap();
            let text = "frame 12 of 36: ray traced";
            for tile in [8, 16, 32] {
                let plain =
                    simulate_tiled(view, &renderer, PanelColor::Rgb888, tile, None).unwrap();
                let labelled =
                    simulate_labelled(view, &renderer, PanelColor::Rgb888, tile, None, Some(text))
                        .unwrap();
                let mut want = Picture(plain.clone());
                let Ok(()) = draw_label(&mut want, text, 40);
                assert!(labelled == want.0, "tile {tile}");
                let changed = plain
                    .pixels()
                    .zip(labelled.pixels())
                    .filter(|(a, b)| a != b);
                assert!(changed.count() > 500, "tile {tile}: no label drawn");
            }
            for bad in ["caf\u{e9}", "tab\there", &"x".repeat(65)] {
                let e = simulate_labelled(view, &renderer, PanelColor::Rgb565, 16, None, Some(bad))
                    .unwrap_err()
                    .to_string();
                assert!(e.contains("label"), "{bad:?}: {e}");
            }
        })
        .unwrap();
    }

    #[test]
    fn orbit_keeps_the_distance_and_returns_home() {
        let cam =
            Camera::look_at(Vec3::new(0.0, 1.0, 5.0), Vec3::ZERO, Vec3::Y, 0.1, 50.0).unwrap();
        let cams = orbit(&cam, Vec3::ZERO, 8).unwrap();
        assert_eq!(cams.len(), 8);
        for c in &cams {
            assert!((c.position().length() - cam.position().length()).abs() < 1e-4);
        }
        assert!((cams[0].position() - cam.position()).length() < 1e-5);
        // Half way round: the other side.
        assert!((cams[4].position().z + 5.0).abs() < 1e-4);
        let frames: Vec<RgbImage> = (0..2).map(|_| RgbImage::new(4, 4)).collect();
        let g = gif(&frames, 50).unwrap();
        assert_eq!(&g[..6], b"GIF89a");
        let _ = RenderSettings::default();
    }

    /// A dithered panel is a function of the frame's pixels and their positions
    /// only: the same for tiles of 8, 16 and 32 (the pattern follows the absolute
    /// position); `none` is embedded-graphics' own conversion; dithering brings
    /// every built-in scene closer to its 8-bit image (mean FLIP).
    #[test]
    fn dithering_is_the_same_for_every_tile_size_and_closer_to_8_bits() {
        for &b in Builtin::ALL {
            b.with_scene(|view, cam| {
                let renderer = Renderer::try_new(cam, Viewport::new(72, 56), b.settings()).unwrap();
                let full = crate::render_tiles::<16>(view, &renderer, None).unwrap();
                for color in [PanelColor::Rgb565, PanelColor::Rgb555, PanelColor::Gray8] {
                    for d in Dither::ALL {
                        let at = |t| simulate_tiled(view, &renderer, color, t, Some(d)).unwrap();
                        let p16 = at(16);
                        assert!(p16 == at(8) && p16 == at(32), "{} {color} {d}", b.name());
                    }
                }
                let own = simulate_tiled(view, &renderer, PanelColor::Rgb565, 16, None).unwrap();
                let near =
                    simulate_tiled(view, &renderer, PanelColor::Rgb565, 16, Some(Dither::None));
                assert!(near.unwrap() == own, "{}", b.name());
                let flip = |d| {
                    let p = simulate_tiled(view, &renderer, PanelColor::Rgb565, 16, Some(d));
                    crate::compare::mean_flip(&full, &p.unwrap()).unwrap()
                };
                let (n, b4) = (flip(Dither::None), flip(Dither::Bayer4));
                assert!(b4 < n, "{}: bayer4 {b4} none {n}", b.name());
            })
            .unwrap();
        }
    }
}
