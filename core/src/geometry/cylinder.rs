//! Finite cylinder: the tube of a radius around the segment from a base centre
//! to a top centre, optionally closed by its two end caps.
//!
//! The tests run in the cylinder's own frame (pbrt-v4's cylinder, along the
//! local `z`): the ray is carried into the frame of the axis `w` and its
//! tangents `u`, `v` ([`tangent_basis`]`(w)`), the side is the quadratic
//! `x^2 + y^2 = r^2` for `0 <= z <= h`, and each cap the plane `z = 0` or
//! `z = h` within the radius. A hit point is re-projected onto the side (or the
//! cap's plane) in that frame and carried back, with an error bound that covers
//! both the re-projection and the frame's own roundings. A side much larger than
//! the ray's reach (a tube of radius `10^6` seen from a few units) takes its
//! roots from `f64` and its point on the ray, as the sphere does (see `wide`).

use super::wide::{REACH, W3, gamma64};
use super::{Candidate, Extent, Locate, Shape, Surface, tangent_basis};
use crate::error::{Error, Field, length, position};
use crate::math::{self, gamma};
use crate::ray::Ray;
use crate::vec::Vec3;
use core::f32::consts::{FRAC_1_PI, PI};

/// Where a cylinder's hit lies ([`Candidate::face`]).
const SIDE: u8 = 0;
/// The cap at the base (`z = 0`).
const BASE: u8 = 1;
/// The cap at the top (`z = h`).
const TOP: u8 = 2;

/// A finite cylinder of radius `radius > 0` around the segment from `base` to
/// `top`, open or closed by two caps.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Cylinder {
    base: Vec3,
    top: Vec3,
    radius: f32,
    capped: bool,
    /// The unit axis, from the base to the top (rounded from `f64`).
    axis: Vec3,
    /// The tangents of [`tangent_basis`]`(axis)`: the frame's `x` and `y`.
    tangents: (Vec3, Vec3),
    /// The height: `(top - base) . axis`, from `f64`.
    height: f32,
}

impl Cylinder {
    /// A cylinder; the centres' components must be finite and within
    /// [`crate::error::MAX_EXTENT`], the radius and the height (the distance
    /// of the centres) within `[`[`crate::error::MIN_LENGTH`]`,
    /// `[`crate::error::MAX_EXTENT`]`]`.
    ///
    /// ```
    /// use tessera_core::{Error, error::Field, geometry::Cylinder, Vec3};
    /// assert!(Cylinder::try_new(Vec3::ZERO, Vec3::Y, 0.5, true).is_ok());
    /// assert_eq!(
    ///     Cylinder::try_new(Vec3::ZERO, Vec3::ZERO, 0.5, true),
    ///     Err(Error::ZeroLength(Field::CylinderTop))
    /// );
    /// ```
    pub fn try_new(base: Vec3, top: Vec3, radius: f32, capped: bool) -> Result<Self, Error> {
        let base = position(base, Field::CylinderBase)?;
        let top = position(top, Field::CylinderTop)?;
        let radius = crate::error::finite(radius, Field::CylinderRadius)?;
        if radius <= 0.0 {
            return Err(Error::NotPositive(Field::CylinderRadius));
        }
        let radius = length(radius, Field::CylinderRadius)?;
        // The axis and the height from `f64` (the difference of two `f32` is
        // exact there), each rounded once.
        let d = W3::from(top).sub(W3::from(base));
        let h = d.length();
        if h == 0.0 {
            return Err(Error::ZeroLength(Field::CylinderTop));
        }
        let height = length(h as f32, Field::CylinderTop)?;
        let axis = crate::error::flush3(d.div(h).round());
        Ok(Self {
            base,
            top,
            radius,
            capped,
            axis,
            tangents: tangent_basis(axis),
            height,
        })
    }

