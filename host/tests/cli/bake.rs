//! `tessera bake`: the generated Rust file compiles against the real core, without
//! warnings, whatever text the scene holds (material names, the scene's path);
//! `--crate` takes only what Rust accepts as a `use` path.

use crate::common::{bin, scratch, text};
use std::path::{Path, PathBuf};
use std::process::Command;

/// Material names that would end a `//` comment, trip a deny-by-default lint
/// (bidirectional-text controls) or end a string literal if written as they are.
const HOSTILE: &[&str] = &[
    "ok\npub static INJECTED: u32 = 1; compile_error!(\"injected from a material name\");",
    "cr\rpub static INJECTED_CR: u32 = 1; compile_error!(\"injected after a CR\");",
    "line\u{2028}separator\u{2029}paragraph\u{85}next line",
    "bidi \u{202a}\u{202b}\u{202c}\u{202d}\u{202e} isolates \u{2066}\u{2067}\u{2068}\u{2069} marks \u{200e}\u{200f}\u{61c}",
    "*/ pub static INJECTED_BLOCK: u32 = 1; /*",
    "\"; pub static INJECTED_QUOTE: u32 = 1; //",
    "back\\slash \\\" \\u{41} \\n",
    "nul\0byte",
    "tab\tescape\u{1b}[31m del\u{7f} bom\u{feff}",
    "émail ✓ 日本",
    "",
];

/// `s` as a TOML basic string (every character outside printable ASCII as
/// `\UXXXXXXXX`).
fn toml_string(s: &str) -> String {
    let mut out = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            ' '..='~' => out.push(c),
            c => out.push_str(&format!("\\U{:08X}", u32::from(c))),
        }
    }
    out + "\""
}

/// A scene with a triangle and a mesh per hostile material name.
fn hostile_scene() -> String {
    let mut s = String::from(
        "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\nnear = 0.1\nfar = 100\n\n\
         [[light]]\nposition = [0, 5, 5]\nintensity = 10\n\n",
    );
    for (i, name) in HOSTILE.iter().enumerate() {
        let name = toml_string(name);
        let x = i as f64;
        s += &format!(
            "[[material]]\nname = {name}\n\n\
             [[triangle]]\nvertices = [[{x}, 0, 0], [{x}.5, 0, 0], [{x}, 1, 0]]\nmaterial = {name}\n\n\
             [[mesh]]\nobj = \"tri.obj\"\nmaterial = {name}\ntranslate = [{x}, 2, 0]\n\n"
        );
    }
    s
}

/// The string literals of the generated file's comment lines, in order.
fn literals_in_comments(source: &str) -> Vec<String> {
    let mut found = Vec::new();
    for line in source.lines().filter(|l| l.starts_with("//")) {
        let mut rest = line;
        while let Some(start) = rest.find('"') {
            let body = &rest[start + 1..];
            let mut escaped = false;
            let end = body
                .char_indices()
                .find(|&(_, c)| {
                    let end = c == '"' && !escaped;
                    escaped = c == '\\' && !escaped;
                    end
                })
                .map(|(i, _)| i)
                .unwrap_or_else(|| panic!("an unterminated string literal in {line:?}"));
            found.push(format!("\"{}\"", &body[..end]));
            rest = &body[end + 1..];
        }
    }
    found
}

/// The folder in the workspace's `target/` where the compile checks build, so
/// that the core is compiled once across runs.
fn check_target_dir() -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR")).join("bake-check")
}

/// The core's features for a program that must render like this build's
/// `tessera`: `bvh`, the optional kinds (`all-kinds`), image textures, the sun,
/// mesh instances and their animation, and the math backend's features this
/// package was built with.
fn core_features() -> Vec<&'static str> {
    let mut f = vec!["bvh", "all-kinds", "image", "sun", "instances", "animation"];
    for (on, name) in [
        (cfg!(feature = "fast-math"), "fast-math"),
        (cfg!(feature = "fast-rsqrt"), "fast-rsqrt"),
        (cfg!(feature = "fast-recip"), "fast-recip"),
        (cfg!(feature = "fast-pow"), "fast-pow"),
    ] {
        if on {
            f.push(name);
        }
    }
    f
}

