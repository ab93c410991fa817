//! Axis-aligned boxes (the chapter's cube), intersected with a NaN-safe slab test.
//!
//! Each axis bounds the ray to a slab `[t_near, t_far]`. A direction component of
//! `±0` gives `1/d = ±inf`, and a ray lying in a face plane gives `0 * inf = NaN`;
//! the updates below are written so that a NaN never replaces a bound, which makes
//! such a ray count as inside that slab, the same way on all six faces.

use super::{Candidate, Locate, Shape, Surface};
use crate::error::{Error, Field, position};
use crate::math;
use crate::ray::Ray;
use crate::vec::Vec3;

/// An axis-aligned box `[min, max]`; a flat box (`min == max` on an axis) is allowed.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Aabb {
    min: Vec3,
    max: Vec3,
}

/// The ray's parametric span inside the box and the faces that bound it.
struct Span {
    /// Entry time (0 when the origin is inside every slab).
    t0: f32,
    /// Face through which the ray enters (meaningful when `t0 > 0`).
    entry: u8,
    /// Exit time (`t_max` when no slab ends before it).
    t1: f32,
    /// Face through which the ray leaves (meaningful when `t1 < t_max`).
    exit: u8,
}

impl Aabb {
    /// A box from its min and max corners.
    ///
    /// # Errors
    /// [`Error::NotFinite`] with [`Field::BoxMin`] or [`Field::BoxMax`] if a
    /// component is NaN or infinite, [`Error::OutOfRange`] if it is beyond
    /// [`crate::error::MAX_EXTENT`]; [`Error::InvertedBox`] if `min > max` on some
    /// axis.
    pub fn try_new(min: Vec3, max: Vec3) -> Result<Self, Error> {
        let min = position(min, Field::BoxMin)?;
        let max = position(max, Field::BoxMax)?;
        if min.x > max.x || min.y > max.y || min.z > max.z {
            return Err(Error::InvertedBox);
        }
        Ok(Self { min, max })
    }

    /// A box of baked data (`static` tables written by `tessera bake`), not
    /// checked here, in a `const` context: [`crate::BakedScene::view`] checks it
    /// against [`Aabb::try_new`] before any render takes it.
    #[must_use]
    pub const fn baked(min: [f32; 3], max: [f32; 3]) -> Self {
        Self {
            min: Vec3::new(min[0], min[1], min[2]),
            max: Vec3::new(max[0], max[1], max[2]),
        }
    }

    /// The min corner.
    #[must_use]
    pub fn min(&self) -> Vec3 {
        self.min
    }

    /// The max corner.
    #[must_use]
    pub fn max(&self) -> Vec3 {
        self.max
    }

