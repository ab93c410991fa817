//! What `f32` and the `f64` paths cannot place: the loader's warnings about
//! numbers whose rounding to `f32` moves a surface, or leaves the camera, by more
//! than a fraction of a pixel, about triangle edges far longer than their
//! distance to the camera, and about surfaces far larger than their distance.
//!
//! The core gets every number of the scene in `f32`; the `f64` reference gets
//! them as written. A surface whose numbers are not exact in `f32` is drawn where
//! the rounded numbers put it: a sphere's centre and radius, a plane's unit
//! normal and its offset from the origin (as the core holds it), a triangle's
//! vertices (list and mesh faces, after the mesh's scale and translation), a
//! box's corners. [`rounding_warnings`] measures that move at the surface's point
//! nearest the camera (for a tilted triangle far larger than its distance, the
//! rounded vertices' plane can pass far from the written one there) against the
//! pixel footprint at that distance (the distance times one pixel's angle at the
//! centre of the scene's own frame), and the camera's position against the
//! footprint at the nearest surface: near the camera everything is placed to the
//! spacing of `f32` numbers at the camera's coordinates.
//!
//! The core decides whether a ray crosses a triangle with Woop's watertight test,
//! in `f32`, from the vertices relative to the ray's origin. A vertex `M` away is
//! known to a few ulps of `M`, and the test's shear multiplies the vertex's
//! depth along the ray: an edge that recedes far along the view but passes near
//! the camera is drawn a little off (an edge across the view, however long, is
//! not: its great extent is not a depth). The extremes battery (case 13 of
//! `docs/extremes.md`, "near an edge") shows it within the accuracy bar with ends
//! a million times farther than the edge, and off by whole pixels at ten million
//! (at 96x72; more pixels see it sooner). The hit points and shading of such a
//! triangle stay exact (they come from `f64` there); only its outline moves. An
//! edge shared with one other triangle of the same material in the same plane is
//! no outline (both sides decide it with the same rounding: a floor of two huge
//! triangles shows no seam), and an edge beyond the camera's far distance is not
//! seen: neither is warned about.

use crate::arr3::{cross, dot, length, sub};
use crate::desc::{Face, SceneDesc, num};
use std::collections::HashMap;

/// Above this ratio of an edge's ends' reach along the view to its distance from
/// the camera, the loader warns: the battery (case 13, "near an edge") meets the
/// bar at 1e6 and misses it at 1e7.
pub const EDGE_RATIO: f64 = 1e6;

/// Above this ratio of a triangle's longest edge, or a sphere's radius, to its
/// distance from the camera, the loader warns: the battery (case 13) meets the bar
/// with triangles whose longest edge is 1.1e13 times their distance and spheres of
/// 1e13 times, and misses it at 2.2e13 and 1e14: there the `f64` paths lose the
/// hits of a ground seen from above (the time of a crossing, within its error
/// bound of the origin, is no hit).
pub const SIZE_RATIO: f64 = 1e13;

/// The most such warnings a scene gets (then a count of the rest).
const MAX_WARNINGS: usize = 4;

/// A triangle of the scene: its vertices, material and how messages name it.
struct Tri<'a> {
    face: Face,
    material: &'a str,
    name: String,
}

/// A vertex as the core gets it (`f32`, `-0` as `0`): the key of shared edges.
fn key(p: [f64; 3]) -> [u32; 3] {
    p.map(|x| {
        let y = x as f32;
        if y == 0.0 { 0 } else { y.to_bits() }
    })
}

/// The point of the segment `a b` nearest to `p`, as the fraction of the way from
/// `a` to `b`.
fn nearest(p: [f64; 3], a: [f64; 3], b: [f64; 3]) -> f64 {
    let (ab, ap) = (sub(b, a), sub(p, a));
    (dot(ap, ab) / dot(ab, ab)).clamp(0.0, 1.0)
}

/// True when `p` lies in the plane of `f` (to `1e-9` of the face's size).
fn in_plane(f: &Face, p: [f64; 3]) -> bool {
    let n = cross(sub(f[1], f[0]), sub(f[2], f[0]));
    let size = length(sub(f[1], f[0])).max(length(sub(f[2], f[0])));
    (dot(n, sub(p, f[0])) / length(n)).abs() <= 1e-9 * size
}