    /// A cylinder of baked data (`static` tables written by `tessera bake`),
    /// not checked here, in a `const` context: [`crate::BakedScene::view`]
    /// checks it against [`Cylinder::try_new`] before any render takes it.
    #[must_use]
    #[allow(clippy::too_many_arguments)]
    pub const fn baked(
        base: [f32; 3],
        top: [f32; 3],
        radius: f32,
        capped: bool,
        axis: [f32; 3],
        tangents: [[f32; 3]; 2],
        height: f32,
    ) -> Self {
        const fn v(a: [f32; 3]) -> Vec3 {
            Vec3::new(a[0], a[1], a[2])
        }
        Self {
            base: v(base),
            top: v(top),
            radius,
            capped,
            axis: v(axis),
            tangents: (v(tangents[0]), v(tangents[1])),
            height,
        }
    }

    /// The centre of the base.
    #[must_use]
    pub fn base(&self) -> Vec3 {
        self.base
    }

    /// The centre of the top.
    #[must_use]
    pub fn top(&self) -> Vec3 {
        self.top
    }

    /// The radius.
    #[must_use]
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// Whether the two caps close it.
    #[must_use]
    pub fn capped(&self) -> bool {
        self.capped
    }

    /// What `tessera bake` writes after the numbers given: the unit axis, the
    /// frame's tangents and the height.
    #[must_use]
    pub fn parts(&self) -> ([f32; 3], [[f32; 3]; 2], f32) {
        (
            self.axis.to_array(),
            [self.tangents.0.to_array(), self.tangents.1.to_array()],
            self.height,
        )
    }

    /// `v` in the cylinder's frame (a direction: no translation).
    #[inline(always)]
    fn local(&self, v: Vec3) -> Vec3 {
        Vec3::new(
            v.dot(self.tangents.0),
            v.dot(self.tangents.1),
            v.dot(self.axis),
        )
    }

    /// The point of local coordinates `q` in the world.
    #[inline(always)]
    fn world(&self, q: Vec3) -> Vec3 {
        self.base + self.tangents.0 * q.x + self.tangents.1 * q.y + self.axis * q.z
    }

    /// The nearest hit of `ray` with `0 < t < t_max`: the side's two roots and
    /// the caps', the nearest in range.
    #[inline(never)]
    fn hit(&self, ray: &Ray, t_max: f32) -> Option<Candidate> {
        let o = self.local(ray.origin - self.base);
        let d = self.local(ray.dir);
        let mut best: Option<Candidate> = None;
        let mut t_best = t_max;
        // The side.
        if let Some((t0, t1)) = self.side_roots(ray, o, d) {
            for t in [t0, t1] {
                if t > 0.0 && t < t_best {
                    let z = o.z + d.z * t;
                    if self.within_height(z, o.z, d.z, t) {
                        t_best = t;
                        best = Some(Candidate {
                            face: SIDE,
                            ..Candidate::at(t)
                        });
                        break;
                    }
                }
            }
        }
        // The caps: `z = 0` and `z = h`, within the radius.
        if self.capped && d.z != 0.0 {
            for (face, z) in [(BASE, 0.0), (TOP, self.height)] {
                let t = (z - o.z) / d.z;
                if t > 0.0 && t < t_best {
                    let (x, y) = (o.x + d.x * t, o.y + d.y * t);
                    // Within the radius and the roundings of `x`, `y` (so that
                    // no ray slips between the cap and the side).
                    let slack = gamma(5)
                        * (math::abs(o.x) + math::abs(o.y) + t * (math::abs(d.x) + math::abs(d.y)))
                        + gamma(4) * self.radius;
                    let reach = self.radius + slack;
                    if x * x + y * y <= reach * reach {
                        t_best = t;
                        best = Some(Candidate {
                            face,
                            ..Candidate::at(t)
                        });
                    }
                }
            }
        }
        best
    }

    /// Whether a side hit at local height `z` lies between the caps: strictly
    /// for an open tube, within its rounding for a closed one (so that no ray
    /// slips between the side and a cap along the rim).
    #[inline(always)]
    fn within_height(&self, z: f32, oz: f32, dz: f32, t: f32) -> bool {
        let slack = if self.capped {
            gamma(4) * (math::abs(oz) + math::abs(dz * t) + self.height)
        } else {
            0.0
        };
        z >= -slack && z <= self.height + slack
    }