    /// A box from corners known to be ordered and finite (no range check: a
    /// culling bound, never a primitive).
    pub(crate) fn enclosing(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    /// True when the ray from `origin` (reciprocal direction `inv`) passes through
    /// the box between times 0 and `t_max`.
    #[inline(always)]
    pub(crate) fn spans(&self, origin: Vec3, inv: Vec3, t_max: f32) -> bool {
        self.times(origin, inv, t_max).is_some()
    }

    /// The nearest hit with `0 < t < t_max`, for a ray of origin `origin` and
    /// reciprocal direction `inv` ([`inverse`]): what the renderer calls per box.
    #[inline(always)]
    pub(crate) fn hit_inv(&self, origin: Vec3, inv: Vec3, t_max: f32) -> Option<Candidate> {
        let s = self.span_inv(origin, inv, t_max)?;
        Self::nearest(&s, t_max).map(|(t, face)| Candidate {
            t,
            face,
            ..Candidate::default()
        })
    }

    /// The time of [`Aabb::hit_inv`]'s hit, bit for bit, without its face: the
    /// searches' test (a box's face is needed only when it is the nearest hit,
    /// [`Aabb::face_inv`]), fewer instructions than the test that tracks
    /// faces.
    #[inline(always)]
    pub(crate) fn time_inv(&self, origin: Vec3, inv: Vec3, t_max: f32) -> Option<f32> {
        let (t0, t1) = self.times(origin, inv, t_max)?;
        let t = if t0 > 0.0 { t0 } else { t1 };
        (t > 0.0 && t < t_max).then_some(t)
    }

    /// [`Aabb::span_inv`]'s times `(t0, t1)`, without the faces.
    #[inline(always)]
    fn times(&self, origin: Vec3, inv: Vec3, t_max: f32) -> Option<(f32, f32)> {
        let (mut t0, mut t1) = (0.0, t_max);
        slab_time(&mut t0, &mut t1, origin.x, inv.x, self.min.x, self.max.x);
        if t0 > t1 {
            return None;
        }
        slab_time(&mut t0, &mut t1, origin.y, inv.y, self.min.y, self.max.y);
        // A slab only raises t0 and lowers t1 (a NaN one leaves them): an empty
        // span stays empty, and most boxes are missed by then.
        if t0 > t1 {
            return None;
        }
        slab_time(&mut t0, &mut t1, origin.z, inv.z, self.min.z, self.max.z);
        if t0 > t1 { None } else { Some((t0, t1)) }
    }

    /// The face of the hit that [`Aabb::time_inv`] found for this ray (with any
    /// `t_max`): the entry face when the ray starts outside, else the exit face.
    /// The same as [`Aabb::hit_inv`]'s: the entry face does not depend on `t_max`,
    /// and the exit face is the first slab reaching the smallest exit time, which
    /// lies below the `t_max` the hit was found with, so an infinite `t_max` picks
    /// the same slab.
    pub(crate) fn face_inv(&self, origin: Vec3, inv: Vec3) -> u8 {
        self.span_inv(origin, inv, f32::INFINITY)
            .map_or(0, |s| if s.t0 > 0.0 { s.entry } else { s.exit })
    }

    /// The slab test: the span `[t0, t1]` of the ray inside the box, clipped to
    /// `[0, t_max]`, or `None` when it is empty (for [`Shape::occluded`]).
    #[cfg_attr(not(any(test, feature = "testing")), allow(dead_code))]
    fn span(&self, ray: &Ray, t_max: f32) -> Option<Span> {
        self.span_inv(ray.origin, inverse(ray.dir), t_max)
    }

    /// [`Aabb::span`] with the ray's reciprocal direction `inv` computed once per
    /// ray ([`inverse`]).
    #[inline(always)]
    fn span_inv(&self, origin: Vec3, inv: Vec3, t_max: f32) -> Option<Span> {
        let mut s = Span {
            t0: 0.0,
            entry: 0,
            t1: t_max,
            exit: 0,
        };
        slab(&mut s, origin.x, inv.x, self.min.x, self.max.x, 0);
        slab(&mut s, origin.y, inv.y, self.min.y, self.max.y, 2);
        slab(&mut s, origin.z, inv.z, self.min.z, self.max.z, 4);
        if s.t0 > s.t1 { None } else { Some(s) }
    }

    /// The nearest hit of a span: the entry when the origin is outside, else the exit.
    fn nearest(s: &Span, t_max: f32) -> Option<(f32, u8)> {
        let (t, face) = if s.t0 > 0.0 {
            (s.t0, s.entry)
        } else {
            (s.t1, s.exit)
        };
        // False for NaN; t1 == t_max means no face ends the span before t_max.
        if t > 0.0 && t < t_max {
            Some((t, face))
        } else {
            None
        }
    }
}

/// The times at which a ray of origin `o` and reciprocal direction `inv` on one
/// axis crosses the near and the far plane of the slab `[lo, hi]`, and whether the
/// near plane is `hi`: the one computation behind [`slab`] and [`slab_time`].
#[inline(always)]
fn crossings(o: f32, inv: f32, lo: f32, hi: f32) -> (f32, f32, bool) {
    // Choose the near plane by the sign of 1/d (as pbrt-v4's `dirIsNeg`) rather
    // than by swapping after the fact: a NaN t_near would defeat the swap, and then
    // -0.0 and +0.0 would treat a face plane differently.
    let flipped = inv < 0.0;
    let (near, far) = if flipped { (hi, lo) } else { (lo, hi) };
    // The exit widened so that rounding cannot make a grazing ray miss (pbrt-v4).
    let t_far = (far - o) * inv * (1.0 + 2.0 * math::gamma(3));
    ((near - o) * inv, t_far, flipped)
}

/// One axis of the slab test: narrows `s` to the slab `[lo, hi]` of the axis whose
/// faces are `face` (the `lo` side) and `face + 1`, for a ray of origin `o` and
/// reciprocal direction `inv` on that axis.
#[inline(always)]
fn slab(s: &mut Span, o: f32, inv: f32, lo: f32, hi: f32, face: u8) {
    let (t_near, t_far, flipped) = crossings(o, inv, lo, hi);
    let (near_face, far_face) = if flipped {
        (face + 1, face)
    } else {
        (face, face + 1)
    };
    // Comparisons with NaN are false: a NaN slab leaves the span alone.
    if t_near > s.t0 {
        s.t0 = t_near;
        s.entry = near_face;
    }
    if t_far < s.t1 {
        s.t1 = t_far;
        s.exit = far_face;
    }
}

/// [`slab`] without the faces: the same times, bit for bit.
#[inline(always)]
fn slab_time(t0: &mut f32, t1: &mut f32, o: f32, inv: f32, lo: f32, hi: f32) {
    let (t_near, t_far, _) = crossings(o, inv, lo, hi);
    if t_near > *t0 {
        *t0 = t_near;
    }
    if t_far < *t1 {
        *t1 = t_far;
    }
}

/// The reciprocal of each component of a direction (`+-inf` for `+-0`): the slab
/// test's per-ray constant.
#[inline]
pub(crate) fn inverse(dir: Vec3) -> Vec3 {
    Vec3::new(1.0 / dir.x, 1.0 / dir.y, 1.0 / dir.z)
}

/// Axis (0, 1, 2) and sign (`true` = max side) of a face index.
fn face_axis(face: u8) -> (usize, bool) {
    (usize::from(face / 2).min(2), face % 2 == 1)
}

/// A box is closed and convex.
impl super::Kinded for Aabb {
    const FLAT: bool = false;

