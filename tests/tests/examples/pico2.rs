//! The Raspberry Pi Pico 2 example (`examples/pico2-st7789`, an RP2350 with a
//! Waveshare Pico-LCD-1.3): it builds and links for the Cortex-M33 within the
//! Pico 2's flash and the RP2350's RAM (the statics and both cores' stacks), the
//! boot ROM finds its block and the boot stack is core 0's, its README's sizes
//! are those of the linked ELF (its default build, with the features `defmt` and
//! `fps-label`; the RAM copy of the animated scene's instances among them), and
//! its frame-rate estimate is docs/chip-cost.md's for the animated scene.

use object::{Object, ObjectSection, ObjectSymbol};
use std::path::PathBuf;
use tessera_tests::firmware::{self, Sizes};
use tessera_tests::readme::{figure_after, llvm_size_row, table_figure, within};
use tessera_tests::thousands;

/// Where the RP2350 maps the QSPI flash (XIP).
const FLASH_ORIGIN: u64 = 0x1000_0000;
/// The Pico 2's flash: 4 MiB.
const PICO2_FLASH: u64 = 4 * 1024 * 1024;
/// The RP2350's SRAM: 520 KiB (SRAM0 to SRAM7 striped, then SRAM8 and SRAM9).
const RP2350_SRAM: u64 = 520 * 1024;
/// SRAM8 and SRAM9, where `memory.x` puts core 0's stack.
const CORE0_STACK: (u64, u64) = (0x2008_0000, 0x2008_2000);
/// The boot ROM looks for the IMAGE_DEF block within the first 4 KiB of flash.
const BOOT_SEARCH: u64 = 4 * 1024;

fn example() -> PathBuf {
    firmware::repo_root().join("examples").join("pico2-st7789")
}

