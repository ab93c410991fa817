//! Case 11: the edges of the supported range (the analytic sphere anywhere).

use tessera_core::{Color, RenderSettings, Vec3, Viewport};

/// The analytic scene of case 9 with its centre at `center`: a diffuse sphere of
/// radius `r` (colour `(0.9, 0.6, 0.3)`, diffuse 0.8), the camera and a light of
/// intensity `0.9 r^2` at its centre, so every pixel is `0.72 * colour`.
pub fn lit_sphere_at(
    center: Vec3,
    r: f32,
) -> Result<
    tessera_core::Scene<tessera_core::capacities!(spheres: 1, materials: 1, lights: 1)>,
    tessera_core::Error,
> {
    crate::inside_sphere_at(center, r, 0.9 * r * r, 0.8, Color::new(0.9, 0.6, 0.3))
}

/// Largest difference (LSB) of a [`lit_sphere_at`] render (32x24, pixel centres)
/// from the analytic value, and the count of non-finite pixels.
#[must_use]
pub fn lit_sphere_error(
    scene: &tessera_core::Scene<tessera_core::capacities!(spheres: 1, materials: 1, lights: 1)>,
) -> (i32, usize) {
    let want = [0.9f64, 0.6, 0.3].map(|c| (c * 0.72 * 255.0).round() as i32);
    let renderer = scene
        .renderer(Viewport::new(32, 24), RenderSettings::default())
        .expect("frame");
    let (mut worst, mut non_finite) = (0, 0);
    for y in 0..24 {
        for x in 0..32 {
            let c = renderer.pixel_color(&scene.view(), x, y, &mut ());
            non_finite += usize::from(!c.is_finite());
            let p = c.to_rgb8();
            for (got, want) in [p.r, p.g, p.b].into_iter().zip(want) {
                worst = worst.max((i32::from(got) - want).abs());
            }
        }
    }
    (worst, non_finite)
}
