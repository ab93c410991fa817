//! Case 1: far spheres, hit/miss and `t` against `f64` as the sphere moves away.

use super::{INF, V3, V3Ext, ray_towards, ulp32};
use tessera_core::geometry::Sphere;
use tessera_core::testing::Shape;

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
    let axis = V3::new(0.36, -0.48, -0.8).normalize();
    for origin in [V3::ZERO, V3::new(0.75, -0.5, 0.25) * r] {
        let o32 = origin.f32();
        let c32 = (origin + axis * (ratio * r)).f32();
        let Ok(sphere) = Sphere::try_new(c32, radius) else {
            continue;
        };
        let (o, c) = (V3::of(o32), V3::of(c32));
        let (e1, e2) = (c - o).normalize().basis();
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
                let d = V3::of(ray.dir());
                let dl = d.length();
                let dn = d * (1.0 / dl);
                let f = o - c;
                let b = -f.dot(dn);
                let l = f + dn * b;
                let h_true = l.length();
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
