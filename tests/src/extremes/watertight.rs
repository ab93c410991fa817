//! Case 3: watertightness of a non-planar fan and of a closed icosphere, each
//! triangle on its own and through a scene's BVH (`Bvh`: its grown node boxes and
//! its traversal must lose no ray the triangles hit).

use super::{INF, Rng, V3, V3Ext, exact_ray, ray_towards, show};
use tessera_core::testing::Shape;
use tessera_core::testing::ViewHooks as _;
use tessera_core::{
    Camera, Color, Scene, SceneView, Vec3, bvh::Bvh, geometry::Triangle, material::Material,
    trace::Ray,
};

/// Figures of one watertightness configuration.
#[derive(Clone, Debug, Default)]
pub struct Watertight {
    /// What was shot at.
    pub name: String,
    /// Triangles in the mesh.
    pub triangles: usize,
    /// Rays cast.
    pub rays: usize,
    /// Rays that hit no triangle (with `intersect` or `occluded`) although they must.
    pub leaks: usize,
}

/// The scene a mesh is put in to be searched through a BVH.
type MeshScene = Scene<tessera_core::capacities!(triangles: 2048, materials: 1)>;
/// Its BVH.
type MeshBvh = Bvh<4096, 2048>;

/// The mesh as the triangles of a scene, and their BVH.
fn through_bvh(mesh: &[Triangle]) -> (Box<MeshScene>, Box<MeshBvh>) {
    let cam =
        Camera::look_at(Vec3::new(0.0, 0.0, 1.0), Vec3::ZERO, Vec3::Y, 0.1, 10.0).expect("camera");
    let mut scene = Box::new(MeshScene::new(cam));
    let m = scene
        .add_material(Material::matte(Color::WHITE))
        .expect("material");
    for t in mesh {
        scene.add_triangle(*t, m).expect("capacity");
    }
    let mut bvh = Box::new(MeshBvh::new());
    bvh.build(scene.view().triangles()).expect("bvh");
    (scene, bvh)
}

/// A leak: no triangle reports a hit, with `intersect` or `occluded` one by one,
/// or with the scene's search through the BVH (`view`).
fn leaks(mesh: &[Triangle], view: &SceneView<'_>, ray: &Ray) -> bool {
    !mesh.iter().any(|t| t.intersect(ray, INF).is_some())
        || !mesh.iter().any(|t| t.occluded(ray, INF))
        || tessera_core::trace::first_hit(view, ray, INF).is_none()
}

/// Case 3, fans: a non-planar fan of 7 triangles around `center` (ring radius about
/// `radius`), rays from random directions (not grazing) aimed at the shared centre
/// vertex and at points of the shared edges; every ray must hit the fan.
#[must_use]
pub fn fan(center: Vec3, radius: f64, rays_per_target: usize) -> Watertight {
    let mut rng = Rng::new(0xfa17 ^ u64::from(center.x.to_bits()));
    let nf = V3::new(0.2, -0.3, 0.93).normalize();
    let (e1, e2) = nf.basis();
    let c = V3::of(center);
    let ring: Vec<Vec3> = (0..7)
        .map(|i| {
            let th = i as f64 * std::f64::consts::TAU / 7.0 + rng.range(-0.3, 0.3);
            let r = radius * rng.range(0.6, 1.4);
            (c + e1 * (r * th.cos()) + e2 * (r * th.sin()) + nf * (radius * rng.range(-0.3, 0.3)))
                .f32()
        })
        .collect();
    let mesh: Vec<Triangle> = (0..7)
        .map(|i| Triangle::try_new(center, ring[i], ring[(i + 1) % 7]).expect("fan triangle"))
        .collect();
    // Each target with the triangles around it: the ray must cross all of them the
    // same way (transversally), else it may just touch a ridge of the non-planar fan.
    let normals: Vec<V3> = mesh
        .iter()
        .map(|t| {
            let [a, b, d] = t.vertices().map(V3::of);
            (b - a).cross(d - a).normalize()
        })
        .collect();
    let (scene, bvh) = through_bvh(&mesh);
    let view = scene.view().with_bvh_always(&bvh).expect("the mesh's BVH");
    let mut targets = vec![(c, normals.clone())];
    for (i, v) in ring.iter().enumerate() {
        let around = vec![normals[i], normals[(i + 6) % 7]];
        for l in [0.1, 0.25, 0.5, 0.75, 0.9] {
            targets.push((c + (V3::of(*v) - c) * l, around.clone()));
        }
    }
    let mut out = Watertight {
        name: format!("fan of 7 at {}, radius {radius}", show(center)),
        triangles: mesh.len(),
        ..Watertight::default()
    };
    for (target, around) in targets {
        for _ in 0..rays_per_target {
            let mut v = rng.dir();
            while !(around.iter().all(|n| v.dot(*n) > 0.05)
                || around.iter().all(|n| v.dot(*n) < -0.05))
            {
                v = rng.dir();
            }
            let o = (target + v * (radius * rng.range(0.5, 20.0))).f32();
            let Some(ray) = ray_towards(o, target) else {
                continue;
            };
            out.rays += 1;
            out.leaks += usize::from(leaks(&mesh, &view, &ray));
        }
    }
    out
}

