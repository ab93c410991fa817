//! `nofpu-report`: what a chip without an FPU pays per pixel; writes
//! `docs/chip-nofpu.md`.
//!
//! Builds the firmware test image (exact math) for the Cortex-M4F and for the two
//! cores without an FPU (`firmware::NOFPU_CORES`: Armv6-M run on `mps2-an385`'s
//! Cortex-M3, rv32imc on `virt` without F and D), renders each built-in scene at
//! 64x64 with its own settings on each under qemu (the instruction counts; the
//! pixels of the cores without an FPU must equal the Cortex-M4F's), profiles the
//! same renders with the instruction plugin (`tests/profiler/`), adds the profiles
//! up by out-of-line routine (`tessera_tests::nofpu`: software floating point,
//! integer helpers, libm, the renderer) and estimates Cortex-M0+ cycles from the
//! Armv6-M profile.
//!
//! ```sh
//! cargo run -p tessera-tests --release --bin nofpu-report
//! ```

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};
use std::time::Instant;
use tessera_core::builtin::Builtin;
use tessera_tests::firmware::{self, Core, Run, RunResult, Sizes};
use tessera_tests::nofpu::{self, Kind, RoutineCost, Routines};
use tessera_tests::profile::{self, Profile};
use tessera_tests::{cycles, thousands, thousands_rounded};

const COMMAND: &str = "cargo run -p tessera-tests --release --bin nofpu-report";
/// The renders' size.
const SIZE: u16 = 64;
/// The scenes whose top routines are listed.
const DETAILED: [Builtin; 2] = [Builtin::ChapterDirect, Builtin::Teapot];
/// Routines listed per scene and core.
const TOP: usize = 12;

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
            eprintln!("nofpu-report: {e}");
            ExitCode::FAILURE
        }
    }
}

/// One core's figures.
struct Measured {
    core: Core,
    sizes: Sizes,
    /// One result per scene of [`runs`].
    results: Vec<RunResult>,
    stack_peak: u64,
    /// One profile per scene.
    profiles: Vec<Profile>,
    /// Each profile by routine.
    routines: Vec<Vec<RoutineCost>>,
    /// Floating-point instructions in the image's disassembly, if llvm-objdump ran.
    float_insns: Option<usize>,
}

impl Measured {
    fn per_px(&self, n: u64) -> f64 {
        n as f64 / (f64::from(SIZE) * f64::from(SIZE))
    }
}

/// Each built-in scene at 64x64 with its own settings (centre sampling).
fn runs() -> Vec<Run> {
    Builtin::ALL
        .iter()
        .map(|&b| Run::of(b, SIZE, SIZE))
        .collect()
}

fn report() -> Result<PathBuf, String> {
    let cores = [
        firmware::CORTEX_M4F,
        firmware::CORTEX_M0_ON_M3,
        firmware::RV32IMC,
    ];
    let mut versions = Vec::new();
    for core in &cores {
        let v = core.qemu_version()?;
        if !versions.contains(&v) {
            versions.push(v);
        }
    }
    let rustc = tessera_tests::tool_version("rustc");
    let objdump = objdump();
    println!("building the firmware for each core and the qemu plugin...");
    let mut elves = Vec::new();
    for core in &cores {
        elves.push(core.build(&[])?);
    }
    let plugin = profile::build_plugin()?;
    let runs = runs();

    println!("rendering and profiling under qemu...");
    let mut measured = Vec::new();
    for (core, elf) in cores.iter().zip(&elves) {
        measured.push(measure(core, elf, &plugin, &runs, objdump.as_deref())?);
    }
    // The pixels of the cores without an FPU equal the Cortex-M4F's (which the
    // tests check against the host).
    for m in &measured[1..] {
        for ((r, a), b) in runs.iter().zip(&m.results).zip(&measured[0].results) {
            if a.pixels.as_raw() != b.pixels.as_raw() {
                return Err(format!(
                    "{}: the pixels of {r} differ from the Cortex-M4F's",
                    m.core.title
                ));
            }
        }
    }
    let path = firmware::repo_root().join("docs").join("chip-nofpu.md");
    let d = document(&versions, &rustc, objdump.is_some(), &runs, &measured);
    std::fs::write(&path, d).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    Ok(path)
}

