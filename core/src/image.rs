//! Image textures: texel tables (in flash on a chip) sampled at a surface's uv.
//!
//! An [`Image`] is a `'static` table of sRGB-encoded texels, [`TexelFormat::Rgb565`]
//! (2 bytes a texel) or [`TexelFormat::Srgb8`] (3 bytes), read with glTF's sampler
//! rules: a [`Filter`] (nearest or bilinear) and a [`Wrap`] mode per axis. Texels
//! are decoded to linear light through a 256-entry table (1 KiB of flash, no
//! `powf`) before they are filtered, as a GPU filters an sRGB texture.
//!
//! The uv convention is glTF's: `u = 0` is the image's left edge and `u = 1` its
//! right edge, `v = 0` its top edge and `v = 1` its bottom edge. Row 0 of the table
//! is the top row. Texel `(x, y)` of a `w x h` image covers `[x/w, (x+1)/w] x
//! [y/h, (y+1)/h]`; its centre is at `((x + 0.5)/w, (y + 0.5)/h)`.
//!
//! ```
//! use tessera_core::image::{Filter, Image, TexelFormat, Wrap};
//! // A 2x1 image, red then blue, in 8-bit sRGB.
//! static TEXELS: [u8; 6] = [255, 0, 0, 0, 0, 255];
//! let image = Image::try_new(
//!     2, 1, TexelFormat::Srgb8, Filter::Nearest, [Wrap::Repeat; 2], &TEXELS,
//! )?;
//! assert_eq!(image.sample([0.25, 0.5]).r, 1.0);
//! assert_eq!(image.sample([1.75, 0.5]).b, 1.0); // repeated
//! # Ok::<(), tessera_core::Error>(())
//! ```

use crate::color::Color;
use crate::error::{Error, Field};
use crate::math;

/// The largest width or height of an image texture, in texels: 4096.
pub const MAX_SIZE: u16 = 4096;

/// How the texels of an [`Image`] are stored, each an sRGB-encoded colour (the
/// usual encoding of colour images, glTF's for base colour textures).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TexelFormat {
    /// 2 bytes a texel: a little-endian `u16` with red in its 5 high bits, green in
    /// the 6 middle ones and blue in the 5 low ones, each channel an sRGB code
    /// (expanded to 8 bits by bit replication when read).
    Rgb565,
    /// 3 bytes a texel: red, green and blue, each an 8-bit sRGB code.
    Srgb8,
}

impl TexelFormat {
    /// The bytes a texel takes: 2 or 3.
    #[must_use]
    pub const fn bytes_per_texel(self) -> usize {
        match self {
            Self::Rgb565 => 2,
            Self::Srgb8 => 3,
        }
    }

    /// `rgb565` or `srgb8`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Rgb565 => "rgb565",
            Self::Srgb8 => "srgb8",
        }
    }
}

/// How an [`Image`] is read between texel centres (glTF's `magFilter`; there are
/// no mipmaps: a minified image is averaged by [`Image::average`] under the
/// prefiltered sampler).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Filter {
    /// The texel that contains the point (glTF's `NEAREST`).
    Nearest,
    /// The four texel centres around the point, weighted by its distance to them
    /// (glTF's `LINEAR`), in linear light: the default.
    #[default]
    Bilinear,
}

impl Filter {
    /// `nearest` or `bilinear`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Nearest => "nearest",
            Self::Bilinear => "bilinear",
        }
    }
}

/// What an [`Image`] shows outside `[0, 1]` along one axis (glTF's `wrapS`,
/// `wrapT`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Wrap {
    /// The image repeats every unit (glTF's `REPEAT`, its default): `u` and
    /// `u + 1` show the same texel.
    #[default]
    Repeat,
    /// The image repeats every two units, every other copy mirrored (glTF's
    /// `MIRRORED_REPEAT`): `u` and `-u`, `u` and `2 - u`, show the same texel.
    MirroredRepeat,
    /// The edge texels extend forever (glTF's `CLAMP_TO_EDGE`).
    ClampToEdge,
}

impl Wrap {
    /// `repeat`, `mirrored-repeat` or `clamp-to-edge`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Self::Repeat => "repeat",
            Self::MirroredRepeat => "mirrored-repeat",
            Self::ClampToEdge => "clamp-to-edge",
        }
    }
}

/// An image texture: a `width x height` table of texels, row 0 at the top (the
/// module doc gives the uv convention), and how to sample it.
///
/// The texels are `'static`: in a firmware a `static` table that `tessera bake`
/// writes (placed in flash); on the host, images loaded for a scene are leaked
/// once and live as long as the process.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Image {
    width: u16,
    height: u16,
    format: TexelFormat,
    filter: Filter,
    wrap: [Wrap; 2],
    texels: &'static [u8],
}

/// The range message for sizes.
const SIZE_RANGE: &str = "[1, 4096] texels a side";
/// The range message for the texel table.
const TEXELS_RANGE: &str =
    "a table of exactly width x height texels (2 bytes each in rgb565, 3 in srgb8)";