/// The warnings of `desc` about what `f32` and the `f64` paths cannot place:
/// surfaces moved by the rounding of their numbers and a camera held too coarsely
/// ([`rounding_warnings`]), triangles and spheres too large for their distance
/// ([`SIZE_RATIO`]), then triangle edges receding along the view ([`EDGE_RATIO`]).
#[must_use]
pub fn warnings(desc: &SceneDesc) -> Vec<String> {
    let mut out = rounding_warnings(desc);
    out.extend(size_warnings(desc));
    out.extend(edge_warnings(desc));
    out
}

/// The point of the triangle `f` nearest to `p` (Ericson, "Real-Time Collision
/// Detection", 5.1.5).
fn nearest_on_triangle(p: [f64; 3], f: &Face) -> [f64; 3] {
    let [a, b, c] = *f;
    let at = |u: f64, v: f64| [0, 1, 2].map(|i| a[i] + (b[i] - a[i]) * u + (c[i] - a[i]) * v);
    let (ab, ac, ap) = (sub(b, a), sub(c, a), sub(p, a));
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return at(d1 / (d1 - d3), 0.0);
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return at(0.0, d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return [0, 1, 2].map(|i| b[i] + (c[i] - b[i]) * w);
    }
    let denom = 1.0 / (va + vb + vc);
    at(vb * denom, vc * denom)
}

/// Every triangle of the scene, the list's and the meshes' faces, with the name a
/// warning gives it (`triangle 2`, `mesh 1 ("bunny.obj"), face 7`).
fn named_faces(desc: &SceneDesc) -> impl Iterator<Item = (String, Face)> + '_ {
    let faces = desc
        .triangles
        .iter()
        .enumerate()
        .map(|(i, t)| (format!("triangle {}", i + 1), t.vertices));
    let mesh_faces = desc.meshes.iter().enumerate().flat_map(|(i, m)| {
        m.faces
            .iter()
            .enumerate()
            .map(move |(j, f)| (format!("mesh {} ({:?}), face {}", i + 1, m.obj, j + 1), *f))
    });
    faces.chain(mesh_faces)
}

/// The warnings about triangles (list and mesh faces) and spheres larger than
/// [`SIZE_RATIO`] times their distance from the camera.
fn size_warnings(desc: &SceneDesc) -> Vec<String> {
    let cam = desc.camera.position;
    let mut named: Vec<(String, &str, f64, f64)> = Vec::new();
    for (name, f) in named_faces(desc) {
        let size = (0..3)
            .map(|k| length(sub(f[(k + 1) % 3], f[k])))
            .fold(0.0, f64::max);
        let distance = length(sub(nearest_on_triangle(cam, &f), cam));
        named.push((name, "its longest edge", size, distance));
    }
    for (i, s) in desc.spheres.iter().enumerate() {
        let distance = (length(sub(s.center, cam)) - s.radius).abs();
        named.push((
            format!("sphere {}", i + 1),
            "its radius",
            s.radius,
            distance,
        ));
    }
    for (i, c) in desc.cylinders.iter().enumerate() {
        // The camera's distance from the side (of the infinite tube).
        let axis = sub(c.top, c.base);
        let f = sub(cam, c.base);
        let along = dot(f, axis) / dot(axis, axis);
        let radial = length(sub(f, axis.map(|a| a * along)));
        named.push((
            format!("cylinder {}", i + 1),
            "its radius",
            c.radius,
            (radial - c.radius).abs(),
        ));
    }
    let mut out = Vec::new();
    let mut more = 0;
    // False for NaN (a degenerate distance): no warning.
    let too_large = named
        .into_iter()
        .filter(|(_, _, size, distance)| *size > SIZE_RATIO * distance);
    for (name, what, size, distance) in too_large {
        if out.len() == MAX_WARNINGS {
            more += 1;
            continue;
        }
        out.push(format!(
            "{name}: {what} is {size:.2e}, {:.1e} times its distance from the camera \
             ({distance:.3e}), above {SIZE_RATIO:.0e}: beyond that its hits may be lost \
             (they are placed in f64, whose error then exceeds the distance; \
             docs/extremes.md, case 13); make it smaller or move the camera away",
            size / distance
        ));
    }
    if more > 0 {
        out.push(format!(
            "{more} more surface(s) too large for their distance (the first {MAX_WARNINGS} are named above)"
        ));
    }
    out
}

