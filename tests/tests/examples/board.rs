//! The board example (`examples/blackpill-st7789`, an STM32F411 "Black Pill" with an
//! ST7789 panel): it builds and links for the Cortex-M4F within the chip's memory,
//! for its default scene file (the teapot) and for a textured one named by
//! `TESSERA_SCENE`, with the scene's tables in flash; and its README's sizes are
//! those of the linked ELF (its default build, with the feature `defmt`).

use std::path::PathBuf;
use tessera_tests::firmware::{self, Sizes, Symbol};
use tessera_tests::readme::{figure_after, llvm_size_row, table_figure, within};
use tessera_tests::thousands;

/// A scene file besides the default, as `TESSERA_SCENE` names it (relative to the
/// example's folder): files from 3D tools, with image textures (RGB565, in flash)
/// and a sun, which the README's "Another scene" builds.
const TEXTURED: &str = "../../tests/data/tools.toml";

fn example() -> PathBuf {
    firmware::repo_root()
        .join("examples")
        .join("blackpill-st7789")
}

/// The target folder the example is built in here: the qemu example's, so that
/// the scene baker both build scripts use (tessera-host and its readers, a
/// build-dependency of each, the same versions in both lock files) is compiled
/// once for the two (`tests/run-all.sh` lints it there too). A user's build in
/// the example's own folder links the same code (the README's figures are
/// checked within 1 %).
fn target_dir() -> PathBuf {
    tessera_tests::qemu_example::example().join("target")
}

/// Builds the example as a user does (`cargo build --release` in its folder: its
/// `.cargo/config.toml` names the target; in [`target_dir`]) for the scene file
/// `scene` (`TESSERA_SCENE`; `None`: its default, the teapot) with the core's
/// features the scene needs, as its build.rs asks for them, and returns the
/// ELF's path.
fn build(scene: Option<&str>) -> Result<PathBuf, String> {
    let dir = example();
    let mut cmd = firmware::cargo();
    cmd.current_dir(&dir)
        .args(["build", "--release"])
        .env("CARGO_TARGET_DIR", target_dir());
    if let Some(scene) = scene {
        let desc = tessera_host::file::load(&dir.join(scene)).map_err(|e| e.to_string())?;
        let features = tessera_host::bake::kind_features(&desc);
        if !features.is_empty() {
            cmd.args(["--features", &features.join(",")]);
        }
        cmd.env("TESSERA_SCENE", scene);
    } else {
        cmd.env_remove("TESSERA_SCENE");
    }
    let name = scene.unwrap_or("its default scene");
    firmware::checked(
        &mut cmd,
        "cargo to build examples/blackpill-st7789",
        &format!(
            "building examples/blackpill-st7789 for {name} failed; is the {} target \
             installed? ({})",
            firmware::TARGET,
            firmware::INSTALL_HINT
        ),
    )?;
    let elf = target_dir()
        .join(firmware::TARGET)
        .join("release")
        .join("blackpill-st7789");
    if elf.is_file() {
        Ok(elf)
    } else {
        Err(format!(
            "the build for {name} left no ELF at {}",
            elf.display()
        ))
    }
}

/// The scene's tables in `elf`: the statics of the firmware's module `scene`, each
/// asserted to lie in `.rodata` (flash).
fn tables_in_flash(elf: &std::path::Path, what: &str) -> Vec<Symbol> {
    let tables: Vec<Symbol> = firmware::symbols(elf)
        .unwrap_or_else(|e| panic!("{e}"))
        .into_iter()
        .filter(|s| s.name.starts_with("blackpill_st7789::scene::"))
        .collect();
    assert!(!tables.is_empty(), "{what}: no scene tables in the ELF");
    for t in &tables {
        assert_eq!(
            t.section.as_deref(),
            Some(".rodata"),
            "{what}: {t:?} is not in flash"
        );
    }
    tables
}

