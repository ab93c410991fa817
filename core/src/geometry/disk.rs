//! Disk: the points of a plane within a radius of a centre, and beyond an inner
//! radius when it has one (an annulus, a ring).
//!
//! Its plane is a [`Plane`] through the centre (pbrt-v4's disk is the plane
//! `z = h` of its frame): the same robust time, against the plane's offset from
//! the world's origin, and the same error bound of the point. The radial test
//! then keeps the hits within the radii, widened by the point's rounding so that
//! two disks sharing an edge leave no crack between them.

use super::{Candidate, Extent, Locate, Plane, Shape, Surface};
use crate::error::{Error, Field, length};
use crate::math::{self, gamma};
use crate::ray::Ray;
use crate::vec::Vec3;
use core::f32::consts::{FRAC_1_PI, PI};

/// The disk of centre `center`, unit normal `normal` (double-sided) and radius
/// `radius`, without the points nearer the centre than `inner` (`0 <= inner <
/// radius`).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Disk {
    plane: Plane,
    radius: f32,
    inner: f32,
}

impl Disk {
    /// A disk; the centre's components must be finite and within
    /// [`crate::error::MAX_EXTENT`], the normal finite and not zero (any
    /// length: it is normalised), the radius within `[`[`crate::error::MIN_LENGTH`]`,
    /// `[`crate::error::MAX_EXTENT`]`]` and the inner radius in `[0, radius)`.
    ///
    /// ```
    /// use tessera_core::{Error, error::Field, geometry::Disk, Vec3};
    /// assert!(Disk::try_new(Vec3::ZERO, Vec3::Y, 1.0, 0.5).is_ok());
    /// assert_eq!(
    ///     Disk::try_new(Vec3::ZERO, Vec3::Y, -1.0, 0.0),
    ///     Err(Error::NotPositive(Field::DiskRadius))
    /// );
    /// ```
    pub fn try_new(center: Vec3, normal: Vec3, radius: f32, inner: f32) -> Result<Self, Error> {
        let plane = Plane::try_new(center, normal).map_err(|e| match e {
            Error::NotFinite(Field::PlanePoint) => Error::NotFinite(Field::DiskCenter),
            Error::OutOfRange {
                field: Field::PlanePoint,
                range,
            } => Error::OutOfRange {
                field: Field::DiskCenter,
                range,
            },
            Error::NotFinite(Field::PlaneNormal) => Error::NotFinite(Field::DiskNormal),
            Error::ZeroLength(Field::PlaneNormal) => Error::ZeroLength(Field::DiskNormal),
            other => other,
        })?;
        let radius = crate::error::finite(radius, Field::DiskRadius)?;
        if radius <= 0.0 {
            return Err(Error::NotPositive(Field::DiskRadius));
        }
        let radius = length(radius, Field::DiskRadius)?;
        let inner = crate::error::flush(crate::error::finite(inner, Field::DiskInnerRadius)?);
        if !(0.0..radius).contains(&inner) {
            return Err(Error::OutOfRange {
                field: Field::DiskInnerRadius,
                range: "[0, radius)",
            });
        }
        Ok(Self {
            plane,
            radius,
            inner,
        })
    }

    /// A disk of baked data (`static` tables written by `tessera bake`): its
    /// plane ([`Plane::baked`]) and radii, not checked here, in a `const`
    /// context: [`crate::BakedScene::view`] checks it against
    /// [`Disk::try_new`] before any render takes it.
    #[must_use]
    pub const fn baked(plane: Plane, radius: f32, inner: f32) -> Self {
        Self {
            plane,
            radius,
            inner,
        }
    }

    /// The centre.
    #[must_use]
    pub fn center(&self) -> Vec3 {
        self.plane.point()
    }

    /// The unit normal.
    #[must_use]
    pub fn normal(&self) -> Vec3 {
        self.plane.normal()
    }

    /// The radius.
    #[must_use]
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// The inner radius (0 for a whole disk).
    #[must_use]
    pub fn inner(&self) -> f32 {
        self.inner
    }

    /// The disk's plane.
    #[must_use]
    pub fn plane(&self) -> &Plane {
        &self.plane
    }

    /// The hit time of `ray` with `0 < t < t_max`, if any: the plane's, kept
    /// when the point lies between the radii (widened by its rounding).
    #[inline(never)]
    fn hit(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        let t = self.plane.hit(ray, t_max)?;
        let d = ray.at(t) - self.center();
        let rho2 = d.length_squared();
        // The point is off by a few roundings of what the ray spans; the
        // centre's own coordinates round the difference once more.
        let slack =
            gamma(4) * (ray.origin.abs() + (ray.dir * t).abs() + self.center().abs()).max_element();
        let outer = self.radius + slack;
        let inner = math::max(0.0, self.inner - slack);
        (rho2 <= outer * outer && rho2 >= inner * inner).then_some(t)
    }
}

