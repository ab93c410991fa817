//! Output files: what `-o` may replace, symbolic links, long names, the inputs
//! (the scene, its OBJ files), all-or-nothing orbit frames, and no temporary file
//! left behind by an error, a file size limit, SIGINT or SIGTERM.

use crate::common::{self, bin, entries, scenes, scratch, temps, text};
use std::path::Path;
use std::process::Output;

fn run(dir: &Path, args: &[&str]) -> Output {
    bin().current_dir(dir).args(args).output().unwrap()
}

/// Runs `args` in `dir`; it must fail with status 1 and a message containing
/// `message`.
fn refused(dir: &Path, args: &[&str], message: &str) {
    let out = run(dir, args);
    let e = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{args:?}: {e}");
    assert!(e.contains(message), "{args:?}: {e}");
}

/// True when `p` is itself a symbolic link (dangling or not).
fn is_link(p: &Path) -> bool {
    std::fs::symlink_metadata(p).is_ok_and(|m| m.is_symlink())
}

fn is_png(p: &Path) -> bool {
    std::fs::read(p).is_ok_and(|b| b.starts_with(b"\x89PNG"))
}

#[test]
fn a_long_output_name_is_written() {
    // 250 characters: a valid name, whatever the temporary file's name.
    let dir = scratch("long");
    let name = format!("{}.png", "n".repeat(246));
    assert_eq!(name.len(), 250);
    let out = run(&dir, &["render", "--size", "16x16", "-o", &name]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(is_png(&dir.join(&name)));
    assert_eq!(entries(&dir), vec![name]);
}

#[test]
fn an_output_that_is_not_a_regular_file_is_refused() {
    let dir = scratch("fifo");
    let fifo = dir.join("pipe.png");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    refused(
        &dir,
        &["render", "--size", "16x16", "-o", "pipe.png"],
        "refusing to write pipe.png: it is a FIFO",
    );
    use std::os::unix::fs::FileTypeExt;
    assert!(
        std::fs::symlink_metadata(&fifo)
            .unwrap()
            .file_type()
            .is_fifo()
    );
    assert_eq!(entries(&dir), vec!["pipe.png"]);
    // (Devices are checked without writing by the library's unit tests: a test
    // here would replace /dev/null when run as root if the check broke.)
}

#[test]
fn a_symbolic_link_is_written_through_and_stays() {
    use std::os::unix::fs::symlink;
    let dir = scratch("links");
    std::fs::create_dir(dir.join("sub")).unwrap();
    // To a file: the file gets the image, the link stays a link.
    std::fs::write(dir.join("sub/real.png"), b"old").unwrap();
    symlink("sub/real.png", dir.join("link.png")).unwrap();
    let out = run(&dir, &["render", "--size", "16x16", "-o", "link.png"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(is_link(&dir.join("link.png")));
    assert!(is_png(&dir.join("sub/real.png")));
    // Dangling, through a chain of two links: the file is created where it points.
    symlink("sub/new.png", dir.join("dangling.png")).unwrap();
    symlink("dangling.png", dir.join("chain.png")).unwrap();
    let out = run(&dir, &["render", "--size", "16x16", "-o", "chain.png"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(is_link(&dir.join("chain.png")) && is_link(&dir.join("dangling.png")));
    assert!(is_png(&dir.join("sub/new.png")));
    // To a folder: refused, the link and the folder untouched.
    symlink("sub", dir.join("folder.png")).unwrap();
    refused(
        &dir,
        &["render", "--size", "16x16", "-o", "folder.png"],
        "refusing to write folder.png: it is a folder (the symbolic link's target sub)",
    );
    assert!(is_link(&dir.join("folder.png")));
    assert_eq!(entries(&dir.join("sub")), vec!["new.png", "real.png"]);
    assert!(temps(&dir).is_empty() && temps(&dir.join("sub")).is_empty());
}

#[test]
fn the_input_scene_is_never_the_output() {
    let dir = scratch("input");
    let scene = std::fs::read(scenes().join("chapter-direct.toml")).unwrap();
    std::fs::write(dir.join("scene.toml"), &scene).unwrap();
    std::fs::hard_link(dir.join("scene.toml"), dir.join("alias.png")).unwrap();
    std::os::unix::fs::symlink("scene.toml", dir.join("link.png")).unwrap();
    for args in [
        vec![
            "render",
            "scene.toml",
            "--size",
            "16x16",
            "-o",
            "scene.toml",
        ],
        vec![
            "render",
            "scene.toml",
            "--size",
            "16x16",
            "-o",
            "./scene.toml",
        ],
        vec!["render", "scene.toml", "--size", "16x16", "-o", "alias.png"],
        vec!["render", "scene.toml", "--size", "16x16", "-o", "link.png"],
        vec![
            "compare",
            "scene.toml",
            "--size",
            "16x16",
            "--heatmap",
            "scene.toml",
        ],
        vec![
            "simulate",
            "scene.toml",
            "--size",
            "16x16",
            "-o",
            "scene.toml",
        ],
    ] {
        refused(&dir, &args, "it is the input scene file scene.toml");
        assert_eq!(
            std::fs::read(dir.join("scene.toml")).unwrap(),
            scene,
            "{args:?}"
        );
        assert!(temps(&dir).is_empty(), "{args:?}");
    }
}

/// A scene of one mesh whose OBJ file is `obj` (relative to the scene's folder).
fn mesh_scene(obj: &str) -> String {
    format!(
        "[camera]\nposition = [0, 0.5, 4]\nlook_at = [0, 0.5, 0]\nnear = 0.1\nfar = 100\n\n\
         [[material]]\nname = \"m\"\n\n[[light]]\nposition = [0, 4, 4]\nintensity = 20\n\n\
         [[mesh]]\nobj = {obj:?}\nmaterial = \"m\"\n"
    )
}

const OBJ: &[u8] = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

/// A folder with scenes of one mesh each: `m.toml` (`ok.obj`, also reached by
/// the hard link `alias.png` and the symbolic links `link.png` and
/// `sub/up.rs`), `sub/s.toml` (`sub/ok.obj`), `frames.toml` (`o-000.png`) and
/// `gif.toml` (`anim.gif`).
fn mesh_folder(name: &str) -> common::Scratch {
    let dir = scratch(name);
    std::fs::create_dir(dir.join("sub")).unwrap();
    for (scene, obj) in MESH_SCENES {
        let folder = Path::new(scene).parent().unwrap();
        std::fs::write(dir.join(scene), mesh_scene(obj)).unwrap();
        std::fs::write(dir.join(folder).join(obj), OBJ).unwrap();
    }
    std::fs::hard_link(dir.join("ok.obj"), dir.join("alias.png")).unwrap();
    std::os::unix::fs::symlink("ok.obj", dir.join("link.png")).unwrap();
    std::os::unix::fs::symlink("../ok.obj", dir.join("sub/up.rs")).unwrap();
    dir
}

const MESH_SCENES: [(&str, &str); 4] = [
    ("m.toml", "ok.obj"),
    ("sub/s.toml", "ok.obj"),
    ("frames.toml", "o-000.png"),
    ("gif.toml", "anim.gif"),
];

/// No command writes over the OBJ file of a mesh of its scene, whichever way the
/// output names it: the same path, another path, a hard link, a symbolic link, an
/// orbit frame's name, in the scene's folder or not. The file keeps its bytes and
/// nothing else is left.
#[test]
fn no_output_replaces_a_meshs_obj_file() {
    let ok = "it is the OBJ file ok.obj of mesh 1 (scene m.toml); choose another output";
    let cases: &[(&[&str], &str)] = &[
        (&["render", "m.toml", "-o", "ok.obj"], ok),
        (&["render", "m.toml", "-o", "./ok.obj"], ok),
        (&["render", "m.toml", "-o", "alias.png"], ok),
        (
            &["render", "m.toml", "-o", "link.png"],
            "it is the OBJ file ok.obj of mesh 1 (scene m.toml) (the symbolic link's \
             target ok.obj); choose another output",
        ),
        (&["compare", "m.toml", "--heatmap", "ok.obj"], ok),
        (&["compare", "m.toml", "--heatmap", "alias.png"], ok),
        (&["simulate", "m.toml", "-o", "./ok.obj"], ok),
        (
            &["simulate", "m.toml", "-o", "link.png"],
            "it is the OBJ file ok.obj",
        ),
        (&["bake", "m.toml", "-o", "ok.obj"], ok),
        (&["bake", "m.toml", "-o", "sub/../ok.obj"], ok),
        (
            &["bake", "m.toml", "-o", "sub/up.rs"],
            "it is the OBJ file ok.obj of mesh 1 (scene m.toml) (the symbolic link's \
             target sub/../ok.obj)",
        ),
        (
            &["render", "sub/s.toml", "-o", "sub/ok.obj"],
            "it is the OBJ file sub/ok.obj of mesh 1 (scene sub/s.toml)",
        ),
        (
            &["simulate", "frames.toml", "--orbit", "2", "-o", "o.png"],
            "refusing to write o-000.png: it is the OBJ file o-000.png of mesh 1 \
             (scene frames.toml)",
        ),
        (
            &["simulate", "gif.toml", "--orbit", "2", "-o", "anim.gif"],
            "refusing to write anim.gif: it is the OBJ file anim.gif of mesh 1 (scene gif.toml)",
        ),
    ];
    // Each case in a fresh folder, every failure listed.
    let mut wrong = Vec::new();
    for (args, message) in cases {
        let dir = mesh_folder("obj-input");
        let before = entries(&dir);
        let mut args = args.to_vec();
        if args[0] != "bake" {
            args.extend(["--size", "16x16"]);
        }
        let out = run(&dir, &args);
        let e = text(&out.stderr);
        if out.status.code() != Some(1) || !e.contains(message) {
            wrong.push(format!("{args:?}: status {:?}: {e}", out.status.code()));
        }
        for (scene, obj) in MESH_SCENES {
            let file = dir.join(Path::new(scene).parent().unwrap()).join(obj);
            if std::fs::read(&file).unwrap() != OBJ {
                wrong.push(format!("{args:?}: {} was replaced", file.display()));
            }
        }
        if entries(&dir) != before || !temps(&dir.join("sub")).is_empty() {
            wrong.push(format!("{args:?}: left {:?}", entries(&dir)));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    // The same scenes write any other file; the built-in teapot is no file.
    let dir = mesh_folder("obj-input");
    let out = run(
        &dir,
        &["render", "m.toml", "--size", "16x16", "-o", "fine.png"],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    std::fs::write(dir.join("teapot.toml"), mesh_scene("builtin:teapot")).unwrap();
    let out = run(&dir, &["bake", "teapot.toml", "-o", "builtin:teapot"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
}

#[test]
fn orbit_frames_are_all_or_nothing() {
    let dir = scratch("orbit");
    std::fs::write(dir.join("f-000.png"), b"precious").unwrap();
    std::fs::create_dir(dir.join("f-001.png")).unwrap();
    refused(
        &dir,
        &["simulate", "--orbit", "3", "--size", "16x16", "-o", "f.png"],
        "f-001.png: it is a folder",
    );
    assert_eq!(std::fs::read(dir.join("f-000.png")).unwrap(), b"precious");
    assert_eq!(entries(&dir), vec!["f-000.png", "f-001.png"]);
    // Unblocked: all three written.
    std::fs::remove_dir(dir.join("f-001.png")).unwrap();
    let out = run(
        &dir,
        &["simulate", "--orbit", "3", "--size", "16x16", "-o", "f.png"],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("wrote 3 frames, f-000.png"));
    assert_eq!(entries(&dir), vec!["f-000.png", "f-001.png", "f-002.png"]);
    assert!((0..3).all(|i| is_png(&dir.join(format!("f-{i:03}.png")))));
}

#[test]
fn a_file_size_limit_is_an_error_that_leaves_nothing() {
    // `ulimit -f 1`: 512 bytes; the PNG is larger. Without a handler SIGXFSZ would
    // kill the process with its temporary file left behind.
    let dir = scratch("ulimit");
    std::fs::write(dir.join("out.png"), b"precious").unwrap();
    let out = std::process::Command::new("sh")
        .current_dir(&dir)
        .arg("-c")
        .arg("ulimit -f 1 && exec \"$0\" render --size 200x150 -o out.png")
        .arg(env!("CARGO_BIN_EXE_tessera"))
        .output()
        .unwrap();
    let e = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{e}");
    assert!(
        e.contains("cannot write out.png: writing the temporary file ./.tessera-")
            && e.contains("File too large"),
        "{e}"
    );
    assert_eq!(std::fs::read(dir.join("out.png")).unwrap(), b"precious");
    assert_eq!(entries(&dir), vec!["out.png"]);
}

/// Starts a long render into `dir`, waits for its temporary file, sends `signal`
/// and checks that the process died of it with nothing left but `keep`.
fn interrupted(name: &str, signal: &str, number: i32) {
    use std::os::unix::process::ExitStatusExt;
    use std::time::{Duration, Instant};
    let dir = scratch(name);
    std::fs::write(dir.join("out.png"), b"precious").unwrap();
    let mut child = bin()
        .current_dir(&dir)
        .args(["render", "showcase", "--size", "4000x4000"])
        .args(["--sampler", "random:64", "-o", "out.png"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while temps(&dir).is_empty() {
        assert!(
            start.elapsed() < Duration::from_secs(20),
            "no temporary file appeared"
        );
        assert!(
            child.try_wait().unwrap().is_none(),
            "the render ended early"
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    std::thread::sleep(Duration::from_millis(150));
    let sent = std::process::Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let status = child.wait().unwrap();
    assert_eq!(status.signal(), Some(number), "{status:?}");
    assert_eq!(entries(&dir), vec!["out.png"], "{signal}");
    assert_eq!(std::fs::read(dir.join("out.png")).unwrap(), b"precious");
}

#[test]
fn sigterm_during_a_render_leaves_no_temporary_file() {
    interrupted("sigterm", "-TERM", 15);
}

#[test]
fn sigint_during_a_render_leaves_no_temporary_file() {
    interrupted("sigint", "-INT", 2);
}
