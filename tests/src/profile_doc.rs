//! The sections of `docs/chip-profile.md` (written by the `chip-profile` binary):
//! one profiled run ([`Measured`]) with its instruction-class and function tables,
//! the statement of the cycle model, and the host's callgrind profile.

use crate::cycles::{self, Class, Cost};
use crate::dwarf::{self, FunctionCost};
use crate::firmware::{Run, RunResult};
use crate::profile::Profile;
use crate::{callgrind, thousands};
use std::fmt::Write as _;

/// Functions listed per run before "other" (self cost).
pub const TOP: usize = 15;
/// Functions listed per run, inclusive of inlined code.
pub const TOP_INCLUSIVE: usize = 12;
/// Host functions listed per scene.
pub const HOST_TOP: usize = 10;
/// Host renders (320x240, their own settings).
pub const HOST_SCENES: [&str; 2] = ["chapter-reflect", "showcase"];

/// One profiled run and what was made of it.
pub struct Measured {
    /// The render.
    pub run: Run,
    /// The firmware's own result (SysTick count) of the profiled qemu run.
    pub systick: RunResult,
    /// The plugin's profile.
    pub profile: Profile,
    /// SysTick minus plugin, instructions.
    pub diff: i64,
    /// The estimated cost of each instruction of the profile.
    pub costs: Vec<Cost>,
    /// Self cost per innermost function.
    pub functions: Vec<FunctionCost>,
    /// Cost of each function with the code inlined into it.
    pub inclusive: Vec<FunctionCost>,
}

impl Measured {
    /// Pixels of the render.
    #[must_use]
    pub fn pixels(&self) -> f64 {
        f64::from(self.run.width) * f64::from(self.run.height)
    }
    /// `n` per pixel.
    #[must_use]
    pub fn per_px(&self, n: u64) -> f64 {
        n as f64 / self.pixels()
    }
    /// Estimated cycles with the refill `p` for a taken branch.
    #[must_use]
    pub fn cycles_at(&self, p: u64) -> u64 {
        self.costs.iter().map(|c| c.cycles_at(p)).sum()
    }
    /// The run's heading: scene, sampler, depth, size, tiles.
    #[must_use]
    pub fn title(&self) -> String {
        let r = &self.run;
        format!(
            "{} ({}, depth {}, {}x{}, tiles {})",
            r.scene.name(),
            r.sampler,
            r.depth,
            r.width,
            r.height,
            r.tile
        )
    }
}

/// The section that states the cycle model and its assumptions.
pub fn cycle_model(w: &mut String) {
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

/// A run's section: class table, self-cost and inclusive function tables.
pub fn run_section(w: &mut String, m: &Measured) {
    let px = |n: u64| m.per_px(n);
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
    class_table(w, m, total_cycles);

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

/// The instruction classes of a run: instructions and estimated cycles per
/// class, branches split into taken and not taken.
fn class_rows(m: &Measured) -> Vec<(String, u64, u64)> {
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
    rows
}

/// The table of instruction classes of a run, and its pipelined loads and stores.
/// `total_cycles` is the run's estimate ([`Measured::cycles_at`] with the refill
/// penalty), computed once by the caller.
fn class_table(w: &mut String, m: &Measured, total_cycles: f64) {
    let px = |n: u64| m.per_px(n);
    let total = m.profile.total.max(1) as f64;
    let rows = class_rows(m);
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
pub fn short(name: &str) -> String {
    name.split(" < ")
        .map(dwarf::short_name)
        .collect::<Vec<_>>()
        .join(" < ")
}

/// The host section (callgrind), or a note that valgrind is missing.
pub fn host_section(w: &mut String, host: Option<&(String, Vec<callgrind::HostProfile>)>) {
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
