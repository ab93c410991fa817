//! `bvh-report`: where a BVH starts to pay. Renders a triangle mesh on a floor
//! (the first N faces of a unit icosphere subdivided 1 to 4 times, one light,
//! centre sampling, depth 3) with the flat triangle list and with a BVH, side by
//! side in one run (the median of 7 alternating renders each, one thread), and
//! counts the BVH's node tests per search; prints a markdown table.
//!
//! ```sh
//! cargo run -p tessera-tests --release --bin bvh-report
//! ```
//!
//! For instruction counts instead of times, render one setting under callgrind
//! (`--one FACES flat|bvh|none WIDTH`; `none` builds the scene and renders
//! nothing, the cost to subtract):
//!
//! ```sh
//! cargo build -p tessera-tests --release --bin bvh-report
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null \
//!     target/release/bvh-report --one 1280 bvh 160
//! ```
//!
//! and the built-in teapot the same way: `--teapot flat|bvh|none WIDTH` (its faces
//! in the flat triangle list, or as built in: smooth, through its BVH).

use std::time::Instant;
use tessera_core::testing::ViewHooks as _;
use tessera_core::{
    Camera, Color, RenderSettings, Renderer, Sampler, Scene, SceneView, Vec3, Viewport, bvh::Bvh,
    geometry::Plane, geometry::Triangle, light::Light, material::Material,
};
use tessera_tests::extremes::icosphere;

/// The mesh sizes measured: faces of the icosphere of `level`, the first `n`.
const SIZES: [(u32, usize); 10] = [
    (1, 20),
    (1, 40),
    (1, 60),
    (1, 80),
    (2, 100),
    (2, 128),
    (2, 200),
    (2, 320),
    (3, 1280),
    (4, 5120),
];

/// Renders per setting and mode.
const RUNS: usize = 7;

type MeshScene =
    Scene<tessera_core::capacities!(planes: 1, triangles: 8192, materials: 2, lights: 1)>;
type MeshBvh = Bvh<16384, 8192>;

/// The first `faces` faces of the icosphere subdivided `level` times, centred at
/// (0, 1, 0), on a floor.
fn scene(level: u32, faces: usize) -> Box<MeshScene> {
    let cam = Camera::look_at(
        Vec3::new(0.0, 2.5, 6.0),
        Vec3::new(0.0, 1.0, 0.0),
        Vec3::Y,
        0.1,
        100.0,
    )
    .expect("camera");
    let mut s = Box::new(MeshScene::new(cam));
    s.set_ambient(Color::splat(0.1)).expect("ambient");
    s.set_background(Color::new(0.6, 0.7, 0.9))
        .expect("background");
    let floor = s
        .add_material(Material::matte(Color::splat(0.8)))
        .expect("material");
    let gem = s
        .add_material(
            Material::matte(Color::new(0.9, 0.3, 0.2))
                .with_specular(0.5, 32.0)
                .expect("specular"),
        )
        .expect("material");
    s.add_light(Light::point(Vec3::new(4.0, 6.0, 5.0), Color::WHITE, 60.0).expect("light"))
        .expect("light");
    s.add_plane(Plane::try_new(Vec3::ZERO, Vec3::Y).expect("plane"), floor)
        .expect("plane");
    let (v, f) = icosphere(level);
    let p = |i: usize| Vec3::new(v[i].x as f32, v[i].y as f32 + 1.0, v[i].z as f32);
    for &[a, b, c] in f.iter().take(faces) {
        let t = Triangle::try_new(p(a), p(b), p(c)).expect("face");
        s.add_triangle(t, gem).expect("capacity");
    }
    s
}

fn renderer(s: &MeshScene, width: u16) -> Renderer {
    let settings = RenderSettings {
        sampler: Sampler::Centre,
        max_depth: 3,
        seed: 1,
        encoding: tessera_core::Encoding::Linear,
    };
    Renderer::try_new(s.camera(), Viewport::new(width, width * 3 / 4), settings).expect("frame")
}

fn render(view: &SceneView<'_>, renderer: &Renderer) -> image::RgbImage {
    tessera_host::render_tiles::<16>(view, renderer, None).expect("render")
}