/// Renders `runs` on `core` (one qemu), then profiles each (one qemu each, in
/// parallel) and checks the profile's total against the firmware's count.
fn measure(
    core: &Core,
    elf: &Path,
    plugin: &Path,
    runs: &[Run],
    objdump: Option<&Path>,
) -> Result<Measured, String> {
    let out = core.run(elf, runs)?;
    let markers = profile::markers(elf)?;
    let profiled: Vec<Result<(RunResult, Profile), String>> = std::thread::scope(|s| {
        let handles: Vec<_> = runs
            .iter()
            .map(|r| s.spawn(move || profile::run_on(core, elf, plugin, markers, r)))
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err("a profiling thread panicked".into()))
            })
            .collect()
    });
    let symbols = Routines::new(elf)?;
    let mut profiles = Vec::new();
    let mut routines = Vec::new();
    for (r, res) in runs.iter().zip(profiled) {
        let (with_plugin, p) = res?;
        profile::check_total(r, &with_plugin, &p).map_err(|e| format!("{}: {e}", core.title))?;
        routines.push(nofpu::by_routine(&symbols, &p.insns));
        profiles.push(p);
    }
    Ok(Measured {
        core: *core,
        sizes: firmware::sections(elf)?,
        results: out.runs,
        stack_peak: out.stack_peak,
        profiles,
        routines,
        float_insns: objdump.map(|o| float_instructions(o, elf)).transpose()?,
    })
}

/// `llvm-objdump` on the `PATH`, or the one of rustup's `llvm-tools`.
fn objdump() -> Option<PathBuf> {
    let works = |p: &Path| {
        Command::new(p)
            .arg("--version")
            .output()
            .is_ok_and(|o| o.status.success())
    };
    let plain = PathBuf::from("llvm-objdump");
    if works(&plain) {
        return Some(plain);
    }
    let sysroot = Command::new("rustc")
        .args(["--print", "sysroot"])
        .output()
        .ok()?;
    let sysroot = String::from_utf8_lossy(&sysroot.stdout).trim().to_string();
    std::fs::read_dir(Path::new(&sysroot).join("lib").join("rustlib"))
        .ok()?
        .filter_map(Result::ok)
        .map(|e| e.path().join("bin").join("llvm-objdump"))
        .find(|p| works(p))
}

/// Floating-point instructions in the disassembly of `elf`: on Arm every VFP
/// instruction (`v...`), on RISC-V those of F and D (`fadd.s`, `flw`, `fsw`,
/// `fmv.w.x`, `c.flw`, `frcsr`, ...; not `fence`).
fn float_instructions(objdump: &Path, elf: &Path) -> Result<usize, String> {
    let out = firmware::checked(
        Command::new(objdump)
            .args(["-d", "--no-show-raw-insn"])
            .arg(elf),
        "llvm-objdump",
        &format!("llvm-objdump failed on {}", elf.display()),
    )?;
    let text = String::from_utf8_lossy(&out.stdout);
    let riscv = elf.display().to_string().contains("riscv");
    Ok(text
        .lines()
        .filter_map(|l| {
            // `    addr:  \tmnemonic\toperands`
            let (addr, rest) = l.split_once(':')?;
            if addr.trim().is_empty() || !addr.trim().chars().all(|c| c.is_ascii_hexdigit()) {
                return None;
            }
            rest.split_whitespace().next()
        })
        .filter(|m| {
            if riscv {
                let m = m.strip_prefix("c.").unwrap_or(m);
                m.starts_with('f')
                    && !m.starts_with("fence")
                    && (m.contains('.')
                        || [
                            "flw", "fsw", "fld", "fsd", "flwsp", "fswsp", "fldsp", "fsdsp",
                            "frcsr", "fscsr", "frflags", "fsflags", "frrm", "fsrm", "fsrmi",
                            "fsflagsi",
                        ]
                        .contains(&m))
            } else {
                m.starts_with('v')
            }
        })
        .count())
}

