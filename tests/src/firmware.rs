//! The firmware test image (`tests/firmware`, package `tessera-fw`): building it for
//! a core ([`Core`]: the Cortex-M4F on qemu's `mps2-an386` board, [`CORTEX_M4F`],
//! and the other cores with an FPU, [`FPU_CORES`]) and running it under qemu.
//!
//! Protocol: [`run`] writes the run list to `tessera-fw.runs` in a fresh temporary
//! folder, one [`Run`] per line (`<scene>[@k] <sampler> <depth> <tile> <width>
//! <height> <seed>`), starts qemu there with semihosting and `-icount shift=0`, and reads
//! back what the firmware wrote: one result line per run on its standard output,
//! and for run `i` the file `tessera-fw-<i>.rgb`, the frame's pixels in row-major
//! image order, 3 bytes (R, G, B) each, no header. The firmware's side of it is
//! shared, not repeated: its file names, limits and tick rate
//! (`tests/firmware/src/protocol.rs`) and the run list's line ([`Run`] and
//! [`parse_run`], `tests/firmware/src/runs.rs`) are compiled into both.
//!
//! Instruction counts: with `-icount shift=0` a guest instruction takes 1 ns of
//! virtual time and SysTick (processor clock, 25 MHz on `mps2-an386`) ticks every
//! 40 instructions; the firmware counts ticks only inside `render_tile`, so
//! `instructions` is `ticks x 40`, exact to 40 instructions per tile, and
//! repeatable bit for bit. Each core's rate is its [`Core::tick`] (one tick is one
//! instruction on RISC-V, where the clock is the `minstret` CSR).

use image::RgbImage;
use std::io::ErrorKind;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

/// The file names, limits and tick rate the firmware and this harness agree on: the
/// firmware's own `tests/firmware/src/protocol.rs`, included here.
#[path = "../firmware/src/protocol.rs"]
mod protocol;
pub use protocol::*;

/// The Cortex-M4F firmware's target.
pub const TARGET: &str = "thumbv7em-none-eabihf";
/// The Arm emulator.
pub const QEMU: &str = "qemu-system-arm";
/// qemu's arguments before the ELF for the Cortex-M4F (the same as the runner in
/// `.cargo/config.toml`).
pub const QEMU_ARGS: [&str; 10] = [
    "-cpu",
    "cortex-m4",
    "-machine",
    "mps2-an386",
    "-nographic",
    "-semihosting-config",
    "enable=on,target=native",
    "-icount",
    "shift=0",
    "-kernel",
];
/// A qemu run taking longer than this is killed and reported as an error (a
/// firmware that faults into a loop, say, on a core without the instructions it
/// was built for).
pub const TIMEOUT: Duration = Duration::from_secs(300);
/// What to do when qemu or a target is missing.
pub const INSTALL_HINT: &str = "run `bash tests/run-all.sh`, which installs qemu-system-arm, \
     qemu-system-misc (qemu-system-riscv32) and the targets";

/// A core the firmware test image runs on: how to build it (Rust target, flags,
/// the board's feature of `tessera-fw`) and how qemu runs it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Core {
    /// Its name in reports and in the images' folders (`cortex-m7`).
    pub name: &'static str,
    /// Its name in prose (`Cortex-M7`).
    pub title: &'static str,
    /// The Rust target.
    pub target: &'static str,
    /// Flags for rustc (the CPU, where the target does not say it).
    pub rustflags: &'static [&'static str],
    /// The qemu board, also the name of its memory map `tests/firmware/memory/<board>.x`.
    pub board: &'static str,
    /// The features of `tessera-fw` that choose the board (see its build.rs).
    pub board_features: &'static [&'static str],
    /// The emulator.
    pub qemu: &'static str,
    /// qemu's arguments before the ELF, the last one `-kernel`.
    pub qemu_args: &'static [&'static str],
    /// Guest instructions per tick of the firmware's clock on the board.
    pub tick: TickRate,
}

/// The Cortex-M4F (`mps2-an386`): the reference core of the reports and of the
/// instruction-count baseline.
pub const CORTEX_M4F: Core = Core {
    name: "cortex-m4f",
    title: "Cortex-M4F",
    target: TARGET,
    rustflags: &[],
    board: "mps2-an386",
    board_features: &[],
    qemu: QEMU,
    qemu_args: &QEMU_ARGS,
    tick: MPS2_AN386,
};

/// The Cortex-M7 (`mps2-an500`): `thumbv7em-none-eabihf` for that CPU, whose FPU
/// LLVM takes as FPv5 with double precision (`vadd.f64` and the like in the image).
pub const CORTEX_M7: Core = Core {
    name: "cortex-m7",
    title: "Cortex-M7",
    target: "thumbv7em-none-eabihf",
    rustflags: &["-C", "target-cpu=cortex-m7"],
    board: "mps2-an500",
    board_features: &["mps2-an500"],
    qemu: QEMU,
    qemu_args: &[
        "-cpu",
        "cortex-m7",
        "-machine",
        "mps2-an500",
        "-nographic",
        "-semihosting-config",
        "enable=on,target=native",
        "-icount",
        "shift=0",
        "-kernel",
    ],
    tick: MPS2_AN500,
};

