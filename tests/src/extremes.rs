//! The numerical-stability battery: each case measures the `f32` core against `f64`
//! (formulas written here, independent of the core and of the host reference) or an
//! analytic truth, and returns its figures. `tests/tests/extremes.rs` asserts the
//! criteria on them; `src/bin/extremes-report.rs` prints them to `docs/extremes.md`.
//!
//! Everything is deterministic: rays come from fixed grids or a seeded SplitMix64.

use image::RgbImage;
use std::ops::{Add, Mul, Neg, Sub};
use tessera::geometry::{Candidate, Shape, Surface};
use tessera::ray::offset_origin;
use tessera::shade::refract;
use tessera::{
    Aabb, Camera, CameraBasis, Color, Frame, Plane, Ray, RenderSettings, Sampler, Sphere, Triangle,
    Vec3, Viewport,
};
use tessera_host::desc::{SceneDesc, TextureDesc};

const INF: f32 = f32::INFINITY;

/// The offset of the watertightness and re-intersection tests far from the origin.
pub const FAR: Vec3 = Vec3::new(148_376.0, 1234.0, -223_423.0);

/// A point as `(x, y, z)`.
#[must_use]
pub fn show(v: Vec3) -> String {
    format!("({}, {}, {})", v.x, v.y, v.z)
}

// ---------------------------------------------------------------------------------
// f64 vectors, ulps, a seeded generator
// ---------------------------------------------------------------------------------

/// A 3-vector of `f64`: the truth side of every comparison.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct D3 {
    /// x.
    pub x: f64,
    /// y.
    pub y: f64,
    /// z.
    pub z: f64,
}

impl D3 {
    /// `(0, 0, 0)`.
    pub const ZERO: Self = Self::new(0.0, 0.0, 0.0);

    /// From components.
    #[must_use]
    pub const fn new(x: f64, y: f64, z: f64) -> Self {
        Self { x, y, z }
    }
    /// The exact `f64` value of an `f32` vector.
    #[must_use]
    pub fn of(v: Vec3) -> Self {
        Self::new(f64::from(v.x), f64::from(v.y), f64::from(v.z))
    }
    /// Rounded to the nearest `f32` vector.
    #[must_use]
    pub fn f32(self) -> Vec3 {
        Vec3::new(self.x as f32, self.y as f32, self.z as f32)
    }
    /// Dot product.
    #[must_use]
    pub fn dot(self, o: Self) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }
    /// Cross product.
    #[must_use]
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }
    /// Length.
    #[must_use]
    pub fn len(self) -> f64 {
        self.dot(self).sqrt()
    }
    /// Unit vector.
    #[must_use]
    pub fn norm(self) -> Self {
        self * (1.0 / self.len())
    }
    /// Largest absolute component.
    #[must_use]
    pub fn max_abs(self) -> f64 {
        self.x.abs().max(self.y.abs()).max(self.z.abs())
    }
    /// Two unit vectors completing the unit vector `self` to an orthonormal basis.
    #[must_use]
    pub fn basis(self) -> (Self, Self) {
        let a = if self.x.abs() < 0.9 {
            Self::new(1.0, 0.0, 0.0)
        } else {
            Self::new(0.0, 1.0, 0.0)
        };
        let e1 = a.cross(self).norm();
        (e1, self.cross(e1))
    }
}

impl Add for D3 {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}
impl Sub for D3 {
    type Output = Self;
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}
impl Mul<f64> for D3 {
    type Output = Self;
    fn mul(self, s: f64) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}
