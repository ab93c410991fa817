//! Infinite plane: a point and a normal.

use super::wide::W3;
use super::{Candidate, Locate, Shape, Surface, tangent_basis};
use crate::error::{Error, Field, position, unit};
use crate::math::gamma;
use crate::ray::Ray;
use crate::vec::Vec3;

/// The infinite plane through `point` with unit normal `normal` (double-sided).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    point: Vec3,
    normal: Vec3,
    /// The signed distance of the plane from the world's origin: `N . point / |N|`
    /// for the normal `N` as given, the dot product summed almost exactly in `f64`
    /// ([`W3::dot_exact`]), then rounded: the plane is `normal . x = offset`,
    /// within half an ulp of the offset where it crosses the line through the
    /// world's origin along its normal, and off by a few ulps of `|x|` at a point
    /// `x` (the rounding of the unit normal), as close as `f32` can hold `x`
    /// itself. A hit's time
    /// `(offset - n.o) / n.d` then involves the ray's origin and the plane's
    /// distance from the world's origin, never the point the user happened to
    /// give: `(point - o).n` loses ulps of `point`, and a plane through a point
    /// `10^7` away put the hits of a camera near the origin units off the plane.
    offset: f32,
    /// The tangents of [`tangent_basis`]`(normal)`, the axes of the plane's uv,
    /// computed once here rather than at every textured hit.
    tangents: (Vec3, Vec3),
}

impl Plane {
    /// A plane; the normal may have any non-zero finite length (it is normalised);
    /// the point's components must be within [`crate::error::MAX_EXTENT`].
    ///
    /// ```
    /// use tessera::{Error, error::Field, geometry::Plane, Vec3};
    /// assert!(Plane::try_new(Vec3::ZERO, Vec3::new(0.0, 2.0, 0.0)).is_ok());
    /// assert_eq!(
    ///     Plane::try_new(Vec3::ZERO, Vec3::ZERO),
    ///     Err(Error::ZeroLength(Field::PlaneNormal))
    /// );
    /// ```
    pub fn try_new(point: Vec3, normal: Vec3) -> Result<Self, Error> {
        // Checked (finite, not zero), normalised in `f64`: the plane is
        // `N . x = N . point` for the normal `N` as given, its offset summed
        // almost exactly and divided by `|N|`; both numbers rounded once.
        unit(normal, Field::PlaneNormal)?;
        let raw = W3::from(crate::error::flush3(normal));
        let len = raw.length();
        let point = position(point, Field::PlanePoint)?;
        let unit = raw.div(len).round();
        Ok(Self {
            point,
            normal: unit,
            offset: (raw.dot_exact(W3::from(point)) / len) as f32,
            tangents: tangent_basis(unit),
        })
    }

    /// A plane of baked data (`static` tables written by `tessera bake`): the
    /// numbers [`Plane::parts`] gives, not checked here, in a `const` context.
    /// [`crate::BakedScene::view`] checks them before any render takes the plane:
    /// the point and the normal as [`Plane::try_new`] does, the normal a unit
    /// vector to a few ulps, the tangents those of the normal, and the offset the
    /// plane's distance from the world's origin to a few ulps.
    #[must_use]
    pub const fn baked(
        point: [f32; 3],
        normal: [f32; 3],
        offset: f32,
        tangents: [[f32; 3]; 2],
    ) -> Self {
        Self {
            point: Vec3::from_array(point),
            normal: Vec3::from_array(normal),
            offset,
            tangents: (Vec3::from_array(tangents[0]), Vec3::from_array(tangents[1])),
        }
    }

    /// The numbers [`Plane::baked`] takes: the point, the unit normal, the
    /// offset along it from the world's origin and the two tangents of the uv.
    #[must_use]
    pub fn parts(&self) -> ([f32; 3], [f32; 3], f32, [[f32; 3]; 2]) {
        (
            self.point.to_array(),
            self.normal.to_array(),
            self.offset,
            [self.tangents.0.to_array(), self.tangents.1.to_array()],
        )
    }

