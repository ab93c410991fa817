//! A bounding volume hierarchy over a scene's triangles: "a ray should only look at
//! what it can hit".
//!
//! Built without allocation into storage the caller owns ([`Bvh`], capacities `N`
//! nodes and `T` triangles), by binned surface-area heuristic ([`BINS`] bins of the
//! triangles' centroids on each axis, the cheapest split kept; a node of at most [`LEAF`]
//! triangles stays a leaf when splitting does not pay), to a depth of at most
//! [`DEPTH`], so that a traversal needs a stack of [`DEPTH`] node indices. A node is
//! 32 bytes: its triangles' exact bounds, and either the index of its first child
//! (children come in pairs) or the range of its triangles in the BVH's order list.
//!
//! The view links a BVH to the triangles it was built from by a hash of their
//! vertices ([`crate::Error::BvhMismatch`] otherwise).
//!
//! A scene view uses it ([`crate::SceneView::with_bvh`]) when the scene has at least
//! [`CROSSOVER`] triangles: then every ray (camera, shadow, reflected, refracted)
//! searches the other kinds as the flat search does and the triangles through the
//! BVH, and the tiles build no culling lists. The image is the same bytes with or
//! without it:
//!
//! - **conservative bounds**: a node is tested grown by a clearance of
//!   [`CLEARANCE`]` (|origin| + 2 m + e)` for a ray from `origin` (`m` the largest
//!   coordinate of the triangles' bounds, `e` their largest extent). A ray whose
//!   line the triangle test finds on a triangle passes within about
//!   `30 u (|origin| + |point|)` of it (module `cull`), and the test reports a
//!   time at which the ray lies within a fourth of that clearance of the
//!   triangle's box (module `geometry::triangle`'s `HIT_SLACK`, which bounds
//!   the time where the barycentrics of a ray almost in the triangle's plane
//!   cancel); the slab test's roundings stay far inside the clearance
//!   (`NodeRay`). So every node holding the triangle is entered before the
//!   reported time and left after it. A NaN clearance or origin makes every
//!   box "hit";
//! - **the same nearest hit**: the flat search keeps, among equal times, the
//!   earliest triangle of the list; the traversal visits triangles in another order
//!   and so keeps the smallest `(t, index)`: a triangle at the current best time
//!   replaces a later triangle, never a sphere or a plane found before.

use crate::error::{Error, List};
use crate::geometry::triangle::Axes;
use crate::geometry::{Sphere, Triangle};
use crate::primitive::Primitive;
use crate::vec::Vec3;
use heapless::Vec;

/// The deepest a node lies (the root at depth 0): the traversal's stack size.
pub const DEPTH: usize = 32;
/// The bins of the surface-area heuristic.
pub const BINS: usize = 12;
/// The most triangles a leaf holds when a split does not pay (a node deeper than
/// [`DEPTH`] allows, or whose triangles' centroids coincide, holds them all).
pub const LEAF: usize = 4;
/// The cost of descending into a node's children, in triangle tests, for the
/// surface-area heuristic: a node of at most [`LEAF`] triangles is split only when
/// `TRAVERSAL A + n_1 A_1 + n_2 A_2 < n A` (areas `A` of the node and `A_i` of
/// the children). 0 splits down to single triangles (2 n nodes); 2 keeps leaves
/// of 2 to 4 where a split saves less than two triangle tests: a descent tests
/// both children's boxes, which on a chip costs about as much as two triangle
/// tests, and fewer nodes take less flash.
pub const TRAVERSAL: f32 = 2.0;
/// The clearance a node's box is grown by, relative to the ray's origin and
/// the hierarchy's reach: `c = CLEARANCE (|origin| + 2 m + e)` (`|origin|` its
/// largest component; `NodeRay` says why no box holding a hit is rejected).
/// Four times the slack the triangle test leaves its reported time, and far
/// beyond the sphere test's error. A fourth of the culling's clearance: a box
/// grown less is entered by fewer rays (the node tests a search of
/// `bvh-report`'s teapot table). The unit tests
/// `a_node_keeps_every_box_whose_triangle_a_ray_hits` (rays at the vertices and
/// edges) and `a_node_keeps_the_box_of_a_triangle_a_grazing_ray_hits` (rays
/// almost in the plane) check it.
pub const CLEARANCE: f32 = 1.0 / 4096.0;
const _: () = assert!(4.0 * crate::geometry::triangle::HIT_SLACK <= CLEARANCE);
/// The fewest triangles for which [`SceneView::with_bvh`] uses a BVH: below, the
/// flat list (and the tiles' culling) costs less. Measured on the host by
/// `cargo run -p tessera-tests --release --bin bvh-report` (an icosphere and parts
/// of one on a floor, one light, 160x120, side by side), which prints the BVH's
/// time against the flat search's for each count: about even here, longer below,
/// and far shorter with many more triangles;
/// instruction counts under callgrind (its `--one` mode) give the same crossover.
///
/// [`SceneView::with_bvh`]: crate::SceneView::with_bvh
pub const CROSSOVER: usize = 100;
/// The fewest spheres for which [`SceneView::with_sphere_bvh`] uses a BVH,
/// measured as [`CROSSOVER`] (`bvh-report`'s sphere table: a grid of spheres on a
/// floor, 160x120): more than for triangles (a sphere's test is cheaper than a
/// triangle's, and the flat list has the tiles' culling).
///
/// [`SceneView::with_sphere_bvh`]: crate::SceneView::with_sphere_bvh
pub const SPHERE_CROSSOVER: usize = 200;

/// Node tests and searches through a BVH so far (feature `visit-count` only).
#[cfg(feature = "visit-count")]
pub(crate) static VISITS: (
    core::sync::atomic::AtomicUsize,
    core::sync::atomic::AtomicUsize,
) = (
    core::sync::atomic::AtomicUsize::new(0),
    core::sync::atomic::AtomicUsize::new(0),
);

/// `(node tests, searches)` through BVHs since the program started (all threads).
#[cfg(feature = "visit-count")]
#[must_use]
pub fn visits() -> (usize, usize) {
    use core::sync::atomic::Ordering::Relaxed;
    (VISITS.0.load(Relaxed), VISITS.1.load(Relaxed))
}

/// Adds one to a counter of [`VISITS`]. A target without read-modify-write atomics
/// (`thumbv6m-none-eabi`, `riscv32imc-unknown-none-elf`: single-core chips) adds
/// with a load and a store.
#[cfg(feature = "visit-count")]
#[inline(always)]
pub(crate) fn count_visit(counter: &core::sync::atomic::AtomicUsize) {
    use core::sync::atomic::Ordering::Relaxed;
    #[cfg(target_has_atomic = "ptr")]
    counter.fetch_add(1, Relaxed);
    #[cfg(not(target_has_atomic = "ptr"))]
    counter.store(counter.load(Relaxed).wrapping_add(1), Relaxed);
}

/// The largest index a node's `u16` fields hold, plus one.
const INDEXABLE: usize = 1 << 16;

/// A node of a [`Bvh`]: its triangles' bounds and what is below it (28 bytes,
/// aligned to 32 so that a node's address is its index shifted: 28-byte nodes
/// cost the teapot 0.33 % more instructions on the Cortex-M4F, for 4 bytes of
/// flash a node). Public for baked hierarchies ([`BakedBvh`]): generated code
/// writes nodes with [`BvhNode::new`] from the [`BvhNode::parts`] of a built
/// [`Bvh`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[repr(align(32))]
pub struct BvhNode {
    pub(crate) min: Vec3,
    pub(crate) max: Vec3,
    /// An inner node: the index of its first child (the second is the next one);
    /// a leaf: its first entry in [`Bvh::order`].
    pub(crate) first: u16,
    /// A leaf: how many triangles (at least 1); an inner node: 0.
    pub(crate) count: u16,
}

