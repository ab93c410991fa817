//! The firmware a user copies (`examples/qemu-m4f`): built as a user builds it
//! (`cargo build --release` in its folder, another scene file named by
//! `TESSERA_SCENE`) and run under qemu, it writes the picture that the host
//! renders of the same scene file, byte for byte, and prints its checksum; the
//! scene's tables lie in flash, the RAM holds little more than the tile buffer;
//! the README's figures are the build's.
//!
//! These tests need `qemu-system-arm` and the `thumbv7em-none-eabihf` target;
//! without them they fail and say to run `bash tests/run-all.sh`, which installs
//! both.

use image::RgbImage;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
use tessera_tests::firmware::{self, TempDir};
use tessera_tests::qemu_example::{
    DEFAULT, PICTURE, Run, build_and_run, example, field, host, host_of, number, ppm,
};
use tessera_tests::readme::{figure_after, table_row, within};

/// The scene files built, as `TESSERA_SCENE` names them (relative to the
/// example's folder): the teapot (1,000 triangles in a mesh), the showcase (no
/// mesh, no BVH), the cylinders and disks (the core's optional kinds, built with
/// their features), files from 3D tools (Blender's OBJ with its MTL material
/// and PNG, Khronos glTF samples with an embedded PNG: normals, uvs, image
/// textures in flash in RGB565, a sun), an animation (a teapot turning and a
/// ball bouncing, instances of two meshes moved by keyframes: built with the
/// features `instances` and `animation`, it also writes frames of its
/// animation) and the default (the showcase with an OBJ mesh) last, so that the ELF left in the example's target folder is the one a
/// user builds there.
const SCENES: [&str; 6] = [
    "../../scenes/teapot.toml",
    "../../scenes/showcase.toml",
    "../../scenes/pillars.toml",
    "../../tests/data/tools.toml",
    "../../scenes/examples/animated.toml",
    DEFAULT,
];

/// Every scene of [`SCENES`] built and run, one after the other (they share the
/// example's target folder and so its ELF), once for every test of this binary.
fn runs() -> &'static [Run] {
    static RUNS: OnceLock<Result<Vec<Run>, String>> = OnceLock::new();
    RUNS.get_or_init(|| {
        firmware::qemu_version()?;
        SCENES.iter().map(|&scene| build_and_run(scene)).collect()
    })
    .as_deref()
    .unwrap_or_else(|e| panic!("{e}"))
}

/// The FNV-1a 64 hash of the picture's RGB bytes in the order the firmware
/// renders them: tile after tile (left to right, top to bottom), each tile's rows
/// top to bottom.
fn tile_order_fnv1a64(img: &RgbImage, tile: u32) -> u64 {
    let mut hash = 0xcbf2_9ce4_8422_2325_u64;
    for ty in (0..img.height()).step_by(tile as usize) {
        for tx in (0..img.width()).step_by(tile as usize) {
            for y in ty..(ty + tile).min(img.height()) {
                for x in tx..(tx + tile).min(img.width()) {
                    for &b in &img.get_pixel(x, y).0 {
                        hash = (hash ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3);
                    }
                }
            }
        }
    }
    hash
}

/// Every scene file of [`SCENES`] built and run once, then checked four ways,
/// each check's failures reported (one test: the builds are one chain in one
/// target folder, and tests waiting on it would hold the test threads).
#[test]
fn each_scene_file_builds_runs_and_is_what_the_host_and_readme_say() {
    let checks: [(&str, fn()); 4] = [
        (
            "the host's picture",
            writes_the_hosts_picture_of_each_scene_file,
        ),
        (
            "the host's frames of the animation",
            plays_the_hosts_frames_of_each_animation,
        ),
        (
            "scenes in flash, tile in RAM",
            keeps_its_scenes_in_flash_and_its_tile_in_ram,
        ),
        ("the README's figures", readme_has_its_figures),
    ];
    let failed: Vec<&str> = checks
        .into_iter()
        .filter(|(_, check)| std::panic::catch_unwind(check).is_err())
        .map(|(what, _)| what)
        .collect();
    assert!(
        failed.is_empty(),
        "failed (their messages above): {failed:?}"
    );
}

