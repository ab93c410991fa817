//! Indexed triangle meshes: shared vertices, faces of three `u16` vertex indices,
//! optional per-vertex normals (smooth shading), one material, and a BVH over the
//! faces. Everything is borrowed, so a mesh can lie where it is, in flash on a chip
//! (`static` data written by `tessera bake`), or in a host's vectors.
//!
//! A face is the [`Triangle`] of its three vertices, tested by the same watertight
//! test as the triangle list, so a mesh gives the image of its faces as
//! triangles (with flat normals); with normals, the shading normal is the
//! vertex normals interpolated by the hit's barycentrics, turned to the side of
//! the face's own normal (which still places the secondary rays and decides which
//! side of the surface a ray leaves from).
//!
//! Memory: 12 bytes a vertex (24 with its normal), 6 a face, 32 a BVH node and 2
//! a face for the BVH's order; a triangle of the flat list takes 40 bytes.

use crate::bvh::{BakedBvh, BvhView};
use crate::error::Error;
use crate::geometry::Triangle;
use crate::material::MaterialId;
use crate::primitive::Primitive;
use crate::vec::Vec3;

/// The most meshes a scene view takes ([`crate::SceneView::with_meshes`]): a hit
/// names its mesh and face in one index, `mesh << 16 | face`.
pub const MAX_MESHES: usize = 16;

/// How far from its face [`Mesh::lift`] may move a point of a mesh of these
/// parts: each vertex's term moves it by at most its distance to the vertex
/// (a projection on the unit normal), and the weights add up to 1, so by at
/// most the largest face's diameter, bounded here by twice its largest extent
/// on an axis (more than `sqrt(3)` times it, with room for rounding). 0 for a
/// flat mesh, which lifts nothing; a face with an index out of range counts
/// for nothing (the view refuses the mesh). Linear in the faces; a `const fn`,
/// so that a baked mesh's is computed when it is compiled.
#[allow(clippy::indexing_slicing)] // every index is checked just before
const fn lift_of(vertices: &[[f32; 3]], faces: &[[u16; 3]], normals: &[[f32; 3]]) -> f32 {
    if normals.is_empty() {
        return 0.0;
    }
    let mut largest = 0.0f32;
    let mut f = 0;
    while f < faces.len() {
        let face = faces[f];
        let mut axis = 0;
        while axis < 3 {
            let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
            let mut k = 0;
            while k < 3 {
                let i = face[k] as usize;
                if i < vertices.len() {
                    let x = vertices[i][axis];
                    if x < lo {
                        lo = x;
                    }
                    if x > hi {
                        hi = x;
                    }
                }
                k += 1;
            }
            // NaN or no vertex: no extent (the view refuses such a mesh).
            if hi - lo > largest {
                largest = hi - lo;
            }
            axis += 1;
        }
        f += 1;
    }
    2.0 * largest
}

/// An indexed triangle mesh (see the module doc). Build with [`Mesh::new`] (a
/// `const fn`, for baked data) and give it to a view with
/// [`crate::SceneView::with_meshes`], which checks it.
#[derive(Clone, Copy, Debug)]
pub struct Mesh<'a> {
    vertices: &'a [[f32; 3]],
    faces: &'a [[u16; 3]],
    normals: &'a [[f32; 3]],
    uvs: &'a [[f32; 2]],
    material: MaterialId,
    bvh: BakedBvh<'a>,
    /// [`Mesh::lift_bound`], computed when built (at compile time for a
    /// baked mesh).
    lift: f32,
}

/// How far from 1 a vertex normal's squared length may be, in units of
/// `f32::EPSILON`: what normalising in `f32` leaves (a squared length within 3
/// ulps of 1, seen over random directions) with room, and far less than a
/// normal that would shade visibly otherwise (1.0009 times a unit normal is
/// 15,000 of them).
pub const NORMAL_LENGTH_ULPS: u32 = 8;

