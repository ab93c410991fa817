//! The searches of a ray through the scene's lists: the nearest hit (camera and
//! secondary rays) and any hit (shadow rays), over every primitive or over the
//! candidates a tile's culling kept ([`crate::cull`]); and the nearest hit resolved
//! into the chapter's [`Hit`] (point, normal, material, texture colour).
//!
//! A hit goes through three stages, each computed only when needed: every
//! primitive's test returns a [`Candidate`] (the time `t` and the little the test
//! already knows, e.g. a triangle's barycentrics); the search keeps the nearest as a
//! [`Nearest`] (the candidate and which primitive); only that one is resolved into a
//! [`Hit`], and the point's error bound only when a ray leaves it.
//!
//! Per-ray work is done once per ray, not once per primitive: the triangle test's
//! ray frame ([`Shear`], Woop's axis permutation and shear) and the box test's
//! reciprocal direction are computed only when the ray meets a non-empty list of
//! that kind; the sphere test's cheap miss test is inlined in its loop and the rest
//! of the test is out of line.
//!
//! A ray that leaves a surface cannot hit that same primitive again when it leaves a
//! flat one (plane, triangle) or leaves a closed convex one (sphere, box) outwards:
//! the searches skip it ([`Skip`]), which saves a test that could only answer "no"
//! in exact arithmetic (and that rounding must never turn into a "yes").

#[cfg(feature = "bvh")]
mod bvh;
use crate::cull::Hull;
use crate::geometry::triangle::{Axes, Shear, with_axes};
use crate::geometry::{Candidate, aabb_inverse};
use crate::primitive::Primitive;
use crate::ray::Ray;
use crate::vec::Vec3;
use crate::view::SceneView;
#[cfg(feature = "bvh")]
use bvh::{nearest_through, occluded_through};

/// The geometry kinds, in the order the searches visit their lists (the meshes,
/// feature `bvh`, last).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Sphere = 0,
    Plane = 1,
    Triangle = 2,
    Box = 3,
    #[cfg(feature = "bvh")]
    Mesh = 4,
}

/// A primitive a ray must not test: the one it leaves (see the module doc). One
/// word (the kind in the top three bits, the index below), so that a pending ray
/// stays small.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Skip(u32);

impl Skip {
    /// Nothing to skip (camera rays).
    pub(crate) const NONE: Self = Self(u32::MAX);

    /// Skip primitive `index` of list `kind` (an index beyond 2^29 - 2 skips
    /// nothing: the test is then merely not saved).
    pub(crate) fn new(kind: Kind, index: usize) -> Self {
        match u32::try_from(index) {
            Ok(i) if i < (1 << 29) - 1 => Self((kind as u32) << 29 | i),
            _ => Self::NONE,
        }
    }

    /// The index to skip in list `kind` (`usize::MAX`, never an index, if none).
    #[inline(always)]
    pub(crate) fn index(self, kind: Kind) -> usize {
        if self != Self::NONE && self.0 >> 29 == kind as u32 {
            (self.0 & ((1 << 29) - 1)) as usize
        } else {
            usize::MAX
        }
    }
}

/// The nearest hit: its list, its index there, and the shape's candidate.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Nearest {
    pub(crate) kind: Kind,
    pub(crate) index: usize,
    pub(crate) hit: Candidate,
}

/// Which primitives of each list a search looks at.
pub(crate) trait Candidates: Copy {
    /// Whether the lists' hulls are worth testing first: for every primitive, and
    /// for a tile's shadow lists (whose bound, the hull of a whole tile's visible
    /// points and a light, is much wider than a single ray); not for a tile's
    /// camera lists, culled by the tile's own frustum.
    const HULLS: bool;

    /// Calls `f(index, geometry)` for each candidate of list `kind`, in list order;
    /// stops at the first `true` and returns it.
    fn any<G>(self, list: &[Primitive<G>], kind: Kind, f: impl FnMut(usize, &G) -> bool) -> bool;

    /// True when list `kind` has no candidate.
    fn none<G>(self, list: &[Primitive<G>], kind: Kind) -> bool;
}

/// Every primitive (reflected, refracted and their shadow rays; rays without a
/// tile).
#[derive(Clone, Copy)]
pub(crate) struct Every;

