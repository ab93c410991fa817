//! An estimate of Cortex-M4 cycles from an instruction profile.
//!
//! Each executed instruction is classified by its mnemonic, as QEMU 7.2 prints it
//! for Thumb-2 (`ldr.w r1, [sp, #0xca]`, `vdiv.f32 s0, s1, s2`, `pop {r4, r7, pc}`,
//! `bne #0xa490`; instructions inside an IT block are printed without their
//! condition), and weighted with the timings of the Cortex-M4 Technical Reference
//! Manual (ARM DDI 0439B: table 3-1, "Cortex-M4 instruction set summary", and table
//! 7-1, the FPU instructions). Where the manual gives a range, the assumption is a
//! constant here:
//!
//! - a taken branch costs `1 + P` with the pipeline refill `P` = [`REFILL`] (the
//!   manual: 1 to 3, by the target's alignment and width and whether the address was
//!   speculated); a branch not taken costs 1. Taken or not comes from the profile
//!   (the plugin counts, per PC, how often the next instruction was not `pc + size`);
//! - a load or store *single* (`LDR*`, `STR*`, `VLDR`, `VSTR`) costs 2 cycles, or 1
//!   when the instruction executed just before it was also a load or store single
//!   ("neighbouring load and store single instructions can pipeline their address
//!   and data phases"). How often that happens is exact from the profile: the
//!   fall-through executions of the instruction before it in memory. Address
//!   dependencies and the manual's finer exceptions (nothing pipelines after a
//!   store with a register offset) are ignored: optimistic;
//! - `SDIV`/`UDIV` cost [`DIVIDE`] cycles (2 to 12 by early termination: the worst
//!   case, assumed);
//! - `IT` costs 1 (never folded); an instruction whose condition fails costs as if
//!   it executed (QEMU does not tell them apart), except branches, whose taken count
//!   is measured.
//!
//! Everything else the estimate ignores: flash wait states and the prefetch buffer,
//! stalls between dependent FPU operations (a `vmla.f32` result used at once, a
//! `vmrs` after `vcmp`), bus contention of literal loads, and interrupt entry.

use std::fmt;

/// The pipeline refill `P` assumed for a taken branch (1 to 3 in the manual).
pub const REFILL: u64 = 2;
/// Cycles assumed for `SDIV`/`UDIV` (2 to 12 in the manual): the worst case.
pub const DIVIDE: u64 = 12;
/// `VDIV.F32` and `VSQRT.F32`.
pub const FP_DIV_SQRT: u64 = 14;
/// `VMLA`, `VMLS`, `VNMLA`, `VNMLS`, `VFMA`, `VFMS`, `VFNMA`, `VFNMS` (F32).
pub const FP_MAC: u64 = 3;

/// What an instruction does, for the class table of the report.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Class {
    /// FPU data processing: add, sub, mul, neg, abs, compare, convert, move, VMRS.
    FpArith,
    /// FPU multiply-accumulate (3 cycles).
    FpMac,
    /// `VDIV.F32`, `VSQRT.F32` (14 cycles).
    FpDivSqrt,
    /// Loads: `LDR*`, `LDRD`, `LDM`, `POP` (without PC), `VLDR`, `VLDM`, `VPOP`.
    Load,
    /// Stores: `STR*`, `STRD`, `STM`, `PUSH`, `VSTR`, `VSTM`, `VPUSH`.
    Store,
    /// Anything that may write the PC: `B`, `BL`, `BX`, `CBZ`, `TBB`, `POP {.., pc}`...
    Branch,
    /// Integer multiply and divide.
    MulDiv,
    /// Integer data processing, `IT`, hints.
    Other,
}

impl Class {
    /// Every class, in the report's order.
    pub const ALL: [Class; 8] = [
        Class::FpArith,
        Class::FpMac,
        Class::FpDivSqrt,
        Class::Load,
        Class::Store,
        Class::Branch,
        Class::MulDiv,
        Class::Other,
    ];

    /// The name in the report.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Class::FpArith => "FP arithmetic, compare, convert, move (1)",
            Class::FpMac => "FP multiply-accumulate (3)",
            Class::FpDivSqrt => "vdiv / vsqrt (14)",
            Class::Load => "loads (2, 1 pipelined; multiple 1+N)",
            Class::Store => "stores (2, 1 pipelined; multiple 1+N)",
            Class::Branch => "branches",
            Class::MulDiv => "integer multiply / divide",
            Class::Other => "integer ALU, IT, other (1)",
        }
    }
}

impl fmt::Display for Class {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.label())
    }
}

