//! The dual-core firmware image (`tests/dualcore`, package `tessera-dualcore`):
//! every built-in scene rendered by CPU 0 of qemu's `mps2-an521` (SSE-200, two
//! Cortex-M33) alone, then by both CPUs sharing the tiles; building it, running it
//! under qemu with the plugin `tests/profiler/vcpu_count.c`, which counts each
//! vCPU's instructions in its tile loop, and reading back the frames, which CPU
//! rendered which tile and the counts.
//!
//! The firmware's protocol is described in `tests/dualcore/src/main.rs`: the file
//! `dualcore-<scene>-<cores>.rgb` per frame, a `frame ...` line per frame, then
//! `core1 stack=...` and `done frames=<n>`.

use crate::firmware::{self, Core, TempDir, field, number};
use crate::profile;
use image::RgbImage;
use std::path::{Path, PathBuf};
use tessera_core::builtin::Builtin;

/// The firmware's target.
pub const TARGET: &str = "thumbv8m.main-none-eabihf";
/// The firmware's frames, pixels (square).
pub const SIZE: u16 = 64;
/// Its tile size.
pub const TILE: usize = 16;
/// The plugin counting each vCPU's instructions, relative to the repository root.
pub const PLUGIN_SOURCE: &str = "tests/profiler/vcpu_count.c";

/// Both CPUs of qemu's `mps2-an521`, CPU 0 given the FPU and DSP extension that
/// qemu leaves off by default (both cores of an RP2350 have them). The board's
/// memory map is the AN505's: the `mps2-an505` firmware's tick rate applies.
pub const DUAL_M33: Core = Core {
    name: "dual-cortex-m33",
    title: "two Cortex-M33 (mps2-an521)",
    target: TARGET,
    rustflags: &[],
    board: "mps2-an521",
    board_features: &[],
    qemu: firmware::QEMU,
    qemu_args: &[
        "-machine",
        "mps2-an521",
        "-cpu",
        "cortex-m33",
        "-nographic",
        "-semihosting-config",
        "enable=on,target=native",
        "-icount",
        "shift=0",
        "-global",
        "sse-200.CPU0_FPU=true",
        "-global",
        "sse-200.CPU0_DSP=true",
        "-kernel",
    ],
    tick: firmware::MPS2_AN505,
};

/// The firmware crate's folder (`tests/dualcore`).
#[must_use]
pub fn dir() -> PathBuf {
    firmware::repo_root().join("tests").join("dualcore")
}

/// Builds the firmware (release) into `tests/dualcore/target` and returns the
/// ELF's path.
pub fn build() -> Result<PathBuf, String> {
    let dir = dir();
    DUAL_M33.build_elf(
        &dir.join("Cargo.toml"),
        &dir.join("target"),
        &[],
        "tessera-dualcore",
        "the dual-core firmware",
    )
}

/// Compiles the plugin into `target/profiler/vcpu_count.so`.
pub fn build_plugin() -> Result<PathBuf, String> {
    profile::build_plugin_from(PLUGIN_SOURCE)
}

/// One frame the firmware rendered.
#[derive(Clone, Debug)]
pub struct Frame {
    /// The scene.
    pub scene: Builtin,
    /// How many CPUs rendered it (1 or 2).
    pub cores: u32,
    /// Its pixels.
    pub pixels: RgbImage,
    /// Per tile, row-major: the CPU that rendered it (0 or 1).
    pub owners: Vec<u8>,
    /// Tiles each CPU rendered.
    pub tiles: [u64; 2],
}

/// One vCPU's tile loop of one frame, as the plugin counted it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Span {
    /// Its instructions.
    pub insns: u64,
    /// Of those, the ones executed while the other vCPU's tile loop ran too.
    pub shared: u64,
}

/// A scene's counts: its frame on CPU 0 alone and its frame on both CPUs.
#[derive(Clone, Copy, Debug)]
pub struct SceneCounts {
    /// The scene.
    pub scene: Builtin,
    /// CPU 0's tile loop when it rendered the frame alone.
    pub one_core: u64,
    /// Each CPU's tile loop when both rendered the frame.
    pub dual: [Span; 2],
    /// Tiles each CPU rendered when both did.
    pub tiles: [u64; 2],
}

impl SceneCounts {
    /// One CPU's instructions for the frame over the busier CPU's when two share
    /// it: the frame's speed-up on two cores at one clock.
    #[must_use]
    pub fn speedup(&self) -> f64 {
        let busier = self.dual[0].insns.max(self.dual[1].insns);
        self.one_core as f64 / busier.max(1) as f64
    }
}

/// Everything one run of the firmware reported.
#[derive(Clone, Debug)]
pub struct Output {
    /// The frames, in the order rendered.
    pub frames: Vec<Frame>,
    /// Each scene's counts, in the order rendered.
    pub counts: Vec<SceneCounts>,
    /// The scheduling quantum (CPU 0's SysTick period), instructions.
    pub quantum: u64,
    /// CPU 1's peak stack, bytes.
    pub core1_stack: u64,
    /// The plugin's output.
    pub profile: String,
    /// qemu's standard output.
    pub stdout: String,
}