/// A tile's camera lists: per kind, the indices its culling kept.
#[derive(Clone, Copy)]
pub(crate) struct Listed<'l>(pub(crate) &'l [&'l [u16]; 4]);

/// A tile's shadow lists for one light: per kind, entries `index | mask << 16`,
/// of which those with the light's bit.
#[derive(Clone, Copy)]
pub(crate) struct Masked<'l>(pub(crate) &'l [&'l [u32]; 4], pub(crate) u32);

/// The list of kind `kind` among a tile's four.
#[inline(always)]
fn of<'l, T>(lists: &[&'l [T]; 4], kind: Kind) -> &'l [T] {
    lists.get(kind as usize).copied().unwrap_or(&[])
}

impl Candidates for Every {
    const HULLS: bool = true;

    #[inline(always)]
    fn any<G>(self, list: &[Primitive<G>], _: Kind, mut f: impl FnMut(usize, &G) -> bool) -> bool {
        for (i, p) in list.iter().enumerate() {
            if f(i, &p.geometry) {
                return true;
            }
        }
        false
    }

    #[inline(always)]
    fn none<G>(self, list: &[Primitive<G>], _: Kind) -> bool {
        list.is_empty()
    }
}

impl Candidates for Listed<'_> {
    const HULLS: bool = false;

    #[inline(always)]
    fn any<G>(
        self,
        list: &[Primitive<G>],
        kind: Kind,
        mut f: impl FnMut(usize, &G) -> bool,
    ) -> bool {
        for &i in of(self.0, kind) {
            let i = usize::from(i);
            if let Some(p) = list.get(i)
                && f(i, &p.geometry)
            {
                return true;
            }
        }
        false
    }

    #[inline(always)]
    fn none<G>(self, _: &[Primitive<G>], kind: Kind) -> bool {
        of(self.0, kind).is_empty()
    }
}

impl Candidates for Masked<'_> {
    const HULLS: bool = true;

    #[inline(always)]
    fn any<G>(
        self,
        list: &[Primitive<G>],
        kind: Kind,
        mut f: impl FnMut(usize, &G) -> bool,
    ) -> bool {
        let bit = self.1;
        for &e in of(self.0, kind) {
            let i = (e & 0xffff) as usize;
            if e & bit != 0
                && let Some(p) = list.get(i)
                && f(i, &p.geometry)
            {
                return true;
            }
        }
        false
    }

    #[inline(always)]
    fn none<G>(self, _: &[Primitive<G>], kind: Kind) -> bool {
        of(self.0, kind).is_empty()
    }
}

/// What the list hulls need of a ray, computed on first use: its reciprocal
/// direction and the largest component of its origin.
struct Reach<'r> {
    ray: &'r Ray,
    cached: Option<(Vec3, f32)>,
}

impl<'r> Reach<'r> {
    fn new(ray: &'r Ray) -> Self {
        Self { ray, cached: None }
    }

    /// The ray's reciprocal direction.
    #[inline(always)]
    fn inv(&mut self) -> Vec3 {
        self.get().0
    }

    #[inline(always)]
    fn get(&mut self) -> (Vec3, f32) {
        let ray = self.ray;
        *self
            .cached
            .get_or_insert_with(|| (aabb_inverse(ray.dir), ray.origin.abs().max_element()))
    }

    /// False only when the ray surely misses everything inside `hull` before
    /// `t_max` (a list without a hull is always worth searching).
    #[inline(always)]
    fn may_hit(&mut self, hull: Option<Hull>, t_max: f32) -> bool {
        match hull {
            None => true,
            Some(h) => {
                let (inv, mag) = self.get();
                h.may_hit(self.ray.origin, mag, inv, t_max)
            }
        }
    }
}

/// The triangles' hull where the candidates `S` test hulls
/// ([`Candidates::HULLS`]). A hull for the triangles only: the miss tests of
/// spheres, planes and boxes cost about what the hull's slab test does
/// (measured on the built-in scenes: no gain for the spheres or the boxes).
#[inline(always)]
fn triangle_bound<S: Candidates>(view: &SceneView<'_>) -> Option<Hull> {
    if S::HULLS { view.triangle_hull } else { None }
}

