//! Instruction profiles of the firmware: the qemu plugin `tests/profiler/insn_profile.c`
//! counts, per guest PC, the executions of each instruction and how often the next
//! one executed was not `pc + size` (a taken branch), between the two marker
//! functions of the firmware (`tessera_profile_begin` / `tessera_profile_end`,
//! called around each `render_tile`).
//!
//! [`build_plugin`] compiles the plugin with the system's C compiler, [`markers`]
//! finds the markers in the ELF's symbol table, [`run`] runs one render under qemu
//! with the plugin ([`run_on`] on another core than the Cortex-M4F) and returns the
//! firmware's own result (with the SysTick count) and the profile, and
//! [`check_total`] checks the two counts against each other ([`agree`]).

use crate::cycles::Insn;
use crate::firmware::{self, Core, Run, RunResult, TempDir};
use std::path::{Path, PathBuf};
use std::process::Command;

/// The plugin's source, relative to the repository root.
pub const PLUGIN_SOURCE: &str = "tests/profiler/insn_profile.c";
/// The symbol of the marker called before each `render_tile`.
pub const BEGIN: &str = "tessera_profile_begin";
/// The symbol of the marker called after each `render_tile`.
pub const END: &str = "tessera_profile_end";
/// The largest difference allowed between the SysTick count and the plugin's
/// count, per tile: SysTick counts in steps of 40 instructions (so its count of a
/// tile is off by less than 40 either way), and between its two reads it also
/// counts about 20 instructions that the plugin does not (the end of the first
/// clock read, the `bl` to the begin marker, the end marker's body, the start of
/// the second read): SysTick - plugin lies between about -20 and +60 a tile.
pub const TOLERANCE_PER_TILE: u64 = 80;

/// Compiles the plugin into `target/profiler/insn_profile.so` (every time: it is
/// one small C file) with `gcc -shared -fPIC -O2 -Wall -Wextra
/// -Werror` (or `$CC` when set) and returns the library's path.
pub fn build_plugin() -> Result<PathBuf, String> {
    build_plugin_from(PLUGIN_SOURCE)
}

/// Compiles the qemu plugin `source` (a C file, relative to the repository root)
/// as [`build_plugin`] does, into `target/profiler/<its name>.so`, and returns the
/// library's path.
pub fn build_plugin_from(source: &str) -> Result<PathBuf, String> {
    let root = firmware::repo_root();
    let src = root.join(source);
    let dir = root.join("target").join("profiler");
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let stem = src
        .file_stem()
        .ok_or_else(|| format!("{source} names no file"))?;
    let out = dir.join(stem).with_extension("so");
    // `$CC`, else gcc, else `cc` (the C compiler Rust's host builds link with,
    // so a machine that builds these tests has it).
    let cc = std::env::var("CC").unwrap_or_else(|_| {
        let gcc = Command::new("gcc").arg("--version").output();
        if gcc.is_ok_and(|o| o.status.success()) {
            "gcc".into()
        } else {
            "cc".into()
        }
    });
    firmware::checked(
        Command::new(&cc)
            .args([
                "-shared", "-fPIC", "-O2", "-Wall", "-Wextra", "-Werror", "-o",
            ])
            .arg(&out)
            .arg(&src),
        &format!("{cc} to build the qemu plugin"),
        &format!("{cc} failed to build {source}"),
    )?;
    Ok(out)
}

/// The addresses of the two marker functions (Thumb bit cleared).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Markers {
    /// `tessera_profile_begin`.
    pub begin: u64,
    /// `tessera_profile_end`.
    pub end: u64,
}

/// Finds the markers in the symbol table of `elf`.
pub fn markers(elf: &Path) -> Result<Markers, String> {
    use object::{Object, ObjectSymbol};
    let bytes = std::fs::read(elf).map_err(|e| format!("cannot read {}: {e}", elf.display()))?;
    let file = object::File::parse(&*bytes)
        .map_err(|e| format!("{} is not an object file: {e}", elf.display()))?;
    let find = |name: &str| {
        file.symbols()
            .find(|s| s.name() == Ok(name))
            .map(|s| s.address() & !1)
            .ok_or_else(|| format!("no symbol {name} in {}", elf.display()))
    };
    let m = Markers {
        begin: find(BEGIN)?,
        end: find(END)?,
    };
    if m.begin == m.end {
        return Err(format!(
            "{BEGIN} and {END} share the address {:#x}: the compiler merged them",
            m.begin
        ));
    }
    Ok(m)
}

