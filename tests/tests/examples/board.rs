//! The board example (`examples/blackpill-st7789`, an STM32F411 "Black Pill" with an
//! ST7789 panel): it builds and links for the Cortex-M4F within the chip's memory,
//! and its README's sizes are those of the linked ELF (its default build, with the
//! feature `defmt`).

use std::path::PathBuf;
use tessera_tests::firmware::{self, Sizes};
use tessera_tests::readme::{figure_after, llvm_size_row, table_figure, within};
use tessera_tests::thousands;

fn example() -> PathBuf {
    firmware::repo_root()
        .join("examples")
        .join("blackpill-st7789")
}

#[test]
fn the_board_example_links_within_the_chip_and_its_readme_has_its_sizes() {
    let dir = example();
    let elf = firmware::build_elf(
        &dir.join("Cargo.toml"),
        &dir.join("target"),
        &[],
        "blackpill-st7789",
        "the board example",
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let s: Sizes = firmware::sections(&elf).unwrap();
    let (flash, ram) = firmware::memory_regions(&dir.join("memory.x")).unwrap();
    assert_eq!(
        (flash, ram),
        (512 * 1024, 128 * 1024),
        "the STM32F411CE's memory"
    );
    assert!(s.flash() <= flash && s.ram() <= ram, "{s:?}");
    // It renders the teapot from flash: the baked mesh and BVH are in .rodata.
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
