//! Sphere: centre and radius.

use super::wide::{REACH, W3, gamma64};
use super::{Candidate, Locate, Shape, Surface};
use crate::error::{Error, Field, finite, length, position};
use crate::math::{self, gamma};
use crate::ray::Ray;
use crate::vec::Vec3;
use core::f32::consts::{FRAC_1_PI, PI};

/// `(1 - gamma(3))^2`: the shrink factor of the cheap miss test, squared.
const SHRINK2: f32 = (1.0 - gamma(3)) * (1.0 - gamma(3));

/// A sphere of centre `center` and radius `radius > 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Sphere {
    center: Vec3,
    radius: f32,
}

impl Sphere {
    /// A sphere; the centre's components must be finite and within
    /// [`crate::error::MAX_EXTENT`], the radius within `[`[`crate::error::MIN_LENGTH`]`,
    /// `[`crate::error::MAX_EXTENT`]`]`.
    ///
    /// ```
    /// use tessera_core::{Error, error::Field, geometry::Sphere, Vec3};
    /// assert!(Sphere::try_new(Vec3::ZERO, 1.0).is_ok());
    /// assert_eq!(
    ///     Sphere::try_new(Vec3::ZERO, -1.0),
    ///     Err(Error::NotPositive(Field::SphereRadius))
    /// );
    /// ```
    pub fn try_new(center: Vec3, radius: f32) -> Result<Self, Error> {
        let center = position(center, Field::SphereCenter)?;
        let radius = finite(radius, Field::SphereRadius)?;
        if radius <= 0.0 {
            return Err(Error::NotPositive(Field::SphereRadius));
        }
        // r^2 must be a normal f32 (and squared distances finite): the supported
        // range of scene lengths, see `MIN_LENGTH`.
        let radius = length(radius, Field::SphereRadius)?;
        Ok(Self { center, radius })
    }

