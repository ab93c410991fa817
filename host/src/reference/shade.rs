//! The recursive shader of the reference: ambient, Lambert and Blinn-Phong per
//! light with shadow rays, then mirror and refracted rays (Snell, Schlick, total
//! internal reflection), and the per-pixel signature of what the rays met.

use super::geometry::Shape;
use super::geometry::{Hit, Ray};
use super::scene::{Mat, Object, RefScene, Tex};
use super::vec::V3;

/// An FNV-1a hash of the identities met along a pixel's rays.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Signature(pub u64);

impl Default for Signature {
    fn default() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
}

/// Signature tokens: the role of a ray, what it hit, a shadow ray's outcome, the
/// checker cell it saw, the part of a primitive it hit ([`Tracer::part`]).
const CAMERA: u64 = 1 << 62;
const REFLECTED: u64 = 2 << 62;
const REFRACTED: u64 = 3 << 62;
const MISS: u64 = u64::MAX;
const HIT: u64 = 1 << 60;
const SHADOW: u64 = 1 << 59;
const TEXEL: u64 = 1 << 58;
const PART: u64 = 1 << 57;

impl Signature {
    /// Mixes one token in.
    pub fn push(&mut self, token: u64) {
        for byte in token.to_le_bytes() {
            self.0 = (self.0 ^ u64::from(byte)).wrapping_mul(0x0100_0000_01b3);
        }
    }
}

/// Traces rays through a [`RefScene`] down to `max_depth` bounces.
pub struct Tracer<'a> {
    /// The scene.
    pub scene: &'a RefScene,
    /// Bounces after the camera ray.
    pub max_depth: u8,
}

/// `p` moved off its surface, along the unit normal `n`, to the side of `dir`.
fn spawn(p: V3, n: V3, dir: V3) -> V3 {
    let eps = 1e-9 * (1.0 + p.abs().max_component());
    if dir.dot(n) >= 0.0 {
        p + n * eps
    } else {
        p - n * eps
    }
}

