//! Triangles, intersected with the watertight test of Woop, Benthin and Wald
//! ("Watertight Ray/Triangle Intersection", JCGT 2013).
//!
//! The test works in a ray-aligned frame where the ray is the `+z` axis through the
//! origin. Every vertex is transformed on its own, so two triangles sharing an edge
//! see bit-identical edge endpoints; an edge function `ax*by - ay*bx` then has the
//! exact sign of the 2D orientation, or is zero (rounding is monotone), and zero is
//! resolved in `f64`. Neighbouring triangles therefore agree on which side of their
//! shared edge the ray passes: no ray leaks between them.

use super::wide::{CANCELS, REACH, W3, gamma64};
use super::{Candidate, Locate, Shape, Surface};
use crate::error::{Error, Field, position};
use crate::math;
use crate::ray::Ray;
use crate::vec::Vec3;

/// The axes of a ray frame: `Z` is the ray direction's dominant axis, `X` and `Y`
/// the other two (swapped when the direction is negative along `Z`, which keeps the
/// winding). A type per permutation, so that the triangle test reads the vertices'
/// components directly instead of choosing them at run time.
pub(crate) trait Axes {
    /// The world axis that is the frame's x.
    const X: usize;
    /// The world axis that is the frame's y.
    const Y: usize;
    /// The world axis that is the frame's z (the ray's dominant axis).
    const Z: usize;
}

macro_rules! axes {
    ($($name:ident = ($x:expr, $y:expr, $z:expr)),*) => {$(
        pub(crate) struct $name;
        impl Axes for $name {
            const X: usize = $x;
            const Y: usize = $y;
            const Z: usize = $z;
        }
    )*};
}
axes!(
    Ax120 = (1, 2, 0),
    Ax210 = (2, 1, 0),
    Ax201 = (2, 0, 1),
    Ax021 = (0, 2, 1),
    Ax012 = (0, 1, 2),
    Ax102 = (1, 0, 2)
);

/// Runs `$body` with the type `$a` bound to the axes numbered `$axes` (see
/// [`Shear::axes`]), or evaluates `$none` for a ray without a frame.
macro_rules! with_axes {
    ($axes:expr, $a:ident => $body:expr, $none:expr) => {{
        use $crate::geometry::triangle::{Ax012, Ax021, Ax102, Ax120, Ax201, Ax210};
        match $axes {
            0 => {
                type $a = Ax120;
                $body
            }
            1 => {
                type $a = Ax210;
                $body
            }
            2 => {
                type $a = Ax201;
                $body
            }
            3 => {
                type $a = Ax021;
                $body
            }
            4 => {
                type $a = Ax012;
                $body
            }
            5 => {
                type $a = Ax102;
                $body
            }
            _ => $none,
        }
    }};
}
#[cfg_attr(not(feature = "bvh"), allow(unused_imports))]
pub(crate) use with_axes;

/// The world axes `(kx, ky)` of the ray frame whose z is the world axis `kz`:
/// the next two in cyclic order, swapped when the direction is negative along
/// `kz` (which keeps the winding, hence the sign of the determinant). Shared by
/// [`Shear::new`] and [`Triangle::sheared_time`] (the `with_axes!` arms spell
/// the same six frames out as types).
const fn frame_axes(kz: usize, neg: bool) -> (usize, usize) {
    let kx = if kz == 2 { 0 } else { kz + 1 };
    let ky = if kx == 2 { 0 } else { kx + 1 };
    if neg { (ky, kx) } else { (kx, ky) }
}

/// Woop's per-ray constants (the ray frame): which axes, the shear `(sx, sy)`, the
/// scale `sz`, and the ray origin in the frame's axes. Computed once per ray and
/// shared by every triangle it is tested against.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Shear {
    /// 0 to 5: the permutation, in the order of the arms of `with_axes!`; 6 when
    /// the direction has no frame (zero or NaN).
    pub(crate) axes: u8,
    sx: f32,
    sy: f32,
    sz: f32,
    origin: Vec3,
    /// The direction in the frame (`(d[kx], d[ky], d[kz])`, as `origin`).
    dir: Vec3,
}

impl Shear {
    /// The ray frame of `ray`.
    #[inline]
    pub(crate) fn new(ray: &Ray) -> Self {
        // The ray frame: z is the direction's dominant axis, so the shear is bounded.
        let (dir, o) = (ray.dir, ray.origin);
        let kz = dir.max_dimension();
        let neg = dir.get(kz) < 0.0;
        // The arm of `with_axes!` for (kz, neg).
        let axes = 2 * kz + usize::from(neg);
        // `(v[kx], v[ky], v[kz])` with `(kx, ky) = frame_axes(kz, neg)`, both
        // vectors at once, in the order of the arms of `with_axes!`.
        let (d, origin) = match axes {
            0 => (Vec3::new(dir.y, dir.z, dir.x), Vec3::new(o.y, o.z, o.x)),
            1 => (Vec3::new(dir.z, dir.y, dir.x), Vec3::new(o.z, o.y, o.x)),
            2 => (Vec3::new(dir.z, dir.x, dir.y), Vec3::new(o.z, o.x, o.y)),
            3 => (Vec3::new(dir.x, dir.z, dir.y), Vec3::new(o.x, o.z, o.y)),
            4 => (dir, o),
            _ => (Vec3::new(dir.y, dir.x, dir.z), Vec3::new(o.y, o.x, o.z)),
        };
        let (sx, sy, sz) = (d.x / d.z, d.y / d.z, 1.0 / d.z);
        Self {
            // A zero (or NaN) direction has no frame.
            axes: if d.z == 0.0 || d.z.is_nan() {
                6
            } else {
                axes as u8
            },
            sx,
            sy,
            sz,
            origin,
            dir: d,
        }
    }
}