/// `frame` rendered through `flat` and through `bvh`, which must give the same
/// image (`Err` otherwise), [`RUNS`] times each alternating: the median ns per
/// pixel of each and the BVH's node tests per search.
fn side_by_side(
    flat: &SceneView<'_>,
    bvh: &SceneView<'_>,
    renderer: &Renderer,
) -> Result<(f64, f64, f64), ()> {
    if render(flat, renderer) != render(bvh, renderer) {
        return Err(());
    }
    let vp = renderer.viewport();
    let px = f64::from(vp.width) * f64::from(vp.height);
    let (mut a, mut b) = (Vec::new(), Vec::new());
    let (n0, s0) = tessera_core::testing::visits();
    for _ in 0..RUNS {
        let t = Instant::now();
        render(flat, renderer);
        a.push(t.elapsed().as_nanos() as f64 / px);
        let t = Instant::now();
        render(bvh, renderer);
        b.push(t.elapsed().as_nanos() as f64 / px);
    }
    let (n1, s1) = tessera_core::testing::visits();
    let tests = (n1 - n0) as f64 / (s1 - s0).max(1) as f64;
    Ok((median(a), median(b), tests))
}

/// The median of `xs`.
fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs[xs.len() / 2]
}

/// `--one FACES MODE WIDTH`: one render, for callgrind.
fn one(args: &[String]) -> Result<(), String> {
    let usage = || "usage: bvh-report [--one FACES flat|bvh|none WIDTH]".to_string();
    let [faces, mode, width] = args else {
        return Err(usage());
    };
    let faces: usize = faces.parse().map_err(|_| usage())?;
    let width: u16 = width.parse().map_err(|_| usage())?;
    let &(level, n) = SIZES
        .iter()
        .find(|&&(_, n)| n == faces)
        .ok_or_else(|| format!("FACES is one of {:?}", SIZES.map(|s| s.1)))?;
    let s = scene(level, n);
    let f = renderer(&s, width);
    let mut bvh = Box::new(MeshBvh::new());
    bvh.build(s.view().triangles()).map_err(|e| e.to_string())?;
    let img = match mode.as_str() {
        "flat" => render(&s.view(), &f),
        "bvh" => render(
            &s.view().with_bvh_always(&bvh).map_err(|e| e.to_string())?,
            &f,
        ),
        "none" => return Ok(()),
        _ => return Err(usage()),
    };
    println!("{}x{}", img.width(), img.height());
    Ok(())
}

fn main() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("--one") {
        return one(&args[1..]);
    }
    if args.first().map(String::as_str) == Some("--teapot") {
        return teapot_one(&args[1..]);
    }
    let width = 160;
    println!("# Where a BVH pays\n");
    println!(
        "Generated by `cargo run -p tessera-tests --release --bin bvh-report`: the first N \
         faces of a unit icosphere on a floor, one light, centre sampling, depth 3, \
         {width}x{}, one thread; median of {RUNS} renders each, flat and BVH alternating. \
         Node tests per search: every search through the BVH (camera, shadow and bounce \
         rays; rays that miss the mesh test only the root).\n",
        width * 3 / 4
    );
    println!(
        "| triangles | flat ns/px | BVH ns/px | BVH / flat | BVH nodes | node tests per search |"
    );
    println!("|---|---|---|---|---|---|");
    for (level, n) in SIZES {
        let s = scene(level, n);
        let f = renderer(&s, width);
        let mut bvh = Box::new(MeshBvh::new());
        bvh.build(s.view().triangles()).map_err(|e| e.to_string())?;
        let flat_view = s.view();
        let bvh_view = s.view().with_bvh_always(&bvh).map_err(|e| e.to_string())?;
        let (flat, with, tests) = side_by_side(&flat_view, &bvh_view, &f)
            .map_err(|()| format!("{n} triangles: the BVH changed the image"))?;
        println!(
            "| {n} | {flat:.0} | {with:.0} | {:.2} | {} | {tests:.1} |",
            with / flat,
            bvh.node_count(),
        );
    }
    spheres()?;
    teapot()
}

