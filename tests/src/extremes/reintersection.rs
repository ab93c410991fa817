//! Case 2: re-intersection of secondary rays leaving a surface through `offset_origin`.

use super::{INF, Rng, V3, V3Ext, exact_ray, ray_towards};
use tessera_core::testing::offset_origin;
use tessera_core::testing::refract;
use tessera_core::testing::{Candidate, Shape, Surface};
use tessera_core::{Vec3, geometry::Aabb, geometry::Plane, geometry::Sphere, trace::Ray};

/// Distances of the hit points from the origin in case 2.
pub const MAGNITUDES: [f32; 7] = [0.0, 1.0, 10.0, 100.0, 1e3, 1e4, 1e5];

/// The shapes of case 2.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Solid {
    /// A sphere of radius 1.
    Sphere,
    /// A box of half-extents (1, 0.7, 1.3).
    Box,
    /// A plane.
    Plane,
}

impl Solid {
    /// All three.
    pub const ALL: [Self; 3] = [Self::Sphere, Self::Box, Self::Plane];
    /// Lower-case name.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Sphere => "sphere",
            Self::Box => "box",
            Self::Plane => "plane",
        }
    }
}

/// Figures of case 2 for one shape at one distance.
#[derive(Clone, Debug, Default)]
pub struct Reintersection {
    /// The shape's name.
    pub solid: &'static str,
    /// Distance of the hits from the origin (about).
    pub magnitude: f32,
    /// Primary hits.
    pub hits: usize,
    /// Secondary rays spawned (each tested with `intersect` and `occluded`).
    pub rays: usize,
    /// Secondary rays that hit their own surface again at the spawn point.
    pub self_hits: usize,
    /// Rays into the solid that found no exit (reported, not a self-hit).
    pub inward_misses: usize,
    /// Rays into a sphere along a chord shorter than 4 offsets, or into a box from an
    /// edge point out through the adjacent face (no chord to find; skipped).
    pub skipped: usize,
    /// Largest spawn offset (distance from the hit point to the secondary ray's
    /// origin) over `max(|p|, 1)`, for the record.
    pub worst_offset: f64,
}

/// What an inward secondary ray found.
enum Inward {
    Ok,
    SelfHit,
    Miss,
    Skip,
}

/// Case 2 for one shape at one distance: `primaries` rays hit the shape (from
/// outside and, for closed shapes, from inside); from each hit, the reflected and the
/// refracted direction and 16 random directions (8 on each side) leave through
/// [`offset_origin`] with the surface's error bound. A ray leaving a convex shape (or
/// any ray leaving a plane) must not hit it; a ray entering must find the far side.
#[must_use]
pub fn reintersection(solid: Solid, magnitude: f32, primaries: usize) -> Reintersection {
    let mut rng = Rng::new(0x5eed ^ u64::from(magnitude.to_bits()));
    let p32 = (V3::new(0.6, -0.48, 0.64).normalize() * f64::from(magnitude)).f32();
    let n0 = V3::new(0.3, 0.8, 0.52).normalize();
    let mut out = Reintersection {
        solid: solid.name(),
        magnitude,
        ..Reintersection::default()
    };
    match solid {
        Solid::Sphere => on_sphere(p32, n0, &mut rng, primaries, &mut out),
        Solid::Box => on_box(p32, &mut rng, primaries, &mut out),
        Solid::Plane => on_plane(p32, n0, &mut rng, primaries, &mut out),
    }
    out
}

/// Case 2 on the unit sphere whose surface passes through `p32` with normal `n0`:
/// primaries from outside, and a quarter from inside.
fn on_sphere(p32: Vec3, n0: V3, rng: &mut Rng, primaries: usize, out: &mut Reintersection) {
    let c32 = (V3::of(p32) - n0).f32();
    let s = Sphere::try_new(c32, 1.0).expect("sphere");
    let c = V3::of(c32);
    let primary = |rng: &mut Rng| {
        if rng.index(4) == 0 {
            let o = (c + rng.dir() * rng.range(0.0, 0.8)).f32();
            exact_ray(o, rng.dir().f32())
        } else {
            let u = rng.dir();
            let target = c + u;
            let mut v = rng.dir();
            if v.dot(u) < 0.0 {
                v = -v;
            }
            let o = (target + v * rng.range(0.2, 4.0)).f32();
            ray_towards(o, target).unwrap_or(exact_ray(o, (-v).f32()))
        }
    };
    let inward = |_: &Candidate, sf: &Surface, w: Vec3, o: Vec3, h: Option<Candidate>| {
        let chord = -2.0 * V3::of(w).dot(V3::of(sf.normal));
        let offset = (V3::of(o) - V3::of(sf.point)).length();
        match h {
            _ if chord < 4.0 * offset => Inward::Skip,
            None => Inward::Miss,
            Some(h) if f64::from(h.t) < 0.5 * chord => Inward::SelfHit,
            Some(_) => Inward::Ok,
        }
    };
    run_reintersection(&s, true, primary, inward, rng, primaries, out);
}

