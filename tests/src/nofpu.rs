//! Chips without an FPU (`firmware::NOFPU_CORES`): where an instruction profile of
//! the firmware goes by out-of-line routine, and what kind of routine each is
//! (software floating point, the integer helpers it calls, libm, the renderer's
//! own code); and an estimate of Cortex-M0+ cycles from the profile of the Armv6-M
//! image.
//!
//! Routines come from the ELF's symbol table, not from the DWARF: the software
//! floating point of `compiler_builtins` is never inlined (it is not part of the
//! link-time optimisation), so each of its operations is a call of a routine, and
//! its precompiled code has no inlining information to walk.

use crate::cycles::Insn;
use object::{Object, ObjectSymbol};
use std::collections::HashMap;
use std::path::Path;

/// What an out-of-line routine does.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Kind {
    /// `f32` addition and subtraction (`__addsf3`, `__subsf3`, `__aeabi_fadd`, ...).
    F32Add,
    /// `f32` multiplication (`__mulsf3`, `__aeabi_fmul`).
    F32Mul,
    /// `f32` division (`__divsf3`, `__aeabi_fdiv`).
    F32Div,
    /// `f32` comparisons (`__ltsf2`, `__aeabi_fcmpgt`, `__unordsf2`, ...).
    F32Compare,
    /// Conversions between floats and integers or between `f32` and `f64`
    /// (`__floatsisf`, `__fixsfsi`, `__aeabi_f2d`, ...).
    Conversion,
    /// `f64` arithmetic and comparisons (`__adddf3`, `__aeabi_dmul`, ...).
    F64,
    /// Integer helpers: 64-bit multiply and shifts, count leading zeros, division
    /// (`__aeabi_lmul`, `__clzsi2`, `__aeabi_uidiv`, ...).
    IntHelper,
    /// `memcpy`, `memset` and the like.
    Memory,
    /// libm's functions not inlined (`sqrtf`, ...).
    Libm,
    /// Everything else: the renderer, with everything inlined into it.
    Renderer,
}

impl Kind {
    /// Every kind, in the report's order.
    pub const ALL: [Kind; 10] = [
        Kind::F32Add,
        Kind::F32Mul,
        Kind::F32Div,
        Kind::F32Compare,
        Kind::Conversion,
        Kind::F64,
        Kind::IntHelper,
        Kind::Memory,
        Kind::Libm,
        Kind::Renderer,
    ];

    /// The name in the report.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Kind::F32Add => "f32 add/sub",
            Kind::F32Mul => "f32 mul",
            Kind::F32Div => "f32 div",
            Kind::F32Compare => "f32 compare",
            Kind::Conversion => "int/float and f32/f64 conversions",
            Kind::F64 => "f64 arithmetic",
            Kind::IntHelper => "integer helpers (64-bit multiply, clz, division)",
            Kind::Memory => "memcpy/memset",
            Kind::Libm => "libm (out of line: sqrtf, ...)",
            Kind::Renderer => "the renderer's own code (with what is inlined into it)",
        }
    }

    /// A routine of software floating point (`compiler_builtins`' float module, or
    /// Arm's run-time ABI names for it).
    #[must_use]
    pub fn is_soft_float(self) -> bool {
        matches!(
            self,
            Kind::F32Add
                | Kind::F32Mul
                | Kind::F32Div
                | Kind::F32Compare
                | Kind::Conversion
                | Kind::F64
        )
    }
}