type BallScene =
    Scene<tessera_core::capacities!(spheres: 1024, planes: 1, materials: 2, lights: 1)>;
type BallBvh = Bvh<2048, 1024>;

/// `n` small spheres on a square grid on a floor, one light.
fn balls(n: usize) -> Box<BallScene> {
    let cam = Camera::look_at(
        Vec3::new(0.0, 5.0, 9.0),
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::Y,
        0.1,
        100.0,
    )
    .expect("camera");
    let mut s = Box::new(BallScene::new(cam));
    s.set_ambient(Color::splat(0.1)).expect("ambient");
    let floor = s
        .add_material(Material::matte(Color::splat(0.7)))
        .expect("material");
    let red = s
        .add_material(Material::matte(Color::new(0.8, 0.2, 0.1)))
        .expect("material");
    s.add_plane(Plane::try_new(Vec3::ZERO, Vec3::Y).expect("plane"), floor)
        .expect("plane");
    let side = (n as f64).sqrt().ceil() as usize;
    let step = 8.0 / side as f32;
    for i in 0..n {
        let (x, z) = ((i % side) as f32, (i / side) as f32);
        let c = Vec3::new(-4.0 + (x + 0.5) * step, 0.4 * step, -4.0 + (z + 0.5) * step);
        let ball = tessera_core::geometry::Sphere::try_new(c, 0.4 * step).expect("sphere");
        s.add_sphere(ball, red).expect("sphere");
    }
    s.add_light(Light::point(Vec3::new(2.0, 8.0, 4.0), Color::WHITE, 60.0).expect("light"))
        .expect("light");
    s
}

/// Where a BVH over spheres pays: the same side-by-side measurement.
fn spheres() -> Result<(), String> {
    let width: u16 = 160;
    println!(
        "\n## Spheres\n\nN spheres on a grid on a floor, one light, centre, depth 3, \
         {width}x{}, one thread; median of {RUNS} renders each, flat and BVH alternating.\n",
        width * 3 / 4
    );
    println!("| spheres | flat ns/px | BVH ns/px | BVH / flat | node tests per search |");
    println!("|---|---|---|---|---|");
    for n in [8, 16, 32, 64, 128, 256, 1024] {
        let s = balls(n);
        let settings = RenderSettings {
            sampler: Sampler::Centre,
            max_depth: 3,
            seed: 1,
            encoding: tessera_core::Encoding::Linear,
        };
        let f = Renderer::try_new(s.camera(), Viewport::new(width, width * 3 / 4), settings)
            .map_err(|e| e.to_string())?;
        let mut bvh = Box::new(BallBvh::new());
        bvh.build(s.view().spheres()).map_err(|e| e.to_string())?;
        let flat_view = s.view();
        let bvh_view = s
            .view()
            .with_sphere_bvh_always(&bvh)
            .map_err(|e| e.to_string())?;
        let (flat, with, tests) = side_by_side(&flat_view, &bvh_view, &f)
            .map_err(|()| format!("{n} spheres: the BVH changed the image"))?;
        println!(
            "| {n} | {flat:.0} | {with:.0} | {:.2} | {tests:.1} |",
            with / flat
        );
    }
    Ok(())
}

type TeapotList =
    Scene<tessera_core::capacities!(planes: 1, triangles: 2048, materials: 2, lights: 2)>;

/// The built-in teapot's scene with its faces as a triangle list (`faces`), or
/// without them.
fn teapot_list(view: &SceneView<'_>, cam: &Camera, faces: bool) -> Result<Box<TeapotList>, String> {
    let e = |e: tessera_core::Error| e.to_string();
    let mut s = Box::new(TeapotList::new(*cam));
    s.set_ambient(view.ambient()).map_err(e)?;
    s.set_background(view.background()).map_err(e)?;
    for m in view.materials() {
        s.add_material(*m).map_err(e)?;
    }
    for l in view.lights() {
        s.add_light(*l).map_err(e)?;
    }
    for p in view.planes() {
        s.add_plane(p.geometry, p.material).map_err(e)?;
    }
    if !faces {
        return Ok(s);
    }
    let mesh = view.meshes().first().ok_or("the teapot has no mesh")?;
    let v = |i: u16| {
        let [x, y, z] = mesh.vertices()[usize::from(i)];
        Vec3::new(x, y, z)
    };
    for &[a, b, c] in mesh.faces() {
        let t = Triangle::try_new(v(a), v(b), v(c)).map_err(e)?;
        s.add_triangle(t, mesh.material()).map_err(e)?;
    }
    Ok(s)
}