fn document(
    versions: &[String],
    rustc: &str,
    objdump: bool,
    runs: &[Run],
    measured: &[Measured],
) -> String {
    let mut d = String::new();
    let w = &mut d;
    let _ = writeln!(
        w,
        "# tessera on chips without an FPU: what software floating point costs\n"
    );
    let _ = writeln!(
        w,
        "Generated by `{COMMAND}` (do not edit by hand; run it again after changing the \
         core or the firmware). Companion of [chip-cost.md](chip-cost.md), which counts \
         the Cortex-M4F's instructions for every setting.\n"
    );
    let _ = writeln!(
        w,
        "**These are instruction counts under qemu, not measurements on a board.** No \
         Cortex-M0/M0+ or rv32imc board ran them. Instructions turn into cycles \
         differently on each core: a Cortex-M0/M0+ has no hardware divide and, by the \
         chip maker's choice, a 1-cycle or a 32-cycle multiplier, and its loads and \
         taken branches take 2 cycles or more; the estimate below says what it \
         assumes.\n"
    );
    setup(w, versions, rustc, objdump, measured);
    instructions(w, runs, measured);
    cycles_section(w, runs, measured);
    where_it_goes(w, runs, measured);
    top_routines(w, runs, measured);
    memory(w, measured);
    fixed_point(w, runs, measured);
    let _ = writeln!(w, "## Regenerate\n");
    let _ = writeln!(
        w,
        "It needs `qemu-system-arm` and `qemu-system-riscv32` 7.2 or later (with plugin \
         support, as Debian's), the targets `thumbv7em-none-eabihf`, `thumbv6m-none-eabi` \
         and `riscv32imc-unknown-none-elf`, a C compiler (`gcc`, or `$CC`) for the plugin, \
         and `llvm-objdump` for the check of float instructions (left out, with a note, \
         without it):\n"
    );
    let _ = writeln!(w, "```sh\n{COMMAND}\n```");
    d
}

fn setup(w: &mut String, versions: &[String], rustc: &str, objdump: bool, measured: &[Measured]) {
    let _ = writeln!(w, "## Setup\n");
    for m in measured {
        let c = &m.core;
        let args: Vec<&str> = c
            .qemu_args
            .iter()
            .copied()
            .filter(|a| !["-nographic", "-semihosting-config", "-kernel"].contains(a))
            .filter(|a| !a.starts_with("enable="))
            .collect();
        let _ = writeln!(
            w,
            "- {}: target `{}`, `{} {}`.",
            c.title,
            c.target,
            c.qemu,
            args.join(" ")
        );
    }
    let _ = writeln!(
        w,
        "- {}; {rustc}; the firmware test image `tests/firmware` (exact math), its pinned \
         release profile (`opt-level = 3`, fat LTO). Without an FPU, `f32` arithmetic is \
         software: `compiler_builtins`' routines (`__addsf3`, `__mulsf3`, ...; on Arm \
         reached through the run-time ABI's `__aeabi_fadd`, `__aeabi_fmul`, ...), and the \
         core's square root is libm's correctly rounded `sqrtf` (`core/src/math.rs`: the \
         hardware instruction only where the target has an FPU).",
        versions.join("; ")
    );
    let _ = writeln!(
        w,
        "- Armv6-M is run on qemu's `mps2-an385`, a Cortex-M3: qemu has no Cortex-M0 board \
         with the memory the test image needs, and a Cortex-M3 executes Armv6-M code as a \
         Cortex-M0 would, instruction for instruction. The counts are the Armv6-M \
         code's. The rv32imc CPU is qemu's `rv32` with `f=false,d=false`: its `misa` has \
         neither F nor D (the firmware prints it, `tests/tests/nofpu.rs` checks it), and \
         the rv32imafc image does not run on it."
    );
    if objdump {
        let figures: Vec<String> = measured
            .iter()
            .map(|m| {
                format!(
                    "{} {}",
                    m.core.title,
                    m.float_insns
                        .map_or_else(|| "?".into(), |n| thousands(n as u64))
                )
            })
            .collect();
        let _ = writeln!(
            w,
            "- Floating-point instructions in each `tessera-fw` image (`llvm-objdump -d`: \
             VFP instructions on Arm, F and D ones on RISC-V): {}.",
            figures.join(", ")
        );
    } else {
        let _ = writeln!(
            w,
            "- Floating-point instructions in the images: not checked (no `llvm-objdump`)."
        );
    }
    let _ = writeln!(
        w,
        "- Renders: {SIZE}x{SIZE} pixels, each built-in scene with its own settings (centre \
         sampling, its depth), tiles of 16x16, instructions counted inside `render_tile` \
         (SysTick on Arm, 40 instructions a tick; `minstret` on RISC-V). The pixels of both \
         cores without an FPU equal the Cortex-M4F's, which equal the host's \
         (`tests/tests/nofpu.rs` checks a smaller set against the host on every test run).\n"
    );
}