/// The timing of one instruction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Timing {
    /// Its class.
    pub class: Class,
    /// Cycles per execution, without the refill of a taken branch and before
    /// pipelining.
    pub cycles: u64,
    /// May write the PC: each taken execution adds the refill `P`.
    pub branch: bool,
    /// A load or store single: 1 cycle instead of 2 right after another one.
    pub single: bool,
}

impl Timing {
    fn new(class: Class, cycles: u64) -> Self {
        Self {
            class,
            cycles,
            branch: false,
            single: false,
        }
    }
    fn branch(cycles: u64) -> Self {
        Self {
            branch: true,
            ..Self::new(Class::Branch, cycles)
        }
    }
    fn single(class: Class) -> Self {
        Self {
            single: true,
            ..Self::new(class, 2)
        }
    }
}

const CONDITIONS: [&str; 17] = [
    "eq", "ne", "cs", "hs", "cc", "lo", "mi", "pl", "vs", "vc", "hi", "ls", "ge", "lt", "gt", "le",
    "al",
];

/// Mnemonic roots this model tells apart (without condition, `s` or width suffix).
const ROOTS: [&str; 72] = [
    "b", "bl", "blx", "bx", "cbz", "cbnz", "tbb", "tbh", "ldr", "ldrb", "ldrh", "ldrsb", "ldrsh",
    "ldrd", "ldrex", "ldrexb", "ldrexh", "ldrt", "ldrbt", "ldrht", "ldrsbt", "ldrsht", "ldm",
    "ldmia", "ldmdb", "ldmfd", "ldmea", "str", "strb", "strh", "strd", "strex", "strexb", "strexh",
    "strt", "strbt", "strht", "stm", "stmia", "stmdb", "stmea", "stmfd", "push", "pop", "mul",
    "mla", "mls", "smull", "umull", "smlal", "umlal", "sdiv", "udiv", "vldr", "vstr", "vldm",
    "vldmia", "vldmdb", "vstm", "vstmia", "vstmdb", "vpush", "vpop", "vdiv", "vsqrt", "vmla",
    "vmls", "vnmla", "vnmls", "vfma", "vfms", "vmov",
];

/// The root of a mnemonic: `bne.w` -> `b`, `ldrbeq` -> `ldrb`, `muls` -> `mul`,
/// `vldmia.f32` -> `vldmia`; a mnemonic the model does not tell apart comes back
/// without its `.` suffixes.
fn root(mnemonic: &str) -> &str {
    let base = mnemonic.split('.').next().unwrap_or(mnemonic);
    if ROOTS.contains(&base) {
        return base;
    }
    for c in CONDITIONS {
        if let Some(r) = base.strip_suffix(c) {
            if ROOTS.contains(&r) {
                return r;
            }
            if let Some(r) = r.strip_suffix('s').filter(|r| ROOTS.contains(r)) {
                return r;
            }
        }
    }
    match base.strip_suffix('s') {
        Some(r) if ROOTS.contains(&r) => r,
        _ => base,
    }
}

/// Registers in the `{...}` list of `operands`, counted in 32-bit words (a `d`
/// register is two); ranges such as `d8-d11` are expanded.
fn list_words(operands: &str) -> u64 {
    let Some(list) = operands
        .split_once('{')
        .and_then(|(_, rest)| rest.split_once('}'))
        .map(|(l, _)| l)
    else {
        return 1;
    };
    let number = |r: &str| -> Option<u64> {
        r.trim_start_matches(|c: char| c.is_ascii_alphabetic())
            .parse()
            .ok()
    };
    list.split(',')
        .map(str::trim)
        .filter(|r| !r.is_empty())
        .map(|r| {
            let width = if r.starts_with('d') { 2 } else { 1 };
            let regs = match r.split_once('-') {
                Some((a, b)) => match (number(a.trim()), number(b.trim())) {
                    (Some(a), Some(b)) if b >= a => b - a + 1,
                    _ => 1,
                },
                None => 1,
            };
            width * regs
        })
        .sum()
}

/// Whether the register list of `operands` holds the PC.
fn list_has_pc(operands: &str) -> bool {
    operands
        .split_once('{')
        .and_then(|(_, rest)| rest.split_once('}'))
        .is_some_and(|(l, _)| l.split(',').any(|r| r.trim() == "pc"))
}

/// The first operand is the PC (`mov pc, lr`, `ldr pc, [sp], #4`).
fn writes_pc(operands: &str) -> bool {
    operands.split(',').next().map(str::trim) == Some("pc")
}

