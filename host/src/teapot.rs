//! A teapot made of bicubic Bezier patches, tessellated into a triangle mesh, in
//! `f64`.
//!
//! The shape is tessera's own design (not Martin Newell's Utah teapot data), built
//! the classic way:
//!
//! - the body with its bottom, and the lid with its knob, are surfaces of
//!   revolution about +y: a profile of cubic Bezier segments in (radius, height)
//!   ([`BODY`], [`LID`]), each segment revolved as four quadrant patches whose
//!   circle control points are `(r, 0), (r, k r), (k r, r), (0, r)` in x/z, with
//!   `k = 4/3 tan(pi/8)`. Each profile starts and ends on the axis, so the body and
//!   the lid are each a closed surface; the body is closed across the rim's opening
//!   under the lid, and the lid sinks into that opening;
//! - the spout and the handle are tubes swept along a cubic Bezier spine in the
//!   x-y plane ([`SPOUT`], [`HANDLE`]): at each of the spine's four control points
//!   the four quadrants' circle control points are placed in the plane
//!   perpendicular to the control polygon's direction there, scaled by that point's
//!   radii, which makes four tensor-product bicubic patches. Their ends are open:
//!   the spout's at its tip, the others sunk into the body.
//!
//! y is up, the bottom is at y = 0, the axis goes through the origin, the belly's
//! radius is 1 (at y = 0.3), the knob's top is at y = 1.2, the spout's tip near
//! x = +1.7 and the handle's outside near x = -1.5.
//!
//! [`teapot`] tessellates every patch into a grid of quads, each split into two
//! triangles wound counter-clockwise seen from outside, drops the triangles of zero
//! area (at the poles of the revolved parts) and welds the vertices that patches
//! share; normals are the patches' own (the cross product of the partial
//! derivatives), summed over the patches that share a vertex.

use crate::arr3::{add, cross, length, scale, sub};
use std::collections::HashMap;
use std::collections::hash_map::Entry;

/// A point or vector.
type V3 = [f64; 3];

/// A bicubic Bezier patch: `p[i][j]`, `i` along `u`, `j` along `v`. The normal
/// `dP/du x dP/dv` points outward.
type Patch = [[V3; 4]; 4];

/// A cubic Bezier segment in a plane: four control points.
type Segment = [[f64; 2]; 4];

/// The circle constant: the cubic Bezier quadrant with control points `(1, 0),
/// (1, K), (K, 1), (0, 1)` passes through the 45 degree point of the unit circle
/// (`K = 4/3 tan(pi/8)`, and `tan(pi/8) = sqrt(2) - 1`).
const K: f64 = 4.0 / 3.0 * (std::f64::consts::SQRT_2 - 1.0);

/// The body's profile in (radius, height), from the bottom's centre out to the
/// foot, up the belly (widest, radius 1, at y = 0.3, a third of the body's
/// height), in at the neck and out again into the rim's lip, then across the rim's
/// opening back to the axis (hidden under the lid).
pub const BODY: [Segment; 4] = [
    // The flat bottom.
    [[0.0, 0.0], [0.25, 0.0], [0.5, 0.0], [0.75, 0.0]],
    // The foot rounding up into the belly, vertical at its widest.
    [[0.75, 0.0], [0.92, 0.0], [1.0, 0.12], [1.0, 0.3]],
    // The shoulder narrowing to the neck and flaring out into the lip.
    [[1.0, 0.3], [1.0, 0.62], [0.58, 0.7], [0.74, 0.88]],
    // The rim's top, closed across the opening.
    [[0.74, 0.88], [0.5, 0.88], [0.25, 0.88], [0.0, 0.88]],
];

/// The lid's profile in (radius, height), from the axis under the rim (inside the
/// body) out to the lid's edge, up over the dome to the knob's neck, and round the
/// knob to its top on the axis at y = 1.2.
pub const LID: [Segment; 3] = [
    // The underside, inside the body.
    [[0.0, 0.8], [0.22, 0.8], [0.44, 0.8], [0.66, 0.8]],
    // The edge rising out of the rim's opening and the dome.
    [[0.66, 0.8], [0.66, 0.98], [0.4, 1.04], [0.08, 1.05]],
    // The knob: up from its neck, round out and over to the axis.
    [[0.08, 1.05], [0.08, 1.12], [0.2, 1.2], [0.0, 1.2]],
];

