//! Geometries: the shape of an object (the chapter's "géométrie").
//!
//! Each kind answers the two questions of a ray tracer, in the pbrt way (the
//! core's internal trait `Shape`): `intersect`, the nearest hit (its time `t` and
//! a little scratch that makes the surface details cheap to finish), and
//! `occluded`, the cheaper any-hit for shadow rays. The surface details
//! (`surface`: point, normal, error bound) are computed once, for the winning hit
//! only, and the texture coordinate (`uv`) only when its material is textured:
//! model only what the scene requires.
//!
//! All tests are robust in `f32`: the sphere test of Ray Tracing Gems ch. 7, the
//! watertight triangle test of Woop, Benthin and Wald (2013), a NaN-safe slab test
//! for boxes, and hit points carrying an error bound so that secondary rays start
//! off the surface by exactly as much as rounding requires
//! (`ray::offset_origin`). A surface far larger than the ray's reach (a
//! ground of two triangles 10^7 wide seen from a few units) takes rare, out-of-line
//! paths in `f64` (`wide`).

mod aabb;
#[cfg(feature = "cylinder")]
mod cylinder;
#[cfg(feature = "disk")]
mod disk;
mod plane;
mod sphere;
pub(crate) mod triangle;
mod wide;

pub use aabb::Aabb;
pub(crate) use aabb::inverse as aabb_inverse;
#[cfg(feature = "cylinder")]
pub use cylinder::Cylinder;
#[cfg(feature = "disk")]
pub use disk::Disk;
pub use plane::Plane;
pub use sphere::Sphere;
pub use triangle::Triangle;

pub(crate) mod shape;
pub(crate) use shape::{Candidate, Shape, Surface};

use crate::ray::Ray;
use crate::vec::Vec3;

/// What a geometry kind is, beyond its intersection tests: implemented by each
/// kind's type in its own module.
pub(crate) trait Kinded: Locate + Sized {
    /// Flat (a plane, a triangle): a ray that leaves it never meets it again.
    /// Otherwise closed and convex: a ray that leaves it outwards never meets
    /// it again (see `hit::Hit::skip_for`).
    const FLAT: bool;

    /// What holds it, for the culling of a tile's lists ([`Extent`]).
    fn extent(&self) -> Extent;

    /// What its outline is sure to cover, for the sparse sampler's coarse
    /// level ([`Girth`]).
    fn girth(&self) -> Girth;

    /// Whether a value read from baked tables is what the checked constructor
    /// makes of its own numbers (`false`: not a value the constructor makes).
    ///
    /// # Errors
    /// The constructor's own, for numbers it refuses.
    fn check_baked(&self) -> Result<bool, crate::error::Error>;

    /// The same geometry with every length multiplied by `f` (positions, radii;
    /// directions kept), checked again by its constructor.
    ///
    /// # Errors
    /// The constructor's, for a scaled value out of its range.
    fn scaled(&self, f: f32) -> Result<Self, crate::error::Error>;

    /// The kind's part of a ray's search (module `search` hands it its
    /// candidates, `v`): the nearest hit among them (with [`Visit::FIRST`], the
    /// first), its index and candidate. The kind decides what is worth doing
    /// before its loop (whether to look at an empty list first, a hull, a
    /// per-ray set-up) and what its loop tests.
    fn search<'r, V: Visit<'r, Self>>(v: &mut V) -> Option<(usize, Candidate)>;
}

/// A region that holds a primitive: what a tile's culling knows of it.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Extent {
    /// A ball.
    Ball {
        /// Its centre.
        center: Vec3,
        /// Its radius.
        radius: f32,
    },
    /// The convex hull of three points.
    Points([Vec3; 3]),
    /// An axis-aligned box.
    Box {
        /// Its least corner.
        min: Vec3,
        /// Its greatest corner.
        max: Vec3,
    },
    /// A whole plane, unbounded (culled by rules of its own: a tile sees it or
    /// not, and its points receive shadows).
    Plane {
        /// A point of it.
        point: Vec3,
        /// Its unit normal.
        normal: Vec3,
    },
}

/// What a primitive's outline, seen from a point, is sure to cover: what
/// decides whether the sparse sampler's coarse grid could miss all of it
/// (module `tile::sparse`).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Girth {
    /// A ball inside the primitive's solid: seen from outside the ball, the
    /// primitive's outline covers the ball's. The ball of radius `reach`
    /// about the same centre holds the whole primitive.
    Ball {
        /// Its centre.
        center: Vec3,
        /// Its radius.
        radius: f32,
        /// The radius of the ball about `center` that holds the primitive.
        reach: f32,
    },
    /// A whole plane: its outline is a half of every view that sees it.
    HalfSpace,
    /// Nothing sure: flat, or thin somewhere (a triangle or a disk seen
    /// edge-on, an open tube seen end-on).
    Thin,
}

/// A kind's candidates for one ray, as the search hands them to
/// [`Kinded::search`].
pub(crate) trait Visit<'r, G> {
    /// Whether the search wants the first hit found (an any-hit test) rather
    /// than the nearest.
    const FIRST: bool;

    /// The ray.
    fn ray(&self) -> &'r Ray;

    /// True when no candidate of the kind is to be tested.
    fn none(&self) -> bool;

    /// The ray's reciprocal direction (computed once a ray, shared by the
    /// kinds).
    fn inv(&mut self) -> Vec3;

    /// False only when the kind's hull (where the view keeps one for it and
    /// the source tests hulls) proves that the ray misses every candidate
    /// before the nearest time found so far.
    fn may_hit_hull(&mut self) -> bool;

    /// The candidate at `index` of the kind's list.
    fn get(&self, index: usize) -> Option<&G>;

    /// The candidate that `test(geometry, t_max)` finds nearest (with `FIRST`,
    /// the first found), in list order or through the list's hierarchy, the
    /// primitive the ray leaves skipped; keeps the nearest time for the kinds
    /// after.
    fn each(
        &mut self,
        test: impl FnMut(&G, f32) -> Option<Candidate>,
    ) -> Option<(usize, Candidate)>;
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