/// Above this many pixels of the footprint at its distance from the camera, the
/// move of a surface by the rounding of its numbers to `f32` is warned about.
/// Measured (`tessera compare` at 320x240, a ground sphere 2 below the camera
/// with a unit sphere on it): moved by 0.26 to 3 pixels it meets the accuracy
/// bar (a smooth surface moved a little shades almost alike, and its outline is
/// in the silhouette band, which is not counted), moved by 10 pixels it misses
/// it (35,061 pixels, up to 83 LSB: the unit sphere's shadow and contact move),
/// by 41 pixels by 87 LSB. The warning comes before the bar fails, where an
/// outline may be drawn a pixel off.
pub const ROUNDING_PIXELS: f64 = 0.5;

/// Above this many pixels of the footprint at the nearest surface, the spacing
/// of `f32` numbers at the camera's position (or the error of its view
/// direction) is warned about: everything near the camera, its rays' origins,
/// the hit points, the shadow rays' origins, is placed only that finely.
/// Measured on the minimal scene with a floor, moved away from the origin with
/// its camera: 0.2 pixel (3e4 out) meets the bar, 0.41 (5e4) misses it by two
/// pixels 3 LSB off, 0.81 (7e4, 1e5) by 31 pixels, 3.2 (3e5) by 261 pixels up to
/// 14 LSB.
pub const CAMERA_PIXELS: f64 = 0.25;

/// `x` rounded to `f32`, back in `f64`.
fn r32(x: f64) -> f64 {
    f64::from(x as f32)
}

/// `a` rounded to `f32`.
fn r3(a: [f64; 3]) -> [f64; 3] {
    a.map(r32)
}

/// True when every number of `a` is exact in `f32`.
fn exact(a: &[f64]) -> bool {
    a.iter().all(|&x| r32(x) == x)
}

/// `x` to three significant digits, shortest form ([`num`]).
fn sig(x: f64) -> String {
    num(format!("{x:.2e}").parse().unwrap_or(x))
}

/// What one pixel spans at unit distance: its angle at the centre of the
/// scene's own frame (`2 tan(fovy / 2) / height`).
fn pixel_angle(desc: &SceneDesc) -> f64 {
    let height = f64::from(desc.render.height.max(1));
    2.0 * (desc.camera.fovy.to_radians() / 2.0).tan() / height
}

/// A surface as the rounding check sees it: its name, how far the rounding of
/// its numbers moves it at its point nearest the camera, that point's distance
/// from the camera, and what to do about it.
struct Moved {
    name: String,
    by: f64,
    distance: f64,
    advice: &'static str,
}

const MOVE_ORIGIN: &str = "move the origin near the camera (translate the whole scene) or use \
     numbers exact in f32 (integers below 2^24 times a power of two)";
const SPLIT: &str = "split the triangle into smaller ones, move the origin near the camera, or \
     use vertices exact in f32 (integers below 2^24 times a power of two)";
const SPHERE: &str = "use a centre and radius exact in f32 (integers below 2^24 times a power of \
     two) or a smaller sphere, or move the origin near the camera";