/// The Cortex-M33 (`mps2-an505`, booting in the secure state): Armv8-M Mainline
/// with its single-precision FPU (FPv5).
pub const CORTEX_M33: Core = Core {
    name: "cortex-m33",
    title: "Cortex-M33",
    target: "thumbv8m.main-none-eabihf",
    rustflags: &[],
    board: "mps2-an505",
    board_features: &[],
    qemu: QEMU,
    qemu_args: &[
        "-machine",
        "mps2-an505",
        "-nographic",
        "-semihosting-config",
        "enable=on,target=native",
        "-icount",
        "shift=0",
        "-kernel",
    ],
    tick: MPS2_AN505,
};

/// The Cortex-M55 (`mps3-an547`): Armv8.1-M for that CPU, whose FPU has double
/// precision and whose vector extension (MVE, Helium) LLVM may use.
pub const CORTEX_M55: Core = Core {
    name: "cortex-m55",
    title: "Cortex-M55",
    target: "thumbv8m.main-none-eabihf",
    rustflags: &["-C", "target-cpu=cortex-m55"],
    board: "mps3-an547",
    board_features: &["mps3-an547"],
    qemu: QEMU,
    qemu_args: &[
        "-machine",
        "mps3-an547",
        "-nographic",
        "-semihosting-config",
        "enable=on,target=native",
        "-icount",
        "shift=0",
        "-kernel",
    ],
    tick: MPS3_AN547,
};

/// An rv32imafc core (qemu's `virt` board, its default CPU, without firmware:
/// `-bios none`), single precision in hardware.
pub const RV32IMAFC: Core = Core {
    name: "rv32imafc",
    title: "rv32imafc",
    target: "riscv32imafc-unknown-none-elf",
    rustflags: &[],
    board: "riscv-virt",
    board_features: &[],
    qemu: "qemu-system-riscv32",
    qemu_args: &[
        "-machine",
        "virt",
        "-bios",
        "none",
        "-nographic",
        "-semihosting-config",
        "enable=on,target=native",
        "-icount",
        "shift=0",
        "-kernel",
    ],
    tick: RISCV_VIRT,
};

/// A Cortex-M0/M0+ (Armv6-M, no FPU: `thumbv6m-none-eabi`, floating point in
/// software), run on `mps2-an385`, whose Cortex-M3 executes the same Thumb code
/// (qemu has no Cortex-M0 board with enough memory): the instructions counted are
/// the Cortex-M0's, not their cycles.
pub const CORTEX_M0_ON_M3: Core = Core {
    name: "cortex-m0-on-m3",
    title: "Armv6-M (Cortex-M0/M0+)",
    target: "thumbv6m-none-eabi",
    rustflags: &[],
    board: "mps2-an385",
    board_features: &[],
    qemu: QEMU,
    qemu_args: &[
        "-cpu",
        "cortex-m3",
        "-machine",
        "mps2-an385",
        "-nographic",
        "-semihosting-config",
        "enable=on,target=native",
        "-icount",
        "shift=0",
        "-kernel",
    ],
    tick: MPS2_AN385,
};

/// An rv32imc core (no FPU: `riscv32imc-unknown-none-elf`, floating point in
/// software) on qemu's `virt` board, its CPU without the F and D extensions (an
/// F instruction traps).
pub const RV32IMC: Core = Core {
    name: "rv32imc",
    title: "rv32imc",
    target: "riscv32imc-unknown-none-elf",
    rustflags: &[],
    board: "riscv-virt",
    board_features: &[],
    qemu: "qemu-system-riscv32",
    qemu_args: &[
        "-machine",
        "virt",
        "-cpu",
        "rv32,f=false,d=false",
        "-bios",
        "none",
        "-nographic",
        "-semihosting-config",
        "enable=on,target=native",
        "-icount",
        "shift=0",
        "-kernel",
    ],
    tick: RISCV_VIRT,
};

/// The cores without an FPU.
pub const NOFPU_CORES: [Core; 2] = [CORTEX_M0_ON_M3, RV32IMC];

/// Every core with an FPU beside the Cortex-M4F.
pub const FPU_CORES: [Core; 4] = [CORTEX_M7, CORTEX_M33, CORTEX_M55, RV32IMAFC];

/// Every core the firmware runs on, the Cortex-M4F first.
pub const CORES: [Core; 5] = [CORTEX_M4F, CORTEX_M7, CORTEX_M33, CORTEX_M55, RV32IMAFC];

impl Core {
    /// The core's memory map, `tests/firmware/memory/<board>.x`.
    #[must_use]
    pub fn memory_map(&self) -> PathBuf {
        firmware_dir()
            .join("memory")
            .join(format!("{}.x", self.board))
    }

    /// The FLASH and RAM lengths of its memory map, bytes.
    pub fn memory_budget(&self) -> Result<(u64, u64), String> {
        memory_regions(&self.memory_map())
    }

    /// The first line of `<qemu> --version`, or an error saying how to install it.
    pub fn qemu_version(&self) -> Result<String, String> {
        tool_version(self.qemu)
    }

    /// Builds the firmware for this core with the core features `features` (as
    /// [`build`]) and returns the ELF's path. The Cortex-M4F's images keep their
    /// folders (`tests/firmware/target/<image name>`); another core's are
    /// `tests/firmware/target/<core>-<image name>`.
    pub fn build(&self, features: &[&str]) -> Result<PathBuf, String> {
        let backend = image_name(features)?;
        let folder = if *self == CORTEX_M4F {
            backend.clone()
        } else {
            format!("{}-{backend}", self.name)
        };
        let target_dir = firmware_dir().join("target").join(folder);
        let what = format!("the firmware for the {} ({backend})", self.title);
        let mut all: Vec<&str> = self.board_features.to_vec();
        all.extend_from_slice(features);
        self.build_elf(
            &firmware_dir().join("Cargo.toml"),
            &target_dir,
            &all,
            "tessera-fw",
            &what,
        )
    }