impl Image {
    /// An image from baked data, unchecked (a `const fn`, for the `static` tables
    /// that `tessera bake` writes, which checked them): `wrap` is `[along u,
    /// along v]`. A scene checks its images ([`Image::validate`]); sampling an
    /// unchecked image whose table is too short reads black where texels are
    /// missing, never out of bounds.
    #[must_use]
    pub const fn new(
        width: u16,
        height: u16,
        format: TexelFormat,
        filter: Filter,
        wrap: [Wrap; 2],
        texels: &'static [u8],
    ) -> Self {
        Self {
            width,
            height,
            format,
            filter,
            wrap,
            texels,
        }
    }

    /// An image, checked ([`Image::validate`]).
    ///
    /// # Errors
    /// [`Error::OutOfRange`] of [`Field::ImageSize`]: a width or height of 0 or
    /// above [`MAX_SIZE`]; of [`Field::ImageTexels`]: a table that is not exactly
    /// `width * height * format.bytes_per_texel()` bytes long.
    pub fn try_new(
        width: u16,
        height: u16,
        format: TexelFormat,
        filter: Filter,
        wrap: [Wrap; 2],
        texels: &'static [u8],
    ) -> Result<Self, Error> {
        let image = Self::new(width, height, format, filter, wrap, texels);
        image.validate()?;
        Ok(image)
    }

    /// Checks the size (each side in `[1, 4096]`) and the table's length
    /// (`width * height * format.bytes_per_texel()` bytes).
    ///
    /// # Errors
    /// As [`Image::try_new`].
    pub fn validate(&self) -> Result<(), Error> {
        for side in [self.width, self.height] {
            if !(1..=MAX_SIZE).contains(&side) {
                return Err(Error::OutOfRange {
                    field: Field::ImageSize,
                    range: SIZE_RANGE,
                });
            }
        }
        let texels = usize::from(self.width) * usize::from(self.height);
        if Some(self.texels.len()) != texels.checked_mul(self.format.bytes_per_texel()) {
            return Err(Error::OutOfRange {
                field: Field::ImageTexels,
                range: TEXELS_RANGE,
            });
        }
        Ok(())
    }

    /// The same image read with `filter`.
    #[must_use]
    pub const fn with_filter(self, filter: Filter) -> Self {
        Self { filter, ..self }
    }

    /// The same image wrapped by `wrap` (`[along u, along v]`).
    #[must_use]
    pub const fn with_wrap(self, wrap: [Wrap; 2]) -> Self {
        Self { wrap, ..self }
    }

    /// Width, texels.
    #[must_use]
    pub const fn width(&self) -> u16 {
        self.width
    }

    /// Height, texels.
    #[must_use]
    pub const fn height(&self) -> u16 {
        self.height
    }

    /// How the texels are stored.
    #[must_use]
    pub const fn format(&self) -> TexelFormat {
        self.format
    }

    /// How the image is read between texel centres.
    #[must_use]
    pub const fn filter(&self) -> Filter {
        self.filter
    }

    /// The wrap modes, `[along u, along v]`.
    #[must_use]
    pub const fn wrap(&self) -> [Wrap; 2] {
        self.wrap
    }

