//! Ray/shape intersections of the reference renderer, in `f64`, with textbook
//! formulas: the quadratic for spheres, one division for planes, Möller-Trumbore for
//! triangles, the slab test for boxes. Normals and uv follow the core's conventions.

use super::exact;
use super::vec::V3;
use std::f64::consts::PI;

/// A ray `origin + t dir`, `dir` of unit length.
///
/// The fields are visible to the reference renderer only (which builds every ray
/// from a direction it has just normalised): the sphere's half-`b` quadratic assumes
/// `|dir| = 1`, the same trap as the core's `Ray`, so no code outside can build one
/// with another length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Origin.
    pub(super) origin: V3,
    /// Unit direction.
    pub(super) dir: V3,
}

impl Ray {
    /// The point at time `t`.
    #[must_use]
    pub fn at(&self, t: f64) -> V3 {
        self.origin + self.dir * t
    }
}

/// A shape of the scene, with the values of the description.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// Sphere: centre and radius.
    Sphere {
        /// Centre.
        center: V3,
        /// Radius.
        radius: f64,
    },
    /// Infinite double-sided plane: a point and the unit normal.
    Plane {
        /// A point of the plane.
        point: V3,
        /// Unit normal.
        normal: V3,
        /// The plane is `normal . x = offset`: `N . point / |N|` for the normal
        /// `N` as given, computed almost exactly ([`Shape::plane`]), so that the
        /// plane is exact near the world's origin whatever point was given.
        offset: f64,
    },
    /// Double-sided triangle; outward normal along `(p1 - p0) x (p2 - p0)`.
    Triangle {
        /// Vertices `p0, p1, p2`.
        p: [V3; 3],
    },
    /// Axis-aligned box.
    Box {
        /// Min corner.
        min: V3,
        /// Max corner.
        max: V3,
    },
    /// Finite cylinder: the tube of `radius` around the segment from `base` to
    /// `top`, closed by two caps when `capped`.
    Cylinder {
        /// Centre of the base.
        base: V3,
        /// Centre of the top.
        top: V3,
        /// Radius.
        radius: f64,
        /// Closed by its caps.
        capped: bool,
    },
    /// Disk (double-sided): the points of a plane within `radius` of its
    /// centre and at least `inner` from it.
    Disk {
        /// Centre.
        center: V3,
        /// Unit normal.
        normal: V3,
        /// Radius.
        radius: f64,
        /// Inner radius (0 for a whole disk).
        inner: f64,
    },
}

/// A hit: time, triangle barycentrics of vertices 1 and 2, box face
/// (`0..6` = -x, +x, -y, +y, -z, +z).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Hit {
    /// Hit time.
    pub t: f64,
    /// Triangle: weight of vertex 1.
    pub b1: f64,
    /// Triangle: weight of vertex 2.
    pub b2: f64,
    /// Box: face index.
    pub face: usize,
}

/// `Some(hit at t)` when `0 < t < t_max`.
fn in_range(t: f64, t_max: f64) -> Option<Hit> {
    (t > 0.0 && t < t_max).then_some(Hit {
        t,
        ..Hit::default()
    })
}

impl Shape {
    /// The plane through `point` with normal `n` (any non-zero length).
    #[must_use]
    pub fn plane(point: V3, n: V3) -> Self {
        let len = n.length();
        Self::Plane {
            point,
            normal: n * (1.0 / len),
            offset: exact::dot2(n, point, V3::ZERO) / len,
        }
    }

    /// Whether `u` wraps round (an angle about an axis): a footprint across
    /// its seam is not a box of the texture.
    #[must_use]
    pub fn uv_wraps(&self) -> bool {
        matches!(
            self,
            Self::Sphere { .. } | Self::Cylinder { .. } | Self::Disk { .. }
        )
    }