    /// Builds the binaries of the firmware crate `manifest` for this core (release,
    /// its target and flags, the crate's `features`) into `target_dir` and returns
    /// the path of the ELF of `bin`; `what` names it in errors. Cargo runs from the
    /// repository root so that the root `.cargo/config.toml` applies.
    pub fn build_elf(
        &self,
        manifest: &Path,
        target_dir: &Path,
        features: &[&str],
        bin: &str,
        what: &str,
    ) -> Result<PathBuf, String> {
        let mut cmd = cargo();
        cmd.current_dir(repo_root())
            .args(["build", "--release", "--target", self.target])
            .arg("--manifest-path")
            .arg(manifest)
            .arg("--target-dir")
            .arg(target_dir);
        if !features.is_empty() {
            cmd.arg("--features").arg(features.join(","));
        }
        if !self.rustflags.is_empty() {
            cmd.env("CARGO_ENCODED_RUSTFLAGS", self.rustflags.join("\x1f"));
        }
        let target = self.target;
        checked(
            &mut cmd,
            &format!("cargo to build {what}"),
            &format!("building {what} failed; is the {target} target installed? ({INSTALL_HINT})"),
        )?;
        let elf = target_dir.join(target).join("release").join(bin);
        if elf.is_file() {
            Ok(elf)
        } else {
            Err(format!(
                "the build of {what} left no ELF at {}",
                elf.display()
            ))
        }
    }

    /// Runs `runs` on this core's firmware `elf` under qemu (one qemu process for
    /// the whole list), as [`run`].
    pub fn run(&self, elf: &Path, runs: &[Run]) -> Result<Output, String> {
        self.run_with(elf, runs, &[])
    }

    /// [`Core::run`] with `extra` qemu arguments placed before `-kernel`.
    pub fn run_with(&self, elf: &Path, runs: &[Run], extra: &[String]) -> Result<Output, String> {
        let dir = TempDir::new()?;
        let list = write_run_list(&dir.0, runs)?;
        let (stdout, fail) = self.qemu(&dir.0, elf, extra, Some(&list))?;
        parse_output(&stdout, runs, &dir.0, self.tick).map_err(fail)
    }

    /// Runs an ELF that needs no run list and returns its standard output, as
    /// [`run_alone`].
    pub fn run_alone(&self, elf: &Path) -> Result<String, String> {
        let dir = TempDir::new()?;
        Ok(self.qemu(&dir.0, elf, &[], None)?.0)
    }

    /// Runs an ELF that needs no run list in the folder `dir`, where the files it
    /// writes over semihosting stay, with `extra` qemu arguments before `-kernel`
    /// (a `-plugin`, say), and returns its standard output, as [`run_alone`].
    pub fn run_in(&self, dir: &Path, elf: &Path, extra: &[String]) -> Result<String, String> {
        Ok(self.qemu(dir, elf, extra, None)?.0)
    }
}

/// The repository's root folder.
#[must_use]
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map_or_else(|| PathBuf::from(".."), Path::to_path_buf)
}

/// `p` relative to the repository root (as it is, if it is not under the root), for
/// the reports.
#[must_use]
pub fn repo_relative(p: &Path) -> String {
    let root = repo_root();
    let root = root.canonicalize().unwrap_or(root);
    let p = p.canonicalize().unwrap_or_else(|_| p.to_path_buf());
    p.strip_prefix(&root).unwrap_or(&p).display().to_string()
}

/// The firmware package's folder (`tests/firmware`).
#[must_use]
pub fn firmware_dir() -> PathBuf {
    repo_root().join("tests").join("firmware")
}

/// The first line of `qemu-system-arm --version`, or an error saying how to
/// install qemu.
pub fn qemu_version() -> Result<String, String> {
    tool_version(QEMU)
}

/// The first line of `<qemu> --version`, or an error saying how to install it.
fn tool_version(qemu: &str) -> Result<String, String> {
    match Command::new(qemu).arg("--version").output() {
        Ok(out) if out.status.success() => Ok(String::from_utf8_lossy(&out.stdout)
            .lines()
            .next()
            .unwrap_or("")
            .trim()
            .to_string()),
        Ok(out) => Err(format!(
            "`{qemu} --version` failed ({}): {INSTALL_HINT}",
            out.status
        )),
        Err(e) if e.kind() == ErrorKind::NotFound => {
            Err(format!("{qemu} is not installed: {INSTALL_HINT}"))
        }
        Err(e) => Err(format!("cannot run {qemu}: {e}; {INSTALL_HINT}")),
    }
}