/// How far beyond a triangle's box the triangle test lets its ray's point at
/// the reported time lie, relative to the largest distance of a vertex from
/// the ray's origin along the ray's dominant axis ([`Triangle::hit_with`]): a
/// fourth of the clearance `bvh::CLEARANCE` that a hierarchy's node tests
/// grow boxes by (relative to the origin's largest coordinate plus more than
/// the vertices' largest), so that a node holding a triangle is entered by
/// its ray before the triangle's reported time and left after it.
pub(crate) const HIT_SLACK: f32 = 1.0 / 16384.0;

/// A double-sided triangle. Its outward normal follows the winding:
/// `(p1 - p0) x (p2 - p0)`.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Triangle {
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
}

/// The ray-frame quantities of one ray/triangle pair: the edge functions `u, v, w`
/// (weights of `p0, p1, p2` scaled by `det`) and the vertices' ray-frame depths
/// `z_i = sz * a_z` (the hit time is their barycentric mean).
struct Edges {
    u: f32,
    v: f32,
    w: f32,
    det: f32,
    z: [f32; 3],
}

/// The 2D edge function `p x q`. A plain function (and no FMA contraction in Rust)
/// so that every triangle rounds a shared edge identically.
#[inline]
fn edge(px: f32, py: f32, qx: f32, qy: f32) -> f32 {
    px * qy - py * qx
}

/// [`edge`] with exact products: two `f32` products are exact in `f64`, so the sign
/// of the difference is exact. Used only when the `f32` result is zero.
#[inline]
fn edge_f64(px: f32, py: f32, qx: f32, qy: f32) -> f32 {
    (f64::from(px) * f64::from(qy) - f64::from(py) * f64::from(qx)) as f32
}

/// The three edge functions of the projected vertices `a, b, c` with
/// [`edge_f64`]: out of line and cold (a ray through an edge or a vertex is
/// rare), so that the loops which test triangles keep one call, not the `f64`
/// code, in each of their copies (numbers passed as numbers, not an array: no
/// slot in every caller's frame).
#[cold]
#[inline(never)]
fn edges_f64(ax: f32, ay: f32, bx: f32, by: f32, cx: f32, cy: f32) -> (f32, f32, f32) {
    (
        edge_f64(cx, cy, bx, by),
        edge_f64(ax, ay, cx, cy),
        edge_f64(bx, by, ax, ay),
    )
}

impl Triangle {
    /// A triangle from its vertices.
    ///
    /// # Errors
    /// [`Error::NotFinite`]`(`[`Field::TriangleVertex`]`)` if a component is NaN or
    /// infinite, [`Error::OutOfRange`] if it is beyond [`crate::error::MAX_EXTENT`];
    /// [`Error::DegenerateTriangle`] if the vertices are collinear, i.e. the
    /// normal `(p1 - p0) x (p2 - p0)` cannot be normalised (scale-free: any finite
    /// non-zero cross product is accepted, however small).
    pub fn try_new(p0: Vec3, p1: Vec3, p2: Vec3) -> Result<Self, Error> {
        let t = Self {
            p0: position(p0, Field::TriangleVertex)?,
            p1: position(p1, Field::TriangleVertex)?,
            p2: position(p2, Field::TriangleVertex)?,
        };
        match t.cross().try_normalize() {
            Some(_) => Ok(t),
            None => Err(Error::DegenerateTriangle),
        }
    }

    /// A triangle of baked data (`static` tables written by `tessera bake`), not
    /// checked here, in a `const` context: a view checks every baked triangle
    /// against [`Triangle::try_new`] when it takes them
    /// (`SceneView::with_baked`, feature `bvh`), and no other function
    /// takes a triangle made this way without a scene's checks.
    #[must_use]
    pub const fn baked(p0: [f32; 3], p1: [f32; 3], p2: [f32; 3]) -> Self {
        Self {
            p0: Vec3::new(p0[0], p0[1], p0[2]),
            p1: Vec3::new(p1[0], p1[1], p1[2]),
            p2: Vec3::new(p2[0], p2[1], p2[2]),
        }
    }

    /// The vertices `[p0, p1, p2]`.
    #[must_use]
    pub fn vertices(&self) -> [Vec3; 3] {
        [self.p0, self.p1, self.p2]
    }

    /// The unnormalised normal; the constructor guarantees it normalises.
    fn cross(&self) -> Vec3 {
        (self.p1 - self.p0).cross(self.p2 - self.p0)
    }

    /// The edge functions of the ray against this triangle, or `None` when the ray
    /// passes outside an edge or the projected triangle has no area.
    fn edges(&self, ray: &Ray) -> Option<Edges> {
        let shear = Shear::new(ray);
        with_axes!(shear.axes, A => self.edges_with::<A>(&shear), None)
    }

