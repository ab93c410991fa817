//! The shader: what colour a ray brings back.
//!
//! Direct illumination (the chapter's first picture): an ambient term, then for each
//! light a shadow ray (any-hit), a Lambert diffuse and a Blinn-Phong specular term.
//! Indirect (the second picture): a mirror ray weighted by the material's
//! reflectivity and a refracted ray weighted by its transparency (Snell, Schlick's
//! Fresnel, total internal reflection), to a configurable depth.
//!
//! Simplifications, on purpose (Whitted's model, as in the chapter): shadow rays stop
//! at any surface, transparent or not (no caustics, no coloured shadows); only camera
//! rays are clipped by the far plane; colours are linear, written without a gamma
//! curve.
//!
//! Bounded stack: there is no recursion. Pending rays wait on a fixed-size stack
//! with their weight; each ray adds `weight x local colour` and pushes at most two
//! children. Depth-first, a depth limit `D` needs at most `D + 1` slots, so the
//! stack holds [`MAX_DEPTH`]` + 1`. A ray whose weight is zero is never traced, and
//! no shadow ray, uv or secondary ray is computed where the material does not need
//! it.

use crate::color::Color;
use crate::geometry::{Candidate, Shape, Surface};
use crate::material::Material;
use crate::math;
use crate::ray::{Ray, offset_origin};
use crate::scene::{Primitive, SceneView};
use crate::vec::Vec3;

/// The deepest reflection/transmission recursion a frame may ask for.
pub const MAX_DEPTH: u8 = 8;

/// How many rays a trace cast, by kind (for reports and for tests of what is not
/// traced).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCount {
    /// Camera rays.
    pub primary: u64,
    /// Reflected and refracted rays.
    pub secondary: u64,
    /// Shadow rays.
    pub shadow: u64,
}

impl RayCount {
    /// All rays.
    #[must_use]
    pub fn total(&self) -> u64 {
        self.primary + self.secondary + self.shadow
    }

    /// Adds another count to this one.
    pub fn add(&mut self, o: &Self) {
        self.primary += o.primary;
        self.secondary += o.secondary;
        self.shadow += o.shadow;
    }
}

/// A ray waiting to be traced, with the weight of its contribution.
#[derive(Clone, Copy)]
struct Pending {
    ray: Ray,
    t_max: f32,
    weight: Color,
    depth: u8,
}

/// Which list the nearest hit is in.
#[derive(Clone, Copy)]
enum Kind {
    Sphere,
    Plane,
    Triangle,
    Box,
}

/// The nearest hit so far: list, index, and the shape's candidate.
#[derive(Clone, Copy)]
struct Nearest {
    kind: Kind,
    index: usize,
    hit: Candidate,
}

/// Searches one list for a hit nearer than `*t_max`; shrinks `*t_max` to it.
fn nearest_in<G: Shape>(
    list: &[Primitive<G>],
    ray: &Ray,
    t_max: &mut f32,
) -> Option<(usize, Candidate)> {
    let mut best = None;
    for (i, p) in list.iter().enumerate() {
        if let Some(c) = p.geometry.intersect(ray, *t_max) {
            *t_max = c.t;
            best = Some((i, c));
        }
    }
    best
}

fn occluded_in<G: Shape>(list: &[Primitive<G>], ray: &Ray, t_max: f32) -> bool {
    list.iter().any(|p| p.geometry.occluded(ray, t_max))
}

/// A resolved hit: the surface, its material and (only if textured) its uv.
struct Shaded<'a> {
    surface: Surface,
    material: &'a Material,
    base: Color,
}

fn resolve<'a, G: Shape>(
    view: &SceneView<'a>,
    list: &'a [Primitive<G>],
    n: &Nearest,
    ray: &Ray,
    footprint: Option<&Footprint<'_>>,
) -> Option<Shaded<'a>> {
    let prim = list.get(n.index)?;
    let material = view.materials.get(usize::from(prim.material.0))?;
    let surface = prim.geometry.surface(ray, &n.hit);
    let texture = material.texture();
    let base = if texture.needs_uv() {
        let uv = prim.geometry.uv(&surface, &n.hit);
        match footprint.and_then(|f| uv_box(&prim.geometry, f, uv)) {
            Some((lo, hi)) => texture.eval_box(lo, hi),
            None => texture.eval(uv),
        }
    } else {
        texture.eval([0.0, 0.0])
    };
    Some(Shaded {
        surface,
        material,
        base,
    })
}

