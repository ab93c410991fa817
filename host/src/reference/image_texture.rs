//! Image textures in `f64`: the same texels as the core's
//! [`tessera_core::image::Image`], read by the same rules (glTF's sampler:
//! nearest or bilinear, repeat, mirrored repeat or clamp to edge; row 0 at the
//! top, `v = 0` at the top edge) but written on their own from those rules: each
//! texel decoded by the sRGB formula in `f64` (not the core's table), each
//! coordinate folded by an exact `f64` remainder (not the core's `f32` floor).
//! Only the texels and the sampler's settings are the core's (its getters).

use tessera_core::image::{Filter, Image, TexelFormat, Wrap};

/// The linear value of the 8-bit sRGB code `c`: IEC 61966-2-1 in `f64`.
#[must_use]
pub fn srgb_to_linear(c: u8) -> f64 {
    let s = f64::from(c) / 255.0;
    if s <= 0.04045 {
        s / 12.92
    } else {
        ((s + 0.055) / 1.055).powf(2.4)
    }
}

/// The 8-bit sRGB codes of texel `(x, y)` (row 0 at the top): the bytes as they
/// are (`Srgb8`), or the 5-6-5 fields of the little-endian `u16` widened to 8
/// bits by repeating their high bits (`Rgb565`). Black (0) for a texel the table
/// does not hold.
fn codes(image: &Image, x: usize, y: usize) -> [u8; 3] {
    let per = image.format().bytes_per_texel();
    let at = (y * usize::from(image.width()) + x) * per;
    let Some(bytes) = image.texels().get(at..at + per) else {
        return [0; 3];
    };
    match image.format() {
        TexelFormat::Srgb8 => [bytes[0], bytes[1], bytes[2]],
        TexelFormat::Rgb565 => {
            let v = u32::from(bytes[0]) | (u32::from(bytes[1]) << 8);
            let field = |shift: u32, bits: u32| {
                let f = (v >> shift) & ((1 << bits) - 1);
                // Bit replication: the field, then its top bits again.
                ((f << (8 - bits)) | (f >> (2 * bits - 8))) as u8
            };
            [field(11, 5), field(5, 6), field(0, 5)]
        }
    }
}

/// The linear colour of texel `(x, y)`; black outside the image.
#[must_use]
pub fn texel(image: &Image, x: usize, y: usize) -> [f64; 3] {
    if x >= usize::from(image.width()) || y >= usize::from(image.height()) {
        return [0.0; 3];
    }
    codes(image, x, y).map(srgb_to_linear)
}

/// The position along one axis of `n` texels, in texels, of the coordinate `c`
/// once wrapped: `c mod 1` (repeat) or `c mod 2` (mirrored repeat) by the exact
/// remainder, or `c` clamped to `[0, 1]`, times `n`. As the core: a NaN
/// coordinate is 0, and so is an infinite one that repeats.
fn position(c: f64, n: usize, wrap: Wrap) -> f64 {
    let folded = match wrap {
        Wrap::Repeat => c.rem_euclid(1.0),
        Wrap::MirroredRepeat => c.rem_euclid(2.0),
        Wrap::ClampToEdge => c.clamp(0.0, 1.0),
    };
    if folded.is_nan() {
        0.0
    } else {
        folded * n as f64
    }
}

/// The texel of the whole-texel index `k` (any integer, along the unwrapped
/// axis) on an axis of `n` texels: OpenGL's (and glTF's) wrap of integer texel
/// coordinates.
fn wrapped(k: i64, n: usize, wrap: Wrap) -> usize {
    let n = n.max(1) as i64;
    let t = match wrap {
        Wrap::Repeat => k.rem_euclid(n),
        Wrap::MirroredRepeat => {
            // Period 2n: the second half runs backwards.
            let m = k.rem_euclid(2 * n);
            if m < n { m } else { 2 * n - 1 - m }
        }
        Wrap::ClampToEdge => k.clamp(0, n - 1),
    };
    t as usize
}