/// A profile written by the plugin.
#[derive(Clone, Debug, Default)]
pub struct Profile {
    /// One entry per executed PC, by address.
    pub insns: Vec<Insn>,
    /// How often the plugin was armed (the begin marker executed).
    pub arms: u64,
    /// Instructions counted.
    pub total: u64,
}

impl Profile {
    /// Parses the plugin's output; checks its header (no nested arming, disarmed
    /// at exit, the total equal to the sum of the counts).
    pub fn parse(text: &str) -> Result<Self, String> {
        let mut p = Profile::default();
        let mut header = None;
        for (n, line) in text.lines().enumerate() {
            if let Some(h) = line.strip_prefix("# arms=") {
                header = Some(format!("arms={h}"));
                continue;
            }
            if line.starts_with('#') || line.trim().is_empty() {
                continue;
            }
            let bad = || format!("profile line {}: {line:?}", n + 1);
            let mut f = line.splitn(5, ' ');
            let mut next = || f.next().ok_or_else(bad);
            let pc =
                u64::from_str_radix(next()?.trim_start_matches("0x"), 16).map_err(|_| bad())?;
            let count = next()?.parse().map_err(|_| bad())?;
            let taken = next()?.parse().map_err(|_| bad())?;
            let size = next()?.parse().map_err(|_| bad())?;
            let disas = next().unwrap_or_default().trim().to_string();
            p.insns.push(Insn {
                pc,
                count,
                taken,
                size,
                disas,
            });
        }
        let header = header.ok_or("the profile has no `# arms=` header (did qemu exit early?)")?;
        let value = |key: &str| -> Result<u64, String> {
            header
                .split_whitespace()
                .find_map(|w| w.strip_prefix(key)?.strip_prefix('='))
                .and_then(|v| v.parse().ok())
                .ok_or_else(|| format!("no {key}= in the profile header {header:?}"))
        };
        p.arms = value("arms")?;
        p.total = value("total")?;
        if value("rearms")? != 0 || value("armed_at_exit")? != 0 {
            return Err(format!("the markers did not alternate (header {header:?})"));
        }
        let sum: u64 = p.insns.iter().map(|i| i.count).sum();
        if sum != p.total {
            return Err(format!(
                "the profile's counts add up to {sum}, its header says {}",
                p.total
            ));
        }
        Ok(p)
    }
}

/// Runs `run` on `elf` under qemu with the plugin `plugin` armed by `markers`;
/// returns the firmware's result (SysTick count, pixels) and the profile. The
/// plugin does not change what the guest executes: the SysTick count is the one
/// of a run without it.
pub fn run(
    elf: &Path,
    plugin: &Path,
    markers: Markers,
    run: &Run,
) -> Result<(RunResult, Profile), String> {
    run_on(&firmware::CORTEX_M4F, elf, plugin, markers, run)
}

/// [`run`] on `core`'s firmware `elf`.
pub fn run_on(
    core: &Core,
    elf: &Path,
    plugin: &Path,
    markers: Markers,
    run: &Run,
) -> Result<(RunResult, Profile), String> {
    let dir = TempDir::new()?;
    let out = dir.path().join("profile.txt");
    let arg = plugin_arg(plugin, markers, &out)?;
    let output = core.run_with(elf, std::slice::from_ref(run), &["-plugin".into(), arg])?;
    let text = std::fs::read_to_string(&out)
        .map_err(|e| format!("the plugin wrote no profile ({}): {e}", out.display()))?;
    let profile = Profile::parse(&text).map_err(|e| format!("{run}: {e}"))?;
    let result = output
        .runs
        .into_iter()
        .next()
        .ok_or_else(|| format!("{run}: no result"))?;
    Ok((result, profile))
}