/// A tube swept along a cubic Bezier spine in the x-y plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tube {
    /// The spine's control points (x, y).
    pub spine: Segment,
    /// At each control point, the cross-section's radii: in the x-y plane, and
    /// along z.
    pub radii: [[f64; 2]; 4],
}

/// The spout: from low inside the belly out and up to its open tip above the rim,
/// narrowing all the way.
pub const SPOUT: Tube = Tube {
    spine: [[0.7, 0.3], [1.45, 0.28], [1.3, 0.88], [1.7, 1.02]],
    radii: [[0.26, 0.26], [0.17, 0.17], [0.1, 0.1], [0.075, 0.075]],
};

/// The handle: a loop on the -x side, both ends sunk into the body, its
/// cross-section an ellipse narrower in the x-y plane than across it.
pub const HANDLE: Tube = Tube {
    spine: [[-0.7, 0.68], [-1.62, 0.84], [-1.7, 0.2], [-0.88, 0.16]],
    radii: [[0.08, 0.1], [0.065, 0.09], [0.065, 0.09], [0.08, 0.1]],
};

/// The default tessellation: `teapot(SEGMENTS)` has 1,088 triangles (36 patches
/// of 4 x 4 quads, less the 64 that collapse at the four poles).
pub const SEGMENTS: u32 = 4;

/// A triangle mesh: shared vertices, their unit normals, faces as vertex indices.
#[derive(Clone, Debug, PartialEq)]
pub struct TriMesh {
    /// The vertices' positions.
    pub positions: Vec<[f64; 3]>,
    /// The vertices' unit normals, one per position.
    pub normals: Vec<[f64; 3]>,
    /// The triangles: indices into `positions`, counter-clockwise seen from
    /// outside ((p1 - p0) x (p2 - p0) points outward).
    pub faces: Vec<[u32; 3]>,
}

/// The teapot tessellated with `segments` x `segments` quads per patch (at least
/// one: 0 is taken as 1), each split into two triangles; triangles of zero area
/// (at the axis poles) are dropped; vertices shared between patches are welded.
pub fn teapot(segments: u32) -> TriMesh {
    let mut patches = revolved(&BODY);
    patches.extend(revolved(&LID));
    patches.extend(swept(&SPOUT));
    patches.extend(swept(&HANDLE));
    tessellate(&patches, segments)
}

impl TriMesh {
    /// Wavefront OBJ text: a comment header, then `v` and `vn` lines (one of each
    /// per vertex) and `f a//a b//b c//c` lines (1-based), numbers printed with
    /// `{}` (the shortest text that reads back to the same `f64`).
    pub fn to_obj(&self) -> String {
        use std::fmt::Write as _;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "# tessera's teapot: bicubic Bezier patches tessellated into triangles"
        );
        let _ = writeln!(
            s,
            "# {} vertices, {} triangles; y up, faces counter-clockwise seen from outside",
            self.positions.len(),
            self.faces.len()
        );
        for [x, y, z] in &self.positions {
            let _ = writeln!(s, "v {x} {y} {z}");
        }
        for [x, y, z] in &self.normals {
            let _ = writeln!(s, "vn {x} {y} {z}");
        }
        for f in &self.faces {
            let [a, b, c] = f.map(|i| i + 1);
            let _ = writeln!(s, "f {a}//{a} {b}//{b} {c}//{c}");
        }
        s
    }

    /// The triangles' vertex positions.
    pub fn triangles(&self) -> impl Iterator<Item = [[f64; 3]; 3]> + '_ {
        self.faces
            .iter()
            .map(|f| f.map(|i| self.positions[i as usize]))
    }
}