/// Each surface of `desc` with the move of its `f32` numbers at its point nearest
/// the camera (`cam`, in `f64` as written).
fn moves(desc: &SceneDesc, cam: [f64; 3]) -> Vec<Moved> {
    let mut out = Vec::new();
    for (i, s) in desc.spheres.iter().enumerate() {
        let to_cam = sub(cam, s.center);
        let d = length(to_cam);
        let u = if d > 0.0 {
            to_cam.map(|x| x / d)
        } else {
            [0.0, 1.0, 0.0]
        };
        let by = if exact(&s.center) && exact(&[s.radius]) {
            0.0
        } else {
            // The written surface's point nearest the camera, against the
            // rounded sphere.
            let p = [0, 1, 2].map(|k| s.center[k] + s.radius * u[k]);
            (length(sub(p, r3(s.center))) - r32(s.radius)).abs()
        };
        out.push(Moved {
            name: format!("sphere {}", i + 1),
            by,
            distance: (d - s.radius).abs(),
            advice: SPHERE,
        });
    }
    for (i, pl) in desc.planes.iter().enumerate() {
        let n = pl.normal.map(|x| x / length(pl.normal));
        let h = dot(sub(cam, pl.point), n);
        let p = [0, 1, 2].map(|k| cam[k] - h * n[k]);
        // The core's plane: the rounded unit normal and the rounded offset from
        // the origin, `N . point / |N|` of the rounded numbers.
        let (n32, q32) = (r3(pl.normal), r3(pl.point));
        let len = length(n32);
        let unit = r3(n32.map(|x| x / len));
        let offset = r32(dot(n32, q32) / len);
        out.push(Moved {
            name: format!("plane {}", i + 1),
            by: (dot(unit, p) - offset).abs(),
            distance: h.abs(),
            advice: MOVE_ORIGIN,
        });
    }
    for (name, f) in named_faces(desc) {
        let p = nearest_on_triangle(cam, &f);
        let by = if f.iter().all(|v| exact(v)) {
            0.0
        } else {
            // The plane of the rounded vertices at the written triangle's point
            // nearest the camera: far from the vertices, a tilt by their
            // rounding is multiplied by the distance.
            let g = f.map(r3);
            let n = cross(sub(g[1], g[0]), sub(g[2], g[0]));
            let len = length(n);
            if len > 0.0 {
                (dot(n, sub(p, g[0])) / len).abs()
            } else {
                0.0
            }
        };
        out.push(Moved {
            name,
            by,
            distance: length(sub(p, cam)),
            advice: SPLIT,
        });
    }
    for (i, b) in desc.boxes.iter().enumerate() {
        let p = [0, 1, 2].map(|k| cam[k].clamp(b.min[k], b.max[k]));
        let round = |x: f64| (r32(x) - x).abs();
        let (by, distance) = if p == cam {
            // Inside: the nearest face.
            (0..3)
                .flat_map(|k| [(b.min[k], cam[k] - b.min[k]), (b.max[k], b.max[k] - cam[k])])
                .min_by(|x, y| x.1.total_cmp(&y.1))
                .map_or((0.0, 0.0), |(face, d)| (round(face), d))
        } else {
            // Outside: the faces the nearest point lies on.
            let by = (0..3)
                .map(|k| {
                    if cam[k] < b.min[k] {
                        round(b.min[k])
                    } else if cam[k] > b.max[k] {
                        round(b.max[k])
                    } else {
                        0.0
                    }
                })
                .fold(0.0, f64::max);
            (by, length(sub(p, cam)))
        };
        out.push(Moved {
            name: format!("box {}", i + 1),
            by,
            distance,
            advice: MOVE_ORIGIN,
        });
    }
    out
}

