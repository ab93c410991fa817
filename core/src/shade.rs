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
//! rays are clipped by the far plane. Colours are linear here; the tile loops encode
//! them for output ([`crate::Encoding`]: sRGB by default).
//!
//! Bounded stack: there is no recursion. A camera ray's own hit is shaded inline
//! in the pixel loop's call per sample; only if that hit sends reflected or
//! refracted rays does one more call trace them. Pending rays wait on a fixed-size
//! stack with their (grey) weight; each ray adds `weight x local colour` and pushes
//! at most two children. Depth-first, a depth limit `D` needs at most `D + 1` slots,
//! so the stack holds [`MAX_DEPTH`]` + 1`.
//!
//! Model only what the scene requires: a ray whose weight is zero is never traced;
//! no shadow ray, uv or secondary ray is computed where the material does not need
//! it; a hit's error bound (for the origin of the rays leaving it) is computed only
//! when a ray leaves it; a shadow ray whose tile lists hold no blocker of its light
//! is answered without being built. The Blinn-Phong power is computed by repeated
//! squaring when the shininess is an integer ([`crate::material::Material::highlight`]).

use crate::color::Color;
use crate::cull::{MASKED_LIGHTS, PLANE_RECEIVERS, Picks, SOLID_RECEIVERS, ShadowLists};
use crate::error::MAX_DEPTH;
use crate::hit::{self, Geom, Hit};
use crate::math;
use crate::prefilter::Footprint;
use crate::ray::{Ray, offset_origin};
use crate::search::{self, Listed, Masked, Skip};
use crate::vec::Vec3;
use crate::view::SceneView;

/// How many rays a trace cast, by kind (for reports and for tests of what is not
/// traced).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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

/// Where the rays a render casts are counted: pass `&mut ()` not to count (it
/// compiles to nothing), or a [`RayCount`] for the figures. Sealed: these are
/// the two.
pub trait RayCounter: sealed::Sealed {
    /// A camera ray was traced.
    #[doc(hidden)]
    fn primary(&mut self);
    /// A reflected or refracted ray was traced.
    #[doc(hidden)]
    fn secondary(&mut self);
    /// A shadow ray was traced.
    #[doc(hidden)]
    fn shadow(&mut self);
}

pub(crate) mod sealed {
    pub trait Sealed {}
    impl Sealed for () {}
    impl Sealed for super::RayCount {}
}

impl RayCounter for () {
    #[inline(always)]
    fn primary(&mut self) {}
    #[inline(always)]
    fn secondary(&mut self) {}
    #[inline(always)]
    fn shadow(&mut self) {}
}

/// What the shader reports as it traces: the rays it casts (to a
/// [`RayCounter`]) and, for the adaptive sampler's centre rays only, what they
/// met ([`Signature`]).
pub(crate) trait Observer {
    /// Whether [`Observer::token`] records anything (every token is computed
    /// under `if O::SIGNS`, so that a plain counter compiles it away).
    const SIGNS: bool = false;
    /// A camera ray was traced.
    fn primary(&mut self);
    /// A reflected or refracted ray was traced.
    fn secondary(&mut self);
    /// A shadow ray was traced.
    fn shadow(&mut self);
    /// What a ray met (see [`Signature`]).
    #[inline(always)]
    fn token(&mut self, _token: u32) {}
    /// The camera ray hit a textured surface.
    #[inline(always)]
    fn textured(&mut self) {}
}

impl<C: RayCounter> Observer for C {
    #[inline(always)]
    fn primary(&mut self) {
        RayCounter::primary(self);
    }
    #[inline(always)]
    fn secondary(&mut self) {
        RayCounter::secondary(self);
    }
    #[inline(always)]
    fn shadow(&mut self) {
        RayCounter::shadow(self);
    }
}

/// The adaptive sampler's signature of a centre ray: a hash of what the ray
/// met (the primitive it hit, or that it missed, and which lights are blocked
/// from that hit) and whether the hit is textured; its rays are counted by the
/// counter it wraps.
pub(crate) struct Signature<'c, C> {
    pub(crate) count: &'c mut C,
    pub(crate) hash: u32,
    pub(crate) textured: bool,
}

