//! `Vec3`: three `f32`s, for points, directions and normals.

use crate::math;
use core::ops::{Add, AddAssign, Div, Mul, Neg, Sub};

/// A 3-vector of `f32` (point, direction or normal).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Vec3 {
    /// x component.
    pub x: f32,
    /// y component.
    pub y: f32,
    /// z component.
    pub z: f32,
}

impl Vec3 {
    /// `(0, 0, 0)`.
    pub const ZERO: Self = Self::new(0.0, 0.0, 0.0);
    /// `(1, 0, 0)`.
    pub const X: Self = Self::new(1.0, 0.0, 0.0);
    /// `(0, 1, 0)`.
    pub const Y: Self = Self::new(0.0, 1.0, 0.0);
    /// `(0, 0, 1)`.
    pub const Z: Self = Self::new(0.0, 0.0, 1.0);

    /// A vector from its components.
    #[must_use]
    pub const fn new(x: f32, y: f32, z: f32) -> Self {
        Self { x, y, z }
    }

    /// All three components equal to `v`.
    #[must_use]
    pub const fn splat(v: f32) -> Self {
        Self::new(v, v, v)
    }

    /// The vector `[x, y, z]`.
    #[must_use]
    pub const fn from_array(a: [f32; 3]) -> Self {
        Self::new(a[0], a[1], a[2])
    }

    /// The components `[x, y, z]`.
    #[must_use]
    pub const fn to_array(self) -> [f32; 3] {
        [self.x, self.y, self.z]
    }

    /// Dot product.
    #[inline]
    #[must_use]
    pub fn dot(self, o: Self) -> f32 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Cross product (right-handed).
    #[inline]
    #[must_use]
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }

    /// The cross product with each component to within about 2 ulps however
    /// nearly parallel the two vectors are: Kahan's difference of products
    /// `a b - c d = fma(a, b, -cd) + fma(-c, d, cd)` (the second term is the exact
    /// rounding error of `cd`). For building bases (a software `fma` on chips
    /// without one: once a frame, not per ray). The products must not overflow.
    #[must_use]
    pub fn cross_accurate(self, o: Self) -> Self {
        fn diff(a: f32, b: f32, c: f32, d: f32) -> f32 {
            let cd = c * d;
            libm::fmaf(a, b, -cd) + libm::fmaf(-c, d, cd)
        }
        Self::new(
            diff(self.y, o.z, self.z, o.y),
            diff(self.z, o.x, self.x, o.z),
            diff(self.x, o.y, self.y, o.x),
        )
    }

    /// Squared length.
    #[inline]
    #[must_use]
    pub fn length_squared(self) -> f32 {
        self.dot(self)
    }

    /// Length (through `math::sqrt`: `vsqrt.f32` on the Cortex-M4F).
    #[inline]
    #[must_use]
    pub fn length(self) -> f32 {
        math::sqrt(self.length_squared())
    }

    /// The unit vector along `self`, or `None` when the length is zero, not finite,
    /// or under/overflows when squared. Very small and very large vectors are
    /// rescaled by their largest component first, so any finite non-zero vector
    /// normalises.
    #[must_use]
    pub fn try_normalize(self) -> Option<Self> {
        // No separate finiteness check: a NaN or infinite component makes `m` NaN
        // or infinite, then `len` NaN (inf / inf, or NaN), which is refused below.
        let m = self.abs().max_element();
        if m == 0.0 {
            return None;
        }
        // Scaling by the largest component keeps the squared length in [1, 3].
        let s = self / m;
        let len = s.length();
        if len > 0.0 && len.is_finite() {
            Some(s / len)
        } else {
            None
        }
    }

    /// The unit vector along `self`, or `fallback` when it has none.
    #[must_use]
    pub fn normalize_or(self, fallback: Self) -> Self {
        self.try_normalize().unwrap_or(fallback)
    }

    /// Component-wise absolute value.
    #[inline]
    #[must_use]
    pub fn abs(self) -> Self {
        Self::new(math::abs(self.x), math::abs(self.y), math::abs(self.z))
    }

    /// Component-wise product.
    #[inline]
    #[must_use]
    pub fn mul_elem(self, o: Self) -> Self {
        Self::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }

    /// Component-wise minimum, by comparison (`math::min`: a compare and a
    /// select; where a component is NaN, the result's is `o`'s).
    #[inline]
    #[must_use]
    pub fn min(self, o: Self) -> Self {
        Self::new(
            math::min(self.x, o.x),
            math::min(self.y, o.y),
            math::min(self.z, o.z),
        )
    }

    /// Component-wise maximum, by comparison (`math::max`: a compare and a
    /// select; where a component is NaN, the result's is `o`'s).
    #[inline]
    #[must_use]
    pub fn max(self, o: Self) -> Self {
        Self::new(
            math::max(self.x, o.x),
            math::max(self.y, o.y),
            math::max(self.z, o.z),
        )
    }

    /// The largest component.
    #[inline]
    #[must_use]
    pub fn max_element(self) -> f32 {
        // Compare-select, not `f32::max` (a library call on the Cortex-M4F).
        math::max(math::max(self.x, self.y), self.z)
    }

    /// Index (0, 1, 2) of the component with the largest absolute value; ties go to
    /// the lower index.
    #[inline]
    #[must_use]
    pub fn max_dimension(self) -> usize {
        let a = self.abs();
        if a.x >= a.y && a.x >= a.z {
            0
        } else if a.y >= a.z {
            1
        } else {
            2
        }
    }

    /// Component `i` (0 = x, 1 = y, anything else = z): no indexing, no panic.
    #[inline]
    #[must_use]
    pub fn get(self, i: usize) -> f32 {
        match i {
            0 => self.x,
            1 => self.y,
            _ => self.z,
        }
    }

    /// The vector with component `i` replaced by `v` (0 = x, 1 = y, else z).
    #[inline]
    #[must_use]
    pub fn with(self, i: usize, v: f32) -> Self {
        match i {
            0 => Self::new(v, self.y, self.z),
            1 => Self::new(self.x, v, self.z),
            _ => Self::new(self.x, self.y, v),
        }
    }

    /// The components reordered as `(self[a], self[b], self[c])`.
    #[inline]
    #[must_use]
    pub fn permute(self, a: usize, b: usize, c: usize) -> Self {
        Self::new(self.get(a), self.get(b), self.get(c))
    }

    /// True when all components are finite.
    #[inline]
    #[must_use]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }

    /// Mirror reflection of the direction `self` about the unit normal `n`:
    /// `d - 2 (d.n) n`.
    #[inline]
    #[must_use]
    pub fn reflect(self, n: Self) -> Self {
        self - n * (2.0 * self.dot(n))
    }
}