    /// The side's two roots (smaller first) for the local origin `o` and
    /// direction `d`, or `None` when the ray misses the infinite tube or runs
    /// along its axis. A root that is within its rounding of zero (the ray
    /// starts on the side: a secondary ray leaving it) is returned as zero.
    #[inline]
    fn side_roots(&self, ray: &Ray, o: Vec3, d: Vec3) -> Option<(f32, f32)> {
        let a = d.x * d.x + d.y * d.y;
        // A NaN fails too.
        if a.is_nan() || a <= 0.0 {
            return None;
        }
        let r = self.radius;
        if self.huge_for(ray, o) {
            return self.wide_roots(ray);
        }
        // pbrt-v4's discriminant: the distance `l` of the axis from the line's
        // closest approach, `r^2 - l^2` as `(r - l)(r + l)`, with no
        // cancellation of `b^2 - 4ac`.
        let b = -(o.x * d.x + o.y * d.y);
        let tc = b / a;
        let (vx, vy) = (o.x + d.x * tc, o.y + d.y * tc);
        let l = math::sqrt(vx * vx + vy * vy);
        if l.is_nan() || l > r {
            return None;
        }
        let disc = a * (r - l) * (r + l);
        let q = b + math::copysign(math::sqrt(disc), b);
        let c = o.x * o.x + o.y * o.y - r * r;
        // `c` is the origin's `x^2 + y^2 - r^2`: within its rounding of zero,
        // the origin is on the side and that root is the side it leaves.
        let c_err = gamma(4) * (o.x * o.x + o.y * o.y + r * r);
        let t0 = if math::abs(c) <= c_err || q == 0.0 {
            0.0
        } else {
            c / q
        };
        let t1 = if q == 0.0 { tc } else { q / a };
        Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
    }

    /// True when the side is so large beside the ray's reach (the origin's
    /// distance from the side, `o` its local coordinates, and the origin's
    /// magnitude) that `f32` cannot place the ray against it: its `x^2 + y^2 -
    /// r^2` and its roots lose the distance in ulps of the radius. Then the
    /// roots come from `f64` and the point is the ray's (as the sphere's, see
    /// `wide`). The test's own rounding is a few ulps of the radius, far below
    /// the `r / REACH` it compares with.
    #[inline(always)]
    fn huge_for(&self, ray: &Ray, o: Vec3) -> bool {
        let w = ray.origin.abs();
        let reach = w.x + w.y + w.z;
        self.radius > REACH * reach
            && self.radius
                > REACH * (reach + math::abs(math::sqrt(o.x * o.x + o.y * o.y) - self.radius))
    }

    /// The side's roots in `f64`, smaller first, a root within the rounding of
    /// zero as zero; `None` when the `f64` discriminant says the ray misses.
    #[cold]
    #[inline(never)]
    fn wide_roots(&self, ray: &Ray) -> Option<(f32, f32)> {
        let f = W3::from(ray.origin).sub(W3::from(self.base));
        let (u, v) = (W3::from(self.tangents.0), W3::from(self.tangents.1));
        let d = W3::from(ray.dir);
        let (ox, oy) = (f.dot(u), f.dot(v));
        let (dx, dy) = (d.dot(u), d.dot(v));
        let r = f64::from(self.radius);
        let a = dx * dx + dy * dy;
        let b = -(ox * dx + oy * dy);
        let tc = b / a;
        let (vx, vy) = (ox + dx * tc, oy + dy * tc);
        let l = math::sqrt64(vx * vx + vy * vy);
        let disc = a * (r - l) * (r + l);
        if disc.is_nan() || disc < 0.0 {
            return None;
        }
        let q = b + math::sqrt64(disc).copysign(b);
        let c = ox * ox + oy * oy - r * r;
        let c_err = gamma64(8) * (ox * ox + oy * oy + r * r);
        let t0 = if c.abs() <= c_err || q == 0.0 {
            0.0
        } else {
            c / q
        };
        let t1 = if q == 0.0 { tc } else { q / a };
        let (t0, t1) = (t0 as f32, t1 as f32);
        if !(t0.is_finite() && t1.is_finite()) {
            return None;
        }
        Some(if t0 <= t1 { (t0, t1) } else { (t1, t0) })
    }