/// Builds and runs, with `cargo run --offline` and `-D warnings`, the program
/// `main` (the source of its `main.rs`) in a crate `dir/check` that depends on
/// the core with its features `bvh`, `all-kinds`, `image`, `sun`, `instances` and `animation` (as the host's) and this
/// build's math backend
/// ([`core_features`]), in release when `release`; returns its standard output. Panics with cargo's output if it does not compile cleanly
/// or fails. Its package is named after `dir` (a test's own scratch folder):
/// tests running at once share the target folder (the core compiled once),
/// and a package of one name would be one binary, which one test's build
/// could replace under another's run.
fn cargo_run(dir: &Path, main: &str, release: bool) -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let core = root.join("core");
    let project = dir.join("check");
    // The scratch folder's name without its random suffix.
    let folder = dir.file_name().and_then(|n| n.to_str()).unwrap_or("check");
    let name: String = folder
        .rsplit_once('-')
        .map_or(folder, |(stem, _)| stem)
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() {
                c.to_ascii_lowercase()
            } else {
                '-'
            }
        })
        .collect();
    std::fs::create_dir_all(project.join("src")).unwrap();
    std::fs::write(
        project.join("Cargo.toml"),
        format!(
            "[package]\nname = \"bake-check-{name}\"\nversion = \"0.0.0\"\nedition = \"2024\"\n\
             publish = false\n\n[dependencies]\n\
             tessera-core = {{ path = {:?}, features = {:?} }}\n\n[workspace]\n",
            core.to_str().unwrap(),
            core_features()
        ),
    )
    .unwrap();
    // The workspace's lock: the same versions of the core's dependencies, offline.
    std::fs::copy(root.join("Cargo.lock"), project.join("Cargo.lock")).unwrap();
    std::fs::write(project.join("src/main.rs"), main).unwrap();
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut args = vec!["run", "--offline", "--quiet"];
    if release {
        args.push("--release");
    }
    let out = Command::new(cargo)
        .current_dir(&project)
        .args(args)
        .env("CARGO_TARGET_DIR", check_target_dir())
        .env("RUSTFLAGS", "-D warnings")
        .env_remove("CARGO_ENCODED_RUSTFLAGS")
        .env_remove("CARGO_BUILD_RUSTFLAGS")
        .env_remove("CARGO_BUILD_TARGET")
        .output()
        .unwrap();
    let stderr = text(&out.stderr);
    assert!(
        out.status.success(),
        "the program with the baked files does not compile cleanly or fails:\n{stderr}\n\
         --- main.rs:\n{main}"
    );
    assert!(!stderr.contains("warning"), "{stderr}");
    text(&out.stdout)
}

/// Builds and runs a program in `dir` that includes the baked file `baked`,
/// checks its `SCENE` (a view and a frame), and prints the bytes of each of
/// `literals` (Rust string literals); returns the printed lines.
fn compile_and_run(dir: &Path, baked: &Path, literals: &[String]) -> Vec<String> {
    let main = format!(
        "#[path = {:?}]\nmod baked;\n\n\
         const LITERALS: &[&str] = &[\n{}];\n\n\
         fn main() {{\n    \
             let view = baked::SCENE.view().expect(\"the baked scene is valid\");\n    \
             std::hint::black_box((view, baked::SCENE.renderer().expect(\"its frame\")));\n    \
             for s in LITERALS {{\n        println!(\"{{:?}}\", s.as_bytes());\n    }}\n}}\n",
        baked.to_str().unwrap(),
        literals
            .iter()
            .map(|l| format!("    {l},\n"))
            .collect::<String>()
    );
    cargo_run(dir, &main, false)
        .lines()
        .map(str::to_string)
        .collect()
}

/// The scene files of `scenes/` and `scenes/examples/`, sorted.
fn scene_files() -> Vec<PathBuf> {
    let mut files = Vec::new();
    for dir in [
        crate::common::scenes(),
        crate::common::scenes().join("examples"),
    ] {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_some_and(|x| x == "toml") {
                files.push(p);
            }
        }
    }
    files.sort();
    files
}

