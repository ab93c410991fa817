//! Which source function each PC of the firmware belongs to, inlined frames
//! included, from the ELF's DWARF line and inline information (the firmware is
//! built with `debug = true` and fat LTO: nearly everything is inlined into a few
//! symbols, so the symbol table alone says little). [`by_function`] adds up a
//! profile per innermost function.

use crate::cycles::{Cost, Insn};

use object::{Object, ObjectSection, ObjectSymbol};
use std::borrow::Cow;
use std::collections::{BTreeMap, HashMap};
use std::path::Path;
use std::sync::Arc;

type Reader = gimli::EndianArcSlice<gimli::RunTimeEndian>;

/// One frame at a PC: a function and the source line in it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Frame {
    /// The function, demangled, without its hash.
    pub function: String,
    /// The source file (shortened: relative to the repository, `library/...` for
    /// the standard library, `crate-version/...` for a dependency), if known.
    pub file: Option<String>,
    /// The line in `file`: the PC's line in the innermost frame, the call site in
    /// the outer ones.
    pub line: Option<u32>,
}

/// Maps PCs of one ELF to their frames.
pub struct Symbolizer {
    ctx: addr2line::Context<Reader>,
    /// Function symbols: start, size, demangled name; by start.
    symbols: Vec<(u64, u64, String)>,
    root: String,
}

impl Symbolizer {
    /// Reads the DWARF sections and the symbol table of `elf`.
    pub fn new(elf: &Path) -> Result<Self, String> {
        let bytes =
            std::fs::read(elf).map_err(|e| format!("cannot read {}: {e}", elf.display()))?;
        let file = object::File::parse(&*bytes)
            .map_err(|e| format!("{} is not an object file: {e}", elf.display()))?;
        let endian = if file.is_little_endian() {
            gimli::RunTimeEndian::Little
        } else {
            gimli::RunTimeEndian::Big
        };
        let load = |id: gimli::SectionId| -> Result<Reader, gimli::Error> {
            let data = file
                .section_by_name(id.name())
                .and_then(|s| s.data().ok())
                .unwrap_or(&[]);
            Ok(Reader::new(Arc::from(data), endian))
        };
        let dwarf = gimli::Dwarf::load(load)
            .map_err(|e| format!("cannot read the DWARF of {}: {e}", elf.display()))?;
        let ctx = addr2line::Context::from_dwarf(dwarf)
            .map_err(|e| format!("cannot index the DWARF of {}: {e}", elf.display()))?;
        let mut symbols: Vec<(u64, u64, String)> = file
            .symbols()
            .filter(|s| s.kind() == object::SymbolKind::Text && s.size() > 0)
            .filter_map(|s| {
                let name = s.name().ok()?;
                let name = format!("{:#}", rustc_demangle::demangle(name));
                Some((s.address() & !1, s.size(), name))
            })
            .collect();
        symbols.sort();
        let root = crate::firmware::repo_root();
        let root = root.canonicalize().unwrap_or(root).display().to_string();
        Ok(Self { ctx, symbols, root })
    }

    /// The ELF symbol containing `pc`.
    #[must_use]
    pub fn symbol(&self, pc: u64) -> Option<&str> {
        let i = self.symbols.partition_point(|s| s.0 <= pc);
        let (start, size, name) = self.symbols.get(i.checked_sub(1)?)?;
        (pc < start + size).then_some(name.as_str())
    }

    /// The frames at `pc`, innermost first; never empty (the ELF symbol, or `?`,
    /// when the DWARF has nothing).
    #[must_use]
    pub fn frames(&self, pc: u64) -> Vec<Frame> {
        let mut out = Vec::new();
        if let Ok(mut it) = self.ctx.find_frames(pc).skip_all_loads() {
            while let Ok(Some(f)) = it.next() {
                let function = f
                    .function
                    .as_ref()
                    .and_then(|n| n.demangle().ok())
                    .map_or_else(|| "?".to_string(), Cow::into_owned);
                let (file, line) = f
                    .location
                    .map_or((None, None), |l| (l.file.map(|p| self.shorten(p)), l.line));
                out.push(Frame {
                    function,
                    file,
                    line,
                });
            }
        }
        let symbol = self.symbol(pc).unwrap_or("?").to_string();
        match out.first_mut() {
            None => out.push(Frame {
                function: symbol,
                file: None,
                line: None,
            }),
            Some(f) if f.function == "?" => f.function = symbol,
            Some(_) => {}
        }
        out
    }