impl Add for Vec3 {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl AddAssign for Vec3 {
    #[inline]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl Sub for Vec3 {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl Mul<f32> for Vec3 {
    type Output = Self;
    #[inline]
    fn mul(self, s: f32) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}

/// The component-wise quotient by `s`. With `fast-recip`, one reciprocal and three
/// products where the reciprocal is a normal number (each component within 1.5 ulp
/// of the quotient instead of 0.5; one `vdiv.f32` instead of three); three
/// divisions otherwise (`s` zero, infinite, NaN, or beyond `2^126` either way).
impl Div<f32> for Vec3 {
    type Output = Self;
    #[inline]
    fn div(self, s: f32) -> Self {
        #[cfg(feature = "fast-recip")]
        {
            let r = 1.0 / s;
            if math::is_positive_normal(math::abs(r)) {
                return self * r;
            }
        }
        Self::new(self.x / s, self.y / s, self.z / s)
    }
}

impl Neg for Vec3 {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cross_is_right_handed() {
        assert_eq!(Vec3::X.cross(Vec3::Y), Vec3::Z);
        assert_eq!(Vec3::Y.cross(Vec3::Z), Vec3::X);
    }

    #[test]
    fn normalize_handles_tiny_huge_and_zero() {
        let t = Vec3::new(3e-30, 4e-30, 0.0).try_normalize().unwrap();
        assert!((t.x - 0.6).abs() < 1e-7 && (t.y - 0.8).abs() < 1e-7);
        let h = Vec3::new(3e30, 0.0, -4e30).try_normalize().unwrap();
        assert!((h.x - 0.6).abs() < 1e-7 && (h.z + 0.8).abs() < 1e-7);
        assert_eq!(Vec3::ZERO.try_normalize(), None);
        assert_eq!(Vec3::new(f32::NAN, 1.0, 0.0).try_normalize(), None);
        assert_eq!(Vec3::new(f32::INFINITY, 1.0, 0.0).try_normalize(), None);
        assert_eq!(Vec3::ZERO.normalize_or(Vec3::Y), Vec3::Y);
    }

    #[test]
    fn reflect_mirrors_about_normal() {
        let d = Vec3::new(1.0, -1.0, 0.0);
        assert_eq!(d.reflect(Vec3::Y), Vec3::new(1.0, 1.0, 0.0));
    }

    #[test]
    fn max_dimension_and_permute() {
        assert_eq!(Vec3::new(1.0, -5.0, 2.0).max_dimension(), 1);
        assert_eq!(
            Vec3::new(1.0, 2.0, 3.0).permute(2, 0, 1),
            Vec3::new(3.0, 1.0, 2.0)
        );
        assert_eq!(Vec3::ZERO.with(2, 7.0), Vec3::new(0.0, 0.0, 7.0));
    }
}
