//! The view frustum (rays start on the near plane, nothing beyond the far plane is
//! seen) and "model only what the scene requires" (rays that cannot change a pixel
//! are never cast).

use tessera_core::builtin::Builtin;
use tessera_core::{
    Camera, Color, RenderSettings, Renderer, Scene, Vec3, Viewport, geometry::Sphere,
    material::Material, trace::RayCount,
};

const BG: Color = Color::new(0.0, 0.0, 1.0);

/// A red sphere of radius 0.5 at distance `d` straight ahead of a camera with near
/// 1 and far 10; returns the centre pixel.
fn centre_pixel_with_sphere_at(d: f32) -> tessera_core::color::Rgb8 {
    let cam = Camera::try_new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 60.0, 1.0, 10.0).unwrap();
    let mut s: Scene<tessera_core::capacities!(spheres: 1, materials: 1)> = Scene::new(cam);
    s.set_ambient(Color::WHITE).unwrap();
    s.set_background(BG).unwrap();
    let red = s
        .add_material(Material::matte(Color::new(1.0, 0.0, 0.0)))
        .unwrap();
    s.add_sphere(Sphere::try_new(Vec3::new(0.0, 0.0, -d), 0.5).unwrap(), red)
        .unwrap();
    let renderer = s
        .renderer(Viewport::new(9, 9), RenderSettings::default())
        .unwrap();
    renderer.pixel_color(&s.view(), 4, 4, &mut ()).to_rgb8()
}

#[test]
fn only_what_lies_between_near_and_far_is_seen() {
    let red = tessera_core::color::Rgb8::new(255, 0, 0);
    let blue = tessera_core::color::Rgb8::new(0, 0, 255);
    assert_eq!(centre_pixel_with_sphere_at(5.0), red);
    // Front surface at 9.9: inside the frustum.
    assert_eq!(centre_pixel_with_sphere_at(10.4), red);
    // Front surface at 10.1: beyond the far plane.
    assert_eq!(centre_pixel_with_sphere_at(10.6), blue);
    // Entirely between the camera and the near plane (surface at 0.2..0.8 ahead).
    assert_eq!(centre_pixel_with_sphere_at(0.3), blue);
    // Straddling the near plane: the ray starts inside and sees the far side.
    assert_eq!(centre_pixel_with_sphere_at(1.2), red);
}

fn count(b: Builtin, settings: RenderSettings) -> RayCount {
    b.with_scene(|view, cam| {
        let renderer = Renderer::try_new(cam, Viewport::new(40, 30), settings).unwrap();
        let mut c = RayCount::default();
        for y in 0..30 {
            for x in 0..40 {
                let _ = renderer.pixel_color(view, x, y, &mut c);
            }
        }
        c
    })
    .unwrap()
}

#[test]
fn rays_that_cannot_change_a_pixel_are_never_cast() {
    let deep = |b: Builtin| RenderSettings {
        max_depth: 8,
        ..b.settings()
    };
    // No mirror, no glass: no secondary ray at any depth.
    let c = count(Builtin::ChapterDirect, deep(Builtin::ChapterDirect));
    assert_eq!(c.primary, 1200);
    assert_eq!(c.secondary, 0);
    assert!(c.shadow > 0);
    // No light: no shadow ray.
    let c = count(Builtin::Interference, deep(Builtin::Interference));
    assert_eq!((c.primary, c.secondary, c.shadow), (1200, 0, 0));
    // Mirrors at depth 0: none either.
    let c = count(
        Builtin::ChapterReflect,
        RenderSettings {
            max_depth: 0,
            ..Builtin::ChapterReflect.settings()
        },
    );
    assert_eq!(c.secondary, 0);
    // Depth 1: exactly one reflected ray per primary ray that hits a mirror sphere,
    // fewer than the primary rays.
    let c = count(Builtin::ChapterReflect, Builtin::ChapterReflect.settings());
    assert!(c.secondary > 0 && c.secondary < c.primary, "{c:?}");
}

#[test]
fn unlit_materials_cast_no_shadow_rays() {
    // diffuse 0, specular 0: a light cannot change the colour, so no shadow ray.
    let s = tessera_tests::inside_sphere(1.0, 5.0, 0.0, Color::WHITE).unwrap();
    let renderer = s
        .renderer(Viewport::new(8, 8), RenderSettings::default())
        .unwrap();
    let mut c = RayCount::default();
    for y in 0..8 {
        for x in 0..8 {
            let _ = renderer.pixel_color(&s.view(), x, y, &mut c);
        }
    }
    assert_eq!((c.primary, c.shadow), (64, 0));
}

#[test]
fn deepest_recursion_through_glass_stays_finite() {
    let settings = RenderSettings {
        max_depth: tessera_core::error::MAX_DEPTH,
        sampler: tessera_core::Sampler::Stratified(2),
        seed: 3,
        encoding: tessera_core::Encoding::Linear,
    };
    let c = count(Builtin::Showcase, settings);
    assert!(c.secondary > c.primary, "{c:?}");
    Builtin::Showcase
        .with_scene(|view, cam| {
            let renderer = Renderer::try_new(cam, Viewport::new(40, 30), settings).unwrap();
            for y in 0..30 {
                for x in 0..40 {
                    assert!(renderer.pixel_color(view, x, y, &mut ()).is_finite());
                }
            }
        })
        .unwrap();
}
