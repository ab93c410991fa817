//! Sphere: centre and radius.

use super::{Candidate, Shape, Surface};
use crate::error::{Error, Field, finite, finite3};
use crate::math::{self, gamma};
use crate::ray::Ray;
use crate::vec::Vec3;
use core::f32::consts::{FRAC_1_PI, PI};

/// A sphere of centre `center` and radius `radius > 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    center: Vec3,
    radius: f32,
}

impl Sphere {
    /// A sphere; the radius must be finite and `> 0`, the centre finite.
    ///
    /// ```
    /// use tessera::{Error, Field, Sphere, Vec3};
    /// assert!(Sphere::try_new(Vec3::ZERO, 1.0).is_ok());
    /// assert_eq!(
    ///     Sphere::try_new(Vec3::ZERO, -1.0),
    ///     Err(Error::NotPositive(Field::SphereRadius))
    /// );
    /// ```
    pub fn try_new(center: Vec3, radius: f32) -> Result<Self, Error> {
        let center = finite3(center, Field::SphereCenter)?;
        let radius = finite(radius, Field::SphereRadius)?;
        if radius <= 0.0 {
            return Err(Error::NotPositive(Field::SphereRadius));
        }
        Ok(Self { center, radius })
    }

    /// The centre.
    #[must_use]
    pub fn center(&self) -> Vec3 {
        self.center
    }

    /// The radius.
    #[must_use]
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// Both roots of `|o + t d - c|^2 = r^2`, smaller first, computed as in Ray
    /// Tracing Gems ch. 7: the discriminant from the distance of the centre to the
    /// line (no catastrophic cancellation of `b^2 - 4ac` for far spheres), and the
    /// two roots as `c/q` and `q` (no cancellation of `-b +/- sqrt(disc)`).
    fn roots(&self, ray: &Ray) -> Option<(f32, f32)> {
        let f = ray.origin - self.center;
        let b = -f.dot(ray.dir); // half of -b in the textbook form, with |d| = 1
        let l = f + ray.dir * b; // the centre-to-line vector
        let r2 = self.radius * self.radius;
        let disc = r2 - l.length_squared();
        if disc.is_nan() || disc < 0.0 {
            return None;
        }
        let c = f.length_squared() - r2;
        let q = b + math::copysign(math::sqrt(disc), b);
        if q == 0.0 {
            // b = 0 and disc = 0: a tangent ray whose origin is the touching point.
            return Some((0.0, 0.0));
        }
        let (t0, t1) = (c / q, q);
        Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
    }
}

impl Shape for Sphere {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Candidate> {
        let (t0, t1) = self.roots(ray)?;
        let t = if t0 > 0.0 && t0 < t_max {
            t0
        } else if t1 > 0.0 && t1 < t_max {
            t1
        } else {
            return None;
        };
        Some(Candidate {
            t,
            ..Candidate::default()
        })
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.intersect(ray, t_max).is_some()
    }

    fn surface(&self, ray: &Ray, hit: &Candidate) -> Surface {
        let p = ray.at(hit.t);
        // Re-project the point onto the sphere (pbrt-v4): its error is then bounded
        // by gamma(5) |p - c| instead of growing with t.
        let local = p - self.center;
        let len = local.length();
        let local = if len > 0.0 {
            local * (self.radius / len)
        } else {
            Vec3::new(0.0, self.radius, 0.0)
        };
        let point = self.center + local;
        let error = local.abs() * gamma(5) + point.abs() * gamma(1);
        Surface {
            point,
            normal: local / self.radius,
            error,
        }
    }

    fn uv_wraps(&self) -> bool {
        true
    }

