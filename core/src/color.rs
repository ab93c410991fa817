//! Linear RGB colours (`f32`) and 8-bit output pixels.

use core::ops::{Add, AddAssign, Mul};

/// A linear RGB colour; 1.0 is full scale. Components may exceed 1 before output.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Color {
    /// Red.
    pub r: f32,
    /// Green.
    pub g: f32,
    /// Blue.
    pub b: f32,
}

impl Color {
    /// Black, `(0, 0, 0)`.
    pub const BLACK: Self = Self::new(0.0, 0.0, 0.0);
    /// White, `(1, 1, 1)`.
    pub const WHITE: Self = Self::new(1.0, 1.0, 1.0);

    /// A colour from its components.
    #[must_use]
    pub const fn new(r: f32, g: f32, b: f32) -> Self {
        Self { r, g, b }
    }

    /// A grey of value `v`.
    #[must_use]
    pub const fn splat(v: f32) -> Self {
        Self::new(v, v, v)
    }

    /// True when every component is exactly zero: a weight that must not be traced.
    #[inline]
    #[must_use]
    pub fn is_black(self) -> bool {
        self.r == 0.0 && self.g == 0.0 && self.b == 0.0
    }

    /// True when all components are finite.
    #[must_use]
    pub fn is_finite(self) -> bool {
        self.r.is_finite() && self.g.is_finite() && self.b.is_finite()
    }

    /// The smallest component.
    #[must_use]
    pub fn min_component(self) -> f32 {
        crate::math::min(crate::math::min(self.r, self.g), self.b)
    }

    /// The largest component.
    #[must_use]
    pub fn max_component(self) -> f32 {
        crate::math::max(crate::math::max(self.r, self.g), self.b)
    }

    /// Clamps to `[0, 1]` and rounds to the nearest 8-bit value (NaN gives 0).
    #[must_use]
    pub fn to_rgb8(self) -> Rgb8 {
        Rgb8::new(quantize(self.r), quantize(self.g), quantize(self.b))
    }
}

/// `[0, 1]` to `0..=255`, rounding to nearest; out-of-range values saturate.
#[inline]
fn quantize(v: f32) -> u8 {
    // No clamp on the float: `as i32` saturates (NaN gives 0) and the integer clamp
    // does the rest (`usat` on the Cortex-M4F); on [0, 1] this is the clamped
    // expression, so the bytes are the same. (`as u8` directly costs two float
    // compares more on the chip, `as u32` a 64-bit conversion on x86-64.)
    let i = (v * 255.0 + 0.5) as i32;
    i.clamp(0, 255) as u8
}

impl Add for Color {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self::new(self.r + o.r, self.g + o.g, self.b + o.b)
    }
}

impl AddAssign for Color {
    #[inline]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl Mul for Color {
    type Output = Self;
    #[inline]
    fn mul(self, o: Self) -> Self {
        Self::new(self.r * o.r, self.g * o.g, self.b * o.b)
    }
}

impl Mul<f32> for Color {
    type Output = Self;
    #[inline]
    fn mul(self, s: f32) -> Self {
        Self::new(self.r * s, self.g * s, self.b * s)
    }
}

/// An output pixel: 8 bits per channel, 3 bytes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Rgb8 {
    /// Red.
    pub r: u8,
    /// Green.
    pub g: u8,
    /// Blue.
    pub b: u8,
}

impl Rgb8 {
    /// A pixel from its channels.
    #[must_use]
    pub const fn new(r: u8, g: u8, b: u8) -> Self {
        Self { r, g, b }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantize_rounds_and_saturates() {
        assert_eq!(Color::new(0.0, 1.0, 0.5).to_rgb8(), Rgb8::new(0, 255, 128));
        assert_eq!(
            Color::new(-1.0, 7.0, f32::NAN).to_rgb8(),
            Rgb8::new(0, 255, 0)
        );
        assert_eq!(
            Color::splat(1.0 / 255.0 * 0.49).to_rgb8(),
            Rgb8::new(0, 0, 0)
        );
        assert_eq!(
            Color::splat(1.0 / 255.0 * 0.51).to_rgb8(),
            Rgb8::new(1, 1, 1)
        );
    }
}
