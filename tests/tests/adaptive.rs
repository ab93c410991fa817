//! The adaptive sampler refines exactly the pixels its rule names, with the
//! stratified sampler's samples, and traces nothing else.
//!
//! The expectations are computed here from other renders: the centre-sampled
//! image gives each pixel's class (background, sphere, lit floor, floor in
//! shadow: each has its own colour channel or level, so the class is read off
//! the 8-bit pixel) and its colour; the rule (refine where one of the four
//! neighbours in the frame, above, left, right or below, has another class, or a channel differing by more
//! than the threshold) is applied to that image; refined pixels must equal the
//! stratified render's, the others the centre render's.

use image::RgbImage;
use tessera_core::{
    Camera, Color, RenderSettings, Sampler, Scene, Tile, TileCoord, Vec3, Viewport,
    geometry::Plane, geometry::Sphere, light::Light, material::Material, trace::RayCount,
};
use tessera_host::render_tiles;

pub(crate) const AMBIENT: f32 = 0.2;
pub(crate) const W: u16 = 45;
pub(crate) const H: u16 = 34;

/// A red sphere casting a shadow on a green floor, seen from above (no
/// horizon: every lit floor pixel is several steps above the shadow's level);
/// one light. No texture: the adaptive sampler's centre ray (prefiltered) is
/// the centre sampler's. (The sparse sampler's tests use it too.)
pub(crate) fn scene()
-> Scene<tessera_core::capacities!(spheres: 1, planes: 1, materials: 2, lights: 1)> {
    scene_in()
}

/// [`scene`] in a scene of capacities `C`, room for what a test adds to it.
pub(crate) fn scene_in<C: tessera_core::Capacities>() -> Scene<C> {
    let cam = Camera::try_new(
        Vec3::new(0.0, 5.0, 4.0),
        Vec3::new(0.0, -5.0, -4.5),
        Vec3::Y,
        50.0,
        0.1,
        100.0,
    )
    .unwrap();
    let mut s = Scene::new(cam);
    s.set_ambient(Color::splat(1.0)).unwrap();
    s.set_background(Color::new(0.0, 0.0, 0.7)).unwrap();
    let red = s
        .add_material(
            Material::matte(Color::new(0.9, 0.0, 0.0))
                .with_ambient(AMBIENT)
                .unwrap(),
        )
        .unwrap();
    let green = s
        .add_material(
            Material::matte(Color::new(0.0, 0.8, 0.0))
                .with_ambient(AMBIENT)
                .unwrap(),
        )
        .unwrap();
    s.add_sphere(Sphere::try_new(Vec3::new(0.0, 1.0, 0.0), 0.8).unwrap(), red)
        .unwrap();
    s.add_plane(Plane::try_new(Vec3::ZERO, Vec3::Y).unwrap(), green)
        .unwrap();
    s.add_light(Light::point(Vec3::new(1.5, 5.0, 1.0), Color::WHITE, 30.0).unwrap())
        .unwrap();
    s
}

fn render(sampler: Sampler) -> RgbImage {
    let s = scene();
    let settings = RenderSettings {
        sampler,
        max_depth: 0,
        seed: 3,
        encoding: tessera_core::Encoding::Linear,
    };
    let renderer = s.renderer(Viewport::new(W, H), settings).unwrap();
    render_tiles::<16>(&s.view(), &renderer, None).unwrap()
}

/// What the centre ray of a pixel met, read off its colour.
pub(crate) fn class(p: [u8; 3]) -> u8 {
    let shadowed_floor = (0.8 * AMBIENT * 255.0f32).round() as u8;
    match p {
        [0, 0, b] if b > 0 => 0,               // sky
        [r, 0, 0] if r > 0 => 1,               // sphere
        [0, g, 0] if g == shadowed_floor => 2, // floor in shadow
        [0, g, 0] if g > shadowed_floor => 3,  // lit floor
        _ => panic!("unexpected pixel {p:?}"),
    }
}

/// The pixels the rule refines, from the centre image.
fn expected_mask(centre: &RgbImage, threshold: u8) -> Vec<bool> {
    let (w, h) = (i64::from(W), i64::from(H));
    let mut mask = Vec::new();
    for y in 0..h {
        for x in 0..w {
            let own = centre.get_pixel(x as u32, y as u32).0;
            let mut refine = false;
            for (dx, dy) in [(0, -1), (-1, 0), (1, 0), (0, 1)] {
                let (nx, ny) = (x + dx, y + dy);
                if !(0..w).contains(&nx) || !(0..h).contains(&ny) {
                    continue;
                }
                let n = centre.get_pixel(nx as u32, ny as u32).0;
                let step = own.iter().zip(&n).any(|(a, b)| a.abs_diff(*b) > threshold);
                refine |= class(own) != class(n) || step;
            }
            mask.push(refine);
        }
    }
    mask
}