/// A camera ray's pixel, for the prefiltered sampler: the four corner rays are
/// only built when the ray hits a textured surface.
#[derive(Clone, Copy, Debug)]
pub struct Footprint<'a> {
    basis: &'a crate::camera::CameraBasis,
    x: f32,
    y: f32,
}

impl<'a> Footprint<'a> {
    /// The footprint of pixel `(x, y)` (its top-left corner) of `basis`.
    #[must_use]
    pub fn new(basis: &'a crate::camera::CameraBasis, x: f32, y: f32) -> Self {
        Self { basis, x, y }
    }

    /// The rays through the pixel's four corners.
    #[must_use]
    pub fn corners(&self) -> [Ray; 4] {
        [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)]
            .map(|(dx, dy)| self.basis.ray(self.x + dx, self.y + dy).0)
    }
}

/// The uv bounding box of a pixel's footprint on `shape`: where the rays through the
/// pixel's four corners meet the same shape. `None` (point sampling instead) when a
/// corner ray misses it, or when the box spans more than half the uv range of a
/// wrapping parametrisation (a sphere's seam).
fn uv_box<G: Shape>(
    shape: &G,
    footprint: &Footprint<'_>,
    centre: [f32; 2],
) -> Option<([f32; 2], [f32; 2])> {
    let (mut lo, mut hi) = (centre, centre);
    for r in &footprint.corners() {
        let c = shape.intersect(r, f32::INFINITY)?;
        let [u, v] = shape.uv(&shape.surface(r, &c), &c);
        lo = [lo[0].min(u), lo[1].min(v)];
        hi = [hi[0].max(u), hi[1].max(v)];
    }
    // A footprint that wraps (sphere seam) is not a box of the texture.
    if shape.uv_wraps() && (hi[0] - lo[0] > 0.5 || hi[1] - lo[1] > 0.5) {
        return None;
    }
    Some((lo, hi))
}

impl<'a> SceneView<'a> {
    /// The nearest hit of `ray` with `0 < t < t_max` over every list.
    fn nearest(&self, ray: &Ray, mut t_max: f32) -> Option<Nearest> {
        let mut best = None;
        let mut keep = |kind, found: Option<(usize, Candidate)>| {
            if let Some((index, hit)) = found {
                best = Some(Nearest { kind, index, hit });
            }
        };
        // Each search shrinks t_max, so a later list only reports nearer hits.
        keep(Kind::Sphere, nearest_in(self.spheres, ray, &mut t_max));
        keep(Kind::Plane, nearest_in(self.planes, ray, &mut t_max));
        keep(Kind::Triangle, nearest_in(self.triangles, ray, &mut t_max));
        keep(Kind::Box, nearest_in(self.boxes, ray, &mut t_max));
        best
    }

    /// The time of the nearest hit of `ray` with `0 < t < t_max`, if any.
    #[must_use]
    pub fn first_hit(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        self.nearest(ray, t_max).map(|n| n.hit.t)
    }