/// The firmware's picture of each scene is the host's, byte for byte, with the
/// printed checksum, size and counts.
fn writes_the_hosts_picture_of_each_scene_file() {
    let dir = example();
    let mut bad = Vec::new();
    for run in runs() {
        let path = dir.join(run.scene);
        let want = host(&path);
        let tile = tessera_host::file::load(&path).unwrap().render.tile;
        let out = &run.stdout;
        assert!(
            out.starts_with(&format!("tessera: {}, ", run.scene)),
            "{}: {out}",
            run.scene
        );
        assert_eq!(
            field(out, "size"),
            format!("{}x{}", want.width(), want.height()),
            "{}",
            run.scene
        );
        assert_eq!(
            field(out, "checksum"),
            format!("{:016x}", tile_order_fnv1a64(&run.picture, tile as u32)),
            "{}: the printed checksum is not the picture's",
            run.scene
        );
        assert!(
            number(out, "instructions") > 0 && number(out, "stack") > 0,
            "{out}"
        );
        println!("{}: {}", run.scene, out.replace('\n', "; "));
        if run.picture.as_raw() != want.as_raw() {
            let name = run.scene.rsplit('/').next().unwrap_or("scene");
            let images = tessera_tests::output_dir();
            let _ = run
                .picture
                .save(images.join(format!("qemu-m4f-{name}-chip.png")));
            let _ = want.save(images.join(format!("qemu-m4f-{name}-host.png")));
            let differ = want
                .pixels()
                .zip(run.picture.pixels())
                .filter(|(a, b)| a != b)
                .count();
            bad.push(format!("{}: {differ} pixels differ", run.scene));
        }
    }
    assert!(
        bad.is_empty(),
        "the firmware's pictures differ from the host's (images in target/test-images): {bad:#?}"
    );
}

/// The frames an animated scene's firmware writes are the host's frames of the
/// same number (`tessera render --frame N`: the scene file's instances placed
/// by the host's reading of its keyframes), byte for byte, with the printed
/// checksums: the frames at 0, 1/4, 1/2 and 3/4 of the animation's frames
/// (as many as the host counts at the scene's `fps`), no two alike. A scene
/// without an animation writes no frame.
fn plays_the_hosts_frames_of_each_animation() {
    let dir = example();
    let mut bad = Vec::new();
    let mut animated = 0;
    for run in runs() {
        let desc = tessera_host::file::load(&dir.join(run.scene)).unwrap();
        if desc.keyframes.is_empty() {
            assert!(
                run.frames.is_empty(),
                "{}: frames of no animation",
                run.scene
            );
            continue;
        }
        animated += 1;
        let count = desc.frames().unwrap();
        let out = &run.stdout;
        assert_eq!(number(out, "frames"), u64::from(count), "{out}");
        let written = count.min(4);
        let want: Vec<u32> = (0..written).map(|k| k * count / written).collect();
        let have: Vec<u32> = run.frames.iter().map(|f| f.0).collect();
        assert_eq!(have, want, "{}: the frames written", run.scene);
        for pair in run.frames.windows(2) {
            assert!(
                pair[0].1 != pair[1].1,
                "{}: frames {} and {} are alike: nothing moved",
                run.scene,
                pair[0].0,
                pair[1].0
            );
        }
        for (n, chip) in &run.frames {
            let line = out
                .lines()
                .find(|l| l.starts_with(&format!("frame={n} ")))
                .unwrap_or_else(|| panic!("{}: no line of frame {n} in {out}", run.scene));
            assert_eq!(
                field(line, "checksum"),
                format!("{:016x}", tile_order_fnv1a64(chip, desc.render.tile as u32)),
                "{}: frame {n}'s printed checksum is not its picture's",
                run.scene
            );
            assert!(number(line, "instructions") > 0 && number(line, "setup") > 0);
            let want = host_of(&desc.at_frame(*n).unwrap());
            println!("{}: {line}", run.scene);
            if chip.as_raw() != want.as_raw() {
                let name = run.scene.rsplit('/').next().unwrap_or("scene");
                let images = tessera_tests::output_dir();
                let _ = chip.save(images.join(format!("qemu-m4f-{name}-frame{n}-chip.png")));
                let _ = want.save(images.join(format!("qemu-m4f-{name}-frame{n}-host.png")));
                let differ = want
                    .pixels()
                    .zip(chip.pixels())
                    .filter(|(a, b)| a != b)
                    .count();
                bad.push(format!("{} frame {n}: {differ} pixels differ", run.scene));
            }
        }
    }
    assert!(animated > 0, "no scene of {SCENES:?} is animated");
    assert!(
        bad.is_empty(),
        "the firmware's frames differ from the host's (images in target/test-images): {bad:#?}"
    );
}

