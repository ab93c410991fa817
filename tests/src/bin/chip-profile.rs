//! `chip-profile`: where tessera's instructions and cycles go on a Cortex-M4F, and
//! on the host; writes `docs/chip-profile.md`.
//!
//! Builds the exact firmware, compiles the qemu plugin `tests/profiler/insn_profile.c`,
//! runs five renders under qemu with it (each built-in scene at 64x64 with its own
//! settings, and chapter-direct with stratified 4x4 sampling), checks the plugin's
//! instruction counts against the firmware's SysTick counts, attributes every
//! instruction to its source function (inlined frames included, from the DWARF of
//! the ELF), estimates Cortex-M4 cycles ([`tessera_tests::cycles`]) and, where
//! valgrind is installed, profiles the host binary under callgrind.
//!
//! ```sh
//! cargo run -p tessera-tests --release --bin chip-profile
//! ```

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;
use tessera_tests::cycles;
use tessera_tests::dwarf::{self, Symbolizer};
use tessera_tests::firmware::{self, RunResult};
use tessera_tests::profile::{self, Profile};
use tessera_tests::profile_doc::{self, HOST_SCENES, Measured};
use tessera_tests::{baseline, callgrind, thousands};

const COMMAND: &str = "cargo run -p tessera-tests --release --bin chip-profile";