/// The unit icosphere subdivided `level` times: vertices and outward-wound faces.
#[must_use]
pub fn icosphere(level: u32) -> (Vec<V3>, Vec<[usize; 3]>) {
    let g = (1.0 + 5f64.sqrt()) / 2.0;
    let mut v: Vec<V3> = [
        (-1.0, g, 0.0),
        (1.0, g, 0.0),
        (-1.0, -g, 0.0),
        (1.0, -g, 0.0),
        (0.0, -1.0, g),
        (0.0, 1.0, g),
        (0.0, -1.0, -g),
        (0.0, 1.0, -g),
        (g, 0.0, -1.0),
        (g, 0.0, 1.0),
        (-g, 0.0, -1.0),
        (-g, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| V3::new(x, y, z).normalize())
    .collect();
    let mut f: Vec<[usize; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::with_capacity(f.len() * 4);
        for [a, b, c] in f {
            let mut m = |i: usize, j: usize| {
                *mid.entry((i.min(j), i.max(j))).or_insert_with(|| {
                    v.push((v[i] + v[j]).normalize());
                    v.len() - 1
                })
            };
            let (ab, bc, ca) = (m(a, b), m(b, c), m(c, a));
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        f = next;
    }
    (v, f)
}

/// Case 3, closed mesh: an icosphere (`level` 2: 320 triangles) of `radius` around
/// `center`, rays from inside aimed exactly at every vertex, at every edge midpoint
/// and every face centroid, plus `random` random directions; from the centre and from
/// off-centre origins. Every ray must hit the mesh.
#[must_use]
pub fn icosphere_leaks(center: Vec3, radius: f64, level: u32, random: usize) -> Watertight {
    let (v, faces) = icosphere(level);
    let c = V3::of(center);
    let verts: Vec<Vec3> = v.iter().map(|&p| (c + p * radius).f32()).collect();
    let mesh: Vec<Triangle> = faces
        .iter()
        .map(|&[a, b, d]| Triangle::try_new(verts[a], verts[b], verts[d]).expect("face"))
        .collect();
    let (scene, bvh) = through_bvh(&mesh);
    let view = scene.view().with_bvh_always(&bvh).expect("the mesh's BVH");
    let mut targets: Vec<V3> = verts.iter().map(|&p| V3::of(p)).collect();
    for &[a, b, d] in &faces {
        let (pa, pb, pd) = (V3::of(verts[a]), V3::of(verts[b]), V3::of(verts[d]));
        targets.push((pa + pb) * 0.5);
        targets.push((pa + pb + pd) * (1.0 / 3.0));
    }
    let mut rng = Rng::new(0x1c05 ^ u64::from(center.z.to_bits()));
    let mut out = Watertight {
        name: format!(
            "icosphere of {} at {}, radius {radius}",
            mesh.len(),
            show(center)
        ),
        triangles: mesh.len(),
        ..Watertight::default()
    };
    let origins = [
        center,
        (c + V3::new(0.3, -0.2, 0.1) * radius).f32(),
        (c + V3::new(-0.1, 0.5, -0.45) * radius).f32(),
        (c + rng.dir() * (0.8 * radius)).f32(),
    ];
    for o in origins {
        let rays = targets
            .iter()
            .filter_map(|&t| ray_towards(o, t))
            .chain((0..random).map(|_| exact_ray(o, rng.dir().f32())));
        for ray in rays {
            out.rays += 1;
            out.leaks += usize::from(leaks(&mesh, &view, &ray));
        }
    }
    out
}
