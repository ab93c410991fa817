//! The two questions a ray asks of the scene, as pbrt asks them: its nearest hit
//! ([`nearest`]: camera and bounced rays) and whether anything blocks it before a
//! distance ([`any`]: shadow rays). Both are one generic search over a
//! [`Source`] of candidates, which visits the kinds in one order (spheres, planes,
//! triangles, boxes, then the meshes) and keeps, among equal times, the first
//! primitive in that order:
//!
//! | source | its candidates | searched by |
//! |---|---|---|
//! | [`Every`] | every primitive, list by list | bounced rays and their shadow rays; every ray of a tile without lists |
//! | [`Whole`] (feature `bvh`) | every primitive of the lists, the spheres and triangles through the view's hierarchies; then the meshes and instances, each through its own | the same rays, in a view with hierarchies or meshes |
//! | [`Listed`] | a tile's camera lists (module `cull`); then its list of meshes and instances, if any ([`nearest_untiled`]) | the camera rays of a tile |
//! | [`Masked`] | a tile's shadow lists, for one light, then its meshes and instances ([`any_masked`]) | the shadow rays of a tile's camera hits |
//!
//! Where each instantiation lives, and why:
//!
//! | instantiation | inlined? | why |
//! |---|---|---|
//! | `nearest` over [`Listed`] | into the camera ray's shading (module `shade`) | once per camera ray: a call and the state it spills would cost more than the search of a short list |
//! | `nearest` over [`Listed`] and a tile's meshes and instances ([`nearest_untiled`]) | out of line | only a tile that lists a mesh or an instance: the others' inlined search is what it is without meshes |
//! | `nearest` over [`Every`] ([`nearest_whole`]) | out of line | the bounces and the tiles without lists share one copy, which keeps the camera ray's loop small |
//! | `nearest` over [`Whole`] (`nearest_through`) | out of line, called by [`nearest_whole`] for a view with hierarchies | a view without one never enters it: its walks would crowd the flat loops' registers |
//! | the meshes' and instances' search (`bvh::meshes`) | out of line, called after the lists' search returns | the two searches' frames (each with a walk's stack) are never on the stack together |
//! | `any` over [`Every`] ([`any_whole`]), [`Whole`] (`any_through`), [`Masked`] ([`any_masked`]) | out of line | the light loop that calls them stays small |
//! | `any` (every source) | the primitive tests' hit details compile away (`FIRST`) | a shadow ray asks only whether something blocks it |
//! | a list's loop ([`Source::each`]) | always | its closure is the primitive test, specialised per kind |
//! | the triangle test | one copy per ray frame (`with_axes!`) | Woop's test with its axis permutation a compile-time constant |
//!
//! The chip's cost of each is in docs/chip-profile.md.
//!
//! A hit goes through three stages, each computed only when needed: every
//! primitive's test returns a [`Candidate`] (the time `t` and the little the test
//! already knows, e.g. a triangle's barycentrics); the search keeps the nearest as a
//! [`Nearest`] (the candidate and which primitive); only that one is resolved into a
//! hit (module `hit`), and the point's error bound only when a ray leaves it.
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
#[cfg(feature = "bvh")]
use crate::bvh::BvhView;
use crate::cull::Hull;
use crate::geometry::{Candidate, Kinded, Visit, aabb_inverse};
use crate::kind::{Geometry, each_kind};
use crate::primitive::Primitive;
use crate::ray::Ray;
use crate::vec::Vec3;
use crate::view::SceneView;

use crate::cull::LISTS;
pub(crate) use crate::kind::Kind;

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

/// A face of one of the view's meshes, as a [`Nearest`]'s (and a [`Skip`]'s)
/// index holds it: `mesh << 16 | face` (a mesh has at most 65,536 faces, a view
/// at most [`crate::mesh::MAX_MESHES`] meshes).
#[cfg(feature = "bvh")]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct MeshFace {
    /// The mesh, in the view's list.
    pub(crate) mesh: usize,
    /// The face, in the mesh's list.
    pub(crate) face: usize,
}

#[cfg(feature = "bvh")]
impl MeshFace {
    /// The face that `index` (of kind [`Kind::Mesh`]) names.
    #[inline(always)]
    pub(crate) const fn of(index: usize) -> Self {
        Self {
            mesh: index >> 16,
            face: index & 0xffff,
        }
    }

