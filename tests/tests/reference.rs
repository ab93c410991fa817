//! The core (f32 tiles) against the independent f64 reference, on every built-in
//! scene: >= 99.5% of the pixels within 1 LSB and 100% within 2 LSB outside the
//! 1-pixel silhouette band, and no NaN or infinity.

use tessera_core::builtin::Builtin;
use tessera_core::{RenderSettings, Renderer, Sampler, Viewport};
use tessera_host::compare::{Accuracy, measure};

fn accuracy(b: Builtin, settings: RenderSettings, vp: Viewport) -> Accuracy {
    let core = b
        .with_scene(|view, cam| render(view, cam, vp, settings))
        .unwrap();
    against_reference(core, &tessera_host::file::builtin_desc(b), vp, settings)
}

/// The core's tiles of `view` seen by `cam`, and how many of its pixels have a
/// colour that is not finite.
fn render(
    view: &tessera_core::SceneView<'_>,
    cam: &tessera_core::Camera,
    vp: Viewport,
    settings: RenderSettings,
) -> (image::RgbImage, usize) {
    let renderer = Renderer::try_new(cam, vp, settings).unwrap();
    let img = tessera_host::render_tiles::<16>(view, &renderer, None).unwrap();
    let mut nf = 0;
    for y in 0..u32::from(vp.height) {
        for x in 0..u32::from(vp.width) {
            nf += usize::from(!renderer.pixel_color(view, x, y, &mut ()).is_finite());
        }
    }
    (img, nf)
}

/// The core's render (`core`, from [`render`]) of `desc` against the reference's.
fn against_reference(
    (img, non_finite): (image::RgbImage, usize),
    desc: &tessera_host::desc::SceneDesc,
    vp: Viewport,
    settings: RenderSettings,
) -> Accuracy {
    let r = tessera_host::reference::render(desc, vp, &settings).unwrap();
    measure(&img, non_finite, &r.to_rgb8(), r.non_finite(), &r.signature).unwrap()
}

#[test]
fn every_builtin_scene_agrees_with_the_reference() {
    let vp = Viewport::new(320, 240);
    let mut report = String::new();
    for &b in Builtin::ALL {
        let acc = accuracy(b, b.settings(), vp);
        report.push_str(&format!("== {}\n{acc}\n", b.name()));
        assert!(acc.meets_bar(), "{}:\n{acc}", b.name());
    }
    println!("{report}");
}

#[test]
fn antialiased_renders_agree_with_the_reference() {
    let vp = Viewport::new(160, 120);
    for (b, sampler) in [
        (Builtin::ChapterReflect, Sampler::Stratified(3)),
        (Builtin::Showcase, Sampler::Random(4)),
        (Builtin::Showcase, Sampler::adaptive(3)),
        (Builtin::Interference, Sampler::adaptive(3)),
        (Builtin::Showcase, Sampler::sparse()),
        (
            Builtin::Teapot,
            Sampler::Sparse {
                threshold: 255,
                spacing: 2,
            },
        ),
        (
            Builtin::ChapterDirect,
            Sampler::Sparse {
                threshold: 255,
                spacing: 4,
            },
        ),
    ] {
        let settings = RenderSettings {
            sampler,
            seed: 11,
            ..b.settings()
        };
        let acc = accuracy(b, settings, vp);
        assert!(acc.meets_bar(), "{} {sampler:?}:\n{acc}", b.name());
    }
}

/// sRGB-encoded renders against the reference encoded the same way in f64, on
/// every built-in scene with centre sampling, on two adaptive ones and two sparse
/// ones (whose rules compare the encoded centre pixels): the same bar. And the tiles' pixels are
/// `Renderer::pixel_color` encoded by `Color::to_srgb8`.
#[test]
fn srgb_renders_agree_with_the_reference() {
    let vp = Viewport::new(160, 120);
    let mut cases: Vec<(Builtin, Sampler)> = Builtin::ALL
        .iter()
        .copied()
        .map(|b| (b, b.settings().sampler))
        .collect();
    cases.push((Builtin::Showcase, Sampler::adaptive(3)));
    cases.push((Builtin::ChapterDirect, Sampler::adaptive(2)));
    cases.push((Builtin::ChapterReflect, Sampler::sparse()));
    cases.push((Builtin::Interference, Sampler::sparse()));
    cases.push((Builtin::ChapterReflect, Sampler::sparse_spaced(4)));
    cases.push((Builtin::Interference, Sampler::sparse_spaced(4)));
    for (b, sampler) in cases {
        let settings = RenderSettings {
            sampler,
            seed: 5,
            encoding: tessera_core::Encoding::Srgb,
            ..b.settings()
        };
        let acc = accuracy(b, settings, vp);
        assert!(acc.meets_bar(), "{} {sampler:?} srgb:\n{acc}", b.name());
        b.with_scene(|view, cam| {
            let renderer = Renderer::try_new(cam, vp, settings).unwrap();
            let img = tessera_host::render_tiles::<16>(view, &renderer, None).unwrap();
            let linear = RenderSettings {
                encoding: tessera_core::Encoding::Linear,
                ..settings
            };
            let lin = tessera_host::render(view, cam, vp, linear, 16).unwrap();
            assert!(img != lin, "{}: srgb changed nothing", b.name());
            for (x, y, p) in img.enumerate_pixels().step_by(7) {
                let c = renderer.pixel_color(view, x, y, &mut ()).to_srgb8();
                assert_eq!(p.0, [c.r, c.g, c.b], "{} ({x}, {y})", b.name());
            }
        })
        .unwrap();
    }
}