/// Case 2 on the box of half-extents (1, 0.7, 1.3) around `p32`: primaries at
/// random points of its faces from outside, and a quarter from inside.
fn on_box(p32: Vec3, rng: &mut Rng, primaries: usize, out: &mut Reintersection) {
    let half = V3::new(1.0, 0.7, 1.3);
    let centre = V3::of(p32);
    let (lo, hi) = ((centre - half).f32(), (centre + half).f32());
    let b = Aabb::try_new(lo, hi).expect("box");
    let (lo, hi) = (V3::of(lo), V3::of(hi));
    let primary = |rng: &mut Rng| {
        if rng.index(4) == 0 {
            let o = centre
                + V3::new(
                    rng.range(-0.8, 0.8),
                    rng.range(-0.8, 0.8),
                    rng.range(-0.8, 0.8),
                ) * 0.7;
            exact_ray(o.f32(), rng.dir().f32())
        } else {
            let face = rng.index(6);
            let axis = face / 2;
            let pick = |i: usize, rng: &mut Rng| {
                let (a, b) = (lo.get(i), hi.get(i));
                if i == axis {
                    if face % 2 == 1 { b } else { a }
                } else {
                    rng.range(a, b)
                }
            };
            let target = V3::new(pick(0, rng), pick(1, rng), pick(2, rng));
            let n = V3::ZERO.with(axis, if face % 2 == 1 { 1.0 } else { -1.0 });
            let mut v = rng.dir();
            if v.dot(n) < 0.0 {
                v = -v;
            }
            let o = (target + v * rng.range(0.2, 4.0)).f32();
            ray_towards(o, target).unwrap_or(exact_ray(o, (-v).f32()))
        }
    };
    let (lo32, hi32) = (b.min(), b.max());
    let inward = |c: &Candidate, sf: &Surface, w: Vec3, _: Vec3, h: Option<Candidate>| match h {
        // A point on an edge (on two faces) with a direction leaving through
        // the other face: a chord of length zero, nothing to find.
        _ if (0..3).any(|i| {
            (sf.point.get(i) == lo32.get(i) && w.get(i) < 0.0)
                || (sf.point.get(i) == hi32.get(i) && w.get(i) > 0.0)
        }) =>
        {
            Inward::Skip
        }
        None => Inward::Miss,
        Some(h) if h.face == c.face => Inward::SelfHit,
        Some(_) => Inward::Ok,
    };
    run_reintersection(&b, true, primary, inward, rng, primaries, out);
}

/// Case 2 on the plane through `p32` with normal `n0` (open: every secondary ray
/// leaves it).
fn on_plane(p32: Vec3, n0: V3, rng: &mut Rng, primaries: usize, out: &mut Reintersection) {
    let pl = Plane::try_new(p32, n0.f32()).expect("plane");
    let p = V3::of(p32);
    let (t1, t2) = n0.basis();
    let primary = |rng: &mut Rng| {
        let target = p + t1 * rng.range(-2.0, 2.0) + t2 * rng.range(-2.0, 2.0);
        let mut v = rng.dir();
        if v.dot(n0) == 0.0 {
            v = n0;
        }
        let o = (target + v * rng.range(0.2, 4.0)).f32();
        ray_towards(o, target).unwrap_or(exact_ray(o, (-v).f32()))
    };
    let inward = |_: &Candidate, _: &Surface, _: Vec3, _: Vec3, _: Option<Candidate>| Inward::Ok;
    run_reintersection(&pl, false, primary, inward, rng, primaries, out);
}

/// The shader's rule: the normal turned to face the incoming ray.
fn facing(n: Vec3, d: Vec3) -> Vec3 {
    if n.dot(d) > 0.0 { -n } else { n }
}

fn run_reintersection<G: Shape>(
    shape: &G,
    closed: bool,
    mut primary: impl FnMut(&mut Rng) -> Ray,
    inward: impl Fn(&Candidate, &Surface, Vec3, Vec3, Option<Candidate>) -> Inward,
    rng: &mut Rng,
    primaries: usize,
    out: &mut Reintersection,
) {
    for _ in 0..primaries {
        let ray = primary(rng);
        let Some(c) = shape.intersect(&ray, INF) else {
            continue;
        };
        out.hits += 1;
        let s = shape.surface(&ray, &c);
        let n = facing(s.normal, ray.dir());
        let entering = s.normal.dot(ray.dir()) < 0.0;
        let mut dirs = Vec::with_capacity(18);
        dirs.push(ray.dir().reflect(n).normalize_or(n));
        let cos_i = (-ray.dir().dot(n)).clamp(0.0, 1.0);
        if let Some((t, _)) = refract(ray.dir(), n, cos_i, 1.5, entering) {
            dirs.push(t);
        }
        let nd = V3::of(n);
        for i in 0..16 {
            let mut w = rng.dir();
            if (w.dot(nd) < 0.0) == (i < 8) {
                w = -w;
            }
            dirs.push(w.f32());
        }
        let p = V3::of(s.point);
        for w in dirs {
            if w.dot(n) == 0.0 || !w.is_finite() {
                continue;
            }
            let o = offset_origin(s.point, s.error, n, w);
            out.worst_offset = out
                .worst_offset
                .max((V3::of(o) - p).length() / p.length().max(1.0));
            let r2 = exact_ray(o, w);
            let hit = shape.intersect(&r2, INF);
            let occ = shape.occluded(&r2, INF);
            out.rays += 1;
            let outward = V3::of(w).dot(V3::of(s.normal)) > 0.0;
            if !closed || outward {
                if hit.is_some() || occ {
                    out.self_hits += 1;
                }
                continue;
            }
            match inward(&c, &s, w, o, hit) {
                Inward::Ok => {}
                Inward::SelfHit => out.self_hits += 1,
                Inward::Miss => out.inward_misses += 1,
                Inward::Skip => out.skipped += 1,
            }
        }
    }
}