/// The four quadrants' circle control points in a plane, counter-clockwise
/// (from the first axis towards the second), each quadrant's four.
fn quadrants() -> [[[f64; 2]; 4]; 4] {
    let first = [[1.0, 0.0], [1.0, K], [K, 1.0], [0.0, 1.0]];
    let mut q = [first; 4];
    for i in 1..4 {
        // A quarter turn: (a, b) -> (-b, a), exact.
        q[i] = q[i - 1].map(|[a, b]| [-b, a]);
    }
    q
}

/// The patches of a profile revolved about +y: four per segment, each quadrant
/// from +x towards +z. The normal points away from the profile's left side as
/// it goes (outward for a profile going out, up and back in).
fn revolved(profile: &[Segment]) -> Vec<Patch> {
    let mut patches = Vec::with_capacity(profile.len() * 4);
    for seg in profile {
        for quad in quadrants() {
            patches.push(seg.map(|[r, y]| quad.map(|[c, s]| [r * c, y, r * s])));
        }
    }
    patches
}

/// The unit direction of the spine's control polygon at its control point `i`:
/// the first or last leg at the ends, the two legs' average between.
fn spine_direction(spine: &Segment, i: usize) -> [f64; 2] {
    let leg = |a: usize, b: usize| {
        let (dx, dy) = (spine[b][0] - spine[a][0], spine[b][1] - spine[a][1]);
        let n = dx.hypot(dy);
        [dx / n, dy / n]
    };
    let d = match i {
        0 => leg(0, 1),
        3 => leg(2, 3),
        _ => {
            let (a, b) = (leg(i - 1, i), leg(i, i + 1));
            [a[0] + b[0], a[1] + b[1]]
        }
    };
    let n = d[0].hypot(d[1]);
    [d[0] / n, d[1] / n]
}

/// The four patches of a tube: at control point `i` of the spine, with unit
/// direction `t`, the cross-section's circle lies along `a = (-t.y, t.x, 0)` (in
/// the x-y plane) and `b = a x t = (0, 0, -1)`, scaled by the radii; `t x b = a`
/// makes the normal point outward.
fn swept(tube: &Tube) -> Vec<Patch> {
    let frames: [(V3, V3, V3); 4] = std::array::from_fn(|i| {
        let [x, y] = tube.spine[i];
        let [tx, ty] = spine_direction(&tube.spine, i);
        let [ra, rb] = tube.radii[i];
        ([x, y, 0.0], [-ty * ra, tx * ra, 0.0], [0.0, 0.0, -rb])
    });
    quadrants()
        .iter()
        .map(|quad| {
            frames
                .map(|(centre, a, b)| quad.map(|[c, s]| add(centre, add(scale(a, c), scale(b, s)))))
        })
        .collect()
}

/// The cubic Bernstein polynomials at `t`.
fn bernstein(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t]
}

/// The derivatives of the cubic Bernstein polynomials at `t`.
fn bernstein_derivative(t: f64) -> [f64; 4] {
    let s = 1.0 - t;
    [
        -3.0 * s * s,
        3.0 * s * s - 6.0 * s * t,
        6.0 * s * t - 3.0 * t * t,
        3.0 * t * t,
    ]
}

/// The sum of `w_u[i] w_v[j] p[i][j]`.
fn combine(p: &Patch, wu: &[f64; 4], wv: &[f64; 4]) -> V3 {
    let mut out = [0.0; 3];
    for (row, &a) in p.iter().zip(wu) {
        for (q, &b) in row.iter().zip(wv) {
            out = add(out, scale(*q, a * b));
        }
    }
    out
}

/// The patch's point at `(u, v)`.
fn point(p: &Patch, u: f64, v: f64) -> V3 {
    combine(p, &bernstein(u), &bernstein(v))
}

/// The patch's (not normalized) normal `dP/du x dP/dv` at `(u, v)`.
fn raw_normal(p: &Patch, u: f64, v: f64) -> V3 {
    let (bu, bv) = (bernstein(u), bernstein(v));
    let du = combine(p, &bernstein_derivative(u), &bv);
    let dv = combine(p, &bu, &bernstein_derivative(v));
    cross(du, dv)
}