    /// A sphere of baked data (`static` tables written by `tessera bake`), not
    /// checked here, in a `const` context: [`crate::BakedScene::view`] checks it
    /// against [`Sphere::try_new`] before any render takes it.
    #[must_use]
    pub const fn baked(center: [f32; 3], radius: f32) -> Self {
        Self {
            center: Vec3::new(center[0], center[1], center[2]),
            radius,
        }
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

    /// The hit time of `ray` with `0 < t < t_max`, if any: the cheap miss test,
    /// inlined where the renderer loops over spheres, then the roots out of line.
    ///
    /// Both roots of `|o + t d - c|^2 = r^2` come from Ray Tracing Gems ch. 7 (the
    /// discriminant from the distance of the centre to the line, no cancellation of
    /// `b^2 - 4ac`), made exact enough for far spheres.
    ///
    /// Why more than RTG: the centre-to-line vector `l = f + d (-f.d)` (`f = o - c`)
    /// is the difference of two vectors of length `|f|`, so in plain `f32` it is off
    /// by a few ulps of `|f|`. A sphere `10^5` radii away then has its silhouette
    /// blurred by a few percent of its radius, and near-grazing hit times by 10+ ulps.
    /// So this is a filtered computation: the plain `f32` test runs first and rejects
    /// the rays that miss by more than its rounding error bound (most rays); the
    /// others get `l` from error-free transformations ([`two_diff`], [`split`]),
    /// which leave only the rounding of `l` itself, a few ulps of `r`.
    #[inline(always)]
    pub(crate) fn hit(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        let f = ray.origin - self.center;
        let b = -f.dot(ray.dir);
        let l = f + ray.dir * b;
        // |l - l_exact| <= ~14 u |f|_max, plus (for |d|^2 = 1 +- 4u) the line's own
        // distance differing from |l| by <= 7 u |f|_max near the silhouette: gamma(25)
        // covers both. A certain miss is |l| (1 - gamma(3)) > r + err, compared
        // squared (no square root on the common path; within the supported range of
        // lengths the squares cannot overflow). A NaN (from a NaN or infinite input)
        // fails the comparison too: one compare for both.
        //
        // Here with the sum of the components instead of the largest (fewer
        // instructions than two compare-selects, and never smaller, rounding being
        // monotone): this rejects a subset of what the bound with the largest
        // rejects, and `roots_near` applies that one to the rest, so the decisions
        // are exactly those of the bound with the largest.
        let fa = f.abs();
        let loose = self.radius + gamma(25) * (fa.x + fa.y + fa.z);
        let l2 = l.length_squared();
        let within = l2 * SHRINK2 <= loose * loose;
        if !within {
            return None;
        }
        self.roots_near(ray, t_max, b, l2)
    }

    /// The rest of [`Sphere::hit`] for a ray that the cheap test could not reject:
    /// out of line, so that the loops over spheres stay small.
    #[inline(never)]
    fn roots_near(&self, ray: &Ray, t_max: f32, b: f32, l2: f32) -> Option<f32> {
        // `f` again rather than passed: the loop over spheres then stores nothing.
        let f = ray.origin - self.center;
        let err = gamma(25) * f.abs().max_element();
        let reach = self.radius + err;
        let within = l2 * SHRINK2 <= reach * reach;
        if !within {
            return None;
        }
        let (t0, t1) = self.roots(ray, f, b, l2, err)?;
        if t0 > 0.0 && t0 < t_max {
            Some(t0)
        } else if t1 > 0.0 && t1 < t_max {
            Some(t1)
        } else {
            None
        }
    }

    /// Both roots, smaller first, for a ray that passed the cheap miss test.
    fn roots(&self, ray: &Ray, f: Vec3, b: f32, l2: f32, err: f32) -> Option<(f32, f32)> {
        let r = self.radius;
        // Well inside the silhouette (the line passes within 0.8 r of the centre,
        // with room for the error of l) and with the origin well off the surface
        // (|c| = ||f|^2 - r^2| >= r^2/4): the discriminant is at least 0.36 r^2,
        // nothing cancels, and Ray Tracing Gems' roots c/q and q are accurate (the
        // extremes battery measures at most 2.66 ulp in t). Rays
        // near the silhouette, and rays leaving or entering the sphere's own surface
        // (c near 0: the near root would be rounding noise), take the refinement.
        let half = 0.8 * r - err;
        let c = f.length_squared() - r * r;
        if half > 0.0 && l2 < half * half && math::abs(c) >= 0.25 * r * r {
            let disc = r * r - l2;
            let q = b + math::copysign(math::sqrt(disc), b);
            if q != 0.0 {
                let (t0, t1) = (c / q, q);
                return Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) });
            }
        }
        let (t0, t1) = self.refined_roots(ray)?;
        // The refined roots are still off by a few ulps of the radius (and of the
        // distance to the centre). A root small beside the radius is then mostly
        // error: a ground of radius 10^7 seen from a few units. Those come from
        // `f64`. (The fast path above never needs it: its origin is at least r/8
        // off the surface, so its roots are not small beside r.)
        if self.huge_for(ray, math::min(math::abs(t0), math::abs(t1))) {
            return self.wide_roots(ray, (t0, t1));
        }
        Some((t0, t1))
    }

    /// True when a hit at time `t` of `ray` is so near beside the radius (with
    /// the origin's magnitude: what the ray's own point is accurate to) that the
    /// `f32` roots and the re-projected point lose it: then the roots come from
    /// `f64` and the point is the ray's (see [`super::wide`]).
    #[inline(always)]
    fn huge_for(&self, ray: &Ray, t: f32) -> bool {
        // The first test alone settles the common case (t not small beside r).
        let o = ray.origin.abs();
        self.radius > REACH * t && self.radius > REACH * (t + o.x + o.y + o.z)
    }

    /// Both roots in `f64`, smaller first: Ray Tracing Gems' form (the
    /// discriminant from the centre's distance to the line, the near root as
    /// `c / q`), whose roundings are at `2^-53` of the radius and the distances.
    /// `None` when the `f64` discriminant says the ray misses (it is the more
    /// accurate); the `f32` roots `near` when the `f64` ones are not finite.
    #[cold]
    #[inline(never)]
    fn wide_roots(&self, ray: &Ray, near: (f32, f32)) -> Option<(f32, f32)> {
        let (d, r) = (W3::from(ray.dir), f64::from(self.radius));
        let f = W3::from(ray.origin).sub(W3::from(self.center));
        let dd = d.dot(d);
        let b = -f.dot(d);
        let tc = b / dd;
        let l = W3::new(f.x + d.x * tc, f.y + d.y * tc, f.z + d.z * tc);
        let disc = dd * (r * r - l.dot(l));
        if disc.is_nan() || disc < 0.0 {
            return None;
        }
        let q = b + math::sqrt64(disc).copysign(b);
        let c = f.dot(f) - r * r;
        let (t0, t1) = ((c / q) as f32, (q / dd) as f32);
        if !(t0.is_finite() && t1.is_finite()) {
            return Some(near);
        }
        Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
    }

    /// The roots with `l` computed almost exactly: `f = o - c` as an unevaluated sum
    /// `fh + fl` (exact), each product `d_i b` as `p + e` (exact, Dekker), so
    /// `l_i = (fh_i + p_i) + (fl_i + e_i)` is rounded once at its own magnitude. `b`
    /// itself only approximates the closest approach; one Gram-Schmidt step removes
    /// the component of `l` along `d` that its error leaves (and that a direction
    /// not exactly of unit length leaves). Pure IEEE arithmetic (Rust never contracts
    /// to FMA), so the host and the chip compute the same bits; every step is
    /// homogeneous, so a scene scaled by a power of two gives scaled roots.
    fn refined_roots(&self, ray: &Ray) -> Option<(f32, f32)> {
        let (o, c, d) = (ray.origin, self.center, ray.dir);
        let (fx, ex) = two_diff(o.x, c.x);
        let (fy, ey) = two_diff(o.y, c.y);
        let (fz, ez) = two_diff(o.z, c.z);
        let b = -Vec3::new(fx, fy, fz).dot(d);
        let (bh, bl) = split(b);
        let exact = |fh: f32, fl: f32, di: f32| {
            let p = di * b;
            let (dh, dl) = split(di);
            let e = ((dh * bh - p) + dh * bl + dl * bh) + dl * bl;
            (fh + p) + (fl + e)
        };
        let l = Vec3::new(exact(fx, ex, d.x), exact(fy, ey, d.y), exact(fz, ez, d.z));
        let dd = d.length_squared();
        let k = l.dot(d) / dd;
        let l = l - d * k;
        let disc = self.radius * self.radius - l.length_squared();
        if disc.is_nan() || disc < 0.0 {
            return None;
        }
        // The closest approach is at t = b - k; the roots are half a chord either side.
        let tc = b - k;
        let s = math::sqrt(disc / dd);
        Some((tc - s, tc + s))
    }
}

