//! Per-tile culling: "per tile only the primitives that can reach that tile".
//!
//! Before its pixels, a tile builds two candidate lists per geometry kind:
//!
//! - **camera**: the primitives that meet the tile's view frustum, the pyramid from
//!   the camera through the tile's four corners beyond the near plane. A camera ray
//!   of the tile (any sample position, any sampler) tests only these.
//! - **shadow**: for each light (the first [`MASKED_LIGHTS`]), the primitives that
//!   may lie between the light and a point the tile's camera rays can hit, with one
//!   answer for the points on planes and one for the points on the other shapes.
//!   The shadow rays of the camera rays' hits test only these. A box is put around
//!   each visible part (each camera candidate clipped to the frustum). For a point
//!   on another shape, a primitive can block a shadow ray only if it meets the
//!   convex hull of the union `V` of those boxes and the light `L`, which lies in
//!   the capsule of radius `rho` around the segment from `L` to the centre `m` of
//!   `V` (`rho` = half the diagonal of `V`: a point `(1 - s) L + s y` of the hull,
//!   `|y - m| <= rho`, is within `s rho` of the segment's point `(1 - s) L + s m`).
//!   For a point on a plane, a primitive can block only if its shadow, the
//!   projection of its box from the light onto the plane, meets the plane's visible
//!   part (see [`shadow_meets`]): much tighter for a floor than a capsule. A plane
//!   blocks only if the light and some other visible point lie on opposite sides.
//!
//! The meshes and their instances ("tops", see [`LISTS`]) have a list of their
//! own, camera and shadow, each top culled as a box: a mesh drawn where it lies
//! by its faces' exact bounds (its BVH's root, which its search tests first), an
//! instance by its hull's grown box (module `instance`: the mesh's root box
//! carried into the world and grown by a clearance that covers the rounding of
//! carrying rays and points, its translation's included). A tile's rays search
//! the listed tops' BVHs. The shadow rays of a smooth mesh's hit leave from the
//! hit lifted towards the curved surface its normals describe (`Mesh::lift`),
//! which may lie outside the faces' box: the visible points of a top are its box
//! clipped to the frustum and grown by how far its lift may reach
//! (`Mesh::lift_bound`, times an instance's largest scale). A view of more than
//! [`MAX_TOPS`] tops builds no lists.
//!
//! A scene whose triangles or spheres are searched through a BVH
//! (`SceneView::with_bvh`, `with_sphere_bvh`) builds no lists: its rays all search
//! the whole scene, those lists through their BVH (module `bvh`).
//!
//! Reflected and refracted rays can go anywhere: they test every primitive, except
//! the triangles when they miss the triangles' [`Hull`] (a box around them all). (A
//! per-frame bound for spheres, planes and boxes did not pay on the built-in scenes:
//! their own miss tests cost about what a box test does.)
//!
//! ## Why culling never changes a pixel
//!
//! A culled primitive must be one that the intersection test would have reported
//! no hit for, for every ray the tile traces, whatever the rounding. Each test used
//! here reports a hit only when the exact line of the computed ray passes within a
//! few ulps (relative to the lengths involved) of the primitive: the sphere test
//! rejects with a bound on its own rounding and then needs `|l| <= r`, `l` computed
//! to a few ulps; the watertight triangle test decides from edge functions of
//! vertices each transformed with a few roundings; the slab test widens its exit by
//! `2 gamma(3)`; the plane test needs the signs of two dot products. The computed
//! rays themselves are within a few ulps of the exact rays: a camera ray's origin
//! `r_cam + d` and direction `d / |d|` carry about 5 roundings of `d = n c_a +
//! (x - N_L/2) u1 + (y - N_H/2) u2`; a shadow ray starts at the hit point moved by
//! its error bound (`offset_origin`) and points at the light, the hit point within
//! its own error bound (a few ulps) of the exact hit of the computed camera ray.
//! The frustum planes, the bounds and the distances below are computed in `f32`
//! too, with a few roundings each. All of these are errors of at most about
//! `30 u` times the largest magnitude involved (`u = 2^-24`); every culling test
//! here requires a clearance of [`MARGIN`]` = 2^-10` times the sum of those
//! magnitudes (camera position, corner directions, the primitive's distance and
//! size, the light's position, the visible box), more than `10^4` times the worst
//! case. Anything that comes out NaN or infinite culls nothing. The tests compare
//! culled and unculled renders byte for byte (built-in scenes, scene files, random
//! scenes, and the extreme scales of `Scene::scaled_pow2`).
//!
//! ## Memory
//!
//! The lists live on the stack of [`crate::Renderer::render_tile`], in fixed-capacity
//! storage sized by the scene's capacities (`Scene<C>` lends them, see
//! [`lend`]): per kind a `u16` index list (camera) and a `u32` list (shadow: index
//! and a 16-bit mask of the lights it may block), 6 bytes for each primitive of
//! capacity, plus two lengths and two views (the camera's and the shadows') per
//! kind, which [`TileLists`] holds: 24 bytes a kind on a 32-bit core. A view with
//! meshes is lent lists of tops the same way: 6 bytes a top for [`FEW_TOPS`],
//! [`SOME_TOPS`] or [`MAX_TOPS`] of them (24, 96 or 384 bytes), none without a
//! mesh.

use crate::camera::CameraBasis;
use crate::geometry::{Extent, Kinded, Plane};
use crate::kind::{Capacities, Geometry, KINDS, Kind, PerKind, Primitives, Uniform, each_kind};
use crate::light::{Light, LightKind};
use crate::primitive::Primitive;
use crate::vec::Vec3;
use heapless::vec::VecView;