    /// The nearest hit with `0 < t < t_max`.
    #[must_use]
    pub fn intersect(&self, ray: &Ray, t_max: f64) -> Option<Hit> {
        match *self {
            Self::Sphere { center, radius } => {
                // |o + t d - c|^2 = r^2 with |d| = 1: t^2 + 2 b t + c = 0, the
                // products summed almost exactly (`exact`): near a sphere far
                // larger than the distance, `c` is a small difference of squares.
                let (fh, fl) = exact::diff(ray.origin, center);
                let b = exact::dot2(ray.dir, fh, fl);
                let c = exact::norm2_minus(fh, fl, radius);
                let disc = exact::square_minus(b, c);
                if disc < 0.0 {
                    return None;
                }
                // The roots without cancellation: q and c / q.
                let q = -(b + disc.sqrt().copysign(b));
                let (t0, t1) = if q == 0.0 { (0.0, 0.0) } else { (q, c / q) };
                let (near, far) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
                in_range(near, t_max).or_else(|| in_range(far, t_max))
            }
            Self::Plane { normal, offset, .. } => {
                let denom = ray.dir.dot(normal);
                if denom == 0.0 {
                    return None;
                }
                in_range((offset - ray.origin.dot(normal)) / denom, t_max)
            }
            Self::Triangle { p } => {
                // Möller-Trumbore: o + t d = p0 + u e1 + v e2.
                let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
                let pv = ray.dir.cross(e2);
                let det = e1.dot(pv);
                if det == 0.0 {
                    return None;
                }
                let inv = 1.0 / det;
                let tv = ray.origin - p[0];
                let u = tv.dot(pv) * inv;
                if !(0.0..=1.0).contains(&u) {
                    return None;
                }
                let qv = tv.cross(e1);
                let v = ray.dir.dot(qv) * inv;
                if v < 0.0 || u + v > 1.0 {
                    return None;
                }
                // t = (p0 - o).(e1 x e2) / d.(e1 x e2) by Cramer's rule, the
                // determinants almost exact (`exact`): for a triangle far larger
                // than its distance, Moller-Trumbore's `e2.qv` is a small difference
                // of cubes of its size.
                let (wh, wl) = exact::diff(p[0], ray.origin);
                let num = exact::det3(wh, e1, e2) + wl.dot(e1.cross(e2));
                let t = num / exact::det3(ray.dir, e1, e2);
                in_range(t, t_max).map(|h| Hit { b1: u, b2: v, ..h })
            }
            Self::Box { min, max } => box_hit(min, max, ray, t_max),
            Self::Cylinder {
                base,
                top,
                radius,
                capped,
            } => cylinder_hit(base, top, radius, capped, ray, t_max),
            Self::Disk {
                center,
                normal,
                radius,
                inner,
            } => {
                // The plane's time (its offset summed almost exactly), then the
                // distance from the centre.
                let denom = ray.dir.dot(normal);
                if denom == 0.0 {
                    return None;
                }
                let offset = exact::dot2(normal, center, V3::ZERO);
                let hit = in_range((offset - ray.origin.dot(normal)) / denom, t_max)?;
                let q = ray.at(hit.t) - center;
                let rho2 = q.dot(q);
                (rho2 <= radius * radius && rho2 >= inner * inner).then_some(hit)
            }
        }
    }

    /// The outward unit normal at the hit point `p`.
    #[must_use]
    pub fn normal(&self, p: V3, hit: &Hit) -> V3 {
        match *self {
            Self::Sphere { center, .. } => (p - center).normalize(),
            Self::Plane { normal, .. } | Self::Disk { normal, .. } => normal,
            Self::Triangle { p } => (p[1] - p[0]).cross(p[2] - p[0]).normalize(),
            Self::Cylinder { base, top, .. } => {
                let w = (top - base).normalize();
                match hit.face {
                    0 => {
                        let f = p - base;
                        (f - w * f.dot(w)).normalize()
                    }
                    1 => -w,
                    _ => w,
                }
            }
            Self::Box { .. } => {
                let sign = if hit.face % 2 == 1 { 1.0 } else { -1.0 };
                match hit.face / 2 {
                    0 => V3::new(sign, 0.0, 0.0),
                    1 => V3::new(0.0, sign, 0.0),
                    _ => V3::new(0.0, 0.0, sign),
                }
            }
        }
    }