    /// [`Triangle::edges`] in the ray frame of `shear`, whose axes are `A`.
    #[inline(always)]
    fn edges_with<A: Axes>(&self, shear: &Shear) -> Option<Edges> {
        let o = shear.origin;
        let (sx, sy, sz) = (shear.sx, shear.sy, shear.sz);
        let frame = |p: Vec3| Vec3::new(p.get(A::X) - o.x, p.get(A::Y) - o.y, p.get(A::Z) - o.z);
        let (a, b, c) = (frame(self.p0), frame(self.p1), frame(self.p2));
        let (ax, ay) = (a.x - sx * a.z, a.y - sy * a.z);
        let (bx, by) = (b.x - sx * b.z, b.y - sy * b.z);
        let (cx, cy) = (c.x - sx * c.z, c.y - sy * c.z);

        let (mut u, mut v, mut w) = (
            edge(cx, cy, bx, by),
            edge(ax, ay, cx, cy),
            edge(bx, by, ax, ay),
        );
        if u == 0.0 || v == 0.0 || w == 0.0 {
            // The ray may pass exactly through an edge or vertex: settle each sign
            // exactly, as the paper does, so neighbours cannot both say "outside".
            (u, v, w) = edges_f64(ax, ay, bx, by, cx, cy);
        }
        // Zeros count as inside, so a ray through an edge or vertex hits every
        // triangle touching it.
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            // The ray lies in the triangle's plane (or the triangle projects to a line).
            return None;
        }
        Some(Edges {
            u,
            v,
            w,
            det,
            z: [sz * a.z, sz * b.z, sz * c.z],
        })
    }

    /// The hit of a ray with `0 < t < t_max`, in the ray frame `shear` (axes `A`):
    /// what the renderer calls for each triangle, with the per-ray work done once.
    #[inline(always)]
    pub(crate) fn hit_with<A: Axes>(&self, shear: &Shear, t_max: f32) -> Option<Candidate> {
        let e = self.edges_with::<A>(shear)?;
        // t = (u z0 + v z1 + w z2) / det, evaluated as the barycentric mean of the
        // depths. Woop's delayed division forms `u z0 + ...`, a product of three
        // lengths, which leaves the f32 range for scenes scaled beyond about 2^+-40
        // (its bits then change with the scale); the barycentrics are scale-free and
        // the depths linear, so every quantity here stays within the range of the
        // squared lengths that the edge functions need anyway.
        let inv = 1.0 / e.det;
        let (b0, b1, b2) = (e.u * inv, e.v * inv, e.w * inv);
        let [z0, z1, z2] = e.z;
        let t = b0 * z0 + b1 * z1 + b2 * z2;
        // With every depth positive (the triangle wholly ahead of the origin's
        // depth) the three terms add up. A vertex behind it (a sign bit set) makes
        // them cancel, leaving an error of a few ulps of the largest term: for a
        // triangle far larger than its distance (a floor reaching behind the
        // camera), more than the whole time. Then the time comes from `f64`.
        // Bounded before the range test, whatever `t_max`: a triangle's time
        // is then the same in every search, whichever order it is met in.
        let t = if (z0.to_bits() | z1.to_bits() | z2.to_bits()) >> 31 == 0 {
            self.near_box(shear, [A::X, A::Y, A::Z], e.z, t, false)
        } else {
            // The terms' magnitude (b_i >= 0).
            let m = math::abs(b0 * z0) + math::abs(b1 * z1) + math::abs(b2 * z2);
            let t = self.straddling_time(shear, t, m);
            self.near_box(shear, [A::X, A::Y, A::Z], e.z, t, true)
        };
        // False for NaN.
        if t > 0.0 && t < t_max {
            Some(Candidate { t, b1, b2, face: 0 })
        } else {
            None
        }
    }

    /// `t`, unless the ray's point at `t` lies more than `s = `[`HIT_SLACK`]`
    /// r` beyond the triangle's box (`r` the largest distance of a vertex from
    /// the origin along the frame's z, `z` the vertices' depths): then the
    /// time nearest `t` at which it lies within `s / 2` of the box. The edge
    /// functions decide from the ray's line, whose distance to the triangle
    /// they bound; the time comes from barycentrics that, for a ray almost in
    /// the triangle's plane, cancel, and may put the point far along the ray
    /// from the triangle (a node test that clipped its box at that time would
    /// then lose a hit the flat search keeps). Within the box as computed
    /// here, the point lies within the box grown by the node tests' clearance,
    /// so every node holding the triangle is entered before `t` and left after
    /// it (module `bvh`, [`HIT_SLACK`]). A time that is the barycentric mean
    /// of the depths lies within their range, so only the frame's x and y are
    /// checked; a time from `straddling_time` (`depth`) is checked on z too.
    /// `axes`: the world's axes of the frame's x, y and z.
    /// NaN stays NaN. Out of line: inlined into the searches' triangle tests
    /// it cost the teapot more than the call does (3,124 against 3,087
    /// Cortex-M4F instructions a pixel at 64x64, `chip-report`).
    #[inline(never)]
    fn near_box(&self, shear: &Shear, axes: [usize; 3], z: [f32; 3], t: f32, depth: bool) -> f32 {
        let (o, d) = (shear.origin, shear.dir);
        let [z0, z1, z2] = z.map(math::abs);
        let slack = HIT_SLACK * math::abs(d.z) * math::max(math::max(z0, z1), z2);
        let outside = |axis: usize, o: f32, d: f32| {
            let (a, b, c) = (
                self.p0.get(axis) - o,
                self.p1.get(axis) - o,
                self.p2.get(axis) - o,
            );
            let p = d * t;
            p < math::min(math::min(a, b), c) - slack || p > math::max(math::max(a, b), c) + slack
        };
        let [x, y, z] = axes;
        if outside(x, o.x, d.x) || outside(y, o.y, d.y) || depth && outside(z, o.z, d.z) {
            self.time_in_box(shear, axes, t, slack)
        } else {
            t
        }
    }

    /// [`Triangle::near_box`]'s rare case, out of line: the time nearest `t`
    /// at which the ray lies within `slack / 2` of the triangle's box (`t`
    /// when it never does, or for NaN).
    #[cold]
    #[inline(never)]
    fn time_in_box(&self, shear: &Shear, axes: [usize; 3], t: f32, slack: f32) -> f32 {
        let (o, [x, y, z]) = (shear.origin, axes);
        let frame = |p: Vec3| Vec3::new(p.get(x) - o.x, p.get(y) - o.y, p.get(z) - o.z);
        let (a, b, c) = (frame(self.p0), frame(self.p1), frame(self.p2));
        let half = Vec3::splat(0.5 * slack);
        let (lo, hi) = (a.min(b).min(c) - half, a.max(b).max(c) + half);
        let (mut t0, mut t1) = (f32::NEG_INFINITY, f32::INFINITY);
        for k in 0..3 {
            let d = shear.dir.get(k);
            if d == 0.0 || d.is_nan() {
                continue;
            }
            let (a, b) = (lo.get(k) / d, hi.get(k) / d);
            let (near, far) = if d < 0.0 { (b, a) } else { (a, b) };
            t0 = math::max(t0, near);
            t1 = math::min(t1, far);
        }
        if t0 <= t1 {
            math::min(math::max(t, t0), t1)
        } else {
            t
        }
    }
}

