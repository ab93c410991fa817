//! Culling never changes a pixel: a tile's candidate lists (camera and shadow rays)
//! and the triangle list's hull only skip tests that could not have reported a hit.
//! Every render here is compared byte for byte with the same render with culling
//! off (`SceneView::without_culling`), on the built-in scenes (several samplers and
//! tile sizes), on every scene file of `scenes/`, on the built-in scenes scaled by
//! powers of two up to the ends of the supported range, and on random scenes built
//! through the public API (the generator's `Values::Tame`, in
//! `tessera_tests::random_scene`).

use image::RgbImage;
use proptest::prelude::*;
use std::path::Path;
use tessera_core::builtin::Builtin;
use tessera_core::testing::{BuiltinHooks as _, ViewHooks as _};
use tessera_core::{
    Camera, Color, RenderSettings, Renderer, Sampler, Scene, SceneView, Vec3, Viewport, bvh::Bvh,
    geometry::Plane, geometry::Triangle, light::Light, material::Material,
};
use tessera_host::render_tiles;
use tessera_tests::random_scene::{Values, recipe};

/// A BVH as large as the host scene's.
type TestBvh = Bvh<16384, 8192>;

/// Renders `view` with tiles of 8, 16 and 32, with culling off (tiles of 16), and,
/// when it has triangles, with its triangles through a BVH (whatever their number,
/// tiles of 8 and 16); all must be the same bytes. Returns the image.
fn same_culled_or_not(view: &SceneView<'_>, renderer: &Renderer, what: &str) -> RgbImage {
    let off = render_tiles::<16>(&view.without_culling(), renderer, None).unwrap();
    let mut renders = vec![
        (
            "tiles of 8",
            render_tiles::<8>(view, renderer, None).unwrap(),
        ),
        (
            "tiles of 16",
            render_tiles::<16>(view, renderer, None).unwrap(),
        ),
        (
            "tiles of 32",
            render_tiles::<32>(view, renderer, None).unwrap(),
        ),
    ];
    if !view.spheres().is_empty() {
        let mut bvh = Box::new(TestBvh::new());
        bvh.build(view.spheres()).unwrap();
        let with = view.without_bvh().with_sphere_bvh_always(&bvh).unwrap();
        assert!(with.uses_sphere_bvh());
        renders.push((
            "sphere BVH, tiles of 16",
            render_tiles::<16>(&with, renderer, None).unwrap(),
        ));
        if !view.triangles().is_empty() {
            let mut tris = Box::new(TestBvh::new());
            tris.build(view.triangles()).unwrap();
            let both = with.with_bvh_always(&tris).unwrap();
            renders.push((
                "sphere and triangle BVHs, tiles of 8",
                render_tiles::<8>(&both, renderer, None).unwrap(),
            ));
        }
    }
    if !view.triangles().is_empty() {
        let mut bvh = Box::new(TestBvh::new());
        bvh.build(view.triangles()).unwrap();
        let with = view.without_bvh().with_bvh_always(&bvh).unwrap();
        assert!(with.uses_bvh());
        renders.push((
            "BVH, tiles of 8",
            render_tiles::<8>(&with, renderer, None).unwrap(),
        ));
        renders.push((
            "BVH, tiles of 16",
            render_tiles::<16>(&with, renderer, None).unwrap(),
        ));
    }
    for (n, on) in renders {
        if on.as_raw() != off.as_raw() {
            let differ: Vec<_> = on
                .enumerate_pixels()
                .zip(off.pixels())
                .filter(|((_, _, a), b)| a != b)
                .map(|((x, y, a), b)| format!("({x}, {y}) culled {:?} unculled {:?}", a.0, b.0))
                .take(5)
                .collect();
            panic!("{what}, {n}: culling or the BVH changed pixels: {differ:?}");
        }
    }
    off
}

#[test]
fn builtin_scenes_render_the_same_culled_or_not() {
    // An odd size: partial edge tiles for every tile size.
    let vp = Viewport::new(77, 53);
    for &b in Builtin::ALL {
        for sampler in [
            Sampler::Centre,
            Sampler::Stratified(2),
            Sampler::Random(3),
            Sampler::Prefiltered,
            Sampler::adaptive(2),
            // Its coarse grid's three-pixel apron (the chapter's scenes).
            Sampler::sparse_spaced(4),
        ] {
            let settings = RenderSettings {
                sampler,
                seed: 11,
                ..b.settings()
            };
            b.with_scene(|view, cam| {
                let renderer = Renderer::try_new(cam, vp, settings).unwrap();
                same_culled_or_not(view, &renderer, &format!("{} {sampler:?}", b.name()));
            })
            .unwrap();
        }
    }
}

