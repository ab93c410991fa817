//! Criterion benchmarks of the hot paths, so regressions show:
//! `cargo bench -p tessera-core` (add `--features fast-math` for the other backend).

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use tessera_core::builtin::{self, Builtin};
use tessera_core::testing::Shape;
use tessera_core::{
    RenderSettings, Renderer, Tile, TileCoord, Vec3, Viewport, camera::CameraBasis, geometry::Aabb,
    geometry::Plane, geometry::Sphere, geometry::Triangle, trace::Ray,
};

fn rays(n: usize) -> Vec<Ray> {
    // A deterministic fan of rays from (0, 0, 5) towards the unit square at z = 0.
    (0..n)
        .map(|i| {
            let a = i as f32 * 0.618_034;
            let target = Vec3::new((a % 1.0) * 2.0 - 1.0, ((a * 7.0) % 1.0) * 2.0 - 1.0, 0.0);
            let o = Vec3::new(0.0, 0.0, 5.0);
            Ray::new(o, target - o)
        })
        .collect::<Result<_, _>>()
        .expect("every target is off the origin")
}

fn primary_rays(c: &mut Criterion) {
    let scene = builtin::chapter_reflect().unwrap();
    let basis = CameraBasis::try_new(scene.camera(), Viewport::new(240, 240)).unwrap();
    c.bench_function("primary ray (camera basis)", |b| {
        let mut x = 0.0f32;
        b.iter(|| {
            x = (x + 1.0) % 240.0;
            black_box(basis.ray(black_box(x) + 0.5, black_box(117.5)))
        })
    });
}

fn bench_shape<S: Shape>(c: &mut Criterion, name: &str, shape: &S) {
    let rs = rays(1024);
    c.bench_function(&format!("{name} intersect (1024 rays)"), |b| {
        b.iter(|| {
            rs.iter()
                .filter(|r| shape.intersect(black_box(r), f32::INFINITY).is_some())
                .count()
        })
    });
    c.bench_function(&format!("{name} occluded (1024 rays)"), |b| {
        b.iter(|| {
            rs.iter()
                .filter(|r| shape.occluded(black_box(r), 100.0))
                .count()
        })
    });
}

fn geometries(c: &mut Criterion) {
    bench_shape(c, "sphere", &Sphere::try_new(Vec3::ZERO, 0.7).unwrap());
    bench_shape(
        c,
        "plane",
        &Plane::try_new(Vec3::ZERO, Vec3::new(0.1, 0.2, 1.0)).unwrap(),
    );
    bench_shape(
        c,
        "triangle",
        &Triangle::try_new(
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -0.8, 0.1),
            Vec3::new(0.0, 1.0, -0.1),
        )
        .unwrap(),
    );
    bench_shape(
        c,
        "box",
        &Aabb::try_new(Vec3::splat(-0.6), Vec3::new(0.5, 0.7, 0.4)).unwrap(),
    );
}

fn shading(c: &mut Criterion) {
    // One camera ray through the centre of the default scene: nearest hit over the
    // lists, a shadow ray, Blinn-Phong, one reflection.
    let scene = builtin::chapter_reflect().unwrap();
    let view = scene.view();
    let basis = CameraBasis::try_new(scene.camera(), Viewport::new(240, 240)).unwrap();
    let (ray, t_far) = basis.ray(120.5, 118.5);
    c.bench_function("shade a hit (blue sphere, depth 1)", |b| {
        b.iter(|| {
            black_box(tessera_core::trace::trace(
                &view,
                black_box(ray),
                t_far,
                1,
                &mut (),
            ))
        })
    });
}

fn tiles(c: &mut Criterion) {
    for b in [Builtin::ChapterReflect, Builtin::Showcase] {
        b.with_scene(|view, cam| {
            let renderer =
                Renderer::try_new(cam, Viewport::new(240, 240), RenderSettings::default()).unwrap();
            let mut tile = Tile::<16>::new();
            c.bench_function(&format!("tile 16x16 ({}, centre)", b.name()), |bch| {
                bch.iter(|| {
                    renderer
                        .render_tile(view, black_box(TileCoord::new(7, 7)), &mut tile, &mut ())
                        .unwrap()
                })
            });
        })
        .unwrap();
    }
}

criterion_group!(benches, primary_rays, geometries, shading, tiles);
criterion_main!(benches);