/// The plane of the triangle `p` in `f64`: a vertex, the normal `e1 x e2` (not
/// normalised) and the magnitudes its rounding error is relative to.
fn wide_plane(p: [Vec3; 3]) -> (W3, W3, W3) {
    let [p0, p1, p2] = p.map(W3::from);
    let (n, mag) = p1.sub(p0).cross(p2.sub(p0));
    (p0, n, mag)
}

/// The time at which the ray `o + t d` meets the plane of the triangle `p`:
/// `n.(p0 - o) / n.d` in `f64`, whose error is `2^-53` of the triangle's size
/// times its distance (see [`super::wide`]), rounded to `f32`. `None` for a ray
/// in the plane.
#[cold]
#[inline(never)]
fn plane_time(p: [Vec3; 3], o: Vec3, d: Vec3) -> Option<f32> {
    let (p0, n, _) = wide_plane(p);
    let t = n.dot(p0.sub(W3::from(o))) / n.dot(W3::from(d));
    let t = t as f32;
    t.is_finite().then_some(t)
}

/// The error bound of a point `x` that was placed on the ray rather than on the
/// triangle `p` (see `Triangle::locate`): its distance from the triangle's plane,
/// measured in `f64` with a bound on that measurement's own error, along the
/// normal (so that `offset_origin` moves the point across the plane by at least
/// that much).
#[inline(never)]
fn plane_distance(p: [Vec3; 3], x: Vec3) -> Vec3 {
    let (p0, n, mag) = wide_plane(p);
    let w = W3::from(x).sub(p0);
    let len = n.length();
    // n's components are off by gamma64(4) of `mag` (two differences, a product
    // and the difference of products), so n.w by gamma64(8) of mag.|w| with its
    // own roundings and w's; |n| by gamma64(4) of |mag| (relative to |n| itself
    // that is large for a sliver, whose products cancel), and the division
    // rounds once.
    let dist = n.dot(w) / len;
    let sliver = mag.length() / len;
    let slack =
        gamma64(9) * mag.dot(w.abs()) / len + (gamma64(5) + gamma64(5) * sliver) * dist.abs();
    n.scaled_up((dist.abs() + slack) / len)
}

impl Triangle {
    /// [`Triangle::hit_with`]'s time when a vertex lies behind the ray's origin:
    /// Woop's time `t` unless its terms' magnitude `m` exceeds it by more than
    /// [`CANCELS`]; then [`Triangle::sheared_time`]. Inlined: the call stays in the
    /// rare branch, with the shear's numbers passed as numbers (a reference would
    /// keep every shear in memory, an array a slot in every caller's frame).
    #[inline(always)]
    fn straddling_time(&self, shear: &Shear, t: f32, m: f32) -> f32 {
        // False for NaN: a NaN time stays what the range test rejects.
        if m <= CANCELS * math::abs(t) {
            return t;
        }
        let (s, o) = (shear, shear.origin);
        self.sheared_time(s.axes, s.sx, s.sy, s.sz, o.x, o.y, o.z, t)
    }