impl<'c, C: RayCounter> Signature<'c, C> {
    /// A new signature, counting into `count`.
    #[inline(always)]
    pub(crate) fn new(count: &'c mut C) -> Self {
        Self {
            count,
            hash: 0x811c_9dc5,
            textured: false,
        }
    }
}

impl<C: RayCounter> Observer for Signature<'_, C> {
    const SIGNS: bool = true;
    #[inline(always)]
    fn primary(&mut self) {
        self.count.primary();
    }
    #[inline(always)]
    fn secondary(&mut self) {
        self.count.secondary();
    }
    #[inline(always)]
    fn shadow(&mut self) {
        self.count.shadow();
    }
    #[inline(always)]
    fn token(&mut self, token: u32) {
        self.hash = crate::sample::mix(self.hash ^ token);
    }
    #[inline(always)]
    fn textured(&mut self) {
        self.textured = true;
    }
}

/// Signature tokens: a camera ray that missed; its hit (kind in bits 24-25,
/// index below); a light blocked from that hit (its index below). Only blocked
/// lights count: a light behind the surface and an unblocked one give no
/// token, so that the terminator of a lit sphere (where the light's colour
/// fades out smoothly) is no edge, and a shadow's outline is.
const MISS: u32 = u32::MAX;
const HIT: u32 = 1 << 28;
const SHADOW: u32 = 2 << 28;

/// The token of a camera ray's nearest hit (`None`: a miss) into `count`'s
/// signature.
#[inline(always)]
fn sign_hit<C: Observer>(count: &mut C, hit: Option<&Hit<'_>>) {
    let Some(hit) = hit else {
        count.token(MISS);
        return;
    };
    let (kind, index) = match hit.geom {
        // A mesh is one object: its faces share a token (a smooth mesh has no
        // edge between faces; a flat one's show as colour steps).
        #[cfg(feature = "bvh")]
        Geom::Mesh(..) => (
            crate::kind::Kind::Mesh,
            crate::search::MeshFace::of(hit.index).mesh,
        ),
        #[cfg(feature = "instances")]
        Geom::Placed(..) => (
            crate::kind::Kind::Mesh,
            crate::search::MeshFace::of(hit.index).mesh,
        ),
        g => (g.kind().0, hit.index),
    };
    count.token(HIT | (kind as u32) << 24 | (index as u32 & 0x00ff_ffff));
}

impl RayCounter for RayCount {
    #[inline(always)]
    fn primary(&mut self) {
        self.primary += 1;
    }
    #[inline(always)]
    fn secondary(&mut self) {
        self.secondary += 1;
    }
    #[inline(always)]
    fn shadow(&mut self) {
        self.shadow += 1;
    }
}

/// A ray waiting to be traced, with the weight of its contribution. The weights
/// are grey (products of scalar reflectivities and transmittances), so one `f32`:
/// `c * w` per component is the product with `Color::splat(w)`, bit for bit.
#[derive(Clone, Copy)]
struct Pending {
    ray: Ray,
    weight: f32,
    skip: Skip,
    depth: u8,
}

/// The colour seen along `ray` up to `t_max`, with reflections and
/// transmissions down to `max_depth` bounces (clamped to [`MAX_DEPTH`]), every
/// primitive a candidate; the rays cast are added to `count` (`&mut ()` not to
/// count).
pub fn trace<C: RayCounter>(
    view: &SceneView<'_>,
    ray: Ray,
    t_max: f32,
    max_depth: u8,
    count: &mut C,
) -> Color {
    let depth = view.depth(max_depth);
    let cam = CameraRay {
        ray,
        t_max,
        footprint: None,
    };
    trace_with::<_, true>(view, cam, depth, &Picks::default(), count)
}

/// A camera ray: the ray, how far it looks (the far plane), and the pixel it
/// carries (`footprint`, where the sampler prefilters textures).
#[derive(Clone, Copy)]
pub(crate) struct CameraRay<'a> {
    pub ray: Ray,
    pub t_max: f32,
    pub footprint: Option<&'a Footprint<'a>>,
}