    /// The distance of `x` from the side, along the side's normal there,
    /// measured in `f64` with a bound on its own error: the error bound of a
    /// point taken on the ray (see [`Cylinder::huge_for`]).
    #[inline(never)]
    fn side_distance(&self, x: Vec3) -> Vec3 {
        let f = W3::from(x).sub(W3::from(self.base));
        let (u, v) = (W3::from(self.tangents.0), W3::from(self.tangents.1));
        let (px, py) = (f.dot(u), f.dot(v));
        let r = f64::from(self.radius);
        let w2 = px * px + py * py;
        let len = math::sqrt64(w2);
        let dist = (w2 - r * r) / (len + r);
        let slack = gamma64(8) * (w2 / (len + r) + dist.abs()) + gamma64(6) * r;
        let radial = W3::new(
            u.x * px + v.x * py,
            u.y * px + v.y * py,
            u.z * px + v.z * py,
        );
        radial
            .abs()
            .scaled_up((dist.abs() + slack) / len.max(f64::MIN_POSITIVE))
    }
}

/// Neither flat nor convex when open, but a ray that leaves its side outwards
/// leaves the infinite tube, which is convex, and a closed one is convex.
impl super::Kinded for Cylinder {
    const FLAT: bool = false;

    fn check_baked(&self) -> Result<bool, Error> {
        Ok(Self::try_new(self.base, self.top, self.radius, self.capped)? == *self)
    }

    fn scaled(&self, f: f32) -> Result<Self, Error> {
        Self::try_new(self.base * f, self.top * f, self.radius * f, self.capped)
    }

    /// Closed, the ball at its middle that touches its side or its caps;
    /// open, a tube whose outline seen end-on is a ring. Its rims lie `sqrt(r^2
    /// + (h / 2)^2)` from its middle.
    fn girth(&self) -> super::Girth {
        if !self.capped {
            return super::Girth::Thin;
        }
        let half = (self.top - self.base).length() * 0.5;
        super::Girth::Ball {
            center: (self.base + self.top) * 0.5,
            radius: math::min(self.radius, half),
            reach: math::sqrt(self.radius * self.radius + half * half),
        }
    }

    /// The box of the two end discs: along each world axis `i`, a disc of
    /// radius `r` and normal `w` reaches `r sqrt(1 - w_i^2)` from its centre;
    /// widened by its roundings.
    #[inline]
    fn extent(&self) -> Extent {
        let w = self.axis;
        let r = self.radius * (1.0 + gamma(8));
        let reach = |c: f32| r * math::sqrt(math::max(0.0, 1.0 - c * c) + gamma(4));
        let e = Vec3::new(reach(w.x), reach(w.y), reach(w.z));
        let (lo, hi) = (self.base.min(self.top), self.base.max(self.top));
        let pad = (lo.abs().max(hi.abs())) * gamma(2);
        Extent::Box {
            min: lo - e - pad,
            max: hi + e + pad,
        }
    }

    #[inline(always)]
    fn search<'r, V: super::Visit<'r, Self>>(v: &mut V) -> Option<(usize, Candidate)> {
        if v.none() {
            return None;
        }
        let ray = v.ray();
        v.each(|c, t| c.hit(ray, t))
    }
}