#[test]
fn the_board_example_links_within_the_chip_and_its_readme_has_its_sizes() {
    let dir = example();
    let (flash, ram) = firmware::memory_regions(&dir.join("memory.x")).unwrap();
    assert_eq!(
        (flash, ram),
        (512 * 1024, 128 * 1024),
        "the STM32F411CE's memory"
    );

    // Another scene file first (the default last, so that the ELF left in the
    // example's target folder is the one a user builds there): it links within
    // the chip, its image textures in flash.
    let textured = build(Some(TEXTURED)).unwrap_or_else(|e| panic!("{e}"));
    let t: Sizes = firmware::sections(&textured).unwrap();
    assert!(t.flash() <= flash && t.ram() <= ram, "{TEXTURED}: {t:?}");
    let tables = tables_in_flash(&textured, TEXTURED);
    let images: Vec<&Symbol> = tables
        .iter()
        .filter(|s| s.name.starts_with("blackpill_st7789::scene::IMAGE"))
        .collect();
    assert!(
        !images.is_empty() && images.iter().all(|s| s.size > 0),
        "{TEXTURED}: no image tables (IMAGE0...) in the ELF"
    );
    let image_bytes: u64 = images.iter().map(|s| s.size).sum();

    let elf = build(None).unwrap_or_else(|e| panic!("{e}"));
    let s: Sizes = firmware::sections(&elf).unwrap();
    assert!(s.flash() <= flash && s.ram() <= ram, "{s:?}");
    // It renders the teapot from flash: the baked mesh and BVH are in .rodata,
    // the scene file's bake the core's built-in teapot's, table for table.
    let mesh = {
        use std::mem::size_of_val;
        use tessera_core::builtin::baked::teapot as t;
        size_of_val(&t::MESH0_VERTICES)
            + size_of_val(&t::MESH0_NORMALS)
            + size_of_val(&t::MESH0_FACES)
            + size_of_val(&t::MESH0_NODES)
            + size_of_val(&t::MESH0_ORDER)
    };
    assert!(
        s.rodata >= mesh as u64,
        "{s:?}: the teapot's mesh and BVH are {mesh} bytes"
    );
    let baked: u64 = tables_in_flash(&elf, "the teapot")
        .iter()
        .filter(|s| s.name.contains("::MESH0_"))
        .map(|s| s.size)
        .sum();
    assert_eq!(
        baked, mesh as u64,
        "the default scene's mesh and BVH tables are not the built-in teapot's"
    );

    let readme = std::fs::read_to_string(dir.join("README.md")).unwrap();
    let mut wrong = Vec::new();
    // Within 1 %: the same sources built in another folder link a little
    // differently (the crates' paths enter their symbol hashes, which moves code
    // alignment: 128 bytes of `.text` measured); a stale figure is further off.
    let mut expect = |what: &str, said: Option<u64>, truth: u64| {
        if !within(said, truth, 1) {
            wrong.push(format!("{what}: the README says {said:?}, the ELF {truth}"));
        }
    };
    // The textured scene's build, as "Another scene" states it.
    for (what, label, truth) in [
        ("tools.toml flash", "- flash: ", t.flash()),
        ("tools.toml images", "of which the images: ", image_bytes),
        ("tools.toml static RAM", "- static RAM: ", t.ram()),
    ] {
        expect(what, figure_after(&readme, label), truth);
    }
    for (section, truth) in [
        (".vector_table", s.vector_table),
        (".text", s.text),
        (".rodata", s.rodata),
        (".data", s.data),
        (".bss", s.bss),
        (".uninit", s.uninit),
    ] {
        expect(section, table_figure(&readme, section), truth);
    }
    let said_flash = figure_after(&readme, "- **Flash**: ");
    expect("flash", said_flash, s.flash());
    expect(
        "static RAM",
        figure_after(&readme, "- **Static RAM** (`.data` + `.bss` + `.uninit`): "),
        s.ram(),
    );
    // The llvm-size row of the default build: Berkeley text (flash less
    // `.data`), data, bss (with `.uninit`) and flash.
    for (what, said, truth) in llvm_size_row(
        &readme,
        "| default (`defmt`) |",
        [s.flash() - s.data, s.data, s.bss + s.uninit, s.flash()],
    ) {
        expect(&format!("llvm-size {what}"), said, truth);
    }
    // The README's flash figure in KiB and per cent is its bytes'.
    if let Some(f) = said_flash {
        let kib = format!(
            "{} bytes ({:.1} KiB) of 512 KiB, {:.0} %",
            thousands(f),
            f as f64 / 1024.0,
            100.0 * f as f64 / 524_288.0
        );
        if !readme.contains(&kib) {
            wrong.push(format!("flash: the README lacks `{kib}`"));
        }
    }
    assert!(
        wrong.is_empty(),
        "examples/blackpill-st7789/README.md is not the linked ELF ({}): {wrong:#?}",
        elf.display()
    );
}