/// The nearest hit of `ray` with `0 < t < t_max` among every primitive but
/// `skip`: for the bounces (out of line; camera rays of a tile inline
/// [`SceneView::nearest_in`] with their lists).
#[inline(never)]
pub(crate) fn nearest(view: &SceneView<'_>, ray: &Ray, t_max: f32, skip: Skip) -> Option<Nearest> {
    #[cfg(feature = "bvh")]
    if view.through() {
        return nearest_through(view, ray, t_max, skip);
    }
    nearest_flat(view, ray, t_max, skip)
}

/// [`SceneView::nearest`] without a BVH: out of line on its own with the
/// feature `bvh` (the searches through a BVH reuse it), inlined without.
#[cfg_attr(feature = "bvh", inline(never))]
#[cfg_attr(not(feature = "bvh"), inline(always))]
pub(crate) fn nearest_flat(
    view: &SceneView<'_>,
    ray: &Ray,
    t_max: f32,
    skip: Skip,
) -> Option<Nearest> {
    nearest_in(view, ray, t_max, Every, skip)
}

/// The nearest hit of `ray` with `0 < t < t_max` among the candidates `src`,
/// except `skip`. Each list is searched with the nearest time found so far, so
/// a later list only reports nearer hits; ties keep the earlier primitive.
#[inline(always)]
pub(crate) fn nearest_in<S: Candidates>(
    view: &SceneView<'_>,
    ray: &Ray,
    t_max: f32,
    src: S,
    skip: Skip,
) -> Option<Nearest> {
    let mut t = t_max;
    let mut best = None;
    let mut keep = |kind, index, hit: Candidate, t: &mut f32| {
        *t = hit.t;
        best = Some(Nearest { kind, index, hit });
    };
    let mut reach = Reach::new(ray);
    let sk = skip.index(Kind::Sphere);
    // `none` first, though `any` of an empty list does nothing: without it the
    // chip spends more instructions per pixel, the more so with more samples.
    if !src.none(view.spheres, Kind::Sphere) {
        src.any(view.spheres, Kind::Sphere, |i, s| {
            if i != sk
                && let Some(h) = s.hit(ray, t)
            {
                keep(Kind::Sphere, i, Candidate::at(h), &mut t);
            }
            false
        });
    }
    let sk = skip.index(Kind::Plane);
    src.any(view.planes, Kind::Plane, |i, p| {
        if i != sk
            && let Some(h) = p.hit(ray, t)
        {
            keep(Kind::Plane, i, Candidate::at(h), &mut t);
        }
        false
    });
    if !src.none(view.triangles, Kind::Triangle) && reach.may_hit(triangle_bound::<S>(view), t) {
        let shear = Shear::new(ray);
        let sk = skip.index(Kind::Triangle);
        with_axes!(shear.axes, A => nearest_triangle::<A, S>(view.triangles, src, &shear, sk, &mut t, &mut |i, h, t| keep(Kind::Triangle, i, h, t)), ());
    }
    if !src.none(view.boxes, Kind::Box) {
        let inv = reach.inv();
        let sk = skip.index(Kind::Box);
        src.any(view.boxes, Kind::Box, |i, b| {
            if i != sk
                && let Some(h) = b.time_inv(ray.origin, inv, t)
            {
                keep(Kind::Box, i, Candidate::at(h), &mut t);
            }
            false
        });
        // The face, for the nearest hit only.
        if let Some(n) = best.as_mut().filter(|n| n.kind == Kind::Box)
            && let Some(b) = view.boxes.get(n.index)
        {
            n.hit.face = b.geometry.face_inv(ray.origin, inv);
        }
    }
    best
}

/// True when a primitive other than `skip` blocks `ray` before `t_max`, every
/// primitive a candidate. Out of line: the light loop that calls it then stays
/// small.
#[inline(never)]
pub(crate) fn occluded(view: &SceneView<'_>, ray: &Ray, t_max: f32, skip: Skip) -> bool {
    #[cfg(feature = "bvh")]
    if view.through() {
        return occluded_through(view, ray, t_max, skip);
    }
    occluded_flat(view, ray, t_max, skip)
}