fn ratio(a: f64, b: f64) -> String {
    format!("{:.1}", a / b.max(1.0))
}

fn instructions(w: &mut String, runs: &[Run], measured: &[Measured]) {
    let _ = writeln!(w, "## Instructions per pixel\n");
    let m4f = &measured[0];
    let mut header = format!("| scene | depth | {} instr/px |", m4f.core.title);
    let mut rule = "|---|---|---|".to_string();
    for m in &measured[1..] {
        let _ = write!(
            header,
            " {} instr/px | x {} |",
            m.core.title, m4f.core.title
        );
        rule.push_str("---|---|");
    }
    let _ = writeln!(w, "{header}\n{rule}");
    for (k, r) in runs.iter().enumerate() {
        let base = m4f.results[k].instructions_per_pixel();
        let mut row = format!(
            "| {} | {} | {} |",
            r.scene.name(),
            r.depth,
            thousands_rounded(base)
        );
        for m in &measured[1..] {
            let v = m.results[k].instructions_per_pixel();
            let _ = write!(row, " {} | {} |", thousands_rounded(v), ratio(v, base));
        }
        let _ = writeln!(w, "{row}");
    }
    let _ = writeln!(w);
}

/// The Armv6-M core's measurements, if any.
fn armv6m(measured: &[Measured]) -> Option<&Measured> {
    measured
        .iter()
        .find(|m| m.core.target == "thumbv6m-none-eabi")
}

fn cycles_section(w: &mut String, runs: &[Run], measured: &[Measured]) {
    let _ = writeln!(w, "## An estimate of Cortex-M0+ cycles\n");
    let Some(v6) = armv6m(measured) else { return };
    let m4f = &measured[0];
    let _ = writeln!(
        w,
        "An **estimate**, from the Armv6-M profile (every executed instruction, how often, \
         and how often its branch was taken) weighted with the instruction timings of the \
         Cortex-M0+ Technical Reference Manual: 1 cycle for data processing, 2 for a load \
         or store and for `B`, `BX` and a taken conditional branch (1 not taken), 3 for \
         `BL`, 1 + N for `LDM`, `STM`, `PUSH`, `POP` of N registers, 3 + N for a `POP` \
         that returns (N its registers besides the PC: the assumption here); `MULS` 1 or \
         32 cycles, the core's two multiplier options (a chip's datasheet says which it \
         has). It assumes zero wait states: code and data in SRAM, or a flash cache that \
         always hits (a chip that runs from flash pays its wait states or cache misses on \
         top), and no interrupts. The Cortex-M0 (not M0+) takes a cycle more for each \
         taken branch, call and return: this is the M0+. The Cortex-M4F's column is \
         estimated from its own profile of the same renders with chip-cost.md's model \
         ([chip-profile.md](chip-profile.md)); rv32imc gets none (no single public timing \
         model: its cycles depend on the chip's pipeline).\n"
    );
    let _ = writeln!(
        w,
        "| scene | {} est. cycles/px | Cortex-M0+ est. cycles/px, 1-cycle multiplier | x {} | 32-cycle multiplier | x {} | Cortex-M0+ cycles/instr |",
        m4f.core.title, m4f.core.title, m4f.core.title
    );
    let _ = writeln!(w, "|---|---|---|---|---|---|---|");
    for (k, r) in runs.iter().enumerate() {
        let base = m4f.per_px(cycles::estimate(&m4f.profiles[k].insns));
        let insns = &v6.profiles[k].insns;
        let fast = v6.per_px(nofpu::m0plus_cycles(insns, 1));
        let slow = v6.per_px(nofpu::m0plus_cycles(insns, 32));
        let _ = writeln!(
            w,
            "| {} | {} | {} | {} | {} | {} | {:.2} |",
            r.scene.name(),
            thousands_rounded(base),
            thousands_rounded(fast),
            ratio(fast, base),
            thousands_rounded(slow),
            ratio(slow, base),
            fast / v6.per_px(v6.profiles[k].total).max(1.0)
        );
    }
    let _ = writeln!(w);
}