    /// The index that names this face.
    #[inline(always)]
    pub(crate) const fn index(self) -> usize {
        self.mesh << 16 | self.face
    }
}

/// Where a search finds its candidates (see the module doc).
pub(crate) trait Source<'v>: Copy {
    /// Whether the triangles' hull is worth testing first: for every primitive,
    /// and for a tile's shadow lists (whose bound, the hull of a whole tile's
    /// visible points and a light, is much wider than a single ray); not for a
    /// tile's camera lists, culled by the tile's own frustum.
    const HULLS: bool;

    /// Calls `f(index, geometry)` for each candidate of list `kind`, in list order;
    /// stops at the first `true` and returns it.
    fn each<G>(self, list: &[Primitive<G>], kind: Kind, f: impl FnMut(usize, &G) -> bool) -> bool;

    /// True when list `kind` has no candidate.
    fn none<G>(self, list: &[Primitive<G>], kind: Kind) -> bool;

    /// The hierarchy list `kind` is searched through, if any.
    #[cfg(feature = "bvh")]
    #[inline(always)]
    fn hierarchy(self, _kind: Kind) -> Option<BvhView<'v>> {
        None
    }
}

/// Every primitive of a view, through its hierarchies where it has them.
#[cfg(feature = "bvh")]
#[derive(Clone, Copy)]
pub(crate) struct Whole<'v> {
    spheres: Option<BvhView<'v>>,
    triangles: Option<BvhView<'v>>,
}

#[cfg(feature = "bvh")]
impl<'v> Whole<'v> {
    /// Every primitive of `view`.
    #[inline(always)]
    pub(crate) fn of(view: &SceneView<'v>) -> Self {
        Self {
            spheres: view.sphere_bvh,
            triangles: view.bvh,
        }
    }
}

/// Every primitive of a view that has no hierarchy: its lists, in list order.
#[derive(Clone, Copy)]
pub(crate) struct Every;

/// A tile's camera lists: per kind, the indices its culling kept, then the
/// tops' (see [`crate::cull::LISTS`]).
#[derive(Clone, Copy)]
pub(crate) struct Listed<'l>(pub(crate) &'l [&'l [u16]; LISTS]);

/// A tile's shadow lists for one light: per kind, then of the tops, entries
/// `index | mask << 16`, of which those with the light's bit.
#[derive(Clone, Copy)]
pub(crate) struct Masked<'l>(pub(crate) &'l [&'l [u32]; LISTS], pub(crate) u32);

/// The meshes and instances a search visits (see [`crate::cull::LISTS`]), in
/// their order: the meshes drawn where they lie, then the instances.
#[cfg(feature = "bvh")]
#[derive(Clone, Copy)]
pub(crate) enum Tops<'l> {
    /// All of them.
    All,
    /// A tile's camera list.
    Listed(&'l [u16]),
    /// A tile's shadow list: the entries with this bit.
    Masked(&'l [u32], u32),
}

/// The list of kind `kind` among a tile's.
#[inline(always)]
fn of<'l, T>(lists: &[&'l [T]; LISTS], kind: Kind) -> &'l [T] {
    lists.get(kind as usize).copied().unwrap_or(&[])
}

/// The tops' list among a tile's.
#[cfg(feature = "bvh")]
#[inline(always)]
pub(crate) fn tops_of<'l, T>(lists: &[&'l [T]; LISTS]) -> &'l [T] {
    lists.get(Kind::Mesh as usize).copied().unwrap_or(&[])
}

#[cfg(feature = "bvh")]
impl<'v> Source<'v> for Whole<'v> {
    const HULLS: bool = true;

    #[inline(always)]
    fn each<G>(self, list: &[Primitive<G>], kind: Kind, f: impl FnMut(usize, &G) -> bool) -> bool {
        Every.each(list, kind, f)
    }

    #[inline(always)]
    fn none<G>(self, list: &[Primitive<G>], kind: Kind) -> bool {
        Every.none(list, kind)
    }

    #[inline(always)]
    fn hierarchy(self, kind: Kind) -> Option<BvhView<'v>> {
        match kind {
            Kind::Sphere => self.spheres,
            Kind::Triangle => self.triangles,
            _ => None,
        }
    }
}

impl<'v> Source<'v> for Every {
    const HULLS: bool = true;