/// A bounding volume hierarchy over at most `T` triangles (and 65,535) in at most
/// `N` nodes (and 65,536): `2 T` nodes are always enough up to 32,767 triangles;
/// beyond, a build that splits down to single triangles may need more than 65,536
/// and fails (the view then keeps the flat lists). Build it with
/// [`Bvh::build`] from the triangles of a scene, then give it to the scene's view
/// with [`SceneView::with_bvh`](crate::SceneView::with_bvh).
///
/// ```
/// use tessera_core::{bvh::Bvh, Camera, Color, Error, material::Material, Scene, geometry::Triangle, Vec3};
///
/// let cam = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 0.1, 100.0)?;
/// let mut scene: Scene<tessera_core::capacities!(triangles: 100, materials: 1)> = Scene::new(cam);
/// let red = scene.add_material(Material::matte(Color::new(0.9, 0.1, 0.1)))?;
/// for i in 0..100 {
///     let x = i as f32 * 0.1;
///     let t = Triangle::try_new(Vec3::new(x, 0.0, 0.0), Vec3::new(x + 0.1, 0.0, 0.0), Vec3::new(x, 1.0, 0.0))?;
///     scene.add_triangle(t, red)?;
/// }
/// let mut bvh: Bvh<200, 100> = Bvh::new();
/// bvh.build(scene.view().triangles())?;
/// let view = scene.view().with_bvh(&bvh)?;
/// assert!(view.uses_bvh());
/// # Ok::<(), Error>(())
/// ```
#[derive(Clone, Debug)]
pub struct Bvh<const N: usize, const T: usize> {
    nodes: Vec<BvhNode, N>,
    /// The triangles' indices, each leaf's a contiguous range.
    order: Vec<u16, T>,
    /// `2 m + e` of the triangles' bounds (see the module doc).
    reach: f32,
    /// A hash of the triangles' vertices it was built from (the view checks it).
    key: u32,
}

/// What a scene view keeps of a [`Bvh`]: no capacities.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BvhView<'a> {
    pub(crate) nodes: &'a [BvhNode],
    pub(crate) order: &'a [u16],
    pub(crate) reach: f32,
}

impl<const N: usize, const T: usize> Default for Bvh<N, T> {
    fn default() -> Self {
        Self::new()
    }
}

/// Keeps [`Bounded`] to the core's shapes: a BVH's searches trust its bounds.
mod sealed {
    pub trait Sealed {}
    impl Sealed for crate::geometry::Triangle {}
    impl Sealed for crate::geometry::Sphere {}
}

/// A shape a BVH holds: triangles and spheres (sealed: the searches trust the
/// bounds).
pub trait Bounded: Copy + sealed::Sealed {
    /// Which kind, mixed into a BVH's key: a BVH of spheres is never taken for
    /// one of triangles with the same numbers.
    const KIND: u32;
    /// Its exact bounds.
    fn bounds(&self) -> (Vec3, Vec3);
    /// The numbers that define it (hashed into a BVH's key).
    fn words(&self) -> [f32; 9];
}

impl Bounded for Triangle {
    const KIND: u32 = 2;
    fn bounds(&self) -> (Vec3, Vec3) {
        let [a, b, c] = self.vertices();
        (a.min(b).min(c), a.max(b).max(c))
    }
    fn words(&self) -> [f32; 9] {
        let [a, b, c] = self.vertices();
        [a.x, a.y, a.z, b.x, b.y, b.z, c.x, c.y, c.z]
    }
}

impl Bounded for Sphere {
    const KIND: u32 = 0;
    fn bounds(&self) -> (Vec3, Vec3) {
        let r = Vec3::splat(self.radius());
        (self.center() - r, self.center() + r)
    }
    fn words(&self) -> [f32; 9] {
        let c = self.center();
        [c.x, c.y, c.z, self.radius(), 0.0, 0.0, 0.0, 0.0, 0.0]
    }
}

/// The exact bounds of a shape.
fn bounds<G: Bounded>(g: &G) -> (Vec3, Vec3) {
    g.bounds()
}

/// Half the surface area of a box (0 for an empty one).
fn half_area((min, max): (Vec3, Vec3)) -> f32 {
    let d = max - min;
    if d.x < 0.0 || d.y < 0.0 || d.z < 0.0 {
        return 0.0;
    }
    d.x * d.y + d.y * d.z + d.z * d.x
}

fn union(a: (Vec3, Vec3), b: (Vec3, Vec3)) -> (Vec3, Vec3) {
    (a.0.min(b.0), a.1.max(b.1))
}

const EMPTY: (Vec3, Vec3) = (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY));

/// The bounds of every geometry of `list` (empty bounds for an empty list).
pub(crate) fn list_bounds<G: Bounded>(list: &[Primitive<G>]) -> (Vec3, Vec3) {
    list.iter()
        .fold(EMPTY, |b, t| union(b, bounds(&t.geometry)))
}

/// [`BINS`] bins of the triangles' centroids along one axis, from the smallest
/// centroid to the largest.
#[derive(Clone, Copy)]
struct Binning {
    axis: usize,
    lo: f32,
    /// Bins per unit length.
    scale: f32,
}

impl Binning {
    /// The bins on `axis` of centroids from `cmin` spreading `spread`; `None`
    /// when they do not spread on that axis.
    fn new(axis: usize, cmin: Vec3, spread: Vec3) -> Option<Self> {
        let (lo, extent) = (along(cmin, axis), along(spread, axis));
        (extent > 0.0 && extent.is_finite()).then(|| Self {
            axis,
            lo,
            scale: BINS as f32 / extent,
        })
    }

    /// The bin of `t`'s centroid.
    fn of<G: Bounded>(self, t: &G) -> usize {
        let (b0, b1) = bounds(t);
        let c = along((b0 + b1) * 0.5, self.axis);
        // Truncation of a non-negative finite value (NaN would give 0).
        let k = ((c - self.lo) * self.scale) as usize;
        k.min(BINS - 1)
    }
}

/// Component `axis` of `v`.
fn along(v: Vec3, axis: usize) -> f32 {
    match axis {
        0 => v.x,
        1 => v.y,
        _ => v.z,
    }
}

/// FNV-1a over the bits of every shape's numbers, in list order.
pub(crate) fn key<G: Bounded>(list: &[Primitive<G>]) -> u32 {
    let mut h = (0x811c_9dc5_u32 ^ G::KIND).wrapping_mul(0x0100_0193);
    for t in list {
        for x in t.geometry.words() {
            for byte in x.to_bits().to_le_bytes() {
                h = (h ^ u32::from(byte)).wrapping_mul(0x0100_0193);
            }
        }
    }
    h
}

impl<const N: usize, const T: usize> Bvh<N, T> {
    /// An empty hierarchy (no triangle).
    #[must_use]
    pub const fn new() -> Self {
        Self {
            nodes: Vec::new(),
            order: Vec::new(),
            reach: 0.0,
            key: 0x811c_9dc5,
        }
    }

    /// Builds the hierarchy of `triangles` (the list of a scene:
    /// [`SceneView::triangles`](crate::SceneView::triangles)), or of its spheres
    /// ([`SceneView::spheres`](crate::SceneView::spheres), for
    /// [`SceneView::with_sphere_bvh`](crate::SceneView::with_sphere_bvh)),
    /// replacing what it held.
    ///
    /// # Errors
    /// [`Error::CapacityExceeded`] for [`List::Triangles`] when there are more
    /// triangles than `T` (or than 65,536), for [`List::BvhNodes`] when the nodes do
    /// not fit in `N`; the hierarchy is then empty.
    pub fn build<G: Bounded>(&mut self, triangles: &[Primitive<G>]) -> Result<(), Error> {
        let built = self.try_build(triangles);
        if built.is_err() {
            *self = Self::new();
        }
        built
    }