/// The candidates of one camera ray's tree: its own nearest-hit search (a tile's
/// camera lists, or every primitive) and the shadow rays of its hit (a tile's shadow
/// lists, entries `index | mask << 16`, or every primitive). Reflected and
/// refracted rays, which may go anywhere, always search every primitive.
///
/// A tile that lists meshes or instances gives its camera lists as `with_tops`
/// (searched out of line), `camera` then `None`: the camera ray's inlined search
/// of a tile without them is what it is without meshes.
#[derive(Clone, Copy, Default)]
pub(crate) struct Picks<'l> {
    pub(crate) camera: Option<[&'l [u16]; LISTS]>,
    pub(crate) with_tops: Option<[&'l [u16]; LISTS]>,
    pub(crate) shadow: Option<ShadowLists<'l>>,
}

/// A tile's shadow lists: per list (see [`LISTS`]), entries `index | mask << 16`
/// (see `cull::PLANE_RECEIVERS` and `cull::SOLID_RECEIVERS` for the mask's
/// bits), and the union of their masks.
#[derive(Clone, Copy)]
pub(crate) struct ShadowLists<'l> {
    pub(crate) lists: [&'l [u32]; LISTS],
    pub(crate) lights: u32,
}

/// A tile's lists: one per kind, in search order, then one of the meshes and
/// their instances at index `KINDS` (the index of `Kind::Mesh`, feature
/// `bvh`), their "tops": mesh `m` drawn where it lies is `m`, instance `i` is
/// `MAX_MESHES + i` (the index a hit names them by).
pub(crate) const LISTS: usize = KINDS + 1;

/// The most meshes and instances a tile lists: a view with more builds no
/// lists (every ray searches every primitive).
pub(crate) const MAX_TOPS: usize = 64;

/// The tops' storage lent to a view with at most this many (then
/// [`SOME_TOPS`], then [`MAX_TOPS`]): a tile's lists are on the stack.
#[cfg_attr(not(feature = "bvh"), allow(dead_code))]
const FEW_TOPS: usize = 4;

/// See [`FEW_TOPS`].
#[cfg_attr(not(feature = "bvh"), allow(dead_code))]
const SOME_TOPS: usize = 16;

/// What the tile lists need of a mesh drawn where it lies or of an instance:
/// the box of its faces in the world (an instance's grown as its hull is), and
/// how far from its faces a shadow ray may leave (a smooth mesh's `lift`, at
/// most the largest face's diameter; 0 for a flat mesh).
#[derive(Clone, Copy, Debug)]
pub(crate) struct TopBox {
    pub(crate) min: Vec3,
    pub(crate) max: Vec3,
    pub(crate) lift: f32,
}

/// Lights beyond this index are not in the tile shadow lists' masks (16 bits: 8
/// lights, for hits on planes and on the other shapes): their shadow rays test every
/// primitive.
pub(crate) const MASKED_LIGHTS: usize = 8;

/// What a tile's lists are built from: a scene's primitives and lights (the scene
/// view, module `view`, implements it).
pub(crate) trait Source {
    fn primitives(&self) -> Primitives<'_>;
    fn lights(&self) -> &[Light];

    /// Calls `f(top, box)` for each mesh drawn where it lies and each instance
    /// (see [`LISTS`]) that has faces, in search order; `None` for one whose box
    /// is unknown (a tile then builds no lists).
    fn each_top(&self, f: impl FnMut(usize, Option<TopBox>)) {
        let _ = f;
    }
}

/// The first bit of a shadow list entry's light mask for hits on planes (bit
/// `PLANE_RECEIVERS + l` for light `l`, one of the first [`MASKED_LIGHTS`]).
pub(crate) const PLANE_RECEIVERS: usize = 16;

/// The first bit of a shadow list entry's light mask for hits on the other shapes.
pub(crate) const SOLID_RECEIVERS: usize = PLANE_RECEIVERS + MASKED_LIGHTS;

/// The relative clearance every culling test requires (see the module doc).
pub(crate) const MARGIN: f32 = 1.0 / 1024.0;

/// A box around every primitive of a list (a one-node bounding volume hierarchy):
/// a ray that misses it cannot hit any of them, so the list is skipped. Used for
/// the rays that the tile lists do not cover (reflected, refracted, and their
/// shadow rays), and only for rays whose origin lies within `reach` (largest
/// component), so that the clearance below covers their rounding.
///
/// Conservative by the argument of the module doc: the box is the exact bounds of
/// the list grown by [`MARGIN`] times `2 m + e` (`m` the bounds' largest coordinate,
/// `e` their largest extent); a ray with `|origin| <= reach = 2 m + e` that an
/// intersection test reports as hitting a primitive passes, at that time, within
/// about `30 u (|origin| + |point|) <= 30 u (3 m + e)` of it, far inside the
/// clearance, and the slab test itself never misses a ray that passes through its
/// box (pbrt-v4's widened exit).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Hull {
    bounds: crate::geometry::Aabb,
    reach: f32,
}

impl Hull {
    /// The hull of the primitives within `[min, max]`, or `None` for an empty or
    /// non-finite list.
    pub(crate) fn new(min: Vec3, max: Vec3) -> Option<Self> {
        Self::reaching(min, max, 0.0)
    }

    /// [`Hull::new`] for primitives whose computed hits also carry the
    /// rounding of numbers of magnitude up to `far` (an instance's: its
    /// translation, which a point of its mesh far from the mesh's origin may
    /// cancel, so that the rounding of the carried point exceeds what the
    /// box's own magnitude bounds). `2 far` is added to the reach.
    pub(crate) fn reaching(min: Vec3, max: Vec3, far: f32) -> Option<Self> {
        let b = Bounds::new(min, max);
        if b.is_empty() || !b.is_finite() {
            return None;
        }
        let reach = 2.0 * b.magnitude() + mag(max - min) + 2.0 * far;
        let b = b.grown(MARGIN * reach);
        reach.is_finite().then_some(Self {
            bounds: crate::geometry::Aabb::enclosing(b.min, b.max),
            reach,
        })
    }

    /// The hull's numbers: its grown box's corners and its reach (baked
    /// instances, module `instance`).
    #[cfg(feature = "instances")]
    pub(crate) fn parts(&self) -> [f32; 7] {
        let (lo, hi) = (self.bounds.min(), self.bounds.max());
        [lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, self.reach]
    }

    /// The hull of these numbers ([`Hull::parts`]).
    #[cfg(feature = "instances")]
    pub(crate) const fn from_parts(p: [f32; 7]) -> Self {
        Self {
            bounds: crate::geometry::Aabb::baked([p[0], p[1], p[2]], [p[3], p[4], p[5]]),
            reach: p[6],
        }
    }

    /// False only when the ray from `origin` (reciprocal direction `inv`) surely
    /// misses every primitive inside before `t_max`.
    #[inline(always)]
    pub(crate) fn may_hit(&self, origin: Vec3, origin_mag: f32, inv: Vec3, t_max: f32) -> bool {
        let near = origin_mag <= self.reach; // false for NaN
        !near || self.bounds.spans(origin, inv, t_max)
    }

    /// The grown box's corners.
    #[cfg(feature = "instances")]
    pub(crate) fn corners(&self) -> (Vec3, Vec3) {
        (self.bounds.min(), self.bounds.max())
    }
}

/// The largest list a `u16` index covers.
const INDEXABLE: usize = 1 << 16;

/// A tile's candidate lists, per kind (in search order), then of the tops (see
/// [`LISTS`]).
pub(crate) struct TileLists<'s> {
    camera: [&'s mut VecView<u16>; KINDS],
    shadow: [&'s mut VecView<u32>; KINDS],
    tops: &'s mut VecView<u16>,
    top_shadow: &'s mut VecView<u32>,
}

/// What renders a tile with the lists it is lent (`None`: no culling).
pub(crate) type WithLists<'f> = dyn FnMut(Option<&mut TileLists<'_>>) + 'f;