/// The timing of one instruction from its disassembly (`mnemonic operands`).
#[must_use]
pub fn timing(disassembly: &str) -> Timing {
    let text = disassembly.trim().to_ascii_lowercase();
    let (mnemonic, operands) = text.split_once(char::is_whitespace).unwrap_or((&text, ""));
    let operands = operands.trim();
    let r = root(mnemonic);
    let multiple = 1 + list_words(operands);
    match r {
        "b" | "cbz" | "cbnz" | "bl" | "blx" | "bx" => Timing::branch(1),
        "tbb" | "tbh" => Timing::branch(2),
        "pop" | "ldm" | "ldmia" | "ldmdb" | "ldmfd" | "ldmea" if list_has_pc(operands) => {
            Timing::branch(multiple)
        }
        "pop" | "ldm" | "ldmia" | "ldmdb" | "ldmfd" | "ldmea" => Timing::new(Class::Load, multiple),
        "push" | "stm" | "stmia" | "stmdb" | "stmea" | "stmfd" => {
            Timing::new(Class::Store, multiple)
        }
        "ldr" if writes_pc(operands) => Timing::branch(2),
        "ldr" | "ldrb" | "ldrh" | "ldrsb" | "ldrsh" | "ldrex" | "ldrexb" | "ldrexh" | "ldrt"
        | "ldrbt" | "ldrht" | "ldrsbt" | "ldrsht" | "vldr" => Timing::single(Class::Load),
        "str" | "strb" | "strh" | "strex" | "strexb" | "strexh" | "strt" | "strbt" | "strht"
        | "vstr" => Timing::single(Class::Store),
        "ldrd" => Timing::new(Class::Load, 3),
        "strd" => Timing::new(Class::Store, 3),
        "vldm" | "vldmia" | "vldmdb" | "vpop" => Timing::new(Class::Load, multiple),
        "vstm" | "vstmia" | "vstmdb" | "vpush" => Timing::new(Class::Store, multiple),
        "vdiv" | "vsqrt" => Timing::new(Class::FpDivSqrt, FP_DIV_SQRT),
        "vmla" | "vmls" | "vnmla" | "vnmls" | "vfma" | "vfms" => Timing::new(Class::FpMac, FP_MAC),
        // Two core registers to or from a D register or two S registers: 2 cycles.
        "vmov" if operands.split(',').count() >= 3 => Timing::new(Class::FpArith, 2),
        "mul" | "smull" | "umull" | "smlal" | "umlal" => Timing::new(Class::MulDiv, 1),
        "mla" | "mls" => Timing::new(Class::MulDiv, 2),
        "sdiv" | "udiv" => Timing::new(Class::MulDiv, DIVIDE),
        // vfnma/vfnms: the roots above stop at vfms, catch the rest of the family.
        r if r.starts_with("vfnm") => Timing::new(Class::FpMac, FP_MAC),
        r if r.starts_with('v') => Timing::new(Class::FpArith, 1),
        _ if writes_pc(operands) => Timing::branch(1),
        _ => Timing::new(Class::Other, 1),
    }
}

/// One executed instruction of a profile.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Insn {
    /// Its address.
    pub pc: u64,
    /// Executions.
    pub count: u64,
    /// Executions after which the next instruction executed was not `pc + size`.
    pub taken: u64,
    /// Bytes: 2 or 4.
    pub size: u32,
    /// QEMU's disassembly.
    pub disas: String,
}

/// The estimated cost of one instruction over all its executions.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Cost {
    /// How it was classified.
    pub timing: Timing,
    /// Cycles without the refills of taken branches.
    pub fixed: u64,
    /// Taken executions of a branch: each adds the refill `P`.
    pub refills: u64,
    /// Executions that pipelined with the load/store single before them (1 cycle
    /// saved each, already taken off `fixed`).
    pub pipelined: u64,
}

impl Cost {
    /// Cycles with the refill `p` for each taken branch.
    #[must_use]
    pub fn cycles_at(&self, p: u64) -> u64 {
        self.fixed + self.refills * p
    }
    /// Cycles with the assumed refill [`REFILL`].
    #[must_use]
    pub fn cycles(&self) -> u64 {
        self.cycles_at(REFILL)
    }
}

/// The cost of each instruction of `insns` (any order; one entry per PC), in the
/// same order.
#[must_use]
pub fn costs(insns: &[Insn]) -> Vec<Cost> {
    let timings: Vec<Timing> = insns.iter().map(|i| timing(&i.disas)).collect();
    let by_end: std::collections::HashMap<u64, usize> = insns
        .iter()
        .enumerate()
        .map(|(k, i)| (i.pc + u64::from(i.size), k))
        .collect();
    insns
        .iter()
        .zip(&timings)
        .map(|(i, &t)| {
            let pipelined = if t.single {
                by_end
                    .get(&i.pc)
                    .filter(|&&k| timings[k].single)
                    .map_or(0, |&k| {
                        let before = &insns[k];
                        i.count.min(before.count - before.taken.min(before.count))
                    })
            } else {
                0
            };
            Cost {
                timing: t,
                fixed: i.count * t.cycles - pipelined,
                refills: if t.branch { i.taken.min(i.count) } else { 0 },
                pipelined,
            }
        })
        .collect()
}

