//! Case 4: tiny triangles, the ray aimed at the centroid must hit.

use super::{INF, Rng, V3, V3Ext, ray_towards};
use tessera_core::testing::Shape;
use tessera_core::{Vec3, geometry::Triangle};

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
        let centre = V3::of(o) + towards * rng.range(1.0, 10.0);
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
        let Some(ray) = ray_towards(o, V3::of(centroid)) else {
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