/// How a scene lends a tile the storage of its lists: [`TileStorage::lend`] for
/// the scene's capacities, given the lengths of its lists and its number of
/// tops (see [`LISTS`]; `None` when its tiles build no lists: rays searched
/// through a hierarchy, or culling off).
pub(crate) type Lender = fn(Option<[usize; LISTS]>, &mut WithLists<'_>);

/// The storage of a tile's lists for at most as many primitives of each kind as
/// the capacities `C`: per kind a `u16` index list (camera rays) and a `u32`
/// entry list (shadow rays), 6 bytes a primitive of capacity on the stack of the
/// tile loop.
pub(crate) struct TileStorage<C: Capacities> {
    camera: PerKind<C, u16>,
    shadow: PerKind<C, u32>,
}

/// The entries per list of the storage lent to a scene whose capacities exceed
/// it but whose lists hold no more (see [`TileStorage::lend`]).
const FEW: usize = 64;

impl<C: Capacities> TileStorage<C> {
    /// Lends `f` a tile's candidate lists on the stack, for a scene of capacities
    /// `C` whose lists hold `held` primitives, the last entry its tops (`None`:
    /// lends none, and so does a capacity beyond a `u16` index or more than
    /// [`MAX_TOPS`] tops).
    ///
    /// Sized by what the scene holds, not by its capacity, where the two differ
    /// widely: a scene file read into the host's capacities (thousands of
    /// triangles) holds a handful of primitives, and storage for its capacities
    /// would be tens of KiB to set up for every tile, more than the tile's pixels
    /// cost. Such a scene, when every list holds at most [`FEW`], is lent storage
    /// for [`FEW`] of each kind. A firmware's scene, whose capacities are what it
    /// holds, is lent exactly its capacities (the branch is decided at compile
    /// time). The tops' lists hold none (no mesh), [`FEW_TOPS`], [`SOME_TOPS`]
    /// or [`MAX_TOPS`] entries.
    pub(crate) fn lend(held: Option<[usize; LISTS]>, f: &mut WithLists<'_>) {
        let Some(held) = held else {
            return f(None);
        };
        let caps = C::COUNTS.kinds();
        let tops = held.get(KINDS).copied().unwrap_or(0);
        if caps.iter().any(|&c| c > INDEXABLE) || tops > MAX_TOPS {
            return f(None);
        }
        let kinds = held.get(..KINDS).unwrap_or(&[]);
        if caps.iter().any(|&c| c > FEW) && kinds.iter().all(|&n| n <= FEW) {
            return TileStorage::<Uniform<FEW>>::lend_tops(tops, f);
        }
        Self::lend_tops(tops, f);
    }

    /// Lends `f` lists of every capacity, with room for `tops` tops.
    fn lend_tops(tops: usize, f: &mut WithLists<'_>) {
        #[cfg(feature = "bvh")]
        if tops > SOME_TOPS {
            return Self::lend_all::<MAX_TOPS>(f);
        }
        #[cfg(feature = "bvh")]
        if tops > FEW_TOPS {
            return Self::lend_all::<SOME_TOPS>(f);
        }
        #[cfg(feature = "bvh")]
        if tops > 0 {
            return Self::lend_all::<FEW_TOPS>(f);
        }
        let _ = tops;
        Self::lend_all::<0>(f);
    }

    /// Lends `f` lists of every capacity, and `T` entries for the tops. Out of
    /// line: only the storage of the one lent is on the stack.
    #[inline(never)]
    fn lend_all<const T: usize>(f: &mut WithLists<'_>) {
        let mut st = Self {
            camera: PerKind::EMPTY,
            shadow: PerKind::EMPTY,
        };
        let mut tops = heapless::Vec::<u16, T>::new();
        let mut top_shadow = heapless::Vec::<u32, T>::new();
        f(Some(&mut TileLists {
            camera: st.camera.views(),
            shadow: st.shadow.views(),
            tops: tops.as_mut_view(),
            top_shadow: top_shadow.as_mut_view(),
        }));
    }
}

impl TileLists<'_> {
    /// Fills the lists for the tile covering `[x0, x1] x [y0, y1]` of the viewport
    /// (pixel units) and returns the picks the tile's camera rays use. Picks of
    /// `None` (every primitive) where a bound cannot be formed.
    pub(crate) fn build(
        &mut self,
        basis: &CameraBasis,
        view: &impl Source,
        (x0, y0, x1, y1): (f32, f32, f32, f32),
    ) -> Picks<'_> {
        for l in &mut self.camera {
            l.clear();
        }
        for l in &mut self.shadow {
            l.clear();
        }
        self.tops.clear();
        self.top_shadow.clear();
        let Some(f) = Frustum::new(basis, x0, y0, x1, y1) else {
            return Picks::default();
        };
        let primitives = view.primitives();
        each_kind!(|G| {
            if let Some(list) = self.camera.get_mut(G::KIND as usize) {
                fill(list, G::of(&primitives), |g| !f.misses(g.extent()));
            }
        });
        // The tops the tile sees, and where the shadow rays of their hits may
        // leave from: their boxes clipped to the frustum, grown by the lift.
        let mut unknown = false;
        let mut seen_tops = Bounds::EMPTY;
        view.each_top(|top, b| {
            let Some(b) = b else {
                unknown = true;
                return;
            };
            if !f.misses_box(b.min, b.max) {
                // Cannot fail: the storage holds every top (see `lend`).
                unknown |= self.tops.push(index(top) as u16).is_err();
                let seen = f.clip(Bounds::new(b.min, b.max));
                seen_tops = seen_tops.union(if seen.is_empty() {
                    seen
                } else {
                    seen.grown(b.lift)
                });
            }
        });
        if unknown {
            return Picks::default();
        }

        let shadow = if view.lights().is_empty() {
            None
        } else {
            self.build_shadow(&f, view, seen_tops)
        };
        let lists = lists_of(&self.camera, self.tops);
        let (camera, with_tops) = if self.tops.is_empty() {
            (Some(lists), None)
        } else {
            (None, Some(lists))
        };
        let shadow = shadow.map(|()| {
            let lists = lists_of(&self.shadow, self.top_shadow);
            let lights = lists.iter().flat_map(|l| l.iter()).fold(0, |m, e| m | e);
            ShadowLists {
                lists,
                lights: lights & !0xffff,
            }
        });
        Picks {
            camera,
            with_tops,
            shadow,
        }
    }

    /// The shadow lists, from the camera lists and the box `seen_tops` of where
    /// the shadow rays of the visible tops' hits may leave from; `None` when the
    /// visible points have no finite bound.
    fn build_shadow(&mut self, f: &Frustum, view: &impl Source, seen_tops: Bounds) -> Option<()> {
        let primitives = view.primitives();
        // The visible points of everything but the planes, and of each plane.
        let mut solids = seen_tops;
        each_kind!(|G| {
            let listed = self
                .camera
                .get(G::KIND as usize)
                .map_or(&[][..], |l| &l[..]);
            for &i in listed {
                let g = &G::of(&primitives).get(usize::from(i))?.geometry;
                if let Some(b) = Bounds::of(g.extent()) {
                    solids = solids.union(f.clip(b));
                }
            }
        });
        let cp = self
            .camera
            .get(Kind::Plane as usize)
            .map_or(&[][..], |l| &l[..]);
        // The visible parts of the first few visible planes, each on its own: a
        // blocker's shadow on a plane is bounded much more tightly (its projection
        // from the light) than by a capsule around a tile's whole floor. Beyond
        // `FLOORS` visible planes a capsule around all of them is used instead.
        const FLOORS: usize = 4;
        let mut floors: [Option<(usize, &Plane, Bounds)>; FLOORS] = [None; FLOORS];
        let separate = cp.len() <= FLOORS;
        if separate {
            for (slot, &i) in floors.iter_mut().zip(cp.iter()) {
                let p = &view.primitives().planes.get(usize::from(i))?.geometry;
                *slot = Some((usize::from(i), p, f.on_plane(p)));
            }
        }
        // The visible parts of the planes but `except`, together.
        let flats_but = |except: Option<usize>| {
            let other = |j: usize| Some(j) != except;
            if separate {
                floors
                    .iter()
                    .flatten()
                    .filter(|(j, _, _)| other(*j))
                    .fold(Bounds::EMPTY, |v, (_, _, region)| v.union(*region))
            } else {
                cp.iter()
                    .map(|&i| usize::from(i))
                    .filter(|&j| other(j))
                    .filter_map(|j| view.primitives().planes.get(j))
                    .fold(Bounds::EMPTY, |v, p| v.union(f.on_plane(&p.geometry)))
            }
        };
        let flats = flats_but(None);
        let all = solids.union(flats);
        if all.is_empty() {
            return Some(()); // nothing visible: no shadow ray from this tile
        }
        if !all.is_finite() {
            return None;
        }
        let lights = view.lights().get(..MASKED_LIGHTS).unwrap_or(view.lights());
        // May a blocker (its ball and its box) block a shadow ray from the tile's
        // visible points to each light? Two answers per light: for the points on
        // the planes (mask bit `PLANE_RECEIVERS + l`) and on the other shapes
        // (`SOLID_RECEIVERS + l`).
        let blocks = |c: Vec3, r: f32, b: Bounds| {
            let mut mask = 0u32;
            for (l, light) in lights.iter().enumerate() {
                let at = light.kind();
                let on_flats = if separate {
                    floors
                        .iter()
                        .flatten()
                        .any(|(_, p, region)| shadow_meets(p, at, b, *region))
                } else {
                    !flats.is_empty() && !flats.capsule_misses(at, c, r)
                };
                let on_solids = !solids.is_empty() && !solids.capsule_misses(at, c, r);
                mask |= u32::from(on_flats) << (PLANE_RECEIVERS + l);
                mask |= u32::from(on_solids) << (SOLID_RECEIVERS + l);
            }
            mask
        };
        each_kind!(|G| {
            if let Some(list) = self.shadow.get_mut(G::KIND as usize) {
                fill_masked(list, G::of(&primitives), |g| {
                    let e = g.extent();
                    match (ball_of(e), Bounds::of(e)) {
                        (Some((c, r)), Some(b)) => blocks(c, r, b),
                        // A plane: its own rule, below.
                        _ => 0,
                    }
                });
            }
        });
        let mut full = false;
        view.each_top(|top, b| {
            // Every top has a box here (`build` gave up otherwise).
            let mask = b.map_or(u32::MAX << PLANE_RECEIVERS, |b| {
                let b = Bounds::new(b.min, b.max);
                let (c, r) = b.ball();
                blocks(c, r, b)
            });
            if mask != 0 {
                full |= self.top_shadow.push(index(top) | mask).is_err();
            }
        });
        if full {
            return None;
        }
        let Some(sp) = self.shadow.get_mut(Kind::Plane as usize) else {
            return Some(());
        };
        for (j, p) in view.primitives().planes.iter().enumerate() {
            // A plane blocks a shadow ray only from a point on its far side from the
            // light; its own points cannot be shadowed by it (shadow rays skip the
            // primitive they leave), so only the other planes' points count.
            let other_flats = if cp.iter().any(|&i| usize::from(i) == j) {
                flats_but(Some(j))
            } else {
                flats
            };
            let mut mask = 0u32;
            for (l, light) in lights.iter().enumerate() {
                let at = light.kind();
                let across = |v: &Bounds| !v.is_empty() && !v.beyond_plane(&p.geometry, at);
                mask |= u32::from(across(&other_flats)) << (PLANE_RECEIVERS + l);
                mask |= u32::from(across(&solids)) << (SOLID_RECEIVERS + l);
            }
            if mask != 0 && sp.push(index(j) | mask).is_err() {
                return None;
            }
        }
        Some(())
    }
}