/// The scene's tables lie in flash; the RAM holds the tile and a few words.
fn keeps_its_scenes_in_flash_and_its_tile_in_ram() {
    let (flash, ram) = firmware::memory_regions(&example().join("memory.x")).unwrap();
    let tile = size_of::<tessera_core::Tile<16>>() as u64;
    for run in runs() {
        let s = &run.sizes;
        assert!(s.flash() <= flash && s.ram() <= ram, "{}: {s:?}", run.scene);
        let tables = run.tables();
        let mut need = vec!["SCENE", "MATERIALS", "LIGHTS"];
        if run.scene.ends_with("showcase.toml") {
            need.extend(["SPHERES", "PLANES", "TRIANGLES", "BOXES"]);
        } else if run.scene.ends_with("pillars.toml") {
            need.extend(["PLANES", "CYLINDERS", "DISKS"]);
        } else {
            need.extend(["MESHES", "MESH0_VERTICES", "MESH0_FACES", "MESH0_NODES"]);
        }
        for name in need {
            let found = tables
                .iter()
                .find(|s| s.name == format!("qemu_m4f::scene::{name}"));
            assert!(
                found.is_some_and(|s| s.size > 0),
                "{}: no table {name} in the ELF's symbols",
                run.scene
            );
        }
        // memory.x's FLASH starts at 0, its RAM at 0x2000_0000.
        for t in &tables {
            assert!(
                t.section.as_deref() == Some(".rodata") && t.address + t.size <= flash,
                "{}: {t:?} is not in flash",
                run.scene
            );
        }
        let bytes: u64 = tables.iter().map(|t| t.size).sum();
        println!(
            "{}: flash {} bytes, RAM (.data + .bss) {} bytes, the scene's tables {bytes} \
             bytes in flash",
            run.scene,
            s.flash(),
            s.ram()
        );
        // The RAM is the tile buffer and a few words of the firmware's own
        // (SysTick's wrap count, the flags of what was taken).
        assert!(
            s.ram() <= tile + 64 && s.ram() < bytes,
            "{}: {} bytes of RAM, the {tile}-byte tile and the scene's {bytes} bytes",
            run.scene,
            s.ram()
        );
    }
}

/// The run of the default scene.
fn default_run() -> &'static Run {
    runs()
        .iter()
        .find(|r| r.scene == DEFAULT)
        .expect("the default scene is built")
}

