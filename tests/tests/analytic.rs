//! Scenes whose every pixel has a known value.

use tessera_core::{Color, Encoding, RenderSettings, Sampler, Viewport};
use tessera_tests::inside_sphere;

/// The 8-bit value of `v` (linear, clamped, rounded), computed independently.
fn expected(v: f64) -> i32 {
    (v.clamp(0.0, 1.0) * 255.0).round() as i32
}

#[test]
fn camera_inside_a_lit_diffuse_sphere_sees_one_known_value() {
    let color = Color::new(0.9, 0.6, 0.3);
    let diffuse = 0.8f32;
    // Several scales: the intensity follows r^2 so that E = I / r^2 = 0.9 at each.
    for r in [1e-3f32, 0.37, 1.0, 55.0, 1e4] {
        let intensity = 0.9 * r * r;
        let scene = inside_sphere(r, intensity, diffuse, color).unwrap();
        for sampler in [Sampler::Centre, Sampler::Corner, Sampler::Stratified(2)] {
            let settings = RenderSettings {
                sampler,
                max_depth: 2,
                seed: 1,
                encoding: Encoding::Linear,
            };
            let img = tessera_host::render(
                &scene.view(),
                scene.camera(),
                Viewport::new(48, 36),
                settings,
                16,
            )
            .unwrap();
            let e = f64::from(diffuse) * 0.9;
            let want = [
                expected(e * f64::from(color.r)),
                expected(e * f64::from(color.g)),
                expected(e * f64::from(color.b)),
            ];
            for (x, y, p) in img.enumerate_pixels() {
                for (c, (&got, &want)) in p.0.iter().zip(&want).enumerate() {
                    let got = i32::from(got);
                    assert!(
                        (got - want).abs() <= 1,
                        "r = {r}, {sampler:?}, pixel ({x}, {y}) channel {c}: {got} vs {want}"
                    );
                }
            }
        }
    }
}

#[test]
fn ambient_only_scene_returns_the_material_colour() {
    // No light: only ambient * colour, so every pixel is exactly the colour.
    let mut scene = inside_sphere(2.0, 0.0, 0.0, Color::new(0.2, 0.4, 0.6)).unwrap();
    scene.set_ambient(Color::splat(0.5)).unwrap();
    // Linear: round(255 * (0.1, 0.2, 0.3)); sRGB (the default): the IEC 61966-2-1
    // curve of the same values, in f64.
    let srgb = |v: f64| (255.0 * (1.055 * v.powf(1.0 / 2.4) - 0.055)).round() as u8;
    for (encoding, want) in [
        (Encoding::Linear, [26, 51, 77]),
        (Encoding::Srgb, [srgb(0.1), srgb(0.2), srgb(0.3)]),
    ] {
        let settings = RenderSettings {
            encoding,
            ..RenderSettings::default()
        };
        let img = tessera_host::render(
            &scene.view(),
            scene.camera(),
            Viewport::new(16, 16),
            settings,
            8,
        )
        .unwrap();
        for p in img.pixels() {
            assert_eq!(p.0, want, "{encoding}");
        }
    }
    assert_eq!(RenderSettings::default().encoding, Encoding::Srgb);
}