/// Runs `cmd` to its end and returns its output; an error names `program` (what
/// could not be started) or says `failed` with the exit status and the command's
/// standard error.
pub fn checked(
    cmd: &mut Command,
    program: &str,
    failed: &str,
) -> Result<std::process::Output, String> {
    let out = cmd
        .output()
        .map_err(|e| format!("cannot run {program}: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "{failed} ({}):\n{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    Ok(out)
}

/// The name of the firmware image built with the core features `features`, and
/// of its target folder under `tests/firmware/target/`: `exact` without features,
/// else the features joined by `+` (`fast-math`, `fast-rsqrt+fast-pow`). An error
/// for a feature that is not a cargo feature name (letters, digits, `-`, `_`), so
/// that the name is a plain folder name.
pub fn image_name(features: &[&str]) -> Result<String, String> {
    for f in features {
        if f.is_empty()
            || !f
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
        {
            return Err(format!("{f:?} is not a cargo feature name"));
        }
    }
    Ok(if features.is_empty() {
        "exact".into()
    } else {
        features.join("+")
    })
}

/// Builds the Cortex-M4F firmware (release profile of `tests/firmware`) with the
/// core features `features` (features of `tessera-fw`, which forwards them to the
/// core: `&[]` is the exact math, `&["fast-math"]` the fast-math backend) and
/// returns the ELF's path. Each set of features has its own target folder under
/// `tests/firmware/target/` ([`image_name`]), so the images exist side by side.
/// Cargo runs from the repository root so that the root `.cargo/config.toml`
/// applies. [`Core::build`] builds for another core.
pub fn build(features: &[&str]) -> Result<PathBuf, String> {
    CORTEX_M4F.build(features)
}

/// A cargo command (the cargo running the tests, if any) without the
/// environment's build flags and folders: flags would change the code the figures
/// are of, a target folder from it would mix the images, and a build target from
/// it would override a firmware's own.
#[must_use]
pub fn cargo() -> Command {
    let mut cmd = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()));
    for var in [
        "RUSTFLAGS",
        "CARGO_ENCODED_RUSTFLAGS",
        "CARGO_BUILD_RUSTFLAGS",
        "CARGO_TARGET_DIR",
        "CARGO_BUILD_TARGET",
        "CARGO_BUILD_TARGET_DIR",
    ] {
        cmd.env_remove(var);
    }
    cmd
}

/// Builds the binaries of the firmware crate `manifest` (release, for [`TARGET`],
/// the crate's `features`) into `target_dir` and returns the path of the ELF of
/// `bin`; `what` names it in errors ([`Core::build_elf`] of the Cortex-M4F).
pub fn build_elf(
    manifest: &Path,
    target_dir: &Path,
    features: &[&str],
    bin: &str,
    what: &str,
) -> Result<PathBuf, String> {
    CORTEX_M4F.build_elf(manifest, target_dir, features, bin, what)
}

/// The square root's check (`tessera-sqrt`): its inputs and exact test, the
/// firmware's own `tests/firmware/src/sqrt_check.rs`, included here.
#[path = "../firmware/src/sqrt_check.rs"]
pub mod sqrt_check;

/// What `tessera-sqrt` reported: the number of inputs, how many roots were not
/// correctly rounded, and the hash of the results.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SqrtReport {
    /// Inputs checked.
    pub cases: u64,
    /// Results that were not correctly rounded.
    pub wrong: u64,
    /// FNV-1a of the results' bits ([`sqrt_check::hash`]).
    pub hash: u32,
}

impl SqrtReport {
    /// The host's: the core's `sqrt` built for this machine, on the same inputs.
    #[must_use]
    pub fn host() -> Self {
        let inputs = || sqrt_check::inputs();
        let wrong = inputs()
            .filter(|&x| !sqrt_check::correctly_rounded(x, tessera_core::testing::sqrt(x)))
            .count();
        Self {
            cases: inputs().count() as u64,
            wrong: wrong as u64,
            hash: sqrt_check::hash(inputs().map(tessera_core::testing::sqrt)),
        }
    }
}

/// Runs `tessera-sqrt` (beside `elf`, the core's `tessera-fw`) on `core` and reads
/// its report line.
pub fn check_sqrt(core: &Core, elf: &Path) -> Result<SqrtReport, String> {
    let sqrt = elf.with_file_name("tessera-sqrt");
    let out = core.run_alone(&sqrt)?;
    let line = out
        .lines()
        .find(|l| l.starts_with("sqrt cases="))
        .ok_or_else(|| format!("no `sqrt cases=` line from {}:\n{out}", sqrt.display()))?;
    let hash = field(line, "hash")?;
    Ok(SqrtReport {
        cases: number(line, "cases")?,
        wrong: number(line, "wrong")?,
        hash: u32::from_str_radix(hash, 16)
            .map_err(|_| format!("hash={hash} is not hexadecimal in {line:?}"))?,
    })
    .and_then(|r| {
        if r.wrong == 0 {
            Ok(r)
        } else {
            Err(format!("{} on the {}:\n{out}", line, core.title))
        }
    })
}

/// The run list's line, written here ([`Run`]'s `Display`) and read by the
/// firmware ([`parse_run`]): the firmware's own `tests/firmware/src/runs.rs`,
/// included here.
#[path = "../firmware/src/runs.rs"]
mod runs;
pub use runs::{Run, SceneRef, parse as parse_run};

impl SceneRef {
    /// The scene's own settings (a built-in scene's, or the defaults).
    #[must_use]
    pub fn settings(self) -> tessera_core::RenderSettings {
        match self {
            Self::Builtin(b) | Self::Baked(b) => b.settings(),
            Self::Extreme(_) => tessera_core::RenderSettings::default(),
        }
    }
}

impl Run {
    /// `scene` with its own settings, tiles of 16, `width x height`.
    #[must_use]
    pub fn of(scene: impl Into<SceneRef>, width: u16, height: u16) -> Self {
        let scene = scene.into();
        let s = scene.settings();
        Self {
            scene,
            sampler: s.sampler,
            depth: s.max_depth,
            tile: 16,
            width,
            height,
            seed: s.seed,
            scale: 0,
            encoding: s.encoding,
        }
    }
}