fn check(threshold: u8, k: u8) -> usize {
    let centre = render(Sampler::Centre);
    let strat = render(Sampler::Stratified(k));
    let adaptive = render(Sampler::Adaptive { k, threshold });
    let mask = expected_mask(&centre, threshold);
    for (i, &refine) in mask.iter().enumerate() {
        let (x, y) = ((i % usize::from(W)) as u32, (i / usize::from(W)) as u32);
        let want = if refine { &strat } else { &centre };
        assert_eq!(
            adaptive.get_pixel(x, y),
            want.get_pixel(x, y),
            "threshold {threshold}: pixel ({x}, {y}) should be the {} one",
            if refine { "stratified" } else { "centre" }
        );
    }
    mask.iter().filter(|&&r| r).count()
}

#[test]
fn refines_silhouettes_and_shadow_edges_whatever_their_contrast() {
    // Threshold 255: no colour step refines; the classes' edges do.
    let refined = check(255, 3);
    // The sphere's outline and its shadow's: a band, not the whole image.
    let total = usize::from(W) * usize::from(H);
    assert!(
        (total / 20..total / 2).contains(&refined),
        "{refined} of {total}"
    );
}

#[test]
fn a_lower_threshold_also_refines_colour_steps() {
    let edges = check(255, 2);
    let steps = check(6, 2);
    let all = check(0, 2);
    // The lit floor and sphere are shaded: colour steps add pixels.
    assert!(edges < steps && steps < all, "{edges} {steps} {all}");
}

#[test]
fn traces_the_tiles_and_their_apron_once_then_only_the_refined_samples() {
    let (k, tile) = (3u8, 16usize);
    let centre = render(Sampler::Centre);
    let refined = expected_mask(&centre, 255).iter().filter(|&&r| r).count();
    let s = scene();
    let settings = RenderSettings {
        sampler: Sampler::Adaptive { k, threshold: 255 },
        max_depth: 0,
        seed: 3,
        encoding: tessera_core::Encoding::Linear,
    };
    let renderer = s.renderer(Viewport::new(W, H), settings).unwrap();
    let (across, down) = renderer.tile_grid(tile);
    let mut count = RayCount::default();
    let mut buf = Tile::<16>::new();
    // Centre rays: each tile's pixels and the ring around them inside the frame.
    let mut centres = 0;
    for ty in 0..down {
        for tx in 0..across {
            renderer
                .render_tile(&s.view(), TileCoord::new(tx, ty), &mut buf, &mut count)
                .unwrap();
            let span = |t: u16, n: u16| {
                let lo = (usize::from(t) * tile).saturating_sub(1);
                let hi = ((usize::from(t) + 1) * tile + 1).min(usize::from(n));
                hi - lo
            };
            centres += span(tx, W) * span(ty, H);
        }
    }
    let k2 = usize::from(k) * usize::from(k);
    assert_eq!(count.primary as usize, centres + k2 * refined);
    // One pixel on its own: its centre ray and its four neighbours'.
    let mut one = RayCount::default();
    renderer.pixel_color(&s.view(), 20, 20, &mut one);
    assert!(one.primary == 5 || one.primary == 5 + k2 as u64, "{one:?}");
}

#[test]
fn frame_pixels_match_the_tiles() {
    let s = scene();
    for threshold in [0, 6, 255] {
        let sampler = Sampler::Adaptive { k: 2, threshold };
        let img = render(sampler);
        let renderer = s
            .renderer(
                Viewport::new(W, H),
                RenderSettings {
                    sampler,
                    max_depth: 0,
                    seed: 3,
                    encoding: tessera_core::Encoding::Linear,
                },
            )
            .unwrap();
        for (x, y, p) in img.enumerate_pixels() {
            let q = renderer.pixel_color(&s.view(), x, y, &mut ()).to_rgb8();
            assert_eq!(p.0, [q.r, q.g, q.b], "threshold {threshold}: ({x}, {y})");
        }
    }
}