/// `i` as a list entry (lists never exceed [`INDEXABLE`], see [`lend`]).
fn index(i: usize) -> u32 {
    (i & 0xffff) as u32
}

/// The lists of each kind, then `tops`, as slices (see [`LISTS`]).
fn lists_of<'l, T>(kinds: &'l [&mut VecView<T>; KINDS], tops: &'l VecView<T>) -> [&'l [T]; LISTS] {
    core::array::from_fn(|k| kinds.get(k).map_or(&tops[..], |l| &l[..]))
}

/// Pushes the index of every primitive of `list` that `keep` accepts.
fn fill<G>(out: &mut VecView<u16>, list: &[Primitive<G>], keep: impl Fn(&G) -> bool) {
    for (i, p) in list.iter().enumerate() {
        if keep(&p.geometry) {
            // Cannot fail: the list's capacity is the scene's.
            let _ = out.push((i & 0xffff) as u16);
        }
    }
}

/// Pushes `index | mask` for every primitive of `list` whose light mask is not 0.
fn fill_masked<G>(out: &mut VecView<u32>, list: &[Primitive<G>], mask: impl Fn(&G) -> u32) {
    for (i, p) in list.iter().enumerate() {
        let m = mask(&p.geometry);
        if m != 0 {
            // Cannot fail: the list's capacity is the scene's.
            let _ = out.push(index(i) | m);
        }
    }
}

/// A ball around a bounded extent, for the shadow lists' capsule tests (`None`
/// for a plane): a sphere's own, the triangle's of [`ball`], a box's centre and
/// half-diagonal.
#[inline(always)]
fn ball_of(e: Extent) -> Option<(Vec3, f32)> {
    match e {
        Extent::Ball { center, radius } => Some((center, radius)),
        Extent::Points(p) => Some(ball(&p)),
        Extent::Box { min, max } => Some(Bounds::new(min, max).ball()),
        Extent::Plane { .. } => None,
    }
}

/// A ball around points: their centroid and the largest distance to it.
fn ball(points: &[Vec3; 3]) -> (Vec3, f32) {
    let [a, b, c] = *points;
    let m = (a + b + c) * (1.0 / 3.0);
    let r = points
        .iter()
        .map(|p| (*p - m).length())
        .fold(0.0, crate::math::max);
    (m, r)
}