    /// The texel table, row by row from the top, in [`Image::format`].
    #[must_use]
    pub const fn texels(&self) -> &'static [u8] {
        self.texels
    }

    /// The size of the texel table in bytes (the flash it takes).
    #[must_use]
    pub const fn bytes(&self) -> usize {
        self.texels.len()
    }

    /// The linear colour of texel `(x, y)` (`y = 0` is the top row): its sRGB
    /// channels decoded by the table of the exact sRGB curve (IEC 61966-2-1), an
    /// RGB565 channel first widened to 8 bits by bit replication (`r << 3 | r >>
    /// 2`, `g << 2 | g >> 4`). Black outside the image (or where an unchecked
    /// table is too short).
    #[must_use]
    pub fn texel(&self, x: u16, y: u16) -> Color {
        if x >= self.width || y >= self.height {
            return Color::BLACK;
        }
        self.texel_at(usize::from(x), usize::from(y))
    }

    /// Texel `(x, y)`, known inside the image; black if the table is too short.
    #[inline]
    fn texel_at(&self, x: usize, y: usize) -> Color {
        // y * width + x < 2^32 (both sides below 2^16): no overflow on a 32-bit
        // chip; the product by the texel's bytes may overflow only for an
        // unchecked image, and then reads black.
        let Some(at) = (y * usize::from(self.width) + x).checked_mul(self.format.bytes_per_texel())
        else {
            return Color::BLACK;
        };
        match (self.format, self.texels.get(at..)) {
            (TexelFormat::Rgb565, Some(&[lo, hi, ..])) => {
                let v = u16::from_le_bytes([lo, hi]);
                let (r, g, b) = ((v >> 11) as u8, ((v >> 5) & 0x3f) as u8, (v & 0x1f) as u8);
                Color::new(
                    srgb_to_linear((r << 3) | (r >> 2)),
                    srgb_to_linear((g << 2) | (g >> 4)),
                    srgb_to_linear((b << 3) | (b >> 2)),
                )
            }
            (TexelFormat::Srgb8, Some(&[r, g, b, ..])) => {
                Color::new(srgb_to_linear(r), srgb_to_linear(g), srgb_to_linear(b))
            }
            _ => Color::BLACK,
        }
    }

    /// The colour at `uv`, in linear light: with [`Filter::Nearest`] the texel that
    /// contains the point, with [`Filter::Bilinear`] the four texel centres around
    /// it weighted by the point's position between them (each texel decoded to
    /// linear first); each coordinate wrapped by its [`Wrap`] mode (a bilinear
    /// neighbour beyond an edge is the wrapped texel: the opposite edge's
    /// (repeat), the edge texel itself (mirrored repeat, clamp to edge)).
    ///
    /// Each coordinate is first folded into one period of its wrap mode, `u -
    /// floor(u)` (repeat) or `u - 2 floor(u / 2)` (mirrored repeat), exact in
    /// `f32` for every finite `u` except a negative one above -1 (or -2), whose
    /// `u + 1` (or `u + 2`) is rounded to the nearest `f32` (so a `u` within
    /// about `2^-25` (or `2^-24`) below 0 folds to 0, a period on); clamp to edge
    /// clamps it to `[0, 1]`. The texel is then found from the folded coordinate
    /// times the image's size, rounded once: a point within an `f32` rounding of
    /// a texel edge may read the texel on the other side.
    ///
    /// Total: it never panics and never reads out of bounds. A NaN coordinate
    /// reads as 0 (the image's left or top edge) in every mode, and so does an
    /// infinite one when repeating (clamped, `+inf` is the right or bottom
    /// edge). Huge coordinates fold exactly: from `2^23` (repeat) or `2^24`
    /// (mirrored repeat) in magnitude every `f32` is an integer (an even one),
    /// so every such `u` reads the image at `u = 0`, its left edge, as the exact
    /// `u` would: the texture is the same there at every hit, its detail long
    /// lost to the `f32` spacing of the coordinate itself.
    #[must_use]
    pub fn sample(&self, uv: [f32; 2]) -> Color {
        let (w, h) = (i32::from(self.width), i32::from(self.height));
        let [tu, tv] = [(uv[0], w, self.wrap[0]), (uv[1], h, self.wrap[1])]
            .map(|(c, n, wrap)| fold(c, wrap) * n as f32);
        match self.filter {
            Filter::Nearest => {
                // The texel coordinates are >= 0: truncation is the floor.
                let x = wrap_index(tu as i32, w, self.wrap[0]);
                let y = wrap_index(tv as i32, h, self.wrap[1]);
                self.texel_at(x, y)
            }
            Filter::Bilinear => {
                // Texel centres are at integers + 0.5: the pair around `t` is
                // `floor(t - 0.5)` and the next. Shifted by one texel, `t + 0.5`
                // is >= 0.5, so truncation is the floor and the fraction exact.
                let split = |t: f32, n: i32, wrap: Wrap| {
                    let s = t + 0.5;
                    let i = s as i32;
                    let f = s - i as f32;
                    (wrap_index(i - 1, n, wrap), wrap_index(i, n, wrap), f)
                };
                let (x0, x1, fx) = split(tu, w, self.wrap[0]);
                let (y0, y1, fy) = split(tv, h, self.wrap[1]);
                let top = self.texel_at(x0, y0) * (1.0 - fx) + self.texel_at(x1, y0) * fx;
                let bottom = self.texel_at(x0, y1) * (1.0 - fx) + self.texel_at(x1, y1) * fx;
                top * (1.0 - fy) + bottom * fy
            }
        }
    }

    /// The mean of the texture over the uv box `[lo, hi]`, for the prefiltered
    /// sampler, by a bounded rule (not the exact box filter, whose cost grows
    /// with the box):
    ///
    /// - along each axis the box spans `d = (hi - lo) * size` texels; it is cut
    ///   into `n` equal cells, `n = 1` for `d <= 1` (and for a NaN or negative
    ///   `d`), 2 for `d` in `(1, 2]`, 3 for `(2, 3]` and 4 above 3 (the cap);
    /// - the result is the mean of [`Image::sample`] at the centres of the
    ///   `n_u x n_v` cells. An axis of one cell samples the box's middle,
    ///   `0.5 * (lo + hi)`; otherwise cell `i`'s centre is `lo + (i + 0.5) *
    ///   ((hi - lo) / n)`.
    ///
    /// So a box of at most one texel in each axis gives exactly `sample` at its
    /// centre, and up to 4 texels a side every cell is at most one texel wide;
    /// a larger box is under-sampled (16 point samples of more than 16 texels:
    /// it may still alias, far less than one point sample).
    ///
    /// Cost: at most 16 calls of `sample` (4 x 4), so at most 16 texel reads
    /// with [`Filter::Nearest`] and 64 with [`Filter::Bilinear`], and no loop
    /// that depends on the box beyond that.
    #[must_use]
    pub fn average(&self, lo: [f32; 2], hi: [f32; 2]) -> Color {
        let [(lu, hu), (lv, hv)] = [(lo[0], hi[0]), (lo[1], hi[1])];
        let cells = |lo: f32, hi: f32, size: u16| {
            let d = (hi - lo) * f32::from(size);
            if d > 3.0 {
                4u8
            } else if d > 2.0 {
                3
            } else if d > 1.0 {
                2
            } else {
                1
            }
        };
        let (nu, nv) = (cells(lu, hu, self.width), cells(lv, hv, self.height));
        let centre = |lo: f32, hi: f32, n: u8, i: u8| {
            if n == 1 {
                0.5 * (lo + hi)
            } else {
                lo + (f32::from(i) + 0.5) * ((hi - lo) / f32::from(n))
            }
        };
        let mut sum = Color::BLACK;
        for j in 0..nv {
            let v = centre(lv, hv, nv, j);
            for i in 0..nu {
                sum += self.sample([centre(lu, hu, nu, i), v]);
            }
        }
        if nu == 1 && nv == 1 {
            sum
        } else {
            sum * (1.0 / f32::from(nu * nv))
        }
    }
}