    /// Checks a plane made by [`Plane::baked`]: what [`Plane::try_new`] makes
    /// of its point and normal, but for the offset and the normal's last
    /// bits, which `try_new` computes from the normal as the user gave it: the
    /// normal must be a unit vector to a few ulps, the tangents
    /// [`tangent_basis`] of it, and the offset the plane's distance from the
    /// world's origin, `normal . point` to a few ulps of `|point|`.
    ///
    /// `Ok(true)` when the plane holds together, `Ok(false)` when it is not
    /// what `try_new` makes of its numbers (the caller names the item).
    ///
    /// # Errors
    /// `try_new`'s error for a point or a normal it refuses.
    pub(crate) fn check_baked(&self) -> Result<bool, Error> {
        Self::try_new(self.point, self.normal)?;
        let n = W3::from(self.normal);
        let p = W3::from(self.point);
        let scale = p.x.abs() + p.y.abs() + p.z.abs();
        let slack = 8.0 * f64::from(f32::EPSILON) * (scale + f64::from(self.offset).abs());
        // |n| = 1 to 4 ulps (try_new rounds each component once).
        Ok((n.length() - 1.0).abs() <= 4.0 * f64::from(f32::EPSILON)
            && self.tangents == tangent_basis(self.normal)
            && self.offset.is_finite()
            && (n.dot(p) - f64::from(self.offset)).abs() <= slack)
    }

    /// A point of the plane.
    #[must_use]
    pub fn point(&self) -> Vec3 {
        self.point
    }

    /// The unit normal.
    #[must_use]
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// The hit time of `ray` with `0 < t < t_max`, if any. A ray parallel to the
    /// plane divides by zero and gets an infinite or NaN time, which the range test
    /// rejects: never a hit, never a NaN.
    #[inline(always)]
    pub(crate) fn hit(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        let denom = ray.dir.dot(self.normal);
        let t = (self.offset - ray.origin.dot(self.normal)) / denom;
        (t > 0.0 && t < t_max).then_some(t)
    }
}

impl Locate for Plane {
    #[inline(always)]
    fn locate(&self, ray: &Ray, hit: &Candidate) -> (Vec3, Vec3, Vec3) {
        (ray.origin + ray.dir * hit.t, self.normal, Vec3::ZERO)
    }

    #[inline(always)]
    fn error(&self, ray: &Ray, hit: &Candidate, _: Vec3, _: Vec3) -> Vec3 {
        let t = hit.t;
        let dt = ray.dir * t;
        // Error of the time, against the plane `normal . x = offset` as stored
        // (the plane the renderer defines): the numerator `offset - o.n` carries
        // gamma(4) of `|offset| + |o|.|n|` (the dot product's three roundings and
        // the difference's); the division and the denominator add gamma(4) of t.
        // The point moves along the ray by that much; the final add rounds by
        // gamma(2).
        let denom = crate::math::abs(ray.dir.dot(self.normal));
        let n = self.normal.abs();
        let num_err = gamma(4) * (crate::math::abs(self.offset) + ray.origin.abs().dot(n));
        let t_err = num_err / denom + gamma(4) * t;
        (ray.origin.abs() + dt.abs()) * gamma(2) + ray.dir.abs() * t_err
    }
}

impl Shape for Plane {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Candidate> {
        self.hit(ray, t_max).map(Candidate::at)
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.intersect(ray, t_max).is_some()
    }

    fn surface(&self, ray: &Ray, hit: &Candidate) -> Surface {
        super::surface(self, ray, hit)
    }

