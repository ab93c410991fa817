//! An accepted scene never gives a NaN or infinite colour, and its bytes do not
//! depend on the tile size: random scenes built through the public API with values
//! drawn from the whole accepted range (and beyond it: whatever a constructor
//! refuses is simply left out), lights on surfaces, colours at `MAX_COLOR`,
//! textures at their extreme scales.

use proptest::prelude::*;
use tessera::{
    Aabb, Camera, Color, MAX_COLOR, MAX_EXTENT, MIN_LENGTH, Material, Plane, PointLight,
    RenderSettings, Sampler, Scene, Sphere, Texture, Triangle, Vec3, Viewport,
};
use tessera_host::render_tiles;

/// A number from the whole `f32` range that matters here: exact ends of the
/// accepted ranges, just beyond them, and log-uniform magnitudes of either sign.
fn wild() -> impl Strategy<Value = f32> {
    prop_oneof![
        2 => Just(0.0f32),
        1 => Just(1.0f32),
        1 => Just(MAX_COLOR),
        1 => Just(MAX_EXTENT),
        1 => Just(MIN_LENGTH),
        1 => Just(f32::MIN_POSITIVE),
        1 => Just(3.4e38f32),
        6 => (-60i32..60, 1.0f32..2.0, any::<bool>())
            .prop_map(|(e, m, neg)| if neg { -m * 2f32.powi(e) } else { m * 2f32.powi(e) }),
        4 => -4.0f32..4.0,
    ]
}

/// A non-negative number: colours, weights, intensities, scales.
fn amount() -> impl Strategy<Value = f32> {
    prop_oneof![
        2 => Just(0.0f32),
        2 => 0.0f32..1.0,
        1 => Just(MAX_COLOR),
        1 => Just(3e38f32),
        3 => (-60i32..60, 1.0f32..2.0).prop_map(|(e, m)| m * 2f32.powi(e)),
    ]
}

/// A weight in `[0, 1]`, its ends included, sometimes tiny.
fn unit() -> impl Strategy<Value = f32> {
    prop_oneof![
        2 => Just(0.0f32),
        2 => Just(1.0f32),
        1 => Just(f32::MIN_POSITIVE),
        5 => 0.0f32..=1.0,
    ]
}

fn v3() -> impl Strategy<Value = [f32; 3]> {
    [wild(), wild(), wild()]
}

fn color() -> impl Strategy<Value = [f32; 3]> {
    [amount(), amount(), amount()]
}

#[derive(Clone, Debug)]
struct Mat {
    color: [f32; 3],
    other: [f32; 3],
    /// Ambient, diffuse, specular, reflectivity, transparency (times 1 -
    /// reflectivity when `split`).
    weights: [f32; 5],
    split: bool,
    shininess: f32,
    ior: f32,
    texture: u8,
    scale: f32,
}

fn material() -> impl Strategy<Value = Mat> {
    (
        (color(), color()),
        ([unit(), unit(), unit(), unit(), unit()], any::<bool>()),
        (
            prop_oneof![Just(1.0f32), Just(10_000.0), 1.0f32..10_000.0],
            1.0f32..=4.0,
        ),
        0u8..3,
        amount(),
    )
        .prop_map(
            |((color, other), (weights, split), (shininess, ior), texture, scale)| Mat {
                color,
                other,
                weights,
                split,
                shininess,
                ior,
                texture,
                scale,
            },
        )
}

#[derive(Clone, Debug)]
struct Recipe {
    camera: ([f32; 3], [f32; 3], f32, f32, f32),
    ambient: [f32; 3],
    background: [f32; 3],
    spheres: Vec<([f32; 3], f32)>,
    planes: Vec<([f32; 3], [f32; 3])>,
    triangles: Vec<[[f32; 3]; 3]>,
    boxes: Vec<([f32; 3], [f32; 3])>,
    materials: Vec<Mat>,
    /// Position, colour, intensity, and whether to put the light on the first
    /// plane's point or sphere's surface instead.
    lights: Vec<([f32; 3], [f32; 3], f32, u8)>,
    depth: u8,
    sampler: u8,
}

fn recipe() -> impl Strategy<Value = Recipe> {
    (
        (v3(), v3(), 1.0f32..179.0, amount(), amount()),
        (color(), color()),
        prop::collection::vec((v3(), amount()), 0..4),
        prop::collection::vec((v3(), v3()), 0..3),
        prop::collection::vec([v3(), v3(), v3()], 0..3),
        prop::collection::vec((v3(), v3()), 0..3),
        prop::collection::vec(material(), 1..4),
        prop::collection::vec((v3(), color(), amount(), 0u8..4), 0..4),
        0u8..=8,
        0u8..4,
    )
        .prop_map(
            |(
                camera,
                (ambient, background),
                spheres,
                planes,
                triangles,
                boxes,
                materials,
                lights,
                depth,
                sampler,
            )| {
                Recipe {
                    camera,
                    ambient,
                    background,
                    spheres,
                    planes,
                    triangles,
                    boxes,
                    materials,
                    lights,
                    depth,
                    sampler,
                }
            },
        )
}

type WildScene = Scene<4, 3, 3, 3, 4, 4>;

fn v(a: [f32; 3]) -> Vec3 {
    Vec3::new(a[0], a[1], a[2])
}

fn c(a: [f32; 3]) -> Color {
    Color::new(a[0], a[1], a[2])
}