#[test]
fn scene_files_render_the_same_culled_or_not() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("scenes");
    let mut files = Vec::new();
    for dir in [root.clone(), root.join("examples")] {
        for entry in std::fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            if path.extension().is_some_and(|e| e == "toml") {
                files.push(path);
            }
        }
    }
    files.sort();
    assert!(files.len() >= 20, "{} scene files", files.len());
    for path in &files {
        let desc = tessera_host::file::load(path).unwrap();
        let scene = desc.to_core().unwrap();
        let settings = desc.settings().unwrap();
        let renderer = scene
            .lists()
            .renderer(Viewport::new(64, 48), settings)
            .unwrap();
        scene.with_view(|v| same_culled_or_not(v, &renderer, &path.display().to_string()));
    }
}

#[test]
fn scaled_scenes_render_the_same_culled_or_not() {
    let vp = Viewport::new(48, 36);
    for &b in Builtin::ALL {
        // The extremes of the supported range (see `extremes.rs`, case 12) and two
        // scales in between.
        let ks: &[i32] = if b == Builtin::Interference {
            &[-45, -20, 20, 60]
        } else {
            &[-48, -20, 20, 53]
        };
        for &k in ks {
            b.with_scaled_scene(k, |view, cam| {
                let renderer = Renderer::try_new(cam, vp, b.settings()).unwrap();
                same_culled_or_not(view, &renderer, &format!("{} scaled by 2^{k}", b.name()));
            })
            .unwrap();
        }
    }
}

proptest! {
    // 96 random scenes, each rendered four times at 40x30.
    #![proptest_config(ProptestConfig { cases: 96, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_scenes_render_the_same_culled_or_not(
        r in recipe::<tessera_core::capacities!(spheres: 6, planes: 3, triangles: 8, boxes: 4, cylinders: 3, disks: 3, materials: 4, lights: 4)>(Values::Tame)
    ) {
        let Some(scene) = r.build() else {
            return Ok(());
        };
        let renderer = scene.renderer(Viewport::new(40, 30), r.settings(5)).unwrap();
        same_culled_or_not(&scene.view(), &renderer, &format!("{r:?}"));
    }
}

/// Exact ties: the flat search keeps, among triangles hit at the same time, the
/// earliest of the list; the BVH visits them in its own order and must keep the
/// same one. Coincident copies of triangles (each copy its own colour) scattered
/// through a list of 300, seen head-on and through a mirror, with and without a
/// BVH: the same bytes.
#[test]
fn ties_between_triangles_keep_the_earliest_through_the_bvh() {
    // The mirror below the grid, then a plane through the grid itself: a triangle
    // hit at the plane's time must not replace it (the plane comes first).
    coincident(Copies::Triangles, Vec3::new(0.0, -4.0, 0.0), Vec3::Y);
    coincident(Copies::Triangles, Vec3::ZERO, Vec3::Z);
}

/// The same for spheres through their BVH: coincident copies of spheres (each copy
/// its own colour) scattered through a list of 300, seen head-on and through a
/// mirror: the earliest copy is kept, as the flat search keeps it (a mutated tie
/// rule in the sphere BVH's search changes hundreds of pixels here).
#[test]
fn ties_between_spheres_keep_the_earliest_through_the_bvh() {
    coincident(Copies::Spheres, Vec3::new(0.0, -6.0, 0.0), Vec3::Y);
}

/// What [`coincident`] scatters copies of.
#[derive(Clone, Copy, Debug)]
enum Copies {
    Triangles,
    Spheres,
}

