//! Image textures from PNG and JPEG files (or glTF's images, given as bytes),
//! made into the texel tables of the core's [`Image`]: read within a file size
//! limit, their size checked from the header before anything is decoded,
//! decoded to 8-bit sRGB RGB, made smaller to fit a budget of bytes (filtered in
//! linear light) and encoded in the core's [`TexelFormat`].
//!
//! The steps, and what each refuses:
//! - the file: a regular file of at most `max_file_bytes` ([`load`]);
//! - the format, guessed from the bytes: PNG or JPEG, anything else refused;
//! - the size, read from the header before decoding: at most [`MAX_DECODED_SIDE`]
//!   texels a side (a header that declares more is refused without allocating);
//!   the decoder runs with [`image::Limits`] of that size and [`MAX_DECODE_ALLOC`]
//!   bytes;
//! - the texels: decoded to RGB with 8 bits a channel, taken as sRGB (the usual
//!   encoding of colour images, glTF's for base colour textures; an embedded ICC
//!   profile or gamma is not read); 16-bit channels are rounded to 8 bits; an
//!   alpha channel is dropped, with a warning when a texel was not opaque;
//! - the size kept: at most [`MAX_SIZE`] (4096) a side and `budget_bytes` in all
//!   (see [`fit`]), resampled in linear light when smaller than the file's;
//! - the table: RGB565 (each sRGB channel rounded to the nearest 5- or 6-bit code
//!   that the core reads back) or 8-bit sRGB as is.

use std::io::Cursor;
use std::path::Path;

use image::{DynamicImage, ImageFormat, ImageReader, Limits, Rgb32FImage, RgbImage};
use tessera_core::image::{Filter, Image, MAX_SIZE, TexelFormat, Wrap};

/// The largest width or height an image file may declare: 8192 texels. Its RGBA
/// decoding takes at most 8192 x 8192 x 4 bytes = 256 MiB (16-bit channels: twice
/// that); a larger header is refused before anything is decoded.
pub const MAX_DECODED_SIDE: u32 = 8192;

/// The most the decoder may allocate for one image, [`image::Limits::max_alloc`]:
/// 512 MiB, an 8192 x 8192 image of 16-bit RGBA.
pub const MAX_DECODE_ALLOC: u64 = 512 << 20;

/// An image texture read from a file or bytes, its texels encoded for the core.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct TextureImage {
    /// Width, texels (at most [`MAX_SIZE`]).
    pub width: u16,
    /// Height, texels (at most [`MAX_SIZE`]).
    pub height: u16,
    /// How [`TextureImage::texels`] are stored.
    pub format: TexelFormat,
    /// `width * height` texels, row by row from the top, in `format`.
    pub texels: Vec<u8>,
    /// What the image was read from: the file name as given, or the name given to
    /// [`decode`] (`glTF image 3`).
    pub source: String,
    /// The file's own size, `(width, height)`, when the texels were resampled to a
    /// smaller size (to fit the budget, or [`MAX_SIZE`] a side).
    pub resized_from: Option<(u32, u32)>,
    /// What the reader changed that the user should know: an alpha channel
    /// dropped where some texels were not opaque.
    pub warnings: Vec<String>,
}

impl TextureImage {
    /// The size of the texel table, bytes.
    #[must_use]
    pub fn bytes(&self) -> usize {
        self.texels.len()
    }

    /// The core's image of these texels, read with `filter` and `wrap` (`[along
    /// u, along v]`). The texels are leaked ([`Box::leak`]): the core's images are
    /// `'static` (flash tables on a chip), so an image loaded for a scene lives
    /// as long as the process. Load each image once per scene.
    ///
    /// # Errors
    /// The core's check of the size and table ([`Image::try_new`]): only for a
    /// `TextureImage` whose fields were changed after [`load`] or [`decode`]
    /// made it (its texels are leaked even then).
    pub fn leak(self, filter: Filter, wrap: [Wrap; 2]) -> Result<Image, tessera_core::Error> {
        let texels: &'static [u8] = Box::leak(self.texels.into_boxed_slice());
        Image::try_new(self.width, self.height, self.format, filter, wrap, texels)
    }
}

/// Reads the image file at `path` ([`decode`] of its bytes; messages name the
/// file as given): a regular file of at most `max_file_bytes`, refused by its
/// size before it is read (and at most `max_file_bytes + 1` bytes are read if
/// it grows meanwhile).
///
/// # Errors
/// The message, naming the file: missing or not a regular file, above
/// `max_file_bytes`, and [`decode`]'s.
pub fn load(
    path: &Path,
    max_file_bytes: usize,
    budget_bytes: usize,
    format: TexelFormat,
) -> Result<TextureImage, String> {
    load_tinted(path, max_file_bytes, budget_bytes, format, [1.0; 3])
}

