//! `f64` arithmetic for the few hits that `f32` cannot place: a surface much larger
//! than its distance to the ray's origin (a floor of two triangles `10^7` wide seen
//! from a few units, the ground as a sphere of radius `10^7`).
//!
//! There, the `f32` tests subtract quantities of the surface's size to get a time or
//! a point of the viewer's size, and keep an error of a few ulps of the surface's
//! size: the hit point drifts off the surface by more than the whole scene. The
//! geometry kinds detect the case cheaply (a triangle's vertex behind the ray's
//! origin, a hit time small beside the sphere's radius, a barycentric point small
//! beside its vertices) and only then recompute here, out of line: a scene without
//! such surfaces never runs this code.
//!
//! Every `f32` input is exact in `f64`, and the `f64` products of two of them are
//! exact too (48 significant bits), so the few roundings left are at `2^-53` of
//! quantities of the surface's size: `10^7` times that is still `10^-9` of the
//! viewer's size. The bounds below ([`gamma64`]) follow pbrt's standard model, as
//! [`crate::math::gamma`] does in `f32`.
//!
//! Pure IEEE `f64` operations and `math::sqrt64` (correctly rounded): the host and
//! the chip (where `f64` is software) compute the same bits.

use crate::math;
use crate::vec::Vec3;

/// How much larger than the ray's reach (the magnitude of its origin plus the hit
/// time) a surface may be before its hit point is taken on the ray, at a time
/// from `f64` (a triangle's barycentric terms, a sphere's radius): beyond, the
/// `f32` point is off by more than `2^-24 * 256 * 7`, 1e-4, of the reach. Chosen
/// well below the ratios at which the extremes battery (case 13) leaves the
/// accuracy bar with the `f32` paths, and so that a ground of a few hundred
/// units seen from a few stays in `f32`.
pub(crate) const REACH: f32 = 256.0;

/// How much the terms of Woop's time (`b_i z_i`, some of them negative: a vertex
/// behind the origin) may exceed the time before it comes from `f64`: beyond,
/// its relative error passes `2^-24 * 1024 * 4`, 2.4e-4. A ray leaving one of
/// two coplanar triangles crosses the other at a time far below that bound, and
/// gets the `f64` time whose sign tells it apart.
pub(crate) const CANCELS: f32 = 1024.0;

/// `gamma(n)` in `f64`: `n u / (1 - n u)` with `u = 2^-53`, the bound on the
/// relative error of `n` rounded operations.
pub(crate) const fn gamma64(n: u32) -> f64 {
    let nu = n as f64 * (f64::EPSILON * 0.5);
    nu / (1.0 - nu)
}

/// A non-negative `f64` bound as an `f32` that is not smaller (rounded, then one
/// ulp up: the `f32` rounding of `x` is within half an ulp). Infinite for a bound
/// beyond the `f32` range (which no offset then survives: the caller's checks
/// treat it as unbounded).
pub(crate) fn up(x: f64) -> f32 {
    math::next_up(x as f32)
}

/// A vector of three `f64`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct W3 {
    pub(crate) x: f64,
    pub(crate) y: f64,
    pub(crate) z: f64,
}

impl From<Vec3> for W3 {
    fn from(v: Vec3) -> Self {
        Self {
            x: f64::from(v.x),
            y: f64::from(v.y),
            z: f64::from(v.z),
        }
    }
}

impl W3 {
    pub(crate) const fn new(x: f64, y: f64, z: f64) -> Self {
        Self { x, y, z }
    }

    pub(crate) fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }

    pub(crate) fn dot(self, o: Self) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// The dot product of two vectors of `f32` numbers (their products exact in
    /// `f64`), the three summed with Neumaier's compensation: within a few
    /// `2^-53` of the result itself, whatever the terms cancel.
    pub(crate) fn dot_exact(self, o: Self) -> f64 {
        let (mut sum, mut carry) = (0.0f64, 0.0f64);
        for x in [self.x * o.x, self.y * o.y, self.z * o.z] {
            let t = sum + x;
            carry += if sum.abs() >= x.abs() {
                (sum - t) + x
            } else {
                (x - t) + sum
            };
            sum = t;
        }
        sum + carry
    }

    pub(crate) fn abs(self) -> Self {
        Self::new(self.x.abs(), self.y.abs(), self.z.abs())
    }

    /// The cross product.
    pub(crate) fn cross_product(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }

    /// The cross product and, per component, the sum of the magnitudes of its two
    /// products (what its rounding error is relative to).
    pub(crate) fn cross(self, o: Self) -> (Self, Self) {
        let (a, b, c, d, e, f) = (
            self.y * o.z,
            self.z * o.y,
            self.z * o.x,
            self.x * o.z,
            self.x * o.y,
            self.y * o.x,
        );
        (
            Self::new(a - b, c - d, e - f),
            Self::new(a.abs() + b.abs(), c.abs() + d.abs(), e.abs() + f.abs()),
        )
    }

    pub(crate) fn div(self, s: f64) -> Self {
        Self::new(self.x / s, self.y / s, self.z / s)
    }

    /// Each component rounded to `f32`.
    pub(crate) fn round(self) -> Vec3 {
        Vec3::new(self.x as f32, self.y as f32, self.z as f32)
    }

    pub(crate) fn length(self) -> f64 {
        math::sqrt64(self.dot(self))
    }

    /// The `f32` vector of the magnitudes `|self| * s`, rounded up.
    pub(crate) fn scaled_up(self, s: f64) -> Vec3 {
        Vec3::new(
            up(self.x.abs() * s),
            up(self.y.abs() * s),
            up(self.z.abs() * s),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn up_never_rounds_down() {
        for x in [0.0, 1.0, 0.1, 1e-30, 3.3e-300, 1e30, 123_456_789.123] {
            let u = up(x);
            assert!(f64::from(u) >= x, "{x}: {u}");
            assert!(
                f64::from(u) <= x * (1.0 + 3.0 * f64::from(f32::EPSILON)) + 1e-44,
                "{x}: {u}"
            );
        }
        assert_eq!(up(1e300), f32::INFINITY);
    }

    #[test]
    fn dot_exact_keeps_what_cancels() {
        // Products 2^60 + 2^37, 2^-10 and -2^60 (exact in f64): a plain sum in
        // this order drops the 2^-10 against 2^60, the compensated one keeps it.
        let p = |e: i32| 2f32.powi(e);
        let a = W3::from(Vec3::new(p(30) + p(7), p(-5), -p(30)));
        let b = W3::from(Vec3::new(p(30), p(-5), p(30)));
        let want = 2f64.powi(37) + 2f64.powi(-10);
        assert_eq!(a.dot_exact(b), want);
        assert_ne!(a.dot(b), want, "the plain sum should have lost it");
    }

    #[test]
    fn cross_product_and_magnitudes() {
        let (c, m) = W3::new(1.0, 2.0, 3.0).cross(W3::new(-4.0, 5.0, 0.5));
        assert_eq!(
            c,
            W3::new(2.0 * 0.5 - 3.0 * 5.0, 3.0 * -4.0 - 0.5, 5.0 + 8.0)
        );
        assert_eq!(m, W3::new(1.0 + 15.0, 12.0 + 0.5, 5.0 + 8.0));
    }
}