    /// Longitude/latitude: `u` from `atan2(z, x)` (0 to 1 around y), `v` from the
    /// polar angle (0 at the top, +y, to 1 at the bottom).
    fn uv(&self, surface: &Surface, _hit: &Candidate) -> [f32; 2] {
        let n = surface.normal;
        let u = (math::atan2(n.z, n.x) + PI) * (0.5 * FRAC_1_PI);
        let v = math::acos(n.y) * FRAC_1_PI;
        [u, v]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(o: Vec3, d: Vec3) -> Ray {
        Ray::new(o, d.try_normalize().unwrap())
    }

    #[test]
    fn head_on_hit_has_analytic_t_point_and_normal() {
        let s = Sphere::try_new(Vec3::new(0.0, 0.0, -5.0), 1.0).unwrap();
        let r = ray(Vec3::ZERO, -Vec3::Z);
        let c = s.intersect(&r, f32::INFINITY).unwrap();
        assert_eq!(c.t, 4.0);
        let sf = s.surface(&r, &c);
        assert_eq!(sf.point, Vec3::new(0.0, 0.0, -4.0));
        assert_eq!(sf.normal, Vec3::Z);
        assert!(sf.error.z > 0.0);
    }

    #[test]
    fn offset_ray_hits_at_the_analytic_chord() {
        // Ray at height h = 0.6 from the axis: t = 5 - sqrt(1 - 0.36) = 4.2.
        let s = Sphere::try_new(Vec3::new(0.0, 0.0, -5.0), 1.0).unwrap();
        let r = ray(Vec3::new(0.6, 0.0, 0.0), -Vec3::Z);
        let c = s.intersect(&r, f32::INFINITY).unwrap();
        assert!((c.t - 4.2).abs() < 1e-6, "{}", c.t);
        let n = s.surface(&r, &c).normal;
        assert!((n - Vec3::new(0.6, 0.0, 0.8)).length() < 1e-6);
    }

    #[test]
    fn misses_and_t_max() {
        let s = Sphere::try_new(Vec3::new(0.0, 0.0, -5.0), 1.0).unwrap();
        assert!(
            s.intersect(&ray(Vec3::ZERO, Vec3::Z), f32::INFINITY)
                .is_none()
        );
        assert!(
            s.intersect(&ray(Vec3::new(1.01, 0.0, 0.0), -Vec3::Z), f32::INFINITY)
                .is_none()
        );
        assert!(s.intersect(&ray(Vec3::ZERO, -Vec3::Z), 4.0).is_none());
        assert!(!s.occluded(&ray(Vec3::ZERO, -Vec3::Z), 3.9));
        assert!(s.occluded(&ray(Vec3::ZERO, -Vec3::Z), 4.1));
    }

    #[test]
    fn inside_origin_hits_the_far_side_with_outward_normal() {
        let s = Sphere::try_new(Vec3::ZERO, 2.0).unwrap();
        let r = ray(Vec3::new(0.5, 0.0, 0.0), Vec3::X);
        let c = s.intersect(&r, f32::INFINITY).unwrap();
        assert_eq!(c.t, 1.5);
        assert_eq!(s.surface(&r, &c).normal, Vec3::X);
    }

    #[test]
    fn grazing_ray_is_tangent_not_nan() {
        let s = Sphere::try_new(Vec3::ZERO, 1.0).unwrap();
        // Exactly tangent at (1, 0, 0): disc = 0, a double root at t = 5.
        let r = ray(Vec3::new(1.0, 0.0, 5.0), -Vec3::Z);
        let c = s.intersect(&r, f32::INFINITY).unwrap();
        assert_eq!(c.t, 5.0);
        // Just outside misses.
        let r = ray(Vec3::new(1.000_001, 0.0, 5.0), -Vec3::Z);
        assert!(s.intersect(&r, f32::INFINITY).is_none());
    }

    #[test]
    fn far_sphere_hit_miss_matches_f64() {
        // Rays at 1000 radii, at offsets clearly inside/outside (|h - r| > 1e-3 r).
        let s = Sphere::try_new(Vec3::new(0.0, 0.0, -1000.0), 1.0).unwrap();
        for i in 0..2000 {
            let h = i as f32 * 0.001 + 0.0005; // 0.0005 .. 2.0
            if (h - 1.0).abs() <= 1e-3 {
                continue;
            }
            let r = ray(Vec3::new(h, 0.0, 0.0), -Vec3::Z);
            let hit = s.intersect(&r, f32::INFINITY);
            assert_eq!(hit.is_some(), h < 1.0, "h = {h}");
            if let Some(c) = hit {
                let exact = 1000.0 - (1.0 - (h as f64).powi(2)).sqrt();
                assert!((c.t as f64 - exact).abs() <= 4.0 * (exact * f32::EPSILON as f64));
            }
        }
    }

    #[test]
    fn uv_covers_the_poles_and_equator() {
        let s = Sphere::try_new(Vec3::ZERO, 1.0).unwrap();
        let top = Surface {
            point: Vec3::Y,
            normal: Vec3::Y,
            error: Vec3::ZERO,
        };
        assert_eq!(s.uv(&top, &Candidate::default())[1], 0.0);
        let eq = Surface {
            point: -Vec3::X,
            normal: -Vec3::X,
            error: Vec3::ZERO,
        };
        let [u, v] = s.uv(&eq, &Candidate::default());
        assert!((v - 0.5).abs() < 1e-6 && (u - 1.0).abs() < 1e-6 || u.abs() < 1e-6);
    }

    #[test]
    fn invalid_input_is_rejected() {
        assert_eq!(
            Sphere::try_new(Vec3::ZERO, 0.0),
            Err(Error::NotPositive(Field::SphereRadius))
        );
        assert_eq!(
            Sphere::try_new(Vec3::ZERO, f32::NAN),
            Err(Error::NotFinite(Field::SphereRadius))
        );
        assert_eq!(
            Sphere::try_new(Vec3::new(f32::INFINITY, 0.0, 0.0), 1.0),
            Err(Error::NotFinite(Field::SphereCenter))
        );
    }
}