    fn try_build<G: Bounded>(&mut self, triangles: &[Primitive<G>]) -> Result<(), Error> {
        *self = Self::new();
        let n = triangles.len();
        if n == 0 {
            return Ok(());
        }
        // A node's count is a u16: at most 65,535 triangles.
        let too_many = Error::CapacityExceeded {
            list: List::Triangles,
            capacity: T.min(INDEXABLE - 1),
        };
        if n > T || n >= INDEXABLE {
            return Err(too_many);
        }
        for i in 0..n {
            let i = u16::try_from(i).map_err(|_| too_many)?;
            self.order.push(i).map_err(|_| too_many)?;
        }
        let all = triangles
            .iter()
            .fold(EMPTY, |b, t| union(b, bounds(&t.geometry)));
        self.reach = reach_of(all);
        self.key = key(triangles);
        self.push_node(triangles, 0, n)?;
        // The nodes still to split, with their depth.
        let mut pending: Vec<(usize, usize), DEPTH> = Vec::new();
        let _ = pending.push((0, 0));
        while let Some((index, depth)) = pending.pop() {
            let Some(&node) = self.nodes.get(index) else {
                continue;
            };
            let (start, count) = (usize::from(node.first), usize::from(node.count));
            if depth + 1 >= DEPTH {
                continue;
            }
            let Some(mid) = self.split(triangles, start, start + count, node) else {
                continue;
            };
            let first = self.nodes.len();
            self.push_node(triangles, start, mid)?;
            self.push_node(triangles, mid, start + count)?;
            let full = self.full();
            if let Some(n) = self.nodes.get_mut(index) {
                n.first = u16::try_from(first).map_err(|_| full)?;
                n.count = 0;
            }
            // Depth-first: at most one pending node per level.
            let _ = pending.push((first + 1, depth + 1));
            let _ = pending.push((first, depth + 1));
        }
        Ok(())
    }

    fn full(&self) -> Error {
        Error::CapacityExceeded {
            list: List::BvhNodes,
            capacity: N.min(INDEXABLE),
        }
    }

    /// Adds the leaf of `order[start..end]`.
    fn push_node<G: Bounded>(
        &mut self,
        triangles: &[Primitive<G>],
        start: usize,
        end: usize,
    ) -> Result<(), Error> {
        let b = self.range_bounds(triangles, start, end, bounds);
        let full = self.full();
        let first = u16::try_from(start).map_err(|_| full)?;
        let count = u16::try_from(end - start).map_err(|_| full)?;
        if self.nodes.len() >= INDEXABLE {
            return Err(full);
        }
        self.nodes
            .push(BvhNode {
                min: b.0,
                max: b.1,
                first,
                count,
            })
            .map_err(|_| full)
    }

    /// The union of `f` of the triangles of `order[start..end]`.
    fn range_bounds<G: Bounded>(
        &self,
        triangles: &[Primitive<G>],
        start: usize,
        end: usize,
        f: impl Fn(&G) -> (Vec3, Vec3),
    ) -> (Vec3, Vec3) {
        self.order
            .get(start..end)
            .unwrap_or(&[])
            .iter()
            .filter_map(|&i| triangles.get(usize::from(i)))
            .fold(EMPTY, |b, t| union(b, f(&t.geometry)))
    }

    /// The split of `order[start..end]` (node `node`) by the surface-area
    /// heuristic: reorders that range so that the first child's triangles come
    /// first and returns where the second child starts; `None` to keep the node a
    /// leaf.
    fn split<G: Bounded>(
        &mut self,
        triangles: &[Primitive<G>],
        start: usize,
        end: usize,
        node: BvhNode,
    ) -> Option<usize> {
        let count = end - start;
        if count <= 1 {
            return None;
        }
        let centroid = |t: &G| {
            let (lo, hi) = bounds(t);
            let c = (lo + hi) * 0.5;
            (c, c)
        };
        let (cmin, cmax) = self.range_bounds(triangles, start, end, centroid);
        let spread = cmax - cmin;
        // The cheapest split over the three axes (an axis whose centroids do not
        // spread has none).
        let mut best: Option<(Binning, usize, f32)> = None;
        for axis in 0..3 {
            if let Some(bins) = Binning::new(axis, cmin, spread)
                && let Some((s, cost)) = self.best_on(triangles, start, end, bins)
                && best.is_none_or(|(_, _, c)| cost < c)
            {
                best = Some((bins, s, cost));
            }
        }
        let (bins, s, cost) = best?;
        let area = half_area((node.min, node.max));
        if count <= LEAF && cost + TRAVERSAL * area >= count as f32 * area {
            return None;
        }
        // Partition: the triangles of bins below `s` first.
        let order = self.order.get_mut(start..end)?;
        let (mut i, mut j) = (0, order.len());
        while i < j {
            let t = &triangles.get(usize::from(*order.get(i)?))?.geometry;
            if bins.of(t) < s {
                i += 1;
            } else {
                j -= 1;
                order.swap(i, j);
            }
        }
        (i > 0 && i < count).then_some(start + i)
    }

    /// The cheapest split of `order[start..end]` between two of the bins
    /// `binning`: the first bin of the second child and the cost of the split.
    fn best_on<G: Bounded>(
        &self,
        triangles: &[Primitive<G>],
        start: usize,
        end: usize,
        binning: Binning,
    ) -> Option<(usize, f32)> {
        let mut bins = [(0usize, EMPTY); BINS];
        for &i in self.order.get(start..end)? {
            let t = &triangles.get(usize::from(i))?.geometry;
            if let Some(b) = bins.get_mut(binning.of(t)) {
                b.0 += 1;
                b.1 = union(b.1, bounds(t));
            }
        }
        // `right[s]`: the triangles of bins `s..` and their bounds.
        let mut right = [(0usize, EMPTY); BINS];
        let mut acc = (0usize, EMPTY);
        for (r, b) in right.iter_mut().zip(bins.iter()).rev() {
            acc = (acc.0 + b.0, union(acc.1, b.1));
            *r = acc;
        }
        // The cost of each split before bin `s`: the triangles on each side times
        // the half area of their bounds.
        let mut best: Option<(usize, f32)> = None;
        let mut left = (0usize, EMPTY);
        for (s, (b, r)) in bins.iter().zip(right.iter().skip(1)).enumerate() {
            left = (left.0 + b.0, union(left.1, b.1));
            if left.0 == 0 || r.0 == 0 {
                continue;
            }
            let cost = left.0 as f32 * half_area(left.1) + r.0 as f32 * half_area(r.1);
            if best.is_none_or(|(_, c)| cost < c) {
                best = Some((s + 1, cost));
            }
        }
        best
    }

    /// The nodes (the root first), for the view and the tests.
    pub(crate) fn view(&self) -> BvhView<'_> {
        BvhView {
            nodes: &self.nodes,
            order: &self.order,
            reach: self.reach,
        }
    }

    /// How many nodes it has.
    #[must_use]
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// How many triangles it was built over.
    #[must_use]
    pub fn triangle_count(&self) -> usize {
        self.order.len()
    }

    /// The hash of the vertices it was built from.
    pub(crate) fn key(&self) -> u32 {
        self.key
    }

    /// The nodes, the root first (what a baker writes out: [`BakedBvh`]).
    #[must_use]
    pub fn nodes(&self) -> &[BvhNode] {
        &self.nodes
    }

    /// The triangles' indices, each leaf's a contiguous range.
    #[must_use]
    pub fn order(&self) -> &[u16] {
        &self.order
    }

    /// The reach of the triangles' bounds, `2 m + e` (see the module doc).
    #[must_use]
    pub fn reach(&self) -> f32 {
        self.reach
    }
}

