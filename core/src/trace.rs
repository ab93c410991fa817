//! The searches of a ray through the scene's lists: the nearest hit (camera and
//! secondary rays) and any hit (shadow rays), over every primitive or over the
//! candidates a tile's culling kept ([`crate::cull`]).
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

use crate::geometry::triangle::{Axes, Shear, with_axes};
use crate::geometry::{Candidate, aabb_inverse};
use crate::ray::Ray;
use crate::scene::{Primitive, SceneView};

/// The four geometry kinds, in the order the searches visit their lists.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Kind {
    Sphere = 0,
    Plane = 1,
    Triangle = 2,
    Box = 3,
}

/// A primitive a ray must not test: the one it leaves (see the module doc). One
/// word (the kind in the top two bits, the index below), so that a pending ray
/// stays small.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Skip(u32);

impl Skip {
    /// Nothing to skip (camera rays).
    pub(crate) const NONE: Self = Self(u32::MAX);

    /// Skip primitive `index` of list `kind` (an index beyond 2^30 - 2 skips
    /// nothing: the test is then merely not saved).
    pub(crate) fn new(kind: Kind, index: usize) -> Self {
        match u32::try_from(index) {
            Ok(i) if i < (1 << 30) - 1 => Self((kind as u32) << 30 | i),
            _ => Self::NONE,
        }
    }

