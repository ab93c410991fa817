//! Tests of the reference renderer against hand-computed values and against the core.

use super::*;
use crate::desc::{
    BoxDesc, LightDesc, MaterialDesc, PlaneDesc, SphereDesc, TextureDesc, TriangleDesc,
};
use tessera_core::{RenderSettings, Sampler, Viewport};

fn material(name: &str, color: [f64; 3]) -> MaterialDesc {
    MaterialDesc::matte(name, color)
}

fn camera(position: [f64; 3], forward: [f64; 3]) -> CameraDesc {
    CameraDesc {
        position,
        forward: Some(forward),
        look_at: None,
        up: [0.0, 1.0, 0.0],
        fovy: 60.0,
        near: 0.1,
        far: 100.0,
    }
}

fn empty(camera: CameraDesc) -> SceneDesc {
    SceneDesc::new(camera)
}

/// Camera inside a diffuse sphere of radius r, point light at the centre: every
/// pixel is kd * color * I / r^2 exactly (the light is straight along the normal).
#[test]
fn inside_a_lit_sphere_every_pixel_is_kd_color_i_over_r2() {
    for r in [0.5, 2.0, 10.0, 300.0] {
        let centre = [1.0, -2.0, 3.0];
        let mut d = empty(camera(centre, [0.3, -0.2, -1.0]));
        d.camera.near = r / 100.0;
        d.camera.far = 4.0 * r;
        let mut m = material("wall", [0.5, 0.25, 1.0]);
        m.diffuse = 0.8;
        d.materials.push(m);
        let intensity = 0.7 * r * r;
        d.lights.push(LightDesc {
            name: None,
            direction: None,
            position: centre,
            color: [1.0, 0.5, 1.0],
            intensity,
        });
        d.spheres.push(SphereDesc {
            name: None,
            center: centre,
            radius: r,
            material: "wall".into(),
        });
        let settings = RenderSettings {
            sampler: Sampler::Stratified(2),
            max_depth: 2,
            seed: 9,
            encoding: tessera_core::Encoding::Linear,
        };
        let img = render(&d, Viewport::new(24, 16), &settings).unwrap();
        let e = intensity / (r * r);
        let expect = [0.8 * 0.5 * e, 0.8 * 0.25 * 0.5 * e, 0.8 * e];
        for p in &img.pixels {
            for (a, b) in p.iter().zip(expect) {
                assert!((a - b).abs() < 1e-12, "r = {r}: {p:?} vs {expect:?}");
            }
        }
        assert_eq!(img.non_finite(), 0);
        assert!(img.signature.iter().all(|&s| s == img.signature[0]));
    }
}

/// The chapter's worked example: fovy 90, n = 1, 4 x 2, r_cam = 0, c_a = -z,
/// c_h = +y. H = 2, L = 4, u1 = (1, 0, 0), u2 = (0, -1, 0); the corner of pixel
/// (0, 0) is (-2, 1, -1), direction (-2, 1, -1) / sqrt(6).
#[test]
fn worked_camera_example() {
    let mut c = camera([0.0; 3], [0.0, 0.0, -1.0]);
    (c.fovy, c.near, c.far) = (90.0, 1.0, 10.0);
    let cam = RefCamera::new(&c, Viewport::new(4, 2)).unwrap();
    let (ray, t_far) = cam.ray(0.0, 0.0);
    let s6 = 6f64.sqrt();
    assert!((ray.dir - V3::new(-2.0 / s6, 1.0 / s6, -1.0 / s6)).length() < 1e-15);
    assert!((ray.origin - V3::new(-2.0, 1.0, -1.0)).length() < 1e-15);
    // The far plane z = -10 is 9 sqrt(6) away along that ray.
    assert!((t_far - 9.0 * s6).abs() < 1e-13);
    assert!((ray.at(t_far).z + 10.0).abs() < 1e-13);
    // The image centre looks straight ahead; look_at gives the same camera.
    assert_eq!(cam.ray(2.0, 1.0).0.dir, -V3::Z);
    c.forward = None;
    c.look_at = Some([0.0, 0.0, -7.0]);
    assert_eq!(RefCamera::new(&c, Viewport::new(4, 2)).unwrap(), cam);
    // up parallel to forward still gives an orthonormal frame.
    c.up = [0.0, 0.0, -3.0];
    let cam = RefCamera::new(&c, Viewport::new(4, 2)).unwrap();
    assert!(cam.u1.dot(cam.u2).abs() < 1e-15 && cam.u1.dot(V3::Z).abs() < 1e-15);
}