    fn check_baked(&self) -> Result<bool, crate::error::Error> {
        Ok(Self::try_new(self.min(), self.max())? == *self)
    }

    fn scaled(&self, f: f32) -> Result<Self, crate::error::Error> {
        Self::try_new(self.min() * f, self.max() * f)
    }

    /// The ball at its centre that touches its nearest faces; its corners
    /// half a diagonal away.
    fn girth(&self) -> super::Girth {
        let half = (self.max() - self.min()) * 0.5;
        super::Girth::Ball {
            center: (self.min() + self.max()) * 0.5,
            radius: crate::math::min(crate::math::min(half.x, half.y), half.z),
            reach: half.length(),
        }
    }

    #[inline(always)]
    fn extent(&self) -> super::Extent {
        super::Extent::Box {
            min: self.min(),
            max: self.max(),
        }
    }

    #[inline(always)]
    fn search<'r, V: super::Visit<'r, Self>>(v: &mut V) -> Option<(usize, super::Candidate)> {
        if v.none() {
            return None;
        }
        let inv = v.inv();
        let origin = v.ray().origin;
        let (index, mut hit) =
            v.each(|b, t| b.time_inv(origin, inv, t).map(super::Candidate::at))?;
        // The face, for the nearest hit only.
        if !V::FIRST
            && let Some(b) = v.get(index)
        {
            hit.face = b.face_inv(origin, inv);
        }
        Some((index, hit))
    }
}

impl Locate for Aabb {
    #[inline(always)]
    fn locate(&self, ray: &Ray, hit: &Candidate) -> (Vec3, Vec3, Vec3) {
        let (axis, positive) = face_axis(hit.face);
        let plane = if positive {
            self.max.get(axis)
        } else {
            self.min.get(axis)
        };
        // Snapping to the face makes the error along the normal exactly zero.
        let point = ray.at(hit.t).with(axis, plane);
        let normal = Vec3::ZERO.with(axis, if positive { 1.0 } else { -1.0 });
        (point, normal, Vec3::ZERO)
    }

