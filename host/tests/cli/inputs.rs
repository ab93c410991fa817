//! Inputs that are not regular files (a FIFO, a folder, a device, a socket), as
//! the scene file or as a mesh's OBJ file: refused at once with a message that
//! names the path and what it is. Nothing waits on them (opening a FIFO for
//! reading blocks until a writer comes).

use crate::common::{bin, scratch, text};
use std::os::unix::net::UnixListener;
use std::path::Path;
use std::process::{Output, Stdio};
use std::time::{Duration, Instant};

/// Runs the binary with `args` in `dir`; an error if it has not ended within
/// 20 s (it is killed).
fn run_bounded(dir: &Path, args: &[&str]) -> Result<Output, String> {
    let mut child = bin()
        .current_dir(dir)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(20) {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!(
                "{args:?} still ran after 20 s: it waited on its input"
            ));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    Ok(child.wait_with_output().unwrap())
}

/// Runs `args` in `dir` (see [`run_bounded`]): a description of what is wrong
/// unless it ends with status 1 and stderr `want` (`exact`) or ending with it.
fn refused(dir: &Path, args: &[&str], want: &str, exact: bool) -> Option<String> {
    let out = match run_bounded(dir, args) {
        Ok(out) => out,
        Err(e) => return Some(e),
    };
    let e = text(&out.stderr);
    let right = if exact { e == want } else { e.ends_with(want) };
    (out.status.code() != Some(1) || !right)
        .then(|| format!("{args:?}: status {:?}: {e}", out.status.code()))
}

/// A scene of one mesh whose OBJ file is `obj`.
fn mesh_scene(obj: &str) -> String {
    format!(
        "[camera]\nposition = [0, 0.5, 4]\nlook_at = [0, 0.5, 0]\nnear = 0.1\nfar = 100\n\n\
         [[material]]\nname = \"m\"\n\n[[light]]\nposition = [0, 4, 4]\nintensity = 20\n\n\
         [[mesh]]\nobj = {obj:?}\nmaterial = \"m\"\n"
    )
}

/// Makes, in `dir`, one input of each kind that is not a regular file, named
/// `NAME.EXT`: `fifo`, `folder`, `socket` (bound while the returned listener
/// lives), and `link` (a symbolic link to the FIFO); returns them with the
/// kind the message must name, with `/dev/null` and `/dev/zero`.
fn odd_inputs(dir: &Path, ext: &str) -> (UnixListener, Vec<(String, &'static str)>) {
    let name = |n: &str| format!("{n}.{ext}");
    let made = std::process::Command::new("mkfifo")
        .arg(dir.join(name("fifo")))
        .status()
        .unwrap();
    assert!(made.success());
    std::fs::create_dir(dir.join(name("folder"))).unwrap();
    let listener = UnixListener::bind(dir.join(name("socket"))).unwrap();
    std::os::unix::fs::symlink(name("fifo"), dir.join(name("link"))).unwrap();
    let kinds = vec![
        (
            name("fifo"),
            "it is a FIFO (named pipe), not a regular file",
        ),
        (name("folder"), "it is a folder, not a regular file"),
        (name("socket"), "it is a socket, not a regular file"),
        (
            name("link"),
            "it is a FIFO (named pipe), not a regular file",
        ),
        (
            "/dev/null".to_string(),
            "it is a character device, not a regular file",
        ),
        (
            "/dev/zero".to_string(),
            "it is a character device, not a regular file",
        ),
    ];
    (listener, kinds)
}

/// Every odd kind of OBJ file, for each command that reads a scene: refused
/// within the timeout, status 1, the message naming the scene's mesh, the path
/// and the kind: a FIFO must not hang the command, /dev/null must not read as an
/// empty mesh, nor /dev/zero up to the size limit.
#[test]
fn an_obj_file_that_is_not_a_regular_file_is_refused_at_once() {
    let dir = scratch("odd-obj");
    let (_listener, kinds) = odd_inputs(&dir, "obj");
    let mut wrong = Vec::new();
    for (obj, kind) in &kinds {
        std::fs::write(dir.join("m.toml"), mesh_scene(obj)).unwrap();
        for args in [
            &["compare", "m.toml", "--size", "8x8", "--heatmap", "h.png"][..],
            &["render", "m.toml", "--size", "8x8", "-o", "r.png"],
            &["bake", "m.toml", "-o", "b.rs"],
        ] {
            let want = format!("m.toml:14: mesh 1: {obj}: cannot read the OBJ file: {kind}\n");
            wrong.extend(refused(&dir, args, &want, false).map(|e| format!("{obj}: {e}")));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    assert!(!dir.join("h.png").exists() && !dir.join("r.png").exists());
}

/// The same as the scene file itself.
#[test]
fn a_scene_file_that_is_not_a_regular_file_is_refused_at_once() {
    let dir = scratch("odd-scene");
    let (_listener, kinds) = odd_inputs(&dir, "toml");
    let mut wrong = Vec::new();
    for (scene, kind) in &kinds {
        for args in [
            &["compare", scene, "--size", "8x8", "--heatmap", "h.png"][..],
            &["render", scene, "--size", "8x8", "-o", "r.png"],
            &["simulate", scene, "--size", "8x8", "-o", "s.png"],
            &["bake", scene, "-o", "b.rs"],
        ] {
            let want = format!("tessera: error: {scene}: cannot read the scene file: {kind}\n");
            wrong.extend(refused(&dir, args, &want, true));
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

/// A mesh that is not the first, whose OBJ file cannot be read: the message
/// does not blame the size budget of the OBJ files (it did for any error of a
/// mesh after the first).
#[test]
fn a_later_meshs_unreadable_obj_file_is_not_blamed_on_the_budget() {
    let dir = scratch("second-obj");
    std::fs::write(dir.join("ok.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    let scene = mesh_scene("ok.obj") + "\n[[mesh]]\nobj = \"missing.obj\"\nmaterial = \"m\"\n";
    std::fs::write(dir.join("two.toml"), scene).unwrap();
    let out = run_bounded(
        &dir,
        &["render", "two.toml", "--size", "8x8", "-o", "t.png"],
    )
    .unwrap();
    let e = text(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{e}");
    assert!(
        e.contains("mesh 2: missing.obj: cannot read the OBJ file: No such file")
            && !e.contains("what is left"),
        "{e}"
    );
}