/// The kind of the routine named `name` (the last segment of its demangled symbol,
/// as [`routine_name`] gives it).
#[must_use]
pub fn kind(name: &str) -> Kind {
    const ADD: [&str; 5] = [
        "__addsf3",
        "__subsf3",
        "__aeabi_fadd",
        "__aeabi_fsub",
        "__aeabi_frsub",
    ];
    const INT: [&str; 7] = ["lmul", "muldi3", "mulsi3", "clz", "ctz", "div", "mod"];
    const SHIFT: [&str; 6] = [
        "__aeabi_llsl",
        "__aeabi_llsr",
        "__aeabi_lasr",
        "__ashldi3",
        "__lshrdi3",
        "__ashrdi3",
    ];
    const MEMORY: [&str; 5] = ["memcpy", "memset", "memmove", "memcmp", "bcmp"];
    if ADD.contains(&name) {
        return Kind::F32Add;
    }
    if name == "__mulsf3" || name == "__aeabi_fmul" {
        return Kind::F32Mul;
    }
    if name == "__divsf3" || name == "__aeabi_fdiv" {
        return Kind::F32Div;
    }
    if let Some(rest) = name.strip_prefix("__") {
        // Conversions: `__floatsisf`, `__fixunssfsi`, `__extendsfdf2`,
        // `__truncdfsf2`, `__aeabi_i2f`, `__aeabi_f2iz`, `__aeabi_d2f`, ...
        let aeabi = rest.strip_prefix("aeabi_");
        let aeabi_conversion = aeabi.is_some_and(|r| {
            r.split_once('2').is_some_and(|(a, b)| {
                [a, b]
                    .iter()
                    .all(|s| matches!(s.trim_end_matches('z'), "f" | "d" | "i" | "ui" | "l" | "ul"))
                    && (a.contains(['f', 'd']) || b.contains(['f', 'd']))
            })
        });
        if aeabi_conversion
            || rest.starts_with("float")
            || rest.starts_with("fix")
            || rest.starts_with("extend")
            || rest.starts_with("trunc")
        {
            return Kind::Conversion;
        }
        if rest.ends_with("sf2") || aeabi.is_some_and(|r| r.starts_with("fcmp")) {
            return Kind::F32Compare;
        }
        if rest.ends_with("df3")
            || rest.ends_with("df2")
            || aeabi.is_some_and(|r| {
                ["dadd", "dsub", "drsub", "dmul", "ddiv", "dcmp"]
                    .iter()
                    .any(|p| r.starts_with(p))
            })
        {
            return Kind::F64;
        }
        if SHIFT.contains(&name) || INT.iter().any(|p| rest.contains(p)) {
            if MEMORY.iter().any(|m| rest.contains(m)) {
                return Kind::Memory;
            }
            return Kind::IntHelper;
        }
    }
    if MEMORY.iter().any(|m| name.contains(m)) {
        return Kind::Memory;
    }
    Kind::Renderer
}

/// The name of a routine for the tables: for a `compiler_builtins` routine or any
/// symbol that is not a Rust path, its last segment (`compiler_builtins::float::
/// add::__addsf3` -> `__addsf3`, so that an alias and its body share one name);
/// for libm `libm::<name>`; for the rest [`crate::dwarf::short_name`].
#[must_use]
pub fn routine_name(demangled: &str) -> String {
    let last = demangled.rsplit("::").next().unwrap_or(demangled);
    if last.starts_with("__") || demangled.starts_with("compiler_builtins::") {
        last.to_string()
    } else if demangled.starts_with("libm::") {
        format!("libm::{last}")
    } else {
        crate::dwarf::short_name(demangled)
    }
}

/// The kind of a symbol, by its demangled name.
fn kind_of(demangled: &str) -> Kind {
    if demangled.starts_with("libm::") {
        Kind::Libm
    } else {
        kind(&routine_name(demangled))
    }
}

/// The function symbols of an ELF: start, size, demangled name; by start.
pub struct Routines {
    symbols: Vec<(u64, u64, String)>,
}

impl Routines {
    /// Reads the symbol table of `elf` (functions with a size).
    pub fn new(elf: &Path) -> Result<Self, String> {
        let bytes =
            std::fs::read(elf).map_err(|e| format!("cannot read {}: {e}", elf.display()))?;
        let file = object::File::parse(&*bytes)
            .map_err(|e| format!("{} is not an object file: {e}", elf.display()))?;
        let mut symbols: Vec<(u64, u64, String)> = file
            .symbols()
            .filter(|s| s.kind() == object::SymbolKind::Text && s.size() > 0)
            .filter_map(|s| {
                let name = format!("{:#}", rustc_demangle::demangle(s.name().ok()?));
                Some((s.address() & !1, s.size(), name))
            })
            .collect();
        symbols.sort();
        symbols.dedup_by_key(|s| s.0);
        Ok(Self { symbols })
    }

