//! Surface colours that vary with the texture coordinate `uv`.

use crate::color::Color;
use crate::error::{Error, Field, finite, flush};
#[cfg(feature = "image")]
use crate::image::Image;
use crate::math;

/// What colours a surface: one colour, or a procedural uv texture.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[non_exhaustive]
pub enum Texture {
    /// One colour everywhere; needs no uv (the shader never computes one).
    Solid(Color),
    /// Squares alternating between `a` and `b`, `scale` squares per uv unit.
    Checker {
        /// Colour of the squares where `floor(u s) + floor(v s)` is even.
        a: Color,
        /// Colour of the other squares.
        b: Color,
        /// Squares per uv unit, `> 0`.
        scale: f32,
    },
    /// Young's double-slit interference fringes along `u` (the chapter's example):
    /// `I(u) = cos^2(pi d u / (lambda L))`, bright fringes every
    /// `i = lambda L / d`. With `u` in metres and the chapter's values
    /// (`d` = 2 mm, `lambda` = 500 nm, `L` = 3 m) the spacing is 0.75 mm. Build it
    /// with [`Texture::young`].
    Fringes {
        /// Colour of a bright fringe (the dark fringes are black).
        color: Color,
        /// Fringe spacing `i = lambda L / d`, in uv units.
        spacing: f32,
    },
    /// An image (texels in flash on a chip), sampled at the uv by its filter and
    /// wrap modes, in linear colour (see [`crate::image`]); averaged over a
    /// pixel's footprint by the prefiltered sampler ([`Image::average`]).
    #[cfg(feature = "image")]
    Image(Image),
}

impl Texture {
    /// Young's fringes for slit distance `d`, wavelength `lambda` and screen
    /// distance `screen`, all in the units of `u` (metres for the chapter).
    ///
    /// ```
    /// use tessera_core::{Color, texture::Texture};
    /// let t = Texture::young(Color::WHITE, 2e-3, 500e-9, 3.0).unwrap();
    /// let Texture::Fringes { spacing, .. } = t else { unreachable!() };
    /// assert!((spacing - 0.75e-3).abs() < 1e-9);
    /// ```
    pub fn young(color: Color, d: f32, lambda: f32, screen: f32) -> Result<Self, Error> {
        let [d, lambda, screen] = [d, lambda, screen].map(flush);
        for v in [d, lambda, screen] {
            if finite(v, Field::FringeSpacing)? <= 0.0 {
                return Err(Error::NotPositive(Field::FringeSpacing));
            }
            if v > crate::error::MAX_EXTENT {
                return Err(Error::OutOfRange {
                    field: Field::FringeSpacing,
                    range: SPACING_RANGE,
                });
            }
        }
        let spacing = flush(lambda * screen / d);
        let t = Self::Fringes { color, spacing };
        t.validate()?;
        Ok(t)
    }

    /// True when evaluating needs a texture coordinate.
    #[must_use]
    pub fn needs_uv(&self) -> bool {
        !matches!(self, Self::Solid(_))
    }

    /// The colour at `uv`.
    #[must_use]
    #[inline(always)]
    pub fn eval(&self, uv: [f32; 2]) -> Color {
        match *self {
            Self::Solid(c) => c,
            Self::Checker { a, b, scale } => {
                let [u, v] = uv;
                let cell = parity(math::floor(u * scale)) ^ parity(math::floor(v * scale));
                if cell == 0 { a } else { b }
            }
            Self::Fringes { color, spacing } => color * fringe_intensity(uv[0] / spacing),
            #[cfg(feature = "image")]
            Self::Image(ref image) => image.sample(uv),
        }
    }

    /// Checks colours (each component in `[0, `[`crate::error::MAX_COLOR`]`]`), the
    /// checker's scale (finite, `> 0`) and the fringe spacing (within `[2^-64,
    /// `[`crate::error::MAX_EXTENT`]`]`: `u / spacing` stays finite for every point in
    /// view, whose coordinates are below `2^62`, and a scene scaled down by `2^-48`
    /// keeps its fringes; beyond view an overflowing `u / spacing` is a bright
    /// fringe, see `math::cos_turns`).
    pub fn validate(&self) -> Result<(), Error> {
        let (colors, scale, field) = match *self {
            #[cfg(feature = "image")]
            Self::Image(ref image) => return image.validate(),
            Self::Solid(c) => ([c, c], 1.0, Field::TextureScale),
            Self::Checker { a, b, scale } => ([a, b], scale, Field::TextureScale),
            Self::Fringes { color, spacing } => ([color, color], spacing, Field::FringeSpacing),
        };
        for c in colors {
            crate::error::color(c, Field::TextureColor)?;
        }
        if finite(scale, field)? <= 0.0 {
            return Err(Error::NotPositive(field));
        }
        if field == Field::FringeSpacing
            && !(MIN_SPACING..=crate::error::MAX_EXTENT).contains(&scale)
        {
            return Err(Error::OutOfRange {
                field,
                range: SPACING_RANGE,
            });
        }
        Ok(())
    }