/// A hierarchy kept where it lies, in flash on a chip: the nodes, order and reach
/// of a [`Bvh`] written out as `static` data by a baker (`tessera bake`), given
/// to a view with its triangles by [`crate::SceneView::with_baked`], which checks it.
#[derive(Clone, Copy, Debug)]
pub struct BakedBvh<'a> {
    nodes: &'a [BvhNode],
    order: &'a [u16],
    reach: f32,
}

impl<'a> BakedBvh<'a> {
    /// The hierarchy of these parts ([`Bvh::nodes`], [`Bvh::order`],
    /// [`Bvh::reach`]); checked when a view takes it.
    #[must_use]
    pub const fn new(nodes: &'a [BvhNode], order: &'a [u16], reach: f32) -> Self {
        Self {
            nodes,
            order,
            reach,
        }
    }
}

impl<'a> BakedBvh<'a> {
    /// What a view keeps of it.
    pub(crate) fn view(&self) -> BvhView<'a> {
        BvhView {
            nodes: self.nodes,
            order: self.order,
            reach: self.reach,
        }
    }
}

/// The reach `2 m + e` of the bounds `all` (see the module doc).
fn reach_of(all: (Vec3, Vec3)) -> f32 {
    let m = crate::math::max(all.0.abs().max_element(), all.1.abs().max_element());
    2.0 * m + (all.1 - all.0).max_element()
}

/// Checks baked `triangles` (each as its constructor makes it, its material one of
/// `materials`) and their hierarchy: the reach of their bounds; each node's box
/// the one the build makes, the union of its children's (children after it) or
/// of its leaf's triangles' bounds (so within its parent, and holding its
/// triangles); leaves in depth-first order covering the order list once, which
/// holds each triangle exactly once. Then every search through it finds what
/// the flat list finds.
/// Memory: a stack of [`DEPTH`] and a bitmap of 128 bytes; time: one pass over the
/// nodes, and one over the order per 1,024 triangles.
pub(crate) fn check_faces(
    n: usize,
    face: impl Fn(usize) -> Result<Primitive<Triangle>, Error>,
    materials: usize,
    bvh: &BakedBvh<'_>,
) -> Result<(), Error> {
    let bad = Error::BvhMismatch;
    if bvh.order.len() != n || n >= INDEXABLE || bvh.nodes.len() > INDEXABLE {
        return Err(bad);
    }
    let mut all = EMPTY;
    for i in 0..n {
        let t = face(i)?;
        let [a, b, c] = t.geometry.vertices();
        if Triangle::try_new(a, b, c)? != t.geometry {
            return Err(bad);
        }
        let id = usize::from(t.material.0);
        if id >= materials {
            return Err(Error::MaterialOutOfRange {
                id: t.material.0,
                count: u16::try_from(materials).unwrap_or(u16::MAX),
            });
        }
        all = union(all, bounds(&t.geometry));
    }
    if n == 0 {
        return if bvh.nodes.is_empty() {
            Ok(())
        } else {
            Err(bad)
        };
    }
    if reach_of(all).to_bits() != bvh.reach.to_bits() {
        return Err(bad);
    }
    // Each entry once: a window of 1,024 indices at a time.
    for base in (0..n).step_by(1024) {
        let mut seen = [0u32; 32];
        for &e in bvh.order {
            let i = usize::from(e);
            if i >= n {
                return Err(bad);
            }
            if let Some(k) = i.checked_sub(base).filter(|&k| k < 1024) {
                let (word, bit) = (k / 32, 1u32 << (k % 32));
                let w = seen.get_mut(word).ok_or(bad)?;
                if *w & bit != 0 {
                    return Err(bad);
                }
                *w |= bit;
            }
        }
    }
    // Depth first, first child first: the leaves' ranges follow each other.
    let root = bvh.nodes.first().ok_or(bad)?;
    if all != (root.min, root.max) {
        return Err(bad);
    }
    let mut stack: Vec<(usize, usize), DEPTH> = Vec::new();
    let _ = stack.push((0, 0));
    let mut next = 0usize;
    let mut visited = 0usize;
    while let Some((i, depth)) = stack.pop() {
        visited += 1;
        let node = bvh.nodes.get(i).ok_or(bad)?;
        let outer = (node.min, node.max);
        let first = usize::from(node.first);
        if node.count == 0 {
            if first <= i || depth + 1 >= DEPTH {
                return Err(bad);
            }
            let mut inner = EMPTY;
            for c in [first, first + 1] {
                let child = bvh.nodes.get(c).ok_or(bad)?;
                inner = union(inner, (child.min, child.max));
            }
            if inner != outer {
                return Err(bad);
            }
            stack.push((first + 1, depth + 1)).map_err(|_| bad)?;
            stack.push((first, depth + 1)).map_err(|_| bad)?;
        } else {
            let end = first + usize::from(node.count);
            if first != next {
                return Err(bad);
            }
            let mut inner = EMPTY;
            for &e in bvh.order.get(first..end).ok_or(bad)? {
                inner = union(inner, bounds(&face(usize::from(e))?.geometry));
            }
            if inner != outer {
                return Err(bad);
            }
            next = end;
        }
    }
    if next != n || visited != bvh.nodes.len() {
        return Err(bad);
    }
    Ok(())
}

impl BvhNode {
    /// A node from its parts (as [`BvhNode::parts`] gives them): the bounds
    /// `min`, `max` of its triangles; an inner node has `count` 0, its children at
    /// `first` and `first + 1`; a leaf has `count` triangles from entry `first`
    /// of the order. For generated code: a
    /// hierarchy made of such nodes is checked when a view takes it
    /// ([`crate::SceneView::with_baked`]).
    #[must_use]
    pub const fn new(min: [f32; 3], max: [f32; 3], first: u16, count: u16) -> Self {
        Self {
            min: Vec3::new(min[0], min[1], min[2]),
            max: Vec3::new(max[0], max[1], max[2]),
            first,
            count,
        }
    }

    /// `(min, max, first, count)`: the arguments of [`BvhNode::new`].
    #[must_use]
    pub fn parts(&self) -> ([f32; 3], [f32; 3], u16, u16) {
        let a = |v: Vec3| [v.x, v.y, v.z];
        (a(self.min), a(self.max), self.first, self.count)
    }

    /// `None` when the ray `r` surely misses the node's box grown by its
    /// clearance between the times 0 and `t_max`; else a time before which the
    /// ray is not in that box (at most `t_max`; NaN when unknown; a NaN anywhere:
    /// `Some`). See [`NodeRay`] for why it never
    /// rejects a box the ray passes through. `known`: the ray's side on an axis
    /// where the caller's code knows it.
    #[inline(always)]
    pub(crate) fn entry(&self, r: &NodeRay, known: Known, t_max: f32) -> Option<f32> {
        // The span `[t0, t1]` of the three slabs, then clipped to `[0, t_max]`:
        // the largest near time and the smallest far time. Comparisons with NaN
        // are false: a NaN slab on y or z leaves the span alone; a NaN on x
        // stays in `t0` (or `t1`), which then rejects nothing.
        let (mut t0, mut t1) = r.x.times(self.min.x, self.max.x, known.flipped(0, r.x));
        let (near, far) = r.y.times(self.min.y, self.max.y, known.flipped(1, r.y));
        if near > t0 {
            t0 = near;
        }
        if far < t1 {
            t1 = far;
        }
        let (near, far) = r.z.times(self.min.z, self.max.z, known.flipped(2, r.z));
        if near > t0 {
            t0 = near;
        }
        if far < t1 {
            t1 = far;
        }
        if t0 > t1 || t0 > t_max || t1 < 0.0 {
            None
        } else {
            Some(t0)
        }
    }
}