/// The estimated cycles of a whole profile: the sum of [`costs`] with the
/// assumed refill [`REFILL`] for each taken branch.
#[must_use]
pub fn estimate(insns: &[Insn]) -> u64 {
    costs(insns).iter().map(Cost::cycles).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn t(d: &str) -> Timing {
        timing(d)
    }

    #[test]
    fn fpu_instructions() {
        assert_eq!(t("vdiv.f32 s0, s2, s0"), Timing::new(Class::FpDivSqrt, 14));
        assert_eq!(t("vsqrt.f32 s4, s4"), Timing::new(Class::FpDivSqrt, 14));
        assert_eq!(t("vmla.f32 s16, s20, s20"), Timing::new(Class::FpMac, 3));
        assert_eq!(t("vmls.f32 s20, s2, s15"), Timing::new(Class::FpMac, 3));
        assert_eq!(t("vnmls.f32 s0, s1, s2"), Timing::new(Class::FpMac, 3));
        assert_eq!(t("vfnma.f32 s0, s1, s2"), Timing::new(Class::FpMac, 3));
        for one in [
            "vadd.f32 s5, s18, s20",
            "vsub.f32 s0, s1, s2",
            "vmul.f32 s9, s16, s9",
            "vnmul.f32 s0, s1, s2",
            "vneg.f32 s0, s0",
            "vabs.f32 s1, s1",
            "vcmp.f32 s9, s5",
            "vcmp.f32 s0, #0",
            "vcvt.u32.f32 s0, s6",
            "vcvt.f32.s32 s10, s10",
            "vmov.f32 s4, s18",
            "vmov r0, s0",
            "vmov.f32 s0, #1.000000e+00",
            "vmrs apsr_nzcv, fpscr",
        ] {
            assert_eq!(t(one), Timing::new(Class::FpArith, 1), "{one}");
        }
        assert_eq!(t("vmov r0, r1, d0"), Timing::new(Class::FpArith, 2));
        assert_eq!(t("vldr s9, [pc, #0x288]"), Timing::single(Class::Load));
        assert_eq!(t("vstr s0, [sp, #0x10]"), Timing::single(Class::Store));
        assert_eq!(t("vldmia r0, {s0, s1, s2}"), Timing::new(Class::Load, 4));
        assert_eq!(t("vldmia r1!, {d8, d9}"), Timing::new(Class::Load, 5));
        assert_eq!(t("vpush {d8, d9, d10}"), Timing::new(Class::Store, 7));
        assert_eq!(t("vpop {d8-d11}"), Timing::new(Class::Load, 9));
        assert_eq!(t("vstmia r0, {s16-s19}"), Timing::new(Class::Store, 5));
    }

    #[test]
    fn loads_and_stores() {
        for l in [
            "ldr r3, [r0, #4]",
            "ldr.w r11, [sp, #0x1c]",
            "ldrh.w r1, [sp, #0xca]",
            "ldrb r0, [r1]",
            "ldrsh r0, [r1, r2]",
            "ldrbeq r0, [r1]",
        ] {
            assert_eq!(t(l), Timing::single(Class::Load), "{l}");
        }
        for s in [
            "str r5, [sp, #0x44]",
            "strh.w r6, [r4, #0x304]",
            "strb r0, [r1]",
        ] {
            assert_eq!(t(s), Timing::single(Class::Store), "{s}");
        }
        assert_eq!(t("ldrd r0, r1, [sp, #8]"), Timing::new(Class::Load, 3));
        assert_eq!(t("strd r0, r1, [sp, #8]"), Timing::new(Class::Store, 3));
        assert_eq!(t("ldm r2, {r0, r1, r2}"), Timing::new(Class::Load, 4));
        assert_eq!(
            t("ldm.w r2, {r0, r4, r5, r6, r8, lr}"),
            Timing::new(Class::Load, 7)
        );
        assert_eq!(t("stm r0!, {r1, r2, r3}"), Timing::new(Class::Store, 4));
        assert_eq!(t("push {r4, r5, r6, lr}"), Timing::new(Class::Store, 5));
        assert_eq!(t("push.w {r8, sb, sl, fp}"), Timing::new(Class::Store, 5));
        assert_eq!(t("pop.w {r8, sb, fp}"), Timing::new(Class::Load, 4));
    }

    #[test]
    fn branches() {
        // A pop that loads the PC returns: a taken branch, 1 + N (+ P when taken).
        assert_eq!(t("pop {r4, r5, r6, r7, pc}"), Timing::branch(6));
        assert_eq!(t("pop {r7, pc}"), Timing::branch(3));
        assert_eq!(t("ldm.w sp!, {r4, pc}"), Timing::branch(3));
        assert_eq!(t("ldr pc, [sp], #4"), Timing::branch(2));
        for b in [
            "b #0x39da",
            "b.n #0x39da",
            "b.w #0x39da",
            "bne #0xa490",
            "bne.n #0xa490",
            "beq.w #0xa674",
            "ble #0xa490",
            "bls #0xde8c",
            "blt #0xa542",
            "blo.w #0x39f6",
            "bhs.w #0x1234",
            "bvs.w #0xa674",
            "bl #0x875a",
            "blx r3",
            "bx lr",
            "cbz r0, #0xd7c8",
            "cbnz r1, #0xeb26",
            "mov pc, lr",
        ] {
            assert_eq!(t(b), Timing::branch(1), "{b}");
        }
        assert_eq!(t("tbb [pc, r8]"), Timing::branch(2));
        assert_eq!(t("tbh [pc, r0, lsl #1]"), Timing::branch(2));
    }

    #[test]
    fn integer_and_it() {
        for o in [
            "it hi",
            "itt ne",
            "ittt gt",
            "ite eq",
            "movs r2, #1",
            "mov r3, r1",
            "add.w r9, sp, #0xe0",
            "cmp.w r0, fp, lsl #4",
            "bic r5, r0, #0xff000000",
            "bics r0, r1",
            "lsls r0, r0, #2",
            "movgt r0, r1",
            "nop",
        ] {
            assert_eq!(t(o), Timing::new(Class::Other, 1), "{o}");
        }
        assert_eq!(t("muls r1, r0, r1"), Timing::new(Class::MulDiv, 1));
        assert_eq!(t("mla sl, lr, r1, r0"), Timing::new(Class::MulDiv, 2));
        assert_eq!(t("umull r0, r1, r2, r3"), Timing::new(Class::MulDiv, 1));
        assert_eq!(t("udiv r0, r1, r2"), Timing::new(Class::MulDiv, DIVIDE));
        assert_eq!(t("sdiv r0, r1, r2"), Timing::new(Class::MulDiv, DIVIDE));
    }

    fn insn(pc: u64, count: u64, taken: u64, size: u32, disas: &str) -> Insn {
        Insn {
            pc,
            count,
            taken,
            size,
            disas: disas.into(),
        }
    }

    #[test]
    fn costs_charge_taken_branches_and_pipelined_loads() {
        let insns = [
            // A loop of 10: two loads (the second pipelines), an add, a
            // branch taken 9 times; then a return.
            insn(0x100, 10, 0, 2, "ldr r0, [r1]"),
            insn(0x102, 10, 0, 4, "ldr.w r2, [r1, #4]"),
            insn(0x106, 10, 0, 2, "adds r0, r0, r2"),
            insn(0x108, 10, 9, 2, "bne #0x100"),
            insn(0x10a, 1, 1, 2, "pop {r4, pc}"),
        ];
        let c = costs(&insns);
        assert_eq!(c[0].cycles(), 20);
        assert_eq!((c[1].cycles(), c[1].pipelined), (10, 10));
        assert_eq!(c[2].cycles(), 10);
        assert_eq!(c[3].cycles(), 10 + 9 * REFILL);
        assert_eq!(c[3].cycles_at(1), 19);
        assert_eq!(c[4].cycles(), 3 + REFILL);
        // The whole profile: 20 + 10 + 10 + (10 + 9P) + (3 + P).
        assert_eq!(estimate(&insns), 53 + 10 * REFILL);
        assert_eq!(estimate(&[]), 0);
        // A load reached only by branching to it does not pipeline.
        let jumped = [
            insn(0x200, 5, 5, 2, "ldr r0, [r1]"),
            insn(0x202, 7, 0, 2, "ldr r2, [r3]"),
        ];
        let c = costs(&jumped);
        assert_eq!((c[1].pipelined, c[1].cycles()), (0, 14));
        // Half the executions fall through from the load before it.
        let half = [
            insn(0x300, 4, 0, 2, "str r0, [r1]"),
            insn(0x302, 8, 0, 2, "ldr r2, [r3]"),
        ];
        assert_eq!(costs(&half)[1].cycles(), 8 * 2 - 4);
    }
}