    /// True when anything blocks `ray` before `t_max`.
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        occluded_in(self.spheres, ray, t_max)
            || occluded_in(self.planes, ray, t_max)
            || occluded_in(self.triangles, ray, t_max)
            || occluded_in(self.boxes, ray, t_max)
    }

    fn shaded(
        &self,
        n: &Nearest,
        ray: &Ray,
        footprint: Option<&Footprint<'_>>,
    ) -> Option<Shaded<'a>> {
        match n.kind {
            Kind::Sphere => resolve(self, self.spheres, n, ray, footprint),
            Kind::Plane => resolve(self, self.planes, n, ray, footprint),
            Kind::Triangle => resolve(self, self.triangles, n, ray, footprint),
            Kind::Box => resolve(self, self.boxes, n, ray, footprint),
        }
    }

    /// The colour seen along `ray` up to `t_max`, with reflections and
    /// transmissions down to `max_depth` bounces (clamped to [`MAX_DEPTH`]).
    #[must_use]
    pub fn trace(&self, ray: Ray, t_max: f32, max_depth: u8) -> Color {
        self.trace_counted(ray, t_max, max_depth, &mut RayCount::default())
    }

    /// [`SceneView::trace`], adding the rays it casts to `count`.
    pub fn trace_counted(
        &self,
        ray: Ray,
        t_max: f32,
        max_depth: u8,
        count: &mut RayCount,
    ) -> Color {
        self.trace_footprint(ray, t_max, max_depth, count, None)
    }

    /// [`SceneView::trace_counted`] where the camera ray carries its pixel: a texture
    /// it hits is averaged exactly over the pixel's footprint (box filter) instead of
    /// evaluated at one point.
    pub fn trace_footprint(
        &self,
        ray: Ray,
        t_max: f32,
        max_depth: u8,
        count: &mut RayCount,
        footprint: Option<&Footprint<'_>>,
    ) -> Color {
        let max_depth = if self.secondary {
            max_depth.min(MAX_DEPTH)
        } else {
            0
        };
        let mut stack: heapless::Vec<Pending, { MAX_DEPTH as usize + 1 }> = heapless::Vec::new();
        let mut total = Color::BLACK;
        // Cannot fail: the stack is empty.
        let _ = stack.push(Pending {
            ray,
            t_max,
            weight: Color::WHITE,
            depth: 0,
        });
        while let Some(p) = stack.pop() {
            if p.depth == 0 {
                count.primary += 1;
            } else {
                count.secondary += 1;
            }
            let Some(nearest) = self.nearest(&p.ray, p.t_max) else {
                total += p.weight * self.background;
                continue;
            };
            let corners = if p.depth == 0 { footprint } else { None };
            let Some(hit) = self.shaded(&nearest, &p.ray, corners) else {
                continue; // unreachable for a validated scene: no material, no light
            };
            total += p.weight * self.local(&hit, &p.ray, count);
            if p.depth < max_depth {
                for (ray, w) in secondary(&hit, &p.ray).into_iter().flatten() {
                    let weight = p.weight * w;
                    if !weight.is_black() {
                        // At most depth + 1 pending rays: the push cannot fail.
                        let _ = stack.push(Pending {
                            ray,
                            t_max: f32::INFINITY,
                            weight,
                            depth: p.depth + 1,
                        });
                    }
                }
            }
        }
        total
    }

    /// Ambient + direct light at a hit (no secondary rays).
    fn local(&self, hit: &Shaded<'_>, ray: &Ray, count: &mut RayCount) -> Color {
        let m = hit.material;
        let mut c = hit.base * self.ambient * m.ambient();
        if !m.is_lit() {
            return c;
        }
        let s = &hit.surface;
        let n = facing(s.normal, ray.dir);
        for light in self.lights {
            let to_light = light.position() - s.point;
            let dist2 = to_light.length_squared();
            let dist = math::sqrt(dist2);
            if dist.is_nan() || dist <= 0.0 {
                continue;
            }
            let l = to_light / dist;
            let cos = n.dot(l);
            if cos.is_nan() || cos <= 0.0 {
                continue; // light behind the surface as seen from the ray
            }
            let origin = offset_origin(s.point, s.error, n, l);
            count.shadow += 1;
            if self.occluded(&Ray::new(origin, l), dist) {
                continue;
            }
            let e = light.color() * (light.intensity() / dist2);
            let mut lit = hit.base * (m.diffuse() * cos);
            if m.specular() > 0.0 {
                let h = (l - ray.dir).normalize_or(n);
                let nh = n.dot(h);
                if nh > 0.0 {
                    lit += Color::splat(m.specular() * math::powf(nh, m.shininess()));
                }
            }
            c += e * lit;
        }
        c
    }
}

/// The normal turned to face the incoming ray.
fn facing(normal: Vec3, dir: Vec3) -> Vec3 {
    if normal.dot(dir) > 0.0 {
        -normal
    } else {
        normal
    }
}

/// The reflected and refracted rays of a hit, with their weights (each `None` when
/// its weight is zero).
fn secondary(hit: &Shaded<'_>, ray: &Ray) -> [Option<(Ray, Color)>; 2] {
    let m = hit.material;
    let (kr, kt) = (m.reflectivity(), m.transparency());
    if kr == 0.0 && kt == 0.0 {
        return [None, None];
    }
    let s = &hit.surface;
    let entering = s.normal.dot(ray.dir) < 0.0;
    let n = if entering { s.normal } else { -s.normal };
    let cos_i = (-ray.dir.dot(n)).clamp(0.0, 1.0);
    let mut reflect_w = kr;
    let mut refracted = None;
    if kt > 0.0 {
        match refract(ray.dir, n, cos_i, m.ior(), entering) {
            Some((dir, fresnel)) => {
                reflect_w += kt * fresnel;
                let w = kt * (1.0 - fresnel);
                if w > 0.0 {
                    let origin = offset_origin(s.point, s.error, n, dir);
                    refracted = Some((Ray::new(origin, dir), Color::splat(w)));
                }
            }
            None => reflect_w += kt, // total internal reflection
        }
    }
    let reflected = if reflect_w > 0.0 {
        let dir = ray.dir.reflect(n).normalize_or(n);
        let origin = offset_origin(s.point, s.error, n, dir);
        Some((Ray::new(origin, dir), Color::splat(reflect_w)))
    } else {
        None
    };
    [reflected, refracted]
}