impl Tracer<'_> {
    /// The colour of a camera ray (depth 0) up to `t_max`.
    pub fn trace_camera(&self, ray: &Ray, t_max: f64, sig: &mut Signature) -> V3 {
        sig.push(CAMERA);
        self.trace(ray, t_max, 0, None, sig)
    }

    /// The colour of a camera ray whose texture lookup is averaged over the pixel's
    /// footprint: the box spanned by the uv of the four corner rays on the same
    /// shape (point lookup if a corner misses it or it wraps round a sphere).
    pub fn trace_camera_prefiltered(
        &self,
        ray: &Ray,
        t_max: f64,
        corners: &[Ray; 4],
        sig: &mut Signature,
    ) -> V3 {
        sig.push(CAMERA);
        self.trace(ray, t_max, 0, Some(corners), sig)
    }

    /// The colour seen along `ray` (with its reflections and refractions).
    fn trace(
        &self,
        ray: &Ray,
        t_max: f64,
        depth: u8,
        corners: Option<&[Ray; 4]>,
        sig: &mut Signature,
    ) -> V3 {
        let Some((obj, hit)) = self.scene.nearest(ray, t_max) else {
            sig.push(MISS);
            return self.scene.background;
        };
        sig.push(HIT | obj.kind << 32 | obj.index);
        let m = &self.scene.materials[obj.material];
        let p = ray.at(hit.t);
        let normal = obj.shape.normal(p, &hit);
        let uv = obj.uv(p, normal, &hit);
        Self::part(obj, &hit, m, (ray.dir, uv), sig);
        let footprint = corners.and_then(|cs| {
            let (mut lo, mut hi) = (uv, uv);
            for c in cs {
                let h = obj.shape.intersect(c, f64::INFINITY)?;
                let q = c.at(h.t);
                let [u, v] = obj.uv(q, obj.shape.normal(q, &h), &h);
                lo = [lo[0].min(u), lo[1].min(v)];
                hi = [hi[0].max(u), hi[1].max(v)];
            }
            let wraps = obj.shape.uv_wraps() && (hi[0] - lo[0] > 0.5 || hi[1] - lo[1] > 0.5);
            (!wraps).then_some((lo, hi))
        });
        let base = match footprint {
            Some((lo, hi)) => m.texture.eval_box(lo, hi),
            None => m.texture.eval(uv),
        };
        // A checker's cell edges and a nearest-filtered image's texel edges are
        // discontinuities too: rounding may put a sample on either side, so they
        // belong in the silhouette band.
        if let Some(piece) = m.texture.edge_piece(uv) {
            sig.push(TEXEL | piece);
        }
        let mut c = self.local(m, base, p, (normal, obj, &hit), ray, sig);
        if depth < self.max_depth {
            for (role, child, w) in secondary(m, p, normal, ray).into_iter().flatten() {
                sig.push(role);
                c = c + self.trace(&child, f64::INFINITY, depth + 1, None, sig) * w;
            }
        }
        c
    }

    /// Signs which part of one primitive a ray hit where its shading jumps
    /// across the parts' edges, so that those edges are in the silhouette band
    /// as an edge between two primitives is: a box's face (its normal and uv
    /// change at its edges); a mesh's face when the mesh is textured (its uv are
    /// the face's barycentrics) or flat (its normal, turned to the ray as the
    /// shading turns it, rounded to 2^-20 so that coplanar faces, whose normals
    /// differ by rounding, sign alike); a sphere's half of `u` when it has
    /// fringes (their phase jumps where `u` wraps from 1 to 0, and this also
    /// bands the meridian `u = 0.5`, where nothing jumps). A smooth mesh's vertex
    /// normals and a plane's or triangle's one surface change nothing abruptly
    /// within the primitive (a checker's cells are signed by their parity).
    fn part(obj: &Object, hit: &Hit, m: &Mat, (dir, uv): (V3, [f64; 2]), sig: &mut Signature) {
        match obj.shape {
            Shape::Box { .. } | Shape::Cylinder { .. } => {
                let wrap = obj.shape.uv_wraps() && matches!(m.texture, Tex::Fringes { .. });
                sig.push(PART | hit.face as u64 | u64::from(wrap && uv[0] >= 0.5) << 8);
            }
            _ if obj.shape.uv_wraps() && matches!(m.texture, Tex::Fringes { .. }) => {
                sig.push(PART | u64::from(uv[0] >= 0.5));
            }
            Shape::Triangle { p } if obj.kind == super::scene::MESH_FACE => {
                if !matches!(m.texture, Tex::Solid(_)) {
                    sig.push(PART | obj.face);
                } else if obj.normals.is_none() {
                    let g = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
                    let g = if g.dot(dir) > 0.0 { -g } else { g };
                    sig.push(PART);
                    for c in [g.x, g.y, g.z] {
                        // +0.0 makes -0 sign as 0.
                        sig.push(((c * 1_048_576.0).round() + 0.0).to_bits());
                    }
                }
            }
            _ => {}
        }
    }

    /// Ambient plus direct light from every light not in shadow. `normal`: the
    /// surface's, and the object and hit that give the shading normal (a smooth
    /// mesh's, [`Object::shading`]).
    fn local(
        &self,
        m: &Mat,
        base: V3,
        p: V3,
        (normal, obj, hit): (V3, &Object, &Hit),
        ray: &Ray,
        sig: &mut Signature,
    ) -> V3 {
        let mut c = base.times(self.scene.ambient) * m.ka;
        if m.kd <= 0.0 && m.ks <= 0.0 {
            return c;
        }
        let n = if normal.dot(ray.dir) > 0.0 {
            -normal
        } else {
            normal
        };
        let ns = obj.shading(n, hit);
        let side = if n.dot(normal) < 0.0 { -1.0 } else { 1.0 };
        let from = p + obj.lift(p, hit, side);
        for (i, light) in self.scene.lights.iter().enumerate() {
            let Some((l, dist, e)) = light.toward(p) else {
                continue;
            };
            let cos = ns.dot(l);
            if cos.is_nan() || cos <= 0.0 {
                continue;
            }
            let shadow = Ray {
                origin: spawn(from, n, l),
                dir: l,
            };
            let blocked = self.scene.blocked(&shadow, dist);
            sig.push(SHADOW | (i as u64) << 1 | u64::from(blocked));
            if blocked {
                continue;
            }
            let mut lit = base * (m.kd * cos);
            if m.ks > 0.0 {
                let h = (l - ray.dir).normalize();
                let h = if h.is_finite() { h } else { ns };
                let nh = ns.dot(h);
                if nh > 0.0 {
                    let s = m.ks * nh.powf(m.shininess);
                    lit = lit + V3::new(s, s, s);
                }
            }
            c = c + e.times(lit);
        }
        c
    }

    /// What the adaptive sampler compares of a camera ray besides its colour: a
    /// hash of the primitive it hit (or that it missed) and of the outcome of
    /// each shadow ray from that hit, and whether the hit is textured. The same
    /// rule as the core's (its module `shade`, `Signed`), written from the
    /// sampler's description: only the camera ray's own hit counts, and of its
    /// lights only those blocked (a light behind the surface or unblocked gives
    /// no token).
    pub fn camera_probe(&self, ray: &Ray, t_max: f64) -> (u64, bool) {
        let mut sig = Signature::default();
        let Some((obj, hit)) = self.scene.nearest(ray, t_max) else {
            sig.push(MISS);
            return (sig.0, false);
        };
        sig.push(HIT | obj.kind << 32 | obj.index);
        let m = &self.scene.materials[obj.material];
        let textured = !matches!(m.texture, super::scene::Tex::Solid(_));
        if m.kd <= 0.0 && m.ks <= 0.0 {
            return (sig.0, textured);
        }
        let p = ray.at(hit.t);
        let normal = obj.shape.normal(p, &hit);
        let n = if normal.dot(ray.dir) > 0.0 {
            -normal
        } else {
            normal
        };
        let ns = obj.shading(n, &hit);
        let side = if n.dot(normal) < 0.0 { -1.0 } else { 1.0 };
        let from = p + obj.lift(p, &hit, side);
        for (i, light) in self.scene.lights.iter().enumerate() {
            let Some((l, dist, _)) = light.toward(p) else {
                continue;
            };
            let cos = ns.dot(l);
            if cos.is_nan() || cos <= 0.0 {
                continue;
            }
            let shadow = Ray {
                origin: spawn(from, n, l),
                dir: l,
            };
            if self.scene.blocked(&shadow, dist) {
                sig.push(SHADOW | (i as u64) << 1 | 1);
            }
        }
        (sig.0, textured)
    }
}