/// `c` folded into one period of `wrap`: `[0, 1)` (repeat), `[0, 2)` (mirrored
/// repeat) or `[0, 1]` (clamp to edge); a NaN, an infinite coordinate that
/// repeats, or a negative one that rounds up to a full period, gives 0.
#[inline]
fn fold(c: f32, wrap: Wrap) -> f32 {
    let (r, period) = match wrap {
        // max(NaN, 0) is 0.
        Wrap::ClampToEdge => return math::min(math::max(c, 0.0), 1.0),
        Wrap::Repeat => (c - math::floor(c), 1.0),
        Wrap::MirroredRepeat => (c - 2.0 * math::floor(0.5 * c), 2.0),
    };
    if r >= 0.0 && r < period { r } else { 0.0 }
}

/// The texel index of the integer texel coordinate `i` along an axis of `n`
/// texels (`n >= 1`; 0 is read as 1), by glTF's (OpenGL's) rules: `i mod n`
/// (repeat), `i mod 2n` mirrored in its second half (mirrored repeat), `i`
/// clamped to `[0, n - 1]` (clamp to edge). Always in `[0, n)`.
#[inline]
fn wrap_index(i: i32, n: i32, wrap: Wrap) -> usize {
    let n = n.max(1);
    let k = match wrap {
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::MirroredRepeat => {
            let m = i.rem_euclid(2 * n);
            if m >= n { 2 * n - 1 - m } else { m }
        }
        Wrap::ClampToEdge => i.clamp(0, n - 1),
    };
    k as usize
}

/// The linear value of the 8-bit sRGB code `c`.
#[inline]
fn srgb_to_linear(c: u8) -> f32 {
    // Never out of range: the table has 256 entries.
    SRGB_TO_LINEAR.get(usize::from(c)).copied().unwrap_or(0.0)
}

