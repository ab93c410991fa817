//! Geometries: the shape of an object (the chapter's "géométrie").
//!
//! Each kind answers the two questions of a ray tracer, in the pbrt way:
//! [`Shape::intersect`], the nearest hit (its time `t` and a little scratch that makes
//! the surface details cheap to finish), and [`Shape::occluded`], the cheaper any-hit
//! for shadow rays. The surface details ([`Shape::surface`]: point, normal, error
//! bound) are computed once, for the winning hit only, and the texture coordinate
//! ([`Shape::uv`]) only when its material is textured: model only what the scene
//! requires.
//!
//! All tests are robust in `f32`: the sphere test of Ray Tracing Gems ch. 7, the
//! watertight triangle test of Woop, Benthin and Wald (2013), a NaN-safe slab test
//! for boxes, and hit points carrying an error bound so that secondary rays start
//! off the surface by exactly as much as rounding requires
//! (`ray::offset_origin`). A surface far larger than the ray's reach (a
//! ground of two triangles 10^7 wide seen from a few units) takes rare, out-of-line
//! paths in `f64` (`wide`).

mod aabb;
mod plane;
mod sphere;
pub(crate) mod triangle;
mod wide;

pub use aabb::Aabb;
pub(crate) use aabb::inverse as aabb_inverse;
pub use plane::Plane;
pub use sphere::Sphere;
pub use triangle::Triangle;

use crate::ray::Ray;
use crate::vec::Vec3;

/// The result of [`Shape::intersect`]: the hit time and shape-specific scratch.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Candidate {
    /// Hit time: the point is `ray.origin + ray.dir * t`; `0 < t < t_max`.
    pub t: f32,
    /// Triangle: barycentric weight of vertex 1. Unused by the other kinds.
    pub b1: f32,
    /// Triangle: barycentric weight of vertex 2. Unused by the other kinds.
    pub b2: f32,
    /// Box: the face hit, `0..6` = -x, +x, -y, +y, -z, +z. Unused by the other kinds.
    pub face: u8,
}

impl Candidate {
    /// A hit at time `t` with no scratch (spheres and planes).
    #[inline(always)]
    #[must_use]
    pub(crate) const fn at(t: f32) -> Self {
        Self {
            t,
            b1: 0.0,
            b2: 0.0,
            face: 0,
        }
    }
}

/// The details of a hit, computed for the nearest hit only.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// The hit point.
    pub point: Vec3,
    /// The unit geometric normal, pointing out of the shape (for a triangle: along
    /// `(p1 - p0) x (p2 - p0)`; for a plane: its normal). The shader flips it to face
    /// the incoming ray.
    pub normal: Vec3,
    /// A bound on the absolute rounding error of each component of `point`.
    pub error: Vec3,
}

/// What every geometry kind answers. Implemented by [`Sphere`], [`Plane`],
/// [`Triangle`] and [`Aabb`]; the scene keeps one list per kind, so this trait is
/// always used statically (never `dyn`).
pub trait Shape {
    /// The nearest hit with `0 < t < t_max`, if any. `ray.dir` is unit length.
    /// Never returns a NaN `t`.
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Candidate>;

    /// True when the ray hits the shape at some `0 < t < t_max`: the any-hit test
    /// of each kind, which the tests and the extremes battery check against
    /// `intersect`. (The renderer's shadow search inlines its own, per list.)
    #[cfg_attr(not(any(test, feature = "testing")), allow(dead_code))]
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool;

    /// Point, outward normal and error bound of a hit returned by `intersect` for the
    /// same ray.
    fn surface(&self, ray: &Ray, hit: &Candidate) -> Surface;

    /// Texture coordinate `(u, v)` of a hit, each usually in `[0, 1]` (planes: world
    /// units along the plane's tangents).
    fn uv(&self, surface: &Surface, hit: &Candidate) -> [f32; 2];

    /// True when `uv` wraps around (a sphere's longitude): a footprint crossing the
    /// seam is not a box of the texture.
    fn uv_wraps(&self) -> bool {
        false
    }
}

/// A hit's point and normal first, its error bound only when a ray leaves it (a
/// shadow, reflected or refracted ray): [`Shape::surface`] in two steps, with the
/// same arithmetic, so that hits that spawn nothing skip the bound.
pub(crate) trait Locate: Shape {
    /// The hit point, its outward unit normal, and what [`Locate::error`] needs
    /// besides them (`aux`).
    fn locate(&self, ray: &Ray, hit: &Candidate) -> (Vec3, Vec3, Vec3);

    /// The error bound of the point that [`Locate::locate`] gave.
    fn error(&self, ray: &Ray, hit: &Candidate, point: Vec3, aux: Vec3) -> Vec3;
}

/// [`Shape::surface`] of every kind: [`Locate::locate`], then [`Locate::error`].
fn surface<G: Locate>(g: &G, ray: &Ray, hit: &Candidate) -> Surface {
    let (point, normal, aux) = g.locate(ray, hit);
    Surface {
        point,
        normal,
        error: g.error(ray, hit, point, aux),
    }
}

/// An orthonormal basis `(t, b)` completing the unit vector `n` (Duff et al. 2017,
/// "Building an orthonormal basis, revisited"): branch-free apart from the sign, no
/// singularity, exact for the axes.
#[must_use]
pub(crate) fn tangent_basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = crate::math::copysign(1.0, n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let t = Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let bt = Vec3::new(b, sign + n.y * n.y * a, -n.y);
    (t, bt)
}

/// The geometry tests' deterministic random numbers (xorshift32), in `[-1, 1)`.
#[cfg(test)]
pub(crate) fn test_rand(state: &mut u32) -> f32 {
    *state ^= *state << 13;
    *state ^= *state >> 17;
    *state ^= *state << 5;
    (*state >> 8) as f32 / (1u32 << 23) as f32 - 1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tangent_basis_is_orthonormal() {
        for n in [
            Vec3::X,
            Vec3::Y,
            Vec3::Z,
            -Vec3::Z,
            Vec3::new(0.3, -0.5, 0.8).normalize_or(Vec3::Z),
            Vec3::new(1e-8, 0.0, -1.0).normalize_or(Vec3::Z),
        ] {
            let (t, b) = tangent_basis(n);
            for (u, v) in [(t, b), (t, n), (b, n)] {
                assert!(u.dot(v).abs() < 1e-6, "{n:?}");
            }
            for u in [t, b] {
                assert!((u.length() - 1.0).abs() < 1e-6, "{n:?}");
            }
        }
    }
}