#[test]
fn quantisation_and_non_finite() {
    let img = RefImage {
        width: 3,
        height: 1,
        pixels: vec![
            [0.5, -1.0, 2.0],
            [f64::NAN, 1.0 / 255.0, 0.499 / 255.0],
            [f64::INFINITY, 0.0, 0.0],
        ],
        signature: vec![0; 15],
        encoding: tessera_core::Encoding::Linear,
    };
    let rgb = img.to_rgb8();
    assert_eq!(rgb.get_pixel(0, 0).0, [128, 0, 255]);
    assert_eq!(rgb.get_pixel(1, 0).0, [0, 1, 0]);
    assert_eq!(rgb.get_pixel(2, 0).0, [255, 0, 0]);
    // sRGB: the same curve as the core's table, in f64 (0.5 linear is 188).
    let srgb = RefImage {
        encoding: tessera_core::Encoding::Srgb,
        ..img.clone()
    }
    .to_rgb8();
    assert_eq!(srgb.get_pixel(0, 0).0, [188, 0, 255]);
    assert_eq!(srgb.get_pixel(1, 0).0, [0, 13, 6]);
    assert_eq!(srgb.get_pixel(2, 0).0, [255, 0, 0]);
    for k in 0..=1000 {
        let v = k as f32 / 1000.0;
        let core = tessera_core::Color::splat(v).to_srgb8().r;
        assert_eq!(
            super::encode8(f64::from(v), tessera_core::Encoding::Srgb),
            core,
            "{v}"
        );
    }
    assert_eq!(img.non_finite(), 2);
}

#[test]
fn invalid_scenes_are_rejected_like_the_core() {
    let mut d = empty(camera([0.0; 3], [0.0, 0.0, -1.0]));
    d.materials.push(material("m", [1.0; 3]));
    d.spheres.push(SphereDesc {
        name: None,
        center: [0.0, 0.0, -3.0],
        radius: -1.0,
        material: "m".into(),
    });
    let s = RenderSettings::default();
    let e = render(&d, Viewport::new(4, 4), &s).unwrap_err();
    assert_eq!(e.item, "sphere 1");
    d.spheres[0].radius = 1.0;
    d.spheres[0].material = "nope".into();
    assert!(render(&d, Viewport::new(4, 4), &s).is_err());
    d.spheres[0].material = "m".into();
    assert!(render(&d, Viewport::new(0, 4), &s).is_err());
    let deep = RenderSettings { max_depth: 9, ..s };
    assert!(render(&d, Viewport::new(4, 4), &deep).is_err());
    assert!(render(&d, Viewport::new(4, 4), &s).is_ok());
}