/// The mirror and refracted rays of a hit, with their role token and weight, each
/// `None` when its weight is zero.
fn secondary(m: &Mat, p: V3, normal: V3, ray: &Ray) -> [Option<(u64, Ray, f64)>; 2] {
    if m.kr == 0.0 && m.kt == 0.0 {
        return [None, None];
    }
    let d = ray.dir;
    let entering = normal.dot(d) < 0.0;
    let n = if entering { normal } else { -normal };
    let cos_i = (-d.dot(n)).clamp(0.0, 1.0);
    let mut reflect_w = m.kr;
    let mut refracted = None;
    if m.kt > 0.0 {
        match refract(d, n, cos_i, m.ior, entering) {
            Some((dir, fresnel)) => {
                reflect_w += m.kt * fresnel;
                let w = m.kt * (1.0 - fresnel);
                if w > 0.0 {
                    let child = Ray {
                        origin: spawn(p, n, dir),
                        dir,
                    };
                    refracted = Some((REFRACTED, child, w));
                }
            }
            None => reflect_w += m.kt,
        }
    }
    let reflected = (reflect_w > 0.0).then(|| {
        let dir = (d - n * (2.0 * d.dot(n))).normalize();
        let child = Ray {
            origin: spawn(p, n, dir),
            dir,
        };
        (REFLECTED, child, reflect_w)
    });
    [reflected, refracted]
}

/// Snell's law for the unit direction `d` arriving against the unit normal `n`
/// (`cos_i = -d.n`): the refracted direction and Schlick's reflectance, or `None` on
/// total internal reflection.
#[must_use]
pub fn refract(d: V3, n: V3, cos_i: f64, ior: f64, entering: bool) -> Option<(V3, f64)> {
    let eta = if entering { 1.0 / ior } else { ior };
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let dir = (d * eta + n * (eta * cos_i - cos_t)).normalize();
    let r0 = ((1.0 - ior) / (1.0 + ior)).powi(2);
    let c = if entering { cos_i } else { cos_t };
    Some((dir, r0 + (1.0 - r0) * (1.0 - c).powi(5)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::scene::Tex;

    #[test]
    fn snell_at_45_degrees_into_glass() {
        let d = V3::new(1.0, -1.0, 0.0).normalize();
        let (t, r) = refract(d, V3::Y, -d.dot(V3::Y), 1.5, true).unwrap();
        // sin t = sin 45 / 1.5, written out.
        let sin_t = 0.5f64.sqrt() / 1.5;
        assert!((t.x - sin_t).abs() < 1e-15);
        assert!((t.y + (1.0 - sin_t * sin_t).sqrt()).abs() < 1e-15);
        assert_eq!(t.z, 0.0);
        // Schlick: r0 = (0.5 / 2.5)^2 = 0.04.
        let expect = 0.04 + 0.96 * (1.0 - 0.5f64.sqrt()).powi(5);
        assert!((r - expect).abs() < 1e-15);
    }

    #[test]
    fn total_internal_reflection_beyond_the_critical_angle() {
        // Leaving glass: critical angle asin(1 / 1.5) = 41.81 degrees.
        for (deg, tir) in [(30.0f64, false), (41.8, false), (41.82, true), (60.0, true)] {
            let a = deg.to_radians();
            let d = V3::new(a.sin(), -a.cos(), 0.0);
            assert_eq!(
                refract(d, V3::Y, a.cos(), 1.5, false).is_none(),
                tir,
                "{deg}"
            );
        }
        // TIR sends all of kt to the mirror ray.
        let glass = Mat {
            texture: Tex::Solid(V3::ZERO),
            ka: 0.0,
            kd: 0.0,
            ks: 0.0,
            shininess: 1.0,
            kr: 0.1,
            kt: 0.9,
            ior: 1.5,
        };
        let a = 60f64.to_radians();
        let ray = Ray {
            origin: V3::ZERO,
            dir: V3::new(a.sin(), a.cos(), 0.0),
        };
        // Outward normal +y, ray going out: leaving the glass.
        let [refl, refr] = secondary(&glass, V3::Y, V3::Y, &ray);
        assert!(refr.is_none());
        let (_, r, w) = refl.unwrap();
        assert!((w - 1.0).abs() < 1e-15);
        assert!((r.dir - V3::new(a.sin(), -a.cos(), 0.0)).length() < 1e-15);
    }
}
