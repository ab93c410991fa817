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
    /// The function.
    pub name: String,
    /// Instructions executed in it: in its own code for [`by_function`], in its
    /// code and everything inlined into it for [`inclusive`].
    pub count: u64,
    /// Their estimated cycles.
    pub cycles: u64,
    /// The source lines these instructions come from (in the function itself: for
    /// inlined code, the line of the call): file -> (first line, last line,
    /// instructions).
    pub lines: BTreeMap<String, (u32, u32, u64)>,
    /// Where it was inlined (the chain of up to [`CHAIN`] functions it was inlined
    /// into, innermost first, joined by ` < `; empty where it is the out-of-line
    /// function itself), with the instructions of each.
    pub callers: HashMap<String, u64>,
}

/// Functions shown in a chain of inlining.
pub const CHAIN: usize = 3;

impl FunctionCost {
    fn new(name: &str) -> Self {
        Self {
            name: name.to_string(),
            ..Self::default()
        }
    }

    fn add(&mut self, count: u64, cycles: u64, frame: &Frame) {
        self.count += count;
        self.cycles += cycles;
        // Line 0: code the compiler made up, no source line.
        if let (Some(f), Some(l)) = (&frame.file, frame.line.filter(|&l| l > 0)) {
            let r = self.lines.entry(f.clone()).or_insert((l, l, 0));
            r.0 = r.0.min(l);
            r.1 = r.1.max(l);
            r.2 += count;
        }
    }

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

    /// The chain of inlining with the most instructions and its share of this
    /// function's.
    #[must_use]
    pub fn main_caller(&self) -> Option<(&str, f64)> {
        self.callers
            .iter()
            .max_by(|a, b| a.1.cmp(b.1).then_with(|| b.0.cmp(a.0)))
            .map(|(n, c)| (n.as_str(), *c as f64 / self.count.max(1) as f64))
    }
}

/// The frames of every instruction of `insns` (innermost first), in order.
#[must_use]
pub fn attribute(sym: &Symbolizer, insns: &[Insn]) -> Vec<Vec<Frame>> {
    insns.iter().map(|i| sym.frames(i.pc)).collect()
}

fn sorted(map: HashMap<String, FunctionCost>) -> Vec<FunctionCost> {
    let mut v: Vec<FunctionCost> = map.into_values().collect();
    v.sort_by(|a, b| b.count.cmp(&a.count).then_with(|| a.name.cmp(&b.name)));
    v
}

/// Self cost: `insns` (with their `frames` and `costs`) added up per innermost
/// function, most instructions first.
#[must_use]
pub fn by_function(frames: &[Vec<Frame>], insns: &[Insn], costs: &[Cost]) -> Vec<FunctionCost> {
    let mut map: HashMap<String, FunctionCost> = HashMap::new();
    for ((i, c), fr) in insns.iter().zip(costs).zip(frames) {
        if !fr.is_empty() {
            charge(&mut map, fr, 0, i, c);
        }
    }
    sorted(map)
}

/// Inclusive cost: `insns` added up for every function on their chain of
/// inlining (the function, and all the code inlined into it, down to the
/// out-of-line function executing them; not what it calls out of line). A
/// function that appears twice on a chain counts once. Most instructions first.
#[must_use]
pub fn inclusive(frames: &[Vec<Frame>], insns: &[Insn], costs: &[Cost]) -> Vec<FunctionCost> {
    let mut map: HashMap<String, FunctionCost> = HashMap::new();
    for ((i, c), fr) in insns.iter().zip(costs).zip(frames) {
        let mut seen: Vec<&str> = Vec::new();
        for (k, f) in fr.iter().enumerate() {
            if seen.contains(&f.function.as_str()) {
                continue;
            }
            seen.push(&f.function);
            charge(&mut map, fr, k, i, c);
        }
    }
    sorted(map)
}

