//! The searches through a hierarchy (feature `bvh`): a list's (the spheres', the
//! triangles') and each mesh's, for [`super::Whole`] where the view carries them
//! ([`SceneView::with_bvh`], [`SceneView::with_sphere_bvh`],
//! [`SceneView::with_meshes`]); module [`crate::bvh`] says why the image is the
//! same bytes with or without them.

use super::{Kind, MeshFace, Nearest, Skip};
use crate::bvh::{BvhView, DEPTH, Known, NodeRay};
#[cfg(feature = "visit-count")]
use crate::bvh::{VISITS, count_visit};
use crate::geometry::Candidate;
use crate::geometry::triangle::{Shear, with_axes};
use crate::mesh::MAX_MESHES;
use crate::ray::Ray;
use crate::view::SceneView;
use heapless::Vec;

/// Calls `leaf(entries, t_max)` for the triangles (entries of `bvh.order`) of
/// every leaf whose grown box the ray may pass through before `*t_max` (which
/// `leaf` may narrow: a nearest-hit search); stops when `leaf` returns true and
/// returns it. An inner node tests both children before descending: into the
/// one the ray enters first, the other kept with its entry time. With `ANY`
/// (`*t_max` stays as it is) a kept node is visited when its turn comes; without,
/// only if its entry time is still within `*t_max`, which is exactly what its
/// test would now answer (its exits were at least that entry time, so only
/// `t_max` can have moved below it).
#[inline(always)]
fn walk<const ANY: bool>(
    bvh: &BvhView<'_>,
    at: &NodeRay,
    known: Known,
    t_max: &mut f32,
    mut leaf: impl FnMut(&[u16], &mut f32) -> bool,
) -> bool {
    let nodes = bvh.nodes;
    #[cfg(feature = "visit-count")]
    count_visit(&VISITS.1);
    #[cfg(feature = "visit-count")]
    count_visit(&VISITS.0);
    let Some(mut n) = nodes.first() else {
        return false;
    };
    if n.entry(at, known, *t_max).is_none() {
        return false;
    }
    // The nodes kept for later, with their entry times: at most one per level
    // above the current node, and the build keeps every node above depth
    // `DEPTH`, so it never fills (if it did, the node would only be dropped: never
    // reached, the arm only keeps the walk total). Not zeroed: a `Vec`.
    let mut stack: Vec<(u16, f32), DEPTH> = Vec::new();
    // A node is visited at most once: a bounded loop (which also lets the compiler
    // see that the search returns, which the optimisation of its callers uses).
    for _ in 0..nodes.len() {
        if n.count == 0 {
            let first = usize::from(n.first);
            if let Some([a, b]) = nodes.get(first..first + 2) {
                #[cfg(feature = "visit-count")]
                {
                    count_visit(&VISITS.0);
                    count_visit(&VISITS.0);
                }
                match (a.entry(at, known, *t_max), b.entry(at, known, *t_max)) {
                    (Some(ta), Some(tb)) => {
                        // The nearer first (the first child on a tie).
                        let (near, far, t_far) = if tb < ta {
                            (b, n.first, ta)
                        } else {
                            (a, n.first.wrapping_add(1), tb)
                        };
                        let _ = stack.push((far, t_far));
                        n = near;
                        continue;
                    }
                    (Some(_), None) => {
                        n = a;
                        continue;
                    }
                    (None, Some(_)) => {
                        n = b;
                        continue;
                    }
                    (None, None) => {}
                }
            }
        } else {
            let start = usize::from(n.first);
            let entries = bvh
                .order
                .get(start..start + usize::from(n.count))
                .unwrap_or(&[]);
            if leaf(entries, t_max) {
                return true;
            }
        }
        // The next kept node still worth visiting.
        loop {
            let Some((i, t)) = stack.pop() else {
                return false;
            };
            if !ANY && t > *t_max {
                continue;
            }
            match nodes.get(usize::from(i)) {
                Some(next) => {
                    n = next;
                    break;
                }
                None => return false,
            }
        }
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
    test: impl FnMut(usize, f32) -> Option<Candidate>,
) -> Option<(usize, Candidate)> {
    visit_known::<FIRST>(bvh, ray, Known::NONE, skip, t, test)
}

/// [`visit`] where the ray's side on an axis is `known` (see [`Known`]).
#[inline(always)]
fn visit_known<const FIRST: bool>(
    bvh: &BvhView<'_>,
    ray: &Ray,
    known: Known,
    skip: usize,
    t: &mut f32,
    mut test: impl FnMut(usize, f32) -> Option<Candidate>,
) -> Option<(usize, Candidate)> {
    let at = NodeRay::new(bvh, ray);
    let mut found: Option<(usize, Candidate)> = None;
    walk::<FIRST>(bvh, &at, known, t, |entries, t| {
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

/// The nearest face of the view's meshes and instances among `tops` but
/// `skip` nearer than `*t` (after every list: a face at the time of another
/// primitive does not replace it); with `FIRST`, the first found. Among faces,
/// the mesh listed first, then the face listed first, is kept; the meshes
/// drawn in place come before the instances (feature `instances`), which come
/// in their order (as every list of tops holds them). Out of line: the camera
/// rays' inlined search of a tile's lists only calls it for a view with
/// meshes.
#[inline(never)]
pub(super) fn meshes<const FIRST: bool>(
    view: &SceneView<'_>,
    tops: super::Tops<'_>,
    ray: &Ray,
    skip: Skip,
    t: &mut f32,
) -> Option<Nearest> {
    let (instanced, placed) = view.instancing();
    let meshes = view.meshes;
    // The ray's frame for the meshes drawn where they lie, once (none when
    // every mesh is drawn through its instances).
    let in_place = meshes.len() > instanced.count_ones() as usize;
    let shear = in_place.then(|| Shear::new(ray));
    #[cfg(feature = "instances")]
    let mut reach = None;
    let skipped = MeshFace::of(skip.index(Kind::Mesh));
    let mut best = None;
    // One loop over the tops, whatever their list: one copy of the searches.
    let mut k = 0usize;
    loop {
        let top = match tops {
            super::Tops::All => {
                // The meshes drawn where they lie, then the instances.
                while k < meshes.len() && instanced >> k & 1 != 0 {
                    k += 1;
                }
                if k < meshes.len() {
                    k
                } else if k - meshes.len() < placed {
                    MAX_MESHES + (k - meshes.len())
                } else {
                    break;
                }
            }
            super::Tops::Listed(list) => match list.get(k) {
                Some(&top) => usize::from(top),
                None => break,
            },
            super::Tops::Masked(list, bit) => {
                while list.get(k).is_some_and(|&e| e & bit == 0) {
                    k += 1;
                }
                match list.get(k) {
                    Some(&e) => (e & 0xffff) as usize,
                    None => break,
                }
            }
        };
        k += 1;
        let face = if skipped.mesh == top {
            skipped.face
        } else {
            usize::MAX
        };
        let found = match (meshes.get(top), &shear) {
            (Some(mesh), Some(shear)) => {
                with_axes!(shear.axes, A => visit_known::<FIRST>(&mesh.bvh(), ray, Known::of::<A>(), face, t, |f, limit| mesh.triangle(f)?.hit_with::<A>(shear, limit)), None)
            }
            // A mesh drawn only through instances is never a top.
            (Some(_), None) => None,
            #[cfg(feature = "instances")]
            (None, _) => instance::<FIRST>(view, top, ray, face, t, &mut reach),
            #[cfg(not(feature = "instances"))]
            (None, _) => None,
        };
        if let Some((f, hit)) = found {
            best = Some(Nearest {
                kind: Kind::Mesh,
                index: MeshFace { mesh: top, face: f }.index(),
                hit,
            });
            if FIRST {
                break;
            }
        }
    }
    best
}

/// The nearest face but `face` of instance `top - MAX_MESHES` nearer than
/// `*t`, if its box the ray may pass through before `*t`: searched in its
/// mesh's space (see [`crate::instance`]). `reach`: the ray's reciprocal
/// direction and largest origin component, computed on first use.
#[cfg(feature = "instances")]
#[inline(never)]
fn instance<const FIRST: bool>(
    view: &SceneView<'_>,
    top: usize,
    ray: &Ray,
    face: usize,
    t: &mut f32,
    reach: &mut Option<(crate::vec::Vec3, f32)>,
) -> Option<(usize, Candidate)> {
    let p = view.instances.get(top.checked_sub(MAX_MESHES)?)?;
    if let Some(h) = p.hull {
        let (inv, mag) = *reach.get_or_insert_with(|| {
            (
                crate::geometry::aabb_inverse(ray.dir),
                ray.origin.abs().max_element(),
            )
        });
        if !h.may_hit(ray.origin, mag, inv, *t) {
            return None;
        }
    }
    let local = p.ray(ray);
    let shear = Shear::new(&local);
    let mesh = p.mesh;
    with_axes!(shear.axes, A => visit_known::<FIRST>(&mesh.bvh(), &local, Known::of::<A>(), face, t, |f, limit| mesh.triangle(f)?.hit_with::<A>(&shear, limit)), None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::triangle::with_axes;

    /// The side a ray frame's type claims for its dominant axis is the side
    /// the node test reads from the ray, for every frame and for directions
    /// with zeros, negative zeros and tiny components.
    #[test]
    fn a_frame_knows_the_side_of_its_dominant_axis() {
        let bvh = BvhView {
            nodes: &[],
            order: &[],
            reach: 1.0,
        };
        let parts = [0.0, -0.0, 1e-30, -1e-30, 0.5, -0.5, 1.0, -1.0];
        let mut frames = 0;
        for &x in &parts {
            for &y in &parts {
                for &z in &parts {
                    let ray = Ray {
                        origin: crate::vec::Vec3::new(1.0, -2.0, 3.0),
                        dir: crate::vec::Vec3::new(x, y, z),
                    };
                    let at = NodeRay::new(&bvh, &ray);
                    let shear = Shear::new(&ray);
                    let known = with_axes!(shear.axes, A => Some(Known::of::<A>()), None);
                    if let Some(k) = known {
                        frames += 1;
                        let claims: usize = (0..3)
                            .filter_map(|a| NodeRay::known(k, a).map(|f| (a, f)))
                            .map(|(a, f)| {
                                assert_eq!(f, at.flipped(a), "{ray:?}");
                                1
                            })
                            .sum();
                        assert_eq!(claims, 1);
                    }
                }
            }
        }
        assert!(frames > 400, "{frames}");
    }
}