/// The host build of the core's frame of `b`: the scene built in RAM, its own
/// settings, the firmware's size and tiles (what both cores' pixels must equal).
pub fn host(b: Builtin) -> Result<RgbImage, String> {
    let vp = tessera_core::Viewport::new(SIZE, SIZE);
    b.with_scene(|view, cam| tessera_host::render(view, cam, vp, b.settings(), TILE))
        .map_err(|e| format!("{}: {e}", b.name()))?
        .map_err(|e| format!("{}: {e}", b.name()))
}

/// Runs the firmware `elf` under qemu with the plugin `plugin` and reads back what
/// it wrote.
pub fn run(elf: &Path, plugin: &Path) -> Result<Output, String> {
    let markers = profile::markers(elf)?;
    let dir = TempDir::new()?;
    let counts = dir.path().join("counts.txt");
    let arg = profile::plugin_arg(plugin, markers, &counts)?;
    let stdout = DUAL_M33.run_in(dir.path(), elf, &["-plugin".into(), arg])?;
    let profile = std::fs::read_to_string(&counts)
        .map_err(|e| format!("the plugin wrote no counts ({}): {e}", counts.display()))?;
    parse(&stdout, &profile, dir.path())
        .map_err(|e| format!("{e}\n--- qemu stdout\n{stdout}--- plugin\n{profile}"))
}

/// Reads the firmware's output `stdout`, its frame files in `dir` and the
/// plugin's output `profile`.
fn parse(stdout: &str, profile: &str, dir: &Path) -> Result<Output, String> {
    let line = |prefix: &str| {
        stdout
            .lines()
            .find(|l| l.starts_with(prefix))
            .ok_or_else(|| format!("no `{prefix}` line"))
    };
    let mut frames = Vec::new();
    for l in stdout.lines().filter(|l| l.starts_with("frame ")) {
        frames.push(frame(l, dir)?);
    }
    let done = number(line("done ")?, "frames")?;
    if done != frames.len() as u64 || frames.is_empty() {
        return Err(format!("{done} frames done, {} reported", frames.len()));
    }
    let counts = scene_counts(&frames, profile)?;
    Ok(Output {
        frames,
        counts,
        quantum: number(line("quantum ")?, "instructions")?,
        core1_stack: number(line("core1 ")?, "stack")?,
        profile: profile.to_string(),
        stdout: stdout.to_string(),
    })
}

/// One `frame ...` line and its file.
fn frame(l: &str, dir: &Path) -> Result<Frame, String> {
    let name = field(l, "scene")?;
    let scene = Builtin::from_name(name).ok_or_else(|| format!("unknown scene in {l:?}"))?;
    let cores = number(l, "cores")? as u32;
    let owners: Vec<u8> = field(l, "owners")?
        .bytes()
        .map(|b| b.wrapping_sub(b'0'))
        .collect();
    let n = usize::from(SIZE).div_ceil(TILE).pow(2);
    if owners.len() != n || owners.iter().any(|&o| o > 1) || number(l, "tiles")? != n as u64 {
        return Err(format!("{n} tiles of CPU 0 or 1 expected in {l:?}"));
    }
    let tiles = [number(l, "core0")?, number(l, "core1")?];
    for (cpu, &t) in tiles.iter().enumerate() {
        let owned = owners.iter().filter(|&&o| usize::from(o) == cpu).count() as u64;
        if owned != t {
            return Err(format!("CPU {cpu}: {t} tiles but {owned} owned in {l:?}"));
        }
    }
    let file = format!("dualcore-{name}-{cores}.rgb");
    let bytes = std::fs::read(dir.join(&file)).map_err(|e| format!("cannot read {file}: {e}"))?;
    let fnv = u64::from_str_radix(field(l, "fnv")?, 16).map_err(|_| format!("bad fnv in {l:?}"))?;
    if fnv1a64(&bytes) != fnv {
        return Err(format!("{file} is not the frame the firmware hashed"));
    }
    let len = bytes.len();
    let side = u32::from(SIZE);
    let pixels = RgbImage::from_raw(side, side, bytes)
        .filter(|_| len == (side * side * 3) as usize)
        .ok_or_else(|| format!("{file} is {len} bytes, not {side}x{side}x3"))?;
    Ok(Frame {
        scene,
        cores,
        pixels,
        owners,
        tiles,
    })
}