/// The colour a camera ray brings back: its nearest hit among `picks.camera`,
/// shaded with the shadow rays' candidates `picks.shadow`, then the reflected
/// and refracted rays depth-first on a fixed stack. Where the camera ray carries
/// its pixel (`footprint`), a texture it hits is averaged exactly over the
/// pixel's footprint (box filter) instead of evaluated at one point.
///
/// The camera ray's hit ([`primary`]) is inlined here; with bounces (`BOUNCES`:
/// the caller knows whether the depth is 0) [`bounce`] is called, out of line,
/// only when that hit sends rays. (With `primary` out of line too, its stack
/// frame and `bounce`'s would never add up: less stack in a scene with mirrors,
/// for one more call per camera ray.)
///
/// `max_depth` is the scene's depth, clamped once by the caller
/// ([`SceneView::depth`]).
#[inline(always)]
pub(crate) fn trace_with<C: Observer, const BOUNCES: bool>(
    view: &SceneView<'_>,
    cam: CameraRay<'_>,
    max_depth: u8,
    picks: &Picks<'_>,
    count: &mut C,
) -> Color {
    if !BOUNCES {
        return primary(view, &cam, 0, picks, count, &mut [None, None]);
    }
    let mut first = [None, None];
    let mut total = primary(view, &cam, max_depth, picks, count, &mut first);
    if first.iter().any(Option::is_some) {
        bounce(view, &first, max_depth, &mut total, count);
    }
    total
}

/// The camera ray's own colour; the reflected and refracted rays its hit sends
/// when `max_depth > 0` go to `first` (left as it is otherwise).
#[inline(always)]
fn primary<C: Observer>(
    view: &SceneView<'_>,
    cam: &CameraRay<'_>,
    max_depth: u8,
    picks: &Picks<'_>,
    count: &mut C,
    first: &mut [Option<Pending>; 2],
) -> Color {
    let CameraRay {
        ref ray,
        t_max,
        footprint,
    } = *cam;
    count.primary();
    let nearest = match &picks.camera {
        Some(lists) => search::nearest(view, ray, t_max, Listed(lists), Skip::NONE),
        // Every primitive, or a tile's lists with its meshes and instances,
        // out of line.
        None => search::nearest_untiled(view, ray, t_max, picks.with_tops.as_ref()),
    };
    let Some(nearest) = nearest else {
        if C::SIGNS {
            sign_hit(count, None);
        }
        return view.background;
    };
    let Some(hit) = hit::resolve(view, &nearest, ray, footprint) else {
        return Color::BLACK; // unreachable for a validated scene: no material
    };
    if C::SIGNS {
        sign_hit(count, Some(&hit));
        if hit.material.texture().needs_uv() {
            count.textured();
        }
    }
    // A hit that no light changes and that sends no ray is its ambient colour
    // (what `local` would give). Decided before the hit is rebuilt for the
    // code below, whose out-of-line calls take its address: the hit of this
    // path then never goes to memory (fewer instructions per pixel on the chip,
    // above all on interference, whose unlit screen takes this path).
    let m = hit.material;
    if !(m.is_lit() || max_depth > 0 && m.sends_rays()) {
        return hit.base * view.ambient * m.ambient();
    }
    let hit = Hit {
        error: core::cell::Cell::new(None),
        ..hit
    };
    let total = local::<false, _>(view, &hit, ray, picks.shadow.as_ref(), count, true);
    if max_depth > 0 && hit.material.sends_rays() {
        children(&hit, ray, 1.0, 0, first);
    }
    total
}

/// Adds what `first` (the reflected and refracted rays of a camera ray's hit)
/// bring back to `total`: depth-first, with a fixed stack of pending rays
/// (depth `D` needs at most `D + 1` slots), every primitive a candidate. Out of
/// line: a scene without mirrors or glass never comes here.
#[inline(never)]
fn bounce<C: Observer>(
    view: &SceneView<'_>,
    first: &[Option<Pending>; 2],
    max_depth: u8,
    total: &mut Color,
    count: &mut C,
) {
    let mut stack: heapless::Vec<Pending, { MAX_DEPTH as usize + 1 }> = heapless::Vec::new();
    // At most depth + 1 pending rays: a push cannot fail.
    for p in first.iter().flatten() {
        let _ = stack.push(*p);
    }
    while let Some(p) = stack.pop() {
        count.secondary();
        let Some(nearest) = search::nearest_whole(view, &p.ray, f32::INFINITY, p.skip) else {
            *total += view.background * p.weight;
            continue;
        };
        let Some(hit) = hit::resolve(view, &nearest, &p.ray, None) else {
            continue; // unreachable for a validated scene: no material
        };
        *total += local::<false, _>(view, &hit, &p.ray, None, count, false) * p.weight;
        if p.depth < max_depth && hit.material.sends_rays() {
            let mut next = [None, None];
            children(&hit, &p.ray, p.weight, p.depth, &mut next);
            for c in next.iter().flatten() {
                let _ = stack.push(*c);
            }
        }
    }
}