/// What the chip reported for one run.
#[derive(Clone, Debug)]
pub struct RunResult {
    /// The frame.
    pub pixels: RgbImage,
    /// Clock ticks inside `render_tile` (SysTick on Arm, `minstret` on RISC-V).
    pub ticks: u64,
    /// Guest instructions inside `render_tile`: `ticks x 40` on the Cortex-M4F,
    /// `ticks` at the core's [`Core::tick`] rate.
    pub instructions: u64,
    /// Pixels of the frame.
    pub pixels_count: u64,
    /// Peak stack of the firmware during the run, bytes from the top of RAM.
    pub stack: u64,
    /// Stack the harness itself used when the run started (its `main` frame); the
    /// difference `stack - stack_base` is the scene (built on the stack by
    /// `Builtin::with_scene`), the frame and the renderer.
    pub stack_base: u64,
    /// Peak stack below the tile loop's stack pointer: what `render_tile` needs.
    pub stack_render: u64,
    /// For a baked scene's run, the instructions of a frame's set-up.
    pub setup: Option<Setup>,
}

/// The instructions of a frame's set-up on a baked scene, as the firmware
/// measures them after the run: its whole view checked again with its camera
/// (`BakedScene::view`), and its lights, spheres and planes each handed to the
/// view as a frame's changed list (`SceneView::with_lights`, `with_list`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Setup {
    /// `BakedScene::view` and the camera.
    pub view: u64,
    /// `with_lights` of its lights.
    pub lights: u64,
    /// `with_list` of its spheres.
    pub spheres: u64,
    /// `with_list` of its planes.
    pub planes: u64,
}

impl RunResult {
    /// Instructions per pixel.
    #[must_use]
    pub fn instructions_per_pixel(&self) -> f64 {
        self.instructions as f64 / self.pixels_count.max(1) as f64
    }
}

/// Everything one qemu run reported.
#[derive(Clone, Debug)]
pub struct Output {
    /// One result per run, in order.
    pub runs: Vec<RunResult>,
    /// The largest `stack` over the runs, bytes.
    pub stack_peak: u64,
    /// Bytes between the end of the statics and the top of RAM.
    pub stack_available: u64,
    /// The calibration loop's instruction count (`2 x` its iterations).
    pub calibration_instructions: u64,
    /// The ticks the calibration loop took.
    pub calibration_ticks: u64,
    /// qemu's standard output.
    pub stdout: String,
}

/// A temporary folder, removed when dropped.
pub struct TempDir(PathBuf);

impl TempDir {
    /// Creates a fresh, empty folder under the system's temporary folder.
    pub fn new() -> Result<Self, String> {
        static COUNT: AtomicUsize = AtomicUsize::new(0);
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.subsec_nanos());
        let dir = std::env::temp_dir().join(format!(
            "tessera-fw-{}-{}-{nanos}",
            std::process::id(),
            COUNT.fetch_add(1, Ordering::Relaxed)
        ));
        std::fs::create_dir_all(&dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        Ok(Self(dir))
    }