/// The linear value of each 8-bit sRGB code `c`: `s / 12.92` for `s = c / 255 <=
/// 0.04045`, else `((s + 0.055) / 1.055)^2.4` (IEC 61966-2-1), evaluated in `f64`
/// and rounded to the nearest `f32` when the table was generated (`python3`; the
/// test `srgb_table_is_the_curve` checks every entry against the formula).
#[rustfmt::skip]
static SRGB_TO_LINEAR: [f32; 256] = [
    0.0, 0.000303527, 0.000607054, 0.000910581, 0.001214108, 0.001517635, 0.001821162,
    0.0021246888, 0.002428216, 0.0027317428, 0.00303527, 0.0033465358, 0.0036765074,
    0.004024717, 0.004391442, 0.0047769533, 0.0051815165, 0.0056053917, 0.006048833,
    0.0065120906, 0.00699541, 0.007499032, 0.008023193, 0.008568126, 0.009134059, 0.009721218,
    0.010329823, 0.010960094, 0.011612245, 0.012286488, 0.0129830325, 0.013702083, 0.014443844,
    0.015208514, 0.015996294, 0.016807375, 0.017641954, 0.01850022, 0.019382361, 0.020288562,
    0.02121901, 0.022173885, 0.023153367, 0.024157632, 0.02518686, 0.026241222, 0.027320892,
    0.02842604, 0.029556835, 0.030713445, 0.031896032, 0.033104766, 0.034339808, 0.035601314,
    0.03688945, 0.038204372, 0.039546236, 0.0409152, 0.04231141, 0.04373503, 0.045186203,
    0.046665087, 0.048171826, 0.049706567, 0.051269457, 0.052860647, 0.054480277, 0.05612849,
    0.05780543, 0.059511237, 0.061246052, 0.063010015, 0.064803265, 0.06662594, 0.06847817,
    0.070360094, 0.07227185, 0.07421357, 0.07618538, 0.07818742, 0.08021982, 0.08228271,
    0.08437621, 0.08650046, 0.08865558, 0.09084171, 0.093058966, 0.09530747, 0.09758735,
    0.099898726, 0.10224173, 0.104616486, 0.107023105, 0.10946171, 0.11193243, 0.114435375,
    0.116970666, 0.11953843, 0.122138776, 0.12477182, 0.12743768, 0.13013647, 0.13286832,
    0.13563333, 0.13843161, 0.14126329, 0.14412847, 0.14702727, 0.14995979, 0.15292615,
    0.15592647, 0.15896083, 0.16202937, 0.1651322, 0.1682694, 0.17144111, 0.1746474, 0.17788842,
    0.18116425, 0.18447499, 0.18782078, 0.19120169, 0.19461784, 0.19806932, 0.20155625,
    0.20507874, 0.20863687, 0.21223076, 0.2158605, 0.2195262, 0.22322796, 0.22696587,
    0.23074006, 0.23455058, 0.23839757, 0.24228112, 0.24620132, 0.25015828, 0.2541521,
    0.25818285, 0.26225066, 0.2663556, 0.2704978, 0.2746773, 0.27889428, 0.28314874, 0.28744084,
    0.29177064, 0.29613826, 0.30054379, 0.3049873, 0.30946892, 0.31398872, 0.31854677,
    0.3231432, 0.3277781, 0.33245152, 0.33716363, 0.34191442, 0.34670407, 0.3515326, 0.35640013,
    0.3613068, 0.3662526, 0.3712377, 0.37626213, 0.38132602, 0.38642943, 0.39157248, 0.39675522,
    0.40197778, 0.4072402, 0.4125426, 0.41788507, 0.42326766, 0.4286905, 0.43415365, 0.43965718,
    0.4452012, 0.4507858, 0.45641103, 0.462077, 0.4677838, 0.47353148, 0.47932017, 0.48514995,
    0.49102086, 0.49693298, 0.5028865, 0.50888133, 0.5149177, 0.52099556, 0.5271151, 0.5332764,
    0.5394795, 0.54572445, 0.55201143, 0.5583404, 0.5647115, 0.57112485, 0.57758045, 0.58407843,
    0.59061885, 0.59720176, 0.60382736, 0.61049557, 0.6172066, 0.6239604, 0.63075715,
    0.63759685, 0.6444797, 0.65140563, 0.65837485, 0.6653873, 0.67244315, 0.6795425, 0.6866853,
    0.69387174, 0.7011019, 0.70837575, 0.7156935, 0.7230551, 0.73046076, 0.7379104, 0.7454042,
    0.7529422, 0.7605245, 0.76815116, 0.7758222, 0.7835378, 0.7912979, 0.7991027, 0.80695224,
    0.8148466, 0.82278574, 0.8307699, 0.838799, 0.8468732, 0.8549926, 0.8631572, 0.8713671,
    0.8796224, 0.8879231, 0.8962694, 0.9046612, 0.91309863, 0.92158186, 0.9301109, 0.9386857,
    0.9473065, 0.9559733, 0.9646863, 0.9734453, 0.9822506, 0.9911021, 1.0,
];

#[cfg(test)]
mod tests {
    use super::*;
    extern crate std;
    use std::boxed::Box;
    use std::vec::Vec;

    /// The sRGB curve in f64.
    fn curve(c: u8) -> f64 {
        let s = f64::from(c) / 255.0;
        if s <= 0.04045 {
            s / 12.92
        } else {
            ((s + 0.055) / 1.055).powf(2.4)
        }
    }

    /// An image of leaked texels.
    fn image(
        w: u16,
        h: u16,
        format: TexelFormat,
        filter: Filter,
        wrap: [Wrap; 2],
        texels: Vec<u8>,
    ) -> Image {
        Image::try_new(
            w,
            h,
            format,
            filter,
            wrap,
            Box::leak(texels.into_boxed_slice()),
        )
        .unwrap()
    }

    /// A 1-row image of grey levels `levels` (8-bit sRGB).
    fn row(levels: &[u8], filter: Filter, wrap: Wrap) -> Image {
        let texels = levels.iter().flat_map(|&l| [l, l, l]).collect();
        image(
            levels.len() as u16,
            1,
            TexelFormat::Srgb8,
            filter,
            [wrap, Wrap::ClampToEdge],
            texels,
        )
    }

    fn close(a: Color, b: Color, tol: f32) -> bool {
        (a.r - b.r).abs() <= tol && (a.g - b.g).abs() <= tol && (a.b - b.b).abs() <= tol
    }

    #[test]
    fn srgb_table_is_the_curve() {
        for c in 0..=255u8 {
            let want = curve(c);
            let got = srgb_to_linear(c);
            // Correctly rounded: within half an ulp of the f64 value.
            let ulp = f64::from(math::next_up(got) - got);
            assert!(
                (f64::from(got) - want).abs() <= 0.5 * ulp,
                "{c}: {got} vs {want}"
            );
            assert_eq!(got, want as f32, "{c}");
        }
        assert_eq!((srgb_to_linear(0), srgb_to_linear(255)), (0.0, 1.0));
    }