/// [`local`] at a hit of a smooth mesh, out of line.
#[cfg(feature = "bvh")]
#[inline(never)]
fn local_smooth<C: Observer>(
    view: &SceneView<'_>,
    hit: &Hit<'_>,
    ray: &Ray,
    shadow: Option<&ShadowLists<'_>>,
    count: &mut C,
    sign: bool,
) -> Color {
    local::<true, C>(view, hit, ray, shadow, count, sign)
}

/// Ambient + direct light at a hit (no secondary rays); the shadow rays test the
/// candidates of `shadow` (see [`Picks`]). `SMOOTH`: the hit is a smooth
/// mesh's, whose normal is interpolated; callers pass false and a smooth mesh's
/// hit takes the `SMOOTH` copy out of line, so that the other kinds' code is
/// what it is without meshes.
#[inline(always)]
fn local<const SMOOTH: bool, C: Observer>(
    view: &SceneView<'_>,
    hit: &Hit<'_>,
    ray: &Ray,
    shadow: Option<&ShadowLists<'_>>,
    count: &mut C,
    sign: bool,
) -> Color {
    let m = hit.material;
    let mut c = hit.base * view.ambient * m.ambient();
    if !m.is_lit() {
        return c;
    }
    #[cfg(feature = "bvh")]
    if !SMOOTH
        && let Geom::Mesh(mesh) = hit.geom
        && !mesh.normals().is_empty()
    {
        return local_smooth(view, hit, ray, shadow, count, sign);
    }
    #[cfg(feature = "instances")]
    if !SMOOTH
        && let Geom::Placed(p) = hit.geom
        && !p.mesh.normals().is_empty()
    {
        return local_smooth(view, hit, ray, shadow, count, sign);
    }
    let n = facing(hit.normal, ray.dir);
    // The normal the light is weighed with: a smooth mesh's interpolated one
    // (on `n`'s side); `n` itself places the shadow rays, which for a smooth
    // mesh leave from the curved surface its normals describe (`Mesh::lift`:
    // `lift` is the move there).
    #[cfg(feature = "bvh")]
    let (ns, lift) = match hit.geom {
        Geom::Mesh(mesh) if SMOOTH => {
            let (f, b) = (
                crate::search::MeshFace::of(hit.index).face,
                [hit.aux.x, hit.hit.b1, hit.hit.b2],
            );
            let out = if n.dot(hit.normal) < 0.0 { -1.0 } else { 1.0 };
            let ns = mesh.shading_normal(f, b, n);
            (ns, mesh.lift(f, b, hit.point, out))
        }
        #[cfg(feature = "instances")]
        Geom::Placed(p) if SMOOTH => {
            let (f, b) = (
                crate::search::MeshFace::of(hit.index).face,
                [hit.aux.x, hit.hit.b1, hit.hit.b2],
            );
            let out = if n.dot(hit.normal) < 0.0 { -1.0 } else { 1.0 };
            (p.shading_normal(f, b, n), p.lift(f, b, ray, &hit.hit, out))
        }
        _ => (n, Vec3::ZERO),
    };
    #[cfg(not(feature = "bvh"))]
    let ns = n;
    for (i, light) in view.lights.iter().enumerate() {
        // The unit direction to the light, how far the shadow ray searches, and
        // what the irradiance falls off by (`dist^2`; `1 / dist^2` with
        // `fast-rsqrt`): a sun's irradiance is its intensity at any distance.
        let (l, dist, fall) = if light.is_directional() {
            (light.position(), f32::INFINITY, 1.0)
        } else {
            let to_light = light.position() - hit.point;
            let dist2 = to_light.length_squared();
            // `fast-rsqrt`: one reciprocal square root (`math::rsqrt`) gives the
            // distance, the direction and the irradiance, instead of a `vsqrt`,
            // three `vdiv` here and one in `irradiance` (a zero or infinite
            // `dist2` makes `dist` NaN: skipped, as the exact path skips or
            // darkens it).
            #[cfg(feature = "fast-rsqrt")]
            let inv = math::rsqrt(dist2);
            #[cfg(feature = "fast-rsqrt")]
            let dist = dist2 * inv;
            #[cfg(not(feature = "fast-rsqrt"))]
            let dist = math::sqrt(dist2);
            if dist.is_nan() || dist <= 0.0 {
                continue;
            }
            #[cfg(feature = "fast-rsqrt")]
            let l = to_light * inv;
            #[cfg(not(feature = "fast-rsqrt"))]
            let l = to_light / dist;
            #[cfg(feature = "fast-rsqrt")]
            let fall = inv * inv;
            #[cfg(not(feature = "fast-rsqrt"))]
            let fall = dist2;
            (l, dist, fall)
        };
        let cos = ns.dot(l);
        if cos.is_nan() || cos <= 0.0 {
            continue; // light behind the surface as seen from the ray
        }
        count.shadow();
        // Lists for this light: `None` when no primitive of them may block it
        // (the shadow ray would test nothing, so it needs no origin either).
        let lists = match shadow {
            Some(t) if i < MASKED_LIGHTS => {
                let receivers = match hit.geom {
                    Geom::Plane(_) => PLANE_RECEIVERS,
                    _ => SOLID_RECEIVERS,
                };
                let bit = 1 << (receivers + i);
                (t.lights & bit != 0).then_some(Some(Masked(&t.lists, bit)))
            }
            _ => Some(None),
        };
        if let Some(lists) = lists {
            let origin = offset_origin(hit.point, hit.error(ray), n, l);
            #[cfg(feature = "bvh")]
            let origin = if SMOOTH { origin + lift } else { origin };
            let ray = Ray::unit(origin, l);
            let skip = hit.skip_for(l);
            let blocked = match lists {
                Some(m) => search::any_masked(view, &ray, dist, m, skip),
                None => search::any_whole(view, &ray, dist, skip),
            };
            if blocked {
                if C::SIGNS && sign {
                    count.token(SHADOW | i as u32);
                }
                continue;
            }
        }
        // `intensity / dist2` (`intensity inv^2` over 1 with `fast-rsqrt`: the
        // division by 1 compiles to nothing), capped: a sun's `fall` of 1
        // leaves its intensity, capped the same way (a colour of up to 2^16
        // times an intensity near f32's largest would overflow).
        #[cfg(feature = "fast-rsqrt")]
        let e = light.color() * irradiance(light.intensity() * fall, 1.0);
        #[cfg(not(feature = "fast-rsqrt"))]
        let e = light.color() * irradiance(light.intensity(), fall);
        let mut lit = hit.base * (m.diffuse() * cos);
        if m.specular() > 0.0 {
            // `fast-rsqrt`: `n.h` of the unnormalised half vector, scaled by its
            // reciprocal length, at most 1 (the approximation may exceed it by
            // 2.6e-6, which a power of 10000 would raise to 2.6%). Its length is
            // at least `n.l > 0`: never zero.
            #[cfg(feature = "fast-rsqrt")]
            let nh = {
                let h = l - ray.dir;
                math::min(ns.dot(h) * math::rsqrt(h.length_squared()), 1.0)
            };
            #[cfg(not(feature = "fast-rsqrt"))]
            let nh = {
                let h = (l - ray.dir).normalize_or(ns);
                ns.dot(h)
            };
            if nh > 0.0 {
                lit += Color::splat(m.specular() * m.highlight(nh));
            }
        }
        c += e * lit;
    }
    c
}