/// The patch's unit normal at `(u, v)`, or `None` where the derivatives
/// degenerate there (a pole, collapsed control points): then the normal a step
/// inside the patch, ever larger steps. `size` is the patch's extent.
fn normal(p: &Patch, u: f64, v: f64, size: f64) -> Option<V3> {
    let tiny = 1e-10 * size * size;
    let inward = |t: f64, step: f64| if t < 0.5 { t + step } else { t - step };
    [0.0, 1e-5, 1e-3, 1e-1].iter().find_map(|&step| {
        let n = raw_normal(p, inward(u, step), inward(v, step));
        let len = length(n);
        (len > tiny).then(|| scale(n, 1.0 / len))
    })
}

/// The extent of a patch's control points (the diagonal of their bounding box).
fn extent(p: &Patch) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for q in p.iter().flatten() {
        for k in 0..3 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    length(sub(hi, lo))
}

/// The grid on which vertices are welded.
const WELD: f64 = 1e-9;

/// Welds vertices: a point within [`WELD`] (per coordinate) of one seen before is
/// that vertex; its normals are summed. Vertices are numbered in the order they
/// are first seen, so the map's order never shows.
#[derive(Default)]
struct Welder {
    cells: HashMap<[i64; 3], u32>,
    positions: Vec<V3>,
    normals: Vec<V3>,
}

impl Welder {
    fn vertex(&mut self, p: V3, n: Option<V3>) -> u32 {
        let cell = p.map(|x| (x / WELD).round() as i64);
        // A point near a cell's border may have been seen in the next cell.
        let mut found = None;
        'search: for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let key = [cell[0] + dx, cell[1] + dy, cell[2] + dz];
                    if let Some(&i) = self.cells.get(&key) {
                        let q = self.positions[i as usize];
                        if (0..3).all(|k| (q[k] - p[k]).abs() <= WELD) {
                            found = Some(i);
                            break 'search;
                        }
                    }
                }
            }
        }
        let i = match found {
            Some(i) => i,
            None => {
                let i = self.positions.len() as u32;
                // `+ 0.0` turns -0 into 0.
                self.positions.push(p.map(|x| x + 0.0));
                self.normals.push([0.0; 3]);
                if let Entry::Vacant(e) = self.cells.entry(cell) {
                    e.insert(i);
                }
                i
            }
        };
        if let Some(n) = n {
            let sum = &mut self.normals[i as usize];
            *sum = add(*sum, n);
        }
        i
    }
}

/// `patches` tessellated with `segments` x `segments` quads each (at least 1),
/// split into two triangles each; triangles of zero area dropped, vertices welded.
fn tessellate(patches: &[Patch], segments: u32) -> TriMesh {
    let n = segments.max(1) as usize;
    let mut welder = Welder::default();
    let mut faces = Vec::with_capacity(patches.len() * n * n * 2);
    let mut grid = vec![0u32; (n + 1) * (n + 1)];
    for p in patches {
        let size = extent(p);
        for a in 0..=n {
            let u = a as f64 / n as f64;
            for b in 0..=n {
                let v = b as f64 / n as f64;
                grid[a * (n + 1) + b] = welder.vertex(point(p, u, v), normal(p, u, v, size));
            }
        }
        for a in 0..n {
            for b in 0..n {
                let at = |i: usize, j: usize| grid[i * (n + 1) + j];
                let (p00, p10, p11, p01) = (at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b + 1));
                for f in [[p00, p10, p11], [p00, p11, p01]] {
                    if area2(&welder.positions, f) > 0.0 {
                        faces.push(f);
                    }
                }
            }
        }
    }
    let Welder {
        positions,
        mut normals,
        ..
    } = welder;
    // A vertex whose normals cancelled (or that had none): the average of its
    // faces' normals; failing that, up.
    let bad: Vec<usize> = (0..normals.len())
        .filter(|&i| length(normals[i]) <= 1e-12)
        .collect();
    if !bad.is_empty() {
        for f in &faces {
            let [a, b, c] = f.map(|i| positions[i as usize]);
            let g = cross(sub(b, a), sub(c, a));
            for &i in f {
                if bad.contains(&(i as usize)) {
                    normals[i as usize] = add(normals[i as usize], g);
                }
            }
        }
    }
    for n in &mut normals {
        let len = length(*n);
        *n = if len > 1e-300 {
            scale(*n, 1.0 / len)
        } else {
            [0.0, 1.0, 0.0]
        };
    }
    TriMesh {
        positions,
        normals,
        faces,
    }
}