    /// The symbol containing `pc`: its start and demangled name.
    #[must_use]
    pub fn at(&self, pc: u64) -> Option<(u64, &str)> {
        let i = self.symbols.partition_point(|s| s.0 <= pc);
        let (start, size, name) = self.symbols.get(i.checked_sub(1)?)?;
        (pc < start + size).then_some((*start, name.as_str()))
    }
}

/// A routine's share of a profile.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RoutineCost {
    /// Its name ([`routine_name`]).
    pub name: String,
    /// What it does.
    pub kind: Kind,
    /// Instructions executed in it.
    pub count: u64,
    /// How often it was entered: the executions of its first instruction. Symbols
    /// that share a name add up, except a `__` routine's, which are an alias and
    /// its body (the larger count is taken).
    pub calls: u64,
    /// Entries by a call from a software floating-point routine (Arm only: a `bl`
    /// whose target is this routine's first instruction).
    pub calls_from_float: u64,
}

/// `insns` added up per routine, most instructions first; an instruction outside
/// every symbol counts under `?`.
#[must_use]
pub fn by_routine(routines: &Routines, insns: &[Insn]) -> Vec<RoutineCost> {
    let mut map: HashMap<String, RoutineCost> = HashMap::new();
    let mut entries: HashMap<(String, u64), u64> = HashMap::new();
    let mut starts: HashMap<u64, String> = HashMap::new();
    for i in insns {
        let (start, demangled) = routines.at(i.pc).unwrap_or((u64::MAX, "?"));
        let name = routine_name(demangled);
        let e = map.entry(name.clone()).or_insert_with(|| RoutineCost {
            name: name.clone(),
            kind: kind_of(demangled),
            count: 0,
            calls: 0,
            calls_from_float: 0,
        });
        e.count += i.count;
        if i.pc == start {
            *entries.entry((name.clone(), start)).or_default() += i.count;
            starts.insert(start, name);
        }
    }
    for ((name, _), n) in entries {
        if let Some(e) = map.get_mut(&name) {
            e.calls = if name.starts_with("__") {
                e.calls.max(n)
            } else {
                e.calls + n
            };
        }
    }
    // Calls from the float routines: their `bl #<address>` (QEMU's Arm
    // disassembly), by the routine at the address.
    for i in insns {
        let Some(target) = i
            .disas
            .strip_prefix("bl #0x")
            .and_then(|t| u64::from_str_radix(t.trim(), 16).ok())
        else {
            continue;
        };
        let caller = routines
            .at(i.pc)
            .map_or(Kind::Renderer, |(_, n)| kind_of(n));
        if let (true, Some(callee)) = (caller.is_soft_float(), starts.get(&target))
            && let Some(e) = map.get_mut(callee)
        {
            e.calls_from_float += i.count;
        }
    }
    let mut v: Vec<RoutineCost> = map.into_values().collect();
    v.sort_by(|a, b| b.count.cmp(&a.count).then_with(|| a.name.cmp(&b.name)));
    v
}

/// Instructions by [`Kind`], with the integer helpers split by who called them:
/// `(kind, instructions)` for every kind, and the helpers' instructions charged to
/// the float routines (in proportion to their calls from them).
#[must_use]
pub fn by_kind(routines: &[RoutineCost]) -> (Vec<(Kind, u64)>, u64) {
    let mut helpers_for_float = 0.0;
    let totals = Kind::ALL
        .iter()
        .map(|&k| {
            let n = routines
                .iter()
                .filter(|r| r.kind == k)
                .map(|r| r.count)
                .sum();
            (k, n)
        })
        .collect();
    for r in routines.iter().filter(|r| r.kind == Kind::IntHelper) {
        if r.calls > 0 {
            helpers_for_float +=
                r.count as f64 * r.calls_from_float.min(r.calls) as f64 / r.calls as f64;
        }
    }
    (totals, helpers_for_float.round() as u64)
}