#[test]
fn the_pico2_example_links_within_the_rp2350_and_its_readme_has_its_sizes() {
    let dir = example();
    // Built in the qemu example's target folder, as the board example is: the
    // scene baker all three build scripts use (tessera-host, a
    // build-dependency of each, the same versions in each lock file) is compiled
    // once for the three (`tests/run-all.sh` lints it there too).
    let elf = firmware::CORTEX_M33
        .build_elf(
            &dir.join("Cargo.toml"),
            &tessera_tests::qemu_example::example().join("target"),
            &[],
            "pico2-st7789",
            "the Pico 2 example",
        )
        .unwrap_or_else(|e| panic!("{e}"));
    let s: Sizes = firmware::sections(&elf).unwrap();
    let bytes = std::fs::read(&elf).unwrap();
    let file = object::File::parse(&*bytes).unwrap();
    let section = |name: &str| file.section_by_name(name);
    let size = |name: &str| section(name).map_or(0, |sec| sec.size());
    let symbol = |name: &str| {
        file.symbols()
            .find(|sym| sym.name() == Ok(name))
            .map(|sym| sym.address())
    };

    // The RP2350's sections besides cortex-m-rt's: the boot block and picotool's
    // entries are flashed too.
    let (start_block, bi_entries, end_block) = (
        size(".start_block"),
        size(".bi_entries"),
        size(".end_block"),
    );
    // tessera's code, stored in flash and run from SRAM (ram.x).
    let ram_text = size(".ram_text");
    let flash = s.flash() + start_block + bi_entries + end_block + ram_text;
    let statics = s.ram() + ram_text;

    let (flash_region, ram_region) = firmware::memory_regions(&dir.join("memory.x")).unwrap();
    assert_eq!(
        (flash_region, ram_region),
        (PICO2_FLASH, 512 * 1024),
        "the Pico 2's flash and the RP2350's striped SRAM"
    );
    assert!(flash <= flash_region, "flash {flash} bytes: {s:?}");
    assert!(statics <= ram_region, "statics {statics} bytes: {s:?}");

    // The boot ROM's IMAGE_DEF block lies in the first 4 KiB of flash.
    let boot = section(".start_block").expect("a .start_block section");
    assert!(
        start_block > 0 && boot.address() >= FLASH_ORIGIN,
        "no boot block: {start_block} bytes at {:#x}",
        boot.address()
    );
    assert!(
        boot.address() + start_block <= FLASH_ORIGIN + BOOT_SEARCH,
        "the boot block ends at {:#x}, beyond the first 4 KiB of flash",
        boot.address() + start_block
    );

    // tessera's code runs from SRAM: stored after the boot block, `.text`
    // after it, the renderer's functions at SRAM addresses, and the copy
    // (`__pre_init`) in flash, where it runs before SRAM holds anything.
    let ram_code = section(".ram_text").expect("a .ram_text section (ram.x)");
    assert!(
        ram_text > 64 * 1024 && (0x2000_0000..0x2008_0000).contains(&ram_code.address()),
        ".ram_text: {ram_text} bytes at {:#x}",
        ram_code.address()
    );
    let text = section(".text").expect("a .text section");
    let load = symbol("__siram_text").expect("__siram_text");
    assert_eq!(
        (load, text.address()),
        (
            boot.address() + start_block,
            (load + ram_text).next_multiple_of(text.align())
        ),
        "tessera's code is stored right after the boot block and .text after it"
    );
    let in_ram = |name: &str| {
        firmware::symbols(&elf)
            .unwrap()
            .into_iter()
            .filter(|sym| sym.name.contains(name))
            .map(|sym| sym.address)
            .collect::<Vec<_>>()
    };
    let renders = in_ram("tessera_core::tile::renderer::Renderer::render_tile");
    assert!(
        !renders.is_empty()
            && renders
                .iter()
                .all(|a| (0x2000_0000..0x2008_0000).contains(a)),
        "the tile renderer is not in SRAM: {renders:#x?}"
    );
    let pre_init = symbol("__pre_init").expect("__pre_init (src/ram.rs)");
    assert!(
        (FLASH_ORIGIN..FLASH_ORIGIN + PICO2_FLASH).contains(&pre_init),
        "__pre_init at {pre_init:#x}, not in flash"
    );

    // Core 0's stack is SRAM8 and SRAM9: cortex-m-rt's symbols, and the initial
    // stack pointer of the vector table (its first word).
    let (top, limit) = (symbol("_stack_start"), symbol("_stack_end"));
    assert_eq!(
        (limit, top),
        (Some(CORE0_STACK.0), Some(CORE0_STACK.1)),
        "core 0's stack (_stack_end, _stack_start)"
    );
    let vectors = section(".vector_table").expect("a vector table");
    let data = vectors.data().unwrap();
    let initial_sp = data
        .get(..4)
        .map(|w| u64::from(u32::from_le_bytes([w[0], w[1], w[2], w[3]])));
    assert_eq!(initial_sp, Some(CORE0_STACK.1), "the boot stack pointer");
    let core0_stack = CORE0_STACK.1 - CORE0_STACK.0;

    // Core 1's stack is a static of 8 KiB (and its "taken" flag).
    let core1_stack = firmware::symbols(&elf)
        .unwrap()
        .into_iter()
        .find(|sym| sym.name == "pico2_st7789::CORE1_STACK")
        .map(|sym| sym.size);
    assert!(
        core1_stack.is_some_and(|n| n >= 8 * 1024 && n <= s.bss),
        "core 1's stack: {core1_stack:?}"
    );
    // The instances the animation moves: one static in RAM (`mod placed`), which
    // the README states.
    let instances = firmware::symbols(&elf)
        .unwrap()
        .into_iter()
        .find(|sym| sym.name == "pico2_st7789::placed::SLOT")
        .map(|sym| sym.size);
    assert!(
        instances.is_some_and(|n| n > 0 && n <= s.bss),
        "the instances' static: {instances:?}"
    );
    let ram = statics + core0_stack;
    assert!(
        ram <= RP2350_SRAM,
        "statics {statics} + core 0's stack {core0_stack} bytes"
    );

    let readme = std::fs::read_to_string(dir.join("README.md")).unwrap();
    let mut wrong = Vec::new();
    // Within 1 %, as the Black Pill's (tests/tests/board.rs): the same sources
    // built in another folder link a little differently.
    let mut expect = |what: &str, said: Option<u64>, truth: u64| {
        if !within(said, truth, 1) {
            wrong.push(format!("{what}: the README says {said:?}, the ELF {truth}"));
        }
    };
    for (name, truth) in [
        (".vector_table", s.vector_table),
        (".start_block", start_block),
        (".ram_text", ram_text),
        (".text", s.text),
        (".bi_entries", bi_entries),
        (".rodata", s.rodata),
        (".data", s.data),
        (".bss", s.bss),
        (".uninit", s.uninit),
    ] {
        expect(name, table_figure(&readme, name), truth);
    }
    let said_flash = figure_after(&readme, "- **Flash**: ");
    expect("flash", said_flash, flash);
    expect(
        "static RAM",
        figure_after(
            &readme,
            "- **Static RAM** (`.ram_text` + `.data` + `.bss` + `.uninit`): ",
        ),
        statics,
    );
    // The llvm-size row of the default build: Berkeley text (every flash
    // section but `.data`), data, bss (with `.uninit`) and flash.
    for (what, said, truth) in llvm_size_row(
        &readme,
        "| default (`defmt`, `fps-label`) |",
        [flash - s.data, s.data, s.bss + s.uninit, flash],
    ) {
        expect(&format!("llvm-size {what}"), said, truth);
    }
    if let Some(n) = instances {
        expect(
            "the instances' RAM",
            figure_after(&readme, "- **The animation's RAM**: "),
            n,
        );
    }
    let said_ram = figure_after(&readme, "- **RAM with core 0's stack**: ");
    expect("RAM with core 0's stack", said_ram, ram);
    // The README's figures in KiB and per cent are its bytes'.
    if let Some(f) = said_flash {
        let kib = format!(
            "{} bytes ({:.1} KiB) of 4,096 KiB, {:.1} %",
            thousands(f),
            f as f64 / 1024.0,
            100.0 * f as f64 / PICO2_FLASH as f64
        );
        if !readme.contains(&kib) {
            wrong.push(format!("flash: the README lacks `{kib}`"));
        }
    }
    if let Some(r) = said_ram {
        let kib = format!(
            "{} bytes ({:.1} KiB) of the RP2350's 520 KiB",
            thousands(r),
            r as f64 / 1024.0
        );
        if !readme.contains(&kib) {
            wrong.push(format!("RAM: the README lacks `{kib}`"));
        }
    }
    // The frame-rate estimate is the report's (docs/chip-cost.md, written by
    // chip-report): the animated scene's cycles a pixel on a Pico 2 and its
    // frames a second on both cores.
    for said in pico2_estimate() {
        if !readme.contains(&said) {
            wrong.push(format!(
                "estimate: the README lacks `{said}` (docs/chip-cost.md)"
            ));
        }
    }
    assert!(
        wrong.is_empty(),
        "examples/pico2-st7789/README.md is not the linked ELF ({}): {wrong:#?}",
        elf.display()
    );

    // The flash-only layout (everything run from flash): built after the
    // default in the same folder, so here rather than in a test of its own,
    // which would build in parallel over the same ELF.
    let elf = firmware::CORTEX_M33
        .build_elf(
            &dir.join("Cargo.toml"),
            &tessera_tests::qemu_example::example().join("target"),
            &["flash-only"],
            "pico2-st7789",
            "the Pico 2 example, flash-only",
        )
        .unwrap_or_else(|e| panic!("{e}"));
    let s: Sizes = firmware::sections(&elf).unwrap();
    let bytes = std::fs::read(&elf).unwrap();
    let file = object::File::parse(&*bytes).unwrap();
    assert!(
        file.section_by_name(".ram_text").is_none(),
        "flash-only has a .ram_text"
    );
    let size = |name: &str| file.section_by_name(name).map_or(0, |sec| sec.size());
    let boot = file.section_by_name(".start_block").expect("a boot block");
    let text = file.section_by_name(".text").expect("a .text section");
    assert_eq!(
        text.address(),
        (boot.address() + boot.size()).next_multiple_of(text.align()),
        ".text right after the boot block"
    );
    let flash = s.flash() + size(".start_block") + size(".bi_entries") + size(".end_block");
    let mut wrong = Vec::new();
    for (what, said, truth) in llvm_size_row(
        &readme,
        "| `--features flash-only`",
        [flash - s.data, s.data, s.bss + s.uninit, flash],
    ) {
        if !within(said, truth, 1) {
            wrong.push(format!(
                "flash-only llvm-size {what}: the README says {said:?}, the ELF {truth}"
            ));
        }
    }
    assert!(wrong.is_empty(), "{wrong:#?}");
}