/// Every scene file, baked by `tessera bake` and rendered from its `static`
/// tables by the core (at the file's size, settings and tile size, through the
/// tile loops the baker chose, `SceneLoops`), equals `tessera render FILE`
/// byte for byte.
#[test]
fn every_scene_file_baked_renders_like_tessera_render() {
    let dir = scratch("bake-every");
    let mut files = scene_files();
    assert!(files.len() >= 25, "{files:?}");
    // And a list of triangles long enough for its BVH (baked with it).
    let mut fan = String::from(
        "[camera]\nposition = [0, 0, 3]\nlook_at = [0, 0, 0]\nnear = 0.1\nfar = 100\n\n\
         [render]\nwidth = 96\nheight = 72\n\n\
         [[material]]\nname = \"fan\"\ncolor = [0.9, 0.6, 0.2]\n\n\
         [[light]]\nposition = [1, 2, 4]\nintensity = 20\n\n",
    );
    for i in 0..120 {
        let (a, b) = (i as f64 * 0.05, (i + 1) as f64 * 0.05);
        fan += &format!(
            "[[triangle]]\nvertices = [[0, 0, 0], [{:.6}, {:.6}, 0], [{:.6}, {:.6}, 0]]\n\
             material = \"fan\"\n\n",
            a.cos(),
            a.sin(),
            b.cos(),
            b.sin()
        );
    }
    std::fs::write(dir.join("fan.toml"), fan).unwrap();
    files.push(dir.join("fan.toml"));
    let mut mods = String::new();
    let mut calls = String::new();
    for (i, file) in files.iter().enumerate() {
        let baked = dir.join(format!("s{i}.rs"));
        let out = bin()
            .arg("bake")
            .arg(file)
            .arg("-o")
            .arg(&baked)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}: {}",
            file.display(),
            text(&out.stderr)
        );
        mods += &format!("#[path = {:?}]\nmod s{i};\n", baked.to_str().unwrap());
        if file.ends_with("fan.toml") {
            let text = std::fs::read_to_string(&baked).unwrap();
            assert!(
                text.contains(".with_bvh(BakedBvh::new(&NODES, &ORDER"),
                "{text}"
            );
        }
        calls += &format!(
            "    render::<{{ s{i}::TILE }}, s{i}::SceneLoops, _>(&s{i}::SCENE, \"s{i}\");\n"
        );
    }
    let out_dir = dir.join("pixels");
    std::fs::create_dir(&out_dir).unwrap();
    let main = format!(
        "{mods}\n\
         use tessera_core::{{BakedScene, Tile, TileCoord, tile::Loops}};\n\n\
         /// The scene at its own size, settings and tile size, as RGB bytes in a file.\n\
         fn render<const N: usize, L: Loops, C: tessera_core::Capacities>(\n    \
             scene: &BakedScene<'static, C>,\n    name: &str,\n) {{\n    \
             let view = scene.view().expect(\"a valid scene\");\n    \
             let renderer = scene.renderer().expect(\"a valid frame\");\n    \
             let vp = scene.viewport();\n    \
             let (w, h) = (usize::from(vp.width), usize::from(vp.height));\n    \
             let mut rgb = vec![0u8; 3 * w * h];\n    \
             let mut tile = Tile::<N>::new();\n    \
             let (cols, rows) = renderer.tile_grid(N);\n    \
             for ty in 0..rows {{\n        for tx in 0..cols {{\n            \
                 renderer.render_tile_in::<L, N, _, _>(&view, TileCoord::new(tx, ty), &mut tile, &mut ())\n                \
                     .expect(\"the loops it needs\");\n            \
                 let (x0, y0) = tile.origin();\n            \
                 for (y, row) in tile.rows().enumerate() {{\n                \
                     for (x, p) in row.iter().enumerate() {{\n                    \
                         let i = 3 * ((y0 as usize + y) * w + x0 as usize + x);\n                    \
                         rgb[i..i + 3].copy_from_slice(&[p.r, p.g, p.b]);\n                \
                     }}\n                }}\n            }}\n        }}\n    \
             std::fs::write(format!(\"{{}}/{{name}}.rgb\", {:?}), rgb).expect(\"written\");\n}}\n\n\
         fn main() {{\n{calls}}}\n",
        out_dir.to_str().unwrap()
    );
    cargo_run(&dir, &main, true);
    for (i, file) in files.iter().enumerate() {
        let png = dir.join(format!("s{i}.png"));
        let out = bin()
            .arg("render")
            .arg(file)
            .arg("-o")
            .arg(&png)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}: {}",
            file.display(),
            text(&out.stderr)
        );
        let want = image::open(&png).unwrap().to_rgb8();
        let have = std::fs::read(out_dir.join(format!("s{i}.rgb"))).unwrap();
        assert_eq!(have.len(), want.as_raw().len(), "{}: size", file.display());
        let differ = have
            .iter()
            .zip(want.as_raw())
            .filter(|(a, b)| a != b)
            .count();
        assert!(
            differ == 0,
            "{}: {differ} bytes differ between the baked scene and `tessera render`",
            file.display()
        );
    }
}