/// A disk is flat.
impl super::Kinded for Disk {
    const FLAT: bool = true;

    fn check_baked(&self) -> Result<bool, Error> {
        // The plane as [`Plane::try_new`] makes it from its own point and
        // normal (its own check), then the radii as given.
        let plane_ok = super::Kinded::check_baked(&self.plane)?;
        Ok(plane_ok
            && Self::try_new(self.center(), self.normal(), self.radius, self.inner).is_ok_and(
                |d| d.radius == self.radius && d.inner.to_bits() == self.inner.to_bits(),
            ))
    }

    fn scaled(&self, f: f32) -> Result<Self, Error> {
        Self::try_new(
            self.center() * f,
            self.normal(),
            self.radius * f,
            self.inner * f,
        )
    }

    /// Flat: seen edge-on, a line.
    fn girth(&self) -> super::Girth {
        super::Girth::Thin
    }

    /// The box of the disk: along each world axis `i`, `r sqrt(1 - n_i^2)` from
    /// its centre, widened by its roundings.
    #[inline]
    fn extent(&self) -> Extent {
        let n = self.normal();
        let r = self.radius * (1.0 + gamma(8));
        let reach = |c: f32| r * math::sqrt(math::max(0.0, 1.0 - c * c) + gamma(4));
        let e = Vec3::new(reach(n.x), reach(n.y), reach(n.z));
        let c = self.center();
        let pad = c.abs() * gamma(2);
        Extent::Box {
            min: c - e - pad,
            max: c + e + pad,
        }
    }

    #[inline(always)]
    fn search<'r, V: super::Visit<'r, Self>>(v: &mut V) -> Option<(usize, Candidate)> {
        if v.none() {
            return None;
        }
        let ray = v.ray();
        v.each(|d, t| d.hit(ray, t).map(Candidate::at))
    }
}

impl Locate for Disk {
    #[inline(always)]
    fn locate(&self, ray: &Ray, hit: &Candidate) -> (Vec3, Vec3, Vec3) {
        self.plane.locate(ray, hit)
    }

    #[inline(always)]
    fn error(&self, ray: &Ray, hit: &Candidate, point: Vec3, aux: Vec3) -> Vec3 {
        self.plane.error(ray, hit, point, aux)
    }
}

impl Shape for Disk {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Candidate> {
        self.hit(ray, t_max).map(Candidate::at)
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.hit(ray, t_max).is_some()
    }

    fn surface(&self, ray: &Ray, hit: &Candidate) -> Surface {
        super::surface(self, ray, hit)
    }

    fn uv_wraps(&self) -> bool {
        true
    }