    #[test]
    fn texels_decode_exactly_in_both_formats() {
        // Pure red, mid grey 0x80, white, in srgb8.
        let srgb = image(
            3,
            1,
            TexelFormat::Srgb8,
            Filter::Nearest,
            [Wrap::Repeat; 2],
            std::vec![255, 0, 0, 0x80, 0x80, 0x80, 255, 255, 255],
        );
        assert_eq!(srgb.texel(0, 0), Color::new(1.0, 0.0, 0.0));
        let grey = srgb.texel(1, 0);
        assert_eq!(grey, Color::splat(0.215_860_5));
        assert!((f64::from(grey.r) - curve(0x80)).abs() < 1e-8);
        assert_eq!(srgb.texel(2, 0), Color::WHITE);
        assert_eq!(srgb.texel(3, 0), Color::BLACK); // outside
        // rgb565: pure red 0xf800, pure green 0x07e0, blue 0x001f, and a grey of
        // r = 16 (0x84 once widened), g = 32 (0x82), b = 16.
        let grey565: u16 = (16 << 11) | (32 << 5) | 16;
        let texels = [0xf800u16, 0x07e0, 0x001f, grey565]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        let rgb565 = image(
            2,
            2,
            TexelFormat::Rgb565,
            Filter::Nearest,
            [Wrap::Repeat; 2],
            texels,
        );
        assert_eq!(rgb565.texel(0, 0), Color::new(1.0, 0.0, 0.0));
        assert_eq!(rgb565.texel(1, 0), Color::new(0.0, 1.0, 0.0));
        assert_eq!(rgb565.texel(0, 1), Color::new(0.0, 0.0, 1.0));
        let g = rgb565.texel(1, 1);
        assert_eq!(
            (g.r, g.g, g.b),
            (curve(0x84) as f32, curve(0x82) as f32, curve(0x84) as f32)
        );
        // Row 0 is the top: v in [0, 0.5) reads it.
        assert_eq!(rgb565.sample([0.25, 0.25]), Color::new(1.0, 0.0, 0.0));
        assert_eq!(rgb565.sample([0.25, 0.75]), Color::new(0.0, 0.0, 1.0));
    }

    #[test]
    fn nearest_and_bilinear_at_known_points() {
        let levels = [0u8, 0x80, 255, 40];
        let lin = levels.map(srgb_to_linear);
        let nearest = row(&levels, Filter::Nearest, Wrap::Repeat);
        let bilinear = row(&levels, Filter::Bilinear, Wrap::Repeat);
        for (x, &l) in lin.iter().enumerate() {
            // The texel's centre, and points inside it.
            for du in [0.0, 0.1, -0.1, 0.24] {
                let u = (x as f32 + 0.5 + du) / 4.0;
                assert_eq!(nearest.sample([u, 0.5]).r, l, "{x} {du}");
            }
            // Bilinear is the texel at its centre.
            assert_eq!(bilinear.sample([(x as f32 + 0.5) / 4.0, 0.5]).r, l);
        }
        // Half-way between two centres (u = 0.25, the edge of texels 0 and 1):
        // their mean.
        let mid = bilinear.sample([0.25, 0.5]).r;
        assert!((mid - 0.5 * (lin[0] + lin[1])).abs() < 1e-7, "{mid}");
        // A quarter of the way from texel 1's centre (0.375) to texel 2's.
        let q = bilinear.sample([0.375 + 0.25 * 0.25, 0.5]).r;
        assert!((q - (0.75 * lin[1] + 0.25 * lin[2])).abs() < 1e-6, "{q}");
        // Repeat: left of texel 0's centre blends texel 3 in.
        let edge = bilinear.sample([0.0, 0.5]).r;
        assert!((edge - 0.5 * (lin[3] + lin[0])).abs() < 1e-7);
        // In 2-D: the mean of the four around the image's centre.
        let texels = [0u8, 0x80, 255, 40]
            .iter()
            .flat_map(|&l| [l, 0, 255 - l])
            .collect();
        let square = image(
            2,
            2,
            TexelFormat::Srgb8,
            Filter::Bilinear,
            [Wrap::ClampToEdge; 2],
            texels,
        );
        let c = square.sample([0.5, 0.5]);
        let want = (lin[0] + lin[1] + lin[2] + lin[3]) / 4.0;
        assert!((c.r - want).abs() < 1e-6 && c.g == 0.0, "{c:?}");
    }