/// A baked animation, as a firmware plays it (its instances copied into RAM,
/// `ANIMATION.place` at each frame's time, `with_instances`), renders each
/// frame as `tessera render --frame N` does, byte for byte: the same `f32`
/// evaluation of the same tracks, on the baked tables.
#[test]
fn a_baked_animation_plays_the_frames_tessera_renders() {
    let dir = scratch("bake-animation");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes/examples/animated.toml");
    let baked = dir.join("scene.rs");
    let out = bin()
        .arg("bake")
        .arg(&scene)
        .arg("-o")
        .arg(&baked)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let frames = [0u32, 5, 9, 17];
    let fps = tessera_host::file::load(&scene).unwrap().render.fps;
    let out_dir = dir.join("frames");
    std::fs::create_dir(&out_dir).unwrap();
    let main = format!(
        "#[path = {:?}]\nmod scene;\n\
         use tessera_core::{{Tile, TileCoord, instance::Instances}};\n\n\
         fn main() {{\n    \
             let view = scene::SCENE.view().expect(\"a valid scene\");\n    \
             scene::ANIMATION.check(view.instance_count()).expect(\"valid tracks\");\n    \
             let rest: Vec<_> = {{\n        \
                 let i: Instances<'_, 16> = Instances::of(&view).expect(\"room\");\n        \
                 (0..i.len()).map(|k| i.get(k).expect(\"an instance\").placement).collect()\n    \
             }};\n    \
             let mut moving: Instances<'_, 16> = Instances::of(&view).expect(\"room\");\n    \
             let renderer = scene::SCENE.renderer().expect(\"a valid frame\");\n    \
             let vp = scene::SCENE.viewport();\n    \
             let (w, h) = (usize::from(vp.width), usize::from(vp.height));\n    \
             for n in {frames:?} {{\n        \
                 let t = n as f64 / {fps:?};\n        \
                 scene::ANIMATION.place(t as f32, &rest, &mut moving).expect(\"placed\");\n        \
                 let frame = view.with_instances(&moving).expect(\"its instances\");\n        \
                 let mut rgb = vec![0u8; 3 * w * h];\n        \
                 let mut tile = Tile::<{{ scene::TILE }}>::new();\n        \
                 let (cols, rows) = renderer.tile_grid(scene::TILE);\n        \
                 for ty in 0..rows {{\n            for tx in 0..cols {{\n                \
                     renderer.render_tile(&frame, TileCoord::new(tx, ty), &mut tile, &mut ()).expect(\"rendered\");\n                \
                     let (x0, y0) = tile.origin();\n                \
                     for (y, row) in tile.rows().enumerate() {{\n                    \
                         for (x, p) in row.iter().enumerate() {{\n                        \
                             let i = 3 * ((y0 as usize + y) * w + x0 as usize + x);\n                        \
                             rgb[i..i + 3].copy_from_slice(&[p.r, p.g, p.b]);\n                    \
                         }}\n                }}\n            }}\n        }}\n        \
                 std::fs::write(format!(\"{{}}/{{n}}.rgb\", {:?}), rgb).expect(\"written\");\n    \
             }}\n}}\n",
        baked.to_str().unwrap(),
        out_dir.to_str().unwrap()
    );
    cargo_run(&dir, &main, true);
    for n in frames {
        let png = dir.join(format!("f{n}.png"));
        let out = bin()
            .arg("render")
            .arg(&scene)
            .args(["--frame", &n.to_string(), "-o"])
            .arg(&png)
            .output()
            .unwrap();
        assert!(out.status.success(), "{}", text(&out.stderr));
        let want = image::open(&png).unwrap().to_rgb8();
        let have = std::fs::read(out_dir.join(format!("{n}.rgb"))).unwrap();
        assert!(
            have == want.as_raw().as_slice(),
            "frame {n}: the baked animation's frame differs"
        );
    }
}