/// The argument of qemu's `-plugin` for one of the repository's plugins
/// (`tests/profiler/plugin.h`): `plugin`, the markers, and the file it writes.
///
/// # Errors
/// When a path holds a comma, which qemu's option syntax cannot carry.
pub fn plugin_arg(plugin: &Path, markers: Markers, out: &Path) -> Result<String, String> {
    let arg = format!(
        "{},begin={:#x},end={:#x},out={}",
        plugin.display(),
        markers.begin,
        markers.end,
        out.display()
    );
    if plugin.display().to_string().contains(',') || out.display().to_string().contains(',') {
        return Err(format!(
            "qemu's -plugin cannot take a path with a comma: {arg}"
        ));
    }
    Ok(arg)
}

/// Tiles of `run`.
#[must_use]
pub fn tiles(run: &Run) -> u64 {
    let t = run.tile as u64;
    u64::from(run.width).div_ceil(t) * u64::from(run.height).div_ceil(t)
}

/// Checks the plugin's profile against the SysTick count of the same run: the
/// plugin must have been armed once per tile, and the counts must [`agree`].
/// Returns SysTick minus plugin.
pub fn check_total(run: &Run, systick: &RunResult, profile: &Profile) -> Result<i64, String> {
    let tiles = tiles(run);
    if profile.arms != tiles {
        return Err(format!(
            "{run}: the plugin was armed {} times for {tiles} tiles",
            profile.arms
        ));
    }
    agree(run, systick.instructions, profile.total)
}

/// Checks that the SysTick count `systick` and the plugin's count `plugin` of
/// `run` agree within [`TOLERANCE_PER_TILE`] per tile. Returns SysTick minus
/// plugin.
pub fn agree(run: &Run, systick: u64, plugin: u64) -> Result<i64, String> {
    let tiles = tiles(run);
    let diff = systick as i64 - plugin as i64;
    if diff.unsigned_abs() > TOLERANCE_PER_TILE * tiles {
        return Err(format!(
            "{run}: SysTick counted {systick} instructions, the plugin {plugin}: {diff} \
             apart, more than the {} allowed ({TOLERANCE_PER_TILE} a tile)",
            TOLERANCE_PER_TILE * tiles
        ));
    }
    Ok(diff)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_the_plugin_output() {
        let text = "# insn_profile begin=0x8754 end=0x875a\n\
                    # arms=16 rearms=0 armed_at_exit=0 total=26 pcs=2\n\
                    # pc count taken size disassembly\n\
                    0x3950 16 0 4 ldrh.w r1, [sp, #0xca]\n\
                    0x3954 10 9 2 bne #0x3950\n";
        let p = Profile::parse(text).unwrap();
        assert_eq!((p.arms, p.total, p.insns.len()), (16, 26, 2));
        assert_eq!(p.insns[0].disas, "ldrh.w r1, [sp, #0xca]");
        assert_eq!(
            (p.insns[1].pc, p.insns[1].taken, p.insns[1].size),
            (0x3954, 9, 2)
        );
        assert!(Profile::parse(&text.replace("total=26", "total=27")).is_err());
        assert!(Profile::parse(&text.replace("rearms=0", "rearms=1")).is_err());
        assert!(Profile::parse("0x10 1 0 2 nop\n").is_err());
    }

    #[test]
    fn counts_agree_within_the_tolerance_per_tile() {
        // 64x64 in tiles of 16: 16 tiles, 1,280 instructions allowed either way.
        let run = Run::of(tessera_core::builtin::Builtin::ChapterDirect, 64, 64);
        assert_eq!(tiles(&run), 16);
        assert_eq!(agree(&run, 101_280, 100_000), Ok(1280));
        assert_eq!(agree(&run, 100_000, 101_280), Ok(-1280));
        assert!(agree(&run, 101_281, 100_000).is_err());
        assert!(agree(&run, 100_000, 101_281).is_err());
        let profile = Profile {
            arms: 15,
            total: 100_000,
            ..Profile::default()
        };
        let systick = RunResult {
            pixels: image::RgbImage::new(64, 64),
            ticks: 2_500,
            instructions: 100_000,
            pixels_count: 64 * 64,
            stack: 0,
            stack_base: 0,
            stack_render: 0,
            setup: None,
        };
        // Armed once short of a tile: refused though the totals agree.
        assert!(check_total(&run, &systick, &profile).is_err());
        let profile = Profile {
            arms: 16,
            ..profile
        };
        assert_eq!(check_total(&run, &systick, &profile), Ok(0));
    }
}