    /// World-unit coordinates of the point along two tangents of the plane.
    #[inline(always)]
    fn uv(&self, surface: &Surface, _hit: &Candidate) -> [f32; 2] {
        let (t, b) = self.tangents;
        let d = surface.point - self.point;
        [d.dot(t), d.dot(b)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ray::offset_origin;

    #[test]
    fn hit_from_above_and_below() {
        let p = Plane::try_new(Vec3::new(0.0, -1.0, 0.0), Vec3::Y).unwrap();
        let down = Ray::unit(Vec3::new(2.0, 3.0, 0.0), -Vec3::Y);
        let c = p.intersect(&down, f32::INFINITY).unwrap();
        assert_eq!(c.t, 4.0);
        let s = p.surface(&down, &c);
        assert_eq!(s.point, Vec3::new(2.0, -1.0, 0.0));
        assert_eq!(s.normal, Vec3::Y);
        let up = Ray::unit(Vec3::new(0.0, -3.0, 0.0), Vec3::Y);
        assert_eq!(p.intersect(&up, f32::INFINITY).unwrap().t, 2.0);
    }

    #[test]
    fn oblique_hit_matches_analytic_t() {
        let p = Plane::try_new(Vec3::ZERO, Vec3::Y).unwrap();
        let d = Vec3::new(1.0, -1.0, 0.0).try_normalize().unwrap();
        let r = Ray::unit(Vec3::new(0.0, 1.0, 0.0), d);
        let c = p.intersect(&r, f32::INFINITY).unwrap();
        assert!((c.t - core::f32::consts::SQRT_2).abs() < 1e-6);
    }

    #[test]
    fn parallel_and_receding_rays_miss_without_nan() {
        let p = Plane::try_new(Vec3::ZERO, Vec3::Y).unwrap();
        assert!(
            p.intersect(&Ray::unit(Vec3::Y, Vec3::X), f32::INFINITY)
                .is_none()
        );
        // In the plane itself: parallel, no hit, no NaN.
        assert!(
            p.intersect(&Ray::unit(Vec3::ZERO, Vec3::X), f32::INFINITY)
                .is_none()
        );
        assert!(
            p.intersect(&Ray::unit(Vec3::Y, Vec3::Y), f32::INFINITY)
                .is_none()
        );
        assert!(!p.occluded(&Ray::unit(Vec3::Y, -Vec3::Y), 0.5));
    }

    #[test]
    fn secondary_rays_from_far_hits_do_not_self_intersect() {
        let n = Vec3::new(0.3, 0.9, -0.2).try_normalize().unwrap();
        let p = Plane::try_new(Vec3::new(1234.5, -77.25, 9000.0), n).unwrap();
        let mut self_hits = 0;
        for i in 0..500 {
            let a = i as f32 * 0.731;
            let o = Vec3::new(1000.0 + a * 13.0, 500.0, 8000.0 - a * 7.0);
            let d = (Vec3::new(1234.5 + a, -77.25, 9000.0 + a * 0.5) - o)
                .try_normalize()
                .unwrap();
            let r = Ray::unit(o, d);
            let Some(c) = p.intersect(&r, f32::INFINITY) else {
                continue;
            };
            let s = p.surface(&r, &c);
            // Reflected direction leaves the surface.
            let w = d.reflect(n);
            let o2 = offset_origin(s.point, s.error, n, w);
            if p.intersect(&Ray::unit(o2, w), f32::INFINITY).is_some() {
                self_hits += 1;
            }
        }
        assert_eq!(self_hits, 0);
    }

    #[test]
    fn uv_is_in_world_units() {
        let p = Plane::try_new(Vec3::ZERO, Vec3::Z).unwrap();
        let s = Surface {
            point: Vec3::new(3.0, 4.0, 0.0),
            normal: Vec3::Z,
            error: Vec3::ZERO,
        };
        let [u, v] = p.uv(&s, &Candidate::default());
        assert!(((u * u + v * v) - 25.0).abs() < 1e-4);
    }

    #[test]
    fn invalid_input_is_rejected() {
        assert_eq!(
            Plane::try_new(Vec3::new(f32::NAN, 0.0, 0.0), Vec3::Y),
            Err(Error::NotFinite(Field::PlanePoint))
        );
        assert_eq!(
            Plane::try_new(Vec3::ZERO, Vec3::new(0.0, f32::INFINITY, 0.0)),
            Err(Error::NotFinite(Field::PlaneNormal))
        );
    }
}
