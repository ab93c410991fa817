//! Case 5: boxes, rays in face planes, along edges, signed zeros, against the exact answer.

use super::{INF, V3, V3Ext, exact_ray};
use tessera_core::testing::Shape;
use tessera_core::{Vec3, geometry::Aabb};

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
fn box_truth(lo: V3, hi: V3, o: V3, sign: [i8; 3]) -> Option<(f64, Vec<u8>)> {
    let (mut s0, mut f0) = (f64::NEG_INFINITY, Vec::new());
    let (mut s1, mut f1) = (f64::INFINITY, Vec::new());
    for (axis, &sg) in sign.iter().enumerate() {
        let (l, h, x) = (lo.get(axis), hi.get(axis), o.get(axis));
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
                            let sign = [sign_of(dx), sign_of(dy), sign_of(dz)];
                            let key = check_ray(&b, (lo, hi), o, d, sign, &mut out);
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

/// The sign of a component: 1, -1, or 0 for either zero.
fn sign_of(v: f32) -> i8 {
    if v > 0.0 {
        1
    } else if v < 0.0 {
        -1
    } else {
        0
    }
}

/// One ray of case 5, from `o` along the unit `d` whose components have the signs
/// `sign`, against the exact answer for the box `b` = `[lo, hi]`: counts a
/// disagreement, a wrong hit, a non-finite hit and the in-plane hits in `out`.
/// Returns the hit's `t` (bits) and face, which must not depend on the sign of zero
/// components.
fn check_ray(
    b: &Aabb,
    (lo, hi): (Vec3, Vec3),
    o: Vec3,
    d: Vec3,
    sign: [i8; 3],
    out: &mut BoxRule,
) -> Option<(u32, u8)> {
    let (l, h) = (V3::of(lo), V3::of(hi));
    let ray = exact_ray(o, d);
    let got = b.intersect(&ray, INF);
    let truth = box_truth(l, h, V3::of(o), sign);
    if got.is_some() != truth.is_some() || b.occluded(&ray, INF) != truth.is_some() {
        out.disagreements += 1;
    }
    if let (Some(g), Some((s, faces))) = (got, &truth) {
        let a = f64::from(d.get(sign.iter().position(|&x| x != 0).unwrap_or(0)).abs());
        let t = s / a;
        if !faces.contains(&g.face) || (f64::from(g.t) - t).abs() > 1e-6 * t.max(1.0) {
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
                for (face, plane) in [(2 * axis, lo.get(axis)), (2 * axis + 1, hi.get(axis))] {
                    if o.get(axis) == plane {
                        out.in_plane_hits[face] += 1;
                    }
                }
            }
        }
    }
    got.map(|g| (g.t.to_bits(), g.face))
}
