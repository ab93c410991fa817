//! The chapter's ray equation `r(t) = r0 + v t`, with `|v| = 1`, and the robust
//! spawning of secondary rays.

use crate::math;
use crate::vec::Vec3;

/// A ray: origin `r0` and unit direction `v`; the point at time `t` is `r0 + v t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Origin `r0`.
    pub origin: Vec3,
    /// Unit direction `v`.
    pub dir: Vec3,
}

impl Ray {
    /// A ray from an origin and a direction that the caller guarantees is unit length.
    #[must_use]
    pub const fn new(origin: Vec3, dir: Vec3) -> Self {
        Self { origin, dir }
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
#[must_use]
pub fn offset_origin(p: Vec3, err: Vec3, n: Vec3, w: Vec3) -> Vec3 {
    let d = n.abs().dot(err);
    let mut offset = n * d;
    if w.dot(n) < 0.0 {
        offset = -offset;
    }
    let po = p + offset;
    // Round away from p so that the offset survives the addition's rounding.
    let step = |po: f32, off: f32| {
        if off > 0.0 {
            math::next_up(po)
        } else if off < 0.0 {
            math::next_down(po)
        } else {
            po
        }
    };
    Vec3::new(
        step(po.x, offset.x),
        step(po.y, offset.y),
        step(po.z, offset.z),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn at_follows_the_ray_equation() {
        let r = Ray::new(Vec3::new(1.0, 2.0, 3.0), Vec3::Z);
        assert_eq!(r.at(2.5), Vec3::new(1.0, 2.0, 5.5));
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