/// [`load`], each texel's linear colour multiplied by `tint` (a glTF base colour
/// factor, an MTL file's `Kd`) before it is encoded.
///
/// # Errors
/// As [`load`].
pub fn load_tinted(
    path: &Path,
    max_file_bytes: usize,
    budget_bytes: usize,
    format: TexelFormat,
    tint: [f64; 3],
) -> Result<TextureImage, String> {
    let shown = path.display().to_string();
    let bytes = crate::file::read_bytes(path, max_file_bytes, "image file")
        .map_err(|e| format!("{shown}: {e}"))?;
    decode_tinted(&bytes, &shown, budget_bytes, format, tint)
}

/// Decodes the PNG or JPEG image `bytes` (`name`: what messages call it, e.g.
/// the file name or `glTF image 3`) into a texture of at most `budget_bytes` of
/// texels in `format` (the steps are the module doc's).
///
/// # Errors
/// The message, naming the image: not PNG or JPEG; a header that cannot be read
/// or declares more than [`MAX_DECODED_SIDE`] a side (or no texel); a decoding
/// error; a budget smaller than one texel.
pub fn decode(
    bytes: &[u8],
    name: &str,
    budget_bytes: usize,
    format: TexelFormat,
) -> Result<TextureImage, String> {
    decode_tinted(bytes, name, budget_bytes, format, [1.0; 3])
}

/// [`decode`], each texel's linear colour multiplied by `tint` (components in
/// `[0, 1]`; a tint of 1 leaves the texels as they are) before it is encoded.
///
/// # Errors
/// As [`decode`], and a tint component that is not finite or outside `[0, 1]`.
pub fn decode_tinted(
    bytes: &[u8],
    name: &str,
    budget_bytes: usize,
    format: TexelFormat,
    tint: [f64; 3],
) -> Result<TextureImage, String> {
    if !tint.iter().all(|t| (0.0..=1.0).contains(t)) {
        return Err(format!(
            "{name}: an image's tint multiplies its colours by [0, 1], got [{}, {}, {}]",
            tint[0], tint[1], tint[2]
        ));
    }
    let reader = ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| format!("{name}: cannot read the image: {e}"))?;
    let kind = match reader.format() {
        Some(f @ (ImageFormat::Png | ImageFormat::Jpeg)) => f,
        other => {
            let what = other.map_or_else(
                || "not a PNG or JPEG image".to_string(),
                |f| {
                    let ext = f.extensions_str().first().copied().unwrap_or("other");
                    format!("a {} image", ext.to_uppercase())
                },
            );
            return Err(format!(
                "{name}: {what}: image textures are read from PNG and JPEG files"
            ));
        }
    };
    let kind_name = if kind == ImageFormat::Png {
        "PNG"
    } else {
        "JPEG"
    };
    // The header alone: no limits here, so that the size refused is the one
    // the header declares (nothing of the image is allocated).
    let mut probe = ImageReader::with_format(Cursor::new(bytes), kind);
    probe.no_limits();
    let (w, h) = probe
        .into_dimensions()
        .map_err(|e| format!("{name}: cannot read the {kind_name} header: {e}"))?;
    if w == 0 || h == 0 || w > MAX_DECODED_SIDE || h > MAX_DECODED_SIDE {
        return Err(format!(
            "{name}: the image is {w} x {h} texels; image files of 1 x 1 to \
             {MAX_DECODED_SIDE} x {MAX_DECODED_SIDE} texels are read"
        ));
    }
    let bpt = format.bytes_per_texel();
    let Some((tw, th)) = fit(w, h, budget_bytes, bpt) else {
        return Err(format!(
            "{name}: the budget of {budget_bytes} bytes cannot hold one texel \
             ({bpt} bytes in {})",
            format.name()
        ));
    };
    let mut reader = ImageReader::with_format(Cursor::new(bytes), kind);
    let mut limits = Limits::default();
    limits.max_image_width = Some(MAX_DECODED_SIDE);
    limits.max_image_height = Some(MAX_DECODED_SIDE);
    limits.max_alloc = Some(MAX_DECODE_ALLOC);
    reader.limits(limits);
    let decoded = reader
        .decode()
        .map_err(|e| format!("{name}: cannot decode the {kind_name} image: {e}"))?;
    let mut warnings = Vec::new();
    let translucent = not_opaque(&decoded);
    if translucent > 0 {
        warnings.push(format!(
            "{name}: {translucent} of its {} texels are not opaque: the alpha channel \
             is dropped (image textures are opaque)",
            u64::from(w) * u64::from(h)
        ));
    }
    // 16-bit channels rounded to 8 bits, grey made RGB, alpha dropped.
    let rgb = decoded.into_rgb8();
    let (mut srgb, resized_from) = if (tw, th) == (w, h) {
        (rgb, None)
    } else {
        (resample(&rgb, tw, th), Some((w, h)))
    };
    if tint != [1.0; 3] {
        let linear = linear_table();
        for p in srgb.pixels_mut() {
            for (c, t) in p.0.iter_mut().zip(tint) {
                *c = srgb_code((f64::from(linear[usize::from(*c)]) * t) as f32);
            }
        }
    }
    Ok(TextureImage {
        width: u16::try_from(tw).map_err(|_| format!("{name}: width {tw} above 4096"))?,
        height: u16::try_from(th).map_err(|_| format!("{name}: height {th} above 4096"))?,
        format,
        texels: encode(&srgb, format),
        source: name.to_string(),
        resized_from,
        warnings,
    })
}

