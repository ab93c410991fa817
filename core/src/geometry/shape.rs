//! What every geometry kind answers ([`Shape`]), and what it answers with
//! ([`Candidate`], [`Surface`]): internals of the core, public only through
//! `tessera_core::testing` (feature `testing`) for the test crates.

#[cfg(doc)]
use super::{Aabb, Plane, Sphere, Triangle};
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