/// `--teapot flat|bvh|none WIDTH`: one render of the built-in teapot with its faces
/// in the flat list or as built in (through its BVH), for callgrind.
fn teapot_one(args: &[String]) -> Result<(), String> {
    let usage = || "usage: bvh-report [--teapot flat|bvh|none WIDTH]".to_string();
    let [mode, width] = args else {
        return Err(usage());
    };
    let width: u16 = width.parse().map_err(|_| usage())?;
    let b = tessera_core::builtin::Builtin::Teapot;
    let vp = Viewport::new(width, width * 3 / 4);
    b.with_scene(|view, cam| -> Result<(), String> {
        let renderer = Renderer::try_new(cam, vp, b.settings()).map_err(|e| e.to_string())?;
        let list = teapot_list(view, cam, true)?;
        let img = match mode.as_str() {
            "flat" => render(&list.view(), &renderer),
            "bvh" => render(view, &renderer),
            "none" => return Ok(()),
            _ => return Err(usage()),
        };
        println!("{}x{}", img.width(), img.height());
        Ok(())
    })
    .map_err(|e| e.to_string())?
}

/// The built-in teapot at 800x600 (centre, its own depth 0, one thread): its
/// 1,088 faces as the flat triangle list, as a flat-shaded mesh through its BVH
/// (the same image), and the scene as built in (smooth).
fn teapot() -> Result<(), String> {
    let b = tessera_core::builtin::Builtin::Teapot;
    let vp = Viewport::new(800, 600);
    let px = 800.0 * 600.0;
    b.with_scene(|view, cam| -> Result<(), String> {
        let renderer = Renderer::try_new(cam, vp, b.settings()).map_err(|e| e.to_string())?;
        let list = teapot_list(view, cam, true)?;
        let mut bvh = Box::new(Bvh::<4096, 2048>::new());
        bvh.build(list.view().triangles())
            .map_err(|e| e.to_string())?;
        let mesh = view.meshes()[0];
        let flat_mesh = [tessera_core::mesh::Mesh::new(
            mesh.vertices(),
            mesh.faces(),
            &[],
            mesh.material(),
            tessera_core::bvh::BakedBvh::new(bvh.nodes(), bvh.order(), bvh.reach()),
        )];
        let lists = list.view();
        let no_triangles = teapot_list(view, cam, false)?;
        let flat_meshed = no_triangles
            .view()
            .with_meshes(&flat_mesh)
            .map_err(|e| e.to_string())?;
        if render(&lists, &renderer) != render(&flat_meshed, &renderer) {
            return Err("the teapot: the mesh changed the flat list's image".into());
        }
        println!(
            "\n## The built-in teapot\n\n800x600, centre, depth 0, one thread; the flat \
             list rendered once, the others the median of 3. Node tests per search as \
             above.\n"
        );
        println!("| teapot | ns/px | node tests per search |");
        println!("|---|---|---|");
        for (name, v, runs) in [
            ("1,088 faces as the flat triangle list", &lists, 1),
            ("flat-shaded mesh through its BVH", &flat_meshed, 3),
            ("as built in: smooth mesh, baked BVH", view, 3),
        ] {
            let (n0, s0) = tessera_core::testing::visits();
            let mut t = Vec::new();
            for _ in 0..runs {
                let start = Instant::now();
                render(v, &renderer);
                t.push(start.elapsed().as_nanos() as f64 / px);
            }
            let (n1, s1) = tessera_core::testing::visits();
            let tests = if s1 > s0 {
                format!("{:.1}", (n1 - n0) as f64 / (s1 - s0) as f64)
            } else {
                "-".to_string()
            };
            println!("| {name} | {:.0} | {tests} |", median(t));
        }
        Ok(())
    })
    .map_err(|e| e.to_string())?
}