/// The size a `w x h` image keeps: itself if it has at most [`MAX_SIZE`] texels
/// a side and `w * h * bytes_per_texel <= budget_bytes`; else the largest size
/// that does, with the same aspect ratio as nearly as whole texels allow: the
/// longest side `L'` as large as possible, the other side `round(L' * short /
/// long)` (at least 1). `None` when the budget cannot hold one texel.
///
/// ```
/// use tessera_host::texture_image::fit;
/// assert_eq!(fit(64, 64, 1024, 2), Some((22, 22))); // 484 texels of 512
/// assert_eq!(fit(8192, 2048, usize::MAX, 3), Some((4096, 1024)));
/// assert_eq!(fit(300, 200, 1 << 20, 2), Some((300, 200)));
/// assert_eq!(fit(3, 3, 1, 2), None);
/// ```
#[must_use]
pub fn fit(w: u32, h: u32, budget_bytes: usize, bytes_per_texel: usize) -> Option<(u32, u32)> {
    let max_texels = (budget_bytes / bytes_per_texel.max(1)) as u64;
    if max_texels == 0 || w == 0 || h == 0 {
        return None;
    }
    let side = u64::from(MAX_SIZE);
    let (w, h) = (u64::from(w), u64::from(h));
    if w <= side && h <= side && w * h <= max_texels {
        return Some((w as u32, h as u32));
    }
    let (long, short) = (w.max(h), w.min(h));
    let other = |l: u64| ((l * short + long / 2) / long).max(1);
    // Down from the longest side allowed until it fits (at most 4096 steps).
    let top = long.min(side).min(max_texels);
    let l = (1..=top).rev().find(|&l| l * other(l) <= max_texels)?;
    let s = other(l);
    Some(if w >= h {
        (l as u32, s as u32)
    } else {
        (s as u32, l as u32)
    })
}

/// How many texels of `image` are not opaque (0 without an alpha channel).
fn not_opaque(image: &DynamicImage) -> u64 {
    let count = |it: &mut dyn Iterator<Item = bool>| it.filter(|&t| t).count() as u64;
    match image {
        DynamicImage::ImageLumaA8(b) => count(&mut b.pixels().map(|p| p.0[1] != u8::MAX)),
        DynamicImage::ImageRgba8(b) => count(&mut b.pixels().map(|p| p.0[3] != u8::MAX)),
        DynamicImage::ImageLumaA16(b) => count(&mut b.pixels().map(|p| p.0[1] != u16::MAX)),
        DynamicImage::ImageRgba16(b) => count(&mut b.pixels().map(|p| p.0[3] != u16::MAX)),
        DynamicImage::ImageRgba32F(b) => count(&mut b.pixels().map(|p| p.0[3] < 1.0)),
        _ => 0,
    }
}

/// The linear value of each 8-bit sRGB code (IEC 61966-2-1, in `f64`).
fn linear_table() -> [f32; 256] {
    std::array::from_fn(|c| {
        let s = c as f64 / 255.0;
        let v = if s <= 0.04045 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        };
        v as f32
    })
}

/// The nearest 8-bit sRGB code of the linear value `v` (clamped to `[0, 1]`; NaN
/// gives 0).
fn srgb_code(v: f32) -> u8 {
    let v = f64::from(v).clamp(0.0, 1.0);
    let v = if v.is_nan() { 0.0 } else { v };
    let e = if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (e * 255.0 + 0.5) as u8
}