    /// The time of a ray crossing the triangle's plane in `f64`, in the ray's
    /// sheared frame (`axes`, `sx, sy, sz`, the origin `ox, oy, oz`: Woop's test has
    /// already decided that the ray crosses the triangle); 0 (no hit) when the
    /// crossing is within that computation's error of the origin; `t` when it
    /// cannot tell. Out of line, cold and not generic: one copy for every loop
    /// that tests triangles.
    #[cold]
    #[inline(never)]
    #[allow(clippy::too_many_arguments)] // numbers in registers: see `straddling_time`
    fn sheared_time(
        &self,
        axes: u8,
        sx: f32,
        sy: f32,
        sz: f32,
        ox: f32,
        oy: f32,
        oz: f32,
        t: f32,
    ) -> f32 {
        let [sx, sy, sz, ox, oy, oz] = [sx, sy, sz, ox, oy, oz].map(f64::from);
        // `Shear::axes` is 2 kz + (1 for a negative direction along kz).
        let kz = usize::from(axes / 2);
        let (kx, ky) = frame_axes(kz, axes % 2 == 1);
        let mut big = 0.0f64;
        let [a, b, c] = [self.p0, self.p1, self.p2].map(|p| {
            // Woop's `(ax, ay)` and depth of the vertex, in `f64`: each within
            // gamma64(3) of its terms' magnitude, at most `big`.
            let q = W3::from(p.permute(kx, ky, kz)).sub(W3::new(ox, oy, oz));
            let (zx, zy) = ((sx * q.z).abs(), (sy * q.z).abs());
            big = big
                .max(q.x.abs() + zx)
                .max(q.y.abs() + zy)
                .max((sz * q.z).abs());
            W3::new(q.x - sx * q.z, q.y - sy * q.z, sz * q.z)
        });
        // In that frame the ray is the z axis and z is the time: the time is
        // where the plane through a, b, c crosses the z axis.
        let n = b.sub(a).cross_product(c.sub(a));
        let time = n.dot(a) / n.z;
        // The error of that time: the edges are within 2 big (gamma64(4) of it),
        // the normal within 8 big^2 (gamma64(16)), the numerator's terms within
        // 24 big^3 (gamma64(24)). A crossing within it of the origin cannot be
        // told from the origin's own surface (a ray leaving one triangle of a
        // huge ground across its coplanar neighbour): no hit, as pbrt refuses
        // `t` below its bound.
        let (num_err, den_err) = (
            gamma64(24) * 24.0 * big * big * big,
            gamma64(16) * 8.0 * big * big,
        );
        let slack = n.z.abs() - den_err;
        if !(slack > 0.0 && time.is_finite()) {
            return t;
        }
        let err = (num_err + time.abs() * den_err) / slack;
        if time <= err {
            return 0.0;
        }
        time as f32
    }
}

/// A triangle is flat.
impl super::Kinded for Triangle {
    const FLAT: bool = true;

    fn check_baked(&self) -> Result<bool, crate::error::Error> {
        let [a, b, c] = self.vertices();
        Ok(Self::try_new(a, b, c)? == *self)
    }

    fn scaled(&self, f: f32) -> Result<Self, crate::error::Error> {
        let [a, b, c] = self.vertices();
        Self::try_new(a * f, b * f, c * f)
    }

    /// Flat: seen edge-on, a line.
    fn girth(&self) -> super::Girth {
        super::Girth::Thin
    }

    #[inline(always)]
    fn extent(&self) -> super::Extent {
        super::Extent::Points(self.vertices())
    }

    #[inline(always)]
    fn search<'r, V: super::Visit<'r, Self>>(v: &mut V) -> Option<(usize, super::Candidate)> {
        if v.none() || !v.may_hit_hull() {
            return None;
        }
        let shear = Shear::new(v.ray());
        with_axes!(shear.axes, A => v.each(|g, t| g.hit_with::<A>(&shear, t)), None)
    }
}

impl Locate for Triangle {
    /// `aux.x` is `b0`, the weight of `p0`; `aux.z` is 1 when the point is the
    /// ray's rather than the barycentric one.
    #[inline(always)]
    fn locate(&self, ray: &Ray, hit: &Candidate) -> (Vec3, Vec3, Vec3) {
        let (b1, b2) = (hit.b1, hit.b2);
        // b0 is recomputed as u / det rather than 1 - b1 - b2: the subtraction has an
        // absolute error of about one ulp of 1, which is not covered by the relative
        // bound below when b0 is small and p0 is far from the origin.
        let b0 = match self.edges(ray) {
            Some(e) => e.u * (1.0 / e.det),
            None => 1.0 - b1 - b2,
        };
        let b0 = if b0.is_finite() { b0 } else { 1.0 - b1 - b2 };
        let (q0, q1, q2) = (self.p0 * b0, self.p1 * b1, self.p2 * b2);
        // The constructor checked that the normal normalises; Z only keeps it total.
        let normal = self.cross().normalize_or(Vec3::Z);
        // The barycentric point is off by a few ulps of its terms: of the vertices'
        // size. For a triangle far larger than the ray's reach (a wall 10^8 wide
        // seen from 6 units) that is more than the whole view, while the ray's own
        // point is off by ulps of what the ray spans: take it then, at the time of
        // the plane in `f64`. (Sums of the components stand for the largest: the
        // choice only has to be the more accurate one by a wide margin.)
        let terms = q0.abs() + q1.abs() + q2.abs();
        let reach = ray.origin.abs();
        if terms.x + terms.y + terms.z > REACH * (reach.x + reach.y + reach.z + hit.t)
            && let Some(t) = plane_time([self.p0, self.p1, self.p2], ray.origin, ray.dir)
        {
            // aux.z = 1: the point is the ray's (see `error`).
            return (ray.at(t), normal, Vec3::new(b0, 0.0, 1.0));
        }
        (q0 + q1 + q2, normal, Vec3::new(b0, 0.0, 0.0))
    }