/// The warnings about surfaces moved by more than [`ROUNDING_PIXELS`] by the
/// rounding of their numbers to `f32`, and about a camera whose position (or
/// view direction) `f32` holds more coarsely than [`CAMERA_PIXELS`] at the
/// nearest surface.
#[must_use]
pub fn rounding_warnings(desc: &SceneDesc) -> Vec<String> {
    let c = &desc.camera;
    let cam = c.position;
    let angle = pixel_angle(desc);
    // A pixel's span at `distance`: nothing is seen nearer than `near`.
    let footprint = |distance: f64| distance.max(c.near) * angle;
    let moved = moves(desc, cam);
    let mut out = Vec::new();
    let mut more = 0;
    for m in &moved {
        let pixels = m.by / footprint(m.distance);
        // False for NaN: no warning.
        if !(pixels > ROUNDING_PIXELS && m.distance <= c.far) {
            continue;
        }
        if out.len() == MAX_WARNINGS {
            more += 1;
            continue;
        }
        out.push(format!(
            "{}: rounding its numbers to f32 moves it by {} units where it is nearest the \
             camera, {} pixels at its distance from the camera ({}; a pixel spans {} there), \
             above {ROUNDING_PIXELS}: the f32 core draws it there, the f64 reference where the \
             file says (docs/limits.md); {}",
            m.name,
            sig(m.by),
            sig(pixels),
            sig(m.distance),
            sig(footprint(m.distance)),
            m.advice
        ));
    }
    if more > 0 {
        out.push(format!(
            "{more} more surface(s) moved by their rounding to f32 (the first {MAX_WARNINGS} \
             are named above)"
        ));
    }
    // The camera: the spacing of f32 numbers at its coordinates, against the
    // footprint at the nearest surface.
    let nearest = moved
        .iter()
        .map(|m| m.distance)
        .fold(f64::INFINITY, f64::min);
    if nearest.is_finite() {
        let largest = cam.iter().fold(0.0f64, |a, &x| a.max(x.abs())) as f32;
        let spacing = f64::from(largest.next_up() - largest);
        let pixels = spacing / footprint(nearest);
        if pixels > CAMERA_PIXELS {
            let p = |v: [f64; 3]| format!("[{}, {}, {}]", num(v[0]), num(v[1]), num(v[2]));
            out.push(format!(
                "camera: at {} its position, and the rays and hit points near it, are held in \
                 f32 only to {} units (the spacing of f32 numbers there), {} pixels at the \
                 nearest surface ({} from the camera; a pixel spans {} there), above \
                 {CAMERA_PIXELS}: the image may miss the accuracy bar (docs/limits.md); move \
                 the origin near the camera (translate the whole scene)",
                p(cam),
                sig(spacing),
                sig(pixels),
                sig(nearest),
                sig(footprint(nearest))
            ));
        }
    }
    // Its view direction: `look_at - position` in f32, against the written one.
    if let (Some(at), Ok(n)) = (c.look_at, desc.camera_numbers()) {
        let (f32dir, f64dir) = (n.forward.map(f64::from), sub(at, cam));
        let off = length(cross(f32dir, f64dir)) / (length(f32dir) * length(f64dir));
        let pixels = off / angle;
        if pixels > CAMERA_PIXELS {
            out.push(format!(
                "camera: its view direction, look_at - position rounded to f32, is off by {} \
                 radians, {} pixels, above {CAMERA_PIXELS}: the whole image is turned by that \
                 much (docs/limits.md); move the origin near the camera, put look_at farther \
                 away, or give forward instead",
                sig(off),
                sig(pixels)
            ));
        }
    }
    out
}