/// Two spheres (one a mirror), a glass sphere, a checker floor, a fringed
/// triangle, a box, two lights.
fn test_scene() -> SceneDesc {
    let mut d = empty(CameraDesc {
        position: [0.0, 1.6, 6.0],
        forward: None,
        look_at: Some([0.0, 0.6, 0.0]),
        up: [0.0, 1.0, 0.0],
        fovy: 50.0,
        near: 0.1,
        far: 100.0,
    });
    d.ambient = [0.1, 0.1, 0.12];
    d.background = [0.2, 0.3, 0.5];
    let mut red = material("red", [0.8, 0.2, 0.2]);
    (red.specular, red.shininess) = (0.5, 32.0);
    let mut mirror = material("mirror", [0.9, 0.9, 0.9]);
    (mirror.diffuse, mirror.reflectivity) = (0.2, 0.7);
    (mirror.specular, mirror.shininess) = (0.3, 64.0);
    let mut glass = material("glass", [1.0; 3]);
    (
        glass.ambient,
        glass.diffuse,
        glass.specular,
        glass.shininess,
    ) = (0.0, 0.0, 0.5, 64.0);
    (glass.transparency, glass.ior) = (0.9, 1.5);
    let mut floor = material("floor", [1.0; 3]);
    floor.texture = Some(TextureDesc::Checker {
        a: [0.9, 0.9, 0.9],
        b: [0.1, 0.1, 0.1],
        scale: 1.0,
    });
    floor.diffuse = 0.8;
    let mut fringes = material("fringes", [1.0; 3]);
    fringes.texture = Some(TextureDesc::Fringes {
        color: [0.2, 0.9, 0.3],
        spacing: 0.25,
    });
    let mut young = material("young", [1.0; 3]);
    young.texture = Some(TextureDesc::Young {
        color: [1.0, 0.8, 0.2],
        d: 2e-3,
        wavelength: 500e-9,
        distance: 1000.0,
    });
    d.materials = vec![red, mirror, glass, floor, fringes, young];
    d.lights = vec![
        LightDesc {
            name: None,
            direction: None,
            position: [4.0, 6.0, 3.0],
            color: [1.0, 1.0, 1.0],
            intensity: 40.0,
        },
        LightDesc {
            name: None,
            direction: None,
            position: [-5.0, 4.0, 5.0],
            color: [0.5, 0.5, 1.0],
            intensity: 20.0,
        },
    ];
    let sphere = |center, radius, m: &str| SphereDesc {
        name: None,
        center,
        radius,
        material: m.into(),
    };
    d.spheres = vec![
        sphere([-1.2, 1.0, 0.0], 1.0, "red"),
        sphere([1.2, 1.0, -0.5], 1.0, "mirror"),
        sphere([0.2, 0.6, 2.0], 0.6, "glass"),
    ];
    d.planes = vec![PlaneDesc {
        name: None,
        point: [0.0, 0.0, 0.0],
        normal: [0.0, 2.0, 0.0],
        material: "floor".into(),
    }];
    d.triangles = vec![TriangleDesc {
        name: None,
        vertices: [[-3.5, 0.0, -3.0], [2.5, 0.0, -3.0], [-0.5, 3.5, -4.0]],
        material: "fringes".into(),
    }];
    d.boxes = vec![BoxDesc {
        name: None,
        rotate: None,
        quaternion: None,
        min: [1.9, 0.0, 1.0],
        max: [2.7, 0.8, 1.8],
        material: "young".into(),
    }];
    d
}

/// Share of channel values within 0, 1 and 2 LSB of the core, and the share of
/// pixels whose three channels are all within 1 LSB.
fn agreement(a: &image::RgbImage, b: &image::RgbImage) -> ([f64; 3], f64) {
    let mut within = [0usize; 3];
    let mut pixels_1 = 0;
    for (p, q) in a.pixels().zip(b.pixels()) {
        let worst = (0..3).map(|c| p.0[c].abs_diff(q.0[c])).max().unwrap_or(0);
        for (k, w) in within.iter_mut().enumerate() {
            if usize::from(worst) <= k {
                *w += 1;
            }
        }
        pixels_1 += usize::from(worst <= 1);
    }
    let n = (a.width() * a.height()) as f64;
    (within.map(|w| w as f64 / n), pixels_1 as f64 / n)
}

/// Renders `d` at 160x120, depth 4, centre and stratified 2x2, with the reference
/// (checked finite) and the core; per setting the reference image and the
/// [`agreement`] figures (printed).
fn against_the_core(d: &SceneDesc) -> Vec<(RefImage, [f64; 3], f64)> {
    let vp = Viewport::new(160, 120);
    let scene = d.to_core().unwrap();
    [(Sampler::Centre, 0), (Sampler::Stratified(2), 7)]
        .into_iter()
        .map(|(sampler, seed)| {
            let settings = RenderSettings {
                sampler,
                max_depth: 4,
                seed,
                encoding: tessera_core::Encoding::Linear,
            };
            let reference = render(d, vp, &settings).unwrap();
            assert_eq!(reference.non_finite(), 0);
            let core = scene
                .with_view(|v| crate::render(v, scene.camera(), vp, settings, 16))
                .unwrap();
            let (within, pixels_1) = agreement(&reference.to_rgb8(), &core);
            println!(
                "{sampler:?}: pixels within 0/1/2 LSB: {:.4} / {:.4} / {:.4}",
                within[0], within[1], within[2]
            );
            (reference, within, pixels_1)
        })
        .collect()
}

#[test]
fn agrees_with_the_core_on_a_hand_written_scene() {
    for (reference, within, pixels_1) in against_the_core(&test_scene()) {
        assert!(pixels_1 >= 0.99, "{within:?}");
        // Every kind of primitive is seen: signatures vary across the image.
        let mut kinds = reference.signature.clone();
        kinds.sort_unstable();
        kinds.dedup();
        assert!(kinds.len() > 20, "{}", kinds.len());
    }
}

