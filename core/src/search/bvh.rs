//! The searches through a hierarchy (feature `bvh`): the triangles', the
//! spheres' and each mesh's, for the views that carry one
//! ([`SceneView::with_bvh`], [`SceneView::with_sphere_bvh`],
//! [`SceneView::with_meshes`]); module [`crate::bvh`] says why the image is the
//! same bytes with or without them.

use super::{Kind, Nearest, Skip, nearest_flat, occluded_flat};
use crate::bvh::{BvhView, DEPTH};
#[cfg(feature = "testing")]
use crate::bvh::{VISITS, count_visit};
use crate::cull::MARGIN;
use crate::geometry::triangle::{Axes, Shear, with_axes};
use crate::geometry::{Candidate, Sphere, Triangle, aabb_inverse};
use crate::mesh::Mesh;
use crate::primitive::Primitive;
use crate::ray::Ray;
use crate::vec::Vec3;
use crate::view::SceneView;

/// [`SceneView::nearest`] of a scene with a BVH: the other kinds as the flat
/// search does, then the triangles through the BVH, with the flat search's
/// precedence at equal times (it visits spheres, planes, triangles, boxes, a
/// later kind replacing only a strictly nearer hit): a triangle at the time of
/// a box replaces it, at the time of a sphere or a plane does not.
#[inline(never)]
pub(crate) fn nearest_through(
    view: &SceneView<'_>,
    ray: &Ray,
    t_max: f32,
    skip: Skip,
) -> Option<Nearest> {
    // The spheres first (the flat search's first list): a later kind replaces
    // a sphere only when strictly nearer.
    let sphere = match &view.sphere_bvh {
        Some(bvh) => sphere_nearest(bvh, view.spheres, ray, skip, t_max),
        None => None,
    };
    let t0 = sphere.as_ref().map_or(t_max, |n| n.hit.t);
    let mut best = nearest_flat(&others(view), ray, t0, skip).or(sphere);
    if let Some(bvh) = &view.bvh {
        let (t, box_first) = match &best {
            Some(n) => (n.hit.t, n.kind == Kind::Box),
            None => (t_max, false),
        };
        let sk = skip.index(Kind::Triangle);
        if let Some((index, hit)) = bvh_nearest(bvh, view.triangles, ray, sk, t, box_first) {
            best = Some(Nearest {
                kind: Kind::Triangle,
                index,
                hit,
            });
        }
    }
    let sk = skip.index(Kind::Mesh);
    for (m, mesh) in view.meshes.iter().enumerate() {
        let t = best.as_ref().map_or(t_max, |n| n.hit.t);
        // The face to skip, if it is one of this mesh's.
        let face = if sk >> 16 == m {
            sk & 0xffff
        } else {
            usize::MAX
        };
        if let Some((f, hit)) = bvh_nearest(&mesh.bvh(), mesh, ray, face, t, false) {
            best = Some(Nearest {
                kind: Kind::Mesh,
                index: m << 16 | f,
                hit,
            });
        }
    }
    best
}

/// [`SceneView::occluded`] of a scene with a BVH (as
/// [`SceneView::nearest_through`]).
#[inline(never)]
pub(crate) fn occluded_through(view: &SceneView<'_>, ray: &Ray, t_max: f32, skip: Skip) -> bool {
    if let Some(bvh) = &view.sphere_bvh
        && sphere_any(bvh, view.spheres, ray, skip, t_max)
    {
        return true;
    }
    if occluded_flat(&others(view), ray, t_max, skip) {
        return true;
    }
    if let Some(bvh) = &view.bvh
        && bvh_any(bvh, view.triangles, ray, skip.index(Kind::Triangle), t_max)
    {
        return true;
    }
    let sk = skip.index(Kind::Mesh);
    view.meshes.iter().enumerate().any(|(m, mesh)| {
        let face = if sk >> 16 == m {
            sk & 0xffff
        } else {
            usize::MAX
        };
        bvh_any(&mesh.bvh(), mesh, ray, face, t_max)
    })
}

/// The view without what its hierarchies hold (the triangles when they have
/// one, the spheres when they have one, the meshes): what a scene with a BVH
/// searches with the flat functions (the same instantiations: a search of its
/// own for the other kinds makes the compiler inline the flat searches
/// differently, at more instructions on the chip for scenes without a BVH).
fn others<'a>(view: &SceneView<'a>) -> SceneView<'a> {
    SceneView {
        spheres: if view.sphere_bvh.is_some() {
            &[]
        } else {
            view.spheres
        },
        sphere_bvh: None,
        triangles: if view.bvh.is_some() {
            &[]
        } else {
            view.triangles
        },
        triangle_hull: if view.bvh.is_some() {
            None
        } else {
            view.triangle_hull
        },
        bvh: None,
        meshes: &[],
        through: false,
        ..*view
    }
}