/// The warnings about triangle edges, list and mesh faces alike.
#[must_use]
pub fn edge_warnings(desc: &SceneDesc) -> Vec<String> {
    let mut tris: Vec<Tri<'_>> = desc
        .triangles
        .iter()
        .enumerate()
        .map(|(i, t)| Tri {
            face: t.vertices,
            material: &t.material,
            name: format!("triangle {}", i + 1),
        })
        .collect();
    for (i, m) in desc.meshes.iter().enumerate() {
        tris.extend(m.faces.iter().enumerate().map(|(j, f)| Tri {
            face: *f,
            material: m.material.as_deref().unwrap_or_default(),
            name: format!("mesh {} ({:?}), face {}", i + 1, m.obj, j + 1),
        }));
    }
    let edge = |a: [f64; 3], b: [f64; 3]| {
        let (a, b) = (key(a), key(b));
        if a <= b { (a, b) } else { (b, a) }
    };
    let mut sides: HashMap<([u32; 3], [u32; 3]), Vec<usize>> = HashMap::new();
    for (i, t) in tris.iter().enumerate() {
        for k in 0..3 {
            sides
                .entry(edge(t.face[k], t.face[(k + 1) % 3]))
                .or_default()
                .push(i);
        }
    }
    let cam = desc.camera.position;
    let forward = match (desc.camera.forward, desc.camera.look_at) {
        (Some(f), _) => f,
        (None, Some(at)) => sub(at, cam),
        (None, None) => return Vec::new(),
    };
    let forward = forward.map(|x| x / length(forward));
    let mut out = Vec::new();
    let mut more = 0;
    for (i, t) in tris.iter().enumerate() {
        let worst = (0..3)
            .filter_map(|k| {
                let (a, b) = (t.face[k], t.face[(k + 1) % 3]);
                let c = t.face[(k + 2) % 3];
                // Hidden: one neighbour, same material, same plane (its third
                // vertex on this one's plane, and this one's on its).
                let owners = sides.get(&edge(a, b))?;
                let seamless = owners.len() == 2
                    && owners.iter().filter(|&&j| j != i).all(|&j| {
                        let o = &tris[j];
                        o.material == t.material
                            && o.face.iter().all(|&p| in_plane(&t.face, p))
                            && in_plane(&o.face, c)
                    });
                // Each end is off by ulps of its depth along the view; the edge's
                // point nearest to the camera, a fraction `s` of the way, by the
                // ends' errors weighed as its position weighs them.
                let s = nearest(cam, a, b);
                let q = [0, 1, 2].map(|i| a[i] + (b[i] - a[i]) * s);
                let distance = length(sub(q, cam));
                let depth = |p: [f64; 3]| dot(sub(p, cam), forward).abs();
                let reach = depth(a) * (1.0 - s) + depth(b) * s;
                let ratio = reach / distance;
                (!seamless && distance <= desc.camera.far && ratio > EDGE_RATIO)
                    .then_some((ratio, a, b, distance, reach))
            })
            .max_by(|x, y| x.0.total_cmp(&y.0));
        let Some((ratio, a, b, distance, reach)) = worst else {
            continue;
        };
        if out.len() == MAX_WARNINGS {
            more += 1;
            continue;
        }
        let p = |v: [f64; 3]| format!("[{}, {}, {}]", num(v[0]), num(v[1]), num(v[2]));
        out.push(format!(
            "{}: its edge from {} to {} passes {distance:.3} from the camera while its \
             ends reach about {reach:.2e} along the view there ({ratio:.1e} times \
             farther, above {EDGE_RATIO:.0e}): f32 places such an edge only to within a \
             few ulps of that reach (2^-24 of it is {:.2e}), so its outline may be drawn \
             off by up to that much; split the triangle so that its edges near the view \
             are shorter (docs/extremes.md, case 13)",
            t.name,
            p(a),
            p(b),
            reach / f64::from(1u32 << 24),
        ));
    }
    if more > 0 {
        out.push(format!(
            "{more} more triangle(s) with such edges (the first {MAX_WARNINGS} are named above)"
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::file::parse;

    /// A scene seen from `[0.3, 2, 6.1]` looking at the origin, with `items`.
    fn scene(far: f64, items: &str) -> SceneDesc {
        let text = format!(
            "[camera]\nposition = [0.3, 2, 6.1]\nlook_at = [0, 0, 0]\nnear = 0.1\nfar = {far}\n\
             [[material]]\nname = \"a\"\n[[material]]\nname = \"b\"\n\
             [[light]]\nposition = [2, 6, 4]\nintensity = 40\n{items}"
        );
        parse(&text, "t.toml").unwrap()
    }

    fn triangle(v: [[f64; 3]; 3], material: &str) -> String {
        format!("[[triangle]]\nvertices = {v:?}\nmaterial = \"{material}\"\n")
    }

    /// A huge ground: two triangles 2e7 wide meeting under the camera.
    fn ground(second: &str) -> String {
        let s = 1e7;
        triangle([[-s, 0.0, -s], [s, 0.0, -s], [s, 0.0, s]], "a")
            + &triangle([[-s, 0.0, -s], [s, 0.0, s], [-s, 0.0, s]], second)
    }

    #[test]
    fn a_huge_ground_of_two_triangles_is_no_outline() {
        assert_eq!(
            edge_warnings(&scene(100.0, &ground("a"))),
            Vec::<String>::new()
        );
        // Its outer edges are far beyond the far distance, and nearer than their
        // reach only when the far distance takes them in: still no outline near.
        assert_eq!(
            edge_warnings(&scene(1e9, &ground("a"))),
            Vec::<String>::new()
        );
    }

    #[test]
    fn an_outline_receding_near_the_camera_is_warned_about() {
        // Another material: the diagonal under the camera is an outline.
        let w = edge_warnings(&scene(100.0, &ground("b")));
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(
            w[0].starts_with("triangle 1: its edge from [1e7, 0, 1e7] to [-1e7, 0, -1e7]"),
            "{w:?}"
        );
        assert!(w[0].contains("docs/extremes.md, case 13"), "{w:?}");
        // An edge along the view 0.3 beside the camera's foot: warned from 1e6 on.
        let edge = |s: f64| triangle([[0.0, 0.0, s], [0.0, 0.0, -s], [-s, 0.0, 0.0]], "a");
        assert_eq!(
            edge_warnings(&scene(100.0, &edge(1e5))),
            Vec::<String>::new()
        );
        assert_eq!(edge_warnings(&scene(100.0, &edge(1e7))).len(), 1);
        // Beyond the far distance it is not seen.
        let far = triangle(
            [[200.0, 0.0, 1e9], [200.0, 0.0, -1e9], [1e9, 0.0, 0.0]],
            "a",
        );
        assert_eq!(edge_warnings(&scene(100.0, &far)), Vec::<String>::new());
        assert_eq!(edge_warnings(&scene(1000.0, &far)).len(), 1);
    }

    #[test]
    fn an_edge_across_the_view_or_anchored_near_the_camera_is_not() {
        // A wall 2e8 wide across the view: its base is long, but not in depth.
        let wall = triangle([[1e8, 0.0, 0.0], [-1e8, 0.0, 0.0], [0.0, 1e8, 0.0]], "a");
        assert_eq!(edge_warnings(&scene(100.0, &wall)), Vec::<String>::new());
        // A wedge from a vertex near the camera to the far distance and beyond.
        let wedge = triangle([[0.0, 0.0, 8.0], [5e8, 0.0, -1e9], [-5e8, 0.0, -1e9]], "a");
        assert_eq!(edge_warnings(&scene(100.0, &wedge)), Vec::<String>::new());
    }

    #[test]
    fn a_surface_too_large_for_its_distance_is_warned_about() {
        // The two-triangle ground 2 units below the camera, half-sizes 1e12 and
        // 1e13: longest edges (the diagonal) 5.7e12 and 5.7e13 times the distance.
        let ground = |s: f64| {
            triangle([[-s, 0.0, -s], [s, 0.0, -s], [s, 0.0, s]], "a")
                + &triangle([[-s, 0.0, -s], [s, 0.0, s], [-s, 0.0, s]], "a")
        };
        assert_eq!(warnings(&scene(100.0, &ground(1e12))), Vec::<String>::new());
        // Triangle 2 lies under the camera; triangle 1's nearest point is 4.6
        // away, its ratio 6e12.
        let w = warnings(&scene(100.0, &ground(1e13)));
        assert_eq!(w.len(), 1, "{w:?}");
        assert!(
            w[0].starts_with(
                "triangle 2: its longest edge is 2.83e13, 1.4e13 times its distance from the \
                 camera (2.000e0), above 1e13: beyond that its hits may be lost"
            ),
            "{w:?}"
        );
        // A sphere's radius against its surface's distance.
        let sphere = |r: f64| {
            format!(
                "[[sphere]]\ncenter = [0, {}, 0]\nradius = {r}\nmaterial = \"a\"\n",
                -r
            )
        };
        assert_eq!(warnings(&scene(100.0, &sphere(1e13))), Vec::<String>::new());
        assert_eq!(warnings(&scene(100.0, &sphere(1e14))).len(), 1);
        // The distance is the triangle's, not its plane's: one far to the side.
        let aside = triangle([[1e15, 0.0, 0.0], [2e15, 0.0, 0.0], [1e15, 0.0, 1e15]], "a");
        assert_eq!(warnings(&scene(100.0, &aside)), Vec::<String>::new());
    }

    #[test]
    fn mesh_faces_are_looked_at_and_the_warnings_are_few() {
        let mut d = scene(100.0, "");
        let s = 1e8;
        let faces: Vec<Face> = (0..10)
            .map(|i| {
                let x = 0.5 * f64::from(i);
                [[x, 0.0, s], [x, 0.0, -s], [x - s, 0.0, 0.0]]
            })
            .collect();
        d.meshes.push(crate::desc::MeshDesc {
            faces,
            ..crate::desc::MeshDesc::unplaced("m.obj", Some("a".into()))
        });
        let w = edge_warnings(&d);
        assert_eq!(w.len(), MAX_WARNINGS + 1, "{w:?}");
        assert!(
            w[0].starts_with("mesh 1 (\"m.obj\"), face 1: its edge from"),
            "{w:?}"
        );
        assert_eq!(
            w[MAX_WARNINGS],
            "6 more triangle(s) with such edges (the first 4 are named above)"
        );
    }
}