/// Instructions by kind of routine of one profile, the float routines' share of
/// the integer helpers, and the total.
fn kinds(routines: &[RoutineCost]) -> (Vec<(Kind, u64)>, u64, u64) {
    let (by_kind, helpers) = nofpu::by_kind(routines);
    let total = by_kind.iter().map(|(_, n)| n).sum();
    (by_kind, helpers, total)
}

fn pct(n: u64, total: u64) -> String {
    format!("{:.1}%", 100.0 * n as f64 / total.max(1) as f64)
}

fn where_it_goes(w: &mut String, runs: &[Run], measured: &[Measured]) {
    let _ = writeln!(w, "## Where the instructions go\n");
    let _ = writeln!(
        w,
        "Each instruction of the profile counted in the out-of-line routine it executes \
         in (the ELF's symbols: `compiler_builtins`' float routines are never inlined). \
         \"Soft float\" is every float routine (f32 and f64 arithmetic, comparisons, \
         conversions); \"with their helpers\" adds the integer helpers' instructions in \
         proportion to their calls from the float routines (on Arm, the `bl`s in the \
         float routines that target them; on rv32imc, which has a 32x32 -> 64-bit \
         multiply, none are called here). The renderer's share is its own code, the float \
         operations it calls excluded.\n"
    );
    for m in &measured[1..] {
        let _ = writeln!(w, "### {} (`{}`)\n", m.core.title, m.core.target);
        let mut header = "| routines |".to_string();
        let mut rule = "|---|".to_string();
        for r in runs {
            let _ = write!(header, " {} |", r.scene.name());
            rule.push_str("---|");
        }
        let _ = writeln!(w, "{header}\n{rule}");
        let all: Vec<_> = m.routines.iter().map(|r| kinds(r)).collect();
        for kind in Kind::ALL {
            if all
                .iter()
                .all(|(k, _, _)| k.iter().all(|(kk, n)| *kk != kind || *n == 0))
            {
                continue;
            }
            let mut row = format!("| {} |", kind.label());
            for (k, _, total) in &all {
                let n = k.iter().find(|(kk, _)| *kk == kind).map_or(0, |(_, n)| *n);
                let _ = write!(row, " {} |", pct(n, *total));
            }
            let _ = writeln!(w, "{row}");
        }
        let mut soft = "| **soft float** |".to_string();
        let mut with = "| **soft float with their helpers** |".to_string();
        let mut own = "| the renderer's own, instr/px (the Cortex-M4F's whole count) |".to_string();
        for (i, (k, helpers, total)) in all.iter().enumerate() {
            let s: u64 = k
                .iter()
                .filter(|(kk, _)| kk.is_soft_float())
                .map(|(_, n)| n)
                .sum();
            let _ = write!(soft, " **{}** |", pct(s, *total));
            let _ = write!(with, " **{}** |", pct(s + helpers, *total));
            let r: u64 = k
                .iter()
                .filter(|(kk, _)| *kk == Kind::Renderer)
                .map(|(_, n)| n)
                .sum();
            let _ = write!(
                own,
                " {} ({}) |",
                thousands_rounded(m.per_px(r)),
                thousands_rounded(measured[0].results[i].instructions_per_pixel())
            );
        }
        let _ = writeln!(w, "{soft}\n{with}\n{own}\n");
    }
}