/// What the BVH traversal needs of a ray: its origin, its reciprocal direction and
/// the clearance its nodes are grown by (see the module `bvh`).
struct Probe {
    origin: Vec3,
    inv: Vec3,
    clear: f32,
}

impl Probe {
    /// The probe of `ray` for `bvh`.
    fn new(bvh: &BvhView<'_>, ray: &Ray) -> Self {
        Self {
            origin: ray.origin,
            inv: aabb_inverse(ray.dir),
            clear: MARGIN * (ray.origin.abs().max_element() + bvh.reach),
        }
    }
}

/// Calls `leaf(entries, t_max)` for the triangles (entries of `bvh.order`) of
/// every leaf whose grown box the ray may pass through before `*t_max` (which
/// `leaf` may narrow: a nearest-hit search), nearer child first; stops when
/// `leaf` returns true and returns it.
#[inline(always)]
fn bvh_walk(
    bvh: &BvhView<'_>,
    at: &Probe,
    t_max: &mut f32,
    mut leaf: impl FnMut(&[u16], &mut f32) -> bool,
) -> bool {
    let mut stack = [0u16; DEPTH];
    let mut top = 0;
    let mut node = 0usize;
    // A node is visited at most once: a bounded loop (which also lets the compiler
    // see that the search returns, and so treat its callers as before).
    #[cfg(feature = "testing")]
    count_visit(&VISITS.1);
    for _ in 0..bvh.nodes.len() {
        #[cfg(feature = "testing")]
        count_visit(&VISITS.0);
        if let Some(n) = bvh.nodes.get(node)
            && n.may_hit(at.origin, at.inv, at.clear, *t_max)
        {
            if n.count == 0 {
                let first = n.first;
                // The child on the side the ray comes from first (a negative
                // direction has a negative reciprocal, -0 included).
                let positive = match n.axis {
                    0 => at.inv.x >= 0.0,
                    1 => at.inv.y >= 0.0,
                    _ => at.inv.z >= 0.0,
                };
                let (near, far) = if positive {
                    (first, first.wrapping_add(1))
                } else {
                    (first.wrapping_add(1), first)
                };
                // The stack holds at most one far child per level above the
                // current node, and the build keeps every node above depth
                // `DEPTH`: it never fills. (If it did, only the far child would be
                // searched: never reached, the arm only keeps the walk total.)
                match stack.get_mut(top) {
                    Some(slot) => {
                        *slot = far;
                        top += 1;
                        node = usize::from(near);
                    }
                    None => node = usize::from(far),
                }
                continue;
            }
            let start = usize::from(n.first);
            let entries = bvh
                .order
                .get(start..start + usize::from(n.count))
                .unwrap_or(&[]);
            if leaf(entries, t_max) {
                return true;
            }
        }
        if top == 0 {
            return false;
        }
        top -= 1;
        node = stack.get(top).map_or(usize::MAX, |&n| usize::from(n));
    }
    false
}

/// The nearest triangle hit nearer than `t` through the BVH (but `skip`): its
/// index and candidate. `box_first`: the hit at `t` is a box's, which a triangle at
/// the same time replaces.
#[inline(always)]
fn bvh_nearest<F: Faces + ?Sized>(
    bvh: &BvhView<'_>,
    list: &F,
    ray: &Ray,
    sk: usize,
    t: f32,
    box_first: bool,
) -> Option<(usize, Candidate)> {
    let shear = Shear::new(ray);
    let at = Probe::new(bvh, ray);
    with_axes!(shear.axes, A => bvh_nearest_in::<A, F>(bvh, list, &at, &shear, sk, t, box_first), None)
}

