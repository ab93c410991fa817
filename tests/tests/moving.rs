//! Things that move on a baked scene: a frame's changed list, lights or
//! materials, copied into RAM and handed to the view
//! (`SceneView::with_list`, `with_lights`, `with_materials`), the rest of the
//! scene read where it lies.
//!
//! The expectation is independent of that path: the host reads the same
//! scene file, changes the same item in its description, builds its own scene
//! from it and renders it; the two pictures must be the same bytes (the
//! per-tile and shadow culling of the changed view included). The numbers
//! written into the description are the `f32` the chip's change makes, so
//! both paths build the same geometry.

use image::RgbImage;
use tessera_core::builtin::Builtin;
use tessera_core::builtin::baked::teapot;
use tessera_core::geometry::{Sphere, Triangle};
use tessera_core::light::Light;
use tessera_core::material::MaterialId;
use tessera_core::texture::Texture;
use tessera_core::{Camera, Color, Error, Primitive, SceneView, Vec3, Viewport};
use tessera_host::desc::SceneDesc;

/// A small frame of the scene's own settings and tile size.
const FRAME: Viewport = Viewport::new(96, 72);

fn scene_file(b: Builtin) -> SceneDesc {
    let path = tessera_tests::firmware::repo_root()
        .join("scenes")
        .join(format!("{}.toml", b.name()));
    tessera_host::file::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// The host's picture of `desc`, its scene built by the host.
fn host(desc: &SceneDesc) -> RgbImage {
    let scene = desc.to_core().unwrap_or_else(|e| panic!("{e}"));
    scene
        .with_view(|v| {
            tessera_host::render(
                v,
                scene.camera(),
                FRAME,
                desc.settings().unwrap(),
                desc.render.tile,
            )
        })
        .unwrap()
}

/// The picture of a (changed) view of the baked scene, in the same frame.
fn chip(view: &SceneView<'_>, camera: &Camera, desc: &SceneDesc) -> RgbImage {
    tessera_host::render(
        view,
        camera,
        FRAME,
        desc.settings().unwrap(),
        desc.render.tile,
    )
    .unwrap()
}

fn f64s(v: Vec3) -> [f64; 3] {
    v.to_array().map(f64::from)
}

fn same(a: &RgbImage, b: &RgbImage, what: &str) {
    let differ = a.pixels().zip(b.pixels()).filter(|(x, y)| x != y).count();
    assert!(differ == 0, "{what}: {differ} pixels differ");
}

/// The showcase's glass sphere lifted and a triangle moved, frame after
/// frame: the baked view with the changed lists renders what the host renders
/// of the scene file with the same items moved; the old picture differs.
#[test]
fn moved_primitives_of_a_baked_scene_render_as_the_scene_built_with_them() {
    let mut desc = scene_file(Builtin::Showcase);
    let still = host(&desc);
    Builtin::Showcase
        .with_baked_scene(|view, camera| {
            let mut spheres = view.spheres().to_vec();
            let mut triangles = view.triangles().to_vec();
            for frame in 1..=2u8 {
                let lift = Vec3::new(0.0, 0.25 * f32::from(frame), 0.0);
                let s = view.spheres()[0].geometry;
                spheres[0].geometry = Sphere::try_new(s.center() + lift, s.radius()).unwrap();
                // The triangle raised out of the others' hull, and bent.
                let [a, b, c] = view.triangles()[0].geometry.vertices();
                let up = lift * 6.0;
                let moved = Triangle::try_new(a + up, b + up, c + lift).unwrap();
                triangles[0].geometry = moved;
                let changed = view
                    .with_list(&spheres[..])
                    .and_then(|v| v.with_list(&triangles[..]))
                    .unwrap();
                // The rest of the scene is the view's.
                assert_eq!(changed.planes(), view.planes());
                assert_eq!(changed.boxes(), view.boxes());
                assert_eq!(changed.lights(), view.lights());

                desc.spheres[0].center = f64s(s.center() + lift);
                desc.triangles[0].vertices = moved.vertices().map(f64s);
                let want = host(&desc);
                let got = chip(&changed, camera, &desc);
                same(&got, &want, &format!("frame {frame}"));
                assert_ne!(got, still, "frame {frame}: nothing moved");
            }
        })
        .unwrap();
}

/// The teapot's key light moved and its glaze recoloured, by the baked
/// constants of their names: the mesh stays (no call to forget), and the
/// picture is the host's of the scene file with the same changes.
#[test]
fn moved_lights_and_recoloured_materials_keep_the_baked_mesh() {
    let mut desc = scene_file(Builtin::Teapot);
    Builtin::Teapot
        .with_baked_scene(|view, camera| {
            assert_eq!(view.meshes().len(), 1);
            let mut lights = view.lights().to_vec();
            let key = lights[teapot::LIGHT_KEY];
            let to = Vec3::new(1.5, 4.0, 3.5);
            lights[teapot::LIGHT_KEY] = Light::point(to, key.color(), key.intensity()).unwrap();
            let mut materials = view.materials().to_vec();
            let glaze = usize::from(teapot::MAT_GLAZE.0);
            let green = Color::new(0.1, 0.6, 0.2);
            materials[glaze] = materials[glaze]
                .with_texture(Texture::Solid(green))
                .unwrap();
            let changed = view
                .with_lights(&lights[..])
                .and_then(|v| v.with_materials(&materials[..]))
                .unwrap();
            assert_eq!(changed.meshes().len(), 1, "the mesh is kept");

            let light = desc
                .lights
                .iter_mut()
                .find(|l| l.name.as_deref() == Some("key"))
                .unwrap();
            light.position = f64s(to);
            let m = desc
                .materials
                .iter_mut()
                .find(|m| m.name == "glaze")
                .unwrap();
            m.color = [green.r, green.g, green.b].map(f64::from);
            same(&chip(&changed, camera, &desc), &host(&desc), "teapot");
        })
        .unwrap();
}

/// What the changes refuse: a longer list than the view's, a material out of
/// range, a hand-made item its constructor would not make, fewer materials,
/// a light of a NaN; each by the core's error, and a list of fewer items
/// hides the rest.
#[test]
fn changes_are_checked_when_set() {
    Builtin::Showcase
        .with_baked_scene(|view, _| {
            let mut more = view.spheres().to_vec();
            more.push(more[0]);
            assert!(matches!(
                view.with_list(&more[..]),
                Err(Error::CapacityExceeded { capacity, .. }) if capacity == view.spheres().len()
            ));
            let mut wrong = view.spheres().to_vec();
            wrong[1].material = MaterialId(u16::try_from(view.materials().len()).unwrap());
            assert!(matches!(
                view.with_list(&wrong[..]),
                Err(Error::MaterialOutOfRange { .. })
            ));
            let bent = [Primitive {
                geometry: Sphere::baked([0.0, f32::NAN, 0.0], 1.0),
                material: MaterialId(0),
            }];
            assert!(view.with_list(&bent[..]).is_err());
            let fewer = &view.materials()[1..];
            assert!(matches!(
                view.with_materials(fewer),
                Err(Error::MaterialOutOfRange { .. })
            ));
            let dark = [Light::baked_point([0.0; 3], Color::WHITE, f32::NAN)];
            assert!(view.with_lights(&dark[..]).is_err());
            let one = view.with_list(&view.spheres()[..1]).unwrap();
            assert_eq!(one.spheres().len(), 1);
        })
        .unwrap();
}

/// The scene file at `path` (from the workspace's root), read.
fn file(path: &str) -> SceneDesc {
    let path = tessera_tests::firmware::repo_root().join(path);
    tessera_host::file::load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// The host's picture of `desc` at its own size.
fn full(desc: &SceneDesc) -> RgbImage {
    let scene = desc.to_core().unwrap_or_else(|e| panic!("{e}"));
    scene
        .with_view(|v| {
            tessera_host::render(
                v,
                scene.camera(),
                desc.viewport(),
                desc.settings().unwrap(),
                desc.render.tile,
            )
        })
        .unwrap()
}

/// Instances of one mesh draw what meshes baked in world space draw: the
/// teapot as one instance where it lies is the teapot scene to the byte; four
/// teapots turned, scaled and moved as instances are the four meshes carried
/// there when the file is read, but for the rounding of carrying a hit point
/// back from the mesh's space (a few pixels by one level).
#[test]
fn instances_draw_what_meshes_baked_in_world_space_draw() {
    let once = full(&file("tests/data/instances/teapot-once.toml"));
    assert_eq!(once.as_raw(), full(&file("scenes/teapot.toml")).as_raw());
    let world = full(&file("tests/data/instances/teapots-world.toml"));
    let instanced = full(&file("tests/data/instances/teapots-instanced.toml"));
    let off: Vec<u8> = world
        .pixels()
        .zip(instanced.pixels())
        .map(|(a, b)| {
            a.0.iter()
                .zip(b.0)
                .map(|(x, y)| x.abs_diff(y))
                .max()
                .unwrap_or(0)
        })
        .filter(|&d| d > 0)
        .collect();
    let share = off.len() as f64 / f64::from(world.width() * world.height());
    assert!(share < 0.0005, "{} pixels differ", off.len());
    assert!(off.iter().all(|&d| d <= 2), "{off:?}");
    // Four teapots, not the mesh where it lies.
    assert_ne!(instanced.as_raw(), once.as_raw());
}

/// A frame's moved instance (`Instances::of` the scene's view, `set`, then
/// `with_instances`) renders as the scene file with that instance moved,
/// built by the host on its own; a move refused (a scale of 0) names the
/// field and leaves the instance where it was.
#[test]
fn a_moved_instance_renders_as_the_scene_file_with_it_moved() {
    use tessera_core::instance::{Instances, Placement};
    let mut desc = file("scenes/examples/instances.toml");
    let scene = desc.to_core().unwrap();
    let moved = Placement::new([0.0, 0.6, 0.0, 0.8], [0.5, 0.7, 0.5], [0.25, 0.5, -0.25]);
    let frame = scene.with_view(|view| {
        let mut placed: Instances<'_, 8> = Instances::of(view).unwrap();
        let before = placed.get(1);
        assert_eq!(
            placed.set(
                1,
                Placement {
                    scale: [0.5, 0.0, 0.5],
                    ..moved
                }
            ),
            Err(Error::OutOfRange {
                field: tessera_core::error::Field::InstanceScale,
                range: "[2^-20, 2^20] in magnitude on each axis (not 0)",
            })
        );
        assert_eq!(placed.get(1), before);
        placed.set(1, moved).unwrap();
        let v = view.with_instances(&placed).unwrap();
        chip(&v, scene.camera(), &desc)
    });
    let d = &mut desc.instances[1];
    d.rotate = None;
    d.quaternion = Some(moved.rotation.map(f64::from));
    d.scale = tessera_host::desc::ScaleDesc::Axes(moved.scale.map(f64::from));
    d.translate = moved.translation.map(f64::from);
    same(&frame, &host(&desc), "the moved instance");
    assert_ne!(
        frame.as_raw(),
        host(&file("scenes/examples/instances.toml")).as_raw()
    );
}