/// A 10 x 10 grid of small shapes, some in two or three coincident copies of
/// different colours, over a mirror plane through `plane_point` with `normal`;
/// every list position of a copy is decided by a fixed scramble, so copies of
/// one shape lie far apart in the list. Rendered culled or not, with and without
/// BVHs ([`same_culled_or_not`]): the same bytes.
fn coincident(copies: Copies, plane_point: Vec3, normal: Vec3) {
    type TieScene = Scene<
        tessera_core::capacities!(spheres: 300, planes: 1, triangles: 300, materials: 8, lights: 1),
    >;
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 12.0), Vec3::ZERO, Vec3::Y, 0.1, 100.0).unwrap();
    let mut s = Box::new(TieScene::new(cam));
    let colours: Vec<_> = (0..7)
        .map(|k| {
            let c = Color::new(0.1 + 0.12 * k as f32, 0.9 - 0.1 * k as f32, 0.5);
            s.add_material(Material::matte(c)).unwrap()
        })
        .collect();
    let mirror = s
        .add_material(
            Material::matte(Color::splat(0.2))
                .with_reflectivity(0.8)
                .unwrap(),
        )
        .unwrap();
    s.add_light(Light::point(Vec3::new(2.0, 5.0, 10.0), Color::WHITE, 60.0).unwrap())
        .unwrap();
    s.add_plane(Plane::try_new(plane_point, normal).unwrap(), mirror)
        .unwrap();
    // Triangles from the grid point, spheres centred in its cell.
    let corner = match copies {
        Copies::Triangles => -5.0,
        Copies::Spheres => -4.5,
    };
    let mut items = Vec::new();
    for i in 0..100u32 {
        let (x, y) = ((i % 10) as f32 + corner, (i / 10) as f32 + corner);
        for c in 0..1 + (i % 3) {
            items.push(((i * 37 + c * 101) % 997, x, y, (i + c) as usize % 7));
        }
    }
    items.sort_by_key(|it| it.0);
    for &(_, x, y, m) in &items {
        match copies {
            Copies::Triangles => {
                let t = Triangle::try_new(
                    Vec3::new(x, y, 0.0),
                    Vec3::new(x + 0.9, y, 0.0),
                    Vec3::new(x, y + 0.9, 0.0),
                )
                .unwrap();
                s.add_triangle(t, colours[m]).unwrap();
            }
            Copies::Spheres => {
                let ball =
                    tessera_core::geometry::Sphere::try_new(Vec3::new(x, y, 0.0), 0.45).unwrap();
                s.add_sphere(ball, colours[m]).unwrap();
            }
        }
    }
    let settings = RenderSettings {
        sampler: Sampler::Centre,
        max_depth: 2,
        seed: 1,
        encoding: tessera_core::Encoding::Linear,
    };
    let renderer = s.renderer(Viewport::new(96, 72), settings).unwrap();
    let what = format!("coincident {copies:?}, plane at {plane_point:?}");
    let flat = same_culled_or_not(&s.view(), &renderer, &what);
    // The copies are seen (the background is black).
    assert!(flat.pixels().filter(|p| p.0 != [0, 0, 0]).count() > 1000);
}

/// One instance of [`instanced_scene`]: which mesh (0 smooth, 1 flat, 2 far
/// from its own origin), its rotation in degrees, its scale per axis (a
/// negative one mirrors) and where its mesh's origin goes.
type Placement = (usize, [f32; 3], [f32; 3], [f32; 3]);

/// A scene file of meshes and their instances over a floor: the icosahedron
/// smooth (its large faces lift the shadow rays' origins furthest from the
/// faces), flat, and flat baked 1,000 to the side of its origin (its
/// instances' translations cancel its coordinates); each mesh without an
/// instance drawn where it lies. `mirror`: the floor reflects (bounced rays).
/// `sun`: a directional light beside the point light.
fn instanced_scene(instances: &[Placement], mirror: bool, sun: bool) -> String {
    let ico = tessera_tests::firmware::repo_root().join("scenes/examples/icosahedron.obj");
    let ico = ico.display();
    let mut t = format!(
        r#"ambient = [0.1, 0.1, 0.1]
background = [0.5, 0.7, 0.9]
[render]
sampler = "centre"
depth = {depth}
[camera]
position = [0.0, 2.5, 7.0]
look_at = [0.0, 0.5, 0.0]
up = [0.0, 1.0, 0.0]
fovy = 60.0
near = 0.1
far = 100.0
[[material]]
name = "floor"
color = [0.7, 0.7, 0.7]
reflectivity = {reflect}
[[material]]
name = "red"
color = [0.8, 0.2, 0.1]
specular = 0.5
shininess = 30.0
[[material]]
name = "blue"
color = [0.2, 0.3, 0.9]
[[plane]]
point = [0, 0, 0]
normal = [0, 1, 0]
material = "floor"
[[sphere]]
center = [2.5, 0.6, -1.0]
radius = 0.6
material = "blue"
[[mesh]]
obj = "{ico}"
smooth = true
material = "red"
scale = 0.5
name = "smooth"
[[mesh]]
obj = "{ico}"
material = "blue"
scale = 0.4
translate = [-2.0, 0.8, 0.5]
name = "flat"
[[mesh]]
obj = "{ico}"
material = "red"
scale = 0.3
translate = [1000.0, 0.0, 0.0]
name = "far"
[[light]]
position = [-3.0, 6.0, 4.0]
intensity = 40.0
"#,
        depth = if mirror { 2 } else { 0 },
        reflect = if mirror { 0.6 } else { 0.0 },
    );
    if sun {
        t += "[[light]]\ndirection = [0.6, -1.0, -0.3]\nintensity = 0.6\n";
    }
    for (i, (mesh, rotate, scale, translate)) in instances.iter().enumerate() {
        let name = ["smooth", "flat", "far"][*mesh];
        // The far mesh's origin is 1,000 to the side of its faces.
        let translate = if *mesh == 2 {
            [translate[0] - 1000.0, translate[1], translate[2]]
        } else {
            *translate
        };
        t += &format!(
            "[[instance]]\nmesh = \"{name}\"\nname = \"i{i}\"\nrotate = {rotate:?}\nscale = {scale:?}\ntranslate = {translate:?}\n"
        );
    }
    t
}