/// The nearest sphere hit nearer than `t_max` through `bvh` (but `skip`): the
/// smallest `(t, index)`, as the flat search keeps the first of equal times.
#[inline(never)]
fn sphere_nearest(
    bvh: &BvhView<'_>,
    spheres: &[Primitive<Sphere>],
    ray: &Ray,
    skip: Skip,
    t_max: f32,
) -> Option<Nearest> {
    let at = Probe::new(bvh, ray);
    let sk = skip.index(Kind::Sphere);
    let mut found: Option<(usize, f32)> = None;
    let mut t = t_max;
    bvh_walk(bvh, &at, &mut t, |entries, t| {
        for &e in entries {
            let i = usize::from(e);
            if i == sk {
                continue;
            }
            let tie = found.is_some_and(|(best, _)| i < best);
            let limit = if tie { t.next_up() } else { *t };
            if let Some(s) = spheres.get(i)
                && let Some(h) = s.geometry.hit(ray, limit)
            {
                *t = h;
                found = Some((i, h));
            }
        }
        false
    });
    found.map(|(index, t)| Nearest {
        kind: Kind::Sphere,
        index,
        hit: Candidate::at(t),
    })
}

/// True when a sphere but `skip` blocks `ray` before `t_max`, through `bvh`.
#[inline(never)]
fn sphere_any(
    bvh: &BvhView<'_>,
    spheres: &[Primitive<Sphere>],
    ray: &Ray,
    skip: Skip,
    t_max: f32,
) -> bool {
    let at = Probe::new(bvh, ray);
    let sk = skip.index(Kind::Sphere);
    let mut t = t_max;
    bvh_walk(bvh, &at, &mut t, |entries, _| {
        entries.iter().any(|&e| {
            let i = usize::from(e);
            i != sk
                && spheres
                    .get(i)
                    .is_some_and(|s| s.geometry.hit(ray, t_max).is_some())
        })
    })
}

/// Where a BVH's leaves find their triangles: the scene's list, or a mesh's faces.
trait Faces {
    /// The hit of triangle `i` nearer than `limit`, in the ray frame `shear`.
    fn hit<A: Axes>(&self, i: usize, shear: &Shear, limit: f32) -> Option<Candidate>;
}

impl Faces for [Primitive<Triangle>] {
    #[inline(always)]
    fn hit<A: Axes>(&self, i: usize, shear: &Shear, limit: f32) -> Option<Candidate> {
        self.get(i)?.geometry.hit_with::<A>(shear, limit)
    }
}

impl Faces for Mesh<'_> {
    #[inline(always)]
    fn hit<A: Axes>(&self, i: usize, shear: &Shear, limit: f32) -> Option<Candidate> {
        self.triangle(i)?.hit_with::<A>(shear, limit)
    }
}

/// True when a triangle but `skip` blocks `ray` before `t_max`, through the BVH.
#[inline(always)]
fn bvh_any<F: Faces + ?Sized>(
    bvh: &BvhView<'_>,
    list: &F,
    ray: &Ray,
    sk: usize,
    t_max: f32,
) -> bool {
    let shear = Shear::new(ray);
    let at = Probe::new(bvh, ray);
    with_axes!(shear.axes, A => bvh_any_in::<A, F>(bvh, list, &at, &shear, sk, t_max), false)
}

/// [`bvh_nearest`] in the ray frame with axes `A`: keeps the smallest
/// `(t, index)` (the flat search's tie rule, see the module doc). With no triangle
/// found yet, the hit at `t` is a box's (`box_first`: a triangle at the same time
/// replaces it) or a sphere's or plane's (it does not).
#[inline(always)]
fn bvh_nearest_in<A: Axes, F: Faces + ?Sized>(
    bvh: &BvhView<'_>,
    list: &F,
    at: &Probe,
    shear: &Shear,
    skip: usize,
    t: f32,
    box_first: bool,
) -> Option<(usize, Candidate)> {
    let mut found: Option<(usize, Candidate)> = None;
    let mut t = t;
    bvh_walk(bvh, at, &mut t, |entries, t| {
        for &e in entries {
            let i = usize::from(e);
            if i == skip {
                continue;
            }
            let tie = match found {
                None => box_first,
                Some((best, _)) => i < best,
            };
            let limit = if tie { t.next_up() } else { *t };
            if let Some(h) = list.hit::<A>(i, shear, limit) {
                *t = h.t;
                found = Some((i, h));
            }
        }
        false
    });
    found
}

/// [`bvh_any`] in the ray frame with axes `A`.
#[inline(always)]
fn bvh_any_in<A: Axes, F: Faces + ?Sized>(
    bvh: &BvhView<'_>,
    list: &F,
    at: &Probe,
    shear: &Shear,
    skip: usize,
    t_max: f32,
) -> bool {
    let mut t = t_max;
    bvh_walk(bvh, at, &mut t, |entries, _| {
        entries.iter().any(|&e| {
            let i = usize::from(e);
            i != skip && list.hit::<A>(i, shear, t_max).is_some()
        })
    })
}
