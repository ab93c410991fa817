//! The searches through a hierarchy (feature `bvh`): a list's (the spheres', the
//! triangles') and each mesh's, for [`super::Whole`] where the view carries them
//! ([`SceneView::with_bvh`], [`SceneView::with_sphere_bvh`],
//! [`SceneView::with_meshes`]); module [`crate::bvh`] says why the image is the
//! same bytes with or without them.

use super::{Kind, MeshFace, Nearest, Skip};
use crate::bvh::{BvhView, DEPTH};
#[cfg(feature = "visit-count")]
use crate::bvh::{VISITS, count_visit};
use crate::cull::MARGIN;
use crate::geometry::triangle::{Shear, with_axes};
use crate::geometry::{Candidate, aabb_inverse};
use crate::mesh::Mesh;
use crate::ray::Ray;
use crate::vec::Vec3;
#[cfg(doc)]
use crate::view::SceneView;

/// What the BVH traversal needs of a ray: its origin, its reciprocal direction and
/// the clearance its nodes are grown by (see the module `bvh`).
struct NodeRay {
    origin: Vec3,
    inv: Vec3,
    clear: f32,
}

impl NodeRay {
    /// What the walk of `bvh` needs of `ray`.
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
fn walk(
    bvh: &BvhView<'_>,
    at: &NodeRay,
    t_max: &mut f32,
    mut leaf: impl FnMut(&[u16], &mut f32) -> bool,
) -> bool {
    let mut stack = [0u16; DEPTH];
    let mut top = 0;
    let mut node = 0usize;
    // A node is visited at most once: a bounded loop (which also lets the compiler
    // see that the search returns, and so treat its callers as before).
    #[cfg(feature = "visit-count")]
    count_visit(&VISITS.1);
    for _ in 0..bvh.nodes.len() {
        #[cfg(feature = "visit-count")]
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

/// [`super::visit`] through `bvh`: the candidate but `skip` that
/// `test(index, limit)` finds nearest before `*t`, its time then in `*t`; with
/// `FIRST`, the first found (its candidate left at its default). The walk visits
/// entries out of list order, so among equal times the smallest index is kept (as
/// a list's loop keeps the first): an entry before the best so far is tested with
/// a limit one ulp beyond `*t`.
#[inline(always)]
pub(super) fn visit<const FIRST: bool>(
    bvh: &BvhView<'_>,
    ray: &Ray,
    skip: usize,
    t: &mut f32,
    mut test: impl FnMut(usize, f32) -> Option<Candidate>,
) -> Option<(usize, Candidate)> {
    let at = NodeRay::new(bvh, ray);
    let mut found: Option<(usize, Candidate)> = None;
    walk(bvh, &at, t, |entries, t| {
        for &e in entries {
            let i = usize::from(e);
            if i == skip {
                continue;
            }
            if FIRST {
                if test(i, *t).is_some() {
                    found = Some((i, Candidate::default()));
                    return true;
                }
                continue;
            }
            let tie = found.is_some_and(|(best, _)| i < best);
            let limit = if tie { t.next_up() } else { *t };
            if let Some(h) = test(i, limit) {
                *t = h.t;
                found = Some((i, h));
            }
        }
        false
    });
    found
}

/// The nearest face of `meshes` but `skip` nearer than `*t` (after every list: a
/// face at the time of another primitive does not replace it); with `FIRST`, the
/// first found. Among faces, the mesh listed first, then the face listed first, is
/// kept.
#[inline(always)]
pub(super) fn meshes<const FIRST: bool>(
    meshes: &[Mesh<'_>],
    ray: &Ray,
    skip: Skip,
    t: &mut f32,
) -> Option<Nearest> {
    if meshes.is_empty() {
        return None;
    }
    let shear = Shear::new(ray);
    let sk = skip.index(Kind::Mesh);
    let mut best = None;
    for (m, mesh) in meshes.iter().enumerate() {
        // The face to skip, if it is one of this mesh's.
        let skipped = MeshFace::of(sk);
        let face = if skipped.mesh == m {
            skipped.face
        } else {
            usize::MAX
        };
        let found = with_axes!(shear.axes, A => visit::<FIRST>(&mesh.bvh(), ray, face, t, |f, limit| mesh.triangle(f)?.hit_with::<A>(&shear, limit)), None);
        if let Some((f, hit)) = found {
            best = Some(Nearest {
                kind: Kind::Mesh,
                index: MeshFace { mesh: m, face: f }.index(),
                hit,
            });
            if FIRST {
                break;
            }
        }
    }
    best
}