    /// The texture coordinate at the hit point `p` of outward normal `n`.
    #[must_use]
    pub fn uv(&self, p: V3, n: V3, hit: &Hit) -> [f64; 2] {
        match *self {
            Self::Sphere { .. } => [
                (n.z.atan2(n.x) + PI) / (2.0 * PI),
                n.y.clamp(-1.0, 1.0).acos() / PI,
            ],
            Self::Plane { point, normal, .. } => {
                let (t, b) = tangent_basis(normal);
                let d = p - point;
                [d.dot(t), d.dot(b)]
            }
            Self::Triangle { .. } => [hit.b1, hit.b2],
            Self::Disk {
                center,
                normal,
                radius,
                inner,
            } => {
                // The angle about the centre in the frame of the plane's
                // tangents, and the distance from the inner edge to the rim.
                let (tu, tv) = tangent_basis(normal);
                let q = p - center;
                let (x, y) = (q.dot(tu), q.dot(tv));
                let u = (y.atan2(x) + PI) / (2.0 * PI);
                [u, ((x.hypot(y) - inner) / (radius - inner)).clamp(0.0, 1.0)]
            }
            Self::Cylinder {
                base, top, radius, ..
            } => {
                // The angle about the axis in the frame of its tangents, and the
                // height (side) or the distance from the axis (caps).
                let h = (top - base).length();
                let w = (top - base) * (1.0 / h);
                let (tu, tv) = tangent_basis(w);
                let f = p - base;
                let (x, y) = (f.dot(tu), f.dot(tv));
                let u = (y.atan2(x) + PI) / (2.0 * PI);
                let v = if hit.face == 0 {
                    f.dot(w) / h
                } else {
                    x.hypot(y) / radius
                };
                [u, v.clamp(0.0, 1.0)]
            }
            Self::Box { min, max } => {
                let (a, b) = match hit.face / 2 {
                    0 => (1, 2),
                    1 => (0, 2),
                    _ => (0, 1),
                };
                let coord = |i: usize| {
                    let extent = max.get(i) - min.get(i);
                    if extent > 0.0 {
                        ((p.get(i) - min.get(i)) / extent).clamp(0.0, 1.0)
                    } else {
                        0.0
                    }
                };
                [coord(a), coord(b)]
            }
        }
    }
}

/// A cylinder's nearest hit: the side's roots between the caps' planes (face
/// 0), and each cap within the radius (faces 1, base, and 2, top), with the
/// vectors taken across the axis `w`: `|f + t d|^2 = r^2` for the parts of the
/// origin's offset `f` and of the direction `d` square to it.
fn cylinder_hit(
    base: V3,
    top: V3,
    radius: f64,
    capped: bool,
    ray: &Ray,
    t_max: f64,
) -> Option<Hit> {
    let h = (top - base).length();
    let w = (top - base) * (1.0 / h);
    // The origin's offset from the base summed almost exactly (`exact`), and
    // its part across the axis: near a side far larger than the distance, the
    // quadratic's constant `|f|^2 - r^2` is a small difference of squares.
    let (fh, fl) = exact::diff(ray.origin, base);
    let fz = exact::dot2(w, fh, fl);
    let dz = ray.dir.dot(w);
    let (fph, fpl) = (fh - w * fz, fl);
    let dp = ray.dir - w * dz;
    let mut best: Option<Hit> = None;
    let mut consider = |t: f64, face: usize| {
        if t > 0.0 && t < best.map_or(t_max, |b| b.t) {
            best = Some(Hit {
                t,
                face,
                ..Hit::default()
            });
        }
    };
    let a = dp.dot(dp);
    if a > 0.0 {
        // a t^2 + 2 b t + c = 0, the roots without cancellation: q / a and c / q.
        let b = exact::dot2(dp, fph, fpl);
        let c = exact::norm2_minus(fph, fpl, radius);
        let disc = exact::square_minus(b, a * c);
        if disc >= 0.0 {
            let q = -(b + disc.sqrt().copysign(b));
            let roots = if q == 0.0 { [0.0, 0.0] } else { [q / a, c / q] };
            for t in roots {
                let z = fz + dz * t;
                if (0.0..=h).contains(&z) {
                    consider(t, 0);
                }
            }
        }
    }
    let fp = fph + fpl;
    if capped && dz != 0.0 {
        for (face, z) in [(1, 0.0), (2, h)] {
            let t = (z - fz) / dz;
            let q = fp + dp * t;
            if q.dot(q) <= radius * radius {
                consider(t, face);
            }
        }
    }
    best
}

