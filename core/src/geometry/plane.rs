//! Infinite plane: a point and a normal.

use super::wide::{W3, gamma64};
use super::{Candidate, Locate, Shape, Surface, tangent_basis};
use crate::error::{Error, Field, flush, flush3, position, unit};
use crate::math::gamma;
use crate::math::{next_down, next_up};
use crate::ray::Ray;
use crate::vec::Vec3;

/// The infinite plane through `point` with unit normal `normal` (double-sided).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
    /// give: `(point - o).n` loses ulps of `point`, which for a plane through a
    /// point `10^7` away would put the hits of a camera near the origin units off
    /// the plane.
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
    /// use tessera_core::{Error, error::Field, geometry::Plane, Vec3};
    /// assert!(Plane::try_new(Vec3::ZERO, Vec3::new(0.0, 2.0, 0.0)).is_ok());
    /// assert_eq!(
    ///     Plane::try_new(Vec3::ZERO, Vec3::ZERO),
    ///     Err(Error::ZeroLength(Field::PlaneNormal))
    /// );
    /// ```
    pub fn try_new(point: Vec3, normal: Vec3) -> Result<Self, Error> {
        // Checked (finite, not zero), normalised in `f64`: the plane is
        // `N . x = N . point` for the normal `N` as given, its offset summed
        // almost exactly and divided by `|N|`; both numbers rounded once, and
        // read by the rule for subnormal numbers as every number of a scene.
        unit(normal, Field::PlaneNormal)?;
        let raw = W3::from(flush3(normal));
        let len = raw.length();
        let point = position(point, Field::PlanePoint)?;
        let unit = flush3(raw.div(len).round());
        Ok(Self {
            point,
            normal: unit,
            offset: flush((raw.dot_exact(W3::from(point)) / len) as f32),
            tangents: tangent_basis(unit),
        })
    }

    /// A plane of baked data (`static` tables written by `tessera bake`): the
    /// numbers [`Plane::parts`] gives, not checked here, in a `const` context.
    /// [`crate::BakedScene::view`] checks them before any render takes the plane,
    /// against what [`Plane::try_new`] makes of some normal through the same
    /// point (see `check_baked`).
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

    /// Checks a plane made by [`Plane::baked`] against what [`Plane::try_new`]
    /// makes of its point and of a normal `N`. The table keeps the unit normal
    /// `try_new` rounded, not `N`, and `try_new` computes the offset from `N`:
    /// the offset cannot be computed again bit for bit, and the check is the
    /// strictest that every plane `try_new` makes passes. The point must be
    /// the one `try_new` keeps, bit for bit (a subnormal component is read as
    /// zero there, so a table holding one is refused); the normal without a
    /// subnormal component and the `f32` rounding of some unit vector `u`
    /// ([`unit_cells`]); the tangents [`tangent_basis`] of it, bit for bit;
    /// and the offset the `f32` rounding (subnormals read as zero) of
    /// `u . point` for such a `u`: within the rounding of the normal's
    /// components times the point's (`1e-32` for a plane through
    /// `(1e6, 0, 0)` of normal `y`, whose offset must then be 0), not a
    /// tolerance of `|point|`.
    ///
    /// `Ok(true)` when the plane holds together, `Ok(false)` when it is not
    /// what `try_new` makes of its numbers (the caller names the item).
    ///
    /// # Errors
    /// `try_new`'s error for a point or a normal it refuses.
    pub(crate) fn check_baked(&self) -> Result<bool, Error> {
        // `try_new` refuses a normal that is not finite or is zero.
        let made = Self::try_new(self.point, self.normal)?;
        let n = self.normal;
        // The normal: no subnormal component, and some unit vector rounds to it.
        let cells = if same_bits(flush3(n), n) {
            unit_cells(n)
        } else {
            None
        };
        let Some(cells) = cells else {
            return Ok(false);
        };
        let (t, b) = tangent_basis(n);
        Ok(same_bits(made.point, self.point)
            && same_bits(self.tangents.0, t)
            && same_bits(self.tangents.1, b)
            && self.offset_fits(cells))
    }

    /// True when the offset is the `f32` rounding, flushed, of `u . point` for
    /// a unit vector `u` that rounds to the normal (`cells`, from
    /// [`unit_cells`], bound each of its components), the `f64` sums' own
    /// roundings allowed for.
    fn offset_fits(&self, cells: [(f64, f64); 3]) -> bool {
        if flush(self.offset).to_bits() != self.offset.to_bits() || !self.offset.is_finite() {
            return false;
        }
        let (mut lo, mut hi, mut size) = (0.0f64, 0.0f64, 0.0f64);
        for ((a, b), p) in cells.into_iter().zip(self.point.to_array()) {
            let (a, b) = (a * f64::from(p), b * f64::from(p));
            lo += a.min(b);
            hi += a.max(b);
            size += a.abs().max(b.abs());
        }
        // `try_new`'s offset carries a few roundings of `f64` (its length,
        // division and compensated sum), these products and sums a few more.
        let slack = gamma64(8) * size;
        let (lo, hi) = (flush((lo - slack) as f32), flush((hi + slack) as f32));
        lo <= self.offset && self.offset <= hi
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

    /// The tangents of its uv (the orthonormal basis of Duff et al. that
    /// completes its normal): an orthonormal frame of the plane.
    #[must_use]
    pub fn tangents(&self) -> (Vec3, Vec3) {
        self.tangents
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

/// A plane is flat.
impl super::Kinded for Plane {
    const FLAT: bool = true;

    fn check_baked(&self) -> Result<bool, crate::error::Error> {
        Plane::check_baked(self)
    }

    fn scaled(&self, f: f32) -> Result<Self, crate::error::Error> {
        Self::try_new(self.point() * f, self.normal())
    }

    fn girth(&self) -> super::Girth {
        super::Girth::HalfSpace
    }

    #[inline(always)]
    fn extent(&self) -> super::Extent {
        super::Extent::Plane {
            point: self.point(),
            normal: self.normal(),
        }
    }

    #[inline(always)]
    fn search<'r, V: super::Visit<'r, Self>>(v: &mut V) -> Option<(usize, super::Candidate)> {
        let ray = v.ray();
        v.each(|p, t| p.hit(ray, t).map(super::Candidate::at))
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

/// True when `a` and `b` have the same bits.
fn same_bits(a: Vec3, b: Vec3) -> bool {
    a.to_array().map(f32::to_bits) == b.to_array().map(f32::to_bits)
}

/// The interval of the reals that round to `x` as [`Plane::try_new`] rounds a
/// unit normal's component (to nearest, then subnormals read as zero): half an
/// ulp each side (of each side's ulp, at a power of two), and for a zero the
/// subnormal range of both signs.
fn cell(x: f32) -> (f64, f64) {
    if x == 0.0 {
        let m = f64::from(f32::MIN_POSITIVE);
        return (-m, m);
    }
    // The sum of two neighbouring `f32` is exact in `f64`, and so is its half.
    let v = f64::from(x);
    (
        (v + f64::from(next_down(x))) / 2.0,
        (v + f64::from(next_up(x))) / 2.0,
    )
}

/// Bounds on the components of the unit vectors that round to `n` as
/// [`Plane::try_new`] rounds a normal: each component within the reals that
/// round to `n`'s ([`cell`]), narrowed to what the unit sphere leaves it given
/// the others' cells, the few `f64` roundings of the normalisation and of these
/// sums allowed for. `None` when no unit vector rounds to `n` (the box of the
/// cells misses the sphere). The narrowing bounds `|u_i| = sqrt(1 - x)` (`x`
/// the others' squares) by `1 - x` below and `1 - x / 2` above, which hold on
/// `[0, 1]`: no square root, a smaller check in a firmware's flash, and for an
/// axis-aligned normal as tight as the root (its own component is 1 to `1e-15`).
fn unit_cells(n: Vec3) -> Option<[(f64, f64); 3]> {
    let cells = n.to_array().map(cell);
    // The least and the largest square of each component.
    let near = cells.map(|(lo, hi)| {
        let m = if lo > 0.0 {
            lo
        } else if hi < 0.0 {
            -hi
        } else {
            0.0
        };
        m * m
    });
    let far = cells.map(|(lo, hi)| {
        let m = lo.abs().max(hi.abs());
        m * m
    });
    let (all_near, all_far): (f64, f64) = (near.iter().sum(), far.iter().sum());
    let slack = gamma64(8);
    let (inner, outer) = ((1.0 - slack) * (1.0 - slack), (1.0 + slack) * (1.0 + slack));
    if all_near > outer || all_far < inner {
        return None;
    }
    let mut out = cells;
    for ((lo, hi), (near, far)) in out.iter_mut().zip(near.into_iter().zip(far)) {
        // The least and the largest magnitude the sphere leaves this component.
        let least = (1.0 - slack - (all_far - far)).max(0.0);
        let most = 1.0 + slack - (all_near - near) / 2.0;
        if *lo > 0.0 {
            (*lo, *hi) = (lo.max(least), hi.min(most));
        } else if *hi < 0.0 {
            (*lo, *hi) = (lo.max(-most), hi.min(-least));
        } else {
            (*lo, *hi) = (lo.max(-most), hi.min(most));
        }
        if lo > hi {
            return None;
        }
    }
    Some(out)
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

    /// Every plane `try_new` makes passes the baked check, whatever its normal's
    /// direction and length and however far its point: normals with components
    /// of every scale (down to the edge of the subnormal range, where a unit
    /// component rounds to zero), points up to `1e12` away.
    #[test]
    fn every_plane_try_new_makes_passes_the_baked_check() {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        // A random f32 of binary exponent in [low, high] (normal numbers), or
        // zero one time in eight.
        let mut number = |low: u32, high: u32| {
            let r = next();
            let sign = u32::from(r & 1 == 1) << 31;
            let mantissa = u32::try_from(r >> 8 & 0x7f_ffff).unwrap();
            let exponent = low + u32::try_from((r >> 40) % u64::from(high - low + 1)).unwrap();
            match (r >> 32) & 7 {
                0 => 0.0,
                _ => f32::from_bits(sign | exponent << 23 | mantissa),
            }
        };
        let mut checked = 0;
        for _ in 0..20_000 {
            // Normals' components from 2^-126 to 2^20, points' from 2^-10 to 2^40.
            let normal = Vec3::new(number(1, 147), number(1, 147), number(1, 147));
            let point = Vec3::new(number(117, 167), number(117, 167), number(117, 167));
            let Ok(p) = Plane::try_new(point, normal) else {
                continue;
            };
            assert_eq!(p.check_baked(), Ok(true), "{point:?} {normal:?} {p:?}");
            checked += 1;
        }
        assert!(checked > 15_000, "{checked}");
    }

    /// `try_new` keeps no subnormal number: a unit normal's component or an
    /// offset that rounds to one is read as zero, as the scene's numbers are.
    #[test]
    fn try_new_makes_no_subnormal_number() {
        let p = Plane::try_new(Vec3::ZERO, Vec3::new(1e-37, 10.0, 0.0)).unwrap();
        assert_eq!(
            p.normal().to_array().map(f32::to_bits),
            [0, 1.0f32.to_bits(), 0]
        );
        let p = Plane::try_new(Vec3::new(1e-30, 0.0, 0.0), Vec3::new(1e-10, 1.0, 0.0)).unwrap();
        assert_eq!(p.parts().2.to_bits(), 0);
        assert_eq!(p.check_baked(), Ok(true));
    }

    /// The baked check refuses a normal that no unit vector rounds to (one ulp
    /// too long or too short), a subnormal component, a tangent or an offset
    /// not the ones `try_new` computes.
    #[test]
    fn the_baked_check_refuses_what_try_new_does_not_make() {
        let ok = Plane::try_new(Vec3::new(0.0, -1.0, 0.0), Vec3::Y).unwrap();
        let (point, normal, offset, tangents) = ok.parts();
        assert_eq!(
            Plane::baked(point, normal, offset, tangents).check_baked(),
            Ok(true)
        );
        for n in [
            [0.0, next_up(1.0), 0.0],
            [0.0, next_down(1.0), 0.0],
            [1e-40, 1.0, 0.0],
            [0.0, 1.0, -1e-45],
        ] {
            let p = Plane::baked(point, n, offset, tangents);
            assert_eq!(p.check_baked(), Ok(false), "{n:?}");
        }
        let mut t = tangents;
        t[0][1] = 0.0;
        assert_eq!(
            Plane::baked(point, normal, offset, t).check_baked(),
            Ok(false)
        );
        for o in [next_up(offset), next_down(offset), -1e-40, 0.0] {
            let p = Plane::baked(point, normal, o, tangents);
            assert_eq!(p.check_baked(), Ok(false), "{o}");
        }
        // An oblique normal, rounded: the offset of any normal that rounds to
        // it passes, one far beyond does not.
        let made = Plane::try_new(Vec3::new(3.0, 4.0, 5.0), Vec3::new(1.0, 2.0, 3.0)).unwrap();
        let (point, normal, offset, tangents) = made.parts();
        let p = Plane::baked(point, normal, offset + 1e-4, tangents);
        assert_eq!(p.check_baked(), Ok(false));
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