/// The hand-written scene with the calls that the fast-math backend approximates:
/// non-integer shininess (`powf` for the highlights) and checkered spheres (`atan2`
/// and `acos` for their texture coordinates). The other scene's highlights have
/// integer shininess, which both backends raise by repeated squaring, so that test
/// cannot tell the backends apart.
fn approximated_scene() -> SceneDesc {
    let mut d = test_scene();
    let globe = TextureDesc::Checker {
        a: [0.9, 0.8, 0.2],
        b: [0.2, 0.3, 0.8],
        scale: 6.0,
    };
    for m in &mut d.materials {
        match m.name.as_str() {
            "red" => (m.shininess, m.texture) = (20.5, Some(globe.clone())),
            "mirror" => m.shininess = 90.5,
            "glass" => m.shininess = 45.5,
            _ => {}
        }
    }
    d
}

/// Share of pixels whose channels are all within 1 LSB of the f64 reference on
/// [`approximated_scene`], per backend (the images are deterministic: the same
/// figures on every run). Exact: measured 1.0000 (centre) and 0.9999 (stratified
/// 2x2), bound 0.999. fast-math: measured 0.9995 and 0.9988, bound 0.997: the
/// highlights are within 1.6 LSB (the core's `math::powf`'s bound up to shininess
/// 100.5), the rest is the checker's edges on the red sphere, moved by micromath's
/// `atan2` and `acos` (up to 9.2e-3 of the texture in `v`).
#[test]
fn agrees_with_the_core_where_fast_math_approximates() {
    let bound = if cfg!(feature = "fast-math") {
        0.997
    } else {
        0.999
    };
    for (_, within, pixels_1) in against_the_core(&approximated_scene()) {
        assert!(pixels_1 >= bound, "{pixels_1} < {bound}: {within:?}");
    }
}

#[test]
fn signatures_mark_silhouettes_and_shadows() {
    // One sphere over a floor, lit from above: the sphere's pixels, the floor in
    // its shadow and the lit floor have three different signatures.
    let mut d = empty(camera([0.0, 1.0, 5.0], [0.0, -0.2, -1.0]));
    d.materials.push(material("m", [0.8; 3]));
    d.lights.push(LightDesc {
        name: None,
        direction: None,
        position: [0.0, 10.0, 0.0],
        color: [1.0; 3],
        intensity: 100.0,
    });
    d.spheres.push(SphereDesc {
        name: None,
        center: [0.0, 1.0, 0.0],
        radius: 0.5,
        material: "m".into(),
    });
    d.planes.push(PlaneDesc {
        name: None,
        point: [0.0; 3],
        normal: [0.0, 1.0, 0.0],
        material: "m".into(),
    });
    let vp = Viewport::new(64, 48);
    let img = render(&d, vp, &RenderSettings::default()).unwrap();
    let cam = RefCamera::new(&d.camera, vp).unwrap();
    let scene = RefScene::from_desc(&d).unwrap();
    // Classify every pixel centre by hand: what the camera ray hits first, and
    // whether the floor point sees the light.
    let mut classes = std::collections::HashMap::new();
    for y in 0..48u32 {
        for x in 0..64u32 {
            let (ray, t_far) = cam.ray(f64::from(x) + 0.5, f64::from(y) + 0.5);
            let s = scene.objects[0].shape.intersect(&ray, t_far);
            let f = scene.objects[1].shape.intersect(&ray, t_far);
            let class = match (s, f) {
                (Some(h), _) => {
                    // Lit side (a shadow ray is cast) or the side facing away.
                    let p = ray.at(h.t);
                    let n = (p - V3::new(0.0, 1.0, 0.0)).normalize();
                    if n.dot((V3::new(0.0, 10.0, 0.0) - p).normalize()) > 0.0 {
                        0
                    } else {
                        4
                    }
                }
                (None, Some(h)) => {
                    let p = ray.at(h.t);
                    let up = Ray {
                        origin: p,
                        dir: (V3::new(0.0, 10.0, 0.0) - p).normalize(),
                    };
                    1 + u8::from(scene.objects[0].shape.intersect(&up, 1e9).is_some())
                }
                (None, None) => 3,
            };
            let sig = img.signature_at(x.into(), y.into()).unwrap();
            assert_eq!(*classes.entry(class).or_insert(sig), sig, "class {class}");
        }
    }
    let mut sigs: Vec<u64> = classes.values().copied().collect();
    sigs.sort_unstable();
    sigs.dedup();
    assert_eq!(sigs.len(), classes.len());
    assert!(classes.len() >= 3, "{classes:?}");
}