    /// `u` the angle about the centre (0 to 1 from `atan2` in the frame of the
    /// plane's tangents), `v` from the inner edge (0) to the rim (1).
    fn uv(&self, surface: &Surface, _hit: &Candidate) -> [f32; 2] {
        let (t, b) = self.plane.tangents();
        let d = surface.point - self.center();
        let (x, y) = (d.dot(t), d.dot(b));
        let u = (math::atan2(y, x) + PI) * (0.5 * FRAC_1_PI);
        let v = (math::sqrt(x * x + y * y) - self.inner) / (self.radius - self.inner);
        [u, v.clamp(0.0, 1.0)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(o: Vec3, d: Vec3) -> Ray {
        Ray::unit(o, d.try_normalize().unwrap())
    }

    #[test]
    fn a_ring_is_hit_between_its_radii_only() {
        let d =
            Disk::try_new(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 3.0, 0.0), 2.0, 1.0).unwrap();
        let down = |x: f32| ray(Vec3::new(x, 5.0, 0.0), -Vec3::Y);
        assert_eq!(d.intersect(&down(0.5), f32::INFINITY), None);
        assert_eq!(d.intersect(&down(2.5), f32::INFINITY), None);
        let h = d.intersect(&down(1.5), f32::INFINITY).unwrap();
        assert_eq!(h.t, 4.0);
        let s = d.surface(&down(1.5), &h);
        assert_eq!(s.normal, Vec3::Y);
        let [_, v] = d.uv(&s, &h);
        assert!((v - 0.5).abs() < 1e-6, "{v}");
    }

    /// Rays down onto a ring just inside and just outside its edges: hit, then
    /// missed, the edges widened only by the point's rounding (a few ulps of
    /// what the ray spans); at radii from `2^-40` to `2^40`, the same times
    /// scaled bit for bit.
    #[test]
    fn rays_at_the_edges_hit_or_miss_by_which_side_they_pass_at_any_scale() {
        let e = libm::ldexpf(1.0, -16);
        for k in [-40, 0, 40] {
            let f = libm::ldexpf(1.0, k);
            let d = Disk::try_new(Vec3::ZERO, Vec3::Y, 2.0 * f, f).unwrap();
            let down = |x: f32| Ray::unit(Vec3::new(x * f, 3.0 * f, 0.0), -Vec3::Y);
            for (x, hit) in [
                (2.0 * (1.0 - e), true),
                (2.0 * (1.0 + 4.0 * e), false),
                (1.0 + e, true),
                (1.0 - 4.0 * e, false),
            ] {
                let h = d.intersect(&down(x), f32::INFINITY);
                assert_eq!(h.is_some(), hit, "{k} {x}");
                if let Some(h) = h {
                    assert_eq!(h.t / f, 3.0, "{k} {x}");
                }
            }
        }
    }

    /// A ray almost in the disk's plane (`2^-20` off it, over a thousand
    /// radii) meets it where the analytic time says, and one in the plane
    /// never does.
    #[test]
    fn grazing_rays_meet_the_analytic_time() {
        let d = Disk::try_new(Vec3::ZERO, Vec3::Y, 1.0, 0.0).unwrap();
        let s = libm::ldexpf(1.0, -20);
        // From 1,000 units away, 1e-3 above the plane, falling s per unit.
        let dir = Vec3::new(-1.0, -s, 0.0).try_normalize().unwrap();
        let o = Vec3::new(1000.0, 1000.0 * s, 0.0);
        let h = d.intersect(&Ray::unit(o, dir), f32::INFINITY).unwrap();
        let exact = 1000.0 * (1.0 + f64::from(s) * f64::from(s)).sqrt();
        assert!((f64::from(h.t) - exact).abs() < 1e-3, "{} {exact}", h.t);
        let flat = Ray::unit(Vec3::new(5.0, 0.0, 0.0), -Vec3::X);
        assert_eq!(d.intersect(&flat, f32::INFINITY), None);
    }

    #[test]
    fn bad_numbers_are_refused_by_name() {
        assert_eq!(
            Disk::try_new(Vec3::ZERO, Vec3::Y, 1.0, 1.0),
            Err(Error::OutOfRange {
                field: Field::DiskInnerRadius,
                range: "[0, radius)"
            })
        );
        assert_eq!(
            Disk::try_new(Vec3::ZERO, Vec3::ZERO, 1.0, 0.0),
            Err(Error::ZeroLength(Field::DiskNormal))
        );
        assert_eq!(
            Disk::try_new(Vec3::splat(f32::INFINITY), Vec3::Y, 1.0, 0.0),
            Err(Error::NotFinite(Field::DiskCenter))
        );
        assert!(Disk::try_new(Vec3::ZERO, Vec3::Y, 1.0, -0.5).is_err());
    }

    #[test]
    fn two_rings_sharing_an_edge_leave_no_crack() {
        // A disk of radius 1 and a ring from 1 to 2, tilted: every ray aimed
        // within 1e-6 of the shared circle hits one of them.
        let n = Vec3::new(0.3, 1.0, -0.2);
        let c = Vec3::new(0.4, -0.3, 0.7);
        let a = Disk::try_new(c, n, 1.0, 0.0).unwrap();
        let b = Disk::try_new(c, n, 2.0, 1.0).unwrap();
        let (t, u) = a.plane.tangents();
        let mut s = 11u32;
        for i in 0..4000 {
            let ang = i as f32 / 4000.0;
            let rim = c
                + (t * math::cos_turns(ang) + u * math::sin_turns(ang))
                    * (1.0 + 1e-6 * super::super::test_rand(&mut s));
            let from = rim
                + a.normal() * 3.0
                + Vec3::new(
                    super::super::test_rand(&mut s),
                    super::super::test_rand(&mut s),
                    super::super::test_rand(&mut s),
                );
            let r = Ray::new(from, rim - from).unwrap();
            assert!(
                a.intersect(&r, f32::INFINITY).is_some()
                    || b.intersect(&r, f32::INFINITY).is_some(),
                "ray {i}"
            );
        }
    }

    #[test]
    fn the_extent_holds_the_disk() {
        let d = Disk::try_new(
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(-2.0, 0.5, 4.0),
            0.8,
            0.1,
        )
        .unwrap();
        let Extent::Box { min, max } = super::super::Kinded::extent(&d) else {
            panic!("not a box")
        };
        let (t, u) = d.plane.tangents();
        for i in 0..360 {
            let a = i as f32 / 360.0;
            let p = d.center() + (t * math::cos_turns(a) + u * math::sin_turns(a)) * d.radius;
            assert!(
                p.min(min) == min && p.max(max) == max,
                "{p:?} {min:?} {max:?}"
            );
        }
    }
}