/// May a blocker inside `b` block a shadow ray from a point of `region` (on
/// `plane`) to the light at `light`? A ray from a point `p` of the plane to the
/// light meets a point `x` of the blocker only if `x` lies between the plane and the
/// light's level (`0 < s(x) < s(L)`, `s` the signed distance on the light's side)
/// and `p` is the projection of `x` from the light onto the plane,
/// `L + (x - L) s(L) / (s(L) - s(x))`: the blocker's shadow. A projection from a
/// point maps the box's part between the plane and the light into the convex hull
/// of its corners' projections (and, where the box dips below the plane, of its
/// crossing with the plane, inside the box itself). Corners within 1/64 of the
/// light's level make the shadow unbounded (or the projection ill-conditioned: it
/// magnifies by at most 64 otherwise, and the clearance [`MARGIN`] covers 64 times
/// the rounding of the rays): then the blocker is kept.
fn shadow_meets(plane: &Plane, light: LightKind, b: Bounds, region: Bounds) -> bool {
    // Without the feature `sun`, the match has one arm.
    #[cfg_attr(not(feature = "sun"), allow(clippy::infallible_destructuring_match))]
    let light = match light {
        LightKind::Point(at) => at,
        #[cfg(feature = "sun")]
        LightKind::Directional(toward) => return sun_shadow_meets(plane, toward, b, region),
    };
    let (p0, n) = (plane.point(), plane.normal());
    let s_light = n.dot(light - p0);
    let (n, s_light) = if s_light < 0.0 {
        (-n, -s_light)
    } else {
        (n, s_light)
    };
    let clearance = MARGIN * (mag(light) + b.magnitude() + region.magnitude() + mag(p0));
    // A light on the plane (or a NaN): anything may be in the way.
    let off_plane = s_light > clearance; // false for NaN
    if !off_plane {
        return true;
    }
    let limit = s_light * (1.0 - 1.0 / 64.0);
    let project = |x: Vec3, s: f32| light + (x - light) * (s_light / (s_light - s));
    projection_meets(b, (p0, n), limit, project, (region, clearance))
}

/// Whether the shadow of the box `b` on the plane `(p0, n)` (`n` turned to the
/// light's side), `project` taking a corner `x` at signed distance `s > 0` to
/// its shadow, comes within `clearance` of `region`: the hull of the corners'
/// shadows, and the box itself where it dips below the plane. A corner at `limit` or beyond (up to
/// the light's level; or a NaN) makes the shadow unbounded: the blocker is
/// kept.
#[inline(always)]
fn projection_meets(
    b: Bounds,
    (p0, n): (Vec3, Vec3),
    limit: f32,
    project: impl Fn(Vec3, f32) -> Vec3,
    (region, clearance): (Bounds, f32),
) -> bool {
    let mut shadow = Bounds::EMPTY;
    let mut below = false;
    for i in 0..8 {
        let pick = |bit: usize, lo: f32, hi: f32| if i & bit == 0 { lo } else { hi };
        let x = Vec3::new(
            pick(1, b.min.x, b.max.x),
            pick(2, b.min.y, b.max.y),
            pick(4, b.min.z, b.max.z),
        );
        let s = n.dot(x - p0);
        let below_limit = s < limit; // false for NaN
        if !below_limit {
            return true;
        }
        if s <= 0.0 {
            below = true;
        } else {
            shadow = shadow.with(project(x, s));
        }
    }
    if below {
        shadow = shadow.union(b);
    }
    !shadow.grown(clearance).intersect(region).is_empty()
}

/// [`shadow_meets`] for a directional light, `toward` the unit direction to it:
/// a ray from a point `p` of the plane towards the light meets a point `x` of
/// the blocker above the plane (`s(x) > 0`, `s` the signed distance on the
/// light's side) only if `p = x - toward s(x) / s(toward)`, the projection of
/// `x` along the light's rays. That projection (parallel, so the box's corners'
/// projections bound it) magnifies by `1 / s(toward)`: a light within 1/64 of
/// grazing the plane (or a NaN) keeps the blocker, as a point light near the
/// plane's level does. Where the box dips below the plane, its crossing with the
/// plane is inside the box itself.
#[cfg(feature = "sun")]
fn sun_shadow_meets(plane: &Plane, toward: Vec3, b: Bounds, region: Bounds) -> bool {
    let (p0, n) = (plane.point(), plane.normal());
    let up = n.dot(toward);
    let (n, up) = if up < 0.0 { (-n, -up) } else { (n, up) };
    let steep = up > 1.0 / 64.0; // false for NaN
    if !steep {
        return true;
    }
    let clearance = MARGIN * (1.0 + b.magnitude() + region.magnitude() + mag(p0));
    // No level to stay below: any finite corner projects.
    let project = |x: Vec3, s: f32| x - toward * (s / up);
    projection_meets(b, (p0, n), f32::INFINITY, project, (region, clearance))
}

/// The largest absolute component.
fn mag(v: Vec3) -> f32 {
    v.abs().max_element()
}

/// An axis-aligned box (possibly empty: `min > max`).
#[derive(Clone, Copy, Debug)]
struct Bounds {
    min: Vec3,
    max: Vec3,
}