fn top_routines(w: &mut String, runs: &[Run], measured: &[Measured]) {
    let _ = writeln!(w, "## The top routines\n");
    let _ = writeln!(
        w,
        "The {TOP} routines with the most instructions, per core, in {}. `calls/px` counts \
         the entries of the routine (its first instruction's executions); a Rust \
         function's closures and copies share one name.\n",
        DETAILED
            .iter()
            .map(|b| format!("`{}`", b.name()))
            .collect::<Vec<_>>()
            .join(" and ")
    );
    for m in &measured[1..] {
        for b in DETAILED {
            let Some(k) = runs.iter().position(|r| r.scene.name() == b.name()) else {
                continue;
            };
            let _ = writeln!(w, "### {}, {}\n", m.core.title, b.name());
            let _ = writeln!(
                w,
                "| routine | kind | share | instr/px | calls/px | instr/call |"
            );
            let _ = writeln!(w, "|---|---|---|---|---|---|");
            let total = m.profiles[k].total;
            for r in m.routines[k].iter().take(TOP) {
                let calls = m.per_px(r.calls);
                let _ = writeln!(
                    w,
                    "| `{}` | {} | {} | {} | {} | {} |",
                    r.name.replace('|', "\\|"),
                    short_kind(r.kind),
                    pct(r.count, total),
                    thousands_rounded(m.per_px(r.count)),
                    if calls >= 10.0 {
                        format!("{calls:.0}")
                    } else {
                        format!("{calls:.2}")
                    },
                    if r.calls > 0 {
                        format!("{:.0}", r.count as f64 / r.calls as f64)
                    } else {
                        "-".into()
                    }
                );
            }
            let _ = writeln!(w);
        }
    }
}

fn short_kind(k: Kind) -> &'static str {
    match k {
        Kind::IntHelper => "integer helper",
        Kind::Libm => "libm",
        Kind::Renderer => "renderer",
        Kind::Memory => "memory",
        _ if k.is_soft_float() => "soft float",
        _ => "",
    }
}

fn memory(w: &mut String, measured: &[Measured]) {
    let _ = writeln!(w, "## Flash and stack\n");
    let _ = writeln!(
        w,
        "The whole test image (`tessera-fw`: every built-in scene, the teapot's tables, \
         the BVH, the harness), and the peak stack of the renders above (the scene on the \
         stack, the frame, `render_tile`). The Armv6-M image needs more than the 512 KiB of \
         the Cortex-M4F's memory map: `tests/firmware/memory/mps2-an385.x` gives it 1 MiB.\n"
    );
    let _ = writeln!(w, "| core | flash, bytes | stack peak, bytes |");
    let _ = writeln!(w, "|---|---|---|");
    for m in measured {
        let _ = writeln!(
            w,
            "| {} | {} | {} |",
            m.core.title,
            thousands(m.sizes.flash()),
            thousands(m.stack_peak)
        );
    }
    let _ = writeln!(w);
}

/// The mean over the profiles of `m` of the instructions a call of the routine
/// `name` takes, and its calls per pixel; `None` if it is never called.
fn per_call(m: &Measured, name: &str) -> Option<(f64, f64)> {
    let (mut count, mut calls) = (0, 0);
    for r in m.routines.iter().flatten().filter(|r| r.name == name) {
        count += r.count;
        calls += r.calls;
    }
    (calls > 0).then(|| {
        (
            count as f64 / calls as f64,
            m.per_px(calls) / m.profiles.len() as f64,
        )
    })
}