/// `image` resampled to `tw x th` (smaller, or the same, on each side) in linear
/// light: decoded to linear `f32`, reduced by an exact area average to at most
/// twice the target's size on each side (the memory of the next step stays
/// within 4 target-sized images), then resized with a triangle filter
/// (`image::imageops::resize`, whose filter widens with the reduction: no
/// aliasing), and encoded back to 8-bit sRGB.
fn resample(image: &RgbImage, tw: u32, th: u32) -> RgbImage {
    let (w, h) = image.dimensions();
    let (mw, mh) = (w.min(2 * tw), h.min(2 * th));
    let mid = area_average(image, mw, mh);
    let out = if (mw, mh) == (tw, th) {
        mid
    } else {
        image::imageops::resize(&mid, tw, th, image::imageops::FilterType::Triangle)
    };
    RgbImage::from_fn(tw, th, |x, y| {
        let p = out.get_pixel(x, y).0;
        image::Rgb(p.map(srgb_code))
    })
}

/// The weights of an exact area average from `n` texels to `m <= n` along one
/// axis: for each source texel, the target texels it overlaps (one or two) and
/// the part of each target texel it covers (a target texel covers `n / m`
/// source texels, so each target's weights sum to 1).
fn area_weights(n: u32, m: u32) -> Vec<[(usize, f64); 2]> {
    let (n, m) = (u64::from(n), u64::from(m));
    // In units of 1 / m source texels: source x spans [x m, (x + 1) m), target j
    // spans [j n, (j + 1) n).
    (0..n)
        .map(|x| {
            let (a, b) = (x * m, (x + 1) * m);
            let j = a / n;
            let split = ((j + 1) * n).min(b);
            let first = (j as usize, (split - a) as f64 / n as f64);
            let second = ((j + 1).min(m - 1) as usize, (b - split) as f64 / n as f64);
            [first, second]
        })
        .collect()
}

/// `image` decoded to linear light and area-averaged to `mw x mh` (each at most
/// the image's side), one source row at a time.
fn area_average(image: &RgbImage, mw: u32, mh: u32) -> Rgb32FImage {
    let (w, h) = image.dimensions();
    let table = linear_table();
    let across = area_weights(w, mw);
    let down = area_weights(h, mh);
    let row_len = mw as usize * 3;
    let mut sum = vec![0.0f64; row_len * mh as usize];
    let mut row = vec![0.0f64; row_len];
    for (y, [(ya, wa), (yb, wb)]) in down.iter().enumerate() {
        row.fill(0.0);
        let src = image.as_raw();
        let start = y * w as usize * 3;
        for (x, [(xa, ua), (xb, ub)]) in across.iter().enumerate() {
            let p = &src[start + 3 * x..start + 3 * x + 3];
            for (c, &code) in p.iter().enumerate() {
                let v = f64::from(table[code as usize]);
                row[3 * xa + c] += v * ua;
                row[3 * xb + c] += v * ub;
            }
        }
        for (target, weight) in [(*ya, *wa), (*yb, *wb)] {
            if weight > 0.0 {
                let out = &mut sum[target * row_len..(target + 1) * row_len];
                for (o, r) in out.iter_mut().zip(&row) {
                    *o += r * weight;
                }
            }
        }
    }
    let data = sum.into_iter().map(|v| v as f32).collect();
    Rgb32FImage::from_raw(mw, mh, data).unwrap_or_else(|| Rgb32FImage::new(mw, mh))
}

/// The texel table of the 8-bit sRGB `image` in `format`: RGB565 rounds each
/// channel to the 5- or 6-bit code whose widening (bit replication, as the core
/// reads it) is nearest; `Srgb8` is the bytes as they are.
fn encode(image: &RgbImage, format: TexelFormat) -> Vec<u8> {
    match format {
        TexelFormat::Srgb8 => image.as_raw().clone(),
        TexelFormat::Rgb565 => {
            let five = nearest_codes(5);
            let six = nearest_codes(6);
            image
                .pixels()
                .flat_map(|p| {
                    let [r, g, b] = p.0;
                    let v = (u16::from(five[r as usize]) << 11)
                        | (u16::from(six[g as usize]) << 5)
                        | u16::from(five[b as usize]);
                    v.to_le_bytes()
                })
                .collect()
        }
    }
}