/// Where one primitive's shading jumps, the signature changes as across two
/// primitives: between a box's faces, between a flat mesh's faces that meet at
/// an angle and between a textured mesh's faces (its uv are each face's
/// barycentrics); not between a flat mesh's coplanar faces nor across a smooth
/// mesh's edges, where the shading is continuous.
#[test]
fn signatures_change_where_a_primitives_shading_jumps() {
    // The signatures of pixels (8, 3) and (8, 12), above and below the image's
    // middle, where each scene puts an edge.
    let scene = |setup: &dyn Fn(&mut SceneDesc)| {
        let mut d = empty(camera([0.0, 0.0, 5.0], [0.0, 0.0, -1.0]));
        d.materials.push(material("m", [0.8; 3]));
        d.lights.push(LightDesc {
            name: None,
            direction: None,
            position: [0.0, 0.0, 10.0],
            color: [1.0; 3],
            intensity: 100.0,
        });
        setup(&mut d);
        let img = render(&d, Viewport::new(16, 16), &RenderSettings::default()).unwrap();
        let sig = |y: i64| img.signature_at(8, y).unwrap();
        (sig(3), sig(12))
    };
    // A box seen from above its top (+y) and in front of its front (+z),
    // looking at the edge between them.
    let (upper, lower) = scene(&|d| {
        d.camera.position = [0.0, 3.0, 5.0];
        d.camera.forward = None;
        d.camera.look_at = Some([0.0, 0.0, 1.0]);
        // Lighting both faces.
        d.lights[0].position = [0.0, 10.0, 10.0];
        d.boxes.push(BoxDesc {
            name: None,
            rotate: None,
            quaternion: None,
            min: [-9.0, -9.0, -9.0],
            max: [9.0, 0.0, 1.0],
            material: "m".into(),
        });
    });
    // Row 3 sees the top, row 12 the front: two faces, one box.
    assert_ne!(upper, lower, "box faces");
    // Looking down -z: two triangles of one mesh meeting at y = 0, at an angle
    // (the lower one tilted towards the camera) or coplanar; flat, smooth or
    // textured.
    let fold = |lower_z: f64| -> Vec<[[f64; 3]; 3]> {
        vec![
            [[-9.0, 0.0, 0.0], [9.0, 0.0, 0.0], [0.0, 9.0, 0.0]],
            [[9.0, 0.0, 0.0], [-9.0, 0.0, 0.0], [0.0, -9.0, lower_z]],
        ]
    };
    let mesh = |faces: Vec<[[f64; 3]; 3]>, smooth: bool, textured: bool| {
        move |d: &mut SceneDesc| {
            if textured {
                d.materials[0].texture = Some(TextureDesc::Fringes {
                    color: [1.0; 3],
                    spacing: 0.3,
                });
            }
            d.meshes.push(crate::desc::MeshDesc {
                smooth: Some(smooth),
                faces: faces.clone(),
                ..crate::desc::MeshDesc::unplaced("fold.obj", Some("m".into()))
            });
        }
    };
    let differ = |faces: Vec<[[f64; 3]; 3]>, smooth: bool, textured: bool| {
        let (upper, lower) = scene(&mesh(faces, smooth, textured));
        upper != lower
    };
    assert!(differ(fold(3.0), false, false), "a flat mesh's fold");
    assert!(
        !differ(fold(0.0), false, false),
        "a flat mesh's coplanar faces"
    );
    assert!(differ(fold(0.0), false, true), "a textured mesh's faces");
    assert!(!differ(fold(3.0), true, false), "a smooth mesh's faces");
    // The same scenes with the two faces as two triangles of the list: each
    // its own primitive, always told apart.
    let (upper, lower) = scene(&|d| {
        for p in fold(0.0) {
            d.triangles.push(TriangleDesc {
                name: None,
                vertices: p,
                material: "m".into(),
            });
        }
    });
    assert_ne!(upper, lower, "two triangles");
}