/// The README's table of each scene (flash, RAM, stack, instructions, the
/// scene's tables), its default scene's output and its `llvm-nm` excerpt are the build's. Within 1 %
/// (2 % for the instructions): the same sources built in another folder link a
/// little differently (the crates' paths enter their symbol hashes, which moves
/// code alignment); a stale figure is further off.
fn readme_has_its_figures() {
    let readme = std::fs::read_to_string(example().join("README.md")).unwrap();
    let mut wrong = Vec::new();
    for run in runs() {
        let cells = table_row(&readme, run.scene).unwrap_or_default();
        let cell = |i: usize| cells.get(i).and_then(|c| tessera_tests::readme::number(c));
        let out = &run.stdout;
        for (what, i, truth, percent) in [
            ("flash", 1, run.sizes.flash(), 1),
            ("RAM", 2, run.sizes.ram(), 1),
            ("stack", 3, number(out, "stack"), 1),
            ("instructions", 4, number(out, "instructions"), 2),
            ("tables", 5, run.tables().iter().map(|t| t.size).sum(), 1),
        ] {
            if !within(cell(i), truth, percent) {
                wrong.push(format!(
                    "{}: {what}: the README says {:?}, the build {truth}",
                    run.scene,
                    cell(i)
                ));
            }
        }
    }
    // The output shown is the default scene's.
    let out = &default_run().stdout;
    for key in ["size", "checksum"] {
        let line = out.lines().find(|l| l.starts_with(&format!("{key}=")));
        if !line.is_some_and(|l| readme.lines().any(|r| r == l)) {
            wrong.push(format!("the README lacks the output line {line:?}"));
        }
    }
    for (key, percent) in [("instructions", 2), ("stack", 1)] {
        let said = figure_after(&readme, &format!("\n{key}="));
        if !within(said, number(out, key), percent) {
            wrong.push(format!(
                "output: {key}: the README says {said:?}, the firmware {}",
                number(out, key)
            ));
        }
    }
    // The llvm-nm excerpt: `address size r qemu_m4f::scene::NAME`, each table of
    // the default scene at its size, in flash.
    let mut excerpt = 0;
    for line in readme.lines() {
        let w: Vec<&str> = line.split_whitespace().collect();
        let [address, size, kind, name] = w[..] else {
            continue;
        };
        if !name.starts_with("qemu_m4f::scene::") {
            continue;
        }
        // llvm-nm -C keeps the hash of a Rust symbol (`::h` and 16 hex digits).
        let name = match name.rsplit_once("::h") {
            Some((base, hash)) if hash.len() == 16 => base,
            _ => name,
        };
        excerpt += 1;
        let address = u64::from_str_radix(address, 16).unwrap_or(u64::MAX);
        let size = u64::from_str_radix(size, 16).ok();
        let truth = default_run().symbols.iter().find(|s| s.name == name);
        if kind != "r" || address >= 0x2000_0000 || truth.map(|s| s.size) != size {
            wrong.push(format!(
                "the README's llvm-nm line {line:?}: the ELF has {truth:?}"
            ));
        }
    }
    if excerpt == 0 {
        wrong.push("the README shows no llvm-nm line of the scene's tables".into());
    }
    assert!(
        wrong.is_empty(),
        "examples/qemu-m4f/README.md is not the build's: {wrong:#?}"
    );
}

/// `cargo run --release` in the example's folder (its `.cargo/config.toml`'s
/// runner) starts qemu as these tests do.
#[test]
fn the_qemu_examples_runner_is_the_tests_qemu() {
    let path = example().join(".cargo").join("config.toml");
    let config = std::fs::read_to_string(&path).unwrap();
    firmware::assert_runner_is_qemu(&config, &path);
    assert!(
        config.contains(&format!("target = \"{}\"", firmware::TARGET)),
        "{}",
        path.display()
    );
}

/// The example is the firmware template made with its name and this checkout
/// (`tessera new examples/qemu-m4f --path .`): its manifest is the template's,
/// filled in, and every other file of the template is the example's.
#[test]
fn the_qemu_example_is_the_template_filled_in() {
    let dir = example();
    let files = tessera_host::template::files(
        "qemu-m4f",
        &tessera_host::template::Source::Checkout(PathBuf::from("../..")),
    )
    .unwrap();
    for (path, bytes) in files {
        // The example has a README of its own (how it is measured), and a
        // .gitignore of its own (git reads no linked .gitignore).
        if path == Path::new("README.md") {
            continue;
        }
        let theirs = std::fs::read(dir.join(&path))
            .unwrap_or_else(|e| panic!("examples/qemu-m4f/{}: {e}", path.display()));
        assert!(
            theirs == bytes,
            "examples/qemu-m4f/{} is not the template's",
            path.display()
        );
    }
}

