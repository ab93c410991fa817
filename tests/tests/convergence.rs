//! Anti-aliasing converges at the rate theory predicts: on pixels crossed by a
//! straight edge, the RMSE of random sampling falls as N^-0.5 and that of jittered
//! stratified sampling as N^-0.75 (the slope of log RMSE against log N). The truth
//! is the exact coverage of each pixel by the half-plane, computed analytically.
//! Deterministic: fixed seeds, no timing.

use tessera_core::{
    Camera, Color, RenderSettings, Renderer, Sampler, Scene, Vec3, Viewport, geometry::Triangle,
    material::Material,
};

const N: u16 = 64;
/// The edge in pixel coordinates: y = M x + C (image y down); the triangle covers
/// the side below it (larger y).
const M: f64 = 0.431_7;
const C: f64 = 18.37;
/// Distance of the triangle's plane from the camera.
const D: f32 = 10.0;

/// The world point of the plane z = -D seen at pixel coordinates (px, py).
fn world(px: f64, py: f64) -> Vec3 {
    // 60 degrees, near 1: H = 2 tan 30, one pixel = H / N at the near plane.
    let pixel = 2.0 * (30f64).to_radians().tan() / f64::from(N) * f64::from(D);
    let half = f64::from(N) / 2.0;
    Vec3::new(
        ((px - half) * pixel) as f32,
        (-(py - half) * pixel) as f32,
        -D,
    )
}

fn scene() -> Scene<tessera_core::capacities!(triangles: 1, materials: 1)> {
    let cam = Camera::try_new(Vec3::ZERO, -Vec3::Z, Vec3::Y, 60.0, 1.0, 100.0).unwrap();
    let mut s = Scene::new(cam);
    s.set_ambient(Color::WHITE).unwrap();
    let white = s
        .add_material(Material::matte(Color::WHITE).with_diffuse(0.0).unwrap())
        .unwrap();
    // One edge crosses the image; the other two lie far outside it.
    let a = world(-200.0, M * -200.0 + C);
    let b = world(300.0, M * 300.0 + C);
    let c = world(50.0, 2000.0);
    s.add_triangle(Triangle::try_new(a, b, c).unwrap(), white)
        .unwrap();
    s
}

/// Exact share of pixel (x, y) below the line y = M x + C.
fn coverage(x: u32, y: u32) -> f64 {
    // Integrate the covered height of each thin column (exact in y).
    let steps = 4000;
    let (y0, y1) = (f64::from(y), f64::from(y) + 1.0);
    let mut area = 0.0;
    for i in 0..steps {
        let t = f64::from(x) + (f64::from(i) + 0.5) / f64::from(steps);
        let line = M * t + C;
        area += (y1 - line.max(y0)).clamp(0.0, 1.0);
    }
    area / f64::from(steps)
}

/// RMSE over the edge pixels, averaged (as MSE) over several seeds.
fn rmse(frame_for: impl Fn(u32) -> Renderer, edge: &[(u32, u32, f64)]) -> f64 {
    let s = scene();
    let view = s.view();
    let seeds = 8;
    let mut se = 0.0;
    for seed in 0..seeds {
        let renderer = frame_for(seed);
        for &(x, y, truth) in edge {
            let v = f64::from(renderer.pixel_color(&view, x, y, &mut ()).r);
            se += (v - truth) * (v - truth);
        }
    }
    (se / (edge.len() * seeds as usize) as f64).sqrt()
}

/// Least-squares slope of log(rmse) against log(spp).
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|(x, y)| (x.ln(), y.ln())).unzip();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let num: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let den: f64 = lx.iter().map(|x| (x - mx) * (x - mx)).sum();
    num / den
}

#[test]
fn stratified_converges_faster_than_random_on_edges() {
    let edge: Vec<(u32, u32, f64)> = (0..u32::from(N))
        .flat_map(|y| (0..u32::from(N)).map(move |x| (x, y)))
        .map(|(x, y)| (x, y, coverage(x, y)))
        .filter(|&(_, _, c)| c > 0.0 && c < 1.0)
        .collect();
    assert!(edge.len() > 60, "{} edge pixels", edge.len());
    let s = scene();
    let renderer = |sampler: Sampler| {
        let cam = *s.camera();
        move |seed: u32| {
            Renderer::try_new(
                &cam,
                Viewport::new(N, N),
                RenderSettings {
                    sampler,
                    max_depth: 0,
                    seed,
                    encoding: tessera_core::Encoding::Linear,
                },
            )
            .unwrap()
        }
    };
    // The renderer itself is exact away from the edge: check a few interior pixels.
    let f = renderer(Sampler::Centre)(0);
    assert_eq!(f.pixel_color(&s.view(), 5, 60, &mut ()).r, 1.0);
    assert_eq!(f.pixel_color(&s.view(), 60, 2, &mut ()).r, 0.0);

    let random: Vec<(f64, f64)> = [4u16, 16, 64, 256]
        .iter()
        .map(|&n| (f64::from(n), rmse(renderer(Sampler::Random(n)), &edge)))
        .collect();
    let stratified: Vec<(f64, f64)> = [2u8, 4, 8, 16]
        .iter()
        .map(|&k| {
            (
                f64::from(k) * f64::from(k),
                rmse(renderer(Sampler::Stratified(k)), &edge),
            )
        })
        .collect();
    let (sr, ss) = (slope(&random), slope(&stratified));
    println!("random RMSE {random:?} slope {sr:.3}");
    println!("stratified RMSE {stratified:?} slope {ss:.3}");
    assert!(
        (-0.6..=-0.4).contains(&sr),
        "random slope {sr:.3}, expected -0.5 +/- 0.1"
    );
    assert!(
        ss <= -0.70,
        "stratified slope {ss:.3}, expected <= -0.70 (theory -0.75)"
    );
    assert!(
        ss >= -0.85,
        "stratified slope {ss:.3} steeper than theory: check the truth"
    );
    // And at equal cost stratified is better everywhere.
    for (r, s) in random.iter().zip(&stratified) {
        assert!(
            s.1 < r.1,
            "at {} spp stratified {} >= random {}",
            r.0,
            s.1,
            r.1
        );
    }
}