    /// The folder.
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Runs `runs` on the Cortex-M4F firmware `elf` under qemu (one qemu process for
/// the whole list). A qemu failure, a timeout, an `error:`/`panic:` report or a
/// missing result is an `Err` carrying qemu's output.
pub fn run(elf: &Path, runs: &[Run]) -> Result<Output, String> {
    CORTEX_M4F.run(elf, runs)
}

/// [`run`] with `extra` qemu arguments placed before `-kernel` (a `-plugin`, say).
pub fn run_with(elf: &Path, runs: &[Run], extra: &[String]) -> Result<Output, String> {
    CORTEX_M4F.run_with(elf, runs, extra)
}

/// Runs a Cortex-M4F ELF that needs no run list (the teapot alone,
/// `tessera-teapot`) and returns its standard output; a qemu failure, a timeout
/// or an `error:`/`panic:`/`hard fault` line is an `Err` with qemu's output.
pub fn run_alone(elf: &Path) -> Result<String, String> {
    CORTEX_M4F.run_alone(elf)
}

/// [`run_alone`] in the folder `dir`, where the files the firmware writes over
/// semihosting stay (with qemu's output, `qemu.stdout` and `qemu.stderr`).
pub fn run_in(dir: &Path, elf: &Path) -> Result<String, String> {
    Ok(CORTEX_M4F.qemu(dir, elf, &[], None)?.0)
}

/// Runs qemu on `elf` in `dir` (`extra` arguments before `-kernel`) to its end and
/// returns its standard output, with the way to report a later failure (qemu's
/// outputs and the run list `list`, if any, appended); a qemu failure, a timeout
/// or an `error:`/`panic:`/`hard fault` line is an `Err` so reported.
impl Core {
    fn qemu(
        &self,
        dir: &Path,
        elf: &Path,
        extra: &[String],
        list: Option<&str>,
    ) -> Result<(String, impl Fn(String) -> String + use<>), String> {
        let status = wait_for_qemu(self.start_qemu(dir, elf, extra)?);
        let read = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap_or_default();
        let (stdout, stderr) = (read("qemu.stdout"), read("qemu.stderr"));
        let list = list.map_or_else(String::new, |l| format!("--- run list\n{l}"));
        let (out, elf) = (stdout.clone(), elf.display().to_string());
        let fail = move |why: String| {
            format!(
                "firmware run of {elf} failed: {why}\n{list}--- qemu stdout\n{out}--- qemu stderr\n{stderr}"
            )
        };
        let status = status.map_err(&fail)?;
        if !status.success() {
            return Err(fail(format!("qemu exited with {status}")));
        }
        if let Some(l) = stdout.lines().find(|l| {
            l.starts_with("error:") || l.starts_with("panic:") || l.starts_with("hard fault")
        }) {
            return Err(fail(l.to_string()));
        }
        Ok((stdout, fail))
    }

    /// Starts qemu on `elf` in `dir` ([`Core::qemu_args`], `extra` before `-kernel`),
    /// its output to `qemu.stdout` and `qemu.stderr` there.
    fn start_qemu(&self, dir: &Path, elf: &Path, extra: &[String]) -> Result<Child, String> {
        let file = |name: &str| {
            std::fs::File::create(dir.join(name)).map_err(|e| format!("cannot create {name}: {e}"))
        };
        let (kernel, before) = self.qemu_args.split_last().unwrap_or((&"-kernel", &[]));
        let qemu = self.qemu;
        Command::new(qemu)
            .args(before)
            .args(extra)
            .arg(kernel)
            .arg(elf)
            .current_dir(dir)
            .stdin(Stdio::null())
            .stdout(file("qemu.stdout")?)
            .stderr(file("qemu.stderr")?)
            .spawn()
            .map_err(|e| {
                if e.kind() == ErrorKind::NotFound {
                    format!("{qemu} is not installed: {INSTALL_HINT}")
                } else {
                    format!("cannot start {qemu}: {e}")
                }
            })
    }
}

/// Writes the run list of `runs` to [`RUNS_FILE`] in `dir` and returns it; an error
/// if it is longer than the firmware reads.
fn write_run_list(dir: &Path, runs: &[Run]) -> Result<String, String> {
    let mut list = String::new();
    for r in runs {
        list.push_str(&r.to_string());
        list.push('\n');
    }
    if list.len() > RUNS_MAX {
        return Err(format!(
            "the run list is {} bytes, the firmware reads at most {RUNS_MAX}: split it",
            list.len()
        ));
    }
    std::fs::write(dir.join(RUNS_FILE), list.as_bytes())
        .map_err(|e| format!("cannot write {RUNS_FILE}: {e}"))?;
    Ok(list)
}

/// Waits for qemu to exit; kills it after [`TIMEOUT`].
fn wait_for_qemu(mut child: Child) -> Result<ExitStatus, String> {
    let start = Instant::now();
    loop {
        match child.try_wait() {
            Ok(Some(status)) => break Ok(status),
            Ok(None) if start.elapsed() > TIMEOUT => {
                let _ = child.kill();
                let _ = child.wait();
                break Err(format!("qemu ran for more than {} s", TIMEOUT.as_secs()));
            }
            Ok(None) => std::thread::sleep(Duration::from_millis(10)),
            Err(e) => break Err(format!("waiting for qemu: {e}")),
        }
    }
}

/// The value of `key=` in a result line.
pub(crate) fn field<'a>(line: &'a str, key: &str) -> Result<&'a str, String> {
    line.split_whitespace()
        .find_map(|w| w.strip_prefix(key)?.strip_prefix('='))
        .ok_or_else(|| format!("no {key}= in {line:?}"))
}

/// The value of `key=` in a result line, as a number.
pub(crate) fn number(line: &str, key: &str) -> Result<u64, String> {
    let v = field(line, key)?;
    v.parse()
        .map_err(|_| format!("{key}={v} is not a number in {line:?}"))
}

fn parse_output(stdout: &str, runs: &[Run], dir: &Path, tick: TickRate) -> Result<Output, String> {
    let line = |prefix: &str| {
        stdout
            .lines()
            .find(|l| l.starts_with(prefix))
            .ok_or_else(|| format!("no `{prefix}` line"))
    };
    let done = number(line("done ")?, "runs")?;
    if done != runs.len() as u64 {
        return Err(format!("{done} runs done, {} asked", runs.len()));
    }
    let cal = line("calibration ")?;
    let stack = line("stack peak=")?;
    let mut results = Vec::with_capacity(runs.len());
    for (i, run) in runs.iter().enumerate() {
        let l = line(&format!("run {i} "))?;
        let size = format!("{}x{}", run.width, run.height);
        if field(l, "scene")? != run.scene.name() || field(l, "size")? != size {
            return Err(format!("run {i} reported {l:?}, asked {run}"));
        }
        let ticks = number(l, "ticks")?;
        let instructions = number(l, "instructions")?;
        if instructions != tick.instructions(ticks) {
            return Err(format!(
                "run {i}: instructions != ticks x {}/{} in {l:?}",
                tick.instructions, tick.ticks
            ));
        }
        let name = format!("{FRAME_PREFIX}{i}{FRAME_SUFFIX}");
        let bytes =
            std::fs::read(dir.join(&name)).map_err(|e| format!("cannot read {name}: {e}"))?;
        let n = bytes.len();
        let (w, h) = (u32::from(run.width), u32::from(run.height));
        let pixels = RgbImage::from_raw(w, h, bytes)
            .filter(|_| n == (w * h * 3) as usize)
            .ok_or_else(|| format!("{name} is {n} bytes, not {w}x{h}x3"))?;
        results.push(RunResult {
            pixels,
            ticks,
            instructions,
            pixels_count: number(l, "pixels")?,
            stack: number(l, "stack")?,
            stack_base: number(l, "base")?,
            stack_render: number(l, "render")?,
            setup: match stdout
                .lines()
                .find(|l| l.starts_with(&format!("setup {i} ")))
            {
                Some(l) => Some(Setup {
                    view: number(l, "view")?,
                    lights: number(l, "lights")?,
                    spheres: number(l, "spheres")?,
                    planes: number(l, "planes")?,
                }),
                None => None,
            },
        });
    }
    Ok(Output {
        runs: results,
        stack_peak: number(stack, "peak")?,
        stack_available: number(stack, "available")?,
        calibration_instructions: number(cal, "instructions")?,
        calibration_ticks: number(cal, "ticks")?,
        stdout: stdout.to_string(),
    })
}