/// What docs/chip-cost.md's section on the animated scene estimates for the
/// Pico 2 example, as the README words it: `N cycles a pixel` and `F frames a
/// second` (two cores).
fn pico2_estimate() -> [String; 2] {
    let report = std::fs::read_to_string(firmware::repo_root().join("docs/chip-cost.md")).unwrap();
    let section = report
        .split("\n## ")
        .find(|s| s.starts_with("An animation's frames"))
        .expect("docs/chip-cost.md has its section on the animated scene");
    let said = section
        .split("The Pico 2 example's estimate, the mean of these frames: ")
        .nth(1)
        .expect("the section's estimate for the Pico 2 example");
    let (cycles, rest) = said
        .split_once(" cycles a pixel, ")
        .expect("the estimate's cycles a pixel");
    let (fps, _) = rest
        .split_once(" frames a second")
        .expect("the estimate's frames a second");
    [
        format!("{cycles} cycles a pixel"),
        format!("{fps} frames a second"),
    ]
}

/// The Pico 2's code placement (`ram.x`, `src/ram.rs`), run where it can run:
/// the qemu example, copied to a scratch folder and linked with the same
/// script (anchored after the vector table, which is where that chip's image
/// starts, and with 512 KiB of RAM, which qemu's `mps2-an386` has), renders
/// its default scene on the Cortex-M4F from SRAM: the copy at reset and the
/// linker's thunks between flash and SRAM work, the renderer lies in SRAM, and
/// the picture is the host's, byte for byte.
#[test]
fn the_pico2_code_placement_runs_from_sram_under_qemu() {
    use tessera_tests::qemu_example;
    let pico2 = example();
    let template = qemu_example::example();
    let scratch = firmware::TempDir::new().unwrap();
    let dir = scratch.path().join("qemu-m4f-in-sram");
    let repo = firmware::repo_root();
    // The example's files, its symbolic links followed; its dependencies by
    // absolute path.
    for rel in [
        "Cargo.toml",
        "Cargo.lock",
        "build.rs",
        "scene.toml",
        "icosahedron.obj",
        "src/main.rs",
        "src/animation.rs",
        "src/clock.rs",
        "src/ppm.rs",
        "src/stack.rs",
        ".cargo/config.toml",
    ] {
        let to = dir.join(rel);
        std::fs::create_dir_all(to.parent().unwrap()).unwrap();
        let text = std::fs::read_to_string(template.join(rel))
            .unwrap_or_else(|e| panic!("examples/qemu-m4f/{rel}: {e}"));
        let mut text = text.replace("\"../../", &format!("\"{}/", repo.display()));
        if rel == "Cargo.toml" {
            // Its own name: the ELF shares the example's target folder, where
            // the qemu example's tests build and run theirs.
            text = text.replace("name = \"qemu-m4f\"", "name = \"qemu-m4f-in-sram\"");
        }
        std::fs::write(&to, text).unwrap();
    }
    let ram_x = std::fs::read_to_string(pico2.join("ram.x")).unwrap();
    assert!(
        ram_x.contains("ADDR(.start_block) + SIZEOF(.start_block)"),
        "ram.x stores the code after the boot block"
    );
    let memory = std::fs::read_to_string(template.join("memory.x"))
        .unwrap()
        .replace("LENGTH = 128K", "LENGTH = 512K");
    let ram_here = ram_x.replace(
        "ADDR(.start_block) + SIZEOF(.start_block)",
        "ADDR(.vector_table) + SIZEOF(.vector_table)",
    );
    // The qemu example's memory.x does not set `_stext` (link.x provides it
    // after the vector table): `.text` goes after the stored code.
    std::fs::write(
        dir.join("memory.x"),
        format!("{memory}\n{ram_here}\n_stext = __siram_text + __ram_text_size;\n"),
    )
    .unwrap();
    let main = dir.join("src/main.rs");
    let mut text = std::fs::read_to_string(&main).unwrap();
    text.push_str(&format!(
        "\n#[path = \"{}\"]\nmod ram;\n",
        pico2.join("src/ram.rs").display()
    ));
    std::fs::write(&main, text).unwrap();

    let target = template.join("target");
    firmware::checked(
        firmware::cargo()
            .current_dir(&dir)
            .args(["build", "--release", "--target-dir"])
            .arg(&target)
            .env_remove("TESSERA_SCENE"),
        "cargo to build the qemu example with the Pico 2's code placement",
        "building the qemu example with ram.x failed",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let elf = target.join("thumbv7em-none-eabihf/release/qemu-m4f-in-sram");
    let bytes = std::fs::read(&elf).unwrap();
    let file = object::File::parse(&*bytes).unwrap();
    let ram_text = file
        .section_by_name(".ram_text")
        .expect("a .ram_text section");
    assert!(
        ram_text.size() > 64 * 1024 && ram_text.address() == 0x2000_0000,
        ".ram_text: {} bytes at {:#x}",
        ram_text.size(),
        ram_text.address()
    );
    let renders: Vec<u64> = firmware::symbols(&elf)
        .unwrap()
        .into_iter()
        .filter(|s| {
            s.name
                .contains("tessera_core::tile::renderer::Renderer::render_tile")
        })
        .map(|s| s.address)
        .collect();
    assert!(
        !renders.is_empty() && renders.iter().all(|a| *a >= 0x2000_0000),
        "the tile renderer is not in RAM: {renders:#x?}"
    );

    let run = firmware::TempDir::new().unwrap();
    let stdout = firmware::run_in(run.path(), &elf).unwrap_or_else(|e| panic!("{e}"));
    let picture =
        qemu_example::ppm(&std::fs::read(run.path().join(qemu_example::PICTURE)).unwrap()).unwrap();
    let host = qemu_example::host(&template.join(qemu_example::DEFAULT));
    assert!(
        picture.as_raw() == host.as_raw(),
        "from SRAM, the qemu example's picture is not the host's:\n{stdout}"
    );
}