/// The texel a nearest-filtered `image` shows at `uv` (its column and row), or
/// `None` for a bilinear one (continuous: no edge between texels).
#[must_use]
pub fn nearest_texel(image: &Image, uv: [f64; 2]) -> Option<(usize, usize)> {
    if image.filter() != Filter::Nearest {
        return None;
    }
    let (w, h) = (usize::from(image.width()), usize::from(image.height()));
    let [wu, wv] = image.wrap();
    let (pu, pv) = (position(uv[0], w, wu), position(uv[1], h, wv));
    Some((
        wrapped(pu.floor() as i64, w, wu),
        wrapped(pv.floor() as i64, h, wv),
    ))
}

/// The linear colour of `image` at `uv` (glTF's convention: `u` rightwards from
/// the left edge, `v` downwards from the top), by its filter and wrap modes:
/// nearest, the texel containing the wrapped point; bilinear, the texels of
/// whole-texel indices `floor(p - 1/2)` and the next along each axis (`p` the
/// wrapped position in texels), each wrapped, weighted by the fraction of `p -
/// 1/2` (OpenGL's rule).
#[must_use]
pub fn sample(image: &Image, uv: [f64; 2]) -> [f64; 3] {
    let (w, h) = (usize::from(image.width()), usize::from(image.height()));
    let [wu, wv] = image.wrap();
    let (pu, pv) = (position(uv[0], w, wu), position(uv[1], h, wv));
    match image.filter() {
        Filter::Nearest => texel(
            image,
            wrapped(pu.floor() as i64, w, wu),
            wrapped(pv.floor() as i64, h, wv),
        ),
        Filter::Bilinear => {
            let (su, sv) = (pu - 0.5, pv - 0.5);
            let (i, j) = (su.floor(), sv.floor());
            let (a, b) = (su - i, sv - j);
            let (i, j) = (i as i64, j as i64);
            let corners = [
                (i, j, (1.0 - a) * (1.0 - b)),
                (i + 1, j, a * (1.0 - b)),
                (i, j + 1, (1.0 - a) * b),
                (i + 1, j + 1, a * b),
            ];
            let mut sum = [0.0; 3];
            for (x, y, weight) in corners {
                let c = texel(image, wrapped(x, w, wu), wrapped(y, h, wv));
                for (s, c) in sum.iter_mut().zip(c) {
                    *s += weight * c;
                }
            }
            sum
        }
    }
}

/// The mean of `image` over the uv box `[lo, hi]` by the core's bounded rule
/// (`Image::average`), in `f64`: along each axis the box spans
/// `d = (hi - lo) size` texels and is cut into `n` equal cells, 1 for `d <= 1`
/// (or NaN), 2 up to 2, 3 up to 3, 4 above (the cap); the result is the mean of
/// [`sample`] at the cells' centres (an axis of one cell at the box's middle,
/// `(lo + hi) / 2`). At most 16 samples, as the core's, so that the two agree
/// under the prefiltered sampler.
#[must_use]
pub fn average(image: &Image, lo: [f64; 2], hi: [f64; 2]) -> [f64; 3] {
    let us = cell_centres(lo[0], hi[0], image.width());
    let vs = cell_centres(lo[1], hi[1], image.height());
    let mut sum = [0.0; 3];
    for &v in &vs {
        for &u in &us {
            for (s, c) in sum.iter_mut().zip(sample(image, [u, v])) {
                *s += c;
            }
        }
    }
    let count = (us.len() * vs.len()) as f64;
    sum.map(|s| s / count)
}