fn fixed_point(w: &mut String, runs: &[Run], measured: &[Measured]) {
    let _ = writeln!(w, "## What this says about a fixed-point backend\n");
    let m4f = &measured[0];
    let mut lines = Vec::new();
    for m in &measured[1..] {
        let ratios: Vec<f64> = (0..runs.len())
            .map(|k| {
                m.results[k].instructions_per_pixel()
                    / m4f.results[k].instructions_per_pixel().max(1.0)
            })
            .collect();
        let soft: Vec<f64> = m
            .routines
            .iter()
            .map(|r| {
                let (k, helpers, total) = kinds(r);
                let s: u64 = k
                    .iter()
                    .filter(|(kk, _)| kk.is_soft_float())
                    .map(|(_, n)| n)
                    .sum();
                100.0 * (s + helpers) as f64 / total.max(1) as f64
            })
            .collect();
        let lo = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = |v: &[f64]| v.iter().copied().fold(0.0, f64::max);
        let ceiling: Vec<f64> = soft.iter().map(|s| 100.0 / (100.0 - s).max(1e-9)).collect();
        let lmul: Vec<f64> = m
            .routines
            .iter()
            .map(|r| {
                let total: u64 = r.iter().map(|x| x.count).sum();
                let n: u64 = r
                    .iter()
                    .filter(|x| x.name == "__aeabi_lmul")
                    .map(|x| x.count)
                    .sum();
                100.0 * n as f64 / total.max(1) as f64
            })
            .collect();
        let ops: Vec<String> = ["__addsf3", "__mulsf3", "__divsf3", "__aeabi_lmul"]
            .iter()
            .filter_map(|n| per_call(m, n).map(|(i, c)| format!("`{n}` {i:.0} ({c:.0} calls/px)")))
            .collect();
        let helper = if hi(&lmul) > 0.0 {
            format!(
                " `__aeabi_lmul`, the 32x32 -> 64-bit multiply the float routines call, is \
                 {:.0}% to {:.0}% of all instructions.",
                lo(&lmul),
                hi(&lmul)
            )
        } else {
            String::new()
        };
        lines.push(format!(
            "- {}: {:.0} to {:.0} times the Cortex-M4F's instructions per pixel; soft float \
             (with its helpers) is {:.0}% to {:.0}% of them, so if every float operation \
             cost nothing the count would fall {:.0} to {:.0} times, no more. Instructions a \
             call, averaged over the five scenes: {}.{helper}",
            m.core.title,
            lo(&ratios),
            hi(&ratios),
            lo(&soft),
            hi(&soft),
            lo(&ceiling),
            hi(&ceiling),
            ops.join(", ")
        ));
    }
    for l in &lines {
        let _ = writeln!(w, "{l}");
    }
    let _ = writeln!(
        w,
        "\nWhat the data suggests (measured here, nothing built):\n\n\
         - The cost is the float operations, not the renderer: the renderer's own code is \
         about two times the Cortex-M4F's whole count (the last row of each table above: \
         it also moves the operands of every call), and the float routines are the rest. \
         Any cheaper arithmetic wins at most the factor above.\n\
         - A fixed-point backend would replace most float operations by a few integer \
         instructions, not all of them: a Q16.16 multiply needs a 32x32 -> 64-bit \
         product, which Armv6-M does not have (`__aeabi_lmul` above, tens of instructions \
         a call); divisions and square roots stay routines; and the renderer's ranges (the \
         extremes battery's 2^25-unit grounds, subnormal inputs) would need wider formats \
         or new guards. It would also give up what the float path promises: the same \
         pixels as the host and every other core (a fixed-point host build would have to \
         become the reference for those chips).\n\
         - A cheaper step comes first: faster software floating point with the same \
         IEEE-754 results (correctly rounded add, sub, mul, div and sqrt give the same \
         bits, so the pixels stay the host's). `compiler_builtins`' routines are generic \
         Rust; hand-written ones for these cores (the RP2040's boot ROM ships such \
         routines for its Cortex-M0+) could take fewer instructions a call, and this \
         report measures the result. A fixed-point backend is worth building only if a \
         chip needs more than that gives, up to the ceiling above.\n"
    );
}