/// Hostile material names and a scene path with a line break in a folder name:
/// the baked file compiles without a warning against the real core (the
/// `compile_error!` in a name would stop it if the name became code), every line
/// before the `use` is a comment, and the header's string literals are the
/// names themselves, as the compiler reads them.
#[test]
fn a_baked_file_with_hostile_names_compiles_and_keeps_them_inert() {
    let dir = scratch("bake-hostile");
    let folder = "scene\nfolder\u{2028}\u{202e}x";
    std::fs::create_dir(dir.join(folder)).unwrap();
    std::fs::write(
        dir.join(folder).join("tri.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
    )
    .unwrap();
    let scene = format!("{folder}/x.toml");
    std::fs::write(dir.join(&scene), hostile_scene()).unwrap();
    let out = bin()
        .current_dir(&dir)
        .args(["bake", &scene, "-o", "out.rs"])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let source = std::fs::read_to_string(dir.join("out.rs")).unwrap();
    let head: Vec<&str> = source
        .lines()
        .take_while(|l| !l.starts_with("use "))
        .collect();
    for line in &head {
        assert!(
            line.is_empty() || line.starts_with("//"),
            "not a comment: {line:?}"
        );
    }
    // Outside comments, the injected text is only ever part of a material's
    // constant (an identifier of letters, digits and `_`).
    for line in source.lines().filter(|l| !l.trim_start().starts_with("//")) {
        let code = line.split("//").next().unwrap_or("");
        for token in code.split(|c: char| !(c.is_ascii_alphanumeric() || c == '_')) {
            assert!(
                !token.contains("INJECTED") || token.starts_with("MAT_"),
                "{line:?} in\n{source}"
            );
        }
    }
    // Nothing in the file that a reader or a lint would take as a line break or
    // a reordering of the text.
    let forbidden = |c: char| {
        (c.is_control() && c != '\n')
            || matches!(c, '\u{2028}' | '\u{2029}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}')
    };
    assert!(!source.contains(forbidden), "{source}");
    // One of each kind: in the singular.
    assert!(
        source.contains(
            "// 11 materials, 1 light, 11 triangles; mesh 0: 3 vertices, 1 face, 1 BVH node;"
        ),
        "{source}"
    );
    let literals = literals_in_comments(&source);
    // The scene's path; the header's list of numbered constants (the names
    // without a letter or digit); each constant's doc comment.
    let mut want = vec![scene.clone()];
    want.extend(
        HOSTILE
            .iter()
            .filter(|s| !s.chars().any(|c| c.is_ascii_alphanumeric()))
            .map(|s| s.to_string()),
    );
    want.extend(HOSTILE.iter().map(|s| s.to_string()));
    assert_eq!(literals.len(), want.len(), "{literals:?}");
    let printed = compile_and_run(&dir, &dir.join("out.rs"), &literals);
    let want: Vec<String> = want.iter().map(|s| format!("{:?}", s.as_bytes())).collect();
    assert_eq!(printed, want);
}

/// `--crate` takes a path Rust accepts in `use`; a keyword is a usage error
/// (exit status 2) that says so, and nothing is written.
#[test]
fn bake_refuses_a_keyword_as_the_crate() {
    let dir = scratch("bake-crate");
    let scene = crate::common::scenes().join("examples/triangle.toml");
    for (krate, message) in [
        ("fn", "\"fn\" is a Rust keyword, not a crate name"),
        (
            "tessera_core::async",
            "\"async\" is a Rust keyword, not a module name",
        ),
        ("gen", "\"gen\" is a Rust keyword, not a crate name"),
        ("_", "\"_\" is a placeholder, not a crate name"),
        ("tessera_core::crate", "\"crate\" may only start a path"),
        ("r#self", "\"r#self\" cannot be a raw identifier"),
        ("tessera_core::", "an empty segment"),
        ("tes-sera", "\"tes-sera\" is not an identifier"),
    ] {
        let out = bin()
            .current_dir(&dir)
            .arg("bake")
            .arg(&scene)
            .args(["-o", "out.rs", "--crate", krate])
            .output()
            .unwrap();
        let e = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{krate}: {e}");
        assert!(e.contains("--crate") && e.contains(message), "{krate}: {e}");
        assert!(!dir.join("out.rs").exists(), "{krate}");
    }
}