impl Bounds {
    const EMPTY: Self = Self {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    fn new(min: Vec3, max: Vec3) -> Self {
        Self { min, max }
    }

    /// The box of a bounded extent (`None` for a plane).
    #[inline(always)]
    fn of(e: Extent) -> Option<Self> {
        match e {
            Extent::Ball { center, radius } => {
                let r = Vec3::splat(radius);
                Some(Self::new(center - r, center + r))
            }
            Extent::Points(p) => Some(Self::points(&p)),
            Extent::Box { min, max } => Some(Self::new(min, max)),
            Extent::Plane { .. } => None,
        }
    }

    fn points(points: &[Vec3]) -> Self {
        points.iter().fold(Self::EMPTY, |b, &p| b.with(p))
    }

    fn with(self, p: Vec3) -> Self {
        Self::new(self.min.min(p), self.max.max(p))
    }

    fn union(self, o: Self) -> Self {
        Self::new(self.min.min(o.min), self.max.max(o.max))
    }

    fn intersect(self, o: Self) -> Self {
        Self::new(self.min.max(o.min), self.max.min(o.max))
    }

    fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y && self.min.z <= self.max.z)
    }

    fn is_finite(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }

    /// The ball around the box: its centre and half its diagonal.
    fn ball(&self) -> (Vec3, f32) {
        (
            (self.min + self.max) * 0.5,
            ((self.max - self.min) * 0.5).length(),
        )
    }

    /// Grown by `m` on every side.
    fn grown(self, m: f32) -> Self {
        Self::new(self.min - Vec3::splat(m), self.max + Vec3::splat(m))
    }

    /// The largest absolute coordinate of the box.
    fn magnitude(&self) -> f32 {
        crate::math::max(mag(self.min), mag(self.max))
    }

    /// True when no segment from a point of the box to `light` can come within `r`
    /// of `c` (see the module doc: the capsule around the hull). For a directional
    /// light, the segments are half-lines towards it: the capsule runs from the
    /// box's centre without end.
    fn capsule_misses(&self, light: LightKind, c: Vec3, r: f32) -> bool {
        let (m, rho) = self.ball();
        let (closest, reach) = match light {
            LightKind::Point(light) => {
                let axis = m - light;
                let len2 = axis.length_squared();
                let s = if len2 > 0.0 {
                    ((c - light).dot(axis) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                (light + axis * s, mag(light))
            }
            #[cfg(feature = "sun")]
            LightKind::Directional(toward) => {
                let s = crate::math::max((c - m).dot(toward), 0.0);
                (m + toward * s, 1.0)
            }
        };
        let dist = (c - closest).length();
        let clearance = MARGIN * (mag(c) + r + reach + self.magnitude() + rho);
        // False for NaN: nothing is culled then.
        dist > rho + r + clearance
    }

    /// True when every point of the box lies strictly on the same side of `plane`
    /// as `light`, so that no segment from the box to the light crosses it (for a
    /// directional light: no half-line towards it).
    fn beyond_plane(&self, plane: &Plane, light: LightKind) -> bool {
        let (p0, n) = (plane.point(), plane.normal());
        let (side, reach) = match light {
            LightKind::Point(at) => (n.dot(at - p0), mag(at)),
            #[cfg(feature = "sun")]
            LightKind::Directional(toward) => (n.dot(toward), 1.0),
        };
        let c = (self.min + self.max) * 0.5;
        let h = (self.max - self.min) * 0.5;
        let clearance = MARGIN * (mag(p0) + self.magnitude() + reach);
        // The box's signed distances span n.(c - p0) +- |n|.h.
        let near = crate::math::abs(n.dot(c - p0)) - n.abs().dot(h);
        side.abs() > clearance && near > clearance && (n.dot(c - p0) > 0.0) == (side > 0.0)
    }
}

/// A tile's view frustum: the camera position, the outward unit normals of the four
/// side planes through it, the forward axis with the near and far distances, the
/// directions through the tile's corners, and the scale of the margins.
struct Frustum {
    apex: Vec3,
    sides: [Vec3; 4],
    forward: Vec3,
    near: f32,
    corners: [Vec3; 4],
    /// The truncated frustum's 8 corners: near (0..4) and far (4..8), each set in
    /// the order of `corners`.
    points: [Vec3; 8],
    /// The box around `points`.
    bounds: Bounds,
    /// `|apex| + max |corner direction|` (largest components).
    scale: f32,
}

impl Frustum {
    fn new(basis: &CameraBasis, x0: f32, y0: f32, x1: f32, y1: f32) -> Option<Self> {
        let apex = basis.position();
        let (forward, near, far) = basis.depth_axis();
        let corners = [(x0, y0), (x1, y0), (x0, y1), (x1, y1)].map(|(x, y)| basis.direction(x, y));
        let centre = basis.direction(0.5 * (x0 + x1), 0.5 * (y0 + y1));
        let mut sides = [Vec3::ZERO; 4];
        // Around the tile: top, right, bottom, left edges of the corner quad.
        for (side, (a, b)) in sides.iter_mut().zip([(0, 1), (1, 3), (3, 2), (2, 0)]) {
            let (a, b) = (corners.get(a)?, corners.get(b)?);
            let n = a.cross(*b).try_normalize()?;
            *side = if n.dot(centre) > 0.0 { -n } else { n };
        }
        let k = far / near;
        let mut points = [apex; 8];
        for (i, d) in corners.iter().enumerate() {
            *points.get_mut(i)? = apex + *d;
            *points.get_mut(i + 4)? = apex + *d * k;
        }
        let bounds = Bounds::points(&points);
        let scale = mag(apex) + corners.iter().map(|d| mag(*d)).fold(0.0, crate::math::max);
        if !(bounds.is_finite() && scale.is_finite()) {
            return None;
        }
        Some(Self {
            apex,
            sides,
            forward,
            near,
            corners,
            points,
            bounds,
            scale,
        })
    }

    /// The clearance for a primitive at `centre` of size `size`.
    fn clearance(&self, centre: Vec3, size: f32) -> f32 {
        MARGIN * (self.scale + mag(centre - self.apex) + size)
    }

    /// True when the ball `(c, r)` lies outside the frustum (beyond a side plane or
    /// before the near plane).
    fn misses_ball(&self, c: Vec3, r: f32) -> bool {
        let m = self.clearance(c, r);
        let v = c - self.apex;
        self.sides.iter().any(|n| n.dot(v) - r > m) || self.forward.dot(v) + r < self.near - m
    }

    /// True when no ray of the tile can reach anything inside `e`.
    #[inline(always)]
    fn misses(&self, e: Extent) -> bool {
        match e {
            Extent::Ball { center, radius } => self.misses_ball(center, radius),
            Extent::Points(p) => self.misses_points(&p),
            Extent::Box { min, max } => self.misses_box(min, max),
            Extent::Plane { point, normal } => self.misses_plane(point, normal),
        }
    }

    /// True when all `points` lie beyond one side plane, or all before the near
    /// plane (so does their convex hull).
    fn misses_points(&self, points: &[Vec3]) -> bool {
        let size = points
            .iter()
            .map(|p| mag(*p - self.apex))
            .fold(0.0, crate::math::max);
        let m = MARGIN * (self.scale + size);
        self.sides
            .iter()
            .any(|n| points.iter().all(|p| n.dot(*p - self.apex) > m))
            || points
                .iter()
                .all(|p| self.forward.dot(*p - self.apex) < self.near - m)
    }

    fn misses_box(&self, min: Vec3, max: Vec3) -> bool {
        let c = (min + max) * 0.5;
        let h = (max - min) * 0.5;
        let m = self.clearance(c, mag(h));
        let v = c - self.apex;
        // The box's least signed distance to a plane of unit normal n: n.v - |n|.h.
        self.sides.iter().any(|n| n.dot(v) - n.abs().dot(h) > m)
            || self.forward.dot(v) + self.forward.abs().dot(h) < self.near - m
    }

    /// True when the camera lies strictly off `plane` and every corner direction
    /// points away from it: no ray of the tile can reach it.
    fn misses_plane(&self, p0: Vec3, n: Vec3) -> bool {
        let side = n.dot(self.apex - p0);
        let m = MARGIN * (self.scale + mag(p0));
        crate::math::abs(side) > m
            && self.corners.iter().all(|d| {
                let away = n.dot(*d);
                (away > 0.0) == (side > 0.0) && crate::math::abs(away) > MARGIN * mag(*d)
            })
    }

    /// `b` grown by its clearance, clipped to the box of the truncated frustum grown
    /// by the same (a computed hit point may lie a few ulps outside either).
    fn clip(&self, b: Bounds) -> Bounds {
        if b.is_empty() {
            return b;
        }
        let m = MARGIN * (self.scale + b.magnitude());
        b.grown(m).intersect(self.bounds.grown(m))
    }

    /// A box around the part of `plane` inside the truncated frustum: the points
    /// where it crosses the 12 edges of the frustum (the vertices of that polygon),
    /// grown by their clearance.
    fn on_plane(&self, plane: &Plane) -> Bounds {
        const EDGES: [(usize, usize); 12] = [
            (0, 1),
            (1, 3),
            (3, 2),
            (2, 0),
            (4, 5),
            (5, 7),
            (7, 6),
            (6, 4),
            (0, 4),
            (1, 5),
            (2, 6),
            (3, 7),
        ];
        let (p0, n) = (plane.point(), plane.normal());
        let mut b = Bounds::EMPTY;
        for (i, j) in EDGES {
            let (Some(&a), Some(&c)) = (self.points.get(i), self.points.get(j)) else {
                continue;
            };
            let (sa, sc) = (n.dot(a - p0), n.dot(c - p0));
            if sa == 0.0 {
                b = b.with(a);
            }
            if sc == 0.0 {
                b = b.with(c);
            }
            if (sa < 0.0 && sc > 0.0) || (sa > 0.0 && sc < 0.0) {
                b = b.with(a + (c - a) * (sa / (sa - sc)));
            }
        }
        if b.is_empty() {
            // The plane is a candidate, yet crosses no edge within rounding: fall
            // back on the whole frustum.
            b = self.bounds;
        }
        b.grown(MARGIN * (self.scale + b.magnitude() + mag(p0)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtin::{Builtin, chapter_direct};
    use crate::camera::Viewport;
    use core::mem::size_of;
    extern crate std;
    use std::vec::Vec as StdVec;

    #[cfg(feature = "sun")]
    fn bounds(min: [f32; 3], max: [f32; 3]) -> Bounds {
        Bounds {
            min: Vec3::new(min[0], min[1], min[2]),
            max: Vec3::new(max[0], max[1], max[2]),
        }
    }

    /// A sun's capsule runs from the visible points towards it without end: a
    /// ball beside that half-line is culled, one on it (however far) is kept,
    /// and one behind the points (away from the sun) is culled.
    #[cfg(feature = "sun")]
    #[test]
    fn a_suns_capsule_is_a_half_line_towards_it() {
        let seen = bounds([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]);
        let up = LightKind::Directional(Vec3::Y);
        assert!(seen.capsule_misses(up, Vec3::new(5.0, 0.0, 0.0), 0.5));
        assert!(!seen.capsule_misses(up, Vec3::new(0.0, 1e6, 0.0), 0.5));
        assert!(!seen.capsule_misses(up, Vec3::new(1.5, 40.0, 0.0), 0.5));
        assert!(seen.capsule_misses(up, Vec3::new(0.0, -5.0, 0.0), 0.5));
        // A point light at the same place as the far ball would not reach it.
        let near = LightKind::Point(Vec3::new(0.0, 10.0, 0.0));
        assert!(seen.capsule_misses(near, Vec3::new(0.0, 1e6, 0.0), 0.5));
    }

    /// A blocker's shadow along a sun's rays on the floor `y = 0`: the box
    /// `[4, 5] x [1, 2]` (in x and y) projects to `x - y dx / dy`, where
    /// `(dx, dy)` points to the sun: straight up, `[4, 5]`; from the upper
    /// right at 45 degrees, `[2, 4]`; from `(3, 1)`, `[-2, 2]`, which meets the
    /// visible floor `[-1, 1]`.
    #[cfg(feature = "sun")]
    #[test]
    fn a_suns_shadow_on_a_plane_is_the_parallel_projection() {
        let floor = Plane::try_new(Vec3::ZERO, Vec3::Y).unwrap();
        let seen = bounds([-1.0, 0.0, -1.0], [1.0, 0.0, 1.0]);
        let blocker = bounds([4.0, 1.0, -0.5], [5.0, 2.0, 0.5]);
        let sun =
            |x: f32, y: f32| LightKind::Directional(Vec3::new(x, y, 0.0).normalize_or(Vec3::Y));
        assert!(!shadow_meets(&floor, sun(0.0, 1.0), blocker, seen));
        assert!(!shadow_meets(&floor, sun(1.0, 1.0), blocker, seen));
        assert!(shadow_meets(&floor, sun(3.0, 1.0), blocker, seen));
        // Grazing the floor: anything may be in the way.
        assert!(shadow_meets(&floor, sun(1.0, 0.001), blocker, seen));
        // A sun below the floor lights its other side: the blocker above it
        // casts no shadow there.
        assert!(!shadow_meets(&floor, sun(3.0, -1.0), blocker, seen));
        // A plane between the seen box and the sun shadows it; one beyond it,
        // on the far side from the sun, does not.
        let wall = Plane::try_new(Vec3::new(0.0, 5.0, 0.0), Vec3::Y).unwrap();
        assert!(!seen.beyond_plane(&wall, sun(0.0, 1.0)));
        let below = Plane::try_new(Vec3::new(0.0, -5.0, 0.0), Vec3::Y).unwrap();
        assert!(seen.beyond_plane(&below, sun(0.0, 1.0)));
    }

    /// Per tile of the chapter's scene at 64x64 (tiles of 16, row by row): the
    /// spheres of its camera list, and the spheres whose plane-receiver bit is set
    /// for the light (they may shadow the floor the tile sees).
    fn chapter_tiles() -> StdVec<(StdVec<u16>, StdVec<u16>)> {
        let scene = chapter_direct().unwrap();
        let view = scene.view();
        let renderer = scene
            .renderer(Viewport::new(64, 64), Builtin::ChapterDirect.settings())
            .unwrap();
        let mut out = StdVec::new();
        for ty in 0..4u8 {
            for tx in 0..4u8 {
                let (x0, y0) = (f32::from(tx) * 16.0, f32::from(ty) * 16.0);
                TileStorage::<crate::capacities!(spheres: 4, planes: 1)>::lend(
                    Some(core::array::from_fn(|i| {
                        [4, 1].get(i).copied().unwrap_or(0)
                    })),
                    &mut |lists| {
                        let picks = lists.unwrap().build(
                            renderer.basis(),
                            &view,
                            (x0, y0, x0 + 16.0, y0 + 16.0),
                        );
                        let camera = picks.camera.unwrap()[0].to_vec();
                        let floor_bit = 1 << PLANE_RECEIVERS;
                        let shadow = picks.shadow.map_or_else(StdVec::new, |s| {
                            s.lists[0]
                                .iter()
                                .filter(|&&e| e & floor_bit != 0)
                                .map(|&e| (e & 0xffff) as u16)
                                .collect()
                        });
                        out.push((camera, shadow));
                    },
                );
            }
        }
        out
    }

    /// The lists cull: a tile keeps the spheres it sees, and not the ones on the
    /// other side of the picture (the chapter's red sphere, index 1, is on the left,
    /// the green one, index 2, on the right); the tiles that see the floor on the
    /// left keep the spheres that may shadow it, but not the small yellow sphere
    /// (index 3), whose shadow falls right of the centre, below it.
    #[test]
    fn tile_lists_keep_what_the_tile_may_see_and_no_more() {
        let tiles = chapter_tiles();
        let (left, right): (StdVec<_>, StdVec<_>) = (
            tiles.iter().step_by(4).collect(),
            tiles.iter().skip(3).step_by(4).collect(),
        );
        assert!(left.iter().any(|(c, _)| c.contains(&1)), "{tiles:?}");
        assert!(left.iter().all(|(c, _)| !c.contains(&2)), "{tiles:?}");
        assert!(right.iter().any(|(c, _)| c.contains(&2)), "{tiles:?}");
        assert!(right.iter().all(|(c, _)| !c.contains(&1)), "{tiles:?}");
        // Every visible sphere appears in some tile, and no tile keeps all four.
        for i in 0..4 {
            assert!(tiles.iter().any(|(c, _)| c.contains(&i)), "{i}: {tiles:?}");
        }
        assert!(tiles.iter().all(|(c, _)| c.len() < 4), "{tiles:?}");
        // Shadows on the floor: the left column never lists the yellow sphere,
        // some tile lists a sphere.
        assert!(left.iter().all(|(_, s)| !s.contains(&3)), "{tiles:?}");
        assert!(tiles.iter().any(|(_, s)| !s.is_empty()), "{tiles:?}");
    }

    /// The storage a tile is lent: a scene's capacities when it fills them or
    /// when they are small, [`FEW`] of each kind when large capacities hold few
    /// primitives, none when no lists are built.
    #[test]
    fn list_storage_is_lent_by_what_the_scene_holds() {
        // The first kinds' numbers, the later kinds' 0, no top.
        fn k(first: &[usize]) -> [usize; KINDS] {
            core::array::from_fn(|i| first.get(i).copied().unwrap_or(0))
        }
        fn lent<C: Capacities>(held: Option<[usize; KINDS]>) -> Option<[usize; KINDS]> {
            lent_tops::<C>(held.map(|h| core::array::from_fn(|i| h.get(i).copied().unwrap_or(0))))
                .map(|(kinds, tops)| {
                    assert_eq!(tops, 0);
                    kinds
                })
        }
        // The capacities of the kinds' lists and of the tops'.
        fn lent_tops<C: Capacities>(
            held: Option<[usize; LISTS]>,
        ) -> Option<([usize; KINDS], usize)> {
            let mut caps = None;
            TileStorage::<C>::lend(held, &mut |lists| {
                caps = lists.as_ref().map(|l| {
                    let kinds: [usize; KINDS] = core::array::from_fn(|k| l.camera[k].capacity());
                    let shadow: [usize; KINDS] = core::array::from_fn(|k| l.shadow[k].capacity());
                    assert_eq!(kinds, shadow);
                    assert_eq!(l.tops.capacity(), l.top_shadow.capacity());
                    (kinds, l.tops.capacity())
                });
            });
            caps
        }
        // Small capacities: exactly them, whatever they hold.
        assert_eq!(
            lent::<crate::capacities!(spheres: 4, planes: 1)>(Some(k(&[4, 1, 0, 0]))),
            Some(k(&[4, 1, 0, 0]))
        );
        assert_eq!(
            lent::<crate::capacities!(spheres: 4, planes: 1)>(Some(k(&[0, 0, 0, 0]))),
            Some(k(&[4, 1, 0, 0]))
        );
        // A scene file's large capacities holding a few primitives: FEW each.
        let few = Some([FEW; KINDS]);
        assert_eq!(
            lent::<crate::capacities!(spheres: 512, planes: 16, triangles: 8192, boxes: 256)>(
                Some(k(&[3, 1, 12, 0]))
            ),
            few
        );
        assert_eq!(
            lent::<crate::capacities!(spheres: 512, planes: 16, triangles: 8192, boxes: 256)>(
                Some([FEW; KINDS])
            ),
            few
        );
        // One list beyond FEW: the capacities.
        let all = Some(k(&[512, 16, 8192, 256]));
        assert_eq!(
            lent::<crate::capacities!(spheres: 512, planes: 16, triangles: 8192, boxes: 256)>(
                Some(k(&[3, 1, FEW + 1, 0]))
            ),
            all
        );
        // No lists (a hierarchy, or culling off), and capacities beyond a u16 index.
        assert_eq!(
            lent::<crate::capacities!(spheres: 4, planes: 1)>(None),
            None
        );
        assert_eq!(
            lent::<crate::capacities!(spheres: 4, planes: 1, triangles: { INDEXABLE + 1 })>(Some(
                k(&[4, 1])
            )),
            None
        );
        // The tops: none without a mesh, FEW_TOPS or MAX_TOPS entries, no lists
        // beyond.
        let with = |tops: usize| {
            let mut held = [0; LISTS];
            held[0] = 4;
            held[KINDS] = tops;
            lent_tops::<crate::capacities!(spheres: 4, planes: 1)>(Some(held)).map(|(_, t)| t)
        };
        #[cfg(feature = "bvh")]
        {
            assert_eq!(with(0), Some(0));
            assert_eq!(with(1), Some(FEW_TOPS));
            assert_eq!(with(FEW_TOPS), Some(FEW_TOPS));
            assert_eq!(with(FEW_TOPS + 1), Some(SOME_TOPS));
            assert_eq!(with(SOME_TOPS), Some(SOME_TOPS));
            assert_eq!(with(SOME_TOPS + 1), Some(MAX_TOPS));
            assert_eq!(with(MAX_TOPS), Some(MAX_TOPS));
        }
        assert_eq!(with(MAX_TOPS + 1), None);
    }

    /// The RAM of a tile's lists, as the docs state it: 6 bytes a primitive of capacity
    /// plus two lengths a kind (and alignment), plus the two views a kind that
    /// `TileLists` holds.
    #[test]
    fn list_storage_is_sized_by_the_capacities() {
        let lengths = size_of::<[usize; 2 * KINDS]>();
        // The chapter's scenes (4 spheres, 1 plane) and the showcase (3, 2, 4, 2).
        let chapter = size_of::<TileStorage<crate::capacities!(spheres: 4, planes: 1)>>();
        let showcase = size_of::<
            TileStorage<crate::capacities!(spheres: 3, planes: 2, triangles: 4, boxes: 2)>,
        >();
        assert!(
            chapter >= lengths + 6 * 5 && chapter <= lengths + 6 * 5 + 16,
            "{chapter}"
        );
        assert!(
            showcase >= lengths + 6 * 11 && showcase <= lengths + 6 * 11 + 16,
            "{showcase}"
        );
        assert_eq!(
            size_of::<TileLists<'_>>(),
            size_of::<[usize; 4 * KINDS + 4]>()
        );
    }
}