/// FNV-1a, 64 bits (the firmware's).
#[must_use]
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// Matches the plugin's spans with the frames: each vCPU's spans close in the
/// order of its frames (CPU 0 has one per frame, CPU 1 one per two-core frame).
/// Checks the plugin's header lines (every arming closed, none nested).
fn scene_counts(frames: &[Frame], profile: &str) -> Result<Vec<SceneCounts>, String> {
    let mut spans: [Vec<Span>; 2] = [Vec::new(), Vec::new()];
    for l in profile.lines() {
        if let Some(rest) = l.strip_prefix("span ") {
            let vcpu = number(rest, "vcpu")?;
            let list = spans
                .get_mut(vcpu as usize)
                .ok_or_else(|| format!("a span of vCPU {vcpu}"))?;
            list.push(Span {
                insns: number(rest, "insns")?,
                shared: number(rest, "shared")?,
            });
        } else if l.starts_with("vcpu=")
            && (number(l, "rearms")? != 0 || number(l, "armed_at_exit")? != 0)
        {
            return Err(format!("the markers did not alternate: {l:?}"));
        }
    }
    let dual = frames.iter().filter(|f| f.cores == 2).count();
    if spans[0].len() != frames.len() || spans[1].len() != dual {
        return Err(format!(
            "{} and {} spans for {} frames, {dual} of them on two cores",
            spans[0].len(),
            spans[1].len(),
            frames.len()
        ));
    }
    let (mut cpu0, mut cpu1) = (spans[0].iter(), spans[1].iter());
    let mut one = Vec::new();
    let mut out = Vec::new();
    for f in frames {
        let s0 = *cpu0.next().ok_or("too few spans of vCPU 0")?;
        match f.cores {
            1 => one.push((f.scene, s0.insns)),
            2 => {
                let s1 = *cpu1.next().ok_or("too few spans of vCPU 1")?;
                let one_core = one
                    .iter()
                    .find(|(b, _)| *b == f.scene)
                    .map(|&(_, n)| n)
                    .ok_or_else(|| format!("{} has no one-core frame", f.scene.name()))?;
                out.push(SceneCounts {
                    scene: f.scene,
                    one_core,
                    dual: [s0, s1],
                    tiles: f.tiles,
                });
            }
            n => return Err(format!("a frame on {n} cores")),
        }
    }
    Ok(out)
}

/// The speed-up table: per scene, CPU 0's instructions alone, each CPU's with two,
/// the tiles each rendered, and the speed-up.
#[must_use]
pub fn table(counts: &[SceneCounts]) -> String {
    let mut t = String::from(
        "| scene | one core | two cores: CPU 0 | CPU 1 | tiles (CPU 0/1) | speed-up |\n\
         |-------|---------:|-----------------:|------:|:---------------:|---------:|\n",
    );
    for c in counts {
        t.push_str(&format!(
            "| {} | {} | {} | {} | {}/{} | {:.3} |\n",
            c.scene.name(),
            c.one_core,
            c.dual[0].insns,
            c.dual[1].insns,
            c.tiles[0],
            c.tiles[1],
            c.speedup()
        ));
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fnv_is_the_reference_one() {
        assert_eq!(fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a64(b"a"), 0xaf63_dc4c_8601_ec8c);
    }

    #[test]
    fn spans_go_to_their_frames() {
        let frame = |scene, cores| Frame {
            scene,
            cores,
            pixels: RgbImage::new(1, 1),
            owners: Vec::new(),
            tiles: [3, 1],
        };
        let frames = [
            frame(Builtin::ChapterDirect, 1),
            frame(Builtin::Showcase, 1),
            frame(Builtin::ChapterDirect, 2),
            frame(Builtin::Showcase, 2),
        ];
        let profile = "# vcpu_count begin=0x10 end=0x20\n\
             vcpu=0 arms=4 rearms=0 armed_at_exit=0 spans=4 counted=1 executed=1 switches=1\n\
             vcpu=1 arms=2 rearms=0 armed_at_exit=0 spans=2 counted=1 executed=1 switches=1\n\
             span vcpu=0 insns=100 shared=0\n\
             span vcpu=0 insns=900 shared=0\n\
             span vcpu=1 insns=52 shared=50\n\
             span vcpu=0 insns=51 shared=51\n\
             span vcpu=0 insns=470 shared=460\n\
             span vcpu=1 insns=460 shared=460\n";
        let c = scene_counts(&frames, profile).unwrap();
        assert_eq!(c.len(), 2);
        assert_eq!((c[0].scene, c[0].one_core), (Builtin::ChapterDirect, 100));
        assert_eq!(c[0].dual[0].insns, 51);
        assert_eq!(
            c[0].dual[1],
            Span {
                insns: 52,
                shared: 50
            }
        );
        assert!((c[0].speedup() - 100.0 / 52.0).abs() < 1e-12);
        assert_eq!(
            (c[1].one_core, c[1].dual[0].insns, c[1].dual[1].insns),
            (900, 470, 460)
        );
        // A span short, or a nested arming: refused.
        let short: String = profile.lines().take(8).map(|l| format!("{l}\n")).collect();
        assert!(scene_counts(&frames, &short).is_err());
        assert!(scene_counts(&frames, &profile.replace("rearms=0", "rearms=1")).is_err());
    }
}