/// The scene file at `path` (from the workspace's root) against the reference,
/// at its own settings and with the antialiasing, adaptive, sparse and
/// prefiltered samplers: the same bar. Returns the report.
fn scene_file_agrees(path: &str, check: impl Fn(&tessera_host::desc::SceneDesc)) -> String {
    scene_file_agrees_at(path, check, &SAMPLERS)
}

/// The samplers [`scene_file_agrees`] renders with, beside the scene's own,
/// and their frame sizes.
const SAMPLERS: [(Sampler, Viewport); 4] = [
    (Sampler::Stratified(3), Viewport::new(160, 120)),
    (Sampler::adaptive(3), Viewport::new(160, 120)),
    (Sampler::sparse(), Viewport::new(160, 120)),
    (Sampler::Prefiltered, Viewport::new(160, 120)),
];

/// [`scene_file_agrees`] with the scene's own sampler and `samplers`.
fn scene_file_agrees_at(
    path: &str,
    check: impl Fn(&tessera_host::desc::SceneDesc),
    samplers: &[(Sampler, Viewport)],
) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(path);
    let desc = tessera_host::file::load(&path).unwrap();
    check(&desc);
    let scene = desc.to_core().unwrap();
    let own = desc.settings().unwrap();
    let mut report = String::new();
    let own_size = [(own.sampler, Viewport::new(320, 240))];
    for &(sampler, vp) in own_size.iter().chain(samplers) {
        let settings = RenderSettings {
            sampler,
            seed: 3,
            ..own
        };
        let core = scene.with_view(|view| render(view, scene.camera(), vp, settings));
        let acc = against_reference(core, &desc, vp, settings);
        report.push_str(&format!(
            "== {sampler:?} {}x{}\n{acc}\n",
            vp.width, vp.height
        ));
        assert!(acc.meets_bar(), "{} {sampler:?}:\n{acc}", path.display());
    }
    report
}

/// The scene of the cylinders and disks (`scenes/pillars.toml`: capped and open
/// cylinders, a tilted one, a coin, a ring, disks, glass and mirrors).
#[test]
fn the_cylinders_and_disks_agree_with_the_reference() {
    let report = scene_file_agrees("scenes/pillars.toml", |d| {
        assert!(!d.cylinders.is_empty() && !d.disks.is_empty());
    });
    println!("{report}");
}

/// A directional light (`scenes/examples/sun.toml`: a sun beside a point light,
/// shadows of spheres and a box on a checkered floor, a mirror). The sun's
/// shadow rays search without end, and its irradiance does not fall off.
#[test]
fn a_sun_agrees_with_the_reference() {
    let report = scene_file_agrees("scenes/examples/sun.toml", |d| {
        assert!(d.lights.iter().any(|l| l.direction.is_some()));
    });
    println!("{report}");
}

/// Rigid instances of one mesh (`scenes/examples/instances.toml`: four
/// teapots turned, scaled, one squashed and one mirrored): the core searches
/// each in the mesh's space and carries the hit into the world; the
/// reference carries the faces themselves into the world in `f64`.
#[test]
fn mesh_instances_agree_with_the_reference() {
    // The adaptive and sparse samplers take nothing of an instance's own
    // (their rule is the pixels'): left out, for the reference's cost over
    // four times a thousand faces.
    let samplers = [SAMPLERS[0], SAMPLERS[3]];
    let report = scene_file_agrees_at(
        "scenes/examples/instances.toml",
        |d| {
            assert_eq!(d.instances.len(), 4);
            assert!(d.instances.iter().any(|i| i.scale.axes()[0] < 0.0));
        },
        &samplers,
    );
    println!("{report}");
}