impl Locate for Cylinder {
    #[inline]
    fn locate(&self, ray: &Ray, hit: &Candidate) -> (Vec3, Vec3, Vec3) {
        let p = ray.at(hit.t);
        let q = self.local(p - self.base);
        if hit.face != SIDE {
            let (z, n) = if hit.face == BASE {
                (0.0, -self.axis)
            } else {
                (self.height, self.axis)
            };
            let q = Vec3::new(q.x, q.y, z);
            return (self.world(q), n, q);
        }
        let l = math::sqrt(q.x * q.x + q.y * q.y);
        let radial = self.tangents.0 * q.x + self.tangents.1 * q.y;
        if self.huge_for(ray, self.local(ray.origin - self.base)) {
            // The point on the ray ([`Cylinder::side_distance`] measures how
            // far from the side it is).
            return (p, radial.normalize_or(self.tangents.0), Vec3::ZERO);
        }
        let (x, y) = if l > 0.0 {
            (q.x * (self.radius / l), q.y * (self.radius / l))
        } else {
            (self.radius, 0.0)
        };
        let q = Vec3::new(x, y, q.z);
        let n = (self.tangents.0 * x + self.tangents.1 * y) * (1.0 / self.radius);
        (self.world(q), n, q)
    }

    #[inline]
    fn error(&self, ray: &Ray, hit: &Candidate, point: Vec3, q: Vec3) -> Vec3 {
        if hit.face == SIDE && self.huge_for(ray, self.local(ray.origin - self.base)) {
            return self.side_distance(point) + point.abs() * gamma(2);
        }
        // In the frame: the re-projected `x, y` (or the cap's `z`) within a few
        // roundings of the radius, the frame's tangents and axis off unit
        // length and orthogonality by a few ulps (which moves a point by ulps of
        // the radius across the surface). Carried back: each product and sum
        // rounds once more.
        let (u, v, w) = (
            self.tangents.0.abs(),
            self.tangents.1.abs(),
            self.axis.abs(),
        );
        let e = gamma(8) * self.radius;
        let frame = u * e + v * e + w * e;
        let sums = (self.base.abs() + u * math::abs(q.x) + v * math::abs(q.y) + w * math::abs(q.z))
            * gamma(4);
        frame + sums
    }
}

impl Shape for Cylinder {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Candidate> {
        self.hit(ray, t_max)
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