/// The centres of [`average`]'s cells along an axis of `size` texels, from `lo`
/// to `hi`.
fn cell_centres(lo: f64, hi: f64, size: u16) -> Vec<f64> {
    let d = (hi - lo) * f64::from(size);
    let n: u32 = match d {
        d if d > 3.0 => 4,
        d if d > 2.0 => 3,
        d if d > 1.0 => 2,
        _ => 1,
    };
    if n == 1 {
        vec![0.5 * (lo + hi)]
    } else {
        let step = (hi - lo) / f64::from(n);
        (0..n).map(|i| lo + (f64::from(i) + 0.5) * step).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pseudo-random generator (a 64-bit LCG's high bits).
    struct Lcg(u64);

    impl Lcg {
        fn next(&mut self) -> u32 {
            self.0 = self
                .0
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (self.0 >> 32) as u32
        }
        /// A uniform `f32` in `[lo, hi)`.
        fn uniform(&mut self, lo: f32, hi: f32) -> f32 {
            lo + (hi - lo) * (self.next() >> 8) as f32 / (1u32 << 24) as f32
        }
    }

    /// A `w x h` image of random texels.
    fn random_image(w: u16, h: u16, format: TexelFormat, rng: &mut Lcg) -> Image {
        let len = usize::from(w) * usize::from(h) * format.bytes_per_texel();
        let texels: Vec<u8> = (0..len).map(|_| rng.next() as u8).collect();
        Image::try_new(
            w,
            h,
            format,
            Filter::Nearest,
            [Wrap::Repeat; 2],
            Box::leak(texels.into_boxed_slice()),
        )
        .unwrap()
    }

    fn core(c: tessera_core::Color) -> [f64; 3] {
        [c.r, c.g, c.b].map(f64::from)
    }

    fn max_diff(a: [f64; 3], b: [f64; 3]) -> f64 {
        (0..3).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max)
    }

    const WRAPS: [Wrap; 3] = [Wrap::Repeat, Wrap::MirroredRepeat, Wrap::ClampToEdge];

    /// True when nearest filtering at `uv` is within 1e-4 texel of a texel edge
    /// but not on it, where the core's `f32` coordinate may round to the other
    /// side (a point on an edge is exact in both).
    fn near_edge(image: &Image, uv: [f64; 2]) -> bool {
        let [wu, wv] = image.wrap();
        let p = [
            position(uv[0], usize::from(image.width()), wu),
            position(uv[1], usize::from(image.height()), wv),
        ];
        image.filter() == Filter::Nearest
            && p.iter().any(|p| {
                let off = (p - p.round()).abs();
                off > 0.0 && off < 1e-4
            })
    }

    #[test]
    fn texels_decode_as_the_core_does() {
        let mut rng = Lcg(7);
        for format in [TexelFormat::Srgb8, TexelFormat::Rgb565] {
            let image = random_image(9, 7, format, &mut rng);
            for y in 0..9 {
                for x in 0..11 {
                    let want = core(image.texel(x, y));
                    let got = texel(&image, usize::from(x), usize::from(y));
                    assert!(max_diff(got, want) < 1e-7, "{format:?} ({x}, {y})");
                }
            }
        }
        assert!((srgb_to_linear(0x80) - 0.215_860_5).abs() < 1e-9);
    }

    /// The reference agrees with the core's `sample` within 1e-5 on pseudo-random
    /// uvs (from -3 to 4, and one in ten 10^5 times farther), for every filter,
    /// wrap mode (on each axis) and format, on images whose sizes are mostly not
    /// powers of two; and so does `average` on random boxes of up to 6 texels a
    /// side. With the nearest filter, a point (or a cell centre) within 1e-4
    /// texel of a texel edge is skipped: there the core's `f32` rounding may
    /// pick the texel on the other side.
    #[test]
    fn agrees_with_the_core() {
        let mut rng = Lcg(2024);
        let (mut worst, mut skipped) = (0.0f64, 0);
        for format in [TexelFormat::Srgb8, TexelFormat::Rgb565] {
            for (w, h) in [(5u16, 3u16), (7, 4), (1, 6), (16, 16)] {
                let base = random_image(w, h, format, &mut rng);
                for filter in [Filter::Nearest, Filter::Bilinear] {
                    for wu in WRAPS {
                        for wv in WRAPS {
                            let image = base.with_filter(filter).with_wrap([wu, wv]);
                            for k in 0..300 {
                                let far = if k % 10 == 0 { 1e5 } else { 1.0 };
                                let uv =
                                    [rng.uniform(-3.0, 4.0) * far, rng.uniform(-3.0, 4.0) * far];
                                if near_edge(&image, uv.map(f64::from)) {
                                    skipped += 1;
                                    continue;
                                }
                                let want = core(image.sample(uv));
                                let got = sample(&image, uv.map(f64::from));
                                let d = max_diff(got, want);
                                worst = worst.max(d);
                                assert!(d < 1e-5, "{image:?} at {uv:?}: {got:?} vs {want:?}");
                            }
                            for _ in 0..50 {
                                let lo = [rng.uniform(-2.0, 2.0), rng.uniform(-2.0, 2.0)];
                                let size = [
                                    rng.uniform(0.0, 6.0) / f32::from(w),
                                    rng.uniform(0.0, 6.0) / f32::from(h),
                                ];
                                let hi = [lo[0] + size[0], lo[1] + size[1]];
                                let us = cell_centres(lo[0].into(), hi[0].into(), w);
                                let vs = cell_centres(lo[1].into(), hi[1].into(), h);
                                if us
                                    .iter()
                                    .any(|&u| vs.iter().any(|&v| near_edge(&image, [u, v])))
                                {
                                    skipped += 1;
                                    continue;
                                }
                                let want = core(image.average(lo, hi));
                                let got = average(&image, lo.map(f64::from), hi.map(f64::from));
                                let d = max_diff(got, want);
                                worst = worst.max(d);
                                assert!(d < 1e-5, "{lo:?}..{hi:?}: {got:?} vs {want:?}");
                            }
                        }
                    }
                }
            }
        }
        println!("largest difference from the core: {worst:e}; {skipped} cases skipped");
        assert!(skipped < 200, "{skipped}");
    }

    /// Coordinates that are not numbers, or infinite, read the same texel as in
    /// the core.
    #[test]
    fn special_coordinates_agree_with_the_core() {
        let mut rng = Lcg(99);
        let base = random_image(5, 3, TexelFormat::Srgb8, &mut rng);
        let specials = [
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e30,
            -1e30,
            0.0,
            1.0,
        ];
        for filter in [Filter::Nearest, Filter::Bilinear] {
            for wrap in WRAPS {
                let image = base.with_filter(filter).with_wrap([wrap; 2]);
                for u in specials {
                    for v in specials {
                        let want = core(image.sample([u, v]));
                        let got = sample(&image, [f64::from(u), f64::from(v)]);
                        assert!(max_diff(got, want) < 1e-6, "{filter:?} {wrap:?} {u} {v}");
                    }
                }
            }
        }
    }

    /// By hand: a 2-texel row, black then white (sRGB 255), bilinear, repeat:
    /// white at its centre, half at the edges between the centres.
    #[test]
    fn bilinear_by_hand() {
        static TEXELS: [u8; 6] = [0, 0, 0, 255, 255, 255];
        let image = Image::try_new(
            2,
            1,
            TexelFormat::Srgb8,
            Filter::Bilinear,
            [Wrap::Repeat; 2],
            &TEXELS,
        )
        .unwrap();
        assert_eq!(sample(&image, [0.75, 0.5]), [1.0; 3]);
        assert_eq!(sample(&image, [0.5, 0.5]), [0.5; 3]);
        assert_eq!(sample(&image, [0.0, 0.5]), [0.5; 3]);
        assert_eq!(sample(&image, [0.375, 0.5]), [0.25; 3]);
        assert_eq!(average(&image, [0.0, 0.0], [1.0, 1.0]), [0.5; 3]);
    }
}
