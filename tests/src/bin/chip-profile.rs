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
use tessera::Sampler;
use tessera::builtin::Builtin;
use tessera_tests::cycles::{self, Class, Cost};
use tessera_tests::dwarf::{self, FunctionCost, Symbolizer};
use tessera_tests::firmware::{self, Run, RunResult};
use tessera_tests::profile::{self, Profile};
use tessera_tests::{callgrind, thousands};

const COMMAND: &str = "cargo run -p tessera-tests --release --bin chip-profile";
const SIZE: u16 = 64;
/// Functions listed per run before "other" (self cost).
const TOP: usize = 15;
/// Functions listed per run, inclusive of inlined code.
const TOP_INCLUSIVE: usize = 12;
/// Host functions listed per scene.
const HOST_TOP: usize = 10;
/// Host renders (320x240, their own settings).
const HOST_SCENES: [&str; 2] = ["chapter-reflect", "showcase"];

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

/// Every built-in scene with its own settings, then chapter-direct stratified 4x4.
fn runs() -> Vec<Run> {
    let mut runs: Vec<Run> = Builtin::ALL
        .iter()
        .map(|&b| Run::of(b, SIZE, SIZE))
        .collect();
    runs.push(Run {
        sampler: Sampler::Stratified(4),
        ..Run::of(Builtin::ChapterDirect, SIZE, SIZE)
    });
    runs
}

/// One profiled run and what was made of it.
struct Measured {
    run: Run,
    systick: RunResult,
    profile: Profile,
    /// SysTick minus plugin, instructions.
    diff: i64,
    costs: Vec<Cost>,
    /// Self cost per innermost function.
    functions: Vec<FunctionCost>,
    /// Cost of each function with the code inlined into it.
    inclusive: Vec<FunctionCost>,
}

impl Measured {
    fn pixels(&self) -> f64 {
        f64::from(self.run.width) * f64::from(self.run.height)
    }
    fn per_px(&self, n: u64) -> f64 {
        n as f64 / self.pixels()
    }
    fn cycles_at(&self, p: u64) -> u64 {
        self.costs.iter().map(|c| c.cycles_at(p)).sum()
    }
    fn title(&self) -> String {
        let r = &self.run;
        format!(
            "{} ({}, depth {}, {}x{}, tiles {})",
            r.scene.name(),
            r.sampler_text().unwrap_or_default(),
            r.depth,
            r.width,
            r.height,
            r.tile
        )
    }
}