/// The slab test: the entry face when the origin is outside, else the exit face.
fn box_hit(min: V3, max: V3, ray: &Ray, t_max: f64) -> Option<Hit> {
    let (mut t_in, mut face_in) = (f64::NEG_INFINITY, 0);
    let (mut t_out, mut face_out) = (f64::INFINITY, 0);
    for axis in 0..3 {
        let (o, d) = (ray.origin.get(axis), ray.dir.get(axis));
        let (lo, hi) = (min.get(axis), max.get(axis));
        if d == 0.0 {
            // Parallel to this slab: inside it or never in the box.
            if o < lo || o > hi {
                return None;
            }
            continue;
        }
        let (t_lo, t_hi) = ((lo - o) / d, (hi - o) / d);
        let (near, near_face, far, far_face) = if d > 0.0 {
            (t_lo, 2 * axis, t_hi, 2 * axis + 1)
        } else {
            (t_hi, 2 * axis + 1, t_lo, 2 * axis)
        };
        if near > t_in {
            (t_in, face_in) = (near, near_face);
        }
        if far < t_out {
            (t_out, face_out) = (far, far_face);
        }
    }
    if t_in > t_out {
        return None;
    }
    let (t, face) = if t_in > 0.0 {
        (t_in, face_in)
    } else {
        (t_out, face_out)
    };
    in_range(t, t_max).map(|h| Hit { face, ..h })
}