/// Section sizes of an ELF, bytes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sizes {
    /// `.vector_table` (flash).
    pub vector_table: u64,
    /// `.text` (flash; on RISC-V with riscv-rt's `.init.rust`).
    pub text: u64,
    /// `.rodata` (flash).
    pub rodata: u64,
    /// `.data` (flash for its initial values and RAM).
    pub data: u64,
    /// `.bss` (RAM).
    pub bss: u64,
    /// `.uninit` (RAM).
    pub uninit: u64,
}

impl Sizes {
    /// Flash used: vector table, code, read-only data and `.data`'s initial values.
    #[must_use]
    pub fn flash(&self) -> u64 {
        self.vector_table + self.text + self.rodata + self.data
    }
    /// RAM taken by statics (the stack has the rest).
    #[must_use]
    pub fn ram(&self) -> u64 {
        self.data + self.bss + self.uninit
    }
}

/// The section sizes of `elf` (read with the `object` crate).
pub fn sections(elf: &Path) -> Result<Sizes, String> {
    use object::{Object, ObjectSection};
    let bytes = std::fs::read(elf).map_err(|e| format!("cannot read {}: {e}", elf.display()))?;
    let file = object::File::parse(&*bytes)
        .map_err(|e| format!("{} is not an object file: {e}", elf.display()))?;
    let mut s = Sizes::default();
    for sec in file.sections() {
        let slot = match sec.name().unwrap_or("") {
            ".vector_table" => &mut s.vector_table,
            // riscv-rt's start-up code lies in `.init.rust`, beside `.text`.
            ".text" | ".init.rust" => &mut s.text,
            ".rodata" => &mut s.rodata,
            ".data" => &mut s.data,
            ".bss" => &mut s.bss,
            ".uninit" => &mut s.uninit,
            _ => continue,
        };
        *slot += sec.size();
    }
    Ok(s)
}

/// A symbol of an ELF's symbol table.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Symbol {
    /// Its name demangled, without the hash (`qemu_m4f::scene::SCENE`).
    pub name: String,
    /// Its address.
    pub address: u64,
    /// Its size in bytes.
    pub size: u64,
    /// The name of its section (`.rodata`), if it has one.
    pub section: Option<String>,
}

/// The data and function symbols of `elf` (read with the `object` crate).
pub fn symbols(elf: &Path) -> Result<Vec<Symbol>, String> {
    use object::{Object, ObjectSection, ObjectSymbol, SymbolKind, SymbolSection};
    let bytes = std::fs::read(elf).map_err(|e| format!("cannot read {}: {e}", elf.display()))?;
    let file = object::File::parse(&*bytes)
        .map_err(|e| format!("{} is not an object file: {e}", elf.display()))?;
    Ok(file
        .symbols()
        .filter(|s| matches!(s.kind(), SymbolKind::Data | SymbolKind::Text))
        .filter_map(|s| {
            let name = format!("{:#}", rustc_demangle::demangle(s.name().ok()?));
            let section = match s.section() {
                SymbolSection::Section(i) => file
                    .section_by_index(i)
                    .ok()
                    .and_then(|sec| sec.name().ok().map(str::to_string)),
                _ => None,
            };
            Some(Symbol {
                name,
                address: s.address(),
                size: s.size(),
                section,
            })
        })
        .collect())
}

/// The FLASH and RAM lengths of the Cortex-M4F's memory map
/// (`tests/firmware/memory/mps2-an386.x`), bytes.
pub fn memory_budget() -> Result<(u64, u64), String> {
    CORTEX_M4F.memory_budget()
}

/// The FLASH and RAM lengths of the linker memory file `path`, bytes.
pub fn memory_regions(path: &Path) -> Result<(u64, u64), String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let length = |region: &str| -> Result<u64, String> {
        let l = text
            .lines()
            .find(|l| l.trim_start().starts_with(region))
            .ok_or_else(|| format!("no {region} region in {}", path.display()))?;
        let v = l
            .split("LENGTH")
            .nth(1)
            .and_then(|v| v.split('=').nth(1))
            .map(str::trim)
            .ok_or_else(|| format!("no LENGTH for {region} in {}", path.display()))?;
        let (digits, unit) = match v.strip_suffix('K') {
            Some(d) => (d, 1024),
            None => match v.strip_suffix('M') {
                Some(d) => (d, 1024 * 1024),
                None => (v, 1),
            },
        };
        digits
            .trim()
            .parse::<u64>()
            .map(|n| n * unit)
            .map_err(|_| format!("bad LENGTH {v:?} for {region} in {}", path.display()))
    };
    Ok((length("FLASH")?, length("RAM")?))
}