    #[inline(always)]
    fn each<G>(self, list: &[Primitive<G>], _: Kind, mut f: impl FnMut(usize, &G) -> bool) -> bool {
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

impl<'v> Source<'v> for Listed<'_> {
    const HULLS: bool = false;

    #[inline(always)]
    fn each<G>(
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

impl<'v> Source<'v> for Masked<'_> {
    const HULLS: bool = true;

    #[inline(always)]
    fn each<G>(
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

/// The hull of list `G` of `view`, where the source tests hulls
/// ([`Source::HULLS`]) and searches that list as a list (the view keeps a hull
/// for the triangles only: the miss tests of the other kinds cost about what a
/// hull's slab test does).
#[inline(always)]
fn hull_of<'v, S: Source<'v>, G: Geometry>(view: &SceneView<'_>, src: S) -> Option<Hull> {
    #[cfg(feature = "bvh")]
    if src.hierarchy(G::KIND).is_some() {
        return None;
    }
    #[cfg(not(feature = "bvh"))]
    let _ = src;
    if S::HULLS { view.hull(G::KIND) } else { None }
}

/// A kind's candidates for one ray ([`Visit`]): the search's state lent to
/// [`Kinded::search`].
struct Visitor<'a, 'b, 'v, S, G, const FIRST: bool> {
    view: &'b SceneView<'v>,
    src: S,
    list: &'v [Primitive<G>],
    ray: &'a Ray,
    skip: Skip,
    t: &'b mut f32,
    reach: &'b mut Reach<'a>,
}

impl<'a, 'v, S: Source<'v>, G: Geometry, const FIRST: bool> Visit<'a, G>
    for Visitor<'a, '_, 'v, S, G, FIRST>
{
    const FIRST: bool = FIRST;

    #[inline(always)]
    fn ray(&self) -> &'a Ray {
        self.ray
    }

    #[inline(always)]
    fn none(&self) -> bool {
        self.src.none(self.list, G::KIND)
    }

    #[inline(always)]
    fn inv(&mut self) -> Vec3 {
        self.reach.inv()
    }

    #[inline(always)]
    fn may_hit_hull(&mut self) -> bool {
        self.reach
            .may_hit(hull_of::<S, G>(self.view, self.src), *self.t)
    }

    #[inline(always)]
    fn get(&self, index: usize) -> Option<&G> {
        self.list.get(index).map(|p| &p.geometry)
    }

    #[inline(always)]
    fn each(
        &mut self,
        test: impl FnMut(&G, f32) -> Option<Candidate>,
    ) -> Option<(usize, Candidate)> {
        visit::<S, G, FIRST>(
            self.src,
            self.list,
            G::KIND,
            self.ray,
            self.skip.index(G::KIND),
            self.t,
            test,
        )
    }
}

/// The candidate of list `kind` but `skip` that `test` finds nearest before `*t`
/// (a later one only when strictly nearer: the first of equal times is kept), its
/// time then in `*t`; with `FIRST`, the first found, of which only the index
/// counts (its candidate is left at its default: an any-hit test asks only
/// whether there is a hit). Through the list's hierarchy where the source has one.
#[inline(always)]
fn visit<'v, S: Source<'v>, G, const FIRST: bool>(
    src: S,
    list: &[Primitive<G>],
    kind: Kind,
    ray: &Ray,
    skip: usize,
    t: &mut f32,
    mut test: impl FnMut(&G, f32) -> Option<Candidate>,
) -> Option<(usize, Candidate)> {
    #[cfg(feature = "bvh")]
    if let Some(h) = src.hierarchy(kind) {
        return bvh::visit::<FIRST>(&h, ray, skip, t, |i, limit| {
            test(&list.get(i)?.geometry, limit)
        });
    }
    #[cfg(not(feature = "bvh"))]
    let _ = ray;
    let mut found = None;
    src.each(list, kind, |i, g| {
        if i == skip {
            return false;
        }
        if FIRST {
            let hit = test(g, *t).is_some();
            if hit {
                found = Some((i, Candidate::default()));
            }
            return hit;
        }
        if let Some(h) = test(g, *t) {
            *t = h.t;
            found = Some((i, h));
        }
        false
    });
    found
}

/// The nearest hit of `ray` with `0 < t < t_max` among the candidates of `src`,
/// but `skip`. Each kind is searched with the nearest time found so far, so a
/// later kind only reports nearer hits.
#[inline(always)]
pub(crate) fn nearest<'v, S: Source<'v>>(
    view: &SceneView<'v>,
    ray: &Ray,
    t_max: f32,
    src: S,
    skip: Skip,
) -> Option<Nearest> {
    search::<S, false>(view, ray, t_max, src, skip)
}

/// True when a candidate of `src` but `skip` blocks `ray` before `t_max`.
#[inline(always)]
pub(crate) fn any<'v, S: Source<'v>>(
    view: &SceneView<'v>,
    ray: &Ray,
    t_max: f32,
    src: S,
    skip: Skip,
) -> bool {
    search::<S, true>(view, ray, t_max, src, skip).is_some()
}

/// [`nearest`] over every primitive: [`Every`], or [`Whole`] for a view with
/// hierarchies (out of line, see the module doc).
#[inline(never)]
pub(crate) fn nearest_whole(
    view: &SceneView<'_>,
    ray: &Ray,
    t_max: f32,
    skip: Skip,
) -> Option<Nearest> {
    #[cfg(feature = "bvh")]
    if view.through() || !view.meshes.is_empty() {
        return nearest_through(view, ray, t_max, skip);
    }
    nearest(view, ray, t_max, Every, skip)
}

/// [`nearest`] over [`Whole`], then the nearest face of the meshes and
/// instances (which only replaces a nearer hit), out of line (see the module
/// doc).
#[cfg(feature = "bvh")]
#[inline(never)]
fn nearest_through(view: &SceneView<'_>, ray: &Ray, t_max: f32, skip: Skip) -> Option<Nearest> {
    let found = nearest_through_lists(view, ray, t_max, skip);
    if view.meshes.is_empty() {
        return found;
    }
    nearer_in_tops(view, ray, t_max, found, Tops::All, skip)
}

/// `found` (the nearest hit of the lists before `t_max`), or the nearest face
/// of the meshes and instances `tops` if one is nearer: what [`nearest`]
/// finds after the lists (a face at `found`'s time does not replace it).
#[cfg(feature = "bvh")]
#[inline(always)]
fn nearer_in_tops(
    view: &SceneView<'_>,
    ray: &Ray,
    t_max: f32,
    found: Option<Nearest>,
    tops: Tops<'_>,
    skip: Skip,
) -> Option<Nearest> {
    let mut t = found.map_or(t_max, |n| n.hit.t);
    bvh::meshes::<false>(view, tops, ray, skip, &mut t).or(found)
}

/// True when a face of the meshes and instances `tops` blocks `ray` before
/// `t_max`.
#[cfg(feature = "bvh")]
#[inline(always)]
fn blocked_in_tops(
    view: &SceneView<'_>,
    ray: &Ray,
    t_max: f32,
    tops: Tops<'_>,
    skip: Skip,
) -> bool {
    let mut t = t_max;
    bvh::meshes::<true>(view, tops, ray, skip, &mut t).is_some()
}

/// [`nearest`] over [`Whole`] but the meshes, out of line: its frame (and
/// its walks' stacks) and the meshes' search's are never on the stack
/// together.
#[cfg(feature = "bvh")]
#[inline(never)]
fn nearest_through_lists(
    view: &SceneView<'_>,
    ray: &Ray,
    t_max: f32,
    skip: Skip,
) -> Option<Nearest> {
    nearest(view, ray, t_max, Whole::of(view), skip)
}

/// [`any`] over every primitive: [`Every`], or [`Whole`] for a view with
/// hierarchies (out of line, see the module doc).
#[inline(never)]
pub(crate) fn any_whole(view: &SceneView<'_>, ray: &Ray, t_max: f32, skip: Skip) -> bool {
    #[cfg(feature = "bvh")]
    if view.through() || !view.meshes.is_empty() {
        return any_through(view, ray, t_max, skip);
    }
    any(view, ray, t_max, Every, skip)
}

/// [`any`] over [`Whole`], then the meshes and instances, out of line (see
/// the module doc).
#[cfg(feature = "bvh")]
#[inline(never)]
fn any_through(view: &SceneView<'_>, ray: &Ray, t_max: f32, skip: Skip) -> bool {
    if any_through_lists(view, ray, t_max, skip) {
        return true;
    }
    !view.meshes.is_empty() && blocked_in_tops(view, ray, t_max, Tops::All, skip)
}

/// [`any`] over [`Whole`] but the meshes, out of line (as
/// [`nearest_through_lists`]).
#[cfg(feature = "bvh")]
#[inline(never)]
fn any_through_lists(view: &SceneView<'_>, ray: &Ray, t_max: f32, skip: Skip) -> bool {
    any(view, ray, t_max, Whole::of(view), skip)
}

/// [`any`] over a tile's shadow lists for one light, then its list of
/// meshes and instances, out of line (see the module doc).
#[inline(never)]
pub(crate) fn any_masked(
    view: &SceneView<'_>,
    ray: &Ray,
    t_max: f32,
    src: Masked<'_>,
    skip: Skip,
) -> bool {
    if any_masked_lists(view, ray, t_max, src, skip) {
        return true;
    }
    #[cfg(feature = "bvh")]
    {
        let tops = tops_of(src.0);
        if !tops.is_empty() {
            return blocked_in_tops(view, ray, t_max, Tops::Masked(tops, src.1), skip);
        }
    }
    false
}

/// [`any`] over a tile's shadow lists for one light but its tops, out of
/// line: its frame and the tops' search's are never on the stack together.
#[inline(never)]
fn any_masked_lists(
    view: &SceneView<'_>,
    ray: &Ray,
    t_max: f32,
    src: Masked<'_>,
    skip: Skip,
) -> bool {
    any(view, ray, t_max, src, skip)
}

/// The nearest hit of a camera ray that the tile's inlined search of its
/// lists does not find: every primitive ([`nearest_whole`]) for a tile
/// without lists, or a tile's lists, then its meshes and instances, for a
/// tile that lists some (`with_tops`). Out of line: a tile without meshes
/// searches inline what it searches without the feature `bvh`.
#[inline(never)]
pub(crate) fn nearest_untiled(
    view: &SceneView<'_>,
    ray: &Ray,
    t_max: f32,
    with_tops: Option<&[&[u16]; LISTS]>,
) -> Option<Nearest> {
    #[cfg(feature = "bvh")]
    if let Some(lists) = with_tops {
        let found = nearest_lists(view, ray, t_max, lists);
        return nearer_in_tops(
            view,
            ray,
            t_max,
            found,
            Tops::Listed(tops_of(lists)),
            Skip::NONE,
        );
    }
    #[cfg(not(feature = "bvh"))]
    let _ = with_tops;
    nearest_whole(view, ray, t_max, Skip::NONE)
}

/// [`nearest`] over a tile's camera lists but its tops, out of line: its
/// frame and the tops' search's are never on the stack together.
#[cfg(feature = "bvh")]
#[inline(never)]
fn nearest_lists(
    view: &SceneView<'_>,
    ray: &Ray,
    t_max: f32,
    lists: &[&[u16]; LISTS],
) -> Option<Nearest> {
    nearest(view, ray, t_max, Listed(lists), Skip::NONE)
}

/// The search itself: the nearest hit, or with `FIRST` the first hit found (its
/// candidate left at its default).
#[inline(always)]
fn search<'v, S: Source<'v>, const FIRST: bool>(
    view: &SceneView<'v>,
    ray: &Ray,
    t_max: f32,
    src: S,
    skip: Skip,
) -> Option<Nearest> {
    let mut t = t_max;
    let mut best = None;
    let mut reach = Reach::new(ray);
    each_kind!(|G| {
        let mut v = Visitor::<S, G, FIRST> {
            view,
            src,
            list: G::of(&view.primitives),
            ray,
            skip,
            t: &mut t,
            reach: &mut reach,
        };
        if let Some((index, hit)) = G::search(&mut v) {
            best = Some(Nearest {
                kind: G::KIND,
                index,
                hit,
            });
            if FIRST {
                return best;
            }
        }
    });
    best
}

/// The time of the nearest hit of `ray` with `0 < t < t_max`, if any, every
/// primitive a candidate.
#[must_use]
pub fn first_hit(view: &SceneView<'_>, ray: &Ray, t_max: f32) -> Option<f32> {
    nearest_whole(view, ray, t_max, Skip::NONE).map(|n| n.hit.t)
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