/// What a node test needs of a ray, computed once per ray: per axis, the
/// reciprocal direction and the origin shifted by the clearance `c = CLEARANCE
/// (|origin| + reach)` toward each face ([`CLEARANCE`]).
///
/// Why a node test never rejects a box the ray passes through (so that the walk
/// visits every leaf whose triangles the triangle test could report, see the
/// module doc): on an axis with bounds `[lo, hi]`, origin `o` and direction `d`,
/// the test takes the times `(lo - fl(o + c)) fl(1/d)` and `(hi - fl(o - c))
/// fl(1/d)`, four roundings of relative size `u = 2^-24` each. Where they are
/// finite, each is the exact time at which the ray crosses the plane `lo - c`
/// (`hi + c`) moved by at most `4 u (|lo| + |o| + c)` (the plane's distance from
/// the origin carries the roundings of the shift and the difference; the
/// reciprocal's and the product's scale the time, which is the plane moved
/// along the ray's direction by that fraction of its distance). With `m` the
/// largest coordinate of the triangles' bounds, `|lo|, |hi| <= m`, so the
/// planes move by less than `4 u (m + |o| + c) < 2^-9 c`, since `c >= 2^-12
/// (|o| + 2 m)`. So a ray that passes through the box grown by `(1 - 2^-9) c`
/// between the times 0 and `t_max`, in exact arithmetic, passes the test: the
/// computed entry time of each slab is at most the exact entry of the grown
/// box's slab and the computed exit at least its exit. What the node must
/// hold: a triangle's reported time is one at which the ray lies within
/// `2^-14 r` of the triangle's box, `r <= |o| + m` the largest distance of
/// its vertices from the origin along the ray's dominant axis
/// (`Triangle::hit_with` bounds it so), less than `c / 4`; a sphere's hit lies within a few tens of `u (|o| + m)` of the
/// sphere. So the node's computed entry is at most the reported time and its
/// exit at least it, and a node is never clipped away by `t_max` or 0 before
/// a hit it holds. That bound (and so this argument) holds at every scale: all
/// of it is relative to `|o| + m`. A zero direction component gives `1/d = +-inf`:
/// the times are then `+-inf` of the right signs for an origin strictly
/// inside the grown slab (the differences are nonzero there and rounding keeps
/// their signs), and NaN (the slab ignored, the box kept) for an origin on its
/// plane; a NaN or infinite origin or clearance makes every time NaN or
/// infinite so that no slab rejects wrongly (NaN leaves the span alone).
///
/// Unlike [`crate::geometry::Aabb`]'s slab test, the exit is not widened by
/// `1 + 2 gamma(3)`: that widening covers the rounding of the times of the
/// box's own faces, which here lie `c` inside the tested planes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct NodeRay {
    x: Slab,
    y: Slab,
    z: Slab,
}

/// One axis of a [`NodeRay`].
#[derive(Clone, Copy, Debug)]
pub(crate) struct Slab {
    /// The reciprocal direction.
    inv: f32,
    /// `o + c`: a box's time on its low face `lo - c` is `(lo - low) inv`.
    low: f32,
    /// `o - c`: a box's time on its high face `hi + c` is `(hi - high) inv`.
    high: f32,
    /// The sign bit of the direction (that of its reciprocal, `-0` and `-inf`
    /// included): the ray meets the high face first.
    flipped: bool,
}

impl Slab {
    #[inline(always)]
    fn new(o: f32, inv: f32, c: f32) -> Self {
        Self {
            inv,
            low: o + c,
            high: o - c,
            flipped: inv.is_sign_negative(),
        }
    }

    /// The times `(near, far)` at which the ray crosses the grown slab of the
    /// bounds `[lo, hi]`, the high face first when `flipped` (this slab's, or
    /// the same known otherwise).
    #[inline(always)]
    fn times(&self, lo: f32, hi: f32, flipped: bool) -> (f32, f32) {
        let t_lo = (lo - self.low) * self.inv;
        let t_hi = (hi - self.high) * self.inv;
        if flipped { (t_hi, t_lo) } else { (t_lo, t_hi) }
    }
}

/// A ray's side on one axis where the code that tests nodes knows it when it
/// is generated: the triangle test's ray frame (`with_axes!`) has the
/// direction's dominant axis and its sign in its type, so a walk inlined into
/// it need not choose the near face of that axis at run time.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Known {
    /// The axis (0, 1, 2), or 3 for none.
    axis: usize,
    /// Whether the direction is negative along it.
    flipped: bool,
}

impl Known {
    /// Nothing known.
    pub(crate) const NONE: Self = Self {
        axis: 3,
        flipped: false,
    };

    /// What the ray frame `A` knows: its z is the direction's dominant axis,
    /// negative when the frame swaps its x and y (module `triangle`'s
    /// `frame_axes`). A frame is taken only for a direction whose dominant
    /// component is neither zero nor NaN, whose sign bit is then that of its
    /// reciprocal: [`Slab`]'s `flipped`.
    pub(crate) fn of<A: Axes>() -> Self {
        Self {
            axis: A::Z,
            flipped: A::X != (A::Z + 1) % 3,
        }
    }

    /// The side of axis `axis`: known, or the slab's.
    #[inline(always)]
    fn flipped(self, axis: usize, slab: Slab) -> bool {
        if self.axis == axis {
            self.flipped
        } else {
            slab.flipped
        }
    }
}

impl NodeRay {
    /// Whether the direction is negative along `axis` (0, 1, 2), as the node
    /// test reads it.
    #[cfg(test)]
    pub(crate) fn flipped(&self, axis: usize) -> bool {
        [self.x, self.y, self.z]
            .get(axis)
            .is_some_and(|s| s.flipped)
    }

    /// What [`Known`] claims of `axis`, if anything.
    #[cfg(test)]
    pub(crate) fn known(known: Known, axis: usize) -> Option<bool> {
        (known.axis == axis).then_some(known.flipped)
    }

