//! The chapter's ray equation `r(t) = r0 + v t`, with `|v| = 1`, and the robust
//! spawning of secondary rays.

use crate::error::{Error, Field};
use crate::vec::Vec3;

/// A ray: origin `r0` and unit direction `v`; the point at time `t` is `r0 + v t`.
///
/// The fields are private so that no ray can hold a direction of the wrong length:
/// every intersection test relies on `|v| = 1` (the sphere's half-`b` quadratic most
/// of all, which would report a miss for a direction of length 2 while the plane,
/// triangle and box return the parametric `t`). Build one with [`Ray::new`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Ray {
    pub(crate) origin: Vec3,
    pub(crate) dir: Vec3,
}

/// How far from 1 the squared length of a direction may be for [`Ray::new`] to keep
/// it bit for bit: 2^-20, about 8 ulp of 1. A unit vector rounded to `f32` (each
/// component within half an ulp) is well inside; the intersection tests' error
/// bounds do not depend on more.
const UNIT_TOLERANCE: f32 = 1.0 / (1u32 << 20) as f32;

impl Ray {
    /// A ray from `origin` in the direction of `dir`, of any non-zero length.
    ///
    /// A direction that is already unit to `f32` precision (squared length within
    /// 2^-20 of 1, e.g. one normalised in `f64` and rounded) is kept bit for bit;
    /// any other is normalised, so `Ray::new(o, 2 z)` is the ray `Ray::new(o, z)`.
    ///
    /// # Errors
    ///
    /// [`Error::NotFinite`] for a NaN or infinite component of the origin or the
    /// direction, and [`Error::ZeroLength`] for a direction that cannot be
    /// normalised (zero).
    pub fn new(origin: Vec3, dir: Vec3) -> Result<Self, Error> {
        if !origin.is_finite() {
            return Err(Error::NotFinite(Field::RayOrigin));
        }
        if !dir.is_finite() {
            return Err(Error::NotFinite(Field::RayDirection));
        }
        let dir = if crate::math::abs(dir.length_squared() - 1.0) <= UNIT_TOLERANCE {
            dir
        } else {
            dir.try_normalize()
                .ok_or(Error::ZeroLength(Field::RayDirection))?
        };
        Ok(Self { origin, dir })
    }

    /// A ray whose direction the renderer has just normalised: no check, for the
    /// hot paths (primary, shadow and secondary rays).
    #[inline]
    #[must_use]
    pub(crate) const fn unit(origin: Vec3, dir: Vec3) -> Self {
        Self { origin, dir }
    }

    /// The origin `r0`.
    #[inline]
    #[must_use]
    pub const fn origin(&self) -> Vec3 {
        self.origin
    }

    /// The unit direction `v`.
    #[inline]
    #[must_use]
    pub const fn dir(&self) -> Vec3 {
        self.dir
    }