    /// Each wrap mode at u = -0.25, 1.25 and 2.75 on a 5-texel row (texel edges
    /// at multiples of 0.2, centres at 0.1 + 0.2 k), by hand.
    #[test]
    fn wrap_modes_by_hand() {
        let levels = [10u8, 70, 130, 250, 190];
        let l = levels.map(srgb_to_linear);
        let us = [-0.25f32, 1.25, 2.75];
        // Nearest: repeat folds them to 0.75, 0.25, 0.75 (texels 3, 1, 3);
        // mirrored repeat to 0.25 (the mirror of -0.25), 0.75 (2 - 1.25) and
        // 0.75 (2.75 - 2, not mirrored): texels 1, 3, 3; clamp to edge gives
        // the first texel below 0 and the last above 1.
        for (wrap, texels) in [
            (Wrap::Repeat, [3, 1, 3]),
            (Wrap::MirroredRepeat, [1, 3, 3]),
            (Wrap::ClampToEdge, [0, 4, 4]),
        ] {
            let image = row(&levels, Filter::Nearest, wrap);
            for (u, x) in us.into_iter().zip(texels) {
                assert_eq!(image.sample([u, 0.5]).r, l[x], "{wrap:?} u = {u}");
            }
        }
        // Bilinear: 0.75 is 3.75 texels, a quarter of the way from texel 3's
        // centre (3.5) to texel 4's; 0.25 is 1.25 texels, three quarters of the
        // way from texel 0's (0.5) to texel 1's. Clamped, 0 and 1 are the edge
        // texels themselves.
        let at_075 = 0.75 * l[3] + 0.25 * l[4];
        let at_025 = 0.25 * l[0] + 0.75 * l[1];
        for (wrap, want) in [
            (Wrap::Repeat, [at_075, at_025, at_075]),
            (Wrap::MirroredRepeat, [at_025, at_075, at_075]),
            (Wrap::ClampToEdge, [l[0], l[4], l[4]]),
        ] {
            let image = row(&levels, Filter::Bilinear, wrap);
            for (u, want) in us.into_iter().zip(want) {
                let got = image.sample([u, 0.5]).r;
                assert!((got - want).abs() < 1e-6, "{wrap:?} {u}: {got} vs {want}");
            }
        }
        // The bilinear neighbour beyond an edge: repeat blends in the opposite
        // edge's texel, mirrored repeat and clamp the edge texel itself.
        let edge = |wrap| row(&levels, Filter::Bilinear, wrap).sample([0.0, 0.5]).r;
        assert!((edge(Wrap::Repeat) - 0.5 * (l[4] + l[0])).abs() < 1e-7);
        assert_eq!(edge(Wrap::MirroredRepeat), l[0]);
        assert_eq!(edge(Wrap::ClampToEdge), l[0]);
        let image = row(&levels, Filter::Bilinear, Wrap::MirroredRepeat);
        assert_eq!(image.sample([1.0, 0.5]).r, l[4]);
    }

    #[test]
    fn any_uv_reads_a_texel_without_panicking() {
        let levels = [10u8, 70, 130, 250, 33];
        let lin = levels.map(srgb_to_linear);
        let specials = [
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e30,
            -1e30,
            f32::MAX,
            f32::MIN,
            16_777_216.0,
            16_777_218.0,
            8_388_609.0,
            -8_388_609.0,
            -1e-45,
            1e-45,
            -1e-10,
            -0.0,
            1.0,
            2.0,
            -1.0,
        ];
        for filter in [Filter::Nearest, Filter::Bilinear] {
            for wrap in [Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge] {
                let image = row(&levels, filter, wrap);
                let square = {
                    let texels = (0..25u8).flat_map(|i| [i * 10, 255 - i, i]).collect();
                    image_sq(texels, filter, wrap)
                };
                for &u in &specials {
                    for &v in &specials {
                        let c = image.sample([u, v]);
                        assert!(c.is_finite(), "{filter:?} {wrap:?} {u} {v}");
                        assert!(c.r >= 0.0 && c.r <= 1.0);
                        let c = square.sample([u, v]);
                        assert!(c.is_finite(), "{filter:?} {wrap:?} {u} {v}");
                        assert!(square.average([u, v], [v, u]).is_finite());
                        assert!(square.average([0.0, u], [v, 1.0]).is_finite());
                    }
                    if filter == Filter::Nearest {
                        // A single value reads a texel of the image.
                        let r = image.sample([u, 0.5]).r;
                        assert!(lin.contains(&r), "{wrap:?} {u}: {r}");
                    }
                }
                // NaN reads as 0; huge coordinates fold exactly (to 0: the left
                // edge), like 0 itself.
                let at0 = image.sample([0.0, 0.5]);
                assert_eq!(image.sample([f32::NAN, 0.5]), at0);
                if wrap != Wrap::ClampToEdge {
                    for u in [f32::INFINITY, 1e30, -1e30, 16_777_216.0, -16_777_216.0] {
                        assert_eq!(image.sample([u, 0.5]), at0, "{wrap:?} {u}");
                    }
                }
            }
        }
        // An unchecked image with a short table reads black, never out of bounds.
        static SHORT: [u8; 4] = [255; 4];
        let bad = Image::new(
            4,
            4,
            TexelFormat::Srgb8,
            Filter::Bilinear,
            [Wrap::Repeat; 2],
            &SHORT,
        );
        assert!(bad.validate().is_err());
        assert_eq!(bad.sample([0.6, 0.6]), Color::BLACK);
        assert_eq!(bad.texel(0, 0), Color::WHITE);
        let empty = Image::new(
            0,
            0,
            TexelFormat::Rgb565,
            Filter::Nearest,
            [Wrap::Repeat; 2],
            &[],
        );
        assert_eq!(empty.sample([0.5, 0.5]), Color::BLACK);
        let huge = Image::new(
            u16::MAX,
            u16::MAX,
            TexelFormat::Srgb8,
            Filter::Bilinear,
            [Wrap::ClampToEdge; 2],
            &SHORT,
        );
        assert!(huge.sample([0.99, 0.99]).is_finite());
    }