impl<'a> Mesh<'a> {
    /// A mesh of `faces` (three indices into `vertices` each), shaded smooth with
    /// `normals` (one per vertex) or flat (`normals` empty), of `material`, its
    /// faces found through `bvh` (built over the faces' triangles in face order,
    /// [`crate::bvh::Bvh::build`]). Checked when a view takes it.
    #[must_use]
    pub const fn new(
        vertices: &'a [[f32; 3]],
        faces: &'a [[u16; 3]],
        normals: &'a [[f32; 3]],
        material: MaterialId,
        bvh: BakedBvh<'a>,
    ) -> Self {
        Self {
            vertices,
            faces,
            normals,
            uvs: &[],
            material,
            bvh,
            lift: lift_of(vertices, faces, normals),
        }
    }

    /// The mesh with texture coordinates `uvs`, one per vertex (a 3D tool's,
    /// glTF's convention: `v` down from the image's top), interpolated across
    /// each face by the hit's barycentrics. Without them (or empty) a face's uv
    /// is the hit's barycentrics `(b1, b2)`, as for a lone triangle. Checked
    /// when a view takes the mesh: one per vertex, each finite.
    #[must_use]
    pub const fn with_uvs(mut self, uvs: &'a [[f32; 2]]) -> Self {
        self.uvs = uvs;
        self
    }