    /// `u` the angle about the axis (0 to 1 from `atan2(y, x)` in the frame of
    /// the tangents); `v` the height from the base (0) to the top (1) on the
    /// side, the distance from the axis (0) to the rim (1) on a cap.
    fn uv(&self, surface: &Surface, hit: &Candidate) -> [f32; 2] {
        let q = self.local(surface.point - self.base);
        let u = (math::atan2(q.y, q.x) + PI) * (0.5 * FRAC_1_PI);
        let v = if hit.face == SIDE {
            q.z / self.height
        } else {
            math::sqrt(q.x * q.x + q.y * q.y) / self.radius
        };
        [u, v.clamp(0.0, 1.0)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ray(o: Vec3, d: Vec3) -> Ray {
        Ray::unit(o, d.try_normalize().unwrap())
    }

    fn unit_y() -> Cylinder {
        Cylinder::try_new(Vec3::ZERO, Vec3::new(0.0, 2.0, 0.0), 1.0, true).unwrap()
    }

    #[test]
    fn side_hit_has_the_analytic_time_point_and_normal() {
        let c = unit_y();
        let r = ray(Vec3::new(0.0, 1.0, 5.0), -Vec3::Z);
        let h = c.intersect(&r, f32::INFINITY).unwrap();
        assert_eq!((h.t, h.face), (4.0, SIDE));
        let s = c.surface(&r, &h);
        assert!((s.point - Vec3::new(0.0, 1.0, 1.0)).length() < 1e-6);
        assert!((s.normal - Vec3::Z).length() < 1e-6);
        // Offset by the bound, the point is off the side on each side.
        assert!(s.error.z > 0.0 && s.error.z < 1e-5);
    }

    #[test]
    fn caps_close_it_and_an_open_tube_is_seen_through() {
        let c = unit_y();
        let down = ray(Vec3::new(0.3, 5.0, 0.2), -Vec3::Y);
        let h = c.intersect(&down, f32::INFINITY).unwrap();
        assert_eq!(h.face, TOP);
        assert!((h.t - 3.0).abs() < 1e-6);
        assert_eq!(c.surface(&down, &h).normal, Vec3::Y);
        let open = Cylinder::try_new(Vec3::ZERO, Vec3::new(0.0, 2.0, 0.0), 1.0, false).unwrap();
        assert_eq!(open.intersect(&down, f32::INFINITY), None);
        // From inside the open tube, a ray meets its inner wall.
        let out = ray(Vec3::new(0.0, 1.0, 0.0), Vec3::X);
        let h = open.intersect(&out, f32::INFINITY).unwrap();
        assert!((h.t - 1.0).abs() < 1e-6);
    }

    #[test]
    fn a_ray_along_the_axis_meets_only_the_caps() {
        let c = unit_y();
        let r = ray(Vec3::new(0.5, -3.0, 0.0), Vec3::Y);
        let h = c.intersect(&r, f32::INFINITY).unwrap();
        assert_eq!((h.face, h.t), (BASE, 3.0));
        assert_eq!(c.surface(&r, &h).normal, -Vec3::Y);
    }

    #[test]
    fn no_ray_slips_between_the_side_and_a_cap_along_the_rim() {
        // Rays aimed at points of the top rim from many directions: each hits
        // the side or the cap, never neither.
        let c = Cylinder::try_new(
            Vec3::new(0.3, -0.2, 0.1),
            Vec3::new(1.1, 1.7, -0.4),
            0.7,
            true,
        )
        .unwrap();
        let (u, v) = c.tangents;
        let mut s = 7u32;
        for i in 0..4000 {
            let a = i as f32 * 0.0157;
            // A point 2e-6 inside the rim: a ray to it from outside crosses
            // the surface.
            let rim = c.top - c.axis * 2e-6
                + (u * math::cos_turns(a) + v * math::sin_turns(a)) * (c.radius - 2e-6);
            let from = rim
                + Vec3::new(
                    super::super::test_rand(&mut s),
                    super::super::test_rand(&mut s),
                    super::super::test_rand(&mut s),
                ) * 5.0;
            let Some(r) = Ray::new(from, rim - from).ok() else {
                continue;
            };
            // Only rays from outside the cylinder's box.
            let inside = (from - c.base).dot(c.axis);
            let radial = (from - c.base) - c.axis * inside;
            if inside > 0.0 && inside < c.height && radial.length() < c.radius {
                continue;
            }
            assert!(
                c.intersect(&r, f32::INFINITY).is_some(),
                "ray {i} from {from:?}"
            );
        }
    }

    #[test]
    fn a_ray_leaving_the_side_does_not_hit_it_again() {
        let c = unit_y();
        let mut s = 3u32;
        for _ in 0..2000 {
            let o = Vec3::new(
                super::super::test_rand(&mut s) * 3.0,
                1.0 + super::super::test_rand(&mut s) * 3.0,
                3.0 + super::super::test_rand(&mut s),
            );
            let target = Vec3::new(
                super::super::test_rand(&mut s),
                1.0 + super::super::test_rand(&mut s),
                super::super::test_rand(&mut s),
            );
            let Ok(r) = Ray::new(o, target - o) else {
                continue;
            };
            let Some(h) = c.intersect(&r, f32::INFINITY) else {
                continue;
            };
            let sf = c.surface(&r, &h);
            // Reflected outwards, it leaves; transmitted inwards, it meets the
            // far side only, well away.
            let n = sf.normal;
            let refl = r.dir - n * (2.0 * r.dir.dot(n));
            let o2 = crate::ray::offset_origin(sf.point, sf.error, n, refl);
            let out = Ray::unit(o2, refl);
            if let Some(h2) = c.intersect(&out, f32::INFINITY) {
                assert!(h2.t > 1e-3, "re-hit at {} of {:?}", h2.t, sf.point);
            }
            let o3 = crate::ray::offset_origin(sf.point, sf.error, n, r.dir);
            let through = Ray::unit(o3, r.dir);
            let h3 = c.intersect(&through, f32::INFINITY).unwrap();
            assert!(h3.t > 1e-3, "through: {}", h3.t);
        }
    }

    /// Rays ever nearer the silhouette of the side (`h = r (1 - 2^-k)` from
    /// the axis), against the analytic time `z0 - sqrt(r^2 - h^2)` in `f64`:
    /// within a few ulps for an axis along `y` (its frame is exact), and at
    /// radii from `2^-40` to `2^40` the same bits scaled (every step of the test
    /// is homogeneous); just beyond the silhouette, a miss.
    #[test]
    fn grazing_rays_on_the_side_meet_the_analytic_time_at_any_scale() {
        for k in 1..=22 {
            let h = 1.0 - libm::ldexpf(1.0, -k);
            let mut times = [0.0f32; 3];
            for (slot, e) in times.iter_mut().zip([-40, 0, 40]) {
                let f = libm::ldexpf(1.0, e);
                let c =
                    Cylinder::try_new(Vec3::ZERO, Vec3::new(0.0, 4.0 * f, 0.0), f, true).unwrap();
                let r = Ray::unit(Vec3::new(h * f, 2.0 * f, 5.0 * f), -Vec3::Z);
                let hit = c.intersect(&r, f32::INFINITY).unwrap();
                assert_eq!(hit.face, SIDE);
                *slot = hit.t / f;
            }
            assert!(
                times.iter().all(|&t| t.to_bits() == times[1].to_bits()),
                "{k}: {times:?}"
            );
            let h64 = f64::from(h);
            let exact = 5.0 - (1.0 - h64 * h64).sqrt();
            let err = (f64::from(times[1]) - exact).abs() / exact;
            assert!(err < 4.0 * f64::from(f32::EPSILON), "{k}: {err:e}");
            let beyond = 1.0 + libm::ldexpf(1.0, -20);
            let c = unit_y();
            let r = Ray::unit(Vec3::new(beyond, 1.0, 5.0), -Vec3::Z);
            assert_eq!(c.intersect(&r, f32::INFINITY), None);
        }
    }

    /// The same near a tilted axis (its frame rounded): against the time in
    /// `f64` of the very `f32` numbers the core is given (the centres, the
    /// radius, the ray), so that the difference is the core's own. The axis
    /// and its frame are rounded to `f32`, which moves the side by ulps of the
    /// radius; near the silhouette the time moves by that times `h / sqrt(r^2 -
    /// h^2)` (the slope of the time against the ray's distance from the axis):
    /// within `4 eps (1 + h / sqrt(r^2 - h^2))` of the time, down to `2^-16` of
    /// the radius from the silhouette.
    #[test]
    fn grazing_rays_near_a_tilted_axis_meet_the_time_of_their_numbers() {
        type D = [f64; 3];
        let sub = |a: D, b: D| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
        let dot = |a: D, b: D| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let w64 = |v: Vec3| v.to_array().map(f64::from);
        let (base, top, r) = (Vec3::new(0.2, -0.3, 0.1), Vec3::new(0.9, 2.1, -0.5), 0.6f32);
        let c = Cylinder::try_new(base, top, r, false).unwrap();
        let (b64, r64) = (w64(base), f64::from(r));
        let axis = sub(w64(top), b64);
        let w = axis.map(|x| x / dot(axis, axis).sqrt());
        // The f64 time of the ray `(o, d)` as given: the side's quadratic
        // across the axis.
        let time = |o: D, d: D| {
            let f = sub(o, b64);
            let fp = sub(f, w.map(|x| x * dot(f, w)));
            let dp = sub(d, w.map(|x| x * dot(d, w)));
            let (a, b, cc) = (dot(dp, dp), dot(fp, dp), dot(fp, fp) - r64 * r64);
            (-b - (b * b - a * cc).sqrt()) / a
        };
        let d = Vec3::new(-0.2, 0.1, -1.0).try_normalize().unwrap();
        let d = d - c.axis * d.dot(c.axis);
        let d = d.try_normalize().unwrap();
        let side = c.axis.cross(d);
        let on_axis = base + c.axis * 1.2;
        for k in 1..=16 {
            let h = r * (1.0 - libm::ldexpf(1.0, -k));
            let o = on_axis + side * h - d * 5.0;
            let ray = Ray::unit(o, d);
            let exact = time(w64(o), w64(d));
            let hit = c.intersect(&ray, f32::INFINITY).unwrap();
            let err = (f64::from(hit.t) - exact).abs() / exact;
            let h = f64::from(h);
            let slope = h / (r64 * r64 - h * h).sqrt();
            let bound = 4.0 * f64::from(f32::EPSILON) * (1.0 + slope);
            assert!(err < bound, "{k}: {} {exact} ({err:e} > {bound:e})", hit.t);
        }
    }

    /// Rays parallel to the top cap, just below its plane and just above: the
    /// side, then nothing; and rays down onto the cap just inside the rim and
    /// just outside it: the cap, then nothing.
    #[test]
    fn rays_at_the_rim_hit_or_miss_by_which_side_of_it_they_pass() {
        let c = unit_y();
        let e = libm::ldexpf(1.0, -18);
        let below = Ray::unit(Vec3::new(0.0, 2.0 - e, 5.0), -Vec3::Z);
        assert_eq!(
            c.intersect(&below, f32::INFINITY).map(|h| h.face),
            Some(SIDE)
        );
        let above = Ray::unit(Vec3::new(0.0, 2.0 + e, 5.0), -Vec3::Z);
        assert_eq!(c.intersect(&above, f32::INFINITY), None);
        let inside = Ray::unit(Vec3::new(1.0 - e, 5.0, 0.0), -Vec3::Y);
        assert_eq!(
            c.intersect(&inside, f32::INFINITY).map(|h| h.face),
            Some(TOP)
        );
        let outside = Ray::unit(Vec3::new(1.0 + e, 5.0, 0.0), -Vec3::Y);
        assert_eq!(c.intersect(&outside, f32::INFINITY), None);
    }

    #[test]
    fn uv_go_round_the_axis_and_up_the_side() {
        let c = unit_y();
        let r = ray(Vec3::new(0.0, 0.5, 5.0), -Vec3::Z);
        let h = c.intersect(&r, f32::INFINITY).unwrap();
        let [u, v] = c.uv(&c.surface(&r, &h), &h);
        assert!((v - 0.25).abs() < 1e-6, "{v}");
        assert!((0.0..=1.0).contains(&u));
    }

    #[test]
    fn bad_numbers_are_refused_by_name() {
        let v = Vec3::ZERO;
        assert_eq!(
            Cylinder::try_new(v, Vec3::Y, 0.0, true),
            Err(Error::NotPositive(Field::CylinderRadius))
        );
        assert_eq!(
            Cylinder::try_new(Vec3::splat(f32::NAN), Vec3::Y, 1.0, true),
            Err(Error::NotFinite(Field::CylinderBase))
        );
        assert!(Cylinder::try_new(v, Vec3::Y, 1e-30, true).is_err());
    }

    #[test]
    fn the_extent_holds_the_cylinder() {
        let c = Cylinder::try_new(
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(-2.0, 0.5, 4.0),
            0.8,
            true,
        )
        .unwrap();
        let Extent::Box { min, max } = super::super::Kinded::extent(&c) else {
            panic!("not a box")
        };
        let (u, v) = c.tangents;
        for i in 0..360 {
            let a = i as f32 / 360.0;
            let ring = (u * math::cos_turns(a) + v * math::sin_turns(a)) * c.radius;
            for p in [c.base + ring, c.top + ring] {
                assert!(
                    p.min(min) == min && p.max(max) == max,
                    "{p:?} {min:?} {max:?}"
                );
            }
        }
    }
}