    /// The texture with its numbers read by the rule for subnormal numbers
    /// ([`crate::error::flush`]): what a scene keeps.
    #[must_use]
    pub(crate) fn flushed(self) -> Self {
        let c = |c: Color| Color::new(flush(c.r), flush(c.g), flush(c.b));
        match self {
            Self::Solid(color) => Self::Solid(c(color)),
            Self::Checker { a, b, scale } => Self::Checker {
                a: c(a),
                b: c(b),
                scale: flush(scale),
            },
            Self::Fringes { color, spacing } => Self::Fringes {
                color: c(color),
                spacing: flush(spacing),
            },
            // Texels are bytes: nothing to flush.
            #[cfg(feature = "image")]
            Self::Image(image) => Self::Image(image),
        }
    }

    /// The exact mean of the texture over the uv box `[lo, hi]` (a box filter):
    /// what a pixel whose footprint is that box should show, in one evaluation.
    /// Fringes average `cos^2` analytically along `u`; a checker is the product of
    /// two square waves, whose box means are differences of their integrals (triangle
    /// waves). A box narrower than about 1e-4 of a period falls back to the centre.
    #[must_use]
    pub(crate) fn eval_box(&self, lo: [f32; 2], hi: [f32; 2]) -> Color {
        let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
        match *self {
            Texture::Solid(c) => c,
            Self::Checker { a, b, scale } => {
                let su = square_mean(lo[0] * scale, hi[0] * scale);
                let sv = square_mean(lo[1] * scale, hi[1] * scale);
                match (su, sv) {
                    (Some(su), Some(sv)) => {
                        let even = 0.5 * (1.0 + su * sv);
                        a * even + b * (1.0 - even)
                    }
                    _ => self.eval(mid),
                }
            }
            Self::Fringes { color, spacing } => {
                let (x0, x1) = (lo[0] / spacing, hi[0] / spacing);
                let w = x1 - x0;
                if w.is_nan() || w <= 1e-4 {
                    return self.eval(mid);
                }
                // mean of 0.5 + 0.5 cos(2 pi x) over [x0, x1].
                let m = 0.5
                    + 0.5 * (math::sin_turns(x1) - math::sin_turns(x0))
                        / (core::f32::consts::TAU * w);
                color * m.clamp(0.0, 1.0)
            }
            #[cfg(feature = "image")]
            Self::Image(ref image) => image.average(lo, hi),
        }
    }
}

/// The smallest fringe spacing, `2^-64`.
const MIN_SPACING: f32 = f32::from_bits((127 - 64) << 23);

/// The range message for fringe spacings.
const SPACING_RANGE: &str = "[2^-64, 2^60] (about 5.4e-20 to 1.15e18)";

/// The parity (0 even, 1 odd) of the cell index `n = floor(x)` as the checker
/// defines it: `n as i64`, which saturates (NaN gives 0), summed with wrapping,
/// whose parity is the exclusive or of the parities. Without 64-bit integers
/// (`as i64` is a library call on the Cortex-M4F) and without overflow: below
/// `2^24` an `f32` integer converts exactly to `i32`; from there to `2^63` every
/// `f32` is even; at and beyond `2^63` the saturated `i64::MAX` is odd and
/// `i64::MIN` even.
#[inline]
fn parity(n: f32) -> u32 {
    if math::abs(n) < 16_777_216.0 {
        (n as i32 as u32) & 1
    } else {
        u32::from(n >= 9_223_372_036_854_775_808.0)
    }
}

/// The mean over `[x0, x1]` of the square wave that is +1 on even cells
/// `[2k, 2k+1)` and -1 on odd ones; `None` for an empty or non-finite interval.
pub(crate) fn square_mean(x0: f32, x1: f32) -> Option<f32> {
    let w = x1 - x0;
    if w.is_nan() || w <= 1e-4 || !w.is_finite() {
        return None;
    }
    // The integral from 0: a triangle wave rising on even cells, falling on odd.
    let tri = |x: f32| {
        let n = math::floor(x);
        let f = x - n;
        if parity(n) == 0 { f } else { 1.0 - f }
    };
    Some(((tri(x1) - tri(x0)) / w).clamp(-1.0, 1.0))
}