    /// The texture coordinates (empty: the faces' barycentrics).
    #[must_use]
    pub fn uvs(&self) -> &'a [[f32; 2]] {
        self.uvs
    }

    /// The uv of face `f` at barycentrics `(b1, b2)` of its second and third
    /// vertices: its vertices' uvs interpolated, or `(b1, b2)` itself when the
    /// mesh has none.
    #[inline(always)]
    pub(crate) fn uv(&self, f: usize, [b1, b2]: [f32; 2]) -> [f32; 2] {
        let at = |i: u16| self.uvs.get(usize::from(i)).copied();
        let Some(&[i, j, k]) = self.faces.get(f) else {
            return [b1, b2];
        };
        let (Some(a), Some(b), Some(c)) = (at(i), at(j), at(k)) else {
            return [b1, b2];
        };
        let b0 = 1.0 - b1 - b2;
        let ([au, av], [bu, bv], [cu, cv]) = (a, b, c);
        [au * b0 + bu * b1 + cu * b2, av * b0 + bv * b1 + cv * b2]
    }

    /// The vertices.
    #[must_use]
    pub fn vertices(&self) -> &'a [[f32; 3]] {
        self.vertices
    }

    /// The faces.
    #[must_use]
    pub fn faces(&self) -> &'a [[u16; 3]] {
        self.faces
    }

    /// The vertex normals (empty: flat shading).
    #[must_use]
    pub fn normals(&self) -> &'a [[f32; 3]] {
        self.normals
    }

    /// The material.
    #[must_use]
    pub fn material(&self) -> MaterialId {
        self.material
    }

    /// The triangle of face `f`.
    #[inline(always)]
    pub(crate) fn triangle(&self, f: usize) -> Option<Triangle> {
        let [a, b, c] = *self.faces.get(f)?;
        let v = |i: u16| self.vertices.get(usize::from(i)).copied();
        Some(Triangle::baked(v(a)?, v(b)?, v(c)?))
    }

    /// The face as a primitive of the mesh's material.
    #[inline(always)]
    pub(crate) fn primitive(&self, f: usize) -> Option<Primitive<Triangle>> {
        Some(Primitive {
            geometry: self.triangle(f)?,
            material: self.material,
        })
    }

    /// The hierarchy's view.
    #[inline(always)]
    pub(crate) fn bvh(&self) -> BvhView<'a> {
        self.bvh.view()
    }

    /// The shading normal of face `f` at barycentrics `b` (weights of its three
    /// vertices), turned to the side of `n`, the face's normal as the shading
    /// uses it; `n` itself for a flat mesh (or a sum that does not normalise).
    pub(crate) fn shading_normal(&self, f: usize, b: [f32; 3], n: Vec3) -> Vec3 {
        self.shading_normal_with(f, b, n, |m| m)
    }

    /// [`Mesh::shading_normal`] with each vertex normal carried by `normal`
    /// first (an instance's inverse transpose, normalised: the normals of the
    /// mesh carried into the world).
    #[inline(always)]
    pub(crate) fn shading_normal_with(
        &self,
        f: usize,
        b: [f32; 3],
        n: Vec3,
        normal: impl Fn(Vec3) -> Vec3,
    ) -> Vec3 {
        let Some(&[i, j, k]) = self.faces.get(f) else {
            return n;
        };
        let at = |i: u16| {
            self.normals
                .get(usize::from(i))
                .map(|&[x, y, z]| Vec3::new(x, y, z))
        };
        let (Some(a), Some(bn), Some(c)) = (at(i), at(j), at(k)) else {
            return n;
        };
        let (a, bn, c) = (normal(a), normal(bn), normal(c));
        let s = (a * b[0] + bn * b[1] + c * b[2]).normalize_or(n);
        if s.dot(n) < 0.0 { -s } else { s }
    }

    /// Where a shadow ray leaves face `f` of a smooth mesh, as a move from the hit
    /// point `p` (barycentrics `b`; `out` is -1 when the ray sees the face from
    /// behind its normals, else 1): the point lifted to the curved surface the
    /// vertex normals describe (Hanika, "Hacking the shadow terminator", Ray
    /// Tracing Gems II, ch. 4). Without it a light that the shading normal faces
    /// but the flat face does not is blocked by the face's own neighbours: dark
    /// facets along the terminator. Zero for a flat mesh.
    pub(crate) fn lift(&self, f: usize, b: [f32; 3], p: Vec3, out: f32) -> Vec3 {
        self.lift_with(f, b, p, out, |v| v, |n| n, 1.0)
    }

    /// [`Mesh::lift`] in another space: the differences of points (the
    /// edges, the point from each vertex) carried there by the linear map
    /// `vector` (`p` stays in the mesh's space: no far coordinate cancels),
    /// the unit vertex normals by `normal`; `winding` is -1 where `vector`
    /// mirrors (which turns the carried face's winding against its
    /// normals), else 1. The move is the other space's.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn lift_with(
        &self,
        f: usize,
        b: [f32; 3],
        p: Vec3,
        out: f32,
        vector: impl Fn(Vec3) -> Vec3,
        normal: impl Fn(Vec3) -> Vec3,
        winding: f32,
    ) -> Vec3 {
        let Some(&face) = self.faces.get(f) else {
            return Vec3::ZERO;
        };
        // The face's own normal: each vertex normal is taken on its side (normals
        // against the winding would otherwise lift nothing).
        let Some(tri) = self.triangle(f) else {
            return Vec3::ZERO;
        };
        let [a, b1, c] = tri.vertices();
        let g = vector(b1 - a).cross(vector(c - a)) * winding;
        // p' = sum w_i (p - min(0, (p - v_i) . n_i) n_i), so with sum w_i = 1 the
        // move is the weighted sum of the lifts above each vertex's tangent plane.
        let mut lift = Vec3::ZERO;
        for (i, w) in face.into_iter().zip(b) {
            let k = usize::from(i);
            let (Some(&[x, y, z]), Some(&[nx, ny, nz])) =
                (self.vertices.get(k), self.normals.get(k))
            else {
                return Vec3::ZERO;
            };
            let n = normal(Vec3::new(nx, ny, nz));
            let n = if n.dot(g) < 0.0 { -n } else { n } * out;
            let below = crate::math::min(vector(p - Vec3::new(x, y, z)).dot(n), 0.0);
            lift = lift - n * (below * w);
        }
        if lift.x.is_finite() && lift.y.is_finite() && lift.z.is_finite() {
            lift
        } else {
            Vec3::ZERO
        }
    }

    /// How far from its face [`Mesh::lift`] may move a point (see
    /// `lift_of`; 0 for a flat mesh).
    pub(crate) fn lift_bound(&self) -> f32 {
        self.lift
    }

    /// Checks the mesh for a scene of `materials` materials: its faces (each
    /// vertex index in range, each triangle as [`Triangle::try_new`] makes it), its
    /// normals (none, or one per vertex, each of unit length to
    /// [`NORMAL_LENGTH_ULPS`] ulps with no subnormal component), its uvs (none,
    /// or one per vertex, each finite), its material and
    /// its hierarchy (as for baked triangles).
    pub(crate) fn check(&self, materials: usize) -> Result<(), Error> {
        if self.faces.len() >= 1 << 16 {
            return Err(Error::BadMesh);
        }
        if !self.normals.is_empty() {
            if self.normals.len() != self.vertices.len() {
                return Err(Error::BadMesh);
            }
            // A unit vector as `f32` makes one (the host rounds once from f64, a
            // firmware may normalise in f32: a few ulps), with no subnormal
            // component (a scene's rule, `error::flush`).
            let ulps = NORMAL_LENGTH_ULPS as f32 * f32::EPSILON;
            for &[x, y, z] in self.normals {
                let n = Vec3::new(x, y, z);
                let len2 = n.length_squared();
                if !(len2 - 1.0).abs().le(&ulps) || crate::error::flush3(n) != n {
                    return Err(Error::BadMesh);
                }
            }
        }
        if !self.uvs.is_empty()
            && (self.uvs.len() != self.vertices.len()
                || self
                    .uvs
                    .iter()
                    .any(|&[u, v]| !(u.is_finite() && v.is_finite())))
        {
            return Err(Error::BadMesh);
        }
        crate::bvh::check_faces(
            self.faces.len(),
            |f| self.primitive(f).ok_or(Error::BadMesh),
            materials,
            &self.bvh,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{
        Camera, Color, Renderer, Scene, SceneView, bvh::Bvh, bvh::BvhNode, light::Light,
        material::Material,
    };
    use crate::{RenderSettings, Tile, TileCoord, Viewport, geometry::Sphere};

    extern crate std;
    use std::vec::Vec as StdVec;

    /// The memory the module docs give: 12 bytes a vertex (24 with its normal), 6
    /// a face, 32 a BVH node (as [`BvhNode`]'s docs say), 2 a face for the BVH's
    /// order, 40 a triangle of the flat list.
    #[test]
    fn sizes_match_the_docs() {
        use core::mem::size_of;
        let vertex = size_of::<[f32; 3]>();
        assert_eq!((vertex, 2 * vertex), (12, 24));
        assert_eq!(size_of::<[u16; 3]>(), 6);
        assert_eq!(size_of::<BvhNode>(), 32);
        assert_eq!(size_of::<u16>(), 2);
        assert_eq!(size_of::<Primitive<Triangle>>(), 40);
    }

    /// Vertices, faces, normals.
    type Parts = (StdVec<[f32; 3]>, StdVec<[u16; 3]>, StdVec<[f32; 3]>);

    /// A UV sphere of radius 1 at the origin: `rings x sectors` quads, its
    /// vertices, faces and exact unit normals.
    fn uv_sphere(rings: u16, sectors: u16) -> Parts {
        let mut v = StdVec::new();
        for i in 0..=rings {
            let th = core::f32::consts::PI * f32::from(i) / f32::from(rings);
            for j in 0..sectors {
                let ph = 2.0 * core::f32::consts::PI * f32::from(j) / f32::from(sectors);
                v.push([
                    libm::sinf(th) * libm::cosf(ph),
                    libm::cosf(th),
                    libm::sinf(th) * libm::sinf(ph),
                ]);
            }
        }
        let at = |i: u16, j: u16| i * sectors + j % sectors;
        let mut f = StdVec::new();
        for i in 0..rings {
            for j in 0..sectors {
                let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j + 1), at(i + 1, j));
                if i > 0 {
                    f.push([a, b, c]);
                }
                if i + 1 < rings {
                    f.push([a, c, d]);
                }
            }
        }
        // Normalised in f32, as a firmware building a mesh in RAM would.
        let n = v.iter().map(|p| {
            let q = Vec3::new(p[0], p[1], p[2]).normalize_or(Vec3::Y);
            [q.x, q.y, q.z]
        });
        let n = n.collect();
        (v, f, n)
    }

    fn camera() -> Camera {
        Camera::look_at(Vec3::new(0.0, 0.4, 3.2), Vec3::ZERO, Vec3::Y, 0.1, 100.0).unwrap()
    }

    /// A scene of one red material (shiny) and one light; `sphere`: with the
    /// analytic unit sphere.
    fn scene(sphere: bool) -> Scene<crate::capacities!(spheres: 1, materials: 1, lights: 1)> {
        let mut s = Scene::new(camera());
        s.set_ambient(Color::splat(0.05)).unwrap();
        let m = s
            .add_material(
                Material::matte(Color::new(0.9, 0.3, 0.2))
                    .with_specular(0.4, 30.0)
                    .unwrap(),
            )
            .unwrap();
        s.add_light(Light::point(Vec3::new(-2.0, 3.0, 4.0), Color::WHITE, 30.0).unwrap())
            .unwrap();
        if sphere {
            s.add_sphere(Sphere::try_new(Vec3::ZERO, 1.0).unwrap(), m)
                .unwrap();
        }
        s
    }

    fn render(v: &SceneView<'_>) -> StdVec<[u8; 3]> {
        let vp = Viewport::new(48, 40);
        let renderer = Renderer::try_new(&camera(), vp, RenderSettings::default()).unwrap();
        let (across, down) = renderer.tile_grid(8);
        let mut px = std::vec![[0u8; 3]; 48 * 40];
        for ty in 0..down {
            for tx in 0..across {
                let mut tile = Tile::<8>::new();
                renderer
                    .render_tile(v, TileCoord::new(tx, ty), &mut tile, &mut ())
                    .unwrap();
                for (k, p) in tile.pixels().enumerate() {
                    let (x, y) = (usize::from(tx) * 8 + k % 8, usize::from(ty) * 8 + k / 8);
                    if x < 48 && y < 40 {
                        px[y * 48 + x] = [p.r, p.g, p.b];
                    }
                }
            }
        }
        px
    }

    fn mean_diff(a: &[[u8; 3]], b: &[[u8; 3]]) -> f64 {
        let sum: u64 = a
            .iter()
            .zip(b)
            .flat_map(|(p, q)| p.iter().zip(q).map(|(x, y)| u64::from(x.abs_diff(*y))))
            .sum();
        sum as f64 / (a.len() * 3) as f64
    }

    /// The hierarchy of the faces, as baked data would hold it.
    fn bvh_of(v: &[[f32; 3]], f: &[[u16; 3]]) -> (StdVec<BvhNode>, StdVec<u16>, f32) {
        let tris: StdVec<Primitive<Triangle>> = f
            .iter()
            .map(|&[a, b, c]| Primitive {
                geometry: Triangle::baked(v[usize::from(a)], v[usize::from(b)], v[usize::from(c)]),
                material: MaterialId(0),
            })
            .collect();
        let mut bvh: std::boxed::Box<Bvh<4096, 2048>> = std::boxed::Box::default();
        bvh.build(&tris).unwrap();
        (bvh.nodes().to_vec(), bvh.order().to_vec(), bvh.reach())
    }

    /// A flat mesh renders its faces exactly as the same triangles in the list
    /// (through a BVH or not); smooth normals bring the image of a 12 x 24 sphere
    /// closer to the analytic sphere's, at the same silhouette.
    #[test]
    fn a_mesh_renders_its_faces_and_smooth_normals_round_it() {
        let (v, f, n) = uv_sphere(12, 24);
        let (nodes, order, reach) = bvh_of(&v, &f);
        let bvh = BakedBvh::new(&nodes, &order, reach);
        let flat = [Mesh::new(&v, &f, &[], MaterialId(0), bvh)];
        let smooth = [Mesh::new(&v, &f, &n, MaterialId(0), bvh)];
        let s = scene(false);
        let flat_px = render(&s.view().with_meshes(&flat).unwrap());
        let smooth_px = render(&s.view().with_meshes(&smooth).unwrap());
        // The same faces as triangles of the list.
        let mut list: std::boxed::Box<
            Scene<crate::capacities!(triangles: 600, materials: 1, lights: 1)>,
        > = std::boxed::Box::new(Scene::new(camera()));
        list.set_ambient(Color::splat(0.05)).unwrap();
        list.add_material(s.view().materials()[0]).unwrap();
        list.add_light(s.view().lights()[0]).unwrap();
        add_faces(&mut list, &v, &f);
        assert_eq!(flat_px, render(&list.view()));
        // Normals against the winding shade and lift the same (each is taken on
        // the side of its face's own normal).
        let inward: StdVec<[f32; 3]> = n.iter().map(|m| m.map(|x| -x)).collect();
        let inward = [Mesh::new(&v, &f, &inward, MaterialId(0), bvh)];
        assert_eq!(smooth_px, render(&s.view().with_meshes(&inward).unwrap()));
        let sphere = render(&scene(true).view());
        let (d_flat, d_smooth) = (mean_diff(&flat_px, &sphere), mean_diff(&smooth_px, &sphere));
        assert!(d_smooth < 0.5 * d_flat, "smooth {d_smooth}, flat {d_flat}");
        // The silhouette is the faces': where the flat mesh shows the background,
        // so does the smooth one.
        for (p, q) in flat_px.iter().zip(&smooth_px) {
            assert_eq!(*p == [0, 0, 0], *q == [0, 0, 0]);
        }
    }

    /// A shadow ray of a smooth mesh leaves from its hit lifted towards the
    /// curved surface the normals describe: never further from the face than
    /// [`Mesh::lift_bound`], yet beyond the faces' own box (a coarse sphere's
    /// faces lie inside the box of its vertices, the curved surface bulges out
    /// of it), so the tile lists' box of visible points must grow by it.
    #[test]
    fn the_lift_stays_within_its_bound_and_may_leave_the_faces_box() {
        let (v, f, n) = uv_sphere(4, 6);
        let (nodes, order, reach) = bvh_of(&v, &f);
        let mesh = Mesh::new(
            &v,
            &f,
            &n,
            MaterialId(0),
            BakedBvh::new(&nodes, &order, reach),
        );
        mesh.check(1).unwrap();
        let bound = mesh.lift_bound();
        let root = nodes[0];
        let (mut largest, mut outside) = (0.0f32, 0.0f32);
        for face in 0..f.len() {
            let [a, b, c] = mesh.triangle(face).unwrap().vertices();
            for i in 0..=8u8 {
                for j in 0..=8 - i {
                    let (b1, b2) = (f32::from(i) / 8.0, f32::from(j) / 8.0);
                    let bary = [1.0 - b1 - b2, b1, b2];
                    let p = a * bary[0] + b * b1 + c * b2;
                    for out in [1.0, -1.0] {
                        let lift = mesh.lift(face, bary, p, out);
                        largest = crate::math::max(largest, lift.length());
                        let q = p + lift;
                        let beyond = (root.min - q).max(q - root.max).max_element();
                        outside = crate::math::max(outside, beyond);
                    }
                }
            }
        }
        assert!(largest > 0.0 && largest <= bound, "{largest} {bound}");
        assert!(outside > 0.01, "{outside}");
        // A flat mesh lifts nothing.
        let flat = Mesh::new(
            &v,
            &f,
            &[],
            MaterialId(0),
            BakedBvh::new(&nodes, &order, reach),
        );
        assert_eq!(flat.lift_bound(), 0.0);
    }

    /// Every face of `(v, f)` as a triangle of `list`'s triangle list, material 0.
    fn add_faces<C: crate::Capacities>(list: &mut Scene<C>, v: &[[f32; 3]], f: &[[u16; 3]]) {
        let p = |i: u16| {
            let q = v[usize::from(i)];
            Vec3::new(q[0], q[1], q[2])
        };
        for &[a, b, c] in f {
            list.add_triangle(Triangle::try_new(p(a), p(b), p(c)).unwrap(), MaterialId(0))
                .unwrap();
        }
    }

    /// A mesh among other primitives: the triangle list (without a BVH of its
    /// own), a sphere, found as when the mesh's faces are triangles of the list
    /// (a mesh must not hide the list's triangles from any search).
    #[test]
    fn a_mesh_keeps_the_other_primitives() {
        let (v, f, _) = uv_sphere(8, 12);
        let (nodes, order, reach) = bvh_of(&v, &f);
        let mesh = [Mesh::new(
            &v,
            &f,
            &[],
            MaterialId(0),
            BakedBvh::new(&nodes, &order, reach),
        )];
        let cam = camera();
        let tri = Triangle::try_new(
            Vec3::new(-1.6, -1.0, 0.5),
            Vec3::new(1.6, -1.0, 0.5),
            Vec3::new(0.0, -0.2, 1.5),
        )
        .unwrap();
        let ball = Sphere::try_new(Vec3::new(1.1, 0.9, 0.3), 0.4).unwrap();
        let mut with: std::boxed::Box<
            Scene<crate::capacities!(spheres: 1, triangles: 600, materials: 1, lights: 1)>,
        > = std::boxed::Box::new(Scene::new(cam));
        let mut list: std::boxed::Box<
            Scene<crate::capacities!(spheres: 1, triangles: 600, materials: 1, lights: 1)>,
        > = std::boxed::Box::new(Scene::new(cam));
        for s in [&mut with, &mut list] {
            s.set_ambient(Color::splat(0.05)).unwrap();
            s.add_material(Material::matte(Color::new(0.9, 0.3, 0.2)))
                .unwrap();
            s.add_light(Light::point(Vec3::new(-2.0, 3.0, 4.0), Color::WHITE, 30.0).unwrap())
                .unwrap();
            s.add_sphere(ball, MaterialId(0)).unwrap();
            s.add_triangle(tri, MaterialId(0)).unwrap();
        }
        add_faces(&mut list, &v, &f);
        let meshed = render(&with.view().with_meshes(&mesh).unwrap());
        assert_eq!(meshed, render(&list.view()));
        // The triangle and the sphere are in the picture.
        let only_mesh = render(&scene(false).view().with_meshes(&mesh).unwrap());
        assert!(
            meshed
                .iter()
                .zip(&only_mesh)
                .filter(|(a, b)| a != b)
                .count()
                > 50
        );
    }

    /// Meshes that do not fit are refused: too many, a vertex index or a
    /// material out of range, normals not one per vertex or zero, a hierarchy of
    /// other faces.
    /// What `NORMAL_LENGTH_ULPS` allows is what normalising in `f32` leaves:
    /// directions over every octant and a wide range of lengths, normalised by
    /// the core's `Vec3::normalize_or` (as a firmware building a mesh would),
    /// keep their squared length (`f32` arithmetic, as the check does) within
    /// the bound; the largest seen is printed.
    #[test]
    fn normals_normalised_in_f32_pass_the_length_rule() {
        let mut state = 0x2545_f491_u32;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state as f32 / u32::MAX as f32 * 2.0 - 1.0
        };
        let mut worst = 0.0f32;
        for i in 0..200_000 {
            let scale = [1e-30, 1e-3, 1.0, 7.0, 1e5, 1e30][i % 6];
            let p = Vec3::new(next(), next(), next()) * scale;
            let Some(n) = p.try_normalize() else { continue };
            worst = crate::math::max(worst, (n.length_squared() - 1.0).abs() / f32::EPSILON);
        }
        std::println!("largest |len^2 - 1|: {worst} ulps (bound {NORMAL_LENGTH_ULPS})");
        assert!(worst <= NORMAL_LENGTH_ULPS as f32, "{worst}");
    }

    #[test]
    fn defective_meshes_are_refused() {
        let (v, f, n) = uv_sphere(4, 6);
        let (nodes, order, reach) = bvh_of(&v, &f);
        let bvh = BakedBvh::new(&nodes, &order, reach);
        let s = scene(false);
        let ok = Mesh::new(&v, &f, &n, MaterialId(0), bvh);
        assert!(s.view().with_meshes(&[ok]).is_ok());
        let many = [ok; MAX_MESHES + 1];
        assert_eq!(
            s.view().with_meshes(&many).err(),
            Some(Error::CapacityExceeded {
                list: crate::error::List::Meshes,
                capacity: MAX_MESHES
            })
        );
        assert!(s.view().with_meshes(&many[..MAX_MESHES]).is_ok());
        let bad = Some(Error::BadMesh);
        let mut g = f.clone();
        g[3][1] = 999;
        assert_eq!(
            s.view()
                .with_meshes(&[Mesh::new(&v, &g, &n, MaterialId(0), bvh)])
                .err(),
            bad
        );
        assert_eq!(
            s.view()
                .with_meshes(&[Mesh::new(&v, &f, &n, MaterialId(1), bvh)])
                .err(),
            Some(Error::MaterialOutOfRange { id: 1, count: 1 })
        );
        assert_eq!(
            s.view()
                .with_meshes(&[Mesh::new(&v, &f, &n[1..], MaterialId(0), bvh)])
                .err(),
            bad
        );
        for wrong in [
            [0.0; 3],
            [f32::NAN, 0.0, 1.0],
            [0.0, 0.0, 1.01],
            [0.0, 0.5, 0.0],
        ] {
            let mut m = n.clone();
            m[2] = wrong;
            assert_eq!(
                s.view()
                    .with_meshes(&[Mesh::new(&v, &f, &m, MaterialId(0), bvh)])
                    .err(),
                bad
            );
        }
        // A normal further from unit length than f32 normalising leaves: 16
        // ulps too long (squared), or 1.0009 times a unit normal.
        let mut m = n.clone();
        m[2] = [0.0, 0.0, 1.0 + 8.0 * f32::EPSILON];
        m[3] = [0.0, 1.0, 0.0];
        let once = [Mesh::new(&v, &f, &m[..], MaterialId(0), bvh)];
        assert_eq!(s.view().with_meshes(&once).err(), bad);
        m[2] = [0.0, 0.0, 1.0];
        assert!(
            s.view()
                .with_meshes(&[Mesh::new(&v, &f, &m, MaterialId(0), bvh)])
                .is_ok()
        );
        m[3] = n[3].map(|x| x * 1.0009);
        let once = [Mesh::new(&v, &f, &m[..], MaterialId(0), bvh)];
        assert_eq!(s.view().with_meshes(&once).err(), bad);
        // Meshes given twice.
        let once = [ok];
        let v1 = s.view().with_meshes(&once).unwrap();
        assert_eq!(v1.with_meshes(&once).err(), bad);
        // Faces swapped: the hierarchy's leaves no longer hold their faces.
        let mut h = f.clone();
        h.swap(0, f.len() - 1);
        assert_eq!(
            s.view()
                .with_meshes(&[Mesh::new(&v, &h, &n, MaterialId(0), bvh)])
                .err(),
            Some(Error::BvhMismatch)
        );
    }
}