/// A firmware as a user starts one: `tessera new my-firmware --path <checkout>`
/// writes the crate; `cargo build --release` in its folder builds it (its
/// `.cargo/config.toml` names the target, its `build.rs` bakes `scene.toml`);
/// run under qemu, it writes `tessera.ppm`; `tessera render` of the same scene
/// file and `tessera diff` of the two pictures find them identical. The firmware
/// runs under the tests' qemu command (the example's runner, checked equal to it
/// above), with their timeout.
///
/// The build shares the example's target folder and dependency versions (its
/// Cargo.lock), so it compiles only the new crate: the test run's time, not a
/// first build's.
#[test]
fn a_firmware_made_by_tessera_new_draws_the_hosts_picture() {
    firmware::qemu_version().unwrap_or_else(|e| panic!("{e}"));
    let started = std::time::Instant::now();
    let root = firmware::repo_root();
    let scratch = TempDir::new().unwrap();
    let project = scratch.path().join("my-firmware");
    // The command, as built for this test run: the `test` profile's `tessera`
    // in this test binary's target folder, its features unified over the
    // workspace (`cargo test --workspace` has built it so for the host's tests,
    // and this build finds it fresh; `-p tessera-host` alone would resolve the
    // core's features anew and build both again, `cargo run` the whole command
    // in the dev profile).
    let profile_dir = std::env::current_exe()
        .unwrap()
        .parent()
        .and_then(Path::parent)
        .unwrap()
        .to_path_buf();
    let target_dir = profile_dir.parent().unwrap();
    let mut build = firmware::cargo();
    build
        .current_dir(&root)
        .args([
            "build",
            "-q",
            "--workspace",
            "--bin",
            "tessera",
            "--profile",
            "test",
            "--target-dir",
        ])
        .arg(target_dir);
    firmware::checked(&mut build, "cargo", "building the tessera command failed")
        .unwrap_or_else(|e| panic!("{e}"));
    let bin = profile_dir.join("tessera");
    let tessera = |args: &[&std::ffi::OsStr]| {
        let mut cmd = std::process::Command::new(&bin);
        cmd.current_dir(&root).args(args);
        cmd
    };
    let out = firmware::checked(
        &mut tessera(&[
            "new".as_ref(),
            project.as_os_str(),
            "--path".as_ref(),
            root.as_os_str(),
        ]),
        "tessera new",
        "tessera new failed",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let said = String::from_utf8_lossy(&out.stdout);
    assert!(said.starts_with("created "), "{said}");
    std::fs::copy(example().join("Cargo.lock"), project.join("Cargo.lock")).unwrap();
    let generated = started.elapsed();

    let mut build = firmware::cargo();
    build
        .current_dir(&project)
        .args(["build", "--release"])
        .env("CARGO_TARGET_DIR", example().join("target"));
    firmware::checked(&mut build, "cargo", "building the new firmware failed")
        .unwrap_or_else(|e| panic!("{e}"));
    let built = started.elapsed();
    let elf = example().join("target/thumbv7em-none-eabihf/release/my-firmware");
    let stdout = firmware::run_in(&project, &elf).unwrap_or_else(|e| panic!("{e}"));
    assert!(stdout.starts_with("tessera: scene.toml, "), "{stdout}");
    let ran = started.elapsed();

    // As its README says: the host's picture of the same scene file, and the
    // two compared by the command.
    let chip = project.join(PICTURE);
    let host_png = project.join("host.png");
    firmware::checked(
        &mut tessera(&[
            "render".as_ref(),
            project.join("scene.toml").as_os_str(),
            "-o".as_ref(),
            host_png.as_os_str(),
        ]),
        "tessera render",
        "tessera render of the new firmware's scene failed",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let diff = firmware::checked(
        &mut tessera(&["diff".as_ref(), chip.as_os_str(), host_png.as_os_str()]),
        "tessera diff",
        "the new firmware's picture differs from the host's",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let said = String::from_utf8_lossy(&diff.stdout);
    assert!(
        said.lines()
            .any(|l| l.split_whitespace().eq(["identical", "yes"])),
        "{said}"
    );
    // And by this test's own reading of both.
    let picture = ppm(&std::fs::read(&chip).unwrap()).unwrap();
    let want = host(&project.join("scene.toml"));
    assert!(
        picture.as_raw() == want.as_raw(),
        "the new firmware's picture is not the host's"
    );
    println!(
        "tessera new: generated in {:.1} s, built in {:.1} s, ran in {:.1} s ({stdout})",
        generated.as_secs_f64(),
        (built - generated).as_secs_f64(),
        (ran - built).as_secs_f64()
    );
}

/// The bench for any Cortex-M (`examples/qemu-m4f/bench`, docs/bench.md), built
/// in its folder and run under qemu, where the cycle counter does not count:
/// it says so and prints no cycle figure, and each built-in scene's checksum is
/// the host's picture's at 240x240 (its own settings, tiles of 16), as are the
/// checksums and the output docs/bench.md shows.
#[test]
fn the_bench_says_the_counter_does_not_count_and_draws_the_hosts_pictures() {
    use tessera_core::Viewport;
    use tessera_core::builtin::Builtin;
    firmware::qemu_version().unwrap_or_else(|e| panic!("{e}"));
    let dir = example().join("bench");
    // In the example's target folder: the core and cortex-m-rt are compiled
    // once for both.
    let target = example().join("target");
    firmware::checked(
        firmware::cargo()
            .current_dir(&dir)
            .args(["build", "--release", "--target-dir"])
            .arg(&target),
        "cargo to build examples/qemu-m4f/bench",
        "building examples/qemu-m4f/bench failed",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let elf = target.join("thumbv7em-none-eabihf/release/qemu-m4f-bench");
    let out = firmware::run_alone(&elf).unwrap_or_else(|e| panic!("{e}"));
    assert!(
        out.contains("cycle counter: absent or stopped") && !out.contains("cycles="),
        "the bench gives a cycle figure under qemu, or does not say the counter is stopped:\n{out}"
    );
    let docs = std::fs::read_to_string(firmware::repo_root().join("docs/bench.md")).unwrap();
    for &b in Builtin::ALL {
        let line = out
            .lines()
            .find(|l| l.starts_with(&format!("{}: ", b.name())))
            .unwrap_or_else(|| panic!("no line for {}:\n{out}", b.name()));
        assert!(line.contains("no cycle figure"), "{line}");
        assert!(number(line, "instructions") > 0, "{line}");
        let host = b
            .with_baked_scene(|view, cam| {
                tessera_host::render(view, cam, Viewport::new(240, 240), b.settings(), 16)
            })
            .unwrap()
            .unwrap();
        let want = format!("{:016x}", tile_order_fnv1a64(&host, 16));
        assert_eq!(field(line, "checksum"), want, "{}: {line}", b.name());
        assert!(
            docs.contains(&format!("| {} | `{want}` |", b.name())),
            "docs/bench.md lacks the host's checksum of {}: {want}",
            b.name()
        );
        // The output docs/bench.md shows: the line up to its instructions
        // (which move as the core changes), and its checksum.
        let head = line.split(" instructions=").next().unwrap_or(line);
        assert!(
            docs.contains(head) && docs.contains(&format!("checksum={want}")),
            "docs/bench.md does not show the bench's line under qemu: {line}"
        );
    }
}