/// Cortex-M0+ cycles of a profile of Armv6-M code, with a multiplier of
/// `mul_cycles` cycles (1 or 32: the two options of the core), from the
/// instruction timings of the Cortex-M0+ Technical Reference Manual (ARM DDI 0484,
/// "Instruction set summary"), zero wait states:
///
/// - data processing, `MOVS`, compares, `ADR`, extends, `REV`: 1; `MULS`:
///   `mul_cycles`;
/// - a load or store single (`LDR*`, `STR*`): 2; `LDM`, `STM`, `PUSH`, `POP`:
///   1 + N for N registers; `POP` with the PC: 3 + N, N not counting the PC;
/// - `B` and a taken conditional branch: 2, not taken: 1; `BL`: 3; `BX`, `BLX`: 2;
///   `ADD`/`MOV` to the PC: 2;
/// - `DMB`, `DSB`, `ISB`: 3.
#[must_use]
pub fn m0plus_cycles(insns: &[Insn], mul_cycles: u64) -> u64 {
    insns.iter().map(|i| m0plus_cost(i, mul_cycles)).sum()
}

/// The cycles of `i` over all its executions ([`m0plus_cycles`]).
#[must_use]
pub fn m0plus_cost(i: &Insn, mul_cycles: u64) -> u64 {
    let (mnemonic, operands) = i
        .disas
        .trim()
        .split_once(char::is_whitespace)
        .unwrap_or((i.disas.trim(), ""));
    let registers = || {
        operands
            .split_once('{')
            .and_then(|(_, r)| r.split_once('}'))
            .map_or(0, |(r, _)| {
                r.split(',')
                    .map(str::trim)
                    .filter(|r| !r.is_empty() && *r != "pc")
                    .map(|r| {
                        // A range `r4-r7`.
                        r.split_once('-').map_or(1, |(a, b)| {
                            let n = |s: &str| s.trim_start_matches('r').parse::<u64>().ok();
                            match (n(a), n(b)) {
                                (Some(a), Some(b)) if b >= a => b - a + 1,
                                _ => 1,
                            }
                        })
                    })
                    .sum::<u64>()
            })
    };
    let to_pc = operands.split(',').next().map(str::trim) == Some("pc");
    const CONDITIONS: [&str; 16] = [
        "eq", "ne", "cs", "hs", "cc", "lo", "mi", "pl", "vs", "vc", "hi", "ls", "ge", "lt", "gt",
        "le",
    ];
    let each = match mnemonic {
        "bl" => 3,
        "b" | "bx" | "blx" => 2,
        m if m.len() == 3 && m.starts_with('b') && CONDITIONS.contains(&&m[1..]) => {
            // 1 each, and 1 more when taken.
            return i.count + i.taken.min(i.count);
        }
        "pop" if operands.contains("pc") => 3 + registers(),
        "pop" | "push" | "ldm" | "stm" | "ldmia" | "stmia" => 1 + registers(),
        m if m.starts_with("ldr") || m.starts_with("str") => 2,
        "muls" | "mul" => mul_cycles,
        "dmb" | "dsb" | "isb" => 3,
        "add" | "mov" if to_pc => 2,
        _ => 1,
    };
    i.count * each
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn routines_are_sorted_by_kind() {
        for (name, k) in [
            ("__addsf3", Kind::F32Add),
            ("__aeabi_fsub", Kind::F32Add),
            ("__mulsf3", Kind::F32Mul),
            ("__aeabi_fmul", Kind::F32Mul),
            ("__divsf3", Kind::F32Div),
            ("__aeabi_fcmpgt", Kind::F32Compare),
            ("__gtsf2", Kind::F32Compare),
            ("__unordsf2", Kind::F32Compare),
            ("__floatunsisf", Kind::Conversion),
            ("__fixsfsi", Kind::Conversion),
            ("__extendsfdf2", Kind::Conversion),
            ("__truncdfsf2", Kind::Conversion),
            ("__aeabi_ui2f", Kind::Conversion),
            ("__aeabi_f2iz", Kind::Conversion),
            ("__aeabi_d2f", Kind::Conversion),
            ("__aeabi_f2d", Kind::Conversion),
            ("__adddf3", Kind::F64),
            ("__aeabi_dmul", Kind::F64),
            ("__aeabi_dcmplt", Kind::F64),
            ("__ledf2", Kind::F64),
            ("__aeabi_lmul", Kind::IntHelper),
            ("__clzsi2", Kind::IntHelper),
            ("__aeabi_uidiv", Kind::IntHelper),
            ("__aeabi_uidivmod", Kind::IntHelper),
            ("__udivmoddi4", Kind::IntHelper),
            ("__aeabi_llsr", Kind::IntHelper),
            ("__aeabi_memcpy4", Kind::Memory),
            ("memset", Kind::Memory),
            ("Renderer::ray_color_call", Kind::Renderer),
        ] {
            assert_eq!(kind(name), k, "{name}");
        }
        assert!(Kind::F64.is_soft_float() && !Kind::IntHelper.is_soft_float());
        assert_eq!(
            routine_name("compiler_builtins::float::add::__addsf3"),
            "__addsf3"
        );
        assert_eq!(
            routine_name("libm::math::sqrt::sqrtf"),
            "libm::sqrtf".to_string()
        );
        assert_eq!(kind_of("libm::math::sqrt::sqrtf"), Kind::Libm);
    }

    fn insn(disas: &str, count: u64, taken: u64) -> Insn {
        Insn {
            pc: 0,
            count,
            taken,
            size: 2,
            disas: disas.into(),
        }
    }

    #[test]
    fn cortex_m0plus_timings() {
        let cost = |d: &str, count, taken| m0plus_cost(&insn(d, count, taken), 1);
        assert_eq!(cost("adds r0, r1, r2", 10, 0), 10);
        assert_eq!(cost("ldr r0, [sp, #0x88]", 10, 0), 20);
        assert_eq!(cost("strb r0, [r1, r2]", 3, 0), 6);
        assert_eq!(cost("bne #0x3950", 10, 4), 14);
        assert_eq!(cost("b #0x3950", 5, 5), 10);
        assert_eq!(cost("bl #0x6f69c", 2, 2), 6);
        assert_eq!(cost("push {r4, r5, r6, r7, lr}", 1, 0), 6);
        assert_eq!(cost("pop {r4, r5, r6, r7, pc}", 1, 1), 7);
        assert_eq!(cost("pop {r7, pc}", 2, 2), 8);
        assert_eq!(cost("ldm r0!, {r1, r2}", 1, 0), 3);
        assert_eq!(cost("add pc, r0", 4, 4), 8);
        assert_eq!(cost("mov r1, r0", 4, 0), 4);
        assert_eq!(cost("muls r0, r1, r0", 4, 0), 4);
        assert_eq!(m0plus_cost(&insn("muls r0, r1, r0", 4, 0), 32), 128);
    }

    #[test]
    fn helpers_are_charged_to_the_float_routines_that_call_them() {
        let r = |name: &str, count, calls, from| RoutineCost {
            name: name.into(),
            kind: kind(name),
            count,
            calls,
            calls_from_float: from,
        };
        let (totals, helpers) = by_kind(&[
            r("__mulsf3", 600, 10, 0),
            r("__aeabi_lmul", 400, 10, 5),
            r("Renderer::fill", 100, 1, 0),
        ]);
        assert_eq!(helpers, 200);
        assert!(totals.contains(&(Kind::F32Mul, 600)));
        assert!(totals.contains(&(Kind::IntHelper, 400)));
        assert!(totals.contains(&(Kind::Renderer, 100)));
    }
}