/// Renders [`instanced_scene`] culled and not ([`same_culled_or_not`]) at 40x30.
fn instanced_same_culled_or_not(instances: &[Placement], mirror: bool, sun: bool) -> RgbImage {
    instanced_frame(instances, (mirror, sun), Viewport::new(40, 30))
}

/// [`instanced_same_culled_or_not`] in `frame`.
fn instanced_frame(
    instances: &[Placement],
    (mirror, sun): (bool, bool),
    frame: Viewport,
) -> RgbImage {
    let text = instanced_scene(instances, mirror, sun);
    let desc = tessera_host::file::parse(&text, "instances").unwrap_or_else(|e| panic!("{e}"));
    let scene = desc.to_core().unwrap();
    let renderer = scene
        .lists()
        .renderer(frame, desc.settings().unwrap())
        .unwrap();
    scene.with_view(|v| {
        assert_eq!(v.instance_count(), instances.len());
        same_culled_or_not(v, &renderer, &text)
    })
}

fn placement() -> impl Strategy<Value = Placement> {
    let scale = (0.15f32..1.2, any::<bool>()).prop_map(|(s, neg)| if neg { -s } else { s });
    (
        0..3usize,
        [-180.0f32..180.0, -180.0f32..180.0, -180.0f32..180.0],
        [scale.clone(), scale.clone(), scale],
        [-4.0f32..4.0, -0.5f32..3.0, -4.0f32..2.0],
    )
}

proptest! {
    // 48 random placements of up to 24 instances (the tiles' lists of meshes
    // and instances hold 4, 16, then 64), each scene rendered culled and not.
    #![proptest_config(ProptestConfig { cases: 48, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn random_instances_render_the_same_culled_or_not(
        instances in prop::collection::vec(placement(), 0..=24),
        mirror in any::<bool>(),
        sun in any::<bool>(),
    ) {
        instanced_same_culled_or_not(&instances, mirror, sun);
    }
}

/// More meshes and instances than a tile lists ([`tessera_core`]'s 64): the
/// tiles build no lists, and the picture is the same; at 64 they do.
#[test]
fn more_instances_than_a_tile_lists_render_the_same() {
    let grid = |n: usize| -> Vec<Placement> {
        (0..n)
            .map(|i| {
                let (x, z) = ((i % 10) as f32 * 0.8 - 3.6, (i / 10) as f32 * -0.8 + 1.0);
                (i % 3, [0.0, 15.0 * i as f32, 0.0], [0.25; 3], [x, 0.3, z])
            })
            .collect()
    };
    // 3 meshes, each instanced: 61 or 70 tops.
    for n in [61, 70] {
        let image = instanced_frame(&grid(n), (false, true), Viewport::new(120, 90));
        if std::env::var_os("TESSERA_SAVE").is_some() {
            image.save(format!("/tmp/instances-{n}.png")).unwrap();
        }
        // The instances are seen: much of the picture is neither floor nor sky.
        let red = image
            .pixels()
            .filter(|p| i32::from(p.0[0]) > i32::from(p.0[2]) + 40)
            .count();
        assert!(red > 100, "{n} instances: {red} red pixels");
    }
}