/// Frames of an animation (`scenes/examples/animated.toml`: a teapot turning
/// through `rotate` keyframes, a ball bouncing through translations): the
/// core's frame (the host evaluating the tracks with the core's `f32` code)
/// against the reference's, which evaluates the keyframes itself in `f64`
/// (its own search of the times and spherical interpolation) and carries the
/// meshes there on its own; mid-arc frames, between keyframes.
#[test]
fn animation_frames_agree_with_the_reference() {
    let path = tessera_tests::firmware::repo_root().join("scenes/examples/animated.toml");
    let desc = tessera_host::file::load(&path).unwrap();
    assert_eq!(desc.keyframes.len(), 2);
    let vp = Viewport::new(160, 120);
    let settings = desc.settings().unwrap();
    let mut report = String::new();
    for frame in [5u32, 13, 20] {
        let core_desc = desc.at_frame(frame).unwrap();
        let scene = core_desc.to_core().unwrap();
        let core = scene.with_view(|view| render(view, scene.camera(), vp, settings));
        let t = f64::from(frame) / desc.render.fps;
        let ref_desc = tessera_host::reference::animation::animate(&desc, t).unwrap();
        let acc = against_reference(core, &ref_desc, vp, settings);
        report.push_str(&format!("== frame {frame}\n{acc}\n"));
        assert!(acc.meets_bar(), "frame {frame}:\n{acc}");
    }
    println!("{report}");
}

/// Blender's OBJ files (`tests/data/blender/scene.toml`): the file's own vertex
/// normals (a smooth sphere, a bevelled cube, boxes with hard edges), its
/// texture coordinates under a checker (point-sampled and averaged over each
/// pixel's footprint through the mesh's uvs), turned meshes.
#[test]
fn blenders_obj_files_agree_with_the_reference() {
    let report = scene_file_agrees("tests/data/blender/scene.toml", |d| {
        assert!(d.meshes.iter().all(|m| !m.normals.is_empty()));
        assert!(d.meshes.iter().filter(|m| !m.uvs.is_empty()).count() >= 2);
    });
    println!("{report}");
}

/// Image textures (`tests/data/blender/textured.toml`: Blender's cube with its
/// PNG, bilinear; a plane tiling the same image, nearest, mirrored along `v`,
/// tinted), the texels resized to the scene's budget: the reference samples the
/// same texels in `f64`, point-sampled and averaged over each pixel's footprint.
#[test]
fn image_textures_agree_with_the_reference() {
    let report = scene_file_agrees("tests/data/blender/textured.toml", |d| {
        assert!(d.materials.iter().all(|m| matches!(
            m.texture,
            Some(tessera_host::desc::TextureDesc::Image { image: Some(_), .. })
        )));
    });
    println!("{report}");
}

/// Blender's OBJ files with their own MTL materials (`tests/data/blender/mtl.toml`:
/// a map_Kd image in RGB565, resized to the scene's budget and tinted by its Kd;
/// three materials of the file by the rule).
#[test]
fn mtl_materials_agree_with_the_reference() {
    let report = scene_file_agrees("tests/data/blender/mtl.toml", |d| {
        assert_eq!(d.meshes.len(), 4);
    });
    println!("{report}");
}

/// Files from 3D tools in one scene (`tests/data/tools.toml`): Blender's OBJ
/// with its MTL material and PNG, the Khronos BoxTextured glTF (embedded PNG)
/// and Box glTF, placed by scale, rotation (degrees and a quaternion) and
/// translation, images in RGB565.
#[test]
fn files_from_3d_tools_agree_with_the_reference() {
    let report = scene_file_agrees("tests/data/tools.toml", |d| {
        assert!(d.meshes.iter().any(|m| m.obj.ends_with(".gltf")));
        assert!(d.meshes.iter().any(|m| m.obj.ends_with(".obj")));
    });
    println!("{report}");
}

/// A glTF file as a scene of its own (`tests/data/gltf/BoxTextured`): its
/// mesh, material and embedded texture, a default camera and sun made for it.
#[test]
fn a_gltf_scene_agrees_with_the_reference() {
    let report = scene_file_agrees("tests/data/gltf/BoxTextured/BoxTextured.gltf", |d| {
        assert_eq!(d.meshes.len(), 1);
        assert!(!d.meshes[0].uvs.is_empty());
    });
    println!("{report}");
}