/// The tangents `(t, b)` of the unit normal `n` (Duff et al. 2017), as in the core.
#[must_use]
pub fn tangent_basis(n: V3) -> (V3, V3) {
    let sign = 1f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        V3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        V3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() < 1e-12
    }

    #[test]
    fn head_on_sphere_hit() {
        let s = Shape::Sphere {
            center: V3::new(0.0, 0.0, -5.0),
            radius: 1.0,
        };
        let ray = Ray {
            origin: V3::ZERO,
            dir: -V3::Z,
        };
        let h = s.intersect(&ray, f64::INFINITY).unwrap();
        assert_eq!(h.t, 4.0);
        assert_eq!(s.normal(ray.at(h.t), &h), V3::Z);
        assert!(s.intersect(&ray, 4.0).is_none());
        // A chord at height 0.6: t = 5 - 0.8, normal (0.6, 0, 0.8).
        let ray = Ray {
            origin: V3::new(0.6, 0.0, 0.0),
            dir: -V3::Z,
        };
        let h = s.intersect(&ray, f64::INFINITY).unwrap();
        assert!(close(h.t, 4.2));
        let n = s.normal(ray.at(h.t), &h);
        assert!((n - V3::new(0.6, 0.0, 0.8)).length() < 1e-12);
        // From inside: the far side, outward normal.
        let ray = Ray {
            origin: V3::new(0.0, 0.0, -5.0),
            dir: V3::X,
        };
        let h = s.intersect(&ray, f64::INFINITY).unwrap();
        assert_eq!((h.t, s.normal(ray.at(h.t), &h)), (1.0, V3::X));
    }

    #[test]
    fn plane_checker_uv() {
        // n = +y: by hand, t = (1, 0, 0) and b = (0, 0, -1).
        let plane = Shape::plane(V3::new(0.0, -1.0, 0.0), V3::Y * 2.0);
        let ray = Ray {
            origin: V3::new(0.3, 2.0, -1.7),
            dir: -V3::Y,
        };
        let h = plane.intersect(&ray, f64::INFINITY).unwrap();
        assert_eq!(h.t, 3.0);
        let p = ray.at(h.t);
        let [u, v] = plane.uv(p, V3::Y, &h);
        assert!(close(u, 0.3) && close(v, 1.7), "{u} {v}");
        // Parallel rays miss.
        let flat = Ray {
            origin: V3::ZERO,
            dir: V3::X,
        };
        assert!(plane.intersect(&flat, f64::INFINITY).is_none());
        // The basis is orthonormal for any normal.
        let n = V3::new(0.3, -0.5, 0.8).normalize();
        let (t, b) = tangent_basis(n);
        for (x, y) in [(t, b), (t, n), (b, n)] {
            assert!(x.dot(y).abs() < 1e-15);
        }
        assert!(close(t.length(), 1.0) && close(b.length(), 1.0));
    }

    #[test]
    fn triangle_barycentrics_both_sides() {
        let tri = Shape::Triangle {
            p: [
                V3::new(0.0, 0.0, 2.0),
                V3::new(4.0, 0.0, 2.0),
                V3::new(0.0, 4.0, 2.0),
            ],
        };
        // (1, 2, 2) = p0 + 0.25 (p1 - p0) + 0.5 (p2 - p0).
        for dir in [V3::Z, -V3::Z] {
            let ray = Ray {
                origin: V3::new(1.0, 2.0, 2.0) - dir * 3.0,
                dir,
            };
            let h = tri.intersect(&ray, f64::INFINITY).unwrap();
            assert!(close(h.t, 3.0) && close(h.b1, 0.25) && close(h.b2, 0.5));
            assert_eq!(tri.normal(ray.at(h.t), &h), V3::Z);
            assert_eq!(tri.uv(ray.at(h.t), V3::Z, &h), [h.b1, h.b2]);
        }
        let outside = Ray {
            origin: V3::new(3.0, 3.0, 0.0),
            dir: V3::Z,
        };
        assert!(tri.intersect(&outside, f64::INFINITY).is_none());
    }

    #[test]
    fn box_faces_normals_and_uv() {
        let b = Shape::Box {
            min: V3::new(-1.0, -2.0, -3.0),
            max: V3::new(1.0, 2.0, 3.0),
        };
        // Each ray enters 3/4 of the way along both other axes, at t = 4.
        let cases = [
            (V3::new(-5.0, 1.0, 1.5), V3::X, 0, -V3::X),
            (V3::new(5.0, 1.0, 1.5), -V3::X, 1, V3::X),
            (V3::new(0.5, -6.0, 1.5), V3::Y, 2, -V3::Y),
            (V3::new(0.5, 6.0, 1.5), -V3::Y, 3, V3::Y),
            (V3::new(0.5, 1.0, -7.0), V3::Z, 4, -V3::Z),
            (V3::new(0.5, 1.0, 7.0), -V3::Z, 5, V3::Z),
        ];
        for (origin, dir, face, n) in cases {
            let ray = Ray { origin, dir };
            let h = b.intersect(&ray, f64::INFINITY).unwrap();
            assert_eq!((h.t, h.face), (4.0, face));
            let p = ray.at(h.t);
            assert_eq!(b.normal(p, &h), n);
            assert_eq!(b.uv(p, n, &h), [0.75, 0.75]);
        }
        // From inside: the exit face.
        let ray = Ray {
            origin: V3::ZERO,
            dir: V3::Z,
        };
        let h = b.intersect(&ray, f64::INFINITY).unwrap();
        assert_eq!((h.t, h.face), (3.0, 5));
    }
}