    fn image_sq(texels: Vec<u8>, filter: Filter, wrap: Wrap) -> Image {
        image(5, 5, TexelFormat::Srgb8, filter, [wrap; 2], texels)
    }

    #[test]
    fn average_is_sample_within_a_texel_and_the_mean_over_the_image() {
        // A 2x2 checker, black and white, in both filters and formats.
        for format in [TexelFormat::Srgb8, TexelFormat::Rgb565] {
            for filter in [Filter::Nearest, Filter::Bilinear] {
                let texel = |white: bool| -> Vec<u8> {
                    match (format, white) {
                        (TexelFormat::Srgb8, w) => std::vec![if w { 255 } else { 0 }; 3],
                        (TexelFormat::Rgb565, w) => std::vec![if w { 0xff } else { 0 }; 2],
                    }
                };
                let texels = [true, false, false, true]
                    .into_iter()
                    .flat_map(texel)
                    .collect();
                let checker = image(2, 2, format, filter, [Wrap::Repeat; 2], texels);
                let mean = checker.average([0.0, 0.0], [1.0, 1.0]);
                assert!(
                    close(mean, Color::splat(0.5), 1e-7),
                    "{format:?} {filter:?} {mean:?}"
                );
                // Two periods: the mean too.
                let mean = checker.average([-0.5, 0.25], [1.5, 2.25]);
                assert!(close(mean, Color::splat(0.5), 1e-6), "{mean:?}");
                // Within one texel's width: sample at the centre, exactly.
                for (lo, hi) in [
                    ([0.1f32, 0.2f32], [0.5f32, 0.6f32]),
                    ([0.3, 0.3], [0.3, 0.3]),
                    ([0.7, -0.4], [1.1, 0.05]),
                ] {
                    let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
                    assert_eq!(checker.average(lo, hi), checker.sample(mid));
                }
            }
        }
        // The rule: 1.5 texels wide gives 2 cells along u, 1 along v.
        let levels = [0u8, 0x80, 255, 40];
        let image = row(&levels, Filter::Nearest, Wrap::Repeat);
        let (lo, hi) = ([0.1f32, 0.4f32], [0.475f32, 0.6f32]);
        let step = (hi[0] - lo[0]) / 2.0;
        let want = (image.sample([lo[0] + 0.5 * step, 0.5])
            + image.sample([lo[0] + 1.5 * step, 0.5]))
            * 0.5;
        assert_eq!(image.average(lo, hi), want);
        // A box over the whole row, 4 texels: one sample per texel, the mean.
        let lin = levels.map(srgb_to_linear);
        let mean = image.average([0.0, 0.0], [1.0, 1.0]).r;
        assert!((mean - lin.iter().sum::<f32>() / 4.0).abs() < 1e-7);
    }

    #[test]
    fn try_new_refuses_wrong_sizes() {
        static T12: [u8; 12] = [0; 12];
        let size = |e: Result<Image, Error>| {
            matches!(
                e,
                Err(Error::OutOfRange {
                    field: Field::ImageSize,
                    ..
                })
            )
        };
        let table = |e: Result<Image, Error>| {
            matches!(
                e,
                Err(Error::OutOfRange {
                    field: Field::ImageTexels,
                    ..
                })
            )
        };
        let w = [Wrap::Repeat; 2];
        assert!(Image::try_new(2, 2, TexelFormat::Srgb8, Filter::Nearest, w, &T12).is_ok());
        assert!(Image::try_new(2, 3, TexelFormat::Rgb565, Filter::Nearest, w, &T12).is_ok());
        assert!(table(Image::try_new(
            2,
            2,
            TexelFormat::Rgb565,
            Filter::Nearest,
            w,
            &T12
        )));
        assert!(table(Image::try_new(
            3,
            2,
            TexelFormat::Srgb8,
            Filter::Nearest,
            w,
            &T12
        )));
        assert!(table(Image::try_new(
            2,
            2,
            TexelFormat::Srgb8,
            Filter::Nearest,
            w,
            &T12[..11]
        )));
        assert!(size(Image::try_new(
            0,
            2,
            TexelFormat::Srgb8,
            Filter::Nearest,
            w,
            &[]
        )));
        assert!(size(Image::try_new(
            2,
            0,
            TexelFormat::Srgb8,
            Filter::Nearest,
            w,
            &[]
        )));
        assert!(size(Image::try_new(
            4097,
            1,
            TexelFormat::Srgb8,
            Filter::Nearest,
            w,
            &T12
        )));
        let big: &'static [u8] = Box::leak(std::vec![0u8; 4096 * 2].into_boxed_slice());
        assert!(Image::try_new(4096, 1, TexelFormat::Rgb565, Filter::Bilinear, w, big).is_ok());
        assert!(size(Image::try_new(
            1,
            4097,
            TexelFormat::Rgb565,
            Filter::Bilinear,
            w,
            big
        )));
        // The message names the field.
        let e = Image::try_new(3, 2, TexelFormat::Srgb8, Filter::Nearest, w, &T12).unwrap_err();
        assert!(
            std::format!("{e}").starts_with("image texture texels"),
            "{e}"
        );
    }
}