    #[inline(always)]
    fn error(&self, _: &Ray, hit: &Candidate, point: Vec3, aux: Vec3) -> Vec3 {
        if aux.z != 0.0 {
            return plane_distance([self.p0, self.p1, self.p2], point);
        }
        let (q0, q1, q2) = (self.p0 * aux.x, self.p1 * hit.b1, self.p2 * hit.b2);
        // pbrt-v4's bound for barycentric interpolation (pbrt 3rd ed. 3.9.6).
        (q0.abs() + q1.abs() + q2.abs()) * math::gamma(7)
    }
}

impl Shape for Triangle {
    fn intersect(&self, ray: &Ray, t_max: f32) -> Option<Candidate> {
        let shear = Shear::new(ray);
        with_axes!(shear.axes, A => self.hit_with::<A>(&shear, t_max), None)
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        // A triangle has one hit at most: any hit is the nearest.
        self.intersect(ray, t_max).is_some()
    }

    fn surface(&self, ray: &Ray, hit: &Candidate) -> Surface {
        super::surface(self, ray, hit)
    }

    fn uv(&self, _surface: &Surface, hit: &Candidate) -> [f32; 2] {
        [hit.b1, hit.b2]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::test_rand as rand;

    /// The ray frame's vectors are the components `(kx, ky, kz)` of
    /// [`frame_axes`], for every dominant axis and sign.
    #[test]
    fn shear_permutes_as_frame_axes() {
        for kz in 0..3 {
            for neg in [false, true] {
                let dir = Vec3::new(0.25, 0.5, 0.125).with(kz, if neg { -0.75 } else { 0.75 });
                let origin = Vec3::new(1.0, 2.0, 3.0);
                let s = Shear::new(&Ray { origin, dir });
                let (kx, ky) = frame_axes(kz, neg);
                let d = dir.permute(kx, ky, kz);
                assert_eq!(usize::from(s.axes), 2 * kz + usize::from(neg));
                assert_eq!(s.origin, origin.permute(kx, ky, kz));
                assert_eq!((s.sx, s.sy, s.sz), (d.x / d.z, d.y / d.z, 1.0 / d.z));
            }
        }
    }

    const INF: f32 = f32::INFINITY;
    const FAR: Vec3 = Vec3::new(148_376.0, 1234.0, -223_423.0);

    fn v(x: f32, y: f32, z: f32) -> Vec3 {
        Vec3::new(x, y, z)
    }

    fn near(a: f32, b: f32, tol: f32) -> bool {
        (a - b).abs() <= tol
    }

    fn tri(a: Vec3, b: Vec3, c: Vec3) -> Triangle {
        Triangle::try_new(a, b, c).unwrap()
    }

    fn ray_to(origin: Vec3, target: Vec3) -> Ray {
        Ray::unit(origin, (target - origin).try_normalize().unwrap())
    }

    /// The triangle (0,0,2), (4,0,2), (0,4,2): normal +z.
    fn flat() -> Triangle {
        tri(v(0.0, 0.0, 2.0), v(4.0, 0.0, 2.0), v(0.0, 4.0, 2.0))
    }

    #[test]
    fn hit_at_known_t_and_barycentrics() {
        // (1, 2, 2) = p0 + 0.25 (p1 - p0) + 0.5 (p2 - p0), aimed at from 3 units away.
        let target = v(1.0, 2.0, 2.0);
        for dir in [Vec3::Z, v(0.6, 0.0, 0.8), v(0.0, -0.6, 0.8)] {
            let ray = Ray::unit(target - dir * 3.0, dir);
            let h = flat().intersect(&ray, INF).unwrap();
            assert!(near(h.t, 3.0, 1e-6), "{dir:?} {h:?}");
            assert!(near(h.b1, 0.25, 1e-6) && near(h.b2, 0.5, 1e-6), "{h:?}");
            let s = flat().surface(&ray, &h);
            assert!((s.point - target).length() < 1e-6);
            assert_eq!((s.normal, flat().uv(&s, &h)), (Vec3::Z, [h.b1, h.b2]));
            assert!(flat().occluded(&ray, INF));
        }
    }

    #[test]
    fn misses_outside_behind_and_hits_back_face() {
        for ray in [
            Ray::unit(v(3.0, 3.0, 0.0), Vec3::Z),
            Ray::unit(v(1.0, 1.0, 0.0), -Vec3::Z),
        ] {
            assert_eq!(flat().intersect(&ray, INF), None);
            assert!(!flat().occluded(&ray, INF));
        }
        // Double-sided; the normal still follows the winding.
        let back = Ray::unit(v(1.0, 1.0, 7.0), -Vec3::Z);
        let h = flat().intersect(&back, INF).unwrap();
        assert_eq!((h.t, flat().surface(&back, &h).normal), (5.0, Vec3::Z));
    }

    #[test]
    fn parallel_and_grazing_rays_give_no_nan() {
        let parallel = Ray::unit(v(-1.0, 1.0, 0.0), Vec3::X);
        assert_eq!(flat().intersect(&parallel, INF), None);
        // In the triangle's plane, through its interior.
        for dir in [Vec3::X, Vec3::Y, v(0.6, 0.8, 0.0), v(-0.8, 0.6, 0.0)] {
            let ray = Ray::unit(v(1.0, 1.0, 2.0) - dir * 5.0, dir);
            if let Some(h) = flat().intersect(&ray, INF) {
                assert!(h.t > 0.0 && h.t.is_finite() && h.b1.is_finite() && h.b2.is_finite());
            }
        }
    }

    #[test]
    fn t_max_is_exclusive() {
        let ray = Ray::unit(v(1.0, 1.0, -1.0), Vec3::Z);
        assert_eq!(
            (flat().intersect(&ray, 3.0), flat().intersect(&ray, 2.9)),
            (None, None)
        );
        assert!(!flat().occluded(&ray, 3.0));
        assert_eq!(flat().intersect(&ray, 3.001).unwrap().t, 3.0);
    }

    /// The rim of the fan: 8 points around the centre, going up and down.
    fn rim() -> [Vec3; 8] {
        let x = [1.0, 1.0, 0.0, -1.0, -1.0, -1.0, 0.0, 1.0];
        core::array::from_fn(|i| v(x[i], x[(i + 6) % 8], 0.25 - 0.5 * (i % 2) as f32))
    }

    // The origins see the fan steeply (slope above its 0.56 gradient) so that no
    // spoke is a silhouette: a ray that merely grazes a ridge may rightly miss it.
    #[test]
    fn fan_is_watertight_at_its_vertex_and_shared_edges() {
        for center in [Vec3::ZERO, FAR] {
            let r = rim();
            let fan: [Triangle; 8] =
                core::array::from_fn(|i| tri(center, center + r[i], center + r[(i + 1) % 8]));
            // The shared vertex and points on every shared edge, all exact in f32.
            let on_edges = r
                .iter()
                .flat_map(|r| [0.25, 0.5, 0.75].map(|s| center + *r * s));
            let targets: [Vec3; 25] = {
                let mut t = [center; 25];
                t[1..].iter_mut().zip(on_edges).for_each(|(t, p)| *t = p);
                t
            };
            let mut leaks = 0;
            for o in [
                v(0.3, 0.7, 5.0),
                v(-2.0, 1.0, 3.0),
                v(1.0, -3.0, -4.0),
                v(-0.1, 0.2, -1.0),
                v(4.0, 4.0, 8.0),
                v(0.0, 0.0, 2.0),
            ] {
                for target in targets {
                    let ray = ray_to(center + o, target);
                    let hit = fan.iter().any(|t| t.intersect(&ray, INF).is_some());
                    if !hit || !fan.iter().any(|t| t.occluded(&ray, INF)) {
                        leaks += 1;
                    }
                }
            }
            assert_eq!(leaks, 0, "center {center:?}");
        }
    }

    #[test]
    fn closed_octahedron_never_leaks() {
        let mut seed = 0x1234_5678;
        let cases = [
            (Vec3::ZERO, 1.0, Vec3::ZERO),
            (Vec3::ZERO, 1.0, v(0.1, -0.2, 0.3)),
        ];
        for (center, r, offset) in cases.into_iter().chain([(FAR, 1000.0, v(3.0, -7.0, 1.0))]) {
            let oct: [Triangle; 8] = core::array::from_fn(|i| {
                let s = |bit: usize| if i & bit == 0 { r } else { -r };
                tri(
                    center + Vec3::X * s(1),
                    center + Vec3::Y * s(2),
                    center + Vec3::Z * s(4),
                )
            });
            // Towards a vertex and an edge exactly, then pseudo-random directions.
            let special = [Vec3::X, -Vec3::Y, v(1.0, 1.0, 0.0), v(0.0, -1.0, 1.0)];
            let random = (0..3000).map(|_| v(rand(&mut seed), rand(&mut seed), rand(&mut seed)));
            let dirs = special.into_iter().chain(random);
            for d in dirs.filter_map(Vec3::try_normalize) {
                let ray = Ray::unit(center + offset, d);
                let hits = oct.iter().filter_map(|t| t.intersect(&ray, INF));
                assert!(hits.clone().count() >= 1, "leak at {d:?} from {offset:?}");
                assert!(hits.into_iter().all(|h| h.t > 0.0 && h.t < 2.0 * r));
            }
        }
    }

    #[test]
    fn tiny_triangles_hit_by_their_centroid_ray() {
        let c = v(0.3, -0.2, 1.5);
        for s in [1e-4, 3e-4, 1e-3, 1e-2, 1e-1] {
            let t = tri(
                c + v(1.0, 0.0, 0.1) * s,
                c + v(-0.5, 0.866, 0.0) * s,
                c + v(-0.5, -0.866, -0.1) * s,
            );
            let [p0, p1, p2] = t.vertices();
            let centroid = (p0 + p1 + p2) / 3.0;
            let ray = ray_to(Vec3::ZERO, centroid);
            let h = t.intersect(&ray, INF).unwrap();
            // Checked through the point, which does not depend on how unit `dir` is.
            let miss = (ray.at(h.t) - centroid).abs().max_element();
            assert!(miss < 1e-6, "{s} {h:?} {miss}");
            let third = 1.0 / 3.0;
            assert!(
                near(h.b1, third, 1e-2) && near(h.b2, third, 1e-2),
                "{s} {h:?}"
            );
        }
    }

    fn f64s(v: Vec3) -> [f64; 3] {
        [f64::from(v.x), f64::from(v.y), f64::from(v.z)]
    }

    fn dot64(a: [f64; 3], b: [f64; 3]) -> f64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    fn sub64(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }

    // The bound covers the rounding of the interpolation, and so the distance off the
    // plane (what `offset_origin` needs). Barycentric rounding only slides the point
    // within the plane, by a few ulps of the ray's length over the cosine: checked too.
    #[test]
    fn surface_error_bounds_the_point() {
        let mut seed = 0x9e37_79b9;
        let mut worst_slide = 0.0f64;
        for (base, scale) in [(Vec3::ZERO, 1.0), (v(10.0, -3.0, 7.0), 0.01), (FAR, 5.0)] {
            let t = tri(
                base + v(1.0, 0.1, 0.3) * scale,
                base + v(-0.2, 1.3, -0.4) * scale,
                base + v(-0.7, -0.9, 0.8) * scale,
            );
            let [p0, p1, p2] = t.vertices();
            let q = t.vertices().map(f64s);
            let (e1, e2) = (sub64(q[1], q[0]), sub64(q[2], q[0]));
            let n = [0, 1, 2].map(|i| {
                let (j, k) = ((i + 1) % 3, (i + 2) % 3);
                e1[j] * e2[k] - e1[k] * e2[j]
            });
            let n = n.map(|c| c / crate::math::sqrt64(dot64(n, n)));
            for _ in 0..500 {
                // b1, b2 in [0, 0.5), so the target is inside the triangle.
                let (b1, b2) = ((rand(&mut seed) + 1.0) / 4.0, (rand(&mut seed) + 1.0) / 4.0);
                let target = p0 + (p1 - p0) * b1 + (p2 - p0) * b2;
                let o = v(rand(&mut seed), rand(&mut seed), rand(&mut seed));
                let ray = ray_to(target + o * (3.0 * scale), target);
                let Some(h) = t.intersect(&ray, INF) else {
                    continue;
                };
                let s = t.surface(&ray, &h);
                let (p, err) = (f64s(s.point), f64s(s.error));
                assert!(err.iter().all(|&e| e > 0.0));
                // Against the exact interpolation of the same barycentrics.
                let e = t.edges(&ray).unwrap();
                let b = [e.u * (1.0 / e.det), h.b1, h.b2].map(f64::from);
                for i in 0..3 {
                    let exact = b[0] * q[0][i] + b[1] * q[1][i] + b[2] * q[2][i];
                    assert!((p[i] - exact).abs() <= err[i], "{i}: {p:?} {exact} {err:?}");
                }
                // Against the exact plane, along the normal.
                let (off_plane, bound) =
                    (dot64(n, sub64(p, q[0])).abs(), dot64(n.map(f64::abs), err));
                assert!(off_plane <= bound, "{off_plane} > {bound}");
                // Against the exact ray/plane intersection.
                let (ro, rd) = (f64s(ray.origin), f64s(ray.dir));
                let k = dot64(n, sub64(q[0], ro)) / dot64(n, rd);
                let slide = (0..3)
                    .map(|i| (p[i] - ro[i] - rd[i] * k).abs())
                    .fold(0.0, f64::max);
                let len = f64::from(ray.origin.abs().max_element() + s.point.abs().max_element());
                worst_slide = worst_slide.max(slide * dot64(n, rd).abs() / len);
            }
        }
        assert!(worst_slide < 1e-6, "{worst_slide}");
    }

    #[test]
    fn constructor_errors() {
        let (a, b, c) = (Vec3::ZERO, Vec3::X, Vec3::Y);
        let degenerate = Err(Error::DegenerateTriangle);
        assert_eq!(Triangle::try_new(a, b, b * 2.0), degenerate);
        assert_eq!(Triangle::try_new(a, a, c), degenerate);
        let (nan, inf) = (v(0.0, f32::NAN, 0.0), v(0.0, 0.0, -INF));
        for (p, q, r) in [(nan, b, c), (a, inf, c), (a, b, nan)] {
            let err = Err(Error::NotFinite(Field::TriangleVertex));
            assert_eq!(Triangle::try_new(p, q, r), err);
        }
        // Scale-free: a tiny but proper triangle is accepted.
        let tiny = Triangle::try_new(a, b * 1e-20, c * 1e-20).unwrap();
        assert_eq!(tiny.vertices(), [a, b * 1e-20, c * 1e-20]);
    }
}
