//! The real `tessera` binary: the default render, a scene file, and bad input. Every
//! failure must print a clear message on stderr, exit non-zero, and leave an
//! existing output file untouched.

mod bake;
mod compare;
mod inputs;

use crate::common::{bin, scenes, scratch, temps, text};
use std::path::Path;
use std::process::Output;

#[test]
fn no_arguments_renders_the_default_scene_and_says_where() {
    let dir = scratch("default");
    let out = bin().current_dir(&dir).output().unwrap();
    assert!(out.status.success(), "stderr: {}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("chapter-reflect: 320x240"), "{stdout}");
    assert!(stdout.contains("rays/s"), "{stdout}");
    assert!(stdout.contains("wrote tessera.png"), "{stdout}");
    let img = image::open(dir.join("tessera.png")).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (320, 240));
    // Same bytes as the library renders.
    let want = tessera_core::builtin::Builtin::DEFAULT
        .with_scene(|v, c| {
            tessera_host::render(
                v,
                c,
                tessera_core::Viewport::new(320, 240),
                tessera_core::builtin::Builtin::DEFAULT.settings(),
                16,
            )
        })
        .unwrap()
        .unwrap();
    assert_eq!(img.as_raw(), want.as_raw());
}

/// `--encoding srgb`: the library's render with sRGB-encoded pixels, brighter
/// than the linear one; a wrong name is a usage error naming the choices.
#[test]
fn encoding_srgb_writes_the_librarys_srgb_render() {
    let dir = scratch("encoding");
    let out = bin()
        .current_dir(&dir)
        .args([
            "render",
            "--encoding",
            "srgb",
            "--size",
            "64x48",
            "-o",
            "s.png",
        ])
        .output()
        .unwrap();
    assert!(out.status.success(), "stderr: {}", text(&out.stderr));
    let img = image::open(dir.join("s.png")).unwrap().to_rgb8();
    let b = tessera_core::builtin::Builtin::DEFAULT;
    let render = |encoding| {
        b.with_scene(|v, c| {
            let settings = tessera_core::RenderSettings {
                encoding,
                ..b.settings()
            };
            tessera_host::render(v, c, tessera_core::Viewport::new(64, 48), settings, 16)
        })
        .unwrap()
        .unwrap()
    };
    let (srgb, linear) = (
        render(tessera_core::Encoding::Srgb),
        render(tessera_core::Encoding::Linear),
    );
    assert_eq!(img.as_raw(), srgb.as_raw());
    let sum = |i: &image::RgbImage| i.as_raw().iter().map(|&x| u64::from(x)).sum::<u64>();
    assert!(sum(&srgb) > sum(&linear));
    let e = fails(&dir, &["render", "--encoding", "gamma", "-o", "g.png"]);
    assert!(e.contains("linear or srgb"), "{e}");
}

#[test]
fn one_thread_and_many_threads_write_the_same_bytes() {
    let dir = scratch("threads");
    for (t, name) in [("1", "one.png"), ("4", "four.png")] {
        let out = bin()
            .current_dir(&dir)
            .args([
                "render",
                "showcase",
                "--size",
                "97x61",
                "--sampler",
                "stratified:2",
            ])
            .args(["--threads", t, "--tile", "8", "-o", name])
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", text(&out.stderr));
    }
    let a = std::fs::read(dir.join("one.png")).unwrap();
    let b = std::fs::read(dir.join("four.png")).unwrap();
    assert_eq!(a, b);
}