impl Sphere {
    /// The error bound of a point `x` placed on the ray rather than on the sphere
    /// (see [`Sphere::huge_for`]): its distance from the sphere, `|x - c| - r`
    /// measured in `f64` as `(|x - c|^2 - r^2) / (|x - c| + r)` (no cancellation
    /// but the exact difference) with a bound on that measurement's own error,
    /// along the normal, so that `offset_origin` moves the point across the
    /// surface by at least that much.
    #[inline(never)]
    fn distance(&self, x: Vec3) -> Vec3 {
        let r = f64::from(self.radius);
        let w = W3::from(x).sub(W3::from(self.center));
        let (w2, len) = (w.dot(w), w.length());
        // w is within gamma64(1) of x - c per component, so w2 within gamma64(5)
        // of the true square (r^2 is exact: 48 bits); the difference rounds once
        // more (u of itself), the square root and the sum `len + r` are within
        // gamma64(5) of the true denominator, the division rounds once: the
        // distance is within gamma64(5) of w2 / (len + r) plus gamma64(8) of itself.
        let dist = (w2 - r * r) / (len + r);
        let slack = gamma64(5) * w2 / (len + r) + gamma64(8) * dist.abs();
        w.scaled_up((dist.abs() + slack) / len)
    }
}

/// `v` normalised, or `+y` (for a huge sphere's hit, see `Sphere::locate`): out
/// of line and cold, its square root and division kept out of every loop.
#[cold]
#[inline(never)]
fn unit_or_up(v: Vec3) -> Vec3 {
    v.normalize_or(Vec3::Y)
}

/// `a - b` as `(s, e)` with `s = fl(a - b)` and `s + e = a - b` exactly (Knuth's
/// TwoSum: six operations, no branch).
#[inline]
fn two_diff(a: f32, b: f32) -> (f32, f32) {
    let s = a - b;
    let bb = s - a;
    (s, (a - (s - bb)) - (b + bb))
}