    /// What a walk of `bvh` needs of `ray`.
    #[inline(always)]
    pub(crate) fn new(bvh: &BvhView<'_>, ray: &crate::ray::Ray) -> Self {
        let inv = crate::geometry::aabb_inverse(ray.dir);
        let o = ray.origin;
        let c = CLEARANCE * (o.abs().max_element() + bvh.reach);
        Self {
            x: Slab::new(o.x, inv.x, c),
            y: Slab::new(o.y, inv.y, c),
            z: Slab::new(o.z, inv.z, c),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::MaterialId;

    fn tri(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> Primitive<Triangle> {
        let v = |p: [f32; 3]| Vec3::new(p[0], p[1], p[2]);
        Primitive {
            geometry: Triangle::try_new(v(a), v(b), v(c)).unwrap(),
            material: MaterialId(0),
        }
    }

    /// A grid of `n x n` small triangles in the plane z = x (so no two coincide).
    fn grid(n: usize) -> std::vec::Vec<Primitive<Triangle>> {
        let mut out = std::vec::Vec::new();
        for i in 0..n {
            for j in 0..n {
                let (x, y) = (i as f32, j as f32);
                out.push(tri([x, y, x], [x + 0.9, y, x + 0.9], [x, y + 0.9, x]));
            }
        }
        out
    }

    extern crate std;

    /// Every triangle lies in exactly one leaf, inside the bounds of every node on
    /// its path; depth within [`DEPTH`]; leaves of at most [`LEAF`] triangles
    /// unless their centroids coincide.
    #[test]
    fn every_triangle_is_in_one_leaf_within_its_ancestors_bounds() {
        let tris = grid(20);
        let mut bvh: Bvh<1000, 400> = Bvh::new();
        bvh.build(&tris).unwrap();
        let v = bvh.view();
        let mut seen = [0u8; 400];
        let mut stack = std::vec![(
            0usize,
            0usize,
            (Vec3::splat(f32::NEG_INFINITY), Vec3::splat(f32::INFINITY))
        )];
        while let Some((i, depth, outer)) = stack.pop() {
            assert!(depth < DEPTH);
            let n = v.nodes[i];
            assert!(outer.0.x <= n.min.x && n.max.x <= outer.1.x);
            assert!(outer.0.z <= n.min.z && n.max.z <= outer.1.z);
            if n.count == 0 {
                let f = usize::from(n.first);
                assert!(f > i && f + 1 < v.nodes.len());
                stack.push((f, depth + 1, (n.min, n.max)));
                stack.push((f + 1, depth + 1, (n.min, n.max)));
            } else {
                assert!(usize::from(n.count) <= LEAF, "a leaf of {}", n.count);
                for &t in &v.order[usize::from(n.first)..][..usize::from(n.count)] {
                    let (lo, hi) = bounds(&tris[usize::from(t)].geometry);
                    assert!(
                        n.min.x <= lo.x && hi.x <= n.max.x && n.min.y <= lo.y && hi.y <= n.max.y
                    );
                    seen[usize::from(t)] += 1;
                }
            }
        }
        assert!(seen.iter().all(|&s| s == 1));
        assert!(bvh.node_count() < 2 * 400);
    }

    /// Uniform numbers in `[0, 1)` from a xorshift generator seeded with `seed`.
    fn uniform(mut seed: u32) -> impl FnMut() -> f32 {
        move || {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            (seed >> 8) as f32 / (1u32 << 24) as f32
        }
    }

    /// Whether the one-node hierarchy of `t` keeps its box for `ray` up to the
    /// time the triangle test reports (`None` for no hit).
    fn keeps(t: Triangle, ray: &crate::ray::Ray) -> Option<bool> {
        use crate::geometry::triangle::{Shear, with_axes};
        let prim = [Primitive {
            geometry: t,
            material: MaterialId(0),
        }];
        let mut bvh: Bvh<2, 2> = Bvh::new();
        bvh.build(&prim).unwrap();
        let view = bvh.view();
        let shear = Shear::new(ray);
        let hit = with_axes!(shear.axes, A => t.hit_with::<A>(&shear, f32::INFINITY), None)?;
        let at = NodeRay::new(&view, ray);
        Some(view.nodes[0].entry(&at, Known::NONE, hit.t).is_some())
    }

    /// A ray almost in a triangle's plane: the edge functions cancel, and the
    /// barycentrics the hit's time comes from may put the ray's point far
    /// from the triangle; the time reported must still lie where the ray is in
    /// the triangle's box grown by the node tests' clearance, or a node test
    /// clipping at that time loses a hit the flat search keeps. Rays through
    /// points inside triangles of aspect 1 to 4,096, tilted 2^0 to 2^-23
    /// off their planes, at scales 2^-20, 1 and 2^20, and a case found so
    /// (which fails without the triangle test's bound on its time, whatever
    /// the clearance).
    #[test]
    fn a_node_keeps_the_box_of_a_triangle_a_grazing_ray_hits() {
        use crate::ray::Ray;
        let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
        let found = Triangle::try_new(
            v(-0.315_491_68, 0.967_968_34, 0.544_150_1),
            v(0.054_899_096, -0.293_787_72, -0.785_270_7),
            v(-0.310_468_85, -0.203_953_18, -1.022_389_9),
        )
        .unwrap();
        let ray = Ray::new(
            v(-0.924_798_9, 0.517_718_5, -0.655_918_5),
            v(0.678_623_1, 0.051_120_52, 0.732_705_5),
        )
        .unwrap();
        assert_eq!(keeps(found, &ray), Some(true));
        let mut rand = uniform(0x9e37_79b9);
        let (mut hits, mut lost) = (0usize, std::vec::Vec::new());
        for scale_pow in [-20i32, 0, 20] {
            let s = libm::ldexpf(1.0, scale_pow);
            for aspect in [1.0f32, 4.0, 256.0, 4096.0] {
                for _ in 0..200 {
                    let mut r3 = || v(rand() - 0.5, rand() - 0.5, rand() - 0.5);
                    let (centre, along, across) = (r3() * (4.0 * s), r3(), r3());
                    let along = along.normalize_or(Vec3::X);
                    let across = across.cross(along).normalize_or(Vec3::Y);
                    let (a, b, c) = (
                        centre,
                        centre + along * s,
                        centre + along * (0.5 * s) + across * (s / aspect),
                    );
                    let Ok(t) = Triangle::try_new(a, b, c) else {
                        continue;
                    };
                    let normal = (b - a).cross(c - a).normalize_or(Vec3::Z);
                    for k in 0..24 {
                        let (w1, w2) = (rand(), rand());
                        let (w1, w2) = if w1 + w2 > 1.0 {
                            (1.0 - w1, 1.0 - w2)
                        } else {
                            (w1, w2)
                        };
                        let target = a + (b - a) * w1 + (c - a) * w2;
                        let spin = rand() * core::f32::consts::TAU;
                        let flat =
                            along * libm::cosf(spin) + normal.cross(along) * libm::sinf(spin);
                        let dir = flat + normal * libm::ldexpf(1.0, -k);
                        let origin =
                            target - dir.normalize_or(Vec3::X) * (s * (1.5 + 20.0 * rand()));
                        let Ok(ray) = Ray::new(origin, target - origin) else {
                            continue;
                        };
                        match keeps(t, &ray) {
                            Some(true) => hits += 1,
                            Some(false) => lost.push((t, ray)),
                            None => {}
                        }
                    }
                }
            }
        }
        assert!(
            lost.is_empty(),
            "{} of {} hits lost, the first {:?}",
            lost.len(),
            hits + lost.len(),
            lost.first()
        );
        assert!(hits > 40_000, "{hits} hits");
    }

    /// A node test never rejects the box of a triangle the triangle test hits,
    /// whatever the scale: rays from near and far aimed at the vertices, at
    /// points of the edges and just beyond them, of triangles tilted and lying
    /// in an axis plane (a box of no thickness), at scales from 2^-40 to 2^40
    /// and far from the origin. Each triangle is its own one-node hierarchy,
    /// whose box is the triangle's bounds: the node test must answer `Some`
    /// before the hit's time whenever the triangle test (the one the searches
    /// run, `hit_with` in the ray's frame) reports a hit. With no clearance the
    /// test fails (the rays aimed at the edges of flat triangles graze their
    /// boxes), and with a clearance of 2^-24; it passes with 2^-22.
    #[test]
    fn a_node_keeps_every_box_whose_triangle_a_ray_hits() {
        use crate::geometry::triangle::{Shear, with_axes};
        use crate::ray::Ray;
        let mut rand = uniform(0x2545_f491);
        let (mut hits, mut rays) = (0usize, 0usize);
        for scale_pow in [-40i32, -20, -3, 0, 5, 20, 40] {
            let s = libm::ldexpf(1.0, scale_pow);
            for shape in 0..24 {
                let centre = Vec3::new(rand() - 0.5, rand() - 0.5, rand() - 0.5)
                    * (s * if shape % 3 == 0 { 1000.0 } else { 3.0 });
                let mut corner =
                    || Vec3::new(rand() - 0.5, rand() - 0.5, rand() - 0.5) * s + centre;
                let (mut a, mut b, mut c) = (corner(), corner(), corner());
                // A third of them lie in a plane of x, y or z.
                if shape % 3 == 1 {
                    match shape % 4 {
                        0 => (a.x, b.x, c.x) = (centre.x, centre.x, centre.x),
                        1 => (a.y, b.y, c.y) = (centre.y, centre.y, centre.y),
                        _ => (a.z, b.z, c.z) = (centre.z, centre.z, centre.z),
                    }
                }
                let Ok(t) = Triangle::try_new(a, b, c) else {
                    continue;
                };
                let prim = [Primitive {
                    geometry: t,
                    material: crate::material::MaterialId(0),
                }];
                let mut bvh: Bvh<2, 2> = Bvh::new();
                bvh.build(&prim).unwrap();
                let view = bvh.view();
                let node = view.nodes[0];
                for k in 0..200 {
                    // A vertex, a point of an edge, or a point just beyond one.
                    let (p, q) = match k % 3 {
                        0 => (a, b),
                        1 => (b, c),
                        _ => (c, a),
                    };
                    let along = if k % 5 == 0 { 0.0 } else { rand() };
                    let out = match k % 4 {
                        0 => 0.0,
                        1 => 1e-6,
                        2 => -1e-6,
                        _ => 1e-3 * (rand() - 0.5),
                    };
                    let mid = (a + b + c) * (1.0 / 3.0);
                    let edge = p + (q - p) * along;
                    let target = edge + (edge - mid) * out;
                    let away = [1.5, 20.0, 1e4][k % 3] * s;
                    let from = Vec3::new(rand() - 0.5, rand() - 0.5, rand() - 0.5);
                    let origin = target + from.normalize_or(Vec3::Y) * away;
                    let Ok(ray) = Ray::new(origin, target - origin) else {
                        continue;
                    };
                    rays += 1;
                    let shear = Shear::new(&ray);
                    let hit =
                        with_axes!(shear.axes, A => t.hit_with::<A>(&shear, f32::INFINITY), None);
                    let Some(hit) = hit else {
                        continue;
                    };
                    hits += 1;
                    let at = NodeRay::new(&view, &ray);
                    assert!(
                        node.entry(&at, Known::NONE, hit.t).is_some(),
                        "scale 2^{scale_pow}, {t:?}, {ray:?}: the triangle is hit at {} but \
                         its node is rejected",
                        hit.t
                    );
                }
            }
        }
        assert!(
            rays > 30_000 && hits > rays / 3,
            "{hits} hits of {rays} rays"
        );
    }

    /// The build splits on the axis whose split is cheapest, not on the one
    /// where the centroids spread most: two rows of small triangles 0.5 apart
    /// in y, each 8 long in x, split into the two rows (children whose boxes do
    /// not meet), where a split across x would give two boxes each spanning
    /// both rows (a surface-area cost about twice as large).
    #[test]
    fn the_split_takes_the_cheapest_axis() {
        let mut tris = std::vec::Vec::new();
        for row in [0.0f32, 0.5] {
            for i in 0..32 {
                let x = i as f32 * 0.25;
                tris.push(tri(
                    [x, row, 0.0],
                    [x + 0.2, row, 0.0],
                    [x, row + 0.05, 0.1],
                ));
            }
        }
        let mut bvh: Bvh<256, 64> = Bvh::new();
        bvh.build(&tris).unwrap();
        let v = bvh.view();
        let root = v.nodes[0];
        assert_eq!(root.count, 0, "{root:?}");
        let (a, b) = (
            v.nodes[usize::from(root.first)],
            v.nodes[usize::from(root.first) + 1],
        );
        let (low, high) = if a.min.y < b.min.y { (a, b) } else { (b, a) };
        assert!(low.max.y < high.min.y, "{low:?} {high:?}");
        // Each child holds one whole row.
        assert_eq!((low.min.y, low.max.y), (0.0, 0.05));
        assert_eq!((high.min.y, high.max.y), (0.5, 0.55));
    }

    /// A view takes a BVH only if it was built from its triangles, and uses it
    /// only from [`CROSSOVER`] triangles on.
    #[test]
    fn a_view_checks_its_bvh_and_uses_it_where_it_pays() {
        use crate::{Camera, Color, Scene, material::Material};
        let cam =
            Camera::look_at(Vec3::new(0.0, 0.0, 50.0), Vec3::ZERO, Vec3::Y, 0.1, 100.0).unwrap();
        let mut s: std::boxed::Box<Scene<crate::capacities!(triangles: 400, materials: 1)>> =
            std::boxed::Box::new(Scene::new(cam));
        let m = s.add_material(Material::matte(Color::WHITE)).unwrap();
        for t in grid(10) {
            s.add_triangle(t.geometry, m).unwrap();
        }
        let mut bvh: Bvh<400, 400> = Bvh::new();
        bvh.build(s.view().triangles()).unwrap();
        // 100 triangles: the crossover.
        assert!(s.view().with_bvh(&bvh).unwrap().uses_bvh());
        let mut few: Bvh<400, 400> = Bvh::new();
        few.build(&s.view().triangles()[..CROSSOVER - 1]).unwrap();
        assert_eq!(s.view().with_bvh(&few).err(), Some(Error::BvhMismatch));
        // Another scene of as many triangles, one vertex moved.
        let mut t = grid(10);
        let [a, b, c] = t[7].geometry.vertices();
        t[7].geometry = Triangle::try_new(a, b, c + Vec3::new(0.0, 0.0, 1e-3)).unwrap();
        let mut other: Bvh<400, 400> = Bvh::new();
        other.build(&t).unwrap();
        assert_eq!(s.view().with_bvh(&other).err(), Some(Error::BvhMismatch));
        // Below the crossover the flat lists are kept.
        let mut small: std::boxed::Box<Scene<crate::capacities!(triangles: 400, materials: 1)>> =
            std::boxed::Box::new(Scene::new(cam));
        let m = small.add_material(Material::matte(Color::WHITE)).unwrap();
        for t in &grid(9)[..CROSSOVER - 20] {
            small.add_triangle(t.geometry, m).unwrap();
        }
        let mut b2: Bvh<400, 400> = Bvh::new();
        b2.build(small.view().triangles()).unwrap();
        assert!(!small.view().with_bvh(&b2).unwrap().uses_bvh());
    }

    /// Capacities: too many triangles or too few nodes is an error that leaves the
    /// hierarchy empty; coincident triangles make one leaf.
    #[test]
    fn capacities_are_errors_and_coincident_triangles_one_leaf() {
        let tris = grid(10);
        let mut small: Bvh<1000, 50> = Bvh::new();
        assert_eq!(
            small.build(&tris),
            Err(Error::CapacityExceeded {
                list: List::Triangles,
                capacity: 50
            })
        );
        assert_eq!(small.node_count(), 0);
        let mut few: Bvh<5, 100> = Bvh::new();
        assert_eq!(
            few.build(&tris),
            Err(Error::CapacityExceeded {
                list: List::BvhNodes,
                capacity: 5
            })
        );
        assert_eq!(few.triangle_count(), 0);
        // A node counts its triangles in a u16: 65,535 at most.
        let many = std::vec![tri([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]); 65_536];
        let mut huge: std::boxed::Box<Bvh<4, 70_000>> = std::boxed::Box::default();
        assert_eq!(
            huge.build(&many),
            Err(Error::CapacityExceeded {
                list: List::Triangles,
                capacity: 65_535
            })
        );
        assert!(huge.build(&many[..65_535]).is_ok());
        assert_eq!(huge.node_count(), 1);
        let same = std::vec![tri([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]); 9];
        let mut b: Bvh<20, 9> = Bvh::new();
        b.build(&same).unwrap();
        assert_eq!(b.node_count(), 1);
        assert_eq!(b.view().nodes[0].count, 9);
    }
}

#[cfg(test)]
mod baked_tests {
    use super::*;
    use crate::material::MaterialId;
    use crate::{Camera, Color, Scene, SceneView, material::Material};

    extern crate std;
    use std::vec::Vec as StdVec;

    /// `n x n` pairs of triangles tiling a wavy sheet, materials 0 and 1.
    fn sheet(n: usize) -> StdVec<Primitive<Triangle>> {
        let mut out = StdVec::new();
        let z = |i: usize, j: usize| 0.3 * ((i * 7 + j * 3) % 5) as f32;
        let p = |i: usize, j: usize| Vec3::new(i as f32, j as f32, z(i, j));
        for i in 0..n {
            for j in 0..n {
                let (a, b, c, d) = (p(i, j), p(i + 1, j), p(i + 1, j + 1), p(i, j + 1));
                for (k, t) in [(a, b, c), (a, c, d)].into_iter().enumerate() {
                    out.push(Primitive {
                        geometry: Triangle::try_new(t.0, t.1, t.2).unwrap(),
                        material: MaterialId(k as u16),
                    });
                }
            }
        }
        out
    }

    fn scene() -> Scene<crate::capacities!(materials: 2, lights: 1)> {
        let cam = Camera::look_at(
            Vec3::new(4.0, 5.0, 12.0),
            Vec3::new(4.0, 4.0, 0.0),
            Vec3::Y,
            0.1,
            100.0,
        )
        .unwrap();
        let mut s = Scene::new(cam);
        s.add_material(Material::matte(Color::new(0.9, 0.2, 0.1)))
            .unwrap();
        s.add_material(Material::matte(Color::new(0.1, 0.3, 0.9)))
            .unwrap();
        s.add_light(
            crate::light::Light::point(Vec3::new(3.0, 2.0, 9.0), Color::WHITE, 40.0).unwrap(),
        )
        .unwrap();
        s
    }

    /// A BVH baked from its parts renders what the same triangles render in a
    /// scene with a BVH built at run time, and in a flat list.
    #[test]
    fn a_baked_bvh_renders_the_built_one() {
        let tris = sheet(8);
        let mut bvh: std::boxed::Box<Bvh<256, 128>> = std::boxed::Box::default();
        bvh.build(&tris).unwrap();
        let nodes: StdVec<BvhNode> = bvh
            .nodes()
            .iter()
            .map(|n| {
                let (a, b, f, c) = n.parts();
                BvhNode::new(a, b, f, c)
            })
            .collect();
        let baked = BakedBvh::new(&nodes, bvh.order(), bvh.reach());
        let s = scene();
        let view = s.view().with_baked(&tris, &baked).unwrap();
        assert!(view.uses_bvh());
        let mut flat: std::boxed::Box<
            Scene<crate::capacities!(triangles: 128, materials: 2, lights: 1)>,
        > = std::boxed::Box::new(Scene::new(*s.camera()));
        for m in s.view().materials() {
            flat.add_material(*m).unwrap();
        }
        flat.add_light(s.view().lights()[0]).unwrap();
        for t in &tris {
            flat.add_triangle(t.geometry, t.material).unwrap();
        }
        let vp = crate::Viewport::new(40, 30);
        let render = |v: &SceneView<'_>| {
            let renderer =
                crate::Renderer::try_new(s.camera(), vp, crate::RenderSettings::default()).unwrap();
            let mut px = StdVec::new();
            let (across, down) = renderer.tile_grid(8);
            for ty in 0..down {
                for tx in 0..across {
                    let mut tile = crate::Tile::<8>::new();
                    let coord = crate::TileCoord::new(tx, ty);
                    renderer.render_tile(v, coord, &mut tile, &mut ()).unwrap();
                    px.extend(tile.pixels().map(|p| (p.r, p.g, p.b)));
                }
            }
            px
        };
        let baked_px = render(&view);
        assert_eq!(baked_px, render(&flat.view()));
        assert!(baked_px.iter().any(|&p| p.0 > 100) && baked_px.iter().any(|&p| p.2 > 100));
    }

    /// Every defect of baked data is refused: the scene's own triangles, a
    /// triangle its constructor refuses or would make otherwise, a material out of
    /// range, another reach, a child outside its parent, a triangle outside its
    /// leaf, an order entry twice or out of range, a node no path reaches.
    #[test]
    fn defects_of_baked_data_are_refused() {
        let tris = sheet(6);
        let mut bvh: std::boxed::Box<Bvh<256, 128>> = std::boxed::Box::default();
        bvh.build(&tris).unwrap();
        let (nodes, order) = (bvh.nodes().to_vec(), bvh.order().to_vec());
        let s = scene();
        let check = |t: &[Primitive<Triangle>], n: &[BvhNode], o: &[u16], r: f32| {
            s.view().with_baked(t, &BakedBvh::new(n, o, r)).err()
        };
        assert_eq!(check(&tris, &nodes, &order, bvh.reach()), None);
        let bad = Some(Error::BvhMismatch);
        // A scene with triangles of its own.
        let mut own: Scene<crate::capacities!(triangles: 1, materials: 2, lights: 1)> =
            Scene::new(*s.camera());
        own.add_material(Material::matte(Color::WHITE)).unwrap();
        own.add_triangle(tris[0].geometry, MaterialId(0)).unwrap();
        let b = BakedBvh::new(&nodes, &order, bvh.reach());
        assert_eq!(own.view().with_baked(&tris, &b).err(), bad);
        // Triangles.
        let mut t = tris.clone();
        t[5].geometry = Triangle::baked([0.0; 3], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]);
        assert_eq!(
            check(&t, &nodes, &order, bvh.reach()),
            Some(Error::DegenerateTriangle)
        );
        let mut t = tris.clone();
        t[5].geometry = Triangle::baked([f32::NAN; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        assert!(check(&t, &nodes, &order, bvh.reach()).is_some());
        let mut t = tris.clone();
        t[3].material = MaterialId(2);
        assert_eq!(
            check(&t, &nodes, &order, bvh.reach()),
            Some(Error::MaterialOutOfRange { id: 2, count: 2 })
        );
        // A triangle moved within the bounds of all (the same reach), out of its
        // leaf.
        let mut t = tris.clone();
        let [a, b2, c] = t[9].geometry.vertices();
        let by = Vec3::new(3.0, 0.0, 0.0);
        t[9].geometry = Triangle::try_new(a + by, b2 + by, c + by).unwrap();
        assert_eq!(check(&t, &nodes, &order, bvh.reach()), bad);
        assert_eq!(check(&tris, &nodes, &order, bvh.reach().next_up()), bad);
        // Nodes.
        let root_child = usize::from(nodes[0].first);
        let mut n = nodes.clone();
        n[root_child].max.x += 100.0;
        assert_eq!(check(&tris, &n, &order, bvh.reach()), bad);
        let leaf = nodes.iter().position(|n| n.count > 1).unwrap();
        let mut n = nodes.clone();
        n[leaf].max = n[leaf].min;
        assert_eq!(check(&tris, &n, &order, bvh.reach()), bad);
        let mut n = nodes.clone();
        n[leaf].count -= 1;
        assert_eq!(check(&tris, &n, &order, bvh.reach()), bad);
        let mut n = nodes.clone();
        n.push(nodes[leaf]);
        assert_eq!(check(&tris, &n, &order, bvh.reach()), bad);
        let mut n = nodes.clone();
        n[0].first = 0;
        assert_eq!(check(&tris, &n, &order, bvh.reach()), bad);
        // Every box grown alike (each child still within its parent, each
        // triangle within its leaf), or one leaf's bound made subnormal: not
        // the boxes the build makes.
        let mut n = nodes.clone();
        for node in &mut n {
            node.min.x -= 1.0;
        }
        assert_eq!(check(&tris, &n, &order, bvh.reach()), bad);
        let mut n = nodes.clone();
        for node in n.iter_mut().filter(|node| node.min.x == 0.0) {
            node.min.x = -1e-40;
        }
        assert_eq!(check(&tris, &n, &order, bvh.reach()), bad);
        // The order.
        let mut o = order.clone();
        o[1] = o[0];
        assert_eq!(check(&tris, &nodes, &o, bvh.reach()), bad);
        let mut o = order.clone();
        o[1] = 1000;
        assert_eq!(check(&tris, &nodes, &o, bvh.reach()), bad);
        assert_eq!(check(&tris, &nodes, &order[1..], bvh.reach()), bad);
        assert_eq!(check(&tris[..71], &nodes, &order, bvh.reach()), bad);
    }
}