    /// The point `r0 + v t`.
    #[inline]
    #[must_use]
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// The origin of a ray leaving a surface point `p` in direction `w`, pushed off the
/// surface along the normal `n` just far enough that rounding cannot put it back on
/// the wrong side (pbrt-v4's `OffsetRayOrigin`).
///
/// `err` bounds the absolute error of each component of `p`. The offset is the
/// error projected on the normal, so it scales with the scene: there is no absolute
/// epsilon, and a scene scaled by a power of two is traced with the same bits.
///
/// Always inlined: out of line, the call (arguments through memory, saved FPU
/// registers) costs about as much as the body, and every reflected, refracted or
/// shadow ray pays it.
#[must_use]
#[inline(always)]
pub fn offset_origin(p: Vec3, err: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    let d = n.abs().dot(err);
    // The offset goes to the side of the new direction: -(n d) = n (-d) exactly.
    let d = if w.dot(n) < 0.0 { -d } else { d };
    let offset = n * d;
    let po = p + offset;
    // Round away from p so that the offset survives the addition's rounding.
    Vec3::new(
        step(po.x, offset.x),
        step(po.y, offset.y),
        step(po.z, offset.z),
    )
}

/// `x` moved one ulp in the direction of the sign of `off` (unchanged for a zero
/// or NaN `off`): [`crate::math::next_up`] or [`crate::math::next_down`], bit for bit, computed on
/// the bits with selects rather than branches. A zero `x` of either sign steps to
/// the smallest subnormal of `off`'s sign; an infinity steps towards zero but not
/// away from it; a NaN stays.
#[inline]
fn step(x: f32, off: f32) -> f32 {
    let (xb, ob) = (x.to_bits(), off.to_bits());
    if ob << 1 == 0 {
        return x; // no offset on this axis (an axis-aligned normal): unchanged
    }
    // `(b << 1) - 1` is below `0xfeff_ffff` exactly for a non-zero finite value
    // (zero wraps around, the infinities and NaNs are at or above it).
    let ordinary = |b: u32| (b << 1).wrapping_sub(1) < 0xfeff_ffff;
    if ordinary(xb) && ordinary(ob) {
        // One ulp away from zero when x has the offset's sign, else towards zero.
        let towards = (xb ^ ob) >> 31;
        return f32::from_bits(xb.wrapping_add(1).wrapping_sub(towards << 1));
    }
    step_rare(x, off)
}

/// [`step`] for a zero, infinite or NaN `x`, or a NaN or infinite `off`.
#[cold]
fn step_rare(x: f32, off: f32) -> f32 {
    if off > 0.0 {
        crate::math::next_up(x)
    } else if off < 0.0 {
        crate::math::next_down(x)
    } else {
        x
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math;

    #[test]
    fn at_follows_the_ray_equation() {
        let r = Ray::new(Vec3::new(1.0, 2.0, 3.0), Vec3::Z).unwrap();
        assert_eq!(r.at(2.5), Vec3::new(1.0, 2.0, 5.5));
    }

    #[test]
    fn new_normalises_any_length_and_keeps_unit_directions() {
        let o = Vec3::new(1.0, -2.0, 0.5);
        for k in [2.0f32, 1e-30, 1e30, 0.5, 1.0 + 1e-5] {
            let r = Ray::new(o, Vec3::new(0.0, 0.0, k)).unwrap();
            assert_eq!((r.origin(), r.dir()), (o, Vec3::Z), "length {k}");
        }
        let skew = Ray::new(o, Vec3::new(3.0, 4.0, 0.0)).unwrap();
        assert_eq!(skew.dir(), Vec3::new(0.6, 0.8, 0.0));
        // A unit vector computed in f64 and rounded keeps its bits.
        let (x, y, z) = (0.3f64, 0.4f64, 0.5f64);
        let l = (x * x + y * y + z * z).sqrt();
        let d = Vec3::new((x / l) as f32, (y / l) as f32, (z / l) as f32);
        assert_eq!(Ray::new(o, d).unwrap().dir(), d);
    }

    #[test]
    fn new_refuses_what_is_not_a_ray() {
        let o = Vec3::ZERO;
        assert_eq!(
            Ray::new(o, Vec3::ZERO),
            Err(Error::ZeroLength(Field::RayDirection))
        );
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            assert_eq!(
                Ray::new(o, Vec3::new(bad, 0.0, 1.0)),
                Err(Error::NotFinite(Field::RayDirection))
            );
            assert_eq!(
                Ray::new(Vec3::new(0.0, bad, 0.0), Vec3::Z),
                Err(Error::NotFinite(Field::RayOrigin))
            );
        }
        // The smallest subnormal direction still normalises.
        let tiny = Ray::new(o, Vec3::new(0.0, -f32::from_bits(1), 0.0)).unwrap();
        assert_eq!(tiny.dir(), -Vec3::Y);
    }

    #[test]
    fn offset_goes_to_the_side_of_the_new_direction() {
        let p = Vec3::new(0.0, 1.0, 0.0);
        let err = Vec3::splat(1e-6);
        let up = offset_origin(p, err, Vec3::Y, Vec3::new(0.3, 0.9, 0.0));
        let down = offset_origin(p, err, Vec3::Y, Vec3::new(0.3, -0.9, 0.0));
        assert!(up.y > 1.0 + 1e-6 && down.y < 1.0 - 1e-6);
        assert_eq!((up.x, up.z), (0.0, 0.0));
    }

    #[test]
    fn step_is_next_up_and_next_down() {
        let values = [
            0.0f32,
            -0.0,
            1.0,
            -1.0,
            f32::MIN_POSITIVE,
            -f32::MIN_POSITIVE,
            f32::from_bits(1),
            -f32::from_bits(1),
            3.5e-40,
            1.0e30,
            -7.25,
            f32::MAX,
            -f32::MAX,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ];
        for x in values {
            for (off, want) in [
                (1e-3f32, math::next_up(x)),
                (-1e-3, math::next_down(x)),
                (0.0, x),
                (-0.0, x),
            ] {
                let got = step(x, off);
                assert_eq!(got.to_bits(), want.to_bits(), "step({x:e}, {off})");
            }
            assert_eq!(step(x, f32::NAN).to_bits(), x.to_bits());
        }
        assert!(step(f32::NAN, 1.0).is_nan());
        assert!(step(f32::from_bits(0x7f80_0001), -1.0).is_nan());
    }

    #[test]
    fn offset_scales_with_the_scene() {
        let p = Vec3::new(3.0, 5.0, -7.0);
        let n = Vec3::new(0.6, 0.8, 0.0);
        let err = p.abs() * math::gamma(3);
        let a = offset_origin(p, err, n, n);
        let k = 2f32.powi(20);
        let b = offset_origin(p * k, err * k, n, n);
        assert_eq!(a * k, b);
    }
}