#[test]
fn a_scene_file_renders_with_its_own_settings() {
    let dir = scratch("file");
    let scene = scenes().join("chapter-direct.toml");
    let out = bin()
        .current_dir(&dir)
        .arg("render")
        .arg(&scene)
        .args(["--size", "64x48", "-o", "f.png"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let img = image::open(dir.join("f.png")).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (64, 48));
}

/// `render --frame N` renders frame N of a scene file's animation (the time
/// N / fps): the library's render of the file's scene at that frame; frames
/// differ; `--frame` of a scene without keyframes (a built-in scene) is an
/// error that says so and keeps the output.
#[test]
fn render_frame_renders_that_frame_of_the_animation() {
    let dir = scratch("frame");
    let scene = scenes().join("examples/animated.toml");
    let render = |n: &str, out: &str| {
        let o = bin()
            .current_dir(&dir)
            .arg("render")
            .arg(&scene)
            .args(["--frame", n, "--size", "80x60", "-o", out])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", text(&o.stderr));
        image::open(dir.join(out)).unwrap().to_rgb8()
    };
    let f7 = render("7", "f7.png");
    let desc = tessera_host::file::load(&scene)
        .unwrap()
        .at_frame(7)
        .unwrap();
    let s = desc.to_core().unwrap();
    let want = s
        .with_view(|v| {
            tessera_host::render(
                v,
                s.camera(),
                tessera_core::Viewport::new(80, 60),
                desc.settings().unwrap(),
                desc.render.tile,
            )
        })
        .unwrap();
    assert_eq!(f7.as_raw(), want.as_raw());
    assert_ne!(f7.as_raw(), render("8", "f8.png").as_raw());
    let stderr = fails(
        &dir,
        &["render", "showcase", "--frame", "3", "-o", "out.png"],
    );
    assert!(stderr.contains("no animation"), "{stderr}");
}

/// The animated example at 4 frames a second (its 2 seconds: frames 0 to 8),
/// written with its sphere's OBJ file in `dir`; its path and description.
fn animated_at_4_fps(dir: &Path) -> (String, tessera_host::desc::SceneDesc) {
    let examples = scenes().join("examples");
    let body = std::fs::read_to_string(examples.join("animated.toml"))
        .unwrap()
        .replace("fps = 12", "fps = 4");
    assert!(body.contains("fps = 4"));
    std::fs::copy(examples.join("icosphere.obj"), dir.join("icosphere.obj")).unwrap();
    let scene = write(dir, "anim4.toml", &body);
    let desc = tessera_host::file::load(Path::new(&scene)).unwrap();
    (scene, desc)
}

/// The frames of the GIF at `path`: each as RGB, and its delay in ms.
fn gif_frames(path: &Path) -> Vec<(image::RgbImage, u32)> {
    use image::AnimationDecoder;
    let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
    let frames = image::codecs::gif::GifDecoder::new(file)
        .unwrap()
        .into_frames()
        .collect_frames()
        .unwrap();
    frames
        .into_iter()
        .map(|f| {
            let (num, den) = f.delay().numer_denom_ms();
            let rgb = image::DynamicImage::ImageRgba8(f.into_buffer()).to_rgb8();
            (rgb, num / den)
        })
        .collect()
}

/// `simulate --animate` plays a scene file's keyframes: a GIF of every frame
/// from 0 to the one at the animation's end (its last keyframe's time times
/// fps), each frame lasting the scene's frame time (1000 / fps ms), each the
/// panel of the still scene at that frame (the library's `at_frame`, drawn
/// by `simulate_labelled` with the frame's label, then made a one-frame GIF
/// the same way).
#[test]
fn simulate_animate_plays_the_scene_files_keyframes_as_a_gif() {
    let dir = scratch("animate");
    let (scene, desc) = animated_at_4_fps(&dir);
    let out = bin()
        .current_dir(&dir)
        .args(["simulate", &scene, "--animate", "--size", "40x30"])
        .args(["--label", "f {frame}"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(stdout.contains("wrote simulator-animation.gif"), "{stdout}");
    let frames = gif_frames(&dir.join("simulator-animation.gif"));
    // 2 s at 4 fps: frames 0, 0.25 s, ..., 2 s.
    let duration = desc.duration().unwrap();
    assert_eq!(duration, 2.0);
    let last = (duration * desc.render.fps) as usize;
    assert_eq!(frames.len(), last + 1);
    let vp = tessera_core::Viewport::new(40, 30);
    let settings = desc.settings().unwrap();
    for (k, (img, delay)) in frames.iter().enumerate() {
        // 1000 / 4 fps = 250 ms, 25 hundredths.
        assert_eq!(*delay, 250, "frame {k}");
        let at = desc.at_frame(k as u32).unwrap();
        let s = at.to_core().unwrap();
        let still = s.with_view(|v| {
            let r = tessera_core::Renderer::try_new(s.camera(), vp, settings).unwrap();
            tessera_host::simulate::simulate_labelled(
                v,
                &r,
                tessera_host::simulate::PanelColor::Rgb565,
                desc.render.tile,
                Some(tessera_core::dither::Dither::Bayer4),
                Some(&format!("f {k}")),
            )
            .unwrap()
        });
        let one = dir.join(format!("still-{k}.gif"));
        std::fs::write(&one, tessera_host::simulate::gif(&[still], 250).unwrap()).unwrap();
        let want = gif_frames(&one);
        assert_eq!(img.as_raw(), want[0].0.as_raw(), "frame {k}");
    }
    // The frames move: the first and the middle differ.
    assert_ne!(frames[0].0.as_raw(), frames[last / 2].0.as_raw());
    // --delay-ms overrides the frame time.
    let out = bin()
        .current_dir(&dir)
        .args(["simulate", &scene, "--animate", "--size", "16x12"])
        .args(["--delay-ms", "120", "-o", "d.gif"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let delays: Vec<u32> = gif_frames(&dir.join("d.gif")).iter().map(|f| f.1).collect();
    assert_eq!(delays, vec![120; last + 1]);
}

/// `simulate --animate` to numbered PNGs on an exact panel (rgb888, no
/// dithering): frame k is, byte for byte, what `tessera render --frame k`
/// writes, for each of the 9 frames (2 s at 4 fps), and no more.
#[test]
fn simulate_animate_frames_are_the_render_of_each_frame() {
    let dir = scratch("animate-png");
    let (scene, _) = animated_at_4_fps(&dir);
    let out = bin()
        .current_dir(&dir)
        .args(["simulate", &scene, "--animate", "--size", "40x30"])
        .args(["--color", "rgb888", "--dither", "none", "-o", "p.png"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("9 frame(s)"));
    assert!(!dir.join("p-009.png").exists());
    for k in 0..9 {
        let name = format!("r{k}.png");
        let o = bin()
            .current_dir(&dir)
            .args([
                "render",
                &scene,
                "--frame",
                &k.to_string(),
                "--size",
                "40x30",
            ])
            .args(["-o", &name])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", text(&o.stderr));
        let want = image::open(dir.join(&name)).unwrap().to_rgb8();
        let got = image::open(dir.join(format!("p-{k:03}.png")))
            .unwrap()
            .to_rgb8();
        assert_eq!(got.as_raw(), want.as_raw(), "frame {k}");
    }
}

/// `--animate` with `--orbit` is a usage error naming both; on a scene
/// without keyframes (a scene file, a built-in) an error naming the scene;
/// an animation of more frames than the limit is refused, naming the count.
#[test]
fn simulate_animate_refuses_what_it_cannot_play() {
    let dir = scratch("animate-bad");
    let e = fails(
        &dir,
        &["simulate", "--animate", "--orbit", "3", "-o", "out.png"],
    );
    assert!(e.contains("--animate") && e.contains("--orbit"), "{e}");
    let still = scenes().join("chapter-direct.toml");
    let still = still.to_str().unwrap();
    let e = fails(&dir, &["simulate", still, "--animate", "-o", "out.png"]);
    assert!(
        e.contains("chapter-direct.toml") && e.contains("no animation (no [[keyframes]])"),
        "{e}"
    );
    let e = fails(
        &dir,
        &["simulate", "showcase", "--animate", "-o", "out.png"],
    );
    assert!(e.contains("showcase") && e.contains("no animation"), "{e}");
    // 2 s at 2000 fps: 4001 frames.
    animated_at_4_fps(&dir);
    let fast = std::fs::read_to_string(dir.join("anim4.toml"))
        .unwrap()
        .replace("fps = 4", "fps = 2000");
    let scene = write(&dir, "fast.toml", &fast);
    let e = fails(&dir, &["simulate", &scene, "--animate", "-o", "out.png"]);
    assert!(
        e.contains(
            "--animate: the animation lasts 2 s, 4001 frames at 2000 fps: it plays at most \
             3600 frames"
        ),
        "{e}"
    );
}

/// Writes `anim.gltf` and its `anim.bin` in `dir`: a box 2 x 1 x 0.5 (12
/// triangles) on a node turned by its first animation from the identity to a
/// quarter about Y and moved from (0, 0, 0) to (1, 0.5, 0) in one second,
/// seen from (0, 1, 5) down -Z, lit by a sun and a point light. Its path.
fn animated_gltf(dir: &Path) -> String {
    let corner = |i: u16| {
        let s = |bit: u16| if i >> bit & 1 == 1 { 1.0f32 } else { -1.0 };
        [s(0), 0.5 * s(1), 0.25 * s(2)]
    };
    let corners: Vec<[f32; 3]> = (0..8).map(corner).collect();
    let mut indices: Vec<u16> = Vec::new();
    for q in [
        [0u16, 2, 6, 4],
        [1, 3, 7, 5],
        [0, 1, 5, 4],
        [2, 3, 7, 6],
        [0, 1, 3, 2],
        [4, 5, 7, 6],
    ] {
        for t in [[q[0], q[1], q[2]], [q[0], q[2], q[3]]] {
            let [a, b, c] = t.map(|i| corners[usize::from(i)]);
            let (u, v) = (
                [0, 1, 2].map(|k| b[k] - a[k]),
                [0, 1, 2].map(|k| c[k] - a[k]),
            );
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            let outward: f32 = (0..3).map(|k| n[k] * (a[k] + b[k] + c[k])).sum();
            indices.extend(if outward > 0.0 { t } else { [t[0], t[2], t[1]] });
        }
    }
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let floats = |v: &[f32]| v.iter().flat_map(|x| x.to_le_bytes()).collect::<Vec<u8>>();
    let parts: Vec<Vec<u8>> = vec![
        floats(&corners.concat()),
        indices.iter().flat_map(|i| i.to_le_bytes()).collect(),
        floats(&[0.0, 1.0]),
        floats(&[0.0, 0.0, 0.0, 1.0, 0.5, 0.0]),
        floats(&[0.0, 0.0, 0.0, 1.0, 0.0, h, 0.0, h]),
    ];
    let mut bin = Vec::new();
    let mut views = Vec::new();
    for p in &parts {
        views.push(format!(
            r#"{{"buffer":0,"byteOffset":{},"byteLength":{}}}"#,
            bin.len(),
            p.len()
        ));
        bin.extend_from_slice(p);
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
    }
    std::fs::write(dir.join("anim.bin"), &bin).unwrap();
    let text = format!(
        r#"{{"asset":{{"version":"2.0"}},
        "buffers":[{{"byteLength":{},"uri":"anim.bin"}}],"bufferViews":[{}],
        "accessors":[
          {{"bufferView":0,"componentType":5126,"type":"VEC3","count":8,"min":[-1,-0.5,-0.25],"max":[1,0.5,0.25]}},
          {{"bufferView":1,"componentType":5123,"type":"SCALAR","count":36}},
          {{"bufferView":2,"componentType":5126,"type":"SCALAR","count":2,"min":[0],"max":[1]}},
          {{"bufferView":3,"componentType":5126,"type":"VEC3","count":2}},
          {{"bufferView":4,"componentType":5126,"type":"VEC4","count":2}}],
        "meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1,"material":0}}]}}],
        "materials":[{{"name":"clay","pbrMetallicRoughness":{{"baseColorFactor":[0.8,0.45,0.2,1],"metallicFactor":0,"roughnessFactor":1}}}}],
        "cameras":[{{"type":"perspective","perspective":{{"yfov":0.8,"znear":0.1,"zfar":50,"aspectRatio":1.3333334}}}}],
        "extensionsUsed":["KHR_lights_punctual"],
        "extensions":{{"KHR_lights_punctual":{{"lights":[{{"type":"directional","intensity":1.5}},{{"type":"point","intensity":4}}]}}}},
        "nodes":[{{"name":"box","mesh":0}},{{"camera":0,"translation":[0,1,5]}},
          {{"rotation":[-0.3826834,0,0,0.9238795],"extensions":{{"KHR_lights_punctual":{{"light":0}}}}}},
          {{"translation":[-2,2,2],"extensions":{{"KHR_lights_punctual":{{"light":1}}}}}}],
        "scenes":[{{"nodes":[0,1,2,3]}}],
        "animations":[{{"name":"turn","channels":[
            {{"sampler":0,"target":{{"node":0,"path":"translation"}}}},
            {{"sampler":1,"target":{{"node":0,"path":"rotation"}}}}],
          "samplers":[{{"input":2,"output":3}},{{"input":2,"output":4}}]}}]}}"#,
        bin.len(),
        views.join(",")
    );
    write(dir, "anim.gltf", &text)
}

/// `tessera render anim.gltf --frame N` plays the glTF file's animation: its
/// frames agree with the f64 reference's render of the file's scene at that
/// time (the reference's own evaluation of the keyframes) under the accuracy
/// bar, and the box moves (frame 15 differs from frame 0).
#[test]
fn render_frame_of_a_gltf_animation_agrees_with_the_reference() {
    let dir = scratch("gltf-frame");
    let scene = animated_gltf(&dir);
    let desc = tessera_host::file::load_gltf(Path::new(&scene), None).unwrap();
    assert_eq!((desc.instances.len(), desc.keyframes.len()), (1, 2));
    let vp = tessera_core::Viewport::new(80, 60);
    let settings = desc.settings().unwrap();
    let render = |n: u32| {
        let out = format!("g{n}.png");
        let o = bin()
            .current_dir(&dir)
            .args([
                "render",
                &scene,
                "--frame",
                &n.to_string(),
                "--size",
                "80x60",
                "-o",
                &out,
            ])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", text(&o.stderr));
        image::open(dir.join(out)).unwrap().to_rgb8()
    };
    for n in [15u32, 30] {
        let img = render(n);
        let t = f64::from(n) / desc.render.fps;
        let at = tessera_host::reference::animation::animate(&desc, t).unwrap();
        let r = tessera_host::reference::render(&at, vp, &settings).unwrap();
        let acc =
            tessera_host::compare::measure(&img, 0, &r.to_rgb8(), r.non_finite(), &r.signature)
                .unwrap();
        assert!(acc.meets_bar(), "frame {n}:\n{acc}");
    }
    assert_ne!(render(0).as_raw(), render(15).as_raw());
}

/// A value that looks like a mistake (fovy in radians) is rendered as written,
/// with a warning on stderr that names the file and says what it looks like.
#[test]
fn a_fovy_in_radians_renders_with_a_warning() {
    let dir = scratch("warn");
    let body = std::fs::read_to_string(scenes().join("chapter-direct.toml"))
        .unwrap()
        .replace("fovy = 60.0", "fovy = 1.05");
    assert!(body.contains("fovy = 1.05"));
    let scene = write(&dir, "radians.toml", &body);
    let out = bin()
        .current_dir(&dir)
        .args(["render", &scene, "--size", "16x12", "-o", "w.png"])
        .output()
        .unwrap();
    let stderr = text(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning")
            && stderr.contains("radians.toml")
            && stderr.contains("fovy 1.05 is less than pi degrees: it looks like radians"),
        "{stderr}"
    );
    assert!(dir.join("w.png").exists());
}

/// Runs the binary on bad input with an existing output file and checks the
/// failure contract; returns stderr.
fn fails(dir: &Path, args: &[&str]) -> String {
    let out_png = dir.join("out.png");
    std::fs::write(&out_png, b"precious").unwrap();
    let out: Output = bin().current_dir(dir).args(args).output().unwrap();
    let stderr = text(&out.stderr);
    assert!(!out.status.success(), "{args:?} succeeded");
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert!(
        !stderr.contains("Error {") && !stderr.contains("Some("),
        "{stderr}"
    );
    assert_eq!(
        std::fs::read(&out_png).unwrap(),
        b"precious",
        "{args:?} touched the output"
    );
    let leftovers = temps(dir);
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");
    stderr
}

fn write(dir: &Path, name: &str, body: &str) -> String {
    let p = dir.join(name);
    std::fs::write(&p, body).unwrap();
    p.to_string_lossy().into_owned()
}

const HEAD: &str = r#"
[camera]
position = [0.0, 0.0, 5.0]
look_at = [0.0, 0.0, 0.0]
near = 0.1
far = 100.0

[[material]]
name = "m"
"#;

#[test]
fn bad_input_gives_a_clear_message_and_keeps_the_output() {
    let dir = scratch("bad");
    let e = fails(&dir, &["render", "missing.toml", "-o", "out.png"]);
    assert!(e.contains("missing.toml"), "{e}");

    let e = fails(&dir, &["render", "no-such-scene", "-o", "out.png"]);
    assert!(e.contains("no-such-scene") && e.contains("built-in"), "{e}");

    let f = write(&dir, "syntax.toml", "[camera\nposition = [0, 0, 5]\n");
    let e = fails(&dir, &["render", &f, "-o", "out.png"]);
    assert!(e.contains("syntax.toml:1:"), "{e}");

    let f = write(
        &dir,
        "unknown.toml",
        &format!("{HEAD}\n[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradiuss = 1.0\nmaterial = \"m\"\n"),
    );
    let e = fails(&dir, &["render", &f, "-o", "out.png"]);
    assert!(e.contains("unknown.toml:") && e.contains("radiuss"), "{e}");

    let f = write(
        &dir,
        "nan.toml",
        &format!("{HEAD}\n[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = nan\nmaterial = \"m\"\n"),
    );
    let e = fails(&dir, &["render", &f, "-o", "out.png"]);
    assert!(e.contains("sphere 1") && e.contains("NaN"), "{e}");

    let f = write(
        &dir,
        "negative.toml",
        &format!(
            "{HEAD}\n[[sphere]]\ncenter = [0.0, 0.0, 0.0]\nradius = 1.0\nmaterial = \"m\"\n\n[[sphere]]\ncenter = [1.0, 0.0, 0.0]\nradius = -1.0\nmaterial = \"m\"\n"
        ),
    );
    let e = fails(&dir, &["render", &f, "-o", "out.png"]);
    assert!(
        e.contains("sphere 2: sphere radius must be > 0, got -1"),
        "{e}"
    );

    let mut many = HEAD.to_string();
    for i in 0..1025 {
        many.push_str(&format!(
            "\n[[sphere]]\ncenter = [{i}.0, 0.0, 0.0]\nradius = 0.5\nmaterial = \"m\"\n"
        ));
    }
    let f = write(&dir, "many.toml", &many);
    let e = fails(&dir, &["render", &f, "-o", "out.png"]);
    assert!(
        e.contains("sphere 1025") && e.contains("at most 1024"),
        "{e}"
    );

    let e = fails(&dir, &["render", "--size", "0x10", "-o", "out.png"]);
    assert!(e.contains("--size"), "{e}");
    let e = fails(&dir, &["render", "--sampler", "random:0", "-o", "out.png"]);
    assert!(e.contains("random"), "{e}");
    let e = fails(&dir, &["render", "--depth", "9", "-o", "out.png"]);
    assert!(e.contains("expected a depth from 0 to 8"), "{e}");
    let e = fails(&dir, &["render", "--tile", "12", "-o", "out.png"]);
    assert!(e.contains("8, 16 or 32"), "{e}");
}

#[test]
fn unwritable_output_is_an_error_that_names_the_file() {
    let dir = scratch("unwritable");
    let target = dir.join("no-such-folder").join("x.png");
    let t = target.to_string_lossy().into_owned();
    let e = fails(&dir, &["render", "--size", "16x16", "-o", &t]);
    assert!(e.contains("cannot write") && e.contains("x.png"), "{e}");
    // The path that failed is the temporary file's, in the missing folder.
    assert!(
        e.contains("creating the temporary file") && e.contains("no-such-folder/.tessera-"),
        "{e}"
    );
    // A folder in the way of the file.
    std::fs::create_dir_all(dir.join("taken.png")).unwrap();
    let e = fails(&dir, &["render", "--size", "16x16", "-o", "taken.png"]);
    assert!(e.contains("taken.png"), "{e}");
}

#[test]
fn compare_prints_the_figures_and_writes_a_heatmap() {
    let dir = scratch("compare");
    let out = bin()
        .current_dir(&dir)
        .args([
            "compare",
            "chapter-direct",
            "--size",
            "80x60",
            "--heatmap",
            "h.png",
        ])
        .output()
        .unwrap();
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}", text(&out.stderr));
    for key in [
        "PSNR",
        "mean FLIP",
        "max abs difference",
        "within 0 / 1 / 2 LSB",
        "NaN/Inf",
    ] {
        assert!(stdout.contains(key), "{key} missing: {stdout}");
    }
    let map = image::open(dir.join("h.png")).unwrap().to_rgb8();
    assert_eq!(map.dimensions(), (80, 60));
}

#[test]
fn simulate_saves_what_a_240x240_rgb565_panel_shows() {
    use embedded_graphics_core::pixelcolor::{Rgb565, Rgb888, RgbColor};
    let dir = scratch("simulate");
    let out = bin()
        .current_dir(&dir)
        .args(["simulate", "-o", "panel.png"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("240x240") && stdout.contains("panel colour rgb565, dither bayer4"),
        "{stdout}"
    );
    // Each colour named so, none after a wrong article ("an gray8").
    let out = bin()
        .current_dir(&dir)
        .args([
            "simulate", "--color", "gray8", "--size", "8x8", "-o", "g.png",
        ])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("panel colour gray8") && !stdout.contains(" an "),
        "{stdout}"
    );
    let shown = image::open(dir.join("panel.png")).unwrap().to_rgb8();
    assert_eq!(shown.dimensions(), (240, 240));
    let b = tessera_core::builtin::Builtin::DEFAULT;
    let host = b
        .with_scene(|v, c| {
            tessera_host::render(
                v,
                c,
                tessera_core::Viewport::new(240, 240),
                b.settings(),
                16,
            )
        })
        .unwrap()
        .unwrap();
    // Dithered by default (bayer4 at each pixel's position).
    for ((x, y, s), h) in shown.enumerate_pixels().zip(host.pixels()) {
        let p = tessera_core::color::Rgb8::new(h[0], h[1], h[2]);
        let (r, g, b) = tessera_core::dither::Dither::Bayer4.rgb565(p, x, y);
        let want: Rgb888 = Rgb565::new(r, g, b).into();
        assert_eq!(s.0, [want.r(), want.g(), want.b()], "({x}, {y})");
    }
    // `--dither none`: embedded-graphics' own conversion, the nearest level.
    let out = bin()
        .current_dir(&dir)
        .args(["simulate", "--dither", "none", "-o", "near.png"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let near = image::open(dir.join("near.png")).unwrap().to_rgb8();
    for (s, h) in near.pixels().zip(host.pixels()) {
        let want: Rgb888 = Rgb565::from(Rgb888::new(h[0], h[1], h[2])).into();
        assert_eq!(s.0, [want.r(), want.g(), want.b()]);
    }
    let e = fails(&dir, &["simulate", "--dither", "floyd", "-o", "f.png"]);
    assert!(e.contains("bayer4"), "{e}");
    // An orbit as an animated GIF.
    let out = bin()
        .current_dir(&dir)
        .args(["simulate", "--orbit", "3", "--size", "32x32", "-o", "o.gif"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let gif = std::fs::read(dir.join("o.gif")).unwrap();
    assert_eq!(&gif[..6], b"GIF89a");
    let e = fails(&dir, &["simulate", "--color", "rgb999", "-o", "out.png"]);
    assert!(e.contains("rgb565"), "{e}");
}

#[test]
fn compare_exits_non_zero_when_the_bar_is_not_met() {
    // A checkerboard of a million squares per unit: the f32 core and the f64
    // reference disagree on the parity of some squares, far from any silhouette.
    let dir = scratch("compare-bar");
    let body = std::fs::read_to_string(scenes().join("examples/texture-checker.toml")).unwrap();
    let body = body.replace("scale = 2 }", "scale = 1e6 }");
    assert!(body.contains("scale = 1e6"));
    std::fs::write(dir.join("fine.toml"), body).unwrap();
    let out = bin()
        .current_dir(&dir)
        .args([
            "compare",
            "fine.toml",
            "--size",
            "64x48",
            "--heatmap",
            "h.png",
        ])
        .output()
        .unwrap();
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert_eq!(out.status.code(), Some(1), "{stdout}{stderr}");
    assert!(stdout.contains("): NOT met"), "{stdout}");
    assert!(
        stderr.contains("fine.toml: the accuracy bar is NOT met") && stderr.contains("needs"),
        "{stderr}"
    );
    // The heat-map, where to look, is still written.
    assert!(stdout.contains("wrote h.png"), "{stdout}");
    assert_eq!(image::open(dir.join("h.png")).unwrap().width(), 64);
}

/// How outputs are written, what inputs may be, the limits and the exit status:
/// said once, in `tessera --help` and the manual page, which each command's own
/// `--help` points to.
#[test]
fn the_help_says_how_outputs_are_written() {
    let flat = |s: &str| s.split_whitespace().collect::<Vec<_>>().join(" ");
    let top = flat(&text(&bin().arg("--help").output().unwrap().stdout));
    let man = text(&bin().arg("man").output().unwrap().stdout);
    let man = flat(&man.replace(r"\-", "-").replace(r"\*(Aq", "'"));
    for key in [
        "A symbolic link is followed: the file it names is written",
        "a link to a folder is refused",
        "every file the command reads: the scene file and its meshes' OBJ files",
        "--threads at most 256",
        "a FIFO, a device, a socket or a folder is refused at once",
        "when compare's accuracy bar is not met",
    ] {
        assert!(top.contains(key), "tessera --help lacks {key:?}: {top}");
        assert!(man.contains(key), "tessera man lacks {key:?}: {man}");
    }
    for cmd in ["render", "compare", "simulate", "bake"] {
        let out = bin().args([cmd, "--help"]).output().unwrap();
        let help = flat(&text(&out.stdout));
        assert!(
            help.contains("output files, inputs, limits, exit status): `tessera --help`"),
            "{cmd} --help does not say where: {help}"
        );
    }
}

/// A value clap quotes back (an invalid value, an unknown argument, an unknown
/// subcommand) reaches the terminal escaped, as values from scene files do: a
/// window-title sequence in `--sampler` is shown as text. Colours are forced on
/// (`CLICOLOR_FORCE`), as on a terminal, where clap passes what it quotes through.
#[test]
fn values_clap_quotes_back_are_escaped() {
    let title = "x\u{1b}]0;pwned\u{7}";
    for args in [
        vec!["render", "--sampler", title],
        vec!["render", "--size", title],
        vec!["compare", "--encoding", title],
        vec!["simulate", "--dither", title],
        vec!["render", &format!("--samp{title}")],
        vec![title],
    ] {
        let out = bin()
            .args(&args)
            .env("CLICOLOR_FORCE", "1")
            .output()
            .unwrap();
        let stderr = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            !stderr.contains("\u{1b}]") && !stderr.contains('\u{7}'),
            "{args:?}: a raw sequence reached the terminal: {stderr:?}"
        );
        assert!(
            stderr.contains(r"x\u{1b}]0;pwned\u{7}"),
            "{args:?}: {stderr:?}"
        );
    }
    // Help is printed as it is, on stdout.
    let out = bin().args(["render", "--help"]).output().unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert!(text(&out.stdout).contains("--sampler"));
}

/// A glTF file renders as a scene: with its camera chosen by name, the same
/// bytes as with its first (the file has one); a name it does not have, or
/// `--camera` with a scene that is not glTF, is refused by name and writes
/// nothing.
#[test]
fn a_gltf_file_renders_with_its_camera_by_name() {
    let dir = scratch("gltf");
    let file = scenes()
        .join("../tests/data/gltf/Cameras/Cameras.gltf")
        .display()
        .to_string();
    let render = |camera: Option<&str>, out: &str| {
        let mut cmd = bin();
        cmd.current_dir(&dir)
            .args(["render", &file, "--size", "32x32", "-o", out]);
        if let Some(c) = camera {
            cmd.args(["--camera", c]);
        }
        cmd.output().unwrap()
    };
    let first = render(None, "first.png");
    assert!(first.status.success(), "stderr: {}", text(&first.stderr));
    let named = render(Some("camera 0"), "named.png");
    assert!(named.status.success(), "stderr: {}", text(&named.stderr));
    assert_eq!(
        std::fs::read(dir.join("first.png")).unwrap(),
        std::fs::read(dir.join("named.png")).unwrap()
    );
    let e = fails(&dir, &["render", &file, "--camera", "nope", "-o", "x.png"]);
    assert!(
        e.contains("no perspective camera named 'nope'") && e.contains("'camera 0'"),
        "{e}"
    );
    let e = fails(
        &dir,
        &["render", "showcase", "--camera", "x", "-o", "x.png"],
    );
    assert!(e.contains("names a glTF file's camera"), "{e}");
    assert!(!dir.join("x.png").exists());
}