/// Snell's law at a surface of relative index `ior`, for a unit direction `d`
/// arriving on the side of the unit normal `n` (so `cos_i = -d.n >= 0`).
/// Returns the refracted unit direction and the Fresnel reflectance (Schlick), or
/// `None` on total internal reflection.
#[must_use]
pub fn refract(d: Vec3, n: Vec3, cos_i: f32, ior: f32, entering: bool) -> Option<(Vec3, f32)> {
    let eta = if entering { 1.0 / ior } else { ior };
    let sin2_i = math::max(1.0 - cos_i * cos_i, 0.0);
    let sin2_t = eta * eta * sin2_i;
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = math::sqrt(1.0 - sin2_t);
    let dir = (d * eta + n * (eta * cos_i - cos_t)).normalize_or(d);
    // Schlick, with the cosine on the lighter side of the interface.
    let r0 = (1.0 - ior) / (1.0 + ior);
    let r0 = r0 * r0;
    let c = 1.0 - if entering { cos_i } else { cos_t };
    let c5 = c * c * c * c * c;
    Some((dir, r0 + (1.0 - r0) * c5))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refraction_follows_snell() {
        // 45 degrees into glass (n = 1.5): sin t = sin 45 / 1.5.
        let d = Vec3::new(1.0, -1.0, 0.0).try_normalize().unwrap();
        let (t, r) = refract(d, Vec3::Y, -d.dot(Vec3::Y), 1.5, true).unwrap();
        let sin_t = (0.5f64).sqrt() / 1.5;
        assert!((t.x as f64 - sin_t).abs() < 1e-6);
        assert!((t.y as f64 + (1.0 - sin_t * sin_t).sqrt()).abs() < 1e-6);
        assert!((t.length() - 1.0).abs() < 1e-6);
        // Schlick at 45 degrees: r0 = 0.04, (1 - cos)^5 = (1 - 0.7071)^5.
        let expect = 0.04 + 0.96 * (1.0 - 0.5f64.sqrt()).powi(5);
        assert!((r as f64 - expect).abs() < 1e-6);
        // Normal incidence: straight through, r = r0.
        let (t, r) = refract(-Vec3::Y, Vec3::Y, 1.0, 1.5, true).unwrap();
        assert_eq!(t, -Vec3::Y);
        assert!((r - 0.04).abs() < 1e-7);
    }

    #[test]
    fn total_internal_reflection_beyond_the_critical_angle() {
        // Leaving glass (1.5): critical angle asin(1/1.5) = 41.81 degrees.
        let crit = (1.0f64 / 1.5).asin();
        for (deg, tir) in [
            (30.0f64, false),
            (41.7, false),
            (41.9, true),
            (60.0, true),
            (89.9, true),
        ] {
            let a = deg.to_radians();
            let d = Vec3::new(a.sin() as f32, -(a.cos() as f32), 0.0);
            let out = refract(d, Vec3::Y, a.cos() as f32, 1.5, false);
            assert_eq!(
                out.is_none(),
                tir,
                "{deg} deg (critical {})",
                crit.to_degrees()
            );
            if let Some((t, r)) = out {
                assert!(t.is_finite() && (0.0..=1.0).contains(&r));
            }
        }
        // Grazing incidence from outside never is TIR and never NaN.
        let (t, r) = refract(Vec3::X, Vec3::Y, 0.0, 1.5, true).unwrap();
        assert!(t.is_finite() && (r - 1.0).abs() < 1e-6);
    }

    #[test]
    fn reflection_vector() {
        let d = Vec3::new(0.6, -0.8, 0.0);
        assert_eq!(d.reflect(Vec3::Y), Vec3::new(0.6, 0.8, 0.0));
        assert_eq!(facing(Vec3::Y, d), Vec3::Y);
        assert_eq!(facing(-Vec3::Y, d), Vec3::Y);
    }
}