/// For each 8-bit code, the `bits`-bit code (5 or 6) whose widening to 8 bits by
/// bit replication is nearest (`round(c (2^bits - 1) / 255)`, checked against
/// its neighbours).
fn nearest_codes(bits: u32) -> [u8; 256] {
    let max = (1u32 << bits) - 1;
    let widen = |k: u32| ((k << (8 - bits)) | (k >> (2 * bits - 8))) as i32;
    std::array::from_fn(|c| {
        let guess = (c as u32 * max + 127) / 255;
        let candidates = [guess.saturating_sub(1), guess, (guess + 1).min(max)];
        candidates
            .into_iter()
            .min_by_key(|&k| (widen(k) - c as i32).abs())
            .unwrap_or(guess) as u8
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;
    use std::time::{Duration, Instant};

    /// The colours of the 4x2 test image, row by row: every channel one whose
    /// RGB565 code is known by hand.
    const COLOURS: [[u8; 3]; 8] = [
        [255, 0, 0],
        [0, 255, 0],
        [0, 0, 255],
        [255, 255, 255],
        [0, 0, 0],
        [128, 128, 128],
        [255, 255, 0],
        [8, 4, 132],
    ];

    fn png(image: &DynamicImage) -> Vec<u8> {
        let mut bytes = Vec::new();
        image
            .write_to(&mut Cursor::new(&mut bytes), ImageFormat::Png)
            .unwrap();
        bytes
    }

    fn test_png() -> Vec<u8> {
        let image = RgbImage::from_fn(4, 2, |x, y| image::Rgb(COLOURS[(y * 4 + x) as usize]));
        png(&DynamicImage::ImageRgb8(image))
    }

    /// The CRC-32 of PNG chunks (ISO 3309, as the PNG specification gives it).
    fn crc32(bytes: &[u8]) -> u32 {
        let mut crc = !0u32;
        for &b in bytes {
            crc ^= u32::from(b);
            for _ in 0..8 {
                crc = if crc & 1 != 0 {
                    (crc >> 1) ^ 0xedb8_8320
                } else {
                    crc >> 1
                };
            }
        }
        !crc
    }

    fn chunk(kind: &[u8; 4], data: &[u8]) -> Vec<u8> {
        let mut out = (data.len() as u32).to_be_bytes().to_vec();
        let mut body = kind.to_vec();
        body.extend_from_slice(data);
        out.extend_from_slice(&body);
        out.extend_from_slice(&crc32(&body).to_be_bytes());
        out
    }

    /// The mean colour of an 8-bit sRGB image in linear light.
    fn mean_linear(image: &RgbImage) -> [f64; 3] {
        let table = linear_table();
        let mut sum = [0.0f64; 3];
        for p in image.pixels() {
            for (s, &code) in sum.iter_mut().zip(&p.0) {
                *s += f64::from(table[code as usize]);
            }
        }
        let n = f64::from(image.width() * image.height());
        sum.map(|s| s / n)
    }

    /// The mean colour of a texture as the core reads it, in linear light.
    fn mean_read(t: &TextureImage) -> [f64; 3] {
        let image = t.clone().leak(Filter::Nearest, [Wrap::Repeat; 2]).unwrap();
        let mut sum = [0.0f64; 3];
        for y in 0..t.height {
            for x in 0..t.width {
                let c = image.texel(x, y);
                for (s, v) in sum.iter_mut().zip([c.r, c.g, c.b]) {
                    *s += f64::from(v);
                }
            }
        }
        let n = f64::from(t.width) * f64::from(t.height);
        sum.map(|s| s / n)
    }

    #[test]
    fn crc_of_iend() {
        // The IEND chunk's CRC every PNG ends with.
        assert_eq!(crc32(b"IEND"), 0xae42_6082);
    }

    #[test]
    fn png_loads_with_exact_texels_in_both_formats() {
        let bytes = test_png();
        let t = decode(&bytes, "test.png", 1 << 20, TexelFormat::Srgb8).unwrap();
        assert_eq!((t.width, t.height, t.resized_from), (4, 2, None));
        assert_eq!(t.texels, COLOURS.concat());
        assert!(t.warnings.is_empty());
        assert_eq!(t.source, "test.png");
        let t = decode(&bytes, "test.png", 1 << 20, TexelFormat::Rgb565).unwrap();
        // By hand: 128 -> r 16 (widened 132), g 32 (130); 8 -> 1 (8); 4 -> g 1
        // (4); 132 -> 16 (132).
        let want: [u16; 8] = [
            0xf800,
            0x07e0,
            0x001f,
            0xffff,
            0x0000,
            (16 << 11) | (32 << 5) | 16,
            0xffe0,
            (1 << 11) | (1 << 5) | 16,
        ];
        let got: Vec<u16> = t
            .texels
            .chunks(2)
            .map(|b| u16::from_le_bytes([b[0], b[1]]))
            .collect();
        assert_eq!(got, want);
        assert_eq!(t.bytes(), 16);
        // And the core reads them back: red, grey 132/130/132.
        let image = t.leak(Filter::Nearest, [Wrap::Repeat; 2]).unwrap();
        assert_eq!(image.texel(0, 0), tessera_core::Color::new(1.0, 0.0, 0.0));
        let table = linear_table();
        let grey = image.texel(1, 1);
        assert_eq!((grey.r, grey.g), (table[132], table[130]));
    }

    #[test]
    fn rgb565_codes_are_the_nearest_widened() {
        for bits in [5u32, 6] {
            let codes = nearest_codes(bits);
            let widen = |k: u32| (k << (8 - bits)) | (k >> (2 * bits - 8));
            for c in 0..=255u32 {
                let best = (0..1u32 << bits)
                    .map(|k| (widen(k) as i32 - c as i32).abs())
                    .min()
                    .unwrap();
                let got = (widen(u32::from(codes[c as usize])) as i32 - c as i32).abs();
                assert_eq!(got, best, "{bits} bits, code {c}");
            }
        }
    }

    #[test]
    fn jpeg_loads() {
        let image = RgbImage::from_fn(16, 8, |x, _| {
            if x < 8 {
                image::Rgb([200, 30, 30])
            } else {
                image::Rgb([30, 30, 200])
            }
        });
        let mut bytes = Vec::new();
        image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, 95)
            .encode_image(&image)
            .unwrap();
        let t = decode(&bytes, "photo.jpg", 1 << 20, TexelFormat::Srgb8).unwrap();
        assert_eq!((t.width, t.height), (16, 8));
        // Lossy: close to the colours, away from the edge.
        let at = |x: usize, y: usize| &t.texels[(y * 16 + x) * 3..(y * 16 + x) * 3 + 3];
        for (p, want) in [(at(2, 4), [200, 30, 30]), (at(13, 4), [30, 30, 200])] {
            for c in 0..3 {
                assert!((i32::from(p[c]) - want[c]).abs() <= 8, "{p:?} vs {want:?}");
            }
        }
    }

    #[test]
    fn a_huge_header_is_refused_quickly_with_its_size() {
        let mut bytes = b"\x89PNG\r\n\x1a\n".to_vec();
        let mut ihdr = Vec::new();
        ihdr.extend_from_slice(&100_000u32.to_be_bytes());
        ihdr.extend_from_slice(&100_000u32.to_be_bytes());
        ihdr.extend_from_slice(&[8, 2, 0, 0, 0]); // 8-bit RGB
        bytes.extend(chunk(b"IHDR", &ihdr));
        bytes.extend(chunk(b"IDAT", &[0x78, 0x9c, 0x03, 0x00]));
        bytes.extend(chunk(b"IEND", &[]));
        let start = Instant::now();
        let e = decode(&bytes, "huge.png", usize::MAX, TexelFormat::Rgb565).unwrap_err();
        assert!(start.elapsed() < Duration::from_secs(1));
        assert!(e.starts_with("huge.png: "), "{e}");
        assert!(e.contains("100000 x 100000"), "{e}");
        assert!(e.contains("8192 x 8192"), "{e}");
        // Just above the limit on one side.
        let mut bytes = b"\x89PNG\r\n\x1a\n".to_vec();
        let mut ihdr = Vec::new();
        ihdr.extend_from_slice(&8193u32.to_be_bytes());
        ihdr.extend_from_slice(&1u32.to_be_bytes());
        ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
        bytes.extend(chunk(b"IHDR", &ihdr));
        bytes.extend(chunk(b"IDAT", &[0x78, 0x9c, 0x03, 0x00]));
        let e = decode(&bytes, "wide.png", usize::MAX, TexelFormat::Rgb565).unwrap_err();
        assert!(e.contains("8193 x 1"), "{e}");
    }

    /// The relative error of each channel's linear mean after [`decode`] with
    /// `budget` bytes in `format`, and the size it kept.
    fn mean_error(image: &RgbImage, budget: usize, format: TexelFormat) -> ([f64; 3], (u16, u16)) {
        let bytes = png(&DynamicImage::ImageRgb8(image.clone()));
        let t = decode(&bytes, "big.png", budget, format).unwrap();
        assert!(t.bytes() <= budget);
        assert_eq!(t.resized_from, Some(image.dimensions()));
        let before = mean_linear(image);
        // The mean of the texels as the core reads them back.
        let after = mean_read(&t);
        let rel = std::array::from_fn(|c| (after[c] - before[c]).abs() / before[c]);
        (rel, (t.width, t.height))
    }

    /// 64x64 into 1 KiB of RGB565: at most 512 texels (22 x 22), square, the
    /// same mean colour in linear light within 1% (measured: 0.49%, 0.79%,
    /// 0.56% by channel, almost all of it the 5/6-bit rounding). The resampling
    /// alone (8-bit sRGB out) is within 0.06%, and keeps the mean of even a
    /// checker of single texels within 0.11%; in RGB565 such a flat result is
    /// off by the rounding of its one colour (1.4% to 1.7%: its mean, 0.5,
    /// falls between two 5- or 6-bit codes).
    #[test]
    fn a_large_image_is_resized_to_the_budget_keeping_its_mean() {
        // A gradient, pseudo-random noise and a smooth pattern.
        let mut seed = 12345u32;
        let varied = RgbImage::from_fn(64, 64, |x, y| {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let noise = (seed >> 24) as u8;
            let wave = 128.0 + 100.0 * (x as f64 / 5.0).sin() * (y as f64 / 7.0).cos();
            image::Rgb([(x * 4) as u8, noise, wave as u8])
        });
        // Single texels alternating black and white: the hardest to resample.
        let checker = RgbImage::from_fn(64, 64, |x, y| {
            image::Rgb([if (x + y) % 2 == 0 { 255 } else { 0 }; 3])
        });
        let worst = |rel: [f64; 3]| rel.into_iter().fold(0.0, f64::max);
        for (name, image, format, budget, bound) in [
            ("varied", &varied, TexelFormat::Rgb565, 1024, 0.01),
            ("varied", &varied, TexelFormat::Srgb8, 1536, 0.01),
            ("checker", &checker, TexelFormat::Srgb8, 1536, 0.01),
            ("checker", &checker, TexelFormat::Rgb565, 1024, 0.03),
        ] {
            let (rel, size) = mean_error(image, budget, format);
            println!(
                "{name} {}: {size:?}, mean error {:.3}% {:.3}% {:.3}%",
                format.name(),
                rel[0] * 100.0,
                rel[1] * 100.0,
                rel[2] * 100.0
            );
            assert_eq!(size, (22, 22), "{name} {format:?}");
            assert!(worst(rel) < bound, "{name} {format:?}: {rel:?}");
        }
        // A wide image keeps its aspect: 300x100 into 1200 texels -> 60x20.
        let wide = RgbImage::from_pixel(300, 100, image::Rgb([90, 160, 30]));
        let bytes = png(&DynamicImage::ImageRgb8(wide));
        let t = decode(&bytes, "wide.png", 1200 * 3, TexelFormat::Srgb8).unwrap();
        assert_eq!((t.width, t.height), (60, 20));
        // A flat colour stays that colour.
        assert!(
            t.texels.chunks(3).all(|p| p == [90, 160, 30]),
            "{:?}",
            &t.texels[..6]
        );
        // Wider than 4096: made 4096 wide whatever the budget.
        let long = RgbImage::from_pixel(5000, 3, image::Rgb([90, 160, 30]));
        let bytes = png(&DynamicImage::ImageRgb8(long));
        let t = decode(&bytes, "long.png", usize::MAX, TexelFormat::Srgb8).unwrap();
        assert_eq!(
            (t.width, t.height, t.resized_from),
            (4096, 2, Some((5000, 3)))
        );
        assert!(t.texels.chunks(3).all(|p| p == [90, 160, 30]));
    }

    #[test]
    fn fit_keeps_the_aspect_and_the_limits() {
        assert_eq!(fit(64, 64, 1024, 2), Some((22, 22)));
        assert_eq!(fit(100, 50, 100 * 50 * 2, 2), Some((100, 50)));
        assert_eq!(fit(100, 50, 100 * 50 * 2 - 1, 2), Some((99, 50)));
        assert_eq!(fit(50, 100, 1250 * 3, 3), Some((25, 50)));
        assert_eq!(fit(8192, 1, usize::MAX, 3), Some((4096, 1)));
        assert_eq!(fit(1, 8192, usize::MAX, 3), Some((1, 4096)));
        assert_eq!(fit(8192, 8192, usize::MAX, 2), Some((4096, 4096)));
        assert_eq!(fit(5000, 3, 2, 2), Some((1, 1)));
        assert_eq!(fit(5000, 3, 1, 2), None);
        for (w, h, budget) in [
            (640u32, 480u32, 10_000usize),
            (1000, 7, 333),
            (17, 4000, 99),
        ] {
            let (a, b) = fit(w, h, budget, 2).unwrap();
            assert!(u64::from(a) * u64::from(b) * 2 <= budget as u64);
            // The aspect, as nearly as whole texels allow.
            let (long, short) = (w.max(h) as f64, w.min(h) as f64);
            let (l, s) = (a.max(b) as f64, a.min(b) as f64);
            assert!(
                (s - l * short / long).abs() <= 0.5 || s == 1.0,
                "{w}x{h}: {a}x{b}"
            );
            // And the next longer side does not fit.
            let l1 = l + 1.0;
            let s1 = (l1 * short / long).round().max(1.0);
            assert!(
                l1 * s1 * 2.0 > budget as f64 || l1 > long,
                "{w}x{h}: {a}x{b}"
            );
        }
    }

    #[test]
    fn alpha_is_dropped_with_a_warning_and_16_bits_rounded() {
        let rgba = image::RgbaImage::from_fn(3, 1, |x, _| {
            image::Rgba([10, 20, 30, if x == 1 { 128 } else { 255 }])
        });
        let t = decode(
            &png(&DynamicImage::ImageRgba8(rgba)),
            "a.png",
            1 << 10,
            TexelFormat::Srgb8,
        )
        .unwrap();
        assert_eq!(t.texels, [10, 20, 30].repeat(3));
        assert_eq!(t.warnings.len(), 1);
        assert!(
            t.warnings[0].contains("a.png: 1 of its 3 texels are not opaque"),
            "{:?}",
            t.warnings
        );
        // Opaque alpha: no warning.
        let rgba = image::RgbaImage::from_pixel(2, 2, image::Rgba([1, 2, 3, 255]));
        let t = decode(
            &png(&DynamicImage::ImageRgba8(rgba)),
            "b.png",
            1 << 10,
            TexelFormat::Srgb8,
        )
        .unwrap();
        assert!(t.warnings.is_empty());
        // 16 bits: 0x8080 is 128 in 8 bits, 0xffff 255; grey made RGB.
        let deep = image::ImageBuffer::<image::Rgb<u16>, _>::from_pixel(
            2,
            1,
            image::Rgb([0x8080, 0xffff, 0]),
        );
        let t = decode(
            &png(&DynamicImage::ImageRgb16(deep)),
            "c.png",
            1 << 10,
            TexelFormat::Srgb8,
        )
        .unwrap();
        assert_eq!(t.texels, [128, 255, 0, 128, 255, 0]);
        let grey = image::GrayImage::from_pixel(1, 1, image::Luma([77]));
        let t = decode(
            &png(&DynamicImage::ImageLuma8(grey)),
            "d.png",
            1 << 10,
            TexelFormat::Srgb8,
        )
        .unwrap();
        assert_eq!(t.texels, [77, 77, 77]);
    }

    #[test]
    fn files_that_are_not_images_missing_or_too_big_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let text = dir.path().join("notes.png");
        std::fs::write(&text, "not an image at all").unwrap();
        let e = load(&text, 1 << 20, 1 << 20, TexelFormat::Rgb565).unwrap_err();
        assert!(e.starts_with(&text.display().to_string()), "{e}");
        assert!(e.contains("not a PNG or JPEG image"), "{e}");
        assert!(e.contains("PNG and JPEG"), "{e}");
        // Another image format: named.
        // A GIF's signature and logical screen: what the format is known by.
        let gif = b"GIF89a\x01\x00\x01\x00\x00\x00\x00;";
        let e = decode(gif, "anim.gif", 1 << 20, TexelFormat::Rgb565).unwrap_err();
        assert!(e.contains("anim.gif: a GIF image"), "{e}");
        // Missing.
        let missing = dir.path().join("missing.png");
        let e = load(&missing, 1 << 20, 1 << 20, TexelFormat::Rgb565).unwrap_err();
        assert!(e.starts_with(&missing.display().to_string()), "{e}");
        assert!(e.contains("cannot read the image file"), "{e}");
        // Above the byte limit: refused by its size.
        let big = dir.path().join("big.png");
        let bytes = test_png();
        std::fs::File::create(&big)
            .unwrap()
            .write_all(&bytes)
            .unwrap();
        let e = load(&big, bytes.len() - 1, 1 << 20, TexelFormat::Rgb565).unwrap_err();
        assert!(
            e.contains(&format!(
                "is {} bytes, more than the limit of {} bytes",
                bytes.len(),
                bytes.len() - 1
            )),
            "{e}"
        );
        assert!(load(&big, bytes.len(), 1 << 20, TexelFormat::Rgb565).is_ok());
        // A folder.
        let e = load(dir.path(), 1 << 20, 1 << 20, TexelFormat::Rgb565).unwrap_err();
        assert!(e.contains("not a regular file"), "{e}");
        // A truncated PNG.
        let e = decode(
            &bytes[..bytes.len() / 2],
            "cut.png",
            1 << 20,
            TexelFormat::Rgb565,
        )
        .unwrap_err();
        assert!(e.starts_with("cut.png: cannot"), "{e}");
        // A budget below one texel.
        let e = decode(&bytes, "tiny.png", 1, TexelFormat::Rgb565).unwrap_err();
        assert!(e.contains("cannot hold one texel"), "{e}");
    }
}