/// The material of a recipe, or `None` where a value is refused.
fn build_material(m: &Mat) -> Option<Material> {
    let [ambient, diffuse, specular, reflectivity, transparency] = m.weights;
    let transparency = if m.split {
        transparency * (1.0 - reflectivity)
    } else {
        transparency
    };
    let mut mat = Material::matte(c(m.color))
        .with_ambient(ambient)
        .ok()?
        .with_diffuse(diffuse)
        .ok()?
        .with_specular(specular, m.shininess)
        .ok()?
        .with_reflectivity(reflectivity)
        .ok()?
        .with_transparency(transparency, m.ior)
        .ok()?;
    let texture = match m.texture {
        1 => Texture::Checker {
            a: c(m.color),
            b: c(m.other),
            scale: m.scale,
        },
        2 => Texture::Fringes {
            color: c(m.color),
            spacing: m.scale,
        },
        _ => return Some(mat),
    };
    mat = mat.with_texture(texture).ok()?;
    Some(mat)
}

/// The scene of a recipe: each item that its constructor refuses is left out
/// (`None` when the camera or every material is refused).
fn build(r: &Recipe) -> Option<WildScene> {
    // The camera within the accepted ranges (the other items go beyond them): a
    // refused camera would refuse the whole scene.
    let (pos, fwd, fovy, near, far) = r.camera;
    let pos = pos.map(|x| x.clamp(-MAX_EXTENT / 4.0, MAX_EXTENT / 4.0));
    let fwd = if fwd.iter().all(|&x| x == 0.0) {
        [0.0, 0.0, -1.0]
    } else {
        fwd
    };
    let near = near.clamp(1e-6, 1e3);
    let far = near * (2.0 + far.min(1e6));
    let cam = Camera::try_new(v(pos), v(fwd), Vec3::Y, fovy, near, far).ok()?;
    let mut s = WildScene::new(cam);
    let _ = s.set_ambient(c(r.ambient));
    let _ = s.set_background(c(r.background));
    for m in &r.materials {
        if let Some(mat) = build_material(m) {
            s.add_material(mat).ok()?;
        }
    }
    let count = s.view().materials().len();
    if count == 0 {
        return None;
    }
    let id = |i: usize| tessera::MaterialId((i % count) as u16);
    let mut surface_points = Vec::new();
    for (i, &(centre, radius)) in r.spheres.iter().enumerate() {
        if let Ok(g) = Sphere::try_new(v(centre), radius) {
            s.add_sphere(g, id(i)).ok()?;
            surface_points.push(v(centre) + Vec3::new(radius, 0.0, 0.0));
        }
    }
    for (i, &(p, n)) in r.planes.iter().enumerate() {
        if let Ok(g) = Plane::try_new(v(p), v(n)) {
            s.add_plane(g, id(i + 1)).ok()?;
            surface_points.push(v(p));
        }
    }
    for (i, t) in r.triangles.iter().enumerate() {
        if let Ok(g) = Triangle::try_new(v(t[0]), v(t[1]), v(t[2])) {
            s.add_triangle(g, id(i + 2)).ok()?;
        }
    }
    for (i, &(min, size)) in r.boxes.iter().enumerate() {
        let size = v(size).abs();
        if let Ok(g) = Aabb::try_new(v(min), v(min) + size) {
            s.add_box(g, id(i + 3)).ok()?;
        }
    }
    for &(p, colour, intensity, on) in &r.lights {
        let p = match surface_points.get(usize::from(on)) {
            Some(&q) if on < 2 => q,
            _ => v(p),
        };
        if let Ok(light) = PointLight::try_new(p, c(colour), intensity) {
            s.add_light(light).ok()?;
        }
    }
    Some(s)
}

/// Scenes built and rendered by the property below (the test checks that the
/// generator is not refused too often to mean anything).
static RENDERED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
/// Scenes generated.
static GENERATED: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

proptest! {
    // A few seconds: 160 random scenes at 20x14, every pixel's colour checked,
    // rendered with three tile sizes.
    #![proptest_config(ProptestConfig { cases: 160, failure_persistence: None, ..ProptestConfig::default() })]

    #[test]
    fn accepted_scenes_give_finite_colours_whatever_the_tile_size(r in recipe()) {
        let generated = GENERATED.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        // By the end, at least an eighth of the scenes (shrinking included) must
        // have been rendered: most recipes hold a value some constructor refuses.
        prop_assert!(generated < 150 || 8 * RENDERED.load(std::sync::atomic::Ordering::Relaxed) >= generated,
            "only {} of {} random scenes were accepted", RENDERED.load(std::sync::atomic::Ordering::Relaxed), generated);
        let Some(scene) = build(&r) else {
            return Ok(());
        };
        let sampler = match r.sampler {
            0 => Sampler::Centre,
            1 => Sampler::Stratified(2),
            2 => Sampler::Prefiltered,
            _ => Sampler::Adaptive { k: 2, threshold: 0 },
        };
        let settings = RenderSettings { sampler, max_depth: r.depth, seed: 1, encoding: tessera::Encoding::Linear };
        let Ok(frame) = scene.frame(Viewport::new(20, 14), settings) else {
            return Ok(());
        };
        RENDERED.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let view = scene.view();
        for y in 0..14 {
            for x in 0..20 {
                let colour = frame.pixel_color(&view, x, y, &mut ());
                prop_assert!(
                    colour.is_finite() && colour.min_component() >= 0.0,
                    "pixel ({}, {}) is {:?}", x, y, colour
                );
            }
        }
        let eight = render_tiles::<8>(&view, &frame, None).unwrap();
        prop_assert!(eight == render_tiles::<16>(&view, &frame, None).unwrap(), "tiles of 8 and 16 differ");
        prop_assert!(eight == render_tiles::<32>(&view, &frame, None).unwrap(), "tiles of 8 and 32 differ");
    }
}