/// Veltkamp's split: `a = hi + lo` exactly, each half with at most 12 significant
/// bits, so the product of two halves is exact in `f32`.
#[inline]
fn split(a: f32) -> (f32, f32) {
    let c = 4097.0 * a; // 2^12 + 1
    let hi = c - (c - a);
    (hi, a - hi)
}

/// A sphere is closed and convex.
impl super::Kinded for Sphere {
    const FLAT: bool = false;

    fn check_baked(&self) -> Result<bool, crate::error::Error> {
        Ok(Self::try_new(self.center(), self.radius())? == *self)
    }

    fn scaled(&self, f: f32) -> Result<Self, crate::error::Error> {
        Self::try_new(self.center() * f, self.radius() * f)
    }

    fn girth(&self) -> super::Girth {
        super::Girth::Ball {
            center: self.center(),
            radius: self.radius(),
            reach: self.radius(),
        }
    }

    #[inline(always)]
    fn extent(&self) -> super::Extent {
        super::Extent::Ball {
            center: self.center(),
            radius: self.radius(),
        }
    }

    #[inline(always)]
    fn search<'r, V: super::Visit<'r, Self>>(v: &mut V) -> Option<(usize, super::Candidate)> {
        // `none` first, though the loop of an empty list does nothing: the
        // camera rays of a tile without spheres then skip the loop's set-up.
        if v.none() {
            return None;
        }
        let ray = v.ray();
        v.each(|s, t| s.hit(ray, t).map(super::Candidate::at))
    }
}

impl Locate for Sphere {
    #[inline(always)]
    fn locate(&self, ray: &Ray, hit: &Candidate) -> (Vec3, Vec3, Vec3) {
        if self.huge_for(ray, hit.t) {
            // The re-projected point would be off by ulps of the centre and the
            // radius, the ray's is off by ulps of what the ray spans
            // ([`Sphere::distance`] then measures how far from the sphere it is).
            let p = ray.at(hit.t);
            let local = p - self.center;
            return (p, unit_or_up(local), local);
        }
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
        (self.center + local, local / self.radius, local)
    }

    #[inline(always)]
    fn error(&self, ray: &Ray, hit: &Candidate, point: Vec3, local: Vec3) -> Vec3 {
        if self.huge_for(ray, hit.t) {
            return self.distance(point);
        }
        local.abs() * gamma(5) + point.abs() * gamma(1)
    }
}

impl Shape for Sphere {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Candidate> {
        self.hit(ray, t_max).map(Candidate::at)
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.intersect(ray, t_max).is_some()
    }

    fn surface(&self, ray: &Ray, hit: &Candidate) -> Surface {
        super::surface(self, ray, hit)
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
        Ray::unit(o, d.try_normalize().unwrap())
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
    fn a_ray_built_with_a_long_direction_hits_like_every_other_kind() {
        // A direction of length 2 would make the sphere's half-`b` quadratic report
        // a miss while the plane returns the parametric t. `Ray::new` normalises it.
        let r = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, -2.0)).unwrap();
        let s = Sphere::try_new(Vec3::new(0.0, 0.0, -5.0), 1.0).unwrap();
        let p = crate::geometry::Plane::try_new(Vec3::new(0.0, 0.0, -4.0), Vec3::Z).unwrap();
        assert_eq!(s.intersect(&r, f32::INFINITY).map(|c| c.t), Some(4.0));
        assert_eq!(p.intersect(&r, f32::INFINITY).map(|c| c.t), Some(4.0));
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

    /// The texture coordinates of a unit normal.
    fn uv_of(s: &Sphere, n: Vec3) -> [f32; 2] {
        let sf = Surface {
            point: s.center() + n * s.radius(),
            normal: n,
            error: Vec3::ZERO,
        };
        s.uv(&sf, &Candidate::default())
    }

    /// How far `v` may be from 0 at the top pole. Exact backend: `acos(1) = 0`.
    /// fast-math: micromath's `acos(1)` is the arc tangent of its bit-trick square
    /// root of 0, 7.6e-20 rad, so `v` = 2.4e-20 (measured): harmless (no texture
    /// tells it from 0), but not 0.
    const POLE_V: f32 = if cfg!(feature = "fast-math") {
        1e-19
    } else {
        0.0
    };