impl Neg for D3 {
    type Output = Self;
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

/// The spacing of `f32` values at the magnitude of `x` (one ulp).
#[must_use]
pub fn ulp32(x: f64) -> f64 {
    let e = ((x.abs() as f32).to_bits() >> 23) & 0xff;
    2f64.powi(e.max(1) as i32 - 150)
}

/// SplitMix64: a small seeded generator, the same sequence on every machine.
#[derive(Clone, Debug)]
pub struct Rng(u64);

impl Rng {
    /// A generator from a seed.
    #[must_use]
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    /// The next 64 random bits.
    pub fn bits(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    /// Uniform in `[0, 1)`.
    pub fn unit(&mut self) -> f64 {
        (self.bits() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }
    /// Uniform in `[a, b)`.
    pub fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.unit()
    }
    /// Uniform on the unit sphere.
    pub fn dir(&mut self) -> D3 {
        let z = self.range(-1.0, 1.0);
        let phi = self.range(0.0, std::f64::consts::TAU);
        let r = (1.0 - z * z).max(0.0).sqrt();
        D3::new(r * phi.cos(), r * phi.sin(), z)
    }
    /// An index in `0..n`.
    pub fn index(&mut self, n: usize) -> usize {
        (self.bits() % n as u64) as usize
    }
}

/// The `f32` ray from `o` towards `target` (direction normalised in `f64`, then
/// rounded), or `None` when they coincide.
#[must_use]
pub fn ray_towards(o: Vec3, target: D3) -> Option<Ray> {
    let d = target - D3::of(o);
    (d.len() > 0.0).then(|| exact_ray(o, d.norm().f32()))
}

/// The ray from `o` along the unit direction `d`, exactly as given: the battery's
/// expectations are computed from these bits, so this asserts that [`Ray::new`]
/// keeps a direction that is unit to `f32` precision (its promise) rather than
/// normalising it again.
#[must_use]
pub fn exact_ray(o: Vec3, d: Vec3) -> Ray {
    let r = Ray::new(o, d).expect("the battery's rays are finite and non-zero");
    assert_eq!(
        (r.origin(), r.dir()),
        (o, d),
        "Ray::new changed a unit direction"
    );
    r
}

// ---------------------------------------------------------------------------------
// Case 1: far spheres
// ---------------------------------------------------------------------------------

/// Distance/radius ratios of case 1: 1e1 to 1e6 in half decades.
pub const FAR_SPHERE_RATIOS: [f64; 11] = [
    1e1, 3.162e1, 1e2, 3.162e2, 1e3, 3.162e3, 1e4, 3.162e4, 1e5, 3.162e5, 1e6,
];

/// Figures of case 1 at one distance/radius ratio.
#[derive(Clone, Debug, Default)]
pub struct FarSphere {
    /// Distance of the centre over the radius.
    pub ratio: f64,
    /// Rays cast.
    pub rays: usize,
    /// Rays clearly inside or outside (`|h - r| > 1e-3 r`).
    pub clear: usize,
    /// Clear rays where the core's hit/miss differs from `f64`.
    pub disagreements: usize,
    /// Largest `|t_core - t_f64|` over the hits, in ulps of `t`.
    pub worst_ulps: f64,
    /// Rays (clear or not) whose core `t` is NaN or infinite.
    pub non_finite: usize,
}

/// Case 1: a sphere at `ratio` radii from the ray origins, rays through a polar
/// grid of offsets `h` in `[0, 2r)` around its centre; each ray's hit/miss and `t`
/// against the same `f32` ray intersected in `f64`.
#[must_use]
pub fn far_sphere(ratio: f64, steps: usize, radius: f32) -> FarSphere {
    let mut out = FarSphere {
        ratio,
        ..FarSphere::default()
    };
    let r = f64::from(radius);
    let axis = D3::new(0.36, -0.48, -0.8).norm();
    for origin in [D3::ZERO, D3::new(0.75, -0.5, 0.25) * r] {
        let o32 = origin.f32();
        let c32 = (origin + axis * (ratio * r)).f32();
        let Ok(sphere) = Sphere::try_new(c32, radius) else {
            continue;
        };
        let (o, c) = (D3::of(o32), D3::of(c32));
        let (e1, e2) = (c - o).norm().basis();
        for i in 0..steps {
            let h = 2.0 * r * (i as f64 + 0.5) / steps as f64;
            for j in 0..8 {
                let phi = 0.3 + j as f64 * std::f64::consts::TAU / 8.0;
                let target = c + (e1 * phi.cos() + e2 * phi.sin()) * h;
                let Some(ray) = ray_towards(o32, target) else {
                    continue;
                };
                out.rays += 1;
                // The same f32 ray, exactly, in f64; RTG ch. 7 form (no cancellation).
                let d = D3::of(ray.dir());
                let dl = d.len();
                let dn = d * (1.0 / dl);
                let f = o - c;
                let b = -f.dot(dn);
                let l = f + dn * b;
                let h_true = l.len();
                let disc = r * r - l.dot(l);
                let core = sphere.intersect(&ray, INF);
                if core.is_some_and(|h| !h.t.is_finite()) {
                    out.non_finite += 1;
                }
                if (h_true - r).abs() <= 1e-3 * r {
                    continue;
                }
                out.clear += 1;
                let hit_true = disc > 0.0 && b > 0.0;
                if core.is_some() != hit_true {
                    out.disagreements += 1;
                    continue;
                }
                if let Some(hit) = core {
                    // Near root c/q, in units of the (not exactly unit) f32 direction.
                    let q = b + disc.sqrt();
                    let t_true = (f.dot(f) - r * r) / q / dl;
                    let err = (f64::from(hit.t) - t_true).abs() / ulp32(t_true);
                    out.worst_ulps = out.worst_ulps.max(err);
                }
            }
        }
    }
    out
}

// ---------------------------------------------------------------------------------
// Case 2: re-intersection of secondary rays
// ---------------------------------------------------------------------------------

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
    let p32 = (D3::new(0.6, -0.48, 0.64).norm() * f64::from(magnitude)).f32();
    let n0 = D3::new(0.3, 0.8, 0.52).norm();
    let half = D3::new(1.0, 0.7, 1.3);
    let mut out = Reintersection {
        solid: solid.name(),
        magnitude,
        ..Reintersection::default()
    };
    match solid {
        Solid::Sphere => {
            let c32 = (D3::of(p32) - n0).f32();
            let s = Sphere::try_new(c32, 1.0).expect("sphere");
            let c = D3::of(c32);
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
                let chord = -2.0 * D3::of(w).dot(D3::of(sf.normal));
                let offset = (D3::of(o) - D3::of(sf.point)).len();
                match h {
                    _ if chord < 4.0 * offset => Inward::Skip,
                    None => Inward::Miss,
                    Some(h) if f64::from(h.t) < 0.5 * chord => Inward::SelfHit,
                    Some(_) => Inward::Ok,
                }
            };
            run_reintersection(&s, true, primary, inward, &mut rng, primaries, &mut out);
        }
        Solid::Box => {
            let centre = D3::of(p32);
            let (lo, hi) = ((centre - half).f32(), (centre + half).f32());
            let b = Aabb::try_new(lo, hi).expect("box");
            let (lo, hi) = (D3::of(lo), D3::of(hi));
            let primary = |rng: &mut Rng| {
                if rng.index(4) == 0 {
                    let o = centre
                        + D3::new(
                            rng.range(-0.8, 0.8),
                            rng.range(-0.8, 0.8),
                            rng.range(-0.8, 0.8),
                        ) * 0.7;
                    exact_ray(o.f32(), rng.dir().f32())
                } else {
                    let face = rng.index(6);
                    let axis = face / 2;
                    let pick = |i: usize, rng: &mut Rng| {
                        let (a, b) = (get(lo, i), get(hi, i));
                        if i == axis {
                            if face % 2 == 1 { b } else { a }
                        } else {
                            rng.range(a, b)
                        }
                    };
                    let target = D3::new(pick(0, rng), pick(1, rng), pick(2, rng));
                    let n = with(D3::ZERO, axis, if face % 2 == 1 { 1.0 } else { -1.0 });
                    let mut v = rng.dir();
                    if v.dot(n) < 0.0 {
                        v = -v;
                    }
                    let o = (target + v * rng.range(0.2, 4.0)).f32();
                    ray_towards(o, target).unwrap_or(exact_ray(o, (-v).f32()))
                }
            };
            let (lo32, hi32) = (b.min(), b.max());
            let inward =
                |c: &Candidate, sf: &Surface, w: Vec3, _: Vec3, h: Option<Candidate>| match h {
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
            run_reintersection(&b, true, primary, inward, &mut rng, primaries, &mut out);
        }
        Solid::Plane => {
            let pl = Plane::try_new(p32, n0.f32()).expect("plane");
            let p = D3::of(p32);
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
            let inward =
                |_: &Candidate, _: &Surface, _: Vec3, _: Vec3, _: Option<Candidate>| Inward::Ok;
            run_reintersection(&pl, false, primary, inward, &mut rng, primaries, &mut out);
        }
    }
    out
}

fn get(v: D3, i: usize) -> f64 {
    match i {
        0 => v.x,
        1 => v.y,
        _ => v.z,
    }
}

fn with(v: D3, i: usize, x: f64) -> D3 {
    match i {
        0 => D3::new(x, v.y, v.z),
        1 => D3::new(v.x, x, v.z),
        _ => D3::new(v.x, v.y, x),
    }
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
        let nd = D3::of(n);
        for i in 0..16 {
            let mut w = rng.dir();
            if (w.dot(nd) < 0.0) == (i < 8) {
                w = -w;
            }
            dirs.push(w.f32());
        }
        let p = D3::of(s.point);
        for w in dirs {
            if w.dot(n) == 0.0 || !w.is_finite() {
                continue;
            }
            let o = offset_origin(s.point, s.error, n, w);
            out.worst_offset = out
                .worst_offset
                .max((D3::of(o) - p).len() / p.len().max(1.0));
            let r2 = exact_ray(o, w);
            let hit = shape.intersect(&r2, INF);
            let occ = shape.occluded(&r2, INF);
            out.rays += 1;
            let outward = D3::of(w).dot(D3::of(s.normal)) > 0.0;
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

// ---------------------------------------------------------------------------------
// Case 3: watertightness
// ---------------------------------------------------------------------------------

/// Figures of one watertightness configuration.
#[derive(Clone, Debug, Default)]
pub struct Watertight {
    /// What was shot at.
    pub name: String,
    /// Triangles in the mesh.
    pub triangles: usize,
    /// Rays cast.
    pub rays: usize,
    /// Rays that hit no triangle (with `intersect` or `occluded`) although they must.
    pub leaks: usize,
}

fn leaks(mesh: &[Triangle], ray: &Ray) -> bool {
    !mesh.iter().any(|t| t.intersect(ray, INF).is_some())
        || !mesh.iter().any(|t| t.occluded(ray, INF))
}

/// Case 3, fans: a non-planar fan of 7 triangles around `center` (ring radius about
/// `radius`), rays from random directions (not grazing) aimed at the shared centre
/// vertex and at points of the shared edges; every ray must hit the fan.
#[must_use]
pub fn fan(center: Vec3, radius: f64, rays_per_target: usize) -> Watertight {
    let mut rng = Rng::new(0xfa17 ^ u64::from(center.x.to_bits()));
    let nf = D3::new(0.2, -0.3, 0.93).norm();
    let (e1, e2) = nf.basis();
    let c = D3::of(center);
    let ring: Vec<Vec3> = (0..7)
        .map(|i| {
            let th = i as f64 * std::f64::consts::TAU / 7.0 + rng.range(-0.3, 0.3);
            let r = radius * rng.range(0.6, 1.4);
            (c + e1 * (r * th.cos()) + e2 * (r * th.sin()) + nf * (radius * rng.range(-0.3, 0.3)))
                .f32()
        })
        .collect();
    let mesh: Vec<Triangle> = (0..7)
        .map(|i| Triangle::try_new(center, ring[i], ring[(i + 1) % 7]).expect("fan triangle"))
        .collect();
    // Each target with the triangles around it: the ray must cross all of them the
    // same way (transversally), else it may just touch a ridge of the non-planar fan.
    let normals: Vec<D3> = mesh
        .iter()
        .map(|t| {
            let [a, b, d] = t.vertices().map(D3::of);
            (b - a).cross(d - a).norm()
        })
        .collect();
    let mut targets = vec![(c, normals.clone())];
    for (i, v) in ring.iter().enumerate() {
        let around = vec![normals[i], normals[(i + 6) % 7]];
        for l in [0.1, 0.25, 0.5, 0.75, 0.9] {
            targets.push((c + (D3::of(*v) - c) * l, around.clone()));
        }
    }
    let mut out = Watertight {
        name: format!("fan of 7 at {}, radius {radius}", show(center)),
        triangles: mesh.len(),
        ..Watertight::default()
    };
    for (target, around) in targets {
        for _ in 0..rays_per_target {
            let mut v = rng.dir();
            while !(around.iter().all(|n| v.dot(*n) > 0.05)
                || around.iter().all(|n| v.dot(*n) < -0.05))
            {
                v = rng.dir();
            }
            let o = (target + v * (radius * rng.range(0.5, 20.0))).f32();
            let Some(ray) = ray_towards(o, target) else {
                continue;
            };
            out.rays += 1;
            out.leaks += usize::from(leaks(&mesh, &ray));
        }
    }
    out
}

/// The unit icosphere subdivided `level` times: vertices and outward-wound faces.
#[must_use]
pub fn icosphere(level: u32) -> (Vec<D3>, Vec<[usize; 3]>) {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<D3> = [
        (-1.0, g, 0.0),
        (1.0, g, 0.0),
        (-1.0, -g, 0.0),
        (1.0, -g, 0.0),
        (0.0, -1.0, g),
        (0.0, 1.0, g),
        (0.0, -1.0, -g),
        (0.0, 1.0, -g),
        (g, 0.0, -1.0),
        (g, 0.0, 1.0),
        (-g, 0.0, -1.0),
        (-g, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| D3::new(x, y, z).norm())
    .collect();
    let mut f: Vec<[usize; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::with_capacity(f.len() * 4);
        for [a, b, c] in f {
            let mut m = |i: usize, j: usize| {
                *mid.entry((i.min(j), i.max(j))).or_insert_with(|| {
                    v.push((v[i] + v[j]).norm());
                    v.len() - 1
                })
            };
            let (ab, bc, ca) = (m(a, b), m(b, c), m(c, a));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = next;
    }
    (v, f)
}

/// Case 3, closed mesh: an icosphere (`level` 2: 320 triangles) of `radius` around
/// `center`, rays from inside aimed exactly at every vertex, at every edge midpoint
/// and every face centroid, plus `random` random directions; from the centre and from
/// off-centre origins. Every ray must hit the mesh.
#[must_use]
pub fn icosphere_leaks(center: Vec3, radius: f64, level: u32, random: usize) -> Watertight {
    let (v, faces) = icosphere(level);
    let c = D3::of(center);
    let verts: Vec<Vec3> = v.iter().map(|&p| (c + p * radius).f32()).collect();
    let mesh: Vec<Triangle> = faces
        .iter()
        .map(|&[a, b, d]| Triangle::try_new(verts[a], verts[b], verts[d]).expect("face"))
        .collect();
    let mut targets: Vec<D3> = verts.iter().map(|&p| D3::of(p)).collect();
    for &[a, b, d] in &faces {
        let (pa, pb, pd) = (D3::of(verts[a]), D3::of(verts[b]), D3::of(verts[d]));
        targets.push((pa + pb) * 0.5);
        targets.push((pa + pb + pd) * (1.0 / 3.0));
    }
    let mut rng = Rng::new(0x1c05 ^ u64::from(center.z.to_bits()));
    let mut out = Watertight {
        name: format!(
            "icosphere of {} at {}, radius {radius}",
            mesh.len(),
            show(center)
        ),
        triangles: mesh.len(),
        ..Watertight::default()
    };
    let origins = [
        center,
        (c + D3::new(0.3, -0.2, 0.1) * radius).f32(),
        (c + D3::new(-0.1, 0.5, -0.45) * radius).f32(),
        (c + rng.dir() * (0.8 * radius)).f32(),
    ];
    for o in origins {
        let rays = targets
            .iter()
            .filter_map(|&t| ray_towards(o, t))
            .chain((0..random).map(|_| exact_ray(o, rng.dir().f32())));
        for ray in rays {
            out.rays += 1;
            out.leaks += usize::from(leaks(&mesh, &ray));
        }
    }
    out
}

// ---------------------------------------------------------------------------------
// Case 4: tiny triangles
// ---------------------------------------------------------------------------------

/// Edge lengths of case 4 (the report goes further down).
pub const TINY_SIZES: [f64; 7] = [1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2, 1e-1];

/// Figures of case 4 at one edge length.
#[derive(Clone, Debug, Default)]
pub struct Tiny {
    /// Edge length (about).
    pub size: f64,
    /// Triangles shot at.
    pub rays: usize,
    /// Centroid rays that missed.
    pub misses: usize,
    /// Largest `|b - 1/3|` of the hits' barycentrics.
    pub worst_bary: f64,
}

/// Case 4: `count` random near-equilateral triangles of edge about `size`, within
/// 1 to 10 units of the ray origin; the ray aimed at the `f32` centroid must hit.
#[must_use]
pub fn tiny_triangles(size: f64, count: usize) -> Tiny {
    let mut rng = Rng::new(0x7171 ^ size.to_bits());
    let mut out = Tiny {
        size,
        ..Tiny::default()
    };
    for i in 0..count {
        let o = if i % 2 == 0 {
            Vec3::ZERO
        } else {
            (rng.dir() * 3.0).f32()
        };
        let towards = rng.dir();
        let centre = D3::of(o) + towards * rng.range(1.0, 10.0);
        // Not grazing: the normal within 75 degrees of the ray (|cos| >= 0.26).
        let mut n = rng.dir();
        while n.dot(towards).abs() < 0.26 {
            n = rng.dir();
        }
        let (e1, e2) = n.basis();
        let circum = size / 3f64.sqrt();
        let p: Vec<Vec3> = (0..3)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 3.0 + rng.range(-0.3, 0.3);
                let r = circum * rng.range(0.8, 1.2);
                (centre + e1 * (r * a.cos()) + e2 * (r * a.sin())).f32()
            })
            .collect();
        let Ok(t) = Triangle::try_new(p[0], p[1], p[2]) else {
            continue;
        };
        let centroid = (p[0] + p[1] + p[2]) / 3.0;
        let Some(ray) = ray_towards(o, D3::of(centroid)) else {
            continue;
        };
        out.rays += 1;
        match t.intersect(&ray, INF) {
            None => out.misses += 1,
            Some(h) => {
                let b = [
                    1.0 - f64::from(h.b1) - f64::from(h.b2),
                    f64::from(h.b1),
                    f64::from(h.b2),
                ];
                for b in b {
                    out.worst_bary = out.worst_bary.max((b - 1.0 / 3.0).abs());
                }
            }
        }
    }
    out
}

// ---------------------------------------------------------------------------------
// Case 5: boxes, rays in face planes, along edges, signed zeros
// ---------------------------------------------------------------------------------

/// Figures of case 5 for one box.
#[derive(Clone, Debug, Default)]
pub struct BoxRule {
    /// Which box.
    pub name: String,
    /// Rays cast (origins on a lattice through the faces, directions with components
    /// in `{-a, -0, +0, +a}`).
    pub rays: usize,
    /// Hit/miss differing from the exact closed-box answer.
    pub disagreements: usize,
    /// Hits whose face is not one of the exact answer's faces, or whose `t` is off by
    /// more than 1e-6 relative.
    pub wrong_hits: usize,
    /// Ray groups differing only by the sign of zero components that disagree.
    pub sign_mismatches: usize,
    /// Hits with a NaN or infinite `t`, point, normal, error or uv.
    pub non_finite: usize,
    /// For each face: rays lying in its plane that hit the box.
    pub in_plane_hits: [usize; 6],
}

/// The exact answer for a closed box `[lo, hi]` and a ray with direction components
/// `sign[i] * a` (`a > 0`): `s = a t` of the nearest hit with `t > 0` and its faces.
fn box_truth(lo: D3, hi: D3, o: D3, sign: [i8; 3]) -> Option<(f64, Vec<u8>)> {
    let (mut s0, mut f0) = (f64::NEG_INFINITY, Vec::new());
    let (mut s1, mut f1) = (f64::INFINITY, Vec::new());
    for (axis, &sg) in sign.iter().enumerate() {
        let (l, h, x) = (get(lo, axis), get(hi, axis), get(o, axis));
        if sg == 0 {
            if x < l || x > h {
                return None;
            }
            continue;
        }
        let lo_face = 2 * axis as u8;
        let (a, b, enter, exit) = if sg > 0 {
            (l - x, h - x, lo_face, lo_face + 1)
        } else {
            (x - h, x - l, lo_face + 1, lo_face)
        };
        if a > s0 {
            (s0, f0) = (a, vec![enter]);
        } else if a == s0 {
            f0.push(enter);
        }
        if b < s1 {
            (s1, f1) = (b, vec![exit]);
        } else if b == s1 {
            f1.push(exit);
        }
    }
    if s1 < s0 || s1 <= 0.0 {
        None
    } else if s0 > 0.0 {
        Some((s0, f0))
    } else {
        Some((s1, f1))
    }
}

/// Case 5 for the box `[lo, hi]`: origins on the lattice `{lo - 1, lo, mid, hi,
/// hi + 1}` per axis, directions with components in `{-1, -0, +0, +1}` (normalised,
/// so every non-zero component has the same magnitude), against the exact answer.
#[must_use]
pub fn box_rule(name: &str, lo: Vec3, hi: Vec3) -> BoxRule {
    let b = Aabb::try_new(lo, hi).expect("box");
    let (l, h) = (D3::of(lo), D3::of(hi));
    let mut out = BoxRule {
        name: name.into(),
        ..BoxRule::default()
    };
    let lattice = |i: usize| {
        let (a, c) = (lo.get(i), hi.get(i));
        [a - 1.0, a, a + (c - a) * 0.5, c, c + 1.0]
    };
    let comps = [-1.0f32, -0.0, 0.0, 1.0];
    for ox in lattice(0) {
        for oy in lattice(1) {
            for oz in lattice(2) {
                let o = Vec3::new(ox, oy, oz);
                // Results per direction, keyed by the direction without zero signs.
                let mut groups: std::collections::HashMap<[i8; 3], Option<(u32, u8)>> =
                    std::collections::HashMap::new();
                for &dx in &comps {
                    for &dy in &comps {
                        for &dz in &comps {
                            let Some(d) = Vec3::new(dx, dy, dz).try_normalize() else {
                                continue;
                            };
                            out.rays += 1;
                            let sg = |v: f32| {
                                if v > 0.0 {
                                    1i8
                                } else if v < 0.0 {
                                    -1
                                } else {
                                    0
                                }
                            };
                            let sign = [sg(dx), sg(dy), sg(dz)];
                            let ray = exact_ray(o, d);
                            let got = b.intersect(&ray, INF);
                            let truth = box_truth(l, h, D3::of(o), sign);
                            if got.is_some() != truth.is_some()
                                || b.occluded(&ray, INF) != truth.is_some()
                            {
                                out.disagreements += 1;
                            }
                            if let (Some(g), Some((s, faces))) = (got, &truth) {
                                let a = f64::from(
                                    d.get(sign.iter().position(|&x| x != 0).unwrap_or(0)).abs(),
                                );
                                let t = s / a;
                                if !faces.contains(&g.face)
                                    || (f64::from(g.t) - t).abs() > 1e-6 * t.max(1.0)
                                {
                                    out.wrong_hits += 1;
                                }
                            }
                            if let Some(g) = got {
                                let s = b.surface(&ray, &g);
                                let uv = b.uv(&s, &g);
                                if !(g.t.is_finite()
                                    && s.point.is_finite()
                                    && s.normal.is_finite()
                                    && s.error.is_finite()
                                    && uv.iter().all(|x| x.is_finite()))
                                {
                                    out.non_finite += 1;
                                }
                                for (axis, &sg) in sign.iter().enumerate() {
                                    if sg == 0 {
                                        for (face, plane) in
                                            [(2 * axis, lo.get(axis)), (2 * axis + 1, hi.get(axis))]
                                        {
                                            if o.get(axis) == plane {
                                                out.in_plane_hits[face] += 1;
                                            }
                                        }
                                    }
                                }
                            }
                            let key = got.map(|g| (g.t.to_bits(), g.face));
                            match groups.get(&sign) {
                                Some(prev) if *prev != key => out.sign_mismatches += 1,
                                Some(_) => {}
                                None => {
                                    groups.insert(sign, key);
                                }
                            }
                        }
                    }
                }
            }
        }
    }
    out
}

// ---------------------------------------------------------------------------------
// Case 6: the camera far from the origin, up close to forward
// ---------------------------------------------------------------------------------

/// Camera distances from the origin in case 6.
pub const CAMERA_DISTANCES: [f32; 5] = [0.0, 1e1, 1e3, 1e4, 1e5];
/// Near distances in case 6.
pub const NEARS: [f32; 3] = [0.01, 0.1, 1.0];

/// The camera's per-frame vectors in `f64`, from the user's inputs.
struct RefBasis {
    near_forward: D3,
    u1: D3,
    u2: D3,
    half: (f64, f64),
}

impl RefBasis {
    fn new(forward: D3, up: D3, fovy: f64, near: f64, vp: Viewport) -> Self {
        let f = forward.norm();
        let up = up.norm();
        let right = f.cross(up);
        let right = (right - f * f.dot(right)).norm();
        let down = f.cross(right).norm();
        let (nl, nh) = (f64::from(vp.width), f64::from(vp.height));
        let height = 2.0 * near * (fovy.to_radians() / 2.0).tan();
        let width = nl / nh * height;
        Self {
            near_forward: f * near,
            u1: right * (width / nl),
            u2: down * (height / nh),
            half: (nl / 2.0, nh / 2.0),
        }
    }
    fn dir(&self, x: f64, y: f64) -> D3 {
        (self.near_forward + self.u1 * (x - self.half.0) + self.u2 * (y - self.half.1)).norm()
    }
}

/// Figures of case 6 at one camera distance and near distance.
#[derive(Clone, Debug, Default)]
pub struct CameraFar {
    /// `|r_cam|`.
    pub distance: f32,
    /// Near distance.
    pub near: f32,
    /// Rays compared.
    pub rays: usize,
    /// Largest angle between the core's and the `f64` direction, in pixels (over the
    /// angular size of that pixel).
    pub worst_px: f64,
    /// 16x16 tiles checked.
    pub tiles: usize,
    /// Pairs of pixels of a tile with bit-identical rays (origin and direction).
    pub shared_rays: usize,
    /// Pairs of pixels of a tile with bit-identical directions.
    pub shared_dirs: usize,
    /// Tiles where two pixels' origins round to the same point (the position's own
    /// f32 spacing, reported only).
    pub tiles_with_shared_origins: usize,
}

/// One view of case 6: forward, up, vertical angle (degrees), width, height.
type View = ([f64; 3], [f64; 3], f32, u16, u16);

/// The orientations and viewports of case 6.
const VIEWS: [View; 4] = [
    ([-0.3, -0.2, -1.0], [0.0, 1.0, 0.0], 60.0, 64, 48),
    ([1.0, 0.1, 0.05], [0.0, 0.0, 1.0], 90.0, 320, 240),
    ([0.2, -1.0, 0.4], [0.0, 1.0, 0.3], 10.0, 1024, 768),
    ([0.6, 0.64, -0.48], [0.1, 0.2, 1.0], 120.0, 4000, 3000),
];

/// Case 6: primary ray directions of a camera at `distance` from the origin with near
/// distance `near`, against `f64`, in four orientations and viewports (64x48 to
/// 4000x3000; large ones on 24 tiles), and shared rays within 16x16 tiles.
#[must_use]
pub fn camera_far(distance: f32, near: f32) -> CameraFar {
    let mut out = CameraFar {
        distance,
        near,
        ..CameraFar::default()
    };
    let pos = (D3::new(0.6, -0.64, 0.48) * f64::from(distance)).f32();
    let mut rng = Rng::new(0xca3e);
    for (fwd, up, fovy, w, h) in VIEWS {
        let (fwd, up) = (
            D3::new(fwd[0], fwd[1], fwd[2]),
            D3::new(up[0], up[1], up[2]),
        );
        let vp = Viewport::new(w, h);
        let cam =
            Camera::try_new(pos, fwd.f32(), up.f32(), fovy, near, near * 1e6).expect("camera");
        let basis = CameraBasis::try_new(&cam, vp).expect("basis");
        // The reference starts from the same f32 inputs.
        let rb = RefBasis::new(
            D3::of(fwd.f32()),
            D3::of(up.f32()),
            f64::from(fovy),
            f64::from(near),
            vp,
        );
        let (across, down) = (w.div_ceil(16), h.div_ceil(16));
        let tiles: Vec<(u16, u16)> = if u32::from(across) * u32::from(down) <= 300 {
            (0..down)
                .flat_map(|ty| (0..across).map(move |tx| (tx, ty)))
                .collect()
        } else {
            let mut t = vec![
                (0, 0),
                (across - 1, 0),
                (0, down - 1),
                (across - 1, down - 1),
            ];
            t.push((across / 2, down / 2));
            t.extend((0..19).map(|_| {
                (
                    rng.index(usize::from(across)) as u16,
                    rng.index(usize::from(down)) as u16,
                )
            }));
            t
        };
        for (tx, ty) in tiles {
            out.tiles += 1;
            let mut rays = std::collections::HashSet::new();
            let mut dirs = std::collections::HashSet::new();
            let mut origins = std::collections::HashSet::new();
            let mut n = 0;
            for y in ty * 16..((ty + 1) * 16).min(h) {
                for x in tx * 16..((tx + 1) * 16).min(w) {
                    let (px, py) = (f64::from(x) + 0.5, f64::from(y) + 0.5);
                    let (ray, _) = basis.ray(px as f32, py as f32);
                    let d = D3::of(ray.dir()).norm();
                    let truth = rb.dir(px, py);
                    let pixel = (rb.dir(px + 0.5, py) - rb.dir(px - 0.5, py))
                        .len()
                        .min((rb.dir(px, py + 0.5) - rb.dir(px, py - 0.5)).len());
                    out.rays += 1;
                    out.worst_px = out.worst_px.max((d - truth).len() / pixel);
                    let bits = |v: Vec3| [v.x.to_bits(), v.y.to_bits(), v.z.to_bits()];
                    rays.insert((bits(ray.origin()), bits(ray.dir())));
                    dirs.insert(bits(ray.dir()));
                    origins.insert(bits(ray.origin()));
                    n += 1;
                }
            }
            out.shared_rays += n - rays.len();
            out.shared_dirs += n - dirs.len();
            out.tiles_with_shared_origins += usize::from(origins.len() < n);
        }
    }
    out
}

/// Angles between up and forward in case 6, radians.
pub const UP_ANGLES: [f64; 3] = [0.0, 1e-7, 1e-5];

/// Figures of case 6, up against forward.
#[derive(Clone, Debug, Default)]
pub struct UpForward {
    /// Cameras built.
    pub cameras: usize,
    /// Cameras with a NaN or infinite vector or ray.
    pub non_finite: usize,
    /// Largest `|e_i . e_j|` among the unit right, down and forward vectors.
    pub worst_dot: f64,
    /// Largest `| |u1| / (L / N_L) - 1 |`, `| |u2| / (H / N_H) - 1 |`, `| |c_a| - 1 |`.
    pub worst_length: f64,
}

/// Case 6, degenerate up: forward along axes and oblique directions, up at each of
/// [`UP_ANGLES`] from forward (and from minus forward), the basis must be finite and
/// orthonormal within `1e-6`.
#[must_use]
pub fn up_forward() -> UpForward {
    let mut out = UpForward::default();
    let forwards = [
        D3::new(0.0, 0.0, 1.0),
        D3::new(0.0, -1.0, 0.0),
        D3::new(1.0, 0.0, 0.0),
        D3::new(0.3, 0.4, 0.5),
        D3::new(-0.7, 0.1, 0.2),
        D3::new(0.577, -0.577, 0.578),
    ];
    for f in forwards {
        let f = f.norm();
        let (p, q) = f.basis();
        for angle in UP_ANGLES {
            for side in [1.0, -1.0] {
                for axis in [p, q, (p + q).norm()] {
                    let up = (f * angle.cos() + axis * angle.sin()) * side;
                    let cam = Camera::try_new(Vec3::ZERO, f.f32(), up.f32(), 60.0, 0.1, 10.0)
                        .expect("camera");
                    let basis = CameraBasis::try_new(&cam, Viewport::new(64, 48)).expect("basis");
                    out.cameras += 1;
                    let rays = [(0.0, 0.0), (32.0, 24.0), (64.0, 48.0), (0.5, 47.5)]
                        .map(|(x, y)| basis.ray(x, y).0);
                    if !(basis.u1().is_finite()
                        && basis.u2().is_finite()
                        && basis.r_ini().is_finite()
                        && rays
                            .iter()
                            .all(|r| r.origin().is_finite() && r.dir().is_finite()))
                    {
                        out.non_finite += 1;
                        continue;
                    }
                    let (u1, u2, fw) = (
                        D3::of(basis.u1()),
                        D3::of(basis.u2()),
                        D3::of(cam.forward()),
                    );
                    let (e1, e2) = (u1.norm(), u2.norm());
                    for d in [e1.dot(e2), e1.dot(fw), e2.dot(fw)] {
                        out.worst_dot = out.worst_dot.max(d.abs());
                    }
                    let px = f64::from(basis.width()) / 64.0;
                    let py = f64::from(basis.height()) / 48.0;
                    for l in [u1.len() / px - 1.0, u2.len() / py - 1.0, fw.len() - 1.0] {
                        out.worst_length = out.worst_length.max(l.abs());
                    }
                }
            }
        }
    }
    out
}

/// Angles between up and forward in the roll part of case 6, radians.
pub const ROLL_ANGLES: [f64; 5] = [1e-7, 1e-6, 1e-5, 1e-4, 1e-3];

/// Figures of case 6, the roll set by an up nearly parallel to forward.
#[derive(Clone, Debug, Default)]
pub struct UpRoll {
    /// Cameras built.
    pub cameras: usize,
    /// Rays compared (corners, edge midpoints and centre of each viewport).
    pub rays: usize,
    /// Largest distance between the core's and the `f64` direction, in pixels.
    pub worst_px: f64,
    /// The angle (radians) at which `worst_px` was found.
    pub worst_angle: f64,
}

/// Case 6, roll: `up` at each of [`ROLL_ANGLES`] from forward (several forwards and
/// directions of the tilt, 640x480 and 64x48 viewports, 60 and 100 degrees), the
/// primary rays' directions against an `f64` basis built from the same `f32`
/// inputs. The example: forward (0.3, 0.4, 0.5), up (0.300002, 0.4,
/// 0.4999988), 640x480, was rolled by 3.9 pixels at the corners.
#[must_use]
pub fn up_roll() -> UpRoll {
    let mut out = UpRoll::default();
    let forwards = [
        D3::new(0.3, 0.4, 0.5),
        D3::new(0.0, 0.0, -1.0),
        D3::new(-0.7, 0.1, 0.2),
        D3::new(1.0, 1e-3, -2e-3),
    ];
    let mut cases: Vec<(Vec3, Vec3)> = vec![(
        Vec3::new(0.3, 0.4, 0.5),
        Vec3::new(0.300_002, 0.4, 0.499_998_8),
    )];
    for f in forwards {
        let fu = f.norm();
        let (p, q) = fu.basis();
        for angle in ROLL_ANGLES {
            for axis in [p, q, (p - q * 0.3).norm()] {
                let up = fu * angle.cos() + axis * angle.sin();
                cases.push((f.f32(), (up * 2.5).f32()));
            }
        }
    }
    for (fwd, up) in cases {
        for (fovy, w, h) in [(60.0f32, 640u16, 480u16), (100.0, 64, 48)] {
            let vp = Viewport::new(w, h);
            let cam = Camera::try_new(Vec3::ZERO, fwd, up, fovy, 0.1, 100.0).expect("camera");
            let basis = CameraBasis::try_new(&cam, vp).expect("basis");
            let rb = RefBasis::new(D3::of(fwd), D3::of(up), f64::from(fovy), 0.1, vp);
            let angle = D3::of(fwd).norm().cross(D3::of(up).norm()).len().asin();
            out.cameras += 1;
            let (fw, fh) = (f64::from(w), f64::from(h));
            for (x, y) in [
                (0.0, 0.0),
                (fw, 0.0),
                (0.0, fh),
                (fw, fh),
                (fw / 2.0, 0.0),
                (0.0, fh / 2.0),
                (fw / 2.0, fh / 2.0),
            ] {
                let (ray, _) = basis.ray(x as f32, y as f32);
                let d = D3::of(ray.dir()).norm();
                let truth = rb.dir(x, y);
                let (cx, cy) = (x.clamp(0.5, fw - 0.5), y.clamp(0.5, fh - 0.5));
                let pixel = (rb.dir(cx + 0.5, cy) - rb.dir(cx - 0.5, cy))
                    .len()
                    .min((rb.dir(cx, cy + 0.5) - rb.dir(cx, cy - 0.5)).len());
                out.rays += 1;
                let px = (d - truth).len() / pixel;
                if px > out.worst_px {
                    out.worst_px = px;
                    out.worst_angle = angle;
                }
            }
        }
    }
    out
}

// ---------------------------------------------------------------------------------
// Case 7: scale invariance (and case 8: flush-to-zero)
// ---------------------------------------------------------------------------------

/// The built-in scene descriptions of case 7.
#[must_use]
pub fn builtins() -> Vec<(&'static str, SceneDesc)> {
    tessera::builtin::Builtin::ALL
        .iter()
        .map(|&b| (b.name(), tessera_host::file::builtin_desc(b)))
        .collect()
}

/// `desc` with every length times `2^k` and every light intensity times `4^k`, so
/// that the image is unchanged in exact arithmetic. Texture coordinates in world
/// units (planes) scale too, so a texture used by planes has its scale divided (its
/// fringe spacing or wavelength multiplied) by `2^k`; other shapes' uv are
/// scale-free. Every product is exact in `f64`, and the `f32` values the core gets
/// are exactly the unscaled ones times `2^k` while they stay normal.
///
/// # Panics
/// If a textured material is used by a plane and by another kind of shape.
#[must_use]
pub fn scaled(desc: &SceneDesc, k: i32) -> SceneDesc {
    let s = 2f64.powi(k);
    let v = |a: [f64; 3]| a.map(|x| x * s);
    let mut d = desc.clone();
    d.camera.position = v(d.camera.position);
    d.camera.look_at = d.camera.look_at.map(v);
    d.camera.near *= s;
    d.camera.far *= s;
    for x in &mut d.spheres {
        x.center = v(x.center);
        x.radius *= s;
    }
    for x in &mut d.planes {
        x.point = v(x.point);
    }
    for x in &mut d.triangles {
        x.vertices = x.vertices.map(v);
    }
    for x in &mut d.boxes {
        x.min = v(x.min);
        x.max = v(x.max);
    }
    for x in &mut d.lights {
        x.position = v(x.position);
        x.intensity *= s * s;
    }
    for m in &mut d.materials {
        let on_planes = desc.planes.iter().any(|p| p.material == m.name);
        let elsewhere = desc.spheres.iter().any(|p| p.material == m.name)
            || desc.triangles.iter().any(|p| p.material == m.name)
            || desc.boxes.iter().any(|p| p.material == m.name);
        let Some(t) = &mut m.texture else { continue };
        assert!(
            !(on_planes && elsewhere),
            "material {} on planes and other shapes",
            m.name
        );
        if on_planes {
            match t {
                TextureDesc::Checker { scale, .. } => *scale /= s,
                TextureDesc::Fringes { spacing, .. } => *spacing *= s,
                TextureDesc::Young { wavelength, .. } => *wavelength *= s,
            }
        }
    }
    d
}

/// A rendered image and how many of its pixels had a NaN or infinite linear colour.
#[derive(Clone, Debug, PartialEq)]
pub struct Rendered {
    /// The 8-bit image.
    pub image: RgbImage,
    /// Pixels whose linear colour is not finite.
    pub non_finite: usize,
}

/// Renders a description with the core (`Frame::pixel_color`, as a tile does) at
/// `vp` with the description's own settings; the core's error if it refuses it.
pub fn render_desc(desc: &SceneDesc, vp: Viewport) -> Result<Rendered, String> {
    let settings = desc.settings().map_err(|e| e.to_string())?;
    let scene = desc.to_core().map_err(|e| e.to_string())?;
    let frame = Frame::try_new(scene.camera(), vp, settings).map_err(|e| e.to_string())?;
    let view = scene.view();
    let mut non_finite = 0;
    let image = RgbImage::from_fn(u32::from(vp.width), u32::from(vp.height), |x, y| {
        let c = frame.pixel_color(&view, x, y);
        non_finite += usize::from(!c.is_finite());
        let p = c.to_rgb8();
        image::Rgb([p.r, p.g, p.b])
    });
    Ok(Rendered { image, non_finite })
}

/// The viewport of cases 7 and 8.
pub const SCALE_VIEWPORT: Viewport = Viewport::new(64, 48);

/// Figures of case 7 for one scene: the range of `k` over which the image is
/// bit-identical to `k = 0`, and what happens just beyond it on each side.
#[derive(Clone, Debug, Default)]
pub struct ScaleRange {
    /// The scene.
    pub name: String,
    /// Smallest `k` of the identical run around 0.
    pub lo: i32,
    /// Largest `k` of the identical run around 0.
    pub hi: i32,
    /// At `lo - 1`: "rejected: <error>", "N pixels differ", or "not tried".
    pub below: String,
    /// At `hi + 1`.
    pub above: String,
}

/// What scaling by `2^k` does: `None` when the image is identical to `base`.
fn scale_outcome(desc: &SceneDesc, k: i32, base: &Rendered) -> Option<String> {
    match render_desc(&scaled(desc, k), SCALE_VIEWPORT) {
        Err(e) => Some(format!("rejected: {e}")),
        Ok(r) if r == *base => None,
        Ok(r) => {
            let n = r
                .image
                .pixels()
                .zip(base.image.pixels())
                .filter(|(a, b)| a != b)
                .count();
            Some(format!("{n} pixels differ, {} non-finite", r.non_finite))
        }
    }
}

/// Case 7 for one scene: scans `k` outwards from 0 up to `|k| = limit`.
#[must_use]
pub fn scale_range(name: &str, desc: &SceneDesc, limit: i32) -> ScaleRange {
    let base = render_desc(desc, SCALE_VIEWPORT).expect("base render");
    let mut out = ScaleRange {
        name: name.into(),
        below: "not tried".into(),
        above: "not tried".into(),
        ..ScaleRange::default()
    };
    for k in 1..=limit {
        if let Some(why) = scale_outcome(desc, k, &base) {
            out.above = why;
            break;
        }
        out.hi = k;
    }
    for k in 1..=limit {
        if let Some(why) = scale_outcome(desc, -k, &base) {
            out.below = why;
            break;
        }
        out.lo = -k;
    }
    out
}

/// The range of `k` for which validation accepts the scene scaled by `2^k`
/// (scanned outwards from 0, up to `|k| = 200`).
#[must_use]
pub fn validated_range(desc: &SceneDesc) -> (i32, i32) {
    let ok = |k: i32| {
        let d = scaled(desc, k);
        match (d.to_core(), d.settings()) {
            (Ok(scene), Ok(settings)) => scene.frame(SCALE_VIEWPORT, settings).is_ok(),
            _ => false,
        }
    };
    let hi = (1..=200).take_while(|&k| ok(k)).last().unwrap_or(0);
    let lo = (1..=200).take_while(|&k| ok(-k)).last().map_or(0, |k| -k);
    (lo, hi)
}

/// The `k` in `ks` for which the scaled scene's image differs from `k = 0`.
#[must_use]
pub fn scale_mismatches(desc: &SceneDesc, ks: impl IntoIterator<Item = i32>) -> Vec<(i32, String)> {
    let base = render_desc(desc, SCALE_VIEWPORT).expect("base render");
    ks.into_iter()
        .filter_map(|k| scale_outcome(desc, k, &base).map(|w| (k, w)))
        .collect()
}

/// Runs `f` with denormals flushed to zero (MXCSR FTZ and DAZ set) on this thread,
/// restoring the previous MXCSR afterwards, even if `f` panics.
#[cfg(target_arch = "x86_64")]
pub fn with_flush_to_zero<R>(f: impl FnOnce() -> R) -> R {
    #[allow(deprecated, unsafe_code)]
    mod csr {
        use core::arch::x86_64::{_mm_getcsr, _mm_setcsr};
        /// FTZ (bit 15) and DAZ (bit 6).
        const FTZ_DAZ: u32 = 0x8040;
        pub struct Guard(u32);
        impl Guard {
            pub fn set() -> Self {
                // SAFETY: reading MXCSR and setting two of its mode bits only changes
                // how this thread rounds tiny results; no memory is involved.
                let old = unsafe { _mm_getcsr() };
                unsafe { _mm_setcsr(old | FTZ_DAZ) };
                Self(old)
            }
        }
        impl Drop for Guard {
            fn drop(&mut self) {
                // SAFETY: restores the value read in `set`.
                unsafe { _mm_setcsr(self.0) };
            }
        }
    }
    let _guard = csr::Guard::set();
    f()
}

/// True when denormals are currently flushed on this thread (checked by computing
/// one).
#[must_use]
pub fn denormals_flushed() -> bool {
    let tiny = std::hint::black_box(f32::MIN_POSITIVE);
    std::hint::black_box(tiny * 0.5) == 0.0
}

/// Figures of case 8 for one scene at one scale.
#[derive(Clone, Debug, Default)]
pub struct Flushed {
    /// The scene.
    pub name: String,
    /// Scale exponent.
    pub k: i32,
    /// Pixels differing from the render with denormals.
    pub differing: usize,
    /// Non-finite pixels with denormals flushed.
    pub non_finite: usize,
}

/// Case 8 for one scene at `2^k`: the render with denormals flushed against the
/// normal one (x86_64 only; elsewhere the two renders are the same code).
#[must_use]
pub fn flushed(name: &str, desc: &SceneDesc, k: i32) -> Flushed {
    let d = scaled(desc, k);
    let normal = render_desc(&d, SCALE_VIEWPORT).expect("render");
    #[cfg(target_arch = "x86_64")]
    let ftz = with_flush_to_zero(|| {
        assert!(denormals_flushed(), "FTZ did not take effect");
        render_desc(&d, SCALE_VIEWPORT)
    })
    .expect("render");
    #[cfg(not(target_arch = "x86_64"))]
    let ftz = normal.clone();
    Flushed {
        name: name.into(),
        k,
        differing: ftz
            .image
            .pixels()
            .zip(normal.image.pixels())
            .filter(|(a, b)| a != b)
            .count(),
        non_finite: ftz.non_finite,
    }
}

// ---------------------------------------------------------------------------------
// Case 9: the analytic scene
// ---------------------------------------------------------------------------------

/// Figures of case 9 at one radius.
#[derive(Clone, Debug, Default)]
pub struct Analytic {
    /// Sphere radius.
    pub radius: f32,
    /// Pixel channels compared.
    pub channels: usize,
    /// Largest difference from the analytic value, 8-bit steps (LSB); -1 if refused.
    pub worst_lsb: i32,
}

/// Case 9: the camera inside a diffuse sphere of radius `r` lit by a point light of
/// intensity `0.9 r^2` at its centre: every pixel is `kd * color * 0.9`.
#[must_use]
pub fn analytic(r: f32) -> Analytic {
    let color = Color::new(0.9, 0.6, 0.3);
    let kd = 0.8f32;
    let mut out = Analytic {
        radius: r,
        worst_lsb: -1,
        ..Analytic::default()
    };
    let Ok(scene) = crate::inside_sphere(r, 0.9 * r * r, kd, color) else {
        return out;
    };
    let e = f64::from(kd) * 0.9;
    let want = [color.r, color.g, color.b].map(|c| (f64::from(c) * e * 255.0).round() as i32);
    out.worst_lsb = 0;
    for sampler in [Sampler::Centre, Sampler::Corner, Sampler::Stratified(2)] {
        let settings = RenderSettings {
            sampler,
            max_depth: 2,
            seed: 1,
        };
        let Ok(frame) = scene.frame(Viewport::new(40, 30), settings) else {
            out.worst_lsb = -1;
            return out;
        };
        for y in 0..30 {
            for x in 0..40 {
                let p = frame.render_pixel(&scene.view(), x, y);
                for (got, want) in [p.r, p.g, p.b].into_iter().zip(want) {
                    out.channels += 1;
                    out.worst_lsb = out.worst_lsb.max((i32::from(got) - want).abs());
                }
            }
        }
    }
    out
}

// ---------------------------------------------------------------------------------
// Case 10: refraction near the critical angle
// ---------------------------------------------------------------------------------

/// Relative indices of case 10.
pub const IORS: [f32; 7] = [1.0, 1.0001, 1.2, 1.33, 1.5, 2.42, 4.0];

/// Half-width of the band around the critical angle where the `f32` decision may
/// differ from `f64`: `|sin^2 t - 1| <= 2^-20` (16 ulps of 1; the rounding of the
/// input vectors and of four operations is a few ulps).
pub const TIR_BAND: f64 = 1.0 / (1u64 << 20) as f64;

/// Figures of case 10.
#[derive(Clone, Debug, Default)]
pub struct Refraction {
    /// Calls of `refract`.
    pub rays: usize,
    /// TIR decisions differing from `f64` outside [`TIR_BAND`].
    pub disagreements: usize,
    /// Decisions differing inside the band (allowed).
    pub band_disagreements: usize,
    /// Largest `|sin^2 t - 1|` among the differing decisions.
    pub widest_disagreement: f64,
    /// Results with a NaN or infinite direction or reflectance, or a reflectance
    /// outside `[0, 1]`.
    pub non_finite: usize,
    /// Largest `| |t| - 1 |` of the refracted directions.
    pub worst_unit: f64,
    /// Largest error of `sin t` against Snell's law in `f64`.
    pub worst_snell: f64,
    /// Refracted directions on the wrong side of the surface.
    pub wrong_side: usize,
}

/// Case 10: for each index, entering and leaving, incidence angles swept over
/// `[0, 90]` degrees and packed around the critical angle (offsets `1e-9` to `1e-1`
/// rad and a few ulps of the input), in an oblique frame; [`refract`] against the
/// geometry of the same `f32` vectors in `f64`.
#[must_use]
pub fn refraction() -> Refraction {
    let mut out = Refraction::default();
    let n64 = D3::new(0.2, 0.9, -0.3).norm();
    let n32 = n64.f32();
    let (tan, _) = n64.basis();
    let n = D3::of(n32);
    for ior in IORS {
        for entering in [true, false] {
            let mut angles: Vec<f64> = (0..=4000)
                .map(|i| i as f64 / 4000.0 * std::f64::consts::FRAC_PI_2)
                .collect();
            if !entering && ior > 1.0 {
                let crit = (1.0 / f64::from(ior)).asin();
                for e in 0..=16 {
                    let off = 10f64.powf(-1.0 - e as f64 * 0.5);
                    angles.extend([crit - off, crit + off]);
                }
                angles.extend((-200..=200).map(|i| crit + i as f64 * 1e-8));
            }
            for a in angles
                .into_iter()
                .filter(|a| (0.0..=std::f64::consts::FRAC_PI_2).contains(a))
            {
                let d32 = (tan * a.sin() - n64 * a.cos()).f32();
                let cos_i = (-d32.dot(n32)).clamp(0.0, 1.0);
                let got = refract(d32, n32, cos_i, ior, entering);
                out.rays += 1;
                // Truth: the same f32 vectors, in f64.
                let d = D3::of(d32);
                let cos_t_in = -(d.dot(n)) / (d.len() * n.len());
                let eta = if entering {
                    1.0 / f64::from(ior)
                } else {
                    f64::from(ior)
                };
                let sin2_t = eta * eta * (1.0 - cos_t_in * cos_t_in).max(0.0);
                let tir = sin2_t >= 1.0;
                if got.is_none() != tir {
                    let dist = (sin2_t - 1.0).abs();
                    out.widest_disagreement = out.widest_disagreement.max(dist);
                    if dist > TIR_BAND {
                        out.disagreements += 1;
                    } else {
                        out.band_disagreements += 1;
                    }
                }
                if let Some((t, fr)) = got {
                    if !(t.is_finite() && fr.is_finite() && (0.0..=1.0).contains(&fr)) {
                        out.non_finite += 1;
                        continue;
                    }
                    let t = D3::of(t);
                    out.worst_unit = out.worst_unit.max((t.len() - 1.0).abs());
                    if t.dot(n) > 0.0 {
                        out.wrong_side += 1;
                    }
                    if !tir {
                        let tn = t.norm();
                        let sin_t = (tn - n.norm() * tn.dot(n.norm())).len();
                        out.worst_snell = out.worst_snell.max((sin_t - sin2_t.sqrt()).abs());
                    }
                }
            }
        }
    }
    out
}

// ---------------------------------------------------------------------------------
// Case 11: the edges of the supported range
// ---------------------------------------------------------------------------------

/// The analytic scene of case 9 with its centre at `center`: a diffuse sphere of
/// radius `r` (colour `(0.9, 0.6, 0.3)`, diffuse 0.8), the camera and a light of
/// intensity `0.9 r^2` at its centre, so every pixel is `0.72 * colour`.
pub fn lit_sphere_at(
    center: Vec3,
    r: f32,
) -> Result<tessera::Scene<1, 0, 0, 0, 1, 1>, tessera::Error> {
    crate::inside_sphere_at(center, r, 0.9 * r * r, 0.8, Color::new(0.9, 0.6, 0.3))
}

/// Largest difference (LSB) of a [`lit_sphere_at`] render (32x24, pixel centres)
/// from the analytic value, and the count of non-finite pixels.
#[must_use]
pub fn lit_sphere_error(scene: &tessera::Scene<1, 0, 0, 0, 1, 1>) -> (i32, usize) {
    let want = [0.9f64, 0.6, 0.3].map(|c| (c * 0.72 * 255.0).round() as i32);
    let frame = scene
        .frame(Viewport::new(32, 24), RenderSettings::default())
        .expect("frame");
    let (mut worst, mut non_finite) = (0, 0);
    for y in 0..24 {
        for x in 0..32 {
            let c = frame.pixel_color(&scene.view(), x, y);
            non_finite += usize::from(!c.is_finite());
            let p = c.to_rgb8();
            for (got, want) in [p.r, p.g, p.b].into_iter().zip(want) {
                worst = worst.max((i32::from(got) - want).abs());
            }
        }
    }
    (worst, non_finite)
}