/// Panics unless the cargo configuration `config` (read from `path`, named in
/// the message) has a `runner = "..."` line that is [`QEMU`] and [`QEMU_ARGS`],
/// word for word: `cargo run` then starts qemu as this harness does.
pub fn assert_runner_is_qemu(config: &str, path: &Path) {
    let runner = config
        .lines()
        .find_map(|l| l.trim().strip_prefix("runner = "))
        .expect("a runner line")
        .trim_matches('"');
    let words: Vec<&str> = runner.split_whitespace().collect();
    let ours: Vec<&str> = std::iter::once(QEMU).chain(QEMU_ARGS).collect();
    assert_eq!(
        words,
        ours,
        "{} and firmware::QEMU_ARGS differ",
        path.display()
    );
}

#[cfg(test)]
mod tests {
    use super::*;
    use tessera_core::Sampler;
    use tessera_core::builtin::Builtin;

    /// Every run the reports and tests send reads back as itself: the run list's
    /// writer and reader agree.
    #[test]
    fn run_lines_read_back_as_written() {
        let mut runs = Vec::new();
        for &b in Builtin::ALL {
            for (sampler, tile, scale) in [
                (Sampler::Centre, 8, 0),
                (Sampler::Stratified(3), 16, -20),
                (Sampler::Random(5), 32, 7),
                (b.settings().sampler, 16, 0),
            ] {
                for encoding in [tessera_core::Encoding::Srgb, tessera_core::Encoding::Linear] {
                    runs.push(Run {
                        sampler,
                        tile,
                        scale,
                        seed: 12345,
                        encoding,
                        ..Run::of(b, 64, 48)
                    });
                }
            }
        }
        runs.extend(crate::baseline::runs());
        for r in runs {
            let line = r.to_string();
            assert_eq!(parse_run(&line), Ok(r), "{line}");
        }
        assert_eq!(
            parse_run("chapter-reflect centre 1 12 8 8 0"),
            Err("tile size is not 8, 16 or 32")
        );
        // The encoding: absent is the default (srgb), named in any case, and
        // nothing after it.
        let srgb = parse_run("chapter-reflect centre 1 16 8 8 0").unwrap();
        assert_eq!(srgb.encoding, tessera_core::Encoding::Srgb);
        let linear = parse_run("chapter-reflect centre 1 16 8 8 0 LINEAR").unwrap();
        assert_eq!(linear.encoding, tessera_core::Encoding::Linear);
        assert_eq!(
            parse_run("chapter-reflect centre 1 16 8 8 0 gamma"),
            Err("bad encoding: linear or srgb")
        );
        assert_eq!(
            parse_run("chapter-reflect centre 1 16 8 8 0 srgb 1"),
            Err("too many fields")
        );
    }

    /// The exact test of a square root agrees with `f64`'s (correctly rounded
    /// to `f32`: 53 >= 2 x 24 + 2 bits, so the double rounding is harmless) on
    /// every input, and refuses the neighbours of the right result; the host's
    /// `sqrt` passes it.
    #[test]
    fn the_square_root_check_is_exact() {
        let mut n = 0;
        for x in sqrt_check::inputs() {
            let want = (f64::from(x)).sqrt() as f32;
            assert!(sqrt_check::correctly_rounded(x, want), "{:#x}", x.to_bits());
            if want.is_finite() && want > 0.0 {
                for wrong in [next(want, -1), next(want, 1)] {
                    assert!(
                        !sqrt_check::correctly_rounded(x, wrong),
                        "{:#x}: {:#x} accepted",
                        x.to_bits(),
                        wrong.to_bits()
                    );
                }
            }
            n += 1;
        }
        assert_eq!(n, SqrtReport::host().cases);
        assert!(!sqrt_check::correctly_rounded(-1.0, 0.0));
        assert!(!sqrt_check::correctly_rounded(-0.0, 0.0));
        assert!(sqrt_check::correctly_rounded(-0.0, -0.0));
        assert!(sqrt_check::correctly_rounded(f32::NAN, f32::NAN));
        assert_eq!(SqrtReport::host().wrong, 0);
    }

    /// The float `steps` ulps from a positive finite `x`.
    fn next(x: f32, steps: i32) -> f32 {
        f32::from_bits(x.to_bits().wrapping_add_signed(steps))
    }

    /// The image names (target folders) of the feature sets: the exact image and
    /// the fast-math one keep the folders they always had; a set of features is
    /// joined with `+`; anything that could leave `tests/firmware/target/` is refused.
    #[test]
    fn image_names_are_plain_folder_names() {
        assert_eq!(image_name(&[]).as_deref(), Ok("exact"));
        assert_eq!(image_name(&["fast-math"]).as_deref(), Ok("fast-math"));
        assert_eq!(
            image_name(&["fast-rsqrt", "fast_pow"]).as_deref(),
            Ok("fast-rsqrt+fast_pow")
        );
        for bad in ["", "../x", "a/b", "a,b", "a b", "."] {
            assert!(image_name(&[bad]).is_err(), "{bad:?}");
        }
    }

    /// `cargo run` of the firmware (the root `.cargo/config.toml`'s runner) and this
    /// harness start qemu the same way: the runner line is [`QEMU`] and
    /// [`QEMU_ARGS`], word for word.
    #[test]
    fn qemu_args_are_the_cargo_runners() {
        let path = repo_root().join(".cargo").join("config.toml");
        let config = std::fs::read_to_string(&path).expect("the root .cargo/config.toml");
        assert_runner_is_qemu(&config, &path);
    }
}
