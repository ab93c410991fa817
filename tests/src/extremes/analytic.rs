//! Case 9: the analytic scene (inside a lit diffuse sphere, every pixel known).

use tessera_core::{Color, RenderSettings, Sampler, Viewport};

/// Figures of case 9 at one radius.
#[derive(Clone, Debug, Default)]
pub struct Analytic {
    /// Sphere radius.
    pub radius: f32,
    /// Pixel channels compared.
    pub channels: usize,
    /// Largest difference from the analytic value, 8-bit steps (LSB); -1 if refused.
    pub worst_lsb: i32,
}

/// Case 9: the camera inside a diffuse sphere of radius `r` lit by a point light of
/// intensity `0.9 r^2` at its centre: every pixel is `kd * color * 0.9`.
#[must_use]
pub fn analytic(r: f32) -> Analytic {
    let color = Color::new(0.9, 0.6, 0.3);
    let kd = 0.8f32;
    let mut out = Analytic {
        radius: r,
        worst_lsb: -1,
        ..Analytic::default()
    };
    let Ok(scene) = crate::inside_sphere(r, 0.9 * r * r, kd, color) else {
        return out;
    };
    let e = f64::from(kd) * 0.9;
    let want = [color.r, color.g, color.b].map(|c| (f64::from(c) * e * 255.0).round() as i32);
    out.worst_lsb = 0;
    for sampler in [Sampler::Centre, Sampler::Corner, Sampler::Stratified(2)] {
        let settings = RenderSettings {
            sampler,
            max_depth: 2,
            seed: 1,
            encoding: tessera_core::Encoding::Linear,
        };
        let Ok(renderer) = scene.renderer(Viewport::new(40, 30), settings) else {
            out.worst_lsb = -1;
            return out;
        };
        for y in 0..30 {
            for x in 0..40 {
                let p = renderer.pixel_color(&scene.view(), x, y, &mut ()).to_rgb8();
                for (got, want) in [p.r, p.g, p.b].into_iter().zip(want) {
                    out.channels += 1;
                    out.worst_lsb = out.worst_lsb.max((i32::from(got) - want).abs());
                }
            }
        }
    }
    out
}