/// `cos^2(pi x) = (1 + cos(2 pi x)) / 2`, `x` in fringes: 1 on bright fringes
/// (integer `x`), 0 half-way between.
#[must_use]
pub(crate) fn fringe_intensity(x: f32) -> f32 {
    0.5 + 0.5 * math::cos_turns(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::next_up;
    extern crate std;

    #[test]
    fn parity_is_that_of_the_saturating_i64() {
        let mut x = 1.0e-3f32;
        let mut values = std::vec![0.0f32, -0.0, f32::NAN, f32::INFINITY, f32::NEG_INFINITY];
        while x < 1e30 {
            for v in [x, -x, x * 1.37, -x * 2.71] {
                values.push(math::floor(v));
            }
            x *= 1.9;
        }
        for n in [
            16_777_215.0f32,
            16_777_216.0,
            16_777_218.0,
            9.223_372e18,
            9.3e18,
        ] {
            values.extend([n, -n]);
        }
        for n in values {
            assert_eq!(parity(n), ((n as i64) & 1) as u32, "{n:e}");
        }
    }

    #[test]
    fn checker_alternates_per_cell() {
        let t = Texture::Checker {
            a: Color::WHITE,
            b: Color::BLACK,
            scale: 2.0,
        };
        assert_eq!(t.eval([0.1, 0.1]), Color::WHITE);
        assert_eq!(t.eval([0.6, 0.1]), Color::BLACK);
        assert_eq!(t.eval([0.6, 0.6]), Color::WHITE);
        assert_eq!(t.eval([-0.1, 0.1]), Color::BLACK);
        assert_eq!(t.eval([f32::NAN, 1e30]), t.eval([0.0, 1e30]));
    }

    #[test]
    fn young_fringes_follow_cos_squared() {
        let t = Texture::young(Color::WHITE, 2e-3, 500e-9, 3.0).unwrap();
        let i = 0.75e-3f32;
        // Bright at 0 and every spacing, dark half-way, half intensity at a quarter.
        assert!((t.eval([0.0, 0.0]).r - 1.0).abs() < 1e-6);
        assert!((t.eval([3.0 * i, 0.0]).r - 1.0).abs() < 1e-5);
        assert!(t.eval([0.5 * i, 0.0]).r.abs() < 1e-5);
        assert!((t.eval([0.25 * i, 0.0]).r - 0.5).abs() < 1e-5);
        for k in 0..200 {
            let u = k as f64 * 0.013e-3;
            let exact = (core::f64::consts::PI * 2e-3 * u / (500e-9 * 3.0))
                .cos()
                .powi(2);
            assert!(
                (t.eval([u as f32, 0.0]).r as f64 - exact).abs() < 1e-4,
                "u = {u}"
            );
        }
    }

    #[test]
    fn box_means_match_numerical_integration() {
        let checker = Texture::Checker {
            a: Color::WHITE,
            b: Color::BLACK,
            scale: 1.0,
        };
        let fringes = Texture::Fringes {
            color: Color::WHITE,
            spacing: 0.75,
        };
        for (lo, hi) in [
            ([0.1f32, 0.2f32], [0.9f32, 0.7f32]),
            ([0.3, -1.7], [2.9, 0.4]),
            ([-3.25, 5.5], [-0.5, 5.75]),
            ([10.0, 10.0], [10.4, 13.0]),
        ] {
            for t in [checker, fringes] {
                // Midpoint rule on a fine grid, in f64.
                let n = 800;
                let mut sum = 0.0f64;
                for i in 0..n {
                    for j in 0..n {
                        let u = lo[0] as f64 + (hi[0] - lo[0]) as f64 * (i as f64 + 0.5) / n as f64;
                        let v = lo[1] as f64 + (hi[1] - lo[1]) as f64 * (j as f64 + 0.5) / n as f64;
                        sum += t.eval([u as f32, v as f32]).r as f64;
                    }
                }
                let want = sum / (n * n) as f64;
                let got = t.eval_box(lo, hi).r as f64;
                assert!(
                    (got - want).abs() < 3e-3,
                    "{t:?} {lo:?}..{hi:?}: {got} vs {want}"
                );
            }
        }
        // Whole periods average to the mean; a tiny box is the point value.
        assert!((fringes.eval_box([0.0, 0.0], [7.5, 1.0]).r - 0.5).abs() < 1e-5);
        assert!((checker.eval_box([0.0, 0.0], [4.0, 4.0]).r - 0.5).abs() < 1e-6);
        assert_eq!(checker.eval_box([0.2, 0.2], [0.2, 0.2]), Color::WHITE);
    }

    #[test]
    fn bad_textures_are_rejected() {
        assert_eq!(
            Texture::young(Color::WHITE, 0.0, 500e-9, 3.0),
            Err(Error::NotPositive(Field::FringeSpacing))
        );
        // A subnormal number is read as zero (`error::flush`).
        assert_eq!(
            Texture::young(Color::WHITE, 1e-40, 500e-9, 3.0),
            Err(Error::NotPositive(Field::FringeSpacing))
        );
        let bad = Texture::Checker {
            a: Color::new(f32::NAN, 0.0, 0.0),
            b: Color::BLACK,
            scale: 1.0,
        };
        assert_eq!(bad.validate(), Err(Error::NotFinite(Field::TextureColor)));
        let bad = Texture::Checker {
            a: Color::WHITE,
            b: Color::BLACK,
            scale: -1.0,
        };
        assert_eq!(bad.validate(), Err(Error::NotPositive(Field::TextureScale)));
    }

    /// Values whose shading would overflow into NaN pixels: colours beyond
    /// `MAX_COLOR`, a fringe spacing below `MIN_LENGTH` (1e-39, and the smallest
    /// normal f32), a Young's slit distance beyond `MAX_EXTENT`.
    #[test]
    fn values_that_could_overflow_the_shading_are_refused() {
        let out_of_range = |field| Err(Error::OutOfRange { field, range: "" });
        let same = |a: Result<(), Error>, b: Result<(), Error>| {
            core::mem::discriminant(&a) == core::mem::discriminant(&b)
                && match (a, b) {
                    (
                        Err(Error::OutOfRange { field: f, .. }),
                        Err(Error::OutOfRange { field: g, .. }),
                    ) => f == g,
                    (a, b) => a == b,
                }
        };
        let huge = Texture::Solid(Color::splat(3e38));
        assert!(same(huge.validate(), out_of_range(Field::TextureColor)));
        let just = Texture::Solid(Color::new(0.0, crate::error::MAX_COLOR, 1.0));
        assert_eq!(just.validate(), Ok(()));
        let above = Texture::Solid(Color::new(0.0, next_up(crate::error::MAX_COLOR), 1.0));
        assert!(same(above.validate(), out_of_range(Field::TextureColor)));
        for spacing in [f32::MIN_POSITIVE, 5e-20, 3e38] {
            let t = Texture::Fringes {
                color: Color::WHITE,
                spacing,
            };
            assert!(
                same(t.validate(), out_of_range(Field::FringeSpacing)),
                "{spacing}"
            );
        }
        // A subnormal spacing is read as zero (`error::flush`).
        let t = Texture::Fringes {
            color: Color::WHITE,
            spacing: 1e-39,
        };
        assert_eq!(t.validate(), Err(Error::NotPositive(Field::FringeSpacing)));
        let ok = Texture::Fringes {
            color: Color::WHITE,
            spacing: MIN_SPACING,
        };
        assert_eq!(ok.validate(), Ok(()));
        assert!(matches!(
            Texture::young(Color::WHITE, 3.4e38, 500e-9, 3.0),
            Err(Error::OutOfRange {
                field: Field::FringeSpacing,
                ..
            })
        ));
        assert!(Texture::young(Color::WHITE, 2e-3, 500e-9, 3.0).is_ok());
    }

    /// A checker at a scale where both cell indices saturate (`scale` 1e20 and
    /// 3.4e38): the parity is computed without an integer sum, so a debug
    /// build does not panic with "attempt to add with overflow".
    #[test]
    fn checker_parity_at_saturating_scales_does_not_overflow() {
        for scale in [1e20f32, 3.4e38] {
            let t = Texture::Checker {
                a: Color::WHITE,
                b: Color::BLACK,
                scale,
            };
            for uv in [[1e20, 1e20], [3e38, 3e38], [-3e38, 3e38], [0.5, 1e30]] {
                let c = t.eval(uv);
                assert!(c == Color::WHITE || c == Color::BLACK);
            }
        }
    }

    /// A fringe texture at points so far that `u / spacing` overflows stays finite
    /// (point sampling and the prefiltered box mean).
    #[test]
    fn fringes_far_away_stay_finite() {
        let t = Texture::Fringes {
            color: Color::WHITE,
            spacing: crate::error::MIN_LENGTH,
        };
        for u in [1e30f32, -3e38, f32::MAX] {
            assert!(t.eval([u, 0.0]).is_finite(), "{u}");
            assert!(t.eval_box([u, 0.0], [f32::MAX, 0.0]).is_finite(), "{u}");
            assert!(t.eval_box([-f32::MAX, 0.0], [u, 0.0]).is_finite(), "{u}");
        }
    }
}