fn main() -> ExitCode {
    let start = Instant::now();
    match report() {
        Ok(path) => {
            println!(
                "wrote {} in {:.0} s",
                path.display(),
                start.elapsed().as_secs_f64()
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("chip-profile: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Profiles the firmware (and the host, when valgrind is there) and writes
/// `docs/chip-profile.md`; returns its path.
fn report() -> Result<PathBuf, String> {
    let qemu = firmware::qemu_version()?;
    let rustc = tessera_tests::tool_version("rustc");
    let cc = tessera_tests::tool_version(&std::env::var("CC").unwrap_or_else(|_| "gcc".into()));
    let measured = profile_firmware()?;
    let host = profile_host()?;
    let path = firmware::repo_root().join("docs").join("chip-profile.md");
    let d = document(&qemu, &rustc, &cc, &measured, host.as_ref());
    std::fs::write(&path, d).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    Ok(path)
}

/// Builds the firmware and the qemu plugin, profiles the guarded runs (one qemu
/// each, in parallel), checks each plugin total against SysTick's, and attributes
/// the instructions and their cycles to source functions.
fn profile_firmware() -> Result<Vec<Measured>, String> {
    println!("building the firmware and the qemu plugin...");
    let elf = firmware::build(&[])?;
    let plugin = profile::build_plugin()?;
    let markers = profile::markers(&elf)?;
    // The guarded runs (`tests/chip-baseline.txt`).
    let runs = baseline::runs();
    println!("profiling {} renders under qemu...", runs.len());
    let results: Vec<Result<(RunResult, Profile), String>> = std::thread::scope(|s| {
        let handles: Vec<_> = runs
            .iter()
            .map(|r| s.spawn(|| profile::run(&elf, &plugin, markers, r)))
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err("a profiling thread panicked".into()))
            })
            .collect()
    });
    let sym = Symbolizer::new(&elf)?;
    let mut measured = Vec::new();
    for (run, res) in runs.iter().zip(results) {
        let (systick, profile) = res?;
        let diff = profile::check_total(run, &systick, &profile)?;
        let costs = cycles::costs(&profile.insns);
        let frames = dwarf::attribute(&sym, &profile.insns);
        let functions = dwarf::by_function(&frames, &profile.insns, &costs);
        let inclusive = dwarf::inclusive(&frames, &profile.insns, &costs);
        measured.push(Measured {
            run: *run,
            systick,
            profile,
            diff,
            costs,
            functions,
            inclusive,
        });
    }
    Ok(measured)
}

/// The host's profiles under callgrind, with valgrind's version; `None` without
/// valgrind.
fn profile_host() -> Result<Option<(String, Vec<callgrind::HostProfile>)>, String> {
    Ok(match callgrind::valgrind_version() {
        Some(v) => {
            println!("building the host binary and profiling it under callgrind...");
            let bin = callgrind::build_host()?;
            let profiles = HOST_SCENES
                .iter()
                .map(|s| callgrind::profile(&bin, s))
                .collect::<Result<Vec<_>, _>>()?;
            Some((v, profiles))
        }
        None => None,
    })
}

/// The document, section after section.
fn document(
    qemu: &str,
    rustc: &str,
    cc: &str,
    measured: &[Measured],
    host: Option<&(String, Vec<callgrind::HostProfile>)>,
) -> String {
    let mut d = String::new();
    let w = &mut d;
    let _ = writeln!(
        w,
        "# tessera on a Cortex-M4F: where the instructions and cycles go\n"
    );
    let _ = writeln!(
        w,
        "Generated by `{COMMAND}` (do not edit by hand; run it again after changing the \
         core or the firmware). Companion of [chip-cost.md](chip-cost.md), which counts \
         instructions for every setting; this file says where they go, and what they \
         would cost in cycles.\n"
    );
    summary(w, measured);
    method(w, qemu, rustc, cc, measured);
    profile_doc::cycle_model(w);
    for m in measured {
        profile_doc::run_section(w, m);
    }
    profile_doc::host_section(w, host);
    let _ = writeln!(w, "## Regenerate\n");
    let _ = writeln!(
        w,
        "It needs `qemu-system-arm` 7.2 or later (with plugin support, as Debian's), the \
         `thumbv7em-none-eabihf` target, a C compiler (`gcc`, or `$CC`) for the plugin, and \
         valgrind for the host section (left out, with a note, without it):\n"
    );
    let _ = writeln!(w, "```sh\n{COMMAND}\n```");
    d
}

fn summary(w: &mut String, measured: &[Measured]) {
    let _ = writeln!(w, "## Summary\n");
    let _ = writeln!(
        w,
        "Instructions and estimated cycles per pixel inside `render_tile`, 64x64 pixels, \
         tiles of 16x16, seed 0. `SysTick` is the firmware's own count (as in \
         chip-cost.md), `plugin` the profile's; their difference is explained under \
         [How it is measured](#how-it-is-measured). Cycles are an **estimate** from the \
         instruction mix ([the model](#the-cycle-estimate)), with a taken branch costing \
         1 + P, P = {} (columns for P = 1 and 3 show how much hangs on it).\n",
        cycles::REFILL
    );
    let _ = writeln!(
        w,
        "| run | SysTick instr/px | plugin instr/px | SysTick - plugin, instr/tile | est. cycles/px | cycles/instr | est. cycles/px, P = 1 / 3 |"
    );
    let _ = writeln!(w, "|---|---|---|---|---|---|---|");
    for m in measured {
        let tiles = profile::tiles(&m.run) as f64;
        let c = m.cycles_at(cycles::REFILL);
        let _ = writeln!(
            w,
            "| {} | {:.1} | {:.1} | {:+.1} | {} | {:.2} | {} / {} |",
            m.title(),
            m.systick.instructions_per_pixel(),
            m.per_px(m.profile.total),
            m.diff as f64 / tiles,
            thousands((m.per_px(c)).round() as u64),
            c as f64 / m.profile.total.max(1) as f64,
            thousands(m.per_px(m.cycles_at(1)).round() as u64),
            thousands(m.per_px(m.cycles_at(3)).round() as u64),
        );
    }
    let _ = writeln!(w);
}

fn method(w: &mut String, qemu: &str, rustc: &str, cc: &str, measured: &[Measured]) {
    let _ = writeln!(w, "## How it is measured\n");
    let _ = writeln!(
        w,
        "- Chip: qemu's `mps2-an386` board (Cortex-M4F), `-icount shift=0`, {qemu}; \
         firmware `tests/firmware` (exact math) built by {rustc} with its pinned release \
         profile (`opt-level = 3`, fat LTO, `debug = true`)."
    );
    let _ = writeln!(
        w,
        "- The plugin `{}` (built with {cc}) registers a callback on every guest \
         instruction: exact counts per PC, whatever qemu's translation blocks look like. \
         It counts only while armed: from the first instruction of \
         `{}` to the first of `{}`, two empty functions the firmware calls just before \
         and after each `render_tile` (their addresses come from the ELF's symbol table). \
         Per PC it also counts how often the next instruction executed was not at \
         `pc + size`: the taken branches.",
        profile::PLUGIN_SOURCE,
        profile::BEGIN,
        profile::END
    );
    let worst = measured
        .iter()
        .map(|m| m.diff.unsigned_abs() as f64 / profile::tiles(&m.run) as f64)
        .fold(0.0, f64::max);
    let _ = writeln!(
        w,
        "- Check: each run's plugin total must agree with the firmware's SysTick count \
         of the same run within {} instructions per tile, or the report fails. SysTick \
         ticks every 40 instructions (a tile's count is off by less than 40 either way), \
         and between its two clock reads it also counts about 20 instructions the plugin \
         does not: the end of the first clock read, the `bl` to the begin marker, the end \
         marker's body (3 instructions) and the start of the second read; so SysTick - \
         plugin lies between about -20 and +60 a tile. Largest difference here, averaged \
         over a run's tiles: {worst:.1} instructions.",
        profile::TOLERANCE_PER_TILE
    );
    let _ = writeln!(
        w,
        "- Functions: each PC is attributed to the innermost function at that address, \
         inlined ones included, from the DWARF line and inline tables of the ELF (the \
         `addr2line` crate); \"source\" is the range of lines of that function's file its \
         instructions come from, \"in\" the function it was inlined into or called from \
         (the largest share, when there are several). Instructions count where they \
         execute, not in their callers: a table of self cost.\n"
    );
}