/// The reflected and refracted rays of `hit` (reached at `depth` by a ray of
/// weight `weight`) that carry weight, reflected first, written to `out`: pushed
/// in this order, the refracted ray is traced first, as a depth-first traversal of
/// the ray tree. Written in place rather than returned: the pair, too large for
/// registers, then is not copied by `memcpy` on its way (a call on the chip for
/// every hit that sends rays).
#[inline(never)]
fn children(hit: &Hit<'_>, ray: &Ray, weight: f32, depth: u8, out: &mut [Option<Pending>; 2]) {
    *out = secondary(hit, ray).map(|child| {
        let (ray, w) = child?;
        let weight = weight * w;
        (weight != 0.0).then(|| Pending {
            skip: hit.skip_for(ray.dir),
            ray,
            weight,
            depth: depth + 1,
        })
    })
}

/// The largest `intensity / r^2` a light gives (`2^64`): reached only by a point
/// within `2^-32` of the light's scale (a light on a surface), where the quotient
/// would otherwise overflow to infinity and an infinity times a zero component
/// would give NaN. With [`crate::error::MAX_COLOR`] it bounds every colour sum (see
/// there).
const MAX_IRRADIANCE: f32 = 18_446_744_073_709_551_616.0;

/// `intensity / dist2`, at most [`MAX_IRRADIANCE`].
#[inline(always)]
fn irradiance(intensity: f32, dist2: f32) -> f32 {
    let q = intensity / dist2;
    if q > MAX_IRRADIANCE {
        MAX_IRRADIANCE
    } else {
        q
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
fn secondary(hit: &Hit<'_>, ray: &Ray) -> [Option<(Ray, f32)>; 2] {
    let m = hit.material;
    let (kr, kt) = (m.reflectivity(), m.transparency());
    if kr == 0.0 && kt == 0.0 {
        return [None, None];
    }
    let error = hit.error(ray);
    let entering = hit.normal.dot(ray.dir) < 0.0;
    let n = if entering { hit.normal } else { -hit.normal };
    let cos_i = (-ray.dir.dot(n)).clamp(0.0, 1.0);
    let mut reflect_w = kr;
    let mut refracted = None;
    if kt > 0.0 {
        match refract(ray.dir, n, cos_i, m.ior(), entering) {
            Some((dir, fresnel)) => {
                reflect_w += kt * fresnel;
                let w = kt * (1.0 - fresnel);
                if w > 0.0 {
                    let origin = offset_origin(hit.point, error, n, dir);
                    refracted = Some((Ray::unit(origin, dir), w));
                }
            }
            None => reflect_w += kt, // total internal reflection
        }
    }
    let reflected = if reflect_w > 0.0 {
        let dir = ray.dir.reflect(n).normalize_or(n);
        let origin = offset_origin(hit.point, error, n, dir);
        Some((Ray::unit(origin, dir), reflect_w))
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
    use crate::camera::Camera;
    use crate::geometry::Plane;
    use crate::light::Light;
    use crate::scene::Scene;

    /// A light almost on a black floor: `intensity / r^2` overflows to infinity,
    /// and infinity times the black material's zero would give a NaN pixel.
    /// Capped at `MAX_IRRADIANCE`, the colour is finite (and black); on a white
    /// floor it is finite and saturates.
    #[test]
    fn a_light_on_a_surface_gives_a_finite_colour() {
        for (grey, expect_black) in [(0.0f32, true), (1.0, false)] {
            let cam =
                Camera::look_at(Vec3::new(0.0, 1.0, 0.0), Vec3::ZERO, Vec3::Z, 0.1, 10.0).unwrap();
            let mut s = Scene::<crate::capacities!(planes: 1, materials: 1, lights: 1)>::new(cam);
            let m = s
                .add_material(crate::material::Material::matte(Color::splat(grey)))
                .unwrap();
            s.add_plane(Plane::try_new(Vec3::ZERO, Vec3::Y).unwrap(), m)
                .unwrap();
            s.add_light(
                Light::point(
                    Vec3::new(0.0, 1e-15, 0.0),
                    Color::splat(crate::error::MAX_COLOR),
                    1e30,
                )
                .unwrap(),
            )
            .unwrap();
            let ray = Ray::unit(Vec3::new(0.0, 1.0, 0.0), -Vec3::Y);
            let c = trace(&s.view(), ray, 10.0, 0, &mut ());
            assert!(c.is_finite(), "{c:?}");
            assert_eq!(c.is_black(), expect_black, "{c:?}");
            assert_eq!(irradiance(1e30, 1e-30), MAX_IRRADIANCE);
            assert_eq!(irradiance(3.0, 4.0), 0.75);
        }
    }

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