    /// The index to skip in list `kind` (`usize::MAX`, never an index, if none).
    #[inline(always)]
    fn index(self, kind: Kind) -> usize {
        if self != Self::NONE && self.0 >> 30 == kind as u32 {
            (self.0 & ((1 << 30) - 1)) as usize
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

/// The candidates of a nearest-hit search: per kind, every primitive (`None`) or the
/// indices a tile's culling kept.
pub(crate) type CameraPick<'l> = Option<&'l [&'l [u16]; 4]>;

/// The candidates of an any-hit search for one light: per kind, every primitive
/// (`None`) or a tile's shadow list, whose entries are `index | mask << 16` with bit
/// `16 + light` set when the primitive may block that light.
pub(crate) type ShadowPick<'l> = Option<(&'l [&'l [u32]; 4], u32)>;

/// Calls `f(index, geometry)` for each primitive of `list` that `pick` keeps, in
/// list order.
#[inline(always)]
fn each<G>(list: &[Primitive<G>], pick: Option<&[u16]>, mut f: impl FnMut(usize, &G)) {
    match pick {
        None => {
            for (i, p) in list.iter().enumerate() {
                f(i, &p.geometry);
            }
        }
        Some(ix) => {
            for &i in ix {
                let i = usize::from(i);
                if let Some(p) = list.get(i) {
                    f(i, &p.geometry);
                }
            }
        }
    }
}

/// True when `f(index, geometry)` is true for some primitive of `list` that `pick`
/// keeps (for the light of `bit`).
#[inline(always)]
fn any<G>(
    list: &[Primitive<G>],
    pick: Option<(&[u32], u32)>,
    mut f: impl FnMut(usize, &G) -> bool,
) -> bool {
    match pick {
        None => list.iter().enumerate().any(|(i, p)| f(i, &p.geometry)),
        Some((entries, bit)) => entries.iter().any(|&e| {
            let i = (e & 0xffff) as usize;
            e & bit != 0 && list.get(i).is_some_and(|p| f(i, &p.geometry))
        }),
    }
}

/// The per-kind pick of a camera pick.
#[inline(always)]
fn kind_pick<'l>(pick: CameraPick<'l>, kind: Kind) -> Option<&'l [u16]> {
    pick.and_then(|p| p.get(kind as usize).copied())
}

/// The per-kind pick of a shadow pick.
#[inline(always)]
fn shadow_kind_pick<'l>(pick: ShadowPick<'l>, kind: Kind) -> Option<(&'l [u32], u32)> {
    pick.and_then(|(p, bit)| p.get(kind as usize).map(|l| (*l, bit)))
}

/// Is the candidate list of `kind` empty (nothing to test, no per-ray work)?
#[inline(always)]
fn nothing<G>(list: &[Primitive<G>], pick: Option<&[u16]>) -> bool {
    pick.map_or(list.is_empty(), <[u16]>::is_empty)
}

impl SceneView<'_> {
    /// The nearest hit of `ray` with `0 < t < t_max` among the candidates `pick`,
    /// except `skip`. Each list is searched with the nearest time found so far, so
    /// a later list only reports nearer hits; ties keep the earlier primitive. Out of
    /// line, for the bounces; camera rays inline [`SceneView::nearest_in`].
    #[inline(never)]
    pub(crate) fn nearest(
        &self,
        ray: &Ray,
        t_max: f32,
        pick: CameraPick<'_>,
        skip: Skip,
    ) -> Option<Nearest> {
        self.nearest_in(ray, t_max, pick, skip)
    }

    /// [`SceneView::nearest`], inlined where it is called.
    #[inline(always)]
    pub(crate) fn nearest_in(
        &self,
        ray: &Ray,
        t_max: f32,
        pick: CameraPick<'_>,
        skip: Skip,
    ) -> Option<Nearest> {
        let mut t = t_max;
        let mut best = None;
        let mut keep = |kind, index, hit: Candidate, t: &mut f32| {
            *t = hit.t;
            best = Some(Nearest { kind, index, hit });
        };
        let sk = skip.index(Kind::Sphere);
        each(self.spheres, kind_pick(pick, Kind::Sphere), |i, s| {
            if i != sk {
                if let Some(h) = s.hit(ray, t) {
                    keep(Kind::Sphere, i, Candidate::at(h), &mut t);
                }
            }
        });
        let sk = skip.index(Kind::Plane);
        each(self.planes, kind_pick(pick, Kind::Plane), |i, p| {
            if i != sk {
                if let Some(h) = p.hit(ray, t) {
                    keep(Kind::Plane, i, Candidate::at(h), &mut t);
                }
            }
        });
        let tri = kind_pick(pick, Kind::Triangle);
        if !nothing(self.triangles, tri) {
            let shear = Shear::new(ray);
            let sk = skip.index(Kind::Triangle);
            with_axes!(shear.axes, A => nearest_triangle::<A>(self.triangles, tri, &shear, sk, &mut t, &mut |i, h, t| keep(Kind::Triangle, i, h, t)), ());
        }
        let boxes = kind_pick(pick, Kind::Box);
        if !nothing(self.boxes, boxes) {
            let inv = aabb_inverse(ray.dir);
            let sk = skip.index(Kind::Box);
            each(self.boxes, boxes, |i, b| {
                if i != sk {
                    if let Some(h) = b.hit_inv(ray.origin, inv, t) {
                        keep(Kind::Box, i, h, &mut t);
                    }
                }
            });
        }
        best
    }

    /// True when a candidate of `pick` other than `skip` blocks `ray` before `t_max`.
    /// Out of line: the light loop that calls it then stays small, with nothing of
    /// the search hoisted into its prologue.
    #[inline(never)]
    pub(crate) fn occluded(&self, ray: &Ray, t_max: f32, pick: ShadowPick<'_>, skip: Skip) -> bool {
        let sk = skip.index(Kind::Sphere);
        if any(
            self.spheres,
            shadow_kind_pick(pick, Kind::Sphere),
            |i, s| i != sk && s.hit(ray, t_max).is_some(),
        ) {
            return true;
        }
        let sk = skip.index(Kind::Plane);
        if any(self.planes, shadow_kind_pick(pick, Kind::Plane), |i, p| {
            i != sk && p.hit(ray, t_max).is_some()
        }) {
            return true;
        }
        let tri = shadow_kind_pick(pick, Kind::Triangle);
        if !tri.map_or(self.triangles.is_empty(), |(l, _)| l.is_empty()) {
            let shear = Shear::new(ray);
            let sk = skip.index(Kind::Triangle);
            let hit = with_axes!(shear.axes, A => any(self.triangles, tri, |i, g| i != sk && g.hit_with::<A>(&shear, t_max).is_some()), false);
            if hit {
                return true;
            }
        }
        let boxes = shadow_kind_pick(pick, Kind::Box);
        if !boxes.map_or(self.boxes.is_empty(), |(l, _)| l.is_empty()) {
            let inv = aabb_inverse(ray.dir);
            let sk = skip.index(Kind::Box);
            return any(self.boxes, boxes, |i, b| {
                i != sk && b.hit_inv(ray.origin, inv, t_max).is_some()
            });
        }
        false
    }

    /// The time of the nearest hit of `ray` with `0 < t < t_max`, if any (every
    /// primitive is a candidate).
    #[must_use]
    pub fn first_hit(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        self.nearest(ray, t_max, None, Skip::NONE).map(|n| n.hit.t)
    }
}

/// The triangle loop of [`SceneView::nearest`] for the ray frame with axes `A`.
#[inline(always)]
fn nearest_triangle<A: Axes>(
    list: &[Primitive<crate::geometry::Triangle>],
    pick: Option<&[u16]>,
    shear: &Shear,
    skip: usize,
    t: &mut f32,
    keep: &mut impl FnMut(usize, Candidate, &mut f32),
) {
    each(list, pick, |i, g| {
        if i != skip {
            if let Some(h) = g.hit_with::<A>(shear, *t) {
                keep(i, h, t);
            }
        }
    });
}