/// Twice the area of triangle `f`, 0 when two of its vertices are one.
fn area2(positions: &[V3], f: [u32; 3]) -> f64 {
    if f[0] == f[1] || f[1] == f[2] || f[2] == f[0] {
        return 0.0;
    }
    let [a, b, c] = f.map(|i| positions[i as usize]);
    length(cross(sub(b, a), sub(c, a)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arr3::dot;

    /// The patches revolved from the body's or the lid's profile, welded.
    fn part(profile: &[Segment], n: u32) -> TriMesh {
        tessellate(&revolved(profile), n)
    }

    /// Twice the area vector of a triangle: (p1 - p0) x (p2 - p0).
    fn face_normal(t: [V3; 3]) -> V3 {
        cross(sub(t[1], t[0]), sub(t[2], t[0]))
    }

    /// The largest distance from the origin of the unit quadrant's cubic Bezier:
    /// the control points (1, 0), (1, K), (K, 1), (0, 1) make a curve a little
    /// outside the circle between its ends and its middle.
    fn circle_overshoot() -> f64 {
        let ctrl = [[1.0, 0.0], [1.0, K], [K, 1.0], [0.0, 1.0]];
        (0..=10_000)
            .map(|i| {
                let w = bernstein(i as f64 / 10_000.0);
                let x: f64 = (0..4).map(|j| w[j] * ctrl[j][0]).sum();
                let z: f64 = (0..4).map(|j| w[j] * ctrl[j][1]).sum();
                x.hypot(z)
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn about_a_thousand_triangles_growing_fourfold_with_twice_the_segments() {
        let count = |n: u32| teapot(n).faces.len();
        assert!(
            (900..=1_100).contains(&count(SEGMENTS)),
            "{}",
            count(SEGMENTS)
        );
        // 36 patches (7 profile segments x 4 quadrants, 2 tubes x 4) of 2 n^2
        // triangles, less n at each of the 16 patches that touch a pole.
        for n in 1..=8usize {
            assert_eq!(count(n as u32), 72 * n * n - 16 * n, "segments {n}");
        }
        for n in [2, 3, 4, 8] {
            let ratio = count(2 * n) as f64 / count(n) as f64;
            assert!((3.9..4.3).contains(&ratio), "{n} -> {}: x{ratio}", 2 * n);
        }
        // Welded: rings of 4n vertices along the profiles (one vertex at each
        // pole) and the tubes, each vertex once.
        let n = SEGMENTS as usize;
        let m = teapot(SEGMENTS);
        let body = (4 * n - 1) * 4 * n + 2;
        let lid = (3 * n - 1) * 4 * n + 2;
        let tubes = 2 * (n + 1) * 4 * n;
        assert_eq!(m.positions.len(), body + lid + tubes);
        assert_eq!(m.normals.len(), m.positions.len());
        assert_eq!(m.triangles().count(), m.faces.len());
        let f = m.faces[17];
        assert_eq!(
            m.triangles().nth(17).unwrap(),
            f.map(|i| m.positions[i as usize])
        );
    }

    #[test]
    fn the_teapot_has_the_stated_size_and_place() {
        let over = circle_overshoot();
        assert!(over > 1.0002 && over < 1.0003, "{over}");
        // (An even number of segments has a vertex at the handle's outside.)
        for n in [2, SEGMENTS, 8] {
            let m = teapot(n);
            assert!(m.positions.iter().flatten().all(|x| x.is_finite()));
            let lo = |k: usize| m.positions.iter().map(|p| p[k]).fold(f64::MAX, f64::min);
            let hi = |k: usize| m.positions.iter().map(|p| p[k]).fold(f64::MIN, f64::max);
            // Bottom at 0, knob's top at 1.2, spout's tip and handle's outside.
            assert_eq!(lo(1), 0.0, "segments {n}");
            assert!((hi(1) - 1.2).abs() < 1e-12, "segments {n}: {}", hi(1));
            assert!((1.65..=1.75).contains(&hi(0)), "segments {n}: {}", hi(0));
            assert!((-1.55..=-1.45).contains(&lo(0)), "segments {n}: {}", lo(0));
            assert!(hi(2) <= over + 1e-12 && lo(2) >= -over - 1e-12);
            // The belly (away from the spout and the handle, which stay near
            // z = 0): no wider than 1 on the quadrants' seams, where the cubic
            // circle is exact, and nowhere wider than the cubic circle's
            // overshoot; radius 1 reached at y = 0.3.
            let belly: Vec<V3> = m
                .positions
                .iter()
                .copied()
                .filter(|p| p[2].abs() > 0.9)
                .collect();
            let radius = |p: &V3| p[0].hypot(p[2]);
            let widest = belly.iter().map(radius).fold(0.0, f64::max);
            assert!((0.99..=over + 1e-12).contains(&widest), "{widest}");
            let seam: Vec<&V3> = belly.iter().filter(|p| p[0] == 0.0).collect();
            assert!(seam.iter().all(|p| radius(p) <= 1.0 + 1e-12));
            let at = seam
                .iter()
                .find(|p| radius(p) == 1.0)
                .expect("a vertex at radius 1");
            assert_eq!(at[1], 0.3);
        }
    }

    #[test]
    fn triangles_have_area_and_normals_agree_with_the_faces() {
        for n in [1, 2, 3, SEGMENTS, 8] {
            let m = teapot(n);
            for nv in &m.normals {
                assert!((length(*nv) - 1.0).abs() < 1e-12, "{nv:?}");
            }
            let mut agree = 0;
            for (f, t) in m.faces.iter().zip(m.triangles()) {
                let g = face_normal(t);
                assert!(length(g) > 1e-8, "segments {n}: {t:?}");
                if f.iter().all(|&i| dot(g, m.normals[i as usize]) > 0.0) {
                    agree += 1;
                }
            }
            if n == 1 {
                // One quad a patch: a face spans a quarter of a tube's whole
                // length, and its corners' normals are not its own.
                continue;
            }
            let share = agree as f64 / m.faces.len() as f64;
            assert!(share >= 0.99, "segments {n}: {share}");
            for profile in [&BODY[..], &LID[..]] {
                let m = part(profile, n);
                for (f, t) in m.faces.iter().zip(m.triangles()) {
                    let g = face_normal(t);
                    for &i in f {
                        assert!(dot(g, m.normals[i as usize]) > 0.0, "segments {n}: {t:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn the_poles_normals_point_along_the_axis() {
        let m = teapot(SEGMENTS);
        let at = |p: V3| m.positions.iter().position(|q| *q == p).unwrap();
        let bottom = m.normals[at([0.0, 0.0, 0.0])];
        let top = m.normals[at([0.0, 1.2, 0.0])];
        assert!(dot(bottom, [0.0, -1.0, 0.0]) > 0.999_999, "{bottom:?}");
        assert!(dot(top, [0.0, 1.0, 0.0]) > 0.999_999, "{top:?}");
    }

    /// The directed edges of `m`'s faces, each with how many faces have it.
    fn edges(m: &TriMesh) -> HashMap<(u32, u32), usize> {
        let mut edges = HashMap::new();
        for &[a, b, c] in &m.faces {
            for e in [(a, b), (b, c), (c, a)] {
                *edges.entry(e).or_insert(0) += 1;
            }
        }
        edges
    }

    #[test]
    fn the_body_and_the_lid_are_closed_and_the_tubes_open_at_their_ends_only() {
        for n in 1..=6 {
            for profile in [&BODY[..], &LID[..]] {
                let m = part(profile, n);
                // Every edge in both directions once: two faces, opposite ways.
                let e = edges(&m);
                assert!(!e.is_empty());
                for (&(a, b), &count) in &e {
                    assert_eq!(count, 1, "segments {n}: edge {a} {b}");
                    assert_eq!(e.get(&(b, a)), Some(&1), "segments {n}: edge {a} {b}");
                }
            }
            // The whole teapot: no edge twice the same way; the edges without
            // their opposite are the four tube ends' circles of 4n edges.
            let m = teapot(n);
            let e = edges(&m);
            assert!(e.values().all(|&c| c == 1), "segments {n}");
            let open = e.keys().filter(|(a, b)| !e.contains_key(&(*b, *a))).count();
            assert_eq!(open, 4 * 4 * n as usize, "segments {n}");
        }
    }

    /// The volume enclosed by a closed mesh: positive when its faces turn
    /// counter-clockwise seen from outside.
    fn signed_volume(m: &TriMesh) -> f64 {
        m.triangles()
            .map(|[a, b, c]| dot(a, cross(b, c)) / 6.0)
            .sum()
    }

    /// The volume of revolution of a closed profile (out from the axis, round and
    /// back to the axis): pi times the integral of r^2 dy along it, the segments
    /// sampled densely by de Casteljau's construction.
    fn volume_of_revolution(profile: &[Segment]) -> f64 {
        let at = |seg: &Segment, t: f64| {
            let mut p = *seg;
            for k in (1..4).rev() {
                for i in 0..k {
                    let (a, b) = (p[i], p[i + 1]);
                    p[i] = [0, 1].map(|c| (1.0 - t) * a[c] + t * b[c]);
                }
            }
            p[0]
        };
        let steps = 20_000;
        let mut v = 0.0;
        for seg in profile {
            let mut prev = at(seg, 0.0);
            for i in 1..=steps {
                let p = at(seg, i as f64 / steps as f64);
                v += std::f64::consts::PI * (prev[0] * prev[0] + p[0] * p[0]) / 2.0
                    * (p[1] - prev[1]);
                prev = p;
            }
        }
        v
    }

    #[test]
    fn the_body_and_the_lid_turn_outward_and_enclose_their_volumes() {
        for profile in [&BODY[..], &LID[..]] {
            let want = volume_of_revolution(profile);
            assert!(want > 0.0);
            let error = |n: u32| (signed_volume(&part(profile, n)) - want) / want;
            let (e4, e8, e16) = (error(4), error(8), error(16));
            assert!(e4.abs() < 0.08, "{e4}");
            assert!(e16.abs() < 0.01, "{e16}");
            assert!(
                e16.abs() < e8.abs() && e8.abs() < e4.abs(),
                "{e4} {e8} {e16}"
            );
            assert!(signed_volume(&part(profile, 1)) > 0.0);
        }
        let body = volume_of_revolution(&BODY);
        assert!((2.0..2.5).contains(&body), "{body}");
    }

    /// The distance from `p` to the tube's spine, sampled densely.
    fn spine_distance(tube: &Tube, p: V3) -> f64 {
        (0..=2_000)
            .map(|i| {
                let w = bernstein(i as f64 / 2_000.0);
                let x: f64 = (0..4).map(|j| w[j] * tube.spine[j][0]).sum();
                let y: f64 = (0..4).map(|j| w[j] * tube.spine[j][1]).sum();
                length(sub(p, [x, y, 0.0]))
            })
            .fold(f64::MAX, f64::min)
    }

    #[test]
    fn the_tubes_turn_outward() {
        for tube in [SPOUT, HANDLE] {
            // Fine enough that no face cuts across the spine's bend.
            let m = tessellate(&swept(&tube), 12);
            for t in m.triangles() {
                // Moving along the face's normal leaves the spine.
                let c = scale(add(add(t[0], t[1]), t[2]), 1.0 / 3.0);
                let g = face_normal(t);
                let out = add(c, scale(g, 0.01 / length(g)));
                let inn = sub(c, scale(g, 0.01 / length(g)));
                assert!(
                    spine_distance(&tube, out) > spine_distance(&tube, inn),
                    "{t:?}"
                );
            }
        }
    }

    #[test]
    fn the_tubes_ends_sink_into_the_body_but_the_spouts_tip() {
        // The body's outer wall (the foot and the shoulder), sampled densely:
        // its radius at a height, from the nearest sample.
        let wall: Vec<[f64; 2]> = BODY[1..3]
            .iter()
            .flat_map(|seg| {
                (0..=4_000).map(move |i| {
                    let w = bernstein(i as f64 / 4_000.0);
                    [0, 1].map(|c| (0..4).map(|j| w[j] * seg[j][c]).sum::<f64>())
                })
            })
            .collect();
        let wall_radius = |y: f64| {
            wall.iter()
                .min_by(|a, b| (a[1] - y).abs().total_cmp(&(b[1] - y).abs()))
                .unwrap()[0]
        };
        let inside = |p: V3| p[1] > 0.0 && p[0].hypot(p[2]) < wall_radius(p[1]) - 0.02;
        let ring = |tube: &Tube, u: f64| -> Vec<V3> {
            swept(tube)
                .iter()
                .flat_map(|p| (0..=8).map(move |j| point(p, u, j as f64 / 8.0)))
                .collect()
        };
        for (tube, u) in [(SPOUT, 0.0), (HANDLE, 0.0), (HANDLE, 1.0)] {
            for p in ring(&tube, u) {
                assert!(inside(p), "{p:?}");
            }
        }
        // The spout's tip: outside, above the rim.
        for p in ring(&SPOUT, 1.0) {
            assert!(p[0] > 1.5 && p[1] > 0.9, "{p:?}");
        }
    }

    #[test]
    fn the_same_mesh_every_time_with_no_vertex_twice() {
        for n in [1, SEGMENTS] {
            let m = teapot(n);
            assert_eq!(m, teapot(n));
            for (i, p) in m.positions.iter().enumerate() {
                for q in &m.positions[i + 1..] {
                    assert!(length(sub(*p, *q)) > 1e-6, "{p:?} twice");
                }
            }
        }
    }

    #[test]
    fn the_obj_text_reads_back_to_the_same_mesh() {
        let m = teapot(SEGMENTS);
        let text = m.to_obj();
        assert!(text.starts_with("# tessera's teapot"));
        let (mut v, mut vn, mut f) = (Vec::new(), Vec::new(), Vec::new());
        let three = |w: &[&str]| -> V3 { std::array::from_fn(|k| w[k].parse::<f64>().unwrap()) };
        for line in text.lines() {
            let words: Vec<&str> = line.split_whitespace().collect();
            match words[0] {
                "#" => {}
                "v" => v.push(three(&words[1..])),
                "vn" => vn.push(three(&words[1..])),
                "f" => {
                    assert_eq!(words.len(), 4, "{line}");
                    f.push(std::array::from_fn::<u32, 3, _>(|k| {
                        let (a, b) = words[k + 1].split_once("//").unwrap();
                        assert_eq!(a, b, "{line}");
                        a.parse::<u32>().unwrap() - 1
                    }));
                }
                _ => panic!("unexpected line {line}"),
            }
        }
        let back = TriMesh {
            positions: v,
            normals: vn,
            faces: f,
        };
        assert_eq!(back.positions.len(), m.positions.len());
        assert_eq!(back.faces.len(), m.faces.len());
        // Bit for bit (-0 would print as "-0": there is none).
        let bits = |m: &TriMesh| -> Vec<u64> {
            m.positions
                .iter()
                .chain(&m.normals)
                .flatten()
                .map(|x| x.to_bits())
                .collect()
        };
        assert_eq!(bits(&back), bits(&m));
        assert_eq!(back, m);
        assert!(!text.contains("-0 ") && !text.contains("NaN") && !text.contains("inf"));
    }
}