    #[inline(always)]
    fn error(&self, ray: &Ray, hit: &Candidate, _: Vec3, _: Vec3) -> Vec3 {
        let (axis, _) = face_axis(hit.face);
        let error = (ray.origin.abs() + (ray.dir * hit.t).abs()) * math::gamma(3);
        error.with(axis, 0.0)
    }
}

impl Shape for Aabb {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Candidate> {
        self.hit_inv(ray.origin, inverse(ray.dir), t_max)
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        // Any hit in (0, t_max) exists exactly when the nearest one does.
        self.span(ray, t_max)
            .and_then(|s| Self::nearest(&s, t_max))
            .is_some()
    }

    fn surface(&self, ray: &Ray, hit: &Candidate) -> Surface {
        super::surface(self, ray, hit)
    }

    fn uv(&self, surface: &Surface, hit: &Candidate) -> [f32; 2] {
        let (a, b) = match face_axis(hit.face).0 {
            0 => (1, 2),
            1 => (0, 2),
            _ => (0, 1),
        };
        let coord = |i: usize| {
            let lo = self.min.get(i);
            let extent = self.max.get(i) - lo;
            // A flat box has no extent on that axis: 0, never 0/0.
            if extent > 0.0 {
                ((surface.point.get(i) - lo) / extent).clamp(0.0, 1.0)
            } else {
                0.0
            }
        };
        [coord(a), coord(b)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::test_rand as rand;

    fn boxed() -> Aabb {
        Aabb::try_new(Vec3::new(-1.0, -2.0, -3.0), Vec3::new(1.0, 2.0, 3.0)).unwrap()
    }

    fn cube() -> Aabb {
        Aabb::try_new(Vec3::splat(-1.0), Vec3::splat(1.0)).unwrap()
    }

    /// Relative closeness allowing for the widened exit time.
    fn close(a: f32, b: f32) -> bool {
        (a - b).abs() <= 1e-6 * crate::math::max(b.abs(), 1.0)
    }

    #[test]
    fn hits_each_face() {
        // Each ray enters a face at the point 3/4 of the way along both face axes.
        let cases = [
            (Vec3::new(-5.0, 1.0, 1.5), Vec3::X, 0, -Vec3::X),
            (Vec3::new(5.0, 1.0, 1.5), -Vec3::X, 1, Vec3::X),
            (Vec3::new(0.5, -6.0, 1.5), Vec3::Y, 2, -Vec3::Y),
            (Vec3::new(0.5, 6.0, 1.5), -Vec3::Y, 3, Vec3::Y),
            (Vec3::new(0.5, 1.0, -7.0), Vec3::Z, 4, -Vec3::Z),
            (Vec3::new(0.5, 1.0, 7.0), -Vec3::Z, 5, Vec3::Z),
        ];
        let b = boxed();
        for (o, d, face, n) in cases {
            let ray = Ray::unit(o, d);
            let h = b.intersect(&ray, f32::INFINITY).unwrap();
            assert_eq!((h.t, h.face), (4.0, face), "{o:?}");
            let s = b.surface(&ray, &h);
            assert_eq!(s.normal, n);
            assert_eq!(s.point, o + d * 4.0);
            assert_eq!(s.error.get(usize::from(face / 2)), 0.0);
            assert_eq!(b.uv(&s, &h), [0.75, 0.75], "{o:?}");
            assert!(b.occluded(&ray, f32::INFINITY));
        }
        // Oblique: enters -x at t = 3 / 0.8, at y = -1 + 0.6 * 3.75 = 1.25.
        let ray = Ray::unit(Vec3::new(-4.0, -1.0, 0.0), Vec3::new(0.8, 0.6, 0.0));
        let h = b.intersect(&ray, f32::INFINITY).unwrap();
        assert!(close(h.t, 3.75) && h.face == 0, "{h:?}");
        let s = b.surface(&ray, &h);
        assert_eq!(s.point.x, -1.0);
        assert!((s.point.y - 1.25).abs() < 1e-6);
    }

    #[test]
    fn origin_inside_returns_exit_face() {
        let b = boxed();
        for (d, t, face) in [(Vec3::Z, 3.0, 5), (-Vec3::X, 1.0, 0), (-Vec3::Y, 2.0, 2)] {
            let ray = Ray::unit(Vec3::ZERO, d);
            let h = b.intersect(&ray, f32::INFINITY).unwrap();
            assert!(close(h.t, t) && h.face == face, "{d:?} {h:?}");
            let s = b.surface(&ray, &h);
            assert_eq!(s.point, d * t, "snapped exactly to the face");
            assert_eq!(s.normal, d);
        }
    }

    #[test]
    fn misses() {
        let b = boxed();
        for ray in [
            Ray::unit(Vec3::new(-5.0, 3.0, 0.0), Vec3::X),
            Ray::unit(Vec3::new(5.0, 0.0, 0.0), Vec3::X),
            Ray::unit(Vec3::new(-5.0, 0.0, 0.0), Vec3::new(0.6, 0.8, 0.0)),
        ] {
            assert_eq!(b.intersect(&ray, f32::INFINITY), None, "{ray:?}");
            assert!(!b.occluded(&ray, f32::INFINITY));
        }
    }

    #[test]
    fn ray_in_a_face_plane_is_inside_that_slab_on_all_faces() {
        let c = cube();
        for axis in 0..3 {
            let (b, other) = ((axis + 1) % 3, (axis + 2) % 3);
            for plane in [-1.0, 1.0] {
                for (sa, so) in [(0.0, 0.0), (-0.0, 0.0), (0.0, -0.0), (-0.0, -0.0)] {
                    for sign in [1.0f32, -1.0] {
                        let dir = Vec3::ZERO.with(axis, sa).with(other, so).with(b, sign);
                        let enter = if sign > 0.0 { 2 * b } else { 2 * b + 1 } as u8;
                        let at = |pb: f32, po: f32| {
                            Vec3::ZERO.with(axis, plane).with(b, pb).with(other, po)
                        };
                        // From outside, within the face: enters through axis b.
                        let ray = Ray::unit(at(-10.0 * sign, 0.5), dir);
                        let h = c.intersect(&ray, f32::INFINITY).unwrap();
                        assert_eq!((h.t, h.face), (9.0, enter), "{ray:?}");
                        assert!(c.occluded(&ray, f32::INFINITY));
                        // Starting on the face: leaves through the opposite side.
                        let ray = Ray::unit(at(0.0, 0.5), dir);
                        let h = c.intersect(&ray, f32::INFINITY).unwrap();
                        assert!(close(h.t, 1.0) && h.face == enter ^ 1, "{ray:?} {h:?}");
                        // In the plane but beside the face: no hit, no NaN.
                        let ray = Ray::unit(at(-10.0 * sign, 5.0), dir);
                        assert_eq!(c.intersect(&ray, f32::INFINITY), None);
                    }
                }
            }
        }
    }

    #[test]
    fn ray_along_an_edge_from_a_corner() {
        let c = cube();
        for (dx, dy) in [(0.0, 0.0), (-0.0, 0.0), (0.0, -0.0), (-0.0, -0.0)] {
            let dir = Vec3::new(dx, dy, 1.0);
            let h = c.intersect(&Ray::unit(Vec3::new(-1.0, -1.0, -5.0), dir), f32::INFINITY);
            assert_eq!(h.map(|h| (h.t, h.face)), Some((4.0, 4)));
            // From the corner itself: the origin is on the box, so the hit is the exit.
            let ray = Ray::unit(Vec3::splat(-1.0), dir);
            let h = c.intersect(&ray, f32::INFINITY).unwrap();
            assert!(close(h.t, 2.0) && h.face == 5, "{h:?}");
            assert_eq!(c.surface(&ray, &h).point, Vec3::new(-1.0, -1.0, 1.0));
            assert_eq!(c.uv(&c.surface(&ray, &h), &h), [0.0, 0.0]);
        }
    }

    #[test]
    fn flat_box_is_hit_and_uv_has_no_nan() {
        let f = Aabb::try_new(Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0)).unwrap();
        let ray = Ray::unit(Vec3::new(0.5, 0.0, -5.0), Vec3::Z);
        let h = f.intersect(&ray, f32::INFINITY).unwrap();
        assert_eq!((h.t, h.face), (5.0, 4));
        assert_eq!(f.uv(&f.surface(&ray, &h), &h), [0.75, 0.5]);
        // Hit on an x face of the flat box: its z extent is zero.
        let ray = Ray::unit(Vec3::new(-3.0, 0.0, 0.0), Vec3::X);
        let h = f.intersect(&ray, f32::INFINITY).unwrap();
        assert_eq!((h.t, h.face), (2.0, 0));
        assert_eq!(f.uv(&f.surface(&ray, &h), &h), [0.5, 0.0]);
    }

    #[test]
    fn t_max_is_exclusive() {
        let b = boxed();
        let ray = Ray::unit(Vec3::new(-5.0, 0.0, 0.0), Vec3::X);
        assert_eq!(b.intersect(&ray, 4.0), None);
        assert!(!b.occluded(&ray, 4.0));
        assert_eq!(b.intersect(&ray, 4.001).map(|h| h.t), Some(4.0));
        let inside = Ray::unit(Vec3::ZERO, Vec3::Z);
        assert_eq!(b.intersect(&inside, 2.9), None);
        assert!(!b.occluded(&inside, 2.9));
        assert!(b.occluded(&inside, 3.1));
    }

    #[test]
    fn occluded_agrees_with_intersect_on_random_rays() {
        let mut seed = 0x2545_f491;
        let b = boxed();
        let mut hits = 0;
        for _ in 0..5000 {
            let o = Vec3::new(rand(&mut seed), rand(&mut seed), rand(&mut seed)) * 5.0;
            let Some(d) =
                Vec3::new(rand(&mut seed), rand(&mut seed), rand(&mut seed)).try_normalize()
            else {
                continue;
            };
            let t_max = 10.0 * (rand(&mut seed) + 1.0);
            let ray = Ray::unit(o, d);
            let h = b.intersect(&ray, t_max);
            assert_eq!(b.occluded(&ray, t_max), h.is_some(), "{ray:?}");
            if let Some(h) = h {
                hits += 1;
                assert!(h.t > 0.0 && h.t < t_max);
                // The reported point lies on the reported face, within the box.
                let s = b.surface(&ray, &h);
                let (axis, positive) = face_axis(h.face);
                let plane = if positive { b.max() } else { b.min() }.get(axis);
                assert_eq!(s.point.get(axis), plane);
                for i in 0..3 {
                    let slack = 1e-5;
                    assert!(
                        s.point.get(i) >= b.min().get(i) - slack
                            && s.point.get(i) <= b.max().get(i) + slack
                    );
                    assert!((s.point.get(i) - ray.at(h.t).get(i)).abs() <= 1e-5);
                }
                // The outward normal faces the ray exactly when it enters.
                let entering = !(o.x > -1.0
                    && o.x < 1.0
                    && o.y > -2.0
                    && o.y < 2.0
                    && o.z > -3.0
                    && o.z < 3.0);
                assert_eq!(s.normal.dot(d) < 0.0, entering, "{ray:?} {h:?}");
            }
        }
        assert!(hits > 500, "{hits}");
    }

    #[test]
    fn constructor_errors() {
        let nan = Vec3::new(f32::NAN, 0.0, 0.0);
        let inf = Vec3::new(0.0, 0.0, f32::INFINITY);
        assert_eq!(
            Aabb::try_new(nan, Vec3::splat(1.0)),
            Err(Error::NotFinite(Field::BoxMin))
        );
        assert_eq!(
            Aabb::try_new(Vec3::ZERO, inf),
            Err(Error::NotFinite(Field::BoxMax))
        );
        let inverted = Aabb::try_new(Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 0.5, 1.0));
        assert_eq!(inverted, Err(Error::InvertedBox));
        let flat = Aabb::try_new(Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 1.0, 1.0)).unwrap();
        assert_eq!(
            (flat.min(), flat.max()),
            (Vec3::new(0.0, 1.0, 0.0), Vec3::splat(1.0))
        );
    }
}