    #[test]
    fn uv_covers_the_poles_and_equator() {
        let s = Sphere::try_new(Vec3::ZERO, 1.0).unwrap();
        let v_top = uv_of(&s, Vec3::Y)[1];
        assert!(
            (0.0..=POLE_V).contains(&v_top),
            "v at the top pole {v_top:e}"
        );
        // The bottom pole: v = fl(pi) * fl(1/pi), 1 within an ulp (0.99999994 with
        // libm's acos).
        let v_bottom = uv_of(&s, -Vec3::Y)[1];
        assert!(
            (1.0 - v_bottom).abs() <= f32::EPSILON,
            "v at the bottom {v_bottom}"
        );
        // On the equator at -x: v = 1/2, u at the seam (1 or 0).
        let [u, v] = uv_of(&s, -Vec3::X);
        assert!((v - 0.5).abs() < 1e-6, "v {v}");
        assert!((u - 1.0).abs() < 1e-6 || u.abs() < 1e-6, "u {u}");
        // At +x, +z and -z: a half, three quarters and a quarter turn.
        for (n, want) in [(Vec3::X, 0.5), (Vec3::Z, 0.75), (-Vec3::Z, 0.25)] {
            let [u, v] = uv_of(&s, n);
            assert!(
                (u - want).abs() < 1e-6 && (v - 0.5).abs() < 1e-6,
                "{n:?}: {u} {v}"
            );
        }
    }

    /// `u` and `v` over the whole sphere against `f64` (of the same `f32` normal).
    /// Exact backend (libm's `atan2f` and `acosf`, within an ulp): measured 1.1e-7
    /// in `u` and 1.0e-7 in `v` (the last bits of the products by `1/pi`). fast-math (micromath): its `atan2` is off by up to 2.8e-3 rad
    /// and its `acos`, which takes micromath's 5 % square root, by up to 2.9e-2 rad
    /// (at 0.707): measured 4.5e-4 in `u` and 9.2e-3 in `v` (a checker of 8 bands
    /// from pole to pole shifts its edges by up to 7 % of a band). The bounds are
    /// those, rounded up; anything beyond is a fault of the backend.
    #[test]
    fn uv_matches_f64_within_the_backends_bound() {
        let (u_bound, v_bound) = if cfg!(feature = "fast-math") {
            (4.7e-4, 9.5e-3)
        } else {
            (1.2e-7, 1.2e-7)
        };
        let s = Sphere::try_new(Vec3::new(3.0, -1.0, 2.0), 2.5).unwrap();
        let (mut du, mut dv) = (0.0f64, 0.0f64);
        for i in 0..=300 {
            let theta = core::f64::consts::PI * f64::from(i) / 300.0;
            for j in 0..600 {
                let phi = core::f64::consts::TAU * (f64::from(j) + 0.37) / 600.0;
                let n = Vec3::new(
                    (theta.sin() * phi.cos()) as f32,
                    theta.cos() as f32,
                    (theta.sin() * phi.sin()) as f32,
                );
                let [u, v] = uv_of(&s, n);
                let (x, y, z) = (f64::from(n.x), f64::from(n.y), f64::from(n.z));
                let eu = (z.atan2(x) + core::f64::consts::PI) / core::f64::consts::TAU;
                let ev = y.clamp(-1.0, 1.0).acos() / core::f64::consts::PI;
                // u wraps: 0 and 1 are the same seam.
                let d = (f64::from(u) - eu).abs();
                du = du.max(d.min(1.0 - d));
                dv = dv.max((f64::from(v) - ev).abs());
            }
        }
        assert!(du <= u_bound, "u off by {du:e} > {u_bound:e}");
        assert!(dv <= v_bound, "v off by {dv:e} > {v_bound:e}");
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
        // The supported range of lengths: 2^-52 to 2^60, both included.
        let (lo, hi) = (crate::error::MIN_LENGTH, crate::error::MAX_EXTENT);
        assert!(Sphere::try_new(Vec3::splat(hi), lo).is_ok());
        assert!(Sphere::try_new(Vec3::ZERO, hi).is_ok());
        for (c, r) in [
            (Vec3::ZERO, math::next_down(lo)),
            (Vec3::ZERO, math::next_up(hi)),
            (Vec3::new(0.0, -math::next_up(hi), 0.0), 1.0),
        ] {
            assert!(
                matches!(Sphere::try_new(c, r), Err(Error::OutOfRange { .. })),
                "{c:?} {r}"
            );
        }
    }
}