/// Charges instruction `i` (cost `c`) to frame `k` of its inlining chain `fr`, and
/// to that frame's callers (the next frames of the chain, up to [`CHAIN`]).
fn charge(map: &mut HashMap<String, FunctionCost>, fr: &[Frame], k: usize, i: &Insn, c: &Cost) {
    let Some(f) = fr.get(k) else { return };
    let chain: Vec<&str> = fr
        .iter()
        .skip(k + 1)
        .take(CHAIN)
        .map(|f| f.function.as_str())
        .collect();
    let e = map
        .entry(f.function.clone())
        .or_insert_with(|| FunctionCost::new(&f.function));
    e.add(i.count, c.cycles(), f);
    *e.callers.entry(chain.join(" < ")).or_default() += i.count;
}

/// A function name for tables: module paths dropped in front of types
/// (`geometry::sphere::Sphere::roots` -> `Sphere::roots`, `<core::slice::iter::Iter<T>
/// as core::iter::traits::iterator::Iterator>::next` -> `<Iter<T> as Iterator>::next`),
/// an inherent impl block named by its type (`shade::<impl scene::SceneView>::trace`
/// -> `SceneView::trace`), and free functions kept with their module
/// (`tessera_core::math::max` -> `math::max`).
#[must_use]
pub fn short_name(name: &str) -> String {
    let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
    let chars: Vec<char> = name.chars().collect();
    let mut out = String::new();
    let mut i = 0;
    while i < chars.len() {
        if !ident(chars[i]) {
            out.push(chars[i]);
            i += 1;
            continue;
        }
        // A path: ident(::ident)*.
        let mut segs = Vec::new();
        loop {
            let start = i;
            while i < chars.len() && ident(chars[i]) {
                i += 1;
            }
            segs.push(chars[start..i].iter().collect::<String>());
            let more = chars.get(i) == Some(&':')
                && chars.get(i + 1) == Some(&':')
                && chars.get(i + 2).is_some_and(|&c| ident(c));
            if !more {
                break;
            }
            i += 2;
        }
        let first_type = segs
            .iter()
            .position(|s| s.starts_with(|c: char| c.is_ascii_uppercase()));
        let keep = match first_type {
            Some(t) => &segs[t..],
            None => &segs[segs.len().saturating_sub(2)..],
        };
        out.push_str(&keep.join("::"));
    }
    // `module::<impl Type>::f` -> `Type::f`.
    while let Some(at) = out.find("<impl ") {
        let mut depth = 0;
        let mut end = None;
        for (k, c) in out[at..].char_indices() {
            match c {
                '<' => depth += 1,
                '>' => {
                    depth -= 1;
                    if depth == 0 {
                        end = Some(at + k);
                        break;
                    }
                }
                _ => {}
            }
        }
        let Some(end) = end else { break };
        let ty = out[at + "<impl ".len()..end].to_string();
        let before = out[..at].strip_suffix("::").unwrap_or(&out[..at]);
        let module_start = before
            .rfind(|c: char| !(c.is_ascii_alphanumeric() || c == '_' || c == ':'))
            .map_or(0, |k| k + 1);
        out = format!("{}{ty}{}", &out[..module_start], &out[end + 1..]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::short_name;

    #[test]
    fn short_names() {
        for (long, short) in [
            ("geometry::sphere::Sphere::roots", "Sphere::roots"),
            ("tessera_core::math::max", "math::max"),
            ("shade::nearest_in", "shade::nearest_in"),
            (
                "<geometry::sphere::Sphere as geometry::Shape>::intersect",
                "<Sphere as Shape>::intersect",
            ),
            (
                "<core::slice::iter::Iter<T> as core::iter::traits::iterator::Iterator>::next",
                "<Iter<T> as Iterator>::next",
            ),
            (
                "tessera_core::shade::<impl tessera_core::scene::SceneView>::trace_footprint",
                "SceneView::trace_footprint",
            ),
            (
                "heapless::vec::VecInner<T,LenT,S>::pop",
                "VecInner<T,LenT,S>::pop",
            ),
            (
                "tessera_fw::render_tiles::{{closure}}",
                "tessera_fw::render_tiles::{{closure}}",
            ),
            ("<f32>::clamp", "<f32>::clamp"),
            (
                "rayon::iter::plumbing::bridge_producer_consumer::helper'2",
                "bridge_producer_consumer::helper'2",
            ),
        ] {
            assert_eq!(short_name(long), short, "{long}");
        }
    }
}