/// [`SceneView::occluded`] without a BVH (as [`SceneView::nearest_flat`]).
#[cfg_attr(feature = "bvh", inline(never))]
#[cfg_attr(not(feature = "bvh"), inline(always))]
pub(crate) fn occluded_flat(view: &SceneView<'_>, ray: &Ray, t_max: f32, skip: Skip) -> bool {
    occluded_in(view, ray, t_max, Every, skip)
}

/// [`SceneView::occluded`] among a tile's shadow lists for one light.
#[inline(never)]
pub(crate) fn occluded_masked(
    view: &SceneView<'_>,
    ray: &Ray,
    t_max: f32,
    src: Masked<'_>,
    skip: Skip,
) -> bool {
    occluded_in(view, ray, t_max, src, skip)
}

/// True when a candidate of `src` other than `skip` blocks `ray` before `t_max`.
#[inline(always)]
fn occluded_in<S: Candidates>(
    view: &SceneView<'_>,
    ray: &Ray,
    t_max: f32,
    src: S,
    skip: Skip,
) -> bool {
    let mut reach = Reach::new(ray);
    let sk = skip.index(Kind::Sphere);
    if !src.none(view.spheres, Kind::Sphere)
        && src.any(view.spheres, Kind::Sphere, |i, s| {
            i != sk && s.hit(ray, t_max).is_some()
        })
    {
        return true;
    }
    let sk = skip.index(Kind::Plane);
    if src.any(view.planes, Kind::Plane, |i, p| {
        i != sk && p.hit(ray, t_max).is_some()
    }) {
        return true;
    }
    if !src.none(view.triangles, Kind::Triangle) && reach.may_hit(triangle_bound::<S>(view), t_max)
    {
        let shear = Shear::new(ray);
        let sk = skip.index(Kind::Triangle);
        let hit = with_axes!(shear.axes, A => src.any(view.triangles, Kind::Triangle, |i, g| i != sk && g.hit_with::<A>(&shear, t_max).is_some()), false);
        if hit {
            return true;
        }
    }
    if !src.none(view.boxes, Kind::Box) {
        let inv = reach.inv();
        let sk = skip.index(Kind::Box);
        return src.any(view.boxes, Kind::Box, |i, b| {
            i != sk && b.time_inv(ray.origin, inv, t_max).is_some()
        });
    }
    false
}

/// The time of the nearest hit of `ray` with `0 < t < t_max`, if any (every
/// primitive is a candidate).
#[must_use]
pub fn first_hit(view: &SceneView<'_>, ray: &Ray, t_max: f32) -> Option<f32> {
    nearest(view, ray, t_max, Skip::NONE).map(|n| n.hit.t)
}

/// The triangle loop of [`SceneView::nearest_in`] for the ray frame with axes `A`.
#[inline(always)]
fn nearest_triangle<A: Axes, S: Candidates>(
    list: &[Primitive<crate::geometry::Triangle>],
    src: S,
    shear: &Shear,
    skip: usize,
    t: &mut f32,
    keep: &mut impl FnMut(usize, Candidate, &mut f32),
) {
    src.any(list, Kind::Triangle, |i, g| {
        if i != skip
            && let Some(h) = g.hit_with::<A>(shear, *t)
        {
            keep(i, h, t);
        }
        false
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skip_names_one_primitive_of_one_kind() {
        let s = Skip::new(Kind::Triangle, 7);
        assert_eq!(s.index(Kind::Triangle), 7);
        for other in [Kind::Sphere, Kind::Plane, Kind::Box] {
            assert_eq!(s.index(other), usize::MAX);
        }
        // Every kind and the largest index that fits.
        let last = (1 << 29) - 2;
        let kinds = [Kind::Sphere, Kind::Plane, Kind::Triangle, Kind::Box];
        #[cfg(feature = "bvh")]
        let kinds = [kinds[0], kinds[1], kinds[2], kinds[3], Kind::Mesh];
        for kind in kinds {
            assert_eq!(Skip::new(kind, 0).index(kind), 0);
            assert_eq!(Skip::new(kind, last).index(kind), last);
            // Beyond: nothing is skipped (the test is merely not saved).
            assert_eq!(Skip::new(kind, last + 1), Skip::NONE);
            assert_eq!(Skip::NONE.index(kind), usize::MAX);
        }
    }
}
