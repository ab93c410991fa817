//! What the `tessera` command says, and with what exit status: a bad command-line
//! value is a usage error (status 2, clap's message naming the range); errors name
//! the scene, the item and the value at fault; the summary lines say what was done.

use crate::common::{self, bin, scratch, text};
use std::path::Path;
use std::process::Output;

fn run(dir: &Path, args: &[&str]) -> Output {
    bin().current_dir(dir).args(args).output().unwrap()
}

/// Runs `args`: it must be a usage error (status 2) whose message contains
/// every one of `want`, and write nothing; returns stderr.
fn usage_error(args: &[&str], want: &[&str]) -> String {
    let dir = scratch("usage");
    let out = run(&dir, args);
    let e = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {e}");
    for w in want {
        assert!(e.contains(w), "{args:?}: {w:?} not in {e}");
    }
    assert!(common::entries(&dir).is_empty(), "{args:?} wrote files");
    e
}

#[test]
fn a_depth_beyond_the_maximum_is_a_usage_error_naming_the_range() {
    let max = tessera_core::error::MAX_DEPTH.to_string();
    for cmd in ["render", "compare", "simulate"] {
        usage_error(
            &[cmd, "--depth", "9"],
            &["--depth", "expected a depth from 0 to ", &max, "got \"9\""],
        );
        usage_error(&[cmd, "--depth=-1"], &["--depth", "got \"-1\""]);
    }
}

/// The frame delays of the GIF at `path`, in hundredths of a second.
fn gif_delays(path: &Path) -> Vec<u16> {
    let file = std::fs::File::open(path).unwrap();
    let mut decoder = gif::DecodeOptions::new().read_info(file).unwrap();
    let mut delays = Vec::new();
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        delays.push(frame.delay);
    }
    delays
}

/// A GIF counts its delays in hundredths of a second, at most 65,535: a longer
/// `--delay-ms` is refused (not clamped to 655.35 s without a word), and a
/// delay that is no multiple of 10 ms goes to the nearest hundredth, never to 0
/// (which viewers show at their own pace).
#[test]
fn orbit_delays_are_bounded_and_rounded_to_hundredths() {
    let max = tessera_host::limits::MAX_GIF_DELAY_MS.to_string();
    assert_eq!(max, "655350");
    for cmd in [&["simulate", "--orbit", "2"][..], &["simulate"]] {
        let mut args = cmd.to_vec();
        args.extend(["--delay-ms", "655351"]);
        usage_error(
            &args,
            &["--delay-ms", "from 0 to 655350 ms", "got \"655351\""],
        );
    }
    let dir = scratch("delays");
    for (ms, cs) in [
        ("80", 8),
        ("5", 1),
        ("14", 1),
        ("15", 2),
        ("0", 0),
        ("655350", 65535),
    ] {
        let name = format!("d{ms}.gif");
        let out = run(
            &dir,
            &[
                "simulate",
                "--orbit",
                "2",
                "--size",
                "8x8",
                "--delay-ms",
                ms,
                "-o",
                &name,
            ],
        );
        assert!(out.status.success(), "{ms}: {}", text(&out.stderr));
        assert_eq!(gif_delays(&dir.join(&name)), vec![cs; 2], "--delay-ms {ms}");
    }
    let help = text(&run(&dir, &["simulate", "--help"]).stdout).replace('\n', " ");
    let help = help.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        help.contains("rounded to the nearest 10 ms") && help.contains("655350"),
        "{help}"
    );
}

/// A scene whose camera is 1e18 from what it looks at, on both x and z: in
/// range, but an orbit swings it to 1.4e18 on one axis, beyond 2^60.
const FAR_CAMERA: &str = "# A camera far out: its orbit leaves the supported range.
[camera]
position = [1e18, 0, 1e18]
look_at = [0, 0, 0]
near = 0.1
far = 1e18

[[material]]
name = \"m\"

[[sphere]]
center = [0, 0, 0]
radius = 1e17
material = \"m\"

[[light]]
position = [0, 1e18, 0]
intensity = 1e36
";