    fn shorten(&self, path: &str) -> String {
        if let Some(rest) = path.strip_prefix(&self.root) {
            return rest.trim_start_matches('/').to_string();
        }
        if let Some(i) = path.find("/library/") {
            return path[i + 1..].to_string();
        }
        if let Some(i) = path.find("/registry/src/") {
            let rest = &path[i + "/registry/src/".len()..];
            return rest.split_once('/').map_or(rest, |(_, r)| r).to_string();
        }
        path.to_string()
    }
}

/// A function's share of a profile.
#[derive(Clone, Debug, Default)]
pub struct FunctionCost {
    /// The innermost function.
    pub name: String,
    /// Instructions executed in it (not in what it calls or inlines).
    pub count: u64,
    /// Their estimated cycles.
    pub cycles: u64,
    /// The source lines these instructions come from: file -> (first line, last
    /// line, instructions).
    pub lines: BTreeMap<String, (u32, u32, u64)>,
    /// The functions it was inlined into or called from (the next frame out, or
    /// the ELF symbol when it is not inlined), with the instructions of each.
    pub callers: HashMap<String, u64>,
}

impl FunctionCost {
    /// The file most of its instructions come from and the range of their lines,
    /// `file:first-last`.
    #[must_use]
    pub fn source(&self) -> String {
        self.lines
            .iter()
            .max_by_key(|(_, (_, _, n))| *n)
            .map_or_else(String::new, |(f, (a, b, _))| {
                if a == b {
                    format!("{f}:{a}")
                } else {
                    format!("{f}:{a}-{b}")
                }
            })
    }

    /// The caller with the most instructions and its share of this function's.
    #[must_use]
    pub fn main_caller(&self) -> Option<(&str, f64)> {
        self.callers
            .iter()
            .max_by(|a, b| a.1.cmp(b.1).then_with(|| b.0.cmp(a.0)))
            .map(|(n, c)| (n.as_str(), *c as f64 / self.count.max(1) as f64))
    }
}

/// Adds up `insns` (with their `costs`) per innermost function, most instructions
/// first.
#[must_use]
pub fn by_function(sym: &Symbolizer, insns: &[Insn], costs: &[Cost]) -> Vec<FunctionCost> {
    let mut map: HashMap<String, FunctionCost> = HashMap::new();
    for (i, c) in insns.iter().zip(costs) {
        let frames = sym.frames(i.pc);
        let inner = &frames[0];
        let caller = frames
            .get(1)
            .map_or_else(|| sym.symbol(i.pc).unwrap_or("?"), |f| f.function.as_str());
        let e = map
            .entry(inner.function.clone())
            .or_insert_with(|| FunctionCost {
                name: inner.function.clone(),
                ..FunctionCost::default()
            });
        e.count += i.count;
        e.cycles += c.cycles();
        // Line 0: code the compiler made up, no source line.
        if let (Some(f), Some(l)) = (&inner.file, inner.line.filter(|&l| l > 0)) {
            let r = e.lines.entry(f.clone()).or_insert((l, l, 0));
            r.0 = r.0.min(l);
            r.1 = r.1.max(l);
            r.2 += i.count;
        }
        *e.callers.entry(caller.to_string()).or_default() += i.count;
    }
    let mut v: Vec<FunctionCost> = map.into_values().collect();
    v.sort_by(|a, b| b.count.cmp(&a.count).then_with(|| a.name.cmp(&b.name)));
    v
}