fn report() -> Result<PathBuf, String> {
    let qemu = firmware::qemu_version()?;
    let rustc = tessera_tests::tool_version("rustc");
    let cc = tessera_tests::tool_version(&std::env::var("CC").unwrap_or_else(|_| "gcc".into()));
    println!("building the firmware and the qemu plugin...");
    let elf = firmware::build(false)?;
    let plugin = profile::build_plugin()?;
    let markers = profile::markers(&elf)?;
    let runs = runs();
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

    let host = match callgrind::valgrind_version() {
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
    };

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
    summary(w, &measured);
    method(w, &qemu, &rustc, &cc, &measured);
    cycle_model(w);
    for m in &measured {
        run_section(w, m);
    }
    host_section(w, host.as_ref());
    let _ = writeln!(w, "## Regenerate\n");
    let _ = writeln!(
        w,
        "It needs `qemu-system-arm` 7.2 or later (with plugin support, as Debian's), the \
         `thumbv7em-none-eabihf` target, a C compiler (`gcc`, or `$CC`) for the plugin, and \
         valgrind for the host section (left out, with a note, without it):\n"
    );
    let _ = writeln!(w, "```sh\n{COMMAND}\n```");
    let path = firmware::repo_root().join("docs").join("chip-profile.md");
    std::fs::write(&path, d).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    Ok(path)
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

fn cycle_model(w: &mut String) {
    let _ = writeln!(w, "## The cycle estimate\n");
    let _ = writeln!(
        w,
        "**An estimate, not a measurement**: qemu counts instructions, not cycles. Each \
         executed instruction is classified by its mnemonic (`tests/src/cycles.rs`, unit \
         tested) and weighted with the Cortex-M4 Technical Reference Manual (ARM DDI 0439, \
         \"Cortex-M4 instruction set summary\" and the FPU instruction table):\n"
    );
    let _ = writeln!(
        w,
        "- 1 cycle: integer data processing, `MUL`, `SMULL`/`UMULL`, `IT` (assumed never \
         folded), FPU add, subtract, multiply, negate, absolute, compare, convert, \
         `VMOV` (2 with two core registers), `VMRS`;"
    );
    let _ = writeln!(
        w,
        "- 2: `MLA`, `MLS`; 3: `VMLA`, `VMLS`, `VNMLA`, `VNMLS`, `VFMA`..; 14: \
         `VDIV.F32`, `VSQRT.F32`; `SDIV`/`UDIV`: {} (the manual: 2 to 12 by early \
         termination; the worst case assumed);",
        cycles::DIVIDE
    );
    let _ = writeln!(
        w,
        "- loads and stores single (`LDR*`, `STR*`, `VLDR`, `VSTR`): 2, or 1 when the \
         instruction executed just before was also a load or store single (\"neighbouring \
         load and store single instructions can pipeline their address and data \
         phases\"); how often that happens is exact from the profile (the fall-through \
         executions of the instruction before it); address dependencies and the manual's \
         finer exceptions are ignored; `LDRD`/`STRD`: 3; `LDM`/`STM`/`PUSH`/`POP`/`VLDM`/\
         `VSTM`/`VPUSH`/`VPOP`: 1 + N (N registers, in 32-bit words);"
    );
    let _ = writeln!(
        w,
        "- branches (`B`, `BL`, `BX`, `BLX`, `CBZ`/`CBNZ`; `TBB`/`TBH` 2; `POP {{.., pc}}` \
         1 + N; anything writing the PC): + P = {} for each taken execution, counted \
         by the plugin (the manual: P = 1 to 3, by the target's alignment and width and \
         whether the address was speculated).\n",
        cycles::REFILL
    );
    let _ = writeln!(
        w,
        "It ignores: flash wait states and the prefetch buffer (at 25 MHz from zero-wait \
         memory none; a real MCU at 100+ MHz from flash adds them, partly hidden by its \
         cache or accelerator), stalls between dependent FPU operations (a result used by \
         the next instruction, `VMRS` right after `VCMP`), conditional instructions whose \
         condition fails (charged as executed; a failed branch is charged as not taken), \
         bus contention of literal loads, interrupts. Read the figures as a cycle count \
         for zero-wait memory, correct to perhaps 10-20%, and the ratio cycles/instruction \
         as the part that the instruction counts hide.\n"
    );
}

fn run_section(w: &mut String, m: &Measured) {
    let px = |n: u64| m.per_px(n);
    let total = m.profile.total.max(1) as f64;
    let total_cycles = m.cycles_at(cycles::REFILL).max(1) as f64;
    let _ = writeln!(w, "## {}\n", m.title());
    let _ = writeln!(
        w,
        "{:.1} instructions/px (SysTick {:.1}), estimated {:.0} cycles/px; {} distinct \
         instructions executed.\n",
        px(m.profile.total),
        m.systick.instructions_per_pixel(),
        px(total_cycles as u64),
        m.profile.insns.len()
    );
    // Instruction classes; branches split into taken and not taken.
    let mut rows: Vec<(String, u64, u64)> = Vec::new();
    for class in Class::ALL {
        let of = |f: &dyn Fn(&cycles::Insn, &Cost) -> (u64, u64)| {
            m.profile
                .insns
                .iter()
                .zip(&m.costs)
                .filter(|(_, c)| c.timing.class == class)
                .map(|(i, c)| f(i, c))
                .fold((0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
        };
        if class == Class::Branch {
            let taken = of(&|_, c| (c.refills, c.refills * (c.timing.cycles + cycles::REFILL)));
            let not = of(&|i, c| {
                let n = i.count - c.refills;
                (n, n * c.timing.cycles)
            });
            rows.push((
                format!("branches taken (1+P, P = {}; pop/ldm +N)", cycles::REFILL),
                taken.0,
                taken.1,
            ));
            rows.push(("branches not taken (1)".into(), not.0, not.1));
        } else {
            let (n, c) = of(&|i, c| (i.count, c.cycles()));
            rows.push((class.label().to_string(), n, c));
        }
    }
    let _ = writeln!(
        w,
        "| instruction class (cycles each) | instr/px | share | est. cycles/px | share of cycles |"
    );
    let _ = writeln!(w, "|---|---|---|---|---|");
    for (label, n, c) in &rows {
        let _ = writeln!(
            w,
            "| {label} | {:.1} | {:.1}% | {:.1} | {:.1}% |",
            px(*n),
            100.0 * *n as f64 / total,
            px(*c),
            100.0 * *c as f64 / total_cycles
        );
    }
    let pipelined: u64 = m.costs.iter().map(|c| c.pipelined).sum();
    let _ = writeln!(
        w,
        "| **total** | **{:.1}** | 100% | **{:.1}** | 100% |\n",
        px(m.profile.total),
        px(total_cycles as u64)
    );
    let _ = writeln!(
        w,
        "Loads and stores pipelined with the one before (1 cycle instead of 2): {:.1}/px.\n",
        px(pipelined)
    );

    let _ = writeln!(
        w,
        "Self cost: each instruction counts in the innermost function it belongs to \
         (inlined ones included); \"inlined into\" is the chain of functions it was \
         inlined into, innermost first (the most frequent, with its share when there \
         are several), empty for an out-of-line function's own code.\n"
    );
    function_table(w, m, &m.functions, TOP, true);
    let _ = writeln!(
        w,
        "Inclusive of inlined code: each function with everything inlined into it (what \
         it calls out of line is not included; a line counts in every function of its \
         chain, so the shares add up to more than 100%). \"source\" is the range of \
         lines of the function itself, call sites of inlined code included.\n"
    );
    function_table(w, m, &m.inclusive, TOP_INCLUSIVE, false);
}

/// A table of `functions` (the first `top`, then the rest as "other" when `other`).
fn function_table(
    w: &mut String,
    m: &Measured,
    functions: &[FunctionCost],
    top: usize,
    other: bool,
) {
    let px = |n: u64| m.per_px(n);
    let total = m.profile.total.max(1) as f64;
    let _ = writeln!(
        w,
        "| # | function | source | inlined into | instr/px | share | est. cycles/px | cycles/instr |"
    );
    let _ = writeln!(w, "|---|---|---|---|---|---|---|---|");
    for (k, f) in functions.iter().take(top).enumerate() {
        let caller = f.main_caller().map_or_else(String::new, |(n, share)| {
            let chain = if n.is_empty() {
                "(out of line)".to_string()
            } else {
                format!("`{}`", short(n))
            };
            if share > 0.95 {
                chain
            } else {
                format!("{chain} ({:.0}%)", 100.0 * share)
            }
        });
        let _ = writeln!(
            w,
            "| {} | `{}` | {} | {} | {:.1} | {:.1}% | {:.1} | {:.2} |",
            k + 1,
            short(&f.name),
            f.source(),
            caller,
            px(f.count),
            100.0 * f.count as f64 / total,
            px(f.cycles),
            f.cycles as f64 / f.count.max(1) as f64
        );
    }
    let rest: Vec<&FunctionCost> = functions.iter().skip(top).collect();
    if other && !rest.is_empty() {
        let n: u64 = rest.iter().map(|f| f.count).sum();
        let c: u64 = rest.iter().map(|f| f.cycles).sum();
        let _ = writeln!(
            w,
            "| | other ({} functions) | | | {:.1} | {:.1}% | {:.1} | {:.2} |",
            rest.len(),
            px(n),
            100.0 * n as f64 / total,
            px(c),
            c as f64 / n.max(1) as f64
        );
    }
    let _ = writeln!(w);
}

/// A name or a chain of names for the tables.
fn short(name: &str) -> String {
    name.split(" < ")
        .map(dwarf::short_name)
        .collect::<Vec<_>>()
        .join(" < ")
}

fn host_section(w: &mut String, host: Option<&(String, Vec<callgrind::HostProfile>)>) {
    let _ = writeln!(w, "## Host (x86-64, callgrind)\n");
    let Some((version, profiles)) = host else {
        let _ = writeln!(
            w,
            "valgrind is not installed on the machine that generated this file, so there is \
             no host profile (install it, e.g. `apt-get install valgrind`, and run the \
             command again).\n"
        );
        return;
    };
    let _ = writeln!(
        w,
        "The release `tessera` binary (`cargo build --release -p tessera-host`: fat LTO, no \
         debug info, so functions are symbols with everything inlined into them) renders \
         each scene at 320x240 with its own settings on one thread under `valgrind \
         --tool=callgrind` ({version}). Instructions are the whole process's `Ir`: \
         parsing the arguments, building the scene, rendering and encoding the PNG (the \
         `png`/`fdeflate`/`write_png` rows); it varies by about 0.01% between runs \
         (temporary file names, timing output). Rays are what the command prints \
         (primary, shadow and secondary rays).\n"
    );
    let _ = writeln!(w, "| scene | size | total Ir | Ir/px | rays | Ir/ray |");
    let _ = writeln!(w, "|---|---|---|---|---|---|");
    for (scene, p) in HOST_SCENES.iter().zip(profiles) {
        let _ = writeln!(
            w,
            "| {scene} | {} px | {} | {:.0} | {} | {:.0} |",
            thousands(p.pixels),
            thousands(p.total),
            p.total as f64 / p.pixels.max(1) as f64,
            thousands(p.rays),
            p.total as f64 / p.rays.max(1) as f64
        );
    }
    let _ = writeln!(w);
    for (scene, p) in HOST_SCENES.iter().zip(profiles) {
        let _ = writeln!(w, "Top functions, {scene} (`{}`):\n", p.command);
        let _ = writeln!(w, "| function (self cost) | Ir/px | share |");
        let _ = writeln!(w, "|---|---|---|");
        for f in p.functions.iter().take(HOST_TOP) {
            let _ = writeln!(
                w,
                "| `{}` | {:.0} | {:.1}% |",
                short(&f.function),
                f.ir as f64 / p.pixels.max(1) as f64,
                f.percent
            );
        }
        let _ = writeln!(w);
    }
}