/// An orbit whose camera leaves the supported range is refused before any
/// frame is drawn, with the scene, the frame and the position refused (not only
/// `camera position must be in [-2^60, 2^60] ...`).
#[test]
fn an_orbit_beyond_the_range_names_the_scene_the_frame_and_the_position() {
    let dir = scratch("orbit-range");
    std::fs::write(dir.join("far.toml"), FAR_CAMERA).unwrap();
    for out in ["f.gif", "f.png"] {
        let o = run(
            &dir,
            &[
                "simulate", "far.toml", "--orbit", "8", "--size", "16x16", "-o", out,
            ],
        );
        let e = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{e}");
        assert_eq!(
            e.trim_end(),
            "tessera: error: far.toml: orbit frame 1 of 8 (numbered from 0): the camera \
             at [1.4142136e18, 0, 0] (on a circle of radius 1.4142136e18 around \
             [0, 0, 0]): camera position must be in [-2^60, 2^60] (about 1.15e18) per \
             component",
        );
        assert_eq!(common::entries(&dir), vec!["far.toml"]);
    }
}

/// A dotted key or a table header of very many parts is refused by the pre-scan
/// at the part beyond the limit, with its line and column (not the parser's
/// `dotted.toml: recursion limit`, nowhere).
#[test]
fn a_key_of_too_many_parts_is_refused_with_its_line_and_column() {
    let dir = scratch("dotted");
    let cases = [
        (format!("a{} = 1\n", ".a".repeat(200_000)), "1:32"),
        (format!("# header\n[t{}]\n", ".t".repeat(200_000)), "2:33"),
        (format!("x = 1\n[[u{}]]\n", ".u".repeat(16)), "2:34"),
        (
            format!("[camera]\nv = {{ w{} = 1 }}\n", ".w".repeat(16)),
            "2:38",
        ),
    ];
    for (body, at) in cases {
        std::fs::write(dir.join("dotted.toml"), &body).unwrap();
        let o = run(&dir, &["render", "dotted.toml", "-o", "x.png"]);
        let e = text(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{e}");
        assert_eq!(
            e.trim_end(),
            format!(
                "tessera: error: dotted.toml:{at}: a dotted key or table header has more \
                 than 16 parts"
            ),
            "{}",
            &body[..body.len().min(80)]
        );
    }
}

/// `compare` writes a heat map only when asked (`--heatmap FILE`), never a
/// `compare-heatmap.png` of its own into the current folder.
#[test]
fn compare_writes_no_heat_map_unless_asked() {
    let dir = scratch("no-heatmap");
    let out = run(&dir, &["compare", "chapter-direct", "--size", "16x12"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    assert!(
        stdout.contains("mean FLIP") && !stdout.contains("wrote"),
        "{stdout}"
    );
    assert!(
        common::entries(&dir).is_empty(),
        "{:?}",
        common::entries(&dir)
    );
    let out = run(
        &dir,
        &[
            "compare",
            "chapter-direct",
            "--size",
            "16x12",
            "--heatmap",
            "h.png",
        ],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(text(&out.stdout).contains("wrote h.png"));
    assert_eq!(common::entries(&dir), vec!["h.png"]);
    let help = text(&run(&dir, &["compare", "--help"]).stdout);
    assert!(!help.contains("compare-heatmap.png"), "{help}");
}

/// The summary of `render`: the sampler's samples a pixel (for the adaptive
/// sampler the most a pixel may take, "at most 17", where about 3 rays a pixel
/// are traced) and the rays traced a pixel, measured.
#[test]
fn the_render_summary_says_the_samples_bound_and_the_rays_traced() {
    let dir = scratch("summary");
    for (sampler, said, camera) in [
        ("adaptive:4", "at most 17 samples/px (adaptive:4)", None),
        ("stratified:4", "16 samples/px (stratified:4)", Some(16.0)),
        ("random:3", "3 samples/px (random:3)", Some(3.0)),
        ("centre", "1 sample/px (centre)", Some(1.0)),
        ("corner", "1 sample/px (corner)", Some(1.0)),
        ("prefiltered", "1 sample/px (prefiltered)", Some(1.0)),
        (
            "offset:0.25,0.5",
            "1 sample/px (offset:0.25,0.5)",
            Some(1.0),
        ),
    ] {
        let out = run(
            &dir,
            &[
                "render",
                "showcase",
                "--size",
                "64x48",
                "--sampler",
                sampler,
                "-o",
                "s.png",
            ],
        );
        let line = text(&out.stdout)
            .lines()
            .next()
            .unwrap_or_default()
            .to_string();
        assert!(out.status.success(), "{}", text(&out.stderr));
        assert!(
            line.starts_with(&format!("showcase: 64x48, {said}, depth 5")),
            "{line}"
        );
        // `..., N rays, R/px (C camera rays/px), M Mrays/s`
        let words: Vec<&str> = line.split_whitespace().collect();
        let at = words.iter().position(|w| *w == "rays,").expect(&line);
        let rays: f64 = words[at - 1].parse().unwrap();
        let per_px: f64 = words[at + 1].trim_end_matches("/px").parse().expect(&line);
        let cam: f64 = words[at + 2].trim_start_matches('(').parse().expect(&line);
        assert_eq!(words[at + 3..at + 5], ["camera", "rays/px),"], "{line}");
        assert_eq!(
            format!("{per_px:.2}"),
            format!("{:.2}", rays / 3072.0),
            "{line}"
        );
        match camera {
            Some(c) => assert_eq!(cam, c, "{line}"),
            // The adaptive sampler traces a centre ray a pixel, and an apron
            // round each tile, and refines some pixels: below its bound.
            None => assert!((1.0..17.0).contains(&cam), "{line}"),
        }
        assert!(per_px > cam, "{line}");
    }
}

/// Runs `args` in `dir` until its first line on stderr (at most 60 s), then
/// stops it (SIGTERM: its temporary files go); returns that line.
fn first_warning(dir: &Path, args: &[&str]) -> String {
    use std::io::BufRead;
    use std::process::Stdio;
    let mut child = bin()
        .current_dir(dir)
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stderr = child.stderr.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let mut line = String::new();
        let _ = std::io::BufReader::new(stderr).read_line(&mut line);
        let _ = tx.send(line);
    });
    let line = rx.recv_timeout(std::time::Duration::from_secs(60));
    let killed = std::process::Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let _ = child.wait();
    line.unwrap_or_else(|_| panic!("{args:?}: nothing on stderr within 60 s"))
}

/// A 5 KB scene that asks for far more work than the warning's threshold (16 glass
/// spheres, 64 lights, depth 8, random:4096 at 320x240) is warned about before the
/// work starts, with the estimate, what drives it and how to make it cheaper;
/// nothing said so.
#[test]
fn a_costly_scene_is_warned_about_before_the_work_starts() {
    let dir = scratch("costly");
    let fixture = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/costly.toml");
    let scene = dir.join("costly.toml");
    std::fs::copy(&fixture, &scene).unwrap();
    assert!(std::fs::metadata(&scene).unwrap().len() < 6000);
    for args in [
        &["render", "costly.toml", "-o", "c.png"][..],
        &["compare", "costly.toml"],
        &["simulate", "costly.toml", "-o", "c.png"],
    ] {
        let w = first_warning(&dir, args);
        for part in [
            "tessera: warning: costly.toml: ",
            " may take about ",
            " on this machine (a trial of 1200 pixels traced ",
            " rays a sample, ",
            "at most 33215 rays a sample: ",
            " x 4096 samples (random:4096) x 511 rays a sample (depth 8, transparent \
             materials: 2 rays a hit) x 65 (64 lights: a shadow ray each a hit)",
            "to make it cheaper: a smaller --size, fewer samples (--sampler), a lower --depth",
        ] {
            assert!(w.contains(part), "{args:?}: {part:?} not in {w}");
        }
        assert!(w.contains(" hours ") || w.contains(" minutes "), "{w}");
        assert_eq!(common::entries(&dir), vec!["costly.toml"], "{args:?}");
    }
    // A smaller size, fewer samples and a lower depth: no warning.
    let out = run(
        &dir,
        &[
            "render",
            "costly.toml",
            "--size",
            "32x24",
            "--sampler",
            "random:4",
            "--depth",
            "2",
            "-o",
            "c.png",
        ],
    );
    assert!(
        out.status.success() && out.stderr.is_empty(),
        "{}",
        text(&out.stderr)
    );
}

/// No built-in scene and no example file is warned about at its own settings,
/// by any command.
#[test]
fn no_scene_of_the_repository_is_warned_about() {
    let dir = scratch("not-costly");
    let mut scenes: Vec<String> = tessera_core::builtin::Builtin::ALL
        .iter()
        .map(|b| b.name().to_string())
        .collect();
    let examples = common::scenes().join("examples");
    for f in common::entries(&examples) {
        if f.ends_with(".toml") {
            scenes.push(examples.join(f).display().to_string());
        }
    }
    assert!(scenes.len() > 20, "{scenes:?}");
    for s in &scenes {
        for args in [
            &["render", s, "-o", "x.png"][..],
            &["compare", s],
            &["simulate", s, "-o", "x.png"],
        ] {
            let out = run(&dir, args);
            assert!(out.status.success(), "{args:?}: {}", text(&out.stderr));
            assert!(out.stderr.is_empty(), "{args:?}: {}", text(&out.stderr));
        }
    }
}

/// `trade` scales the time it takes at its defaults by the work asked for, and
/// warns beyond a minute's worth.
#[test]
fn a_costly_trade_is_warned_about_before_the_work_starts() {
    let dir = scratch("trade-costly");
    let w = first_warning(&dir, &["trade", "--size", "640x480"]);
    for part in [
        "tessera: warning: trade at 640x480 with 5 run(s) may take about ",
        "25.0 times the work of `tessera trade` at its defaults (128x96, 5 runs, every \
         scene, no cached references: 62 s)",
        "to make it cheaper: a smaller --size, fewer --runs or --scenes, a --truth-dir",
    ] {
        assert!(w.contains(part), "{part:?} not in {w}");
    }
    let out = run(
        &dir,
        &[
            "trade",
            "--scenes",
            "chapter-direct",
            "--size",
            "32x24",
            "--runs",
            "1",
        ],
    );
    assert!(
        out.status.success() && out.stderr.is_empty(),
        "{}",
        text(&out.stderr)
    );
}

/// A scene of one mesh whose OBJ file is `obj`, written in `dir`.
fn mesh_scene(dir: &Path, obj: &str) {
    std::fs::write(dir.join("m.obj"), obj).unwrap();
    std::fs::write(
        dir.join("m.toml"),
        "[camera]\nposition = [0, 0, 6]\nlook_at = [0, 0, 0]\nnear = 0.1\nfar = 100\n\n\
         [[material]]\nname = \"m\"\n\n[[light]]\nposition = [3, 4, 5]\nintensity = 30\n\n\
         [[mesh]]\nobj = \"m.obj\"\nmaterial = \"m\"\n",
    )
    .unwrap();
}

/// OBJ faces are bounded before tobj reads them (unbounded, a single 16 MiB face
/// line takes 340 MB): a face of more vertices than a fan the scene could hold, or faces
/// making more than twice the triangles the scene holds, are refused at their
/// line, with the count.
#[test]
fn obj_faces_are_bounded_before_they_are_parsed() {
    let dir = scratch("obj-faces");
    let head = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let huge = format!("{head}# one face\nf{}\n", " 1 2 3".repeat(1_000_000));
    mesh_scene(&dir, &huge);
    let out = run(&dir, &["render", "m.toml", "-o", "x.png"]);
    assert_eq!(
        text(&out.stderr).trim_end(),
        "tessera: error: m.toml:14: mesh 1: m.obj:5: a face of 3000000 vertices, more than \
         the 8194 whose fan fills the scene's 8192 triangles"
    );
    let many = format!("{head}{}", "f 1 2 3\n".repeat(20_000));
    mesh_scene(&dir, &many);
    let out = run(&dir, &["render", "m.toml", "-o", "x.png"]);
    assert_eq!(
        text(&out.stderr).trim_end(),
        "tessera: error: m.toml:14: mesh 1: m.obj:16388: the faces up to this line make \
         more than 16384 triangles (twice the 8192 the scene holds, degenerate faces \
         included)"
    );
    // At the bounds: read, and refused (or not) for what the faces are.
    let fan: Vec<String> = (0..8194).map(|i| format!("v {i} {} 0\n", i * i)).collect();
    let fan = format!(
        "{}f {}\n",
        fan.concat(),
        (1..=8194)
            .map(|i| i.to_string())
            .collect::<Vec<_>>()
            .join(" ")
    );
    mesh_scene(&dir, &fan);
    let out = run(&dir, &["render", "m.toml", "--size", "8x8", "-o", "x.png"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
}

/// A cached reference of `trade --truth-dir` that is not a regular file (a FIFO
/// there made `trade` wait forever) is refused at once, unread, naming it.
#[test]
fn a_cached_reference_that_is_not_a_regular_file_is_refused() {
    use std::process::Stdio;
    let dir = scratch("truth-fifo");
    let b = tessera_core::builtin::Builtin::ChapterDirect;
    let vp = tessera_core::Viewport::new(16, 12);
    let desc = tessera_host::file::builtin_desc(b);
    let name = tessera_host::trade::truth_file_name(b.name(), &desc, vp);
    std::fs::create_dir(dir.join("truth")).unwrap();
    let fifo = dir.join("truth").join(&name);
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let mut child = bin()
        .current_dir(&dir)
        .args([
            "trade",
            "--scenes",
            "chapter-direct",
            "--size",
            "16x12",
            "--runs",
            "1",
        ])
        .args(["--truth-dir", "truth"])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > std::time::Duration::from_secs(20) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("trade waited on the FIFO for 20 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert_eq!(
        text(&out.stderr).trim_end(),
        format!(
            "tessera: error: truth/{name}: cannot read the cached reference: it is a FIFO \
             (named pipe), not a regular file"
        )
    );
}

/// True for a character that must not reach the terminal raw: a control
/// character (C0, DEL, C1), a line or paragraph separator, a bidirectional
/// control.
fn unsafe_char(c: char) -> bool {
    c.is_control()
        || matches!(
            c,
            '\u{2028}' | '\u{2029}' | '\u{61c}' | '\u{200e}' | '\u{200f}'
                | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}'
        )
}

/// Paths and names in messages are escaped: a name with a line break or a
/// terminal escape cannot forge a line or drive the terminal (the output paths
/// of `cannot write`, `refusing to write` and the summary among them).
#[test]
fn paths_and_names_in_messages_are_escaped() {
    let dir = scratch("escapes");
    let evil = "e\nvil\u{1b}[31m\u{2028}\u{202e}\u{85}";
    let shown = "e\\u{a}vil\\u{1b}[31m\\u{2028}\\u{202e}\\u{85}";
    std::fs::create_dir(dir.join(format!("{evil}.png"))).unwrap();
    let missing = format!("no-such-folder/{evil}.png");
    let cases: Vec<(Vec<String>, String)> = vec![
        (
            vec![
                "render".into(),
                "--size".into(),
                "8x8".into(),
                "-o".into(),
                missing.clone(),
            ],
            format!("cannot write no-such-folder/{shown}.png: creating the temporary file"),
        ),
        (
            vec![
                "render".into(),
                "--size".into(),
                "8x8".into(),
                "-o".into(),
                format!("{evil}.png"),
            ],
            format!("refusing to write {shown}.png: it is a folder"),
        ),
        (
            vec!["render".into(), format!("{evil}.toml")],
            format!("{shown}.toml: cannot read the scene file"),
        ),
        (
            vec![
                "compare".into(),
                "--size".into(),
                "8x8".into(),
                "--heatmap".into(),
                missing,
            ],
            format!("cannot write no-such-folder/{shown}.png"),
        ),
    ];
    for (args, want) in cases {
        let out = bin().current_dir(&dir).args(&args).output().unwrap();
        let e = text(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{args:?}: {e}");
        let line = e.strip_suffix('\n').unwrap_or(&e);
        assert!(!line.chars().any(unsafe_char), "{args:?}: raw in {line:?}");
        assert!(line.contains(&want), "{args:?}: {want:?} not in {line:?}");
    }
    // The summary on stdout too.
    let out = bin()
        .current_dir(&dir)
        .args(["render", "--size", "8x8", "-o", &format!("{evil}-ok.png")])
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", text(&out.stderr));
    let stdout = text(&out.stdout);
    for line in stdout.lines() {
        assert!(!line.chars().any(unsafe_char), "raw in {line:?}");
    }
    assert!(
        stdout.contains(&format!("wrote {shown}-ok.png")),
        "{stdout}"
    );
}
