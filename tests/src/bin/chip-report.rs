//! `chip-report`: measures tessera on a Cortex-M4F, and on the other cores with an
//! FPU, and writes `docs/chip-cost.md`.
//!
//! Builds the firmware test image with both math backends, runs every built-in
//! scene with five samplers at 64x64 (chapter-reflect also at depths 0, 1 and 3)
//! under qemu, twice per backend, and writes the instructions per pixel, the ELF
//! section sizes, the peak stack and the flash/RAM budget. Fails if the two passes
//! disagree on any count or if the exact backend's pixels differ from the host's.
//! A third pass of the exact backend runs under the instruction-profiling qemu
//! plugin (`tests/profiler/`): its counts must agree with SysTick's, and its
//! instruction mix gives the estimated cycles per pixel ([`tessera_tests::cycles`]).
//!
//! The same image is then built for every other core with an FPU
//! (`firmware::FPU_CORES`: Cortex-M7, M33, M55, rv32imafc) and runs each built-in
//! scene at 64x64 with centre and stratified:4 sampling, twice, on its qemu board:
//! instructions per pixel per core, flash, `render_tile`'s stack. Fails if a core's
//! counts do not repeat, its pixels differ from the host's or its square root is
//! not correctly rounded there.
//!
//! The instruction counts of the guarded runs are compared with
//! `tests/chip-baseline.txt` and, on the other cores, `tests/chip-baseline-cores.txt`
//! (printed); `--bless-baseline` rewrites both files from this run's counts,
//! `--bless-cores-baseline` the second alone (commit them with a message that says
//! why).
//!
//! ```sh
//! cargo run -p tessera-tests --release --bin chip-report
//! cargo run -p tessera-tests --release --bin chip-report -- --bless-baseline
//! cargo run -p tessera-tests --release --bin chip-report -- --bless-cores-baseline
//! ```

use image::RgbImage;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};
use tessera_core::builtin::Builtin;
use tessera_core::testing::Extreme;
use tessera_core::{Encoding, RenderSettings, Renderer, Viewport};
use tessera_core::{Sampler, Sampler::*};
use tessera_tests::firmware::{self, Core, Output, Run, SceneRef, Sizes, repo_relative};
use tessera_tests::memory::{
    self,
    board::{Imxrt1062, Rp2350, Stm32f411},
    frames::{Board, FLASH, HOT_NAME, RAM_CRATES, TESSERA_IN_RAM, Traced},
};
use tessera_tests::{
    baseline, cycles, dualcore, profile, qemu_example, thousands, thousands_rounded,
};

const COMMAND: &str = "cargo run -p tessera-tests --release --bin chip-report";
const SAMPLERS: [Sampler; 6] = [
    Corner,
    Centre,
    Stratified(2),
    Stratified(4),
    Random(4),
    Sampler::sparse(),
];
const SIZE: u16 = 64;
const TILE: usize = 16;

/// Which baseline files to rewrite from this run's counts.
#[derive(Clone, Copy, Debug, Default)]
struct Bless {
    /// `tests/chip-baseline.txt` (the Cortex-M4F).
    m4f: bool,
    /// `tests/chip-baseline-cores.txt` (the other cores).
    cores: bool,
}

/// The frame of the frame-rate estimates: a 240x240 panel (ST7789).
const FRAME: u16 = 240;
/// The SPI clock of the estimates' panel wire, Hz.
const SPI_HZ: f64 = 50e6;
/// The Black Pill's clock (STM32F411 at 100 MHz), Hz.
const BLACK_PILL_HZ: f64 = 100e6;
/// The Pico 2's clock (RP2350 at 150 MHz), Hz.
const PICO2_HZ: f64 = 150e6;
/// The Teensy 4.1's clock (i.MX RT1062 at 600 MHz), Hz.
const TEENSY_HZ: f64 = 600e6;

fn main() -> ExitCode {
    let mut bless = Bless::default();
    for arg in std::env::args().skip(1) {
        match arg.as_str() {
            "--bless-baseline" => {
                bless = Bless {
                    m4f: true,
                    cores: true,
                }
            }
            "--bless-cores-baseline" => bless.cores = true,
            _ => {
                eprintln!(
                    "chip-report: unknown argument {arg:?} (the options are \
                     --bless-baseline: rewrite {} and {}, and --bless-cores-baseline: \
                     rewrite {} alone)",
                    baseline::FILE,
                    baseline::CORES_FILE,
                    baseline::CORES_FILE
                );
                return ExitCode::FAILURE;
            }
        }
    }
    match report(bless) {
        Ok(path) => {
            println!("wrote {}", path.display());
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("chip-report: {e}");
            ExitCode::FAILURE
        }
    }
}

/// The run list: every scene at its own depth (chapter-reflect at 0, 1, 3) with
/// each sampler, encoded in sRGB (the default); then each scene with its own
/// settings encoded linear, for the encoding's cost; the extremes; and each
/// scene at the estimates' frame size ([`FRAME`]) with its own settings, centre
/// and sparse sampling (what the sparse sampler saves depends on the size).
fn runs() -> Vec<Run> {
    let mut runs = Vec::new();
    for &b in Builtin::ALL {
        let depths = if b == Builtin::ChapterReflect {
            vec![0, 1, 3]
        } else {
            vec![b.settings().max_depth]
        };
        for depth in depths {
            for sampler in SAMPLERS {
                runs.push(Run {
                    sampler,
                    depth,
                    tile: TILE,
                    ..Run::of(b, SIZE, SIZE)
                });
            }
        }
    }
    for &b in Builtin::ALL {
        runs.push(Run {
            tile: TILE,
            encoding: Encoding::Linear,
            ..Run::of(b, SIZE, SIZE)
        });
    }
    for e in Extreme::ALL {
        runs.push(Run {
            tile: TILE,
            ..Run::of(e, SIZE, SIZE)
        });
    }
    runs.extend(frame_runs());
    // Each built-in scene from its baked tables, for a frame's set-up (the
    // firmware measures it after a baked scene's run).
    for &b in Builtin::ALL {
        runs.push(Run {
            tile: TILE,
            ..Run::of(SceneRef::Baked(b), SIZE, SIZE)
        });
    }
    runs
}

/// The samplers of the frame runs of `scene`: centre, sparse, and sparse
/// from its coarse grid where the scene takes it (elsewhere the same frame as
/// sparse).
fn frame_samplers(scene: Builtin) -> Vec<Sampler> {
    let mut samplers = vec![Centre, Sampler::sparse()];
    let coarse = Sampler::sparse_spaced(4);
    let settings = RenderSettings {
        sampler: coarse,
        ..scene.settings()
    };
    let takes = scene
        .with_scene(|view, cam| {
            Renderer::try_new(cam, Viewport::new(FRAME, FRAME), settings)
                .is_ok_and(|r| r.sparse_spacing(view) == Some(4))
        })
        .unwrap_or(false);
    if takes {
        samplers.push(coarse);
    }
    samplers
}

/// Each scene at [`FRAME`]x[`FRAME`] with its own settings, centre then sparse
/// sampling, then sparse from its coarse grid ([`frame_samplers`]).
fn frame_runs() -> Vec<Run> {
    let mut runs = Vec::new();
    for &b in Builtin::ALL {
        for sampler in frame_samplers(b) {
            runs.push(Run {
                sampler,
                tile: TILE,
                ..Run::of(b, FRAME, FRAME)
            });
        }
    }
    runs
}

/// The runs of the per-core table: each scene at 64x64 with its own settings,
/// centre and stratified:4 sampling (both in [`runs`], so the Cortex-M4F's come
/// from its exact backend).
fn core_runs() -> Vec<Run> {
    let mut runs = Vec::new();
    for &b in Builtin::ALL {
        for sampler in [Centre, Stratified(4)] {
            runs.push(Run {
                sampler,
                tile: TILE,
                ..Run::of(b, SIZE, SIZE)
            });
        }
    }
    runs
}

/// One core's image and what it measured ([`core_runs`]).
struct CoreMeasure {
    core: Core,
    elf: PathBuf,
    sizes: Sizes,
    out: Output,
    flash_budget: u64,
    ram_budget: u64,
}

/// Builds the exact image for `core`, runs [`core_runs`] on it twice (the counts
/// must repeat), checks its pixels against the host's and its square root.
fn measure_core(core: Core) -> Result<CoreMeasure, String> {
    let runs = core_runs();
    core.qemu_version()?;
    let elf = core.build(&[])?;
    let first = core.run(&elf, &runs)?;
    let second = core.run(&elf, &runs)?;
    for (i, (a, b)) in first.runs.iter().zip(&second.runs).enumerate() {
        if a.ticks != b.ticks || a.stack != b.stack || a.pixels.as_raw() != b.pixels.as_raw() {
            return Err(format!(
                "{}: run {i} ({}) is not repeatable: {} vs {} ticks",
                core.title, runs[i], a.ticks, b.ticks
            ));
        }
    }
    for (r, res) in runs.iter().zip(&first.runs) {
        if host(r)?.as_raw() != res.pixels.as_raw() {
            return Err(format!(
                "{}: {r}: the chip's pixels differ from the host's",
                core.title
            ));
        }
    }
    let sqrt = firmware::check_sqrt(&core, &elf)?;
    if sqrt != firmware::SqrtReport::host() {
        return Err(format!(
            "{}: sqrt {sqrt:?}, the host's {:?}",
            core.title,
            firmware::SqrtReport::host()
        ));
    }
    let (flash_budget, ram_budget) = core.memory_budget()?;
    Ok(CoreMeasure {
        core,
        sizes: firmware::sections(&elf)?,
        elf,
        out: first,
        flash_budget,
        ram_budget,
    })
}

/// One backend's image and what it measured.
struct Backend {
    elf: PathBuf,
    sizes: Sizes,
    out: Output,
}

/// Runs `runs` twice on `elf`; the two passes must agree on every count.
fn measure(elf: PathBuf, runs: &[Run]) -> Result<Backend, String> {
    let first = firmware::run(&elf, runs)?;
    let second = firmware::run(&elf, runs)?;
    for (i, (a, b)) in first.runs.iter().zip(&second.runs).enumerate() {
        if a.ticks != b.ticks || a.stack != b.stack || a.pixels.as_raw() != b.pixels.as_raw() {
            return Err(format!(
                "{}: run {i} ({}) is not repeatable: {} vs {} ticks",
                elf.display(),
                runs[i],
                a.ticks,
                b.ticks
            ));
        }
    }
    if first.calibration_ticks != second.calibration_ticks {
        return Err("the calibration loop is not repeatable".into());
    }
    let sizes = firmware::sections(&elf)?;
    Ok(Backend {
        elf,
        sizes,
        out: first,
    })
}

/// `f()` and how long it took.
fn timed<T>(f: impl FnOnce() -> Result<T, String>) -> Result<(T, Duration), String> {
    let t = Instant::now();
    f().map(|v| (v, t.elapsed()))
}

/// What the profiled pass found for one run.
struct Profiled {
    /// Instructions the plugin counted.
    total: u64,
    /// Estimated cycles.
    cycles: u64,
}

/// Runs `runs` once more on `elf`, one qemu per run, under the instruction
/// profiling plugin; each plugin count must agree with the SysTick count of its
/// own qemu run. Returns the counts and the estimated cycles.
fn profiled(elf: &std::path::Path, runs: &[Run]) -> Result<Vec<Profiled>, String> {
    let plugin = profile::build_plugin()?;
    let markers = profile::markers(elf)?;
    let mut est = Vec::with_capacity(runs.len());
    for r in runs {
        let (alone, prof) = profile::run(elf, &plugin, markers, r)?;
        profile::check_total(r, &alone, &prof)?;
        est.push(Profiled {
            total: prof.total,
            cycles: cycles::costs(&prof.insns)
                .iter()
                .map(cycles::Cost::cycles)
                .sum(),
        });
    }
    Ok(est)
}

/// The camera rays a pixel of `run` casts, counted on the host (the same core
/// code: the chip casts the same rays).
fn camera_rays(run: &Run) -> Result<f64, String> {
    let vp = Viewport::new(run.width, run.height);
    let (_, rays) = run
        .scene
        .with_scaled_scene(0, |view, cam| {
            let r = tessera_core::Renderer::try_new(cam, vp, run.settings())
                .map_err(|e| e.to_string())?;
            tessera_host::render_with(view, &r, run.tile, 1, &|| {}).map_err(|e| e.to_string())
        })
        .map_err(|e| e.to_string())??;
    Ok(rays.primary as f64 / (f64::from(run.width) * f64::from(run.height)))
}

fn host(run: &Run) -> Result<RgbImage, String> {
    let vp = Viewport::new(run.width, run.height);
    run.scene
        .with_scaled_scene(0, |view, cam| {
            tessera_host::render(view, cam, vp, run.settings(), run.tile)
        })
        .map_err(|e| e.to_string())?
        .map_err(|e| e.to_string())
}

/// Largest per-channel difference and PSNR (dB, `None` when identical).
fn difference(a: &RgbImage, b: &RgbImage) -> (u8, Option<f64>) {
    let mut max = 0u8;
    let mut sq = 0.0f64;
    for (x, y) in a.as_raw().iter().zip(b.as_raw()) {
        let d = x.abs_diff(*y);
        max = max.max(d);
        sq += f64::from(d) * f64::from(d);
    }
    let mse = sq / a.as_raw().len().max(1) as f64;
    let psnr = (mse > 0.0).then(|| 10.0 * (255.0f64 * 255.0 / mse).log10());
    (max, psnr)
}

fn kib(bytes: u64) -> String {
    format!("{:.1} KiB", bytes as f64 / 1024.0)
}
/// Measures, checks, and writes `docs/chip-cost.md`; returns its path.
fn report(bless: Bless) -> Result<PathBuf, String> {
    let qemu = firmware::qemu_version()?;
    let rustc = tessera_tests::tool_version("rustc");
    let (flash, ram) = firmware::memory_budget()?;
    let runs = runs();
    let (exact, fast, prof, cores) = measure_all(&runs)?;
    let est = check(&runs, &exact, &prof, bless.m4f, &qemu)?;
    guard_cores(&cores, bless.cores, &qemu)?;
    println!("both Cortex-M33 of mps2-an521...");
    let dual = dual_core()?;
    println!("the qemu example's scene files...");
    let files = scene_files()?;
    println!("the frames through the boards' memory paths...");
    let memory = memory_paths(&exact.elf, &cores)?;
    let m4f_sqrt = firmware::check_sqrt(&firmware::CORTEX_M4F, &exact.elf)?;
    if m4f_sqrt != firmware::SqrtReport::host() {
        return Err(format!("Cortex-M4F: sqrt {m4f_sqrt:?}"));
    }
    let m = Measured {
        qemu,
        rustc,
        flash,
        ram,
        runs,
        exact,
        fast,
        est,
        cores,
        dual,
        files,
        memory,
    };
    let mut d = String::new();
    m.setup(&mut d);
    m.counting(&mut d);
    m.instructions(&mut d);
    m.encoding(&mut d);
    m.extremes(&mut d);
    m.image_size(&mut d);
    m.stack(&mut d);
    m.scene_files(&mut d);
    m.instances(&mut d);
    m.frame_setup(&mut d);
    m.cores(&mut d);
    m.both_cores(&mut d);
    m.frames(&mut d);
    m.memory_model(&mut d);
    m.animation(&mut d);
    m.regenerate(&mut d);
    let path = firmware::repo_root().join("docs").join("chip-cost.md");
    std::fs::write(&path, d).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    Ok(path)
}

/// A frame's accuracy against its scene's own sampler: the scene, the
/// sampler, its mean FLIP and its pixels off by more than 2 levels, as the
/// tables print them ([`Measured::accuracy`]).
type Accuracy = (Builtin, Sampler, String, String);

/// A frame's cycles a pixel on the Pico 2's two cores, from one core's `c`
/// cycles a pixel of which `stalls` wait on the flash: the measured speed-up
/// `two`, but not below `stalls`, the time the one QSPI flash both cores share
/// (its QMI serves one miss at a time) is busy with one core's misses.
fn two_cores(c: f64, stalls: f64, two: f64) -> f64 {
    (c / two).max(stalls)
}

/// Traces the frame runs on the Cortex-M4F (`m4f`), the Cortex-M33 and the
/// Cortex-M7 images, through the memory paths of the boards they stand for.
fn memory_paths(m4f: &std::path::Path, cores: &[CoreMeasure]) -> Result<Vec<Traced>, String> {
    let elf = |t: &str| {
        cores
            .iter()
            .find(|c| c.core.title == t)
            .map(|c| c.elf.as_path())
            .ok_or_else(|| format!("the {t} was not measured"))
    };
    let started = Instant::now();
    let traced =
        memory::frames::measure(&frame_runs(), [m4f, elf("Cortex-M33")?, elf("Cortex-M7")?])?;
    println!("traced in {:.0} s", started.elapsed().as_secs_f64());
    Ok(traced)
}

/// What [`measure_all`] measured: both backends of the Cortex-M4F, the exact one's
/// profiles, and the other cores.
type Measures = (Backend, Backend, Vec<Profiled>, Vec<CoreMeasure>);

/// Builds the dual-core firmware (`tests/dualcore`) and its per-vCPU counting
/// plugin, runs it, and checks its frames' pixels against the host's (as
/// `tests/tests/dualcore.rs` does).
fn dual_core() -> Result<Vec<dualcore::SceneCounts>, String> {
    let elf = dualcore::build()?;
    let plugin = dualcore::build_plugin()?;
    let out = dualcore::run(&elf, &plugin)?;
    for f in &out.frames {
        if f.pixels != dualcore::host(f.scene)? {
            return Err(format!(
                "{} on {} core(s) of mps2-an521: pixels differ from the host's",
                f.scene.name(),
                f.cores
            ));
        }
    }
    Ok(out.counts)
}

/// The scene files of the table of scenes from files, as the qemu example's
/// `TESSERA_SCENE` names them, and what each shows; its default scene last, so
/// that the ELF left in the example's folder is the one a user builds there.
const SCENE_FILES: [(&str, &str); 9] = [
    (
        "../../scenes/teapot.toml",
        "the built-in teapot's scene file: a mesh of about 1,000 triangles with its normals, no texture",
    ),
    (
        TEAPOT_ONCE,
        "the teapot scene with its teapot drawn as one instance of its mesh, where the mesh lies",
    ),
    (
        TEAPOTS_WORLD,
        "four teapots, each a mesh of its own baked in world space (turned, scaled and moved when read)",
    ),
    (
        TEAPOTS_INSTANCED,
        "the same four teapots as instances of one mesh",
    ),
    (
        "../../scenes/examples/instances.toml",
        "four instances of the teapot's mesh: turned, scaled, one squashed, one mirrored",
    ),
    (
        "../../tests/data/tools.toml",
        "files from 3D tools: Blender's OBJ and MTL with a PNG, Khronos BoxTextured and Box (glTF), \
         turned; two RGB565 images; a sun and a point light",
    ),
    (
        "../../tests/data/blender/textured.toml",
        "two meshes with 8-bit sRGB images, nearest and mirrored, tinted",
    ),
    (
        ANIMATED,
        "an animation: a teapot turning and a ball bouncing, instances of two meshes moved by keyframes (the Pico 2 example's scene, 240x240)",
    ),
    (
        qemu_example::DEFAULT,
        "the example's default: the showcase's primitives and an OBJ icosahedron",
    ),
];

/// The animated scene the Pico 2 example plays, at its panel's size.
const ANIMATED: &str = "../../scenes/examples/animated-pico2.toml";

/// The scene files that compare instances with meshes baked in world space.
const TEAPOT_ONCE: &str = "../../tests/data/instances/teapot-once.toml";
const TEAPOTS_WORLD: &str = "../../tests/data/instances/teapots-world.toml";
const TEAPOTS_INSTANCED: &str = "../../tests/data/instances/teapots-instanced.toml";

/// Builds and runs the qemu example for each of [`SCENE_FILES`] and checks each
/// picture against the host's of the same file, byte for byte (as the example's
/// test does).
fn scene_files() -> Result<Vec<qemu_example::Run>, String> {
    let dir = qemu_example::example();
    let mut out = Vec::new();
    for (scene, _) in SCENE_FILES {
        let run = qemu_example::build_and_run(scene)?;
        if run.picture.as_raw() != qemu_example::host(&dir.join(scene)).as_raw() {
            return Err(format!(
                "the qemu example's picture of {scene} differs from the host's"
            ));
        }
        out.push(run);
    }
    Ok(out)
}

/// Builds both firmware images and measures them on three threads: each backend
/// twice ([`measure`]), and the exact one under the profiling plugin
/// ([`profiled`]); then builds and measures the other cores, two at a time
/// ([`measure_core`]).
fn measure_all(runs: &[Run]) -> Result<Measures, String> {
    println!("building the firmware (exact and fast-math)...");
    let exact_elf = firmware::build(&[])?;
    let fast_elf = firmware::build(&["fast-math"])?;
    println!(
        "running {} renders x 2 passes x 2 backends, and the exact backend once more \
         under the profiling plugin...",
        runs.len()
    );
    let started = Instant::now();
    let (exact, fast, prof) = std::thread::scope(|s| {
        let e = s.spawn(|| timed(|| measure(exact_elf.clone(), runs)));
        let f = s.spawn(|| timed(|| measure(fast_elf, runs)));
        let p = s.spawn(|| timed(|| profiled(&exact_elf, runs)));
        (join(e), join(f), join(p))
    });
    let ((exact, te), (fast, tf), (prof, tp)) = (exact?, fast?, prof?);
    println!(
        "measured in {:.0} s (three threads: exact 2 passes {:.0} s, fast-math 2 passes \
         {:.0} s, exact under the plugin {:.0} s)",
        started.elapsed().as_secs_f64(),
        te.as_secs_f64(),
        tf.as_secs_f64(),
        tp.as_secs_f64()
    );
    println!(
        "building and measuring the other cores ({})...",
        firmware::FPU_CORES.map(|c| c.title).join(", ")
    );
    let started = Instant::now();
    let mut cores = Vec::new();
    for pair in firmware::FPU_CORES.chunks(2) {
        let measured: Vec<_> = std::thread::scope(|s| {
            let handles: Vec<_> = pair
                .iter()
                .map(|&c| s.spawn(move || measure_core(c)))
                .collect();
            handles.into_iter().map(join).collect()
        });
        for m in measured {
            cores.push(m?);
        }
    }
    println!(
        "the other cores measured in {:.0} s",
        started.elapsed().as_secs_f64()
    );
    Ok((exact, fast, prof, cores))
}

/// The result of a measuring thread; a panic is an error.
fn join<T>(h: std::thread::ScopedJoinHandle<'_, Result<T, String>>) -> Result<T, String> {
    h.join()
        .unwrap_or_else(|_| Err("a measuring thread panicked".into()))
}

/// The checks on the measurements: the plugin's counts agree with SysTick's, the
/// guarded counts against the baseline (or blessed), the exact backend's pixels
/// are the host's. Returns the estimated cycles of each run.
fn check(
    runs: &[Run],
    exact: &Backend,
    prof: &[Profiled],
    bless: bool,
    qemu: &str,
) -> Result<Vec<u64>, String> {
    // The plugin's exact counts against the SysTick counts of the list (another
    // SysTick phase than the run alone: up to a tick a tile apart).
    for ((r, res), p) in runs.iter().zip(&exact.out.runs).zip(prof) {
        profile::agree(r, res.instructions, p.total)?;
    }
    let est: Vec<u64> = prof.iter().map(|p| p.cycles).collect();
    guard(runs, &exact.out, bless, qemu)?;

    // The exact backend is bit-identical to the host build.
    for (r, res) in runs.iter().zip(&exact.out.runs) {
        if host(r)?.as_raw() != res.pixels.as_raw() {
            return Err(format!("{r}: the chip's pixels differ from the host's"));
        }
    }
    Ok(est)
}

/// Everything the document is made of.
struct Measured {
    qemu: String,
    rustc: String,
    flash: u64,
    ram: u64,
    runs: Vec<Run>,
    exact: Backend,
    fast: Backend,
    est: Vec<u64>,
    cores: Vec<CoreMeasure>,
    /// Each built-in scene on one and on both Cortex-M33 of `mps2-an521`.
    dual: Vec<dualcore::SceneCounts>,
    /// The qemu example built and run for each of [`SCENE_FILES`].
    files: Vec<qemu_example::Run>,
    /// The frame runs ([`frame_runs`]) through each board's memory path.
    memory: Vec<Traced>,
}

impl Measured {
    /// The title, where the document comes from, and the setup.
    fn setup(&self, w: &mut String) {
        let Self {
            qemu,
            rustc,
            flash,
            ram,
            ..
        } = self;
        let (flash, ram) = (*flash, *ram);
        let _ = writeln!(
            w,
            "# tessera on a Cortex-M4F: instructions, memory, stack\n"
        );
        let _ = writeln!(
            w,
            "Generated by `{COMMAND}` (do not edit by hand; run it again after changing the \
         core or the firmware). It builds the firmware test image (`tests/firmware`, \
         package `tessera-fw`) with both math backends, runs it under qemu and writes \
         this file.\n"
        );
        let _ = writeln!(w, "## Setup\n");
        let _ = writeln!(
            w,
            "- Chip: qemu's `mps2-an386` board, a Cortex-M4F with its single-precision FPU \
         (`-cpu cortex-m4 -machine mps2-an386 -icount shift=0`), {qemu}."
        );
        let _ = writeln!(w, "- Compiler: {rustc}, target `{}`.", firmware::TARGET);
        let _ = writeln!(
            w,
            "- Firmware profile: `opt-level = 3`, `lto = \"fat\"`, `codegen-units = 1`, \
         `panic = \"abort\"`."
        );
        let _ = writeln!(
            w,
            "- Budget (`tests/firmware/memory/mps2-an386.x`): {} of flash, {} of RAM; the link fails \
         if the image does not fit.",
            kib(flash),
            kib(ram)
        );
        let _ = writeln!(
            w,
            "- Renders: {SIZE}x{SIZE} pixels, tiles of {TILE}x{TILE} in row-major order into \
         one static buffer, seed 0.\n"
        );
    }

    /// How instructions are counted, the calibration and the repeatability.
    fn counting(&self, w: &mut String) {
        let Self { runs, exact, .. } = self;
        let _ = writeln!(w, "## How instructions are counted\n");
        let _ = writeln!(
            w,
            "With `-icount shift=0` qemu advances virtual time by 1 ns per guest \
         instruction, and SysTick, clocked from the 25 MHz processor clock, ticks once \
         every 40 instructions, whatever the host machine does. The firmware reads \
         SysTick (24 bits, wraps counted by its exception) just before and after each \
         `render_tile` call, so building the scene and writing the pixels out are not \
         counted; instructions = ticks x 40, to within 40 instructions per tile."
        );
        let cal = &exact.out;
        let _ = writeln!(
            w,
            "Checked on every run: a loop of exactly {} instructions (`subs` + `bne`) took \
         {} ticks, {:.2} instructions per tick.",
            thousands(cal.calibration_instructions),
            thousands(cal.calibration_ticks),
            cal.calibration_instructions as f64 / cal.calibration_ticks.max(1) as f64
        );
        let _ = writeln!(
            w,
            "These are instructions, not cycles: on silicon, loads, taken branches, \
         `vdiv.f32`/`vsqrt.f32` (14 cycles) and flash wait states make the cycle count \
         higher. The `est. cycles/px` column estimates it from the instruction mix of a \
         third pass of the exact backend under the instruction-profiling qemu plugin \
         (`tests/profiler/`; its exact counts agree with SysTick's within {} \
         instructions a tile on every run, or this report fails); \
         [chip-profile.md](chip-profile.md) explains the model and shows where the \
         instructions go.\n",
            profile::TOLERANCE_PER_TILE
        );
        let _ = writeln!(
            w,
            "Repeatability: each backend ran the whole list of {} renders twice; all {} \
         instruction counts, stack peaks and images were identical between the two \
         passes. The exact backend's images are byte-identical to the host build of the \
         core for every render.\n",
            runs.len(),
            2 * runs.len()
        );
    }

    /// The table of instructions per pixel.
    fn instructions(&self, w: &mut String) {
        let Self {
            runs,
            exact,
            fast,
            est,
            ..
        } = self;
        let _ = writeln!(w, "## Instructions per pixel\n");
        let _ = writeln!(
            w,
            "`exact` is the default backend (libm, `vsqrt.f32`), `fast-math` every \
         approximation of the core's math (`--features fast-math`: `fast-rsqrt`, \
         `fast-recip`, `fast-pow`; each measured alone in [trade.md](trade.md)); the last two columns compare the \
         fast-math image with the exact one (largest channel difference in LSB, PSNR). \
         `est. cycles/px` is an **estimate** of Cortex-M4 cycles for the exact backend \
         from its instruction mix (Cortex-M4 TRM timings, taken branches 1 + P with \
         P = {}, zero-wait memory: see [chip-profile.md](chip-profile.md)).\n",
            cycles::REFILL
        );
        let _ = writeln!(
            w,
            "| scene | depth | sampler | rays/px | exact instr/px | est. cycles/px | exact instr/ray | fast-math instr/px | fast/exact | max diff | PSNR |"
        );
        let _ = writeln!(w, "|---|---|---|---|---|---|---|---|---|---|---|");
        for (((r, e), f), c) in runs
            .iter()
            .zip(&exact.out.runs)
            .zip(&fast.out.runs)
            .zip(est)
            .filter(|(((r, _), _), _)| {
                r.encoding == Encoding::Srgb
                    && matches!(r.scene, SceneRef::Builtin(_))
                    && r.width == SIZE
            })
        {
            let spp = r.sampler.count();
            let (max, psnr) = difference(&e.pixels, &f.pixels);
            let psnr = psnr.map_or_else(|| "identical".to_string(), |p| format!("{p:.1} dB"));
            let _ = writeln!(
                w,
                "| {} | {} | {} | {} | {:.0} | {:.0} | {:.0} | {:.0} | {:.2} | {} | {} |",
                r.scene.name(),
                r.depth,
                r.sampler,
                spp,
                e.instructions_per_pixel(),
                *c as f64 / e.pixels_count.max(1) as f64,
                e.instructions_per_pixel() / f64::from(spp),
                f.instructions_per_pixel(),
                f.instructions as f64 / e.instructions.max(1) as f64,
                max,
                psnr
            );
        }
        // Where the exact path stands against the per-pixel figures that were
        // once its targets (guards now: the baseline files), centre sampling.
        let standing: Vec<String> = [
            (Builtin::ChapterDirect, 0, 350.0),
            (Builtin::ChapterReflect, 1, 430.0),
            (Builtin::Teapot, 0, 2500.0),
        ]
        .into_iter()
        .filter_map(|(b, depth, mark)| {
            let (_, e) = runs.iter().zip(&exact.out.runs).find(|(r, _)| {
                r.encoding == Encoding::Srgb
                    && r.scene == SceneRef::Builtin(b)
                    && r.depth == depth
                    && r.sampler == Centre
                    && r.width == SIZE
            })?;
            let (scene, now) = (b.name(), e.instructions_per_pixel());
            Some(format!(
                "{scene} (depth {depth}) {now:.0} against {mark:.0} ({:.2} times)",
                now / mark
            ))
        })
        .collect();
        let _ = writeln!(
            w,
            "\nThe exact path, centre sampling, against the instructions a pixel at {SIZE}x{SIZE} \
             that were once its targets (now only reported; the baseline files guard the \
             counts): {}.",
            standing.join("; ")
        );
    }

    /// The cost of the sRGB encoding: each scene's own settings, linear and sRGB.
    fn encoding(&self, w: &mut String) {
        let Self { runs, exact, .. } = self;
        let _ = writeln!(w, "\n## The output encoding\n");
        let _ = writeln!(
            w,
            "Every figure above encodes the pixels in sRGB, the default (`Color::to_srgb8`: \
         a bucket table of 2 KiB and one comparison a channel, no branch, no `powf`). \
         The same renders with `encoding: Encoding::Linear` (the value itself, rounded), \
         exact backend, each scene with its own settings:\n"
        );
        let _ = writeln!(
            w,
            "| scene | depth | sampler | linear instr/px | srgb instr/px | srgb - linear |"
        );
        let _ = writeln!(w, "|---|---|---|---|---|---|");
        let measured = || runs.iter().zip(&exact.out.runs);
        for (r, lin) in measured().filter(|(r, _)| r.encoding == Encoding::Linear) {
            let srgb = Run {
                encoding: Encoding::Srgb,
                ..*r
            };
            let (_, s) = measured()
                .find(|(x, _)| **x == srgb)
                .expect("runs() measures each linear run's sRGB twin");
            let _ = writeln!(
                w,
                "| {} | {} | {} | {:.0} | {:.0} | {:.0} |",
                r.scene.name(),
                r.depth,
                r.sampler,
                lin.instructions_per_pixel(),
                s.instructions_per_pixel(),
                s.instructions_per_pixel() - lin.instructions_per_pixel()
            );
        }
    }

    /// The extremes battery's scenes: what a surface far larger than its distance
    /// costs (the `f64` paths, software on this chip) beside the same scene at an
    /// ordinary size, and the subnormal scenes.
    fn extremes(&self, w: &mut String) {
        let Self {
            runs, exact, est, ..
        } = self;
        let _ = writeln!(
            w,
            "\n## Surfaces far larger than their distance, subnormal inputs\n"
        );
        let _ = writeln!(
            w,
            "The scenes of `tessera_core::testing::Extreme` (cases 13 and 14 of \
             [extremes.md](extremes.md)), centre sampling, depth 3, exact backend: a ground \
             (two triangles, or a sphere whose top is the ground) `2^25` units across, seen \
             from 2 units, whose hits take the `f64` paths of `core/src/geometry/wide.rs` \
             (software on the Cortex-M4F), beside the same scene with a ground 1,024 units \
             across (256 times its distance, below where the `f64` paths take over) and 32 \
             units across; a camera a subnormal off the vertical through its target, and a scene \
             with subnormal numbers in every kind of input (read as zeros). The chip's \
             pixels are the host's (checked above).\n"
        );
        let _ = writeln!(
            w,
            "| scene | instr/px | est. cycles/px | against the 32-unit ground or sphere |"
        );
        let _ = writeln!(w, "|---|---|---|---|");
        let measured: Vec<(Extreme, f64, f64)> = runs
            .iter()
            .zip(&exact.out.runs)
            .zip(est)
            .filter_map(|((r, e), c)| match r.scene {
                SceneRef::Extreme(x) => Some((
                    x,
                    e.instructions_per_pixel(),
                    *c as f64 / e.pixels_count.max(1) as f64,
                )),
                SceneRef::Builtin(_) | SceneRef::Baked(_) => None,
            })
            .collect();
        let of = |x: Extreme| measured.iter().find(|m| m.0 == x).map(|m| m.1);
        for &(x, instr, cycles) in &measured {
            let twin = match x {
                Extreme::HugeGround | Extreme::MediumGround => of(Extreme::SmallGround),
                Extreme::HugeSphere | Extreme::MediumSphere => of(Extreme::SmallSphere),
                _ => None,
            };
            let against = twin.map_or_else(
                || "-".to_string(),
                |t| format!("{:+.0} instr/px ({:.2}x)", instr - t, instr / t),
            );
            let _ = writeln!(w, "| {} | {instr:.0} | {cycles:.0} | {against} |", x.name());
        }
    }

    /// The ELF sections and the flash/RAM budget.
    fn image_size(&self, w: &mut String) {
        let Self {
            flash,
            ram,
            exact,
            fast,
            ..
        } = self;
        let (flash, ram) = (*flash, *ram);
        let _ = writeln!(w, "\n## Image size (ELF sections, bytes)\n");
        let _ = writeln!(w, "| section | exact | fast-math |");
        let _ = writeln!(w, "|---|---|---|");
        let (a, b) = (&exact.sizes, &fast.sizes);
        let rows: [(&str, u64, u64); 5] = [
            (".vector_table", a.vector_table, b.vector_table),
            (".text", a.text, b.text),
            (".rodata", a.rodata, b.rodata),
            (".data", a.data, b.data),
            (".bss", a.bss, b.bss),
        ];
        for (name, x, y) in rows {
            let _ = writeln!(w, "| `{name}` | {} | {} |", thousands(x), thousands(y));
        }
        let pct = |n: u64, of: u64| 100.0 * n as f64 / of.max(1) as f64;
        let _ = writeln!(
            w,
            "| flash (vector table + text + rodata + data) | {} ({:.1}% of {}) | {} ({:.1}% of {}) |",
            thousands(a.flash()),
            pct(a.flash(), flash),
            kib(flash),
            thousands(b.flash()),
            pct(b.flash(), flash),
            kib(flash)
        );
        let _ = writeln!(
            w,
            "| static RAM (data + bss) | {} ({:.1}% of {}) | {} ({:.1}% of {}) |",
            thousands(a.ram()),
            pct(a.ram(), ram),
            kib(ram),
            thousands(b.ram()),
            pct(b.ram(), ram),
            kib(ram)
        );
        let _ = writeln!(
            w,
            "\nThe whole firmware: tessera with every built-in scene, the run-list parser, \
         semihosting and `core::fmt`. `.bss` holds the three tile buffers (8x8, 16x16 and \
         32x32: 200 + 776 + 3,080 bytes) and the 4 KiB run-list buffer; a firmware \
         that renders with one tile size needs only that buffer.\n"
        );
    }

    /// The stack table and the whole firmware's peak.
    fn stack(&self, w: &mut String) {
        let Self {
            runs, exact, fast, ..
        } = self;
        let _ = writeln!(w, "## Stack\n");
        let _ = writeln!(
            w,
            "The firmware paints the free stack before each render and finds the lowest \
         word that changed afterwards. `render_tile` is the peak below the stack \
         pointer of the tile loop: what rendering a tile needs (the shader's pending \
         rays, the frame's locals). `peak - harness` adds the scene, which \
         `Builtin::with_scene` builds on the stack (this firmware can render any of the \
         four scenes and its frame has room for all of them, so the figure hardly \
         changes between scenes; a firmware with one scene needs less), and the \
         `Renderer`. Each figure is the largest over the scene's runs.\n"
        );
        let _ = writeln!(
            w,
            "| scene | exact: render_tile | exact: peak - harness | fast-math: render_tile | fast-math: peak - harness |"
        );
        let _ = writeln!(w, "|---|---|---|---|---|");
        for &b in Builtin::ALL {
            let worst = |be: &Backend, f: &dyn Fn(&firmware::RunResult) -> u64| {
                runs.iter()
                    .zip(&be.out.runs)
                    .filter(|(r, _)| r.scene == b.into())
                    .map(|(_, x)| f(x))
                    .max()
                    .unwrap_or(0)
            };
            let render = |x: &firmware::RunResult| x.stack_render;
            let scene = |x: &firmware::RunResult| x.stack - x.stack_base;
            let _ = writeln!(
                w,
                "| {} | {} | {} | {} | {} |",
                b.name(),
                thousands(worst(exact, &render)),
                thousands(worst(exact, &scene)),
                thousands(worst(fast, &render)),
                thousands(worst(fast, &scene))
            );
        }
        let base = |be: &Backend| be.out.runs.iter().map(|x| x.stack_base).max().unwrap_or(0);
        let _ = writeln!(
            w,
            "\nWhole firmware, from the top of RAM, over every render: peak {} bytes (exact), \
         {} bytes (fast-math), of which the harness (reset, `main`) {} / {}; {} bytes lie \
         between the statics and the top of RAM.",
            thousands(exact.out.stack_peak),
            thousands(fast.out.stack_peak),
            thousands(base(exact)),
            thousands(base(fast)),
            thousands(exact.out.stack_available)
        );
    }

    /// The table per core: instructions per pixel of [`core_runs`] on every core
    /// with an FPU, the images' flash and `render_tile`'s stack.
    fn cores(&self, w: &mut String) {
        let Self {
            runs,
            exact,
            flash,
            ram,
            cores,
            ..
        } = self;
        let m4f = CoreMeasure {
            core: firmware::CORTEX_M4F,
            elf: exact.elf.clone(),
            sizes: exact.sizes,
            out: Output {
                runs: core_runs()
                    .iter()
                    .filter_map(|c| {
                        runs.iter()
                            .position(|r| r == c)
                            .map(|i| exact.out.runs[i].clone())
                    })
                    .collect(),
                ..exact.out.clone()
            },
            flash_budget: *flash,
            ram_budget: *ram,
        };
        let all: Vec<&CoreMeasure> = std::iter::once(&m4f).chain(cores).collect();
        let _ = writeln!(w, "\n## Every core with an FPU\n");
        let _ = writeln!(
            w,
            "The same firmware image built for each core with an FPU that qemu emulates \
             and run on its board (`tessera_tests::firmware::CORES`): each built-in scene \
             at {SIZE}x{SIZE} with its own settings, tiles of {TILE}x{TILE}, exact math, \
             centre and stratified:4 sampling, twice (the counts repeat exactly). On every \
             core these renders' pixels are byte-identical to the host's (checked here; \
             `tests/tests/cores.rs` checks the Cortex-M4F's whole identity list on each \
             core in CI), and the square root is correctly rounded there (`tessera-sqrt`: \
             {} inputs, hard cases among them). Instructions per pixel, and against the \
             Cortex-M4F:\n",
            thousands(firmware::SqrtReport::host().cases)
        );
        let mut head = String::from("| scene | depth | sampler |");
        let mut rule = String::from("|---|---|---|");
        for c in &all {
            head.push_str(&format!(" {} |", c.core.title));
            rule.push_str("---|");
        }
        let _ = writeln!(w, "{head}\n{rule}");
        for (i, r) in core_runs().iter().enumerate() {
            let mut row = format!("| {} | {} | {} |", r.scene.name(), r.depth, r.sampler);
            let base = all[0].out.runs[i].instructions_per_pixel();
            for (k, c) in all.iter().enumerate() {
                let px = c.out.runs[i].instructions_per_pixel();
                if k == 0 {
                    row.push_str(&format!(" {} |", thousands_rounded(px)));
                } else {
                    row.push_str(&format!(
                        " {} ({:.2}x) |",
                        thousands_rounded(px),
                        px / base.max(1.0)
                    ));
                }
            }
            let _ = writeln!(w, "{row}");
        }
        let _ = writeln!(
            w,
            "\n| core | target (rustc flags) | qemu | instructions a tick | flash, bytes | \
             static RAM, bytes | `render_tile` stack, bytes |"
        );
        let _ = writeln!(w, "|---|---|---|---|---|---|---|");
        for c in &all {
            let k = c.core;
            let flags = if k.rustflags.is_empty() {
                String::new()
            } else {
                format!(" (`{}`)", k.rustflags.join(" "))
            };
            let tick = if k.tick.ticks == 1 {
                k.tick.instructions.to_string()
            } else {
                format!("{}/{}", k.tick.instructions, k.tick.ticks)
            };
            let stack = c.out.runs.iter().map(|x| x.stack_render).max().unwrap_or(0);
            let _ = writeln!(
                w,
                "| {} | `{}`{flags} | `{}` | {tick} | {} ({:.1}% of {}) | {} (of {}) | {} |",
                k.title,
                k.target,
                k.board,
                thousands(c.sizes.flash()),
                100.0 * c.sizes.flash() as f64 / c.flash_budget.max(1) as f64,
                kib(c.flash_budget),
                thousands(c.sizes.ram()),
                kib(c.ram_budget),
                thousands(stack)
            );
        }
        let _ = writeln!(
            w,
            "\nThese are instructions, not cycles: the cores differ in what an instruction \
             costs (the Cortex-M7 issues two a cycle at best, the M55's vector \
             instructions take beats); no cycle estimate is made for them here. Where the \
             counts differ the code differs: the FPv5 FPUs of the Cortex-M7, M33 and M55 \
             have `vminnm`/`vmaxnm` and `vsel`, which LLVM uses for some comparisons and \
             selects; with `target-cpu` the Cortex-M7's and M55's FPUs have double \
             precision, so the `f64` paths (`geometry::wide`, `Renderer::try_new`) are \
             instructions rather than library calls (an image for a part whose FPU has \
             single precision only needs a build without that flag); LLVM vectorises \
             some loops with the M55's MVE; RISC-V has no conditional select and more \
             registers. No image links a software `f32` arithmetic routine (`__aeabi_f*`, \
             `__*sf3`): division is `vdiv.f32`/`fdiv.s`, and `math::sqrt`, every root \
             the core takes itself, is `vsqrt.f32` on the Arm cores and `fsqrt.s` on \
             RISC-V (libm's software `sqrtf` stays linked for libm's own use: its `powf` \
             with an exponent of exactly 0.5, its `acosf` for textured spheres; no \
             built-in scene calls either). No image has a fused multiply-add (`vfma`, \
             `fmadd.s`: Rust does not contract `a * b + c`). The \
             Cortex-M4F, M33 and rv32imafc do their `f64` in software, as the \
             Cortex-M4F always has (the rare wide hits, once-a-frame set-up). On \
             `mps3-an547` SysTick ticks every 31.25 instructions (32 MHz), so its counts \
             are within 32 instructions a tile; on RISC-V the clock is the `minstret` \
             CSR, exact. The RISC-V map's flash is 1 MiB (`memory/riscv-virt.x`): the \
             image does not fit in 512 KiB. Flash and static RAM as in \
             [the image size](#image-size-elf-sections-bytes); the stack is the largest \
             `render_tile` peak over these renders."
        );
        let _ = writeln!(w, "\nThe other cores' ELFs:\n");
        for c in cores {
            let _ = writeln!(w, "- {}: `{}`", c.core.title, repo_relative(&c.elf));
        }
    }

    /// The frame on both Cortex-M33 of qemu's `mps2-an521`.
    fn both_cores(&self, w: &mut String) {
        let _ = writeln!(w, "\n## Both cores of a dual Cortex-M33\n");
        let _ = writeln!(
            w,
            "qemu's `mps2-an521` (two Cortex-M33 sharing SRAM; CPU 0 given an FPU, \
             `-global sse-200.CPU0_FPU=true`, as both cores of an RP2350 have) runs \
             `tests/dualcore`: each built-in scene at {}x{} in tiles of {}x{}, with \
             its own settings, rendered by CPU 0 alone and then by both cores taking \
             tiles from one `tessera_core::tile::TileQueue`. Each core's instructions in its \
             tile loop are counted by a qemu plugin per vCPU \
             (`tests/profiler/vcpu_count.c`: the SysTick clock is shared under \
             `-icount`). Both frames' pixels equal the host's, byte for byte (checked \
             here and by `tests/tests/dualcore.rs`, which also checks that the counts \
             repeat exactly). The speed-up is one core's instructions over the busier \
             core's: the frame's time on two cores at one clock, both cores running \
             at the same rate (qemu alternates them every 10,000 instructions; the \
             contention for memory a real chip has is not modelled).\n",
            dualcore::SIZE,
            dualcore::SIZE,
            dualcore::TILE,
            dualcore::TILE
        );
        let _ = write!(w, "{}", dualcore::table(&self.dual));
    }

    /// Frame times and rates on three boards, each as its example ships,
    /// without and with its memory path ([`Measured::memory_model`]).
    fn frames(&self, w: &mut String) {
        let px = f64::from(FRAME) * f64::from(FRAME);
        // The SPI transfer of a frame of RGB565 at the wire's clock, in ms.
        let spi_ms = px * 2.0 * 8.0 / SPI_HZ * 1e3;
        let _ = writeln!(w, "\n## Frames per second: estimates for three boards\n");
        let _ = writeln!(
            w,
            "**Estimates, not measurements: none of these boards is here** \
             ([bench.md](bench.md) measures them on a board). Each built-in scene with \
             its own settings and centre sampling, a frame of {FRAME}x{FRAME} pixels \
             ({} of them), run at that size. Cycles without waiting on memory \
             (`zero-wait`): **Black Pill** (STM32F411, one Cortex-M4F at 100 MHz): the \
             Cortex-M4 cycle model of [chip-profile.md](chip-profile.md) on the \
             frame's profile. **Pico 2** (RP2350, two Cortex-M33 at 150 MHz): the \
             Cortex-M33's instructions for the frame times the Cortex-M4F model's cycles \
             per instruction for the same frame (both cores have a three-stage pipeline \
             and single-cycle FPU arithmetic; no M33 model is made), for one core, and \
             for two at the speed-up measured on both cores of `mps2-an521` (the section \
             above, with the 16 tiles of a 64x64 frame; the 225 of a 240x240 frame \
             should split at least as evenly), but with memory no faster than the \
             QSPI flash both cores share serves one core's misses. **Teensy 4.1** (i.MX RT1062, one \
             Cortex-M7 at 600 MHz): a range, from the Cortex-M7's instructions at two a \
             cycle (its dual issue at every cycle: the best case) to the Cortex-M4F \
             model's cycles per instruction (no dual issue at all). `with memory`: the \
             same plus the cycles the board's memory path stalls, under the layout its \
             example ships (the Black Pill from flash behind the ART accelerator; the \
             Pico 2 with tessera's code in SRAM; the Teensy 4.1 as teensy4-bsp links \
             it); [the memory model](#frames-per-second-with-the-memory-model) has the \
             model, the other layouts and the sparse sampler. The panel: \
             {FRAME}x{FRAME} RGB565 is {} bytes, {spi_ms:.1} ms on a {} MHz SPI wire; \
             sent tile after tile while the next renders (`Drawing::send`, a DMA \
             channel) it hides behind the rendering but for the last tile; sent by a \
             blocking write it adds at least that to every frame (`fps, blocking \
             SPI`).\n",
            thousands(px as u64),
            thousands((px * 2.0) as u64),
            SPI_HZ / 1e6
        );
        let _ = writeln!(
            w,
            "| scene | Black Pill: cycles/px, zero-wait | with memory | fps | fps, blocking SPI | Pico 2: cycles/px, zero-wait | with memory | one core: fps | two cores: fps | Teensy 4.1: cycles/px, zero-wait | with memory | fps |"
        );
        let _ = writeln!(w, "|---|---|---|---|---|---|---|---|---|---|---|---|");
        let stalls = |b: Board, scene: Builtin| {
            let layout = b.shipped();
            self.traced(b, scene, Centre)
                .iter()
                .find(|t| t.layout == layout)
                .map(|t| t.stalls_px)
        };
        let range =
            |lo: f64, hi: f64| format!("{} to {}", thousands_rounded(lo), thousands_rounded(hi));
        for &scene in Builtin::ALL {
            let (Some((bp, _)), Some((pico, _)), Some((t_lo, Some(t_hi)))) = (
                self.zero_wait(Board::BlackPill, scene, Centre),
                self.zero_wait(Board::Pico2, scene, Centre),
                self.zero_wait(Board::Teensy41, scene, Centre),
            ) else {
                continue;
            };
            let (Some(bp_s), Some(pico_s), Some(t_s)) = (
                stalls(Board::BlackPill, scene),
                stalls(Board::Pico2, scene),
                stalls(Board::Teensy41, scene),
            ) else {
                continue;
            };
            let bp_ms = (bp + bp_s) * px / BLACK_PILL_HZ * 1e3;
            let pico_one = PICO2_HZ / ((pico + pico_s) * px);
            let pico_two = PICO2_HZ / (two_cores(pico + pico_s, pico_s, self.speedup(scene)) * px);
            let _ = writeln!(
                w,
                "| {} | {} | {} | {:.2} | {:.2} | {} | {} | {:.2} | {:.2} | {} | {} | {:.1} to {:.1} |",
                scene.name(),
                thousands_rounded(bp),
                thousands_rounded(bp + bp_s),
                1e3 / bp_ms,
                1e3 / (bp_ms + spi_ms),
                thousands_rounded(pico),
                thousands_rounded(pico + pico_s),
                pico_one,
                pico_two,
                range(t_lo, t_hi),
                range(t_lo + t_s, t_hi + t_s),
                TEENSY_HZ / ((t_hi + t_s) * px),
                TEENSY_HZ / ((t_lo + t_s) * px),
            );
        }
        self.sparse_frames(w);
    }

    /// The frame-rate estimates with each board's memory path: the model, where
    /// each board keeps code and data, and per board a table of each scene,
    /// centre and sparse, without and with the model, under each layout.
    fn memory_model(&self, w: &mut String) {
        let px = f64::from(FRAME) * f64::from(FRAME);
        let _ = writeln!(w, "\n## Frames per second with the memory model\n");
        let _ = writeln!(
            w,
            "**Estimates, not measurements: no board is here.** The cycle model \
             assumes zero-wait memory. Here each frame of the estimates ({FRAME}x{FRAME}, \
             each built-in scene with its own settings, centre and sparse sampling) runs \
             once more under qemu on the core of each board, with the plugin \
             `tests/profiler/mem_trace.c` streaming every instruction fetch and data \
             access of the render; a model of the board's memory path \
             (`tests/src/memory/`, with its unit tests on address traces of known hit \
             counts) adds the cycles each access would wait on the board. The cycles \
             without the model are the cycle model's for the same {FRAME}x{FRAME} run \
             (the Cortex-M4F's profile; the Cortex-M33's and Cortex-M7's instructions \
             times the Cortex-M4F's cycles per instruction for that run, as above). The \
             images traced are the test firmware for each core, with every built-in \
             scene linked: the cache sets its hot code falls in are that image's, not a \
             board example's.\n"
        );
        let _ = writeln!(w, "### The model's parameters\n");
        let _ = writeln!(
            w,
            "| board | memory path | parameters | sources |\n|---|---|---|---|"
        );
        let _ = writeln!(
            w,
            "| Pico 2 (RP2350, 150 MHz) | flash through the XIP cache, shared by fetches and loads; SRAM zero-wait | 16 KiB, 2 ways, 8-byte lines, LRU (policy undocumented), a hit costs nothing; a miss {} cycles, {} for the line after the last miss while the QMI's transfer is open | RP2350 datasheet 4.4 (XIP); pico-sdk `hardware/xip_cache.h`; the bootrom's QMI set-up (`EBh` quad read without continuous mode, 4 dummy clocks, `CLKDIV` 3: SCK 50 MHz), which rp235x-hal leaves as it is |",
            Rp2350::MISS,
            Rp2350::NEXT
        );
        let _ = writeln!(
            w,
            "| Black Pill (STM32F411, 100 MHz) | flash through the ART accelerator; SRAM zero-wait | {} wait states, 128-bit lines; prefetch of the next line; instruction cache 64 lines, data cache 8 lines, LRU, modelled fully associative (sets undocumented); a miss waits the wait states, a prefetched line what its read time exceeds the previous line's instructions | RM0383 3.4 (table 5) and 3.4.2 (ART); stm32f4xx-hal 0.23 `rcc::freeze` turns on prefetch and both caches |",
            Stm32f411::WAIT_STATES
        );
        let _ = writeln!(
            w,
            "| Teensy 4.1 (i.MX RT1062, 600 MHz) | ITCM and DTCM zero-wait; OCRAM uncached (the BSP leaves the caches off) | an OCRAM load {} cycles (undocumented: an assumption to measure) | i.MX RT1060 reference manual 31 (FlexRAM); imxrt-rt `RuntimeBuilder::from_flexspi` (`.rodata` in OCRAM); teensy4-bsp's build script and changelog |",
            Imxrt1062::OCRAM_LOAD
        );
        let _ = writeln!(
            w,
            "\nNot modelled: two cores missing at once in the Pico 2's shared XIP cache; \
             bus contention in SRAM. Code run from SRAM is fetched over the bus its own \
             loads and stores use (the Cortex-M4's S-bus, the Cortex-M33's S-AHB): the \
             `shared/px` columns count the RAM accesses that could delay a fetch by a \
             cycle, a bound the core's fetch buffer mostly hides.\n"
        );
        let _ = writeln!(w, "### Where code and data sit\n");
        let (code_bytes, rodata_bytes) = memory::Image::of(&self.exact.elf)
            .map(|i| i.sizes())
            .unwrap_or((0, 0));
        let ram_code = |b: Board, layout: &str| {
            self.memory
                .iter()
                .find(|t| t.board == b && t.layout == layout)
                .map_or(0, |t| t.code_in_ram)
        };
        let _ = writeln!(
            w,
            "| board | layout | code | read-only data (scene tables, sRGB table) | data, stack, tiles |\n|---|---|---|---|---|"
        );
        let crates = RAM_CRATES.join("`, `");
        let _ = writeln!(
            w,
            "| Black Pill | flash (cortex-m-rt's default) | flash | flash | SRAM |\n\
             | Black Pill | {HOT_NAME} | the functions that waited most from flash, over these frames, as long as they fit {} ({} in the Cortex-M4F's test image), the rest in flash | flash | SRAM |\n\
             | Pico 2 | flash (cortex-m-rt's default) | flash (XIP) | flash (XIP) | SRAM |\n\
             | Pico 2 | tessera in RAM | the code of `{crates}` in SRAM ({} in the Cortex-M33's test image), the rest in flash | flash (XIP) | SRAM |\n\
             | Teensy 4.1 | teensy4-bsp's default | ITCM | OCRAM | DTCM |\n\
             | Teensy 4.1 | `.rodata` in DTCM | ITCM | DTCM | DTCM |\n",
            kib(memory::frames::HOT_BUDGET),
            kib(ram_code(Board::BlackPill, HOT_NAME)),
            kib(ram_code(Board::Pico2, TESSERA_IN_RAM)),
        );
        let _ = writeln!(
            w,
            "(The Cortex-M4F's test image: {} of code, {} of read-only data.)\n",
            kib(code_bytes),
            kib(rodata_bytes)
        );
        // Each frame's accuracy, once for the three boards' tables.
        let accuracy: Vec<Accuracy> = Builtin::ALL
            .iter()
            .flat_map(|&scene| {
                frame_samplers(scene)
                    .into_iter()
                    .map(move |sampler| (scene, sampler))
            })
            .map(|(scene, sampler)| {
                let (flip, off) = self.accuracy(scene, sampler);
                (scene, sampler, flip, off)
            })
            .collect();
        for b in Board::ALL {
            self.memory_table(w, b, px, &accuracy);
        }
        // Ten frames a second of chapter-reflect on the Pico 2's two cores.
        let budget = 2.0 * PICO2_HZ / (10.0 * px);
        let lines: Vec<String> = frame_samplers(Builtin::ChapterReflect)
            .iter()
            .filter_map(|&sampler| {
                let (zero, _) = self.zero_wait(Board::Pico2, Builtin::ChapterReflect, sampler)?;
                let two = self.speedup(Builtin::ChapterReflect);
                let parts: Vec<String> = self
                    .traced(Board::Pico2, Builtin::ChapterReflect, sampler)
                    .iter()
                    .map(|t| {
                        let c = zero + t.stalls_px;
                        format!(
                            "{} cycles a pixel with {} ({:.1} frames a second)",
                            thousands_rounded(c),
                            t.layout,
                            PICO2_HZ / (two_cores(c, t.stalls_px, two) * px)
                        )
                    })
                    .collect();
                Some(format!("{}: {}", sampler, parts.join(", ")))
            })
            .collect();
        let _ = writeln!(
            w,
            "\nTen frames a second of chapter-reflect on the Pico 2's two cores leave \
             {budget:.0} cycles a pixel on each. With the memory model: {}.",
            lines.join("; ")
        );
    }

    /// One board's table of [`Measured::memory_model`].
    fn memory_table(&self, w: &mut String, b: Board, px: f64, accuracy: &[Accuracy]) {
        let layouts: Vec<&str> = {
            let mut l: Vec<&str> = Vec::new();
            for t in self.memory.iter().filter(|t| t.board == b) {
                if !l.contains(&t.layout) {
                    l.push(t.layout);
                }
            }
            l
        };
        let (hz, cores) = match b {
            Board::BlackPill => (BLACK_PILL_HZ, "one core"),
            Board::Pico2 => (
                PICO2_HZ,
                "two cores at the measured speed-up, but no faster than the one flash both share serves the misses",
            ),
            Board::Teensy41 => (TEENSY_HZ, "one core; cycles a range, as above"),
        };
        let _ = writeln!(w, "\n### {} ({cores})\n", b.name());
        let mut head = String::from(
            "| scene | sampler | FLIP against the scene's own | pixels off by more than 2 | zero-wait: cycles/px | fps |",
        );
        let mut rule = String::from("|---|---|---|---|---|---|");
        for l in &layouts {
            let _ = write!(head, " {l}: stalls/px | cycles/px | fps |");
            rule.push_str("---|---|---|");
            if matches!(b, Board::BlackPill | Board::Pico2) && *l != FLASH {
                head.push_str(" shared/px |");
                rule.push_str("---|");
            }
        }
        let _ = writeln!(w, "{head}\n{rule}");
        for &scene in Builtin::ALL {
            for sampler in frame_samplers(scene) {
                let Some((zero, zero_hi)) = self.zero_wait(b, scene, sampler) else {
                    continue;
                };
                let two = self.speedup(scene);
                // Frames a second at `c` cycles a pixel of which `stalls` wait
                // on memory: on the Pico 2's two cores at their speed-up, but
                // never faster than the one QSPI flash both share serves the
                // misses ([`two_cores`]).
                let fps = |c: f64, stalls: f64| {
                    let per_px = if b == Board::Pico2 {
                        two_cores(c, stalls, two)
                    } else {
                        c
                    };
                    hz / (per_px * px)
                };
                let cyc = |lo: f64, hi: Option<f64>| match hi {
                    Some(hi) => format!("{} to {}", thousands_rounded(lo), thousands_rounded(hi)),
                    None => thousands_rounded(lo),
                };
                let rate = |lo: f64, hi: Option<f64>, stalls: f64| match hi {
                    Some(hi) => format!("{:.1} to {:.1}", fps(hi, stalls), fps(lo, stalls)),
                    None => format!("{:.2}", fps(lo, stalls)),
                };
                let (flip, off) = accuracy
                    .iter()
                    .find(|a| a.0 == scene && a.1 == sampler)
                    .map_or(("(not run)", "(not run)"), |a| (a.2.as_str(), a.3.as_str()));
                let mut row = format!(
                    "| {} | {} | {flip} | {off} | {} | {} |",
                    scene.name(),
                    sampler,
                    cyc(zero, zero_hi),
                    rate(zero, zero_hi, 0.0)
                );
                let traced = self.traced(b, scene, sampler);
                for l in &layouts {
                    let Some(t) = traced.iter().find(|t| t.layout == *l) else {
                        row.push_str(" | | |");
                        continue;
                    };
                    let (lo, hi) = (zero + t.stalls_px, zero_hi.map(|h| h + t.stalls_px));
                    let _ = write!(
                        row,
                        " {:.0} | {} | {} |",
                        t.stalls_px,
                        cyc(lo, hi),
                        rate(lo, hi, t.stalls_px)
                    );
                    if matches!(b, Board::BlackPill | Board::Pico2) && *l != FLASH {
                        let _ = write!(row, " {:.0} |", t.shared_px);
                    }
                }
                let _ = writeln!(w, "{row}");
            }
        }
    }

    /// The traced rows of `scene` with `sampler` on board `b`, one a layout.
    fn traced(&self, b: Board, scene: Builtin, sampler: Sampler) -> Vec<&Traced> {
        self.memory
            .iter()
            .filter(|t| {
                t.board == b && t.run.scene == SceneRef::Builtin(scene) && t.run.sampler == sampler
            })
            .collect()
    }

    /// Zero-wait cycles a pixel of the frame run of `scene` with `sampler` on
    /// board `b` (and the top of the range on the Teensy): the Cortex-M4F's
    /// cycle model for that run; on the other cores their traced instructions
    /// times its cycles per instruction.
    fn zero_wait(&self, b: Board, scene: Builtin, sampler: Sampler) -> Option<(f64, Option<f64>)> {
        let r = Run {
            sampler,
            tile: TILE,
            ..Run::of(scene, FRAME, FRAME)
        };
        let j = self.runs.iter().position(|x| *x == r)?;
        let res = &self.exact.out.runs[j];
        let m4f_cyc = self.est[j] as f64 / res.pixels_count.max(1) as f64;
        let cpi = m4f_cyc / res.instructions_per_pixel().max(1.0);
        let instr = |b: Board| self.traced(b, scene, sampler).first().map(|t| t.instr_px);
        match b {
            Board::BlackPill => Some((m4f_cyc, None)),
            Board::Pico2 => Some((instr(b)? * cpi, None)),
            Board::Teensy41 => {
                let i = instr(b)?;
                Some((i / 2.0, Some(i * cpi)))
            }
        }
    }

    /// The dual-core speed-up measured for `scene` (1 when not measured).
    fn speedup(&self, scene: Builtin) -> f64 {
        self.dual
            .iter()
            .find(|c| c.scene == scene)
            .map_or(1.0, dualcore::SceneCounts::speedup)
    }

    /// Mean FLIP and the pixels off by more than 2 levels of the frame with
    /// `sampler` against the frame with the scene's own sampler (the chip's
    /// pixels, which are the host's); dashes for the scene's own sampler.
    fn accuracy(&self, scene: Builtin, sampler: Sampler) -> (String, String) {
        let own = scene.settings().sampler;
        if sampler == own {
            return ("(its own)".into(), "(its own)".into());
        }
        let frame = |s: Sampler| {
            let r = Run {
                sampler: s,
                tile: TILE,
                ..Run::of(scene, FRAME, FRAME)
            };
            let j = self.runs.iter().position(|x| *x == r)?;
            Some(&self.exact.out.runs[j].pixels)
        };
        let (Some(a), Some(b)) = (frame(own), frame(sampler)) else {
            return ("(not run)".into(), "(not run)".into());
        };
        let flip = tessera_host::compare::mean_flip(a, b)
            .map_or_else(|e| format!("({e})"), |f| format!("{f:.4}"));
        let off = a
            .pixels()
            .zip(b.pixels())
            .filter(|(p, q)| p.0.iter().zip(q.0).any(|(x, y)| x.abs_diff(y) > 2))
            .count();
        (flip, thousands(off as u64))
    }

    /// The animated scene's frames on the Cortex-M4F (the qemu example's
    /// frames of `scenes/examples/animated.toml`), each frame's set-up beside
    /// its render, and the estimated frame rate of the Pico 2 example, which
    /// plays that scene on both cores at 240x240.
    fn animation(&self, w: &mut String) {
        let Some(anim) = self.files.iter().find(|r| r.scene == ANIMATED) else {
            return;
        };
        let Self {
            runs,
            exact,
            est,
            cores,
            dual,
            ..
        } = self;
        let _ = writeln!(w, "\n## An animation's frames\n");
        // The teapot's cycles per instruction (the Cortex-M4 model), its
        // Cortex-M33 to Cortex-M4F instructions and its dual-core speed-up: the
        // built-in scene nearest the animation (the same mesh, a checkered floor).
        let teapot = Run {
            sampler: Centre,
            tile: TILE,
            ..Run::of(Builtin::Teapot, SIZE, SIZE)
        };
        let m33 = cores.iter().find(|c| c.core.title == "Cortex-M33");
        let (Some(j), Some(i), Some(m33)) = (
            runs.iter().position(|x| *x == teapot),
            core_runs().iter().position(|x| *x == teapot),
            m33,
        ) else {
            let _ = writeln!(w, "(the teapot or the Cortex-M33 was not measured)");
            return;
        };
        let m4f_px = exact.out.runs[j].instructions_per_pixel();
        let cpi = est[j] as f64 / exact.out.runs[j].pixels_count.max(1) as f64 / m4f_px.max(1.0);
        let m33_ratio = m33.out.runs[i].instructions_per_pixel() / m4f_px.max(1.0);
        let two = dual
            .iter()
            .find(|c| c.scene.name() == Builtin::Teapot.name())
            .map_or(1.0, dualcore::SceneCounts::speedup);
        let pixels = u64::from(anim.picture.width()) * u64::from(anim.picture.height());
        let _ = writeln!(
            w,
            "`{}` ({}x{}, {} pixels): a teapot turning and a ball bouncing, each an \
             instance of a mesh, moved by keyframes; the scene the Pico 2 example plays. \
             The qemu example renders frames at 0, 1/4, 1/2 and 3/4 of the animation \
             (each the host's frame of the same number, byte for byte: the example's \
             test), and counts each frame's set-up apart from its render: the moving \
             instances placed at the frame's time from the tracks in flash \
             (`ANIMATION.place`) and the frame's view made (`with_instances`). \
             **The Pico 2 columns are estimates, not measurements** (no board is here): \
             the Cortex-M4F's instructions a pixel times the teapot's cycles per \
             instruction by the Cortex-M4 model ({cpi:.3}) and its Cortex-M33 to \
             Cortex-M4F instructions ({m33_ratio:.3}: the built-in scene nearest this \
             one, the same mesh over a checkered floor), at 150 MHz on {} \
             pixels, one core, and two at the teapot's speed-up on both cores of \
             `mps2-an521` ({two:.3}); zero-wait memory, as the table above.\n",
            ANIMATED.strip_prefix("../../").unwrap_or(ANIMATED),
            anim.picture.width(),
            anim.picture.height(),
            thousands(pixels),
            thousands(pixels)
        );
        let _ = writeln!(
            w,
            "| frame | set-up, instructions | render, instructions | instr/px | set-up / render | Pico 2: est. cycles/px | one core: fps | two cores: fps |"
        );
        let _ = writeln!(w, "|---|---|---|---|---|---|---|---|");
        let mut per_px = Vec::new();
        for line in anim.stdout.lines().filter(|l| l.starts_with("frame=")) {
            let n = qemu_example::number(line, "frame");
            let setup = qemu_example::number(line, "setup");
            let render = qemu_example::number(line, "instructions");
            let instr_px = render as f64 / pixels.max(1) as f64;
            let cycles = instr_px * cpi * m33_ratio;
            let one = PICO2_HZ / (cycles * pixels as f64);
            per_px.push(cycles);
            let _ = writeln!(
                w,
                "| {n} | {} | {} | {} | {:.5} % | {} | {one:.2} | {:.2} |",
                thousands(setup),
                thousands(render),
                thousands_rounded(instr_px),
                100.0 * setup as f64 / render.max(1) as f64,
                thousands_rounded(cycles),
                two * one
            );
        }
        if !per_px.is_empty() {
            let mean = per_px.iter().sum::<f64>() / per_px.len() as f64;
            let teapot_stalls = self
                .traced(Board::Pico2, Builtin::Teapot, Centre)
                .iter()
                .find(|t| t.layout == Board::Pico2.shipped())
                .map(|t| t.stalls_px)
                .zip(
                    self.zero_wait(Board::Pico2, Builtin::Teapot, Centre)
                        .map(|z| z.0),
                );
            let _ = writeln!(
                w,
                "\nThe Pico 2 example's estimate, the mean of these frames: {} cycles a \
                 pixel, {:.2} frames a second on both cores. A frame's set-up is a few \
                 thousand instructions of a render's tens of millions. These are \
                 zero-wait figures: this scene file runs through the qemu example, \
                 which the memory trace does not arm. The Pico 2 example keeps \
                 tessera's code in SRAM, where what is left to wait on is the read-only \
                 data's misses in the XIP cache: of the traced scenes, the teapot's \
                 mesh tables cost the most, {} cycles a pixel, {:.1} % of its cycles \
                 ([the memory model](#frames-per-second-with-the-memory-model)).",
                thousands_rounded(mean),
                two * PICO2_HZ / (mean * pixels as f64),
                teapot_stalls.map_or_else(|| "(not traced)".into(), |(s, _)| thousands_rounded(s)),
                teapot_stalls.map_or(f64::NAN, |(s, z)| 100.0 * s / (s + z)),
            );
        }
    }

    /// What the sparse sampler saves, from the Cortex-M4F runs at the frame's
    /// own size ([`frame_runs`]): how much depends on the size (the larger the
    /// frame, the smoother the picture between two pixels), so it is measured
    /// at 240x240, against centre sampling at the same size.
    fn sparse_frames(&self, w: &mut String) {
        let Self {
            runs, exact, est, ..
        } = self;
        let _ = writeln!(
            w,
            "\n### With the sparse sampler\n\n`sampler = \"sparse\"` traces a ray through \
             a quarter of the pixels (both coordinates even) and interpolates each other \
             pixel from its traced neighbours where these met the same things and agree \
             within {} levels, else traces it too ([the sampler](../core/src/sample.rs); \
             its error against a converged picture is in [trade.md](trade.md)). Its saving \
             depends on the frame's size, so it is measured at {FRAME}x{FRAME} on the \
             Cortex-M4F (qemu, exact counts; cycles by the model, zero-wait), beside \
             centre sampling at the same size; camera rays counted on the host (the same \
             core code). The boards' frame rates with it, and with their memory paths, \
             are in [the memory model's tables](#frames-per-second-with-the-memory-model).\n",
            Sampler::SPARSE_THRESHOLD
        );
        let _ = writeln!(
            w,
            "`sampler = \"sparse:{t},4\"` starts from a coarser grid, a ray through every \
             pixel whose coordinates are both multiples of 4, and finds the other even \
             pixels from it the same way (on no texture), in the scenes whose every \
             primitive is sure to show at least 8 pixels across (the chapter's, and the \
             interference screen, whose texture keeps every even pixel traced; in the \
             others it is the same frame as `sparse`, and not listed).\n",
            t = Sampler::SPARSE_THRESHOLD
        );
        let _ = writeln!(
            w,
            "| scene | sampler | camera rays/px | M4F instr/px, centre | this sampler | est. cycles/px, centre | this sampler | against centre |"
        );
        let _ = writeln!(w, "|---|---|---|---|---|---|---|---|");
        let at = |b: Builtin, sampler: Sampler| {
            let r = Run {
                sampler,
                tile: TILE,
                ..Run::of(b, FRAME, FRAME)
            };
            let j = runs.iter().position(|x| *x == r)?;
            let res = &exact.out.runs[j];
            let n = res.pixels_count.max(1) as f64;
            Some((r, res.instructions_per_pixel(), est[j] as f64 / n))
        };
        for &b in Builtin::ALL {
            for sampler in frame_samplers(b).into_iter().skip(1) {
                let (Some((_, ci, cc)), Some((sr, si, sc))) = (at(b, Centre), at(b, sampler))
                else {
                    continue;
                };
                let rays = camera_rays(&sr).unwrap_or(f64::NAN);
                let _ = writeln!(
                    w,
                    "| {} | {sampler} | {rays:.2} | {ci:.0} | {si:.0} | {} | {} | {:.2} |",
                    b.name(),
                    thousands_rounded(cc),
                    thousands_rounded(sc),
                    sc / cc,
                );
            }
        }
    }

    /// Whole scene files on the chip, through the qemu example: instructions a
    /// pixel, stack, flash, the scene's tables and its images.
    fn scene_files(&self, w: &mut String) {
        let _ = writeln!(w, "\n## Scenes from files, textured models\n");
        let _ = writeln!(
            w,
            "The firmware a user starts from (`examples/qemu-m4f`, the same Cortex-M4F \
             board) built for each scene file as a user builds it (`TESSERA_SCENE=<file> \
             cargo build --release` with the core's features the scene needs: its build.rs \
             bakes the file into flash), run under qemu at the file's own size and \
             settings. Instructions are counted around each `render_tile_in` call as \
             above, over the whole frame. The stack is the firmware's peak from the top of \
             RAM over the run (`render_tile_in`, its scene view and renderer, `main`). \
             Flash is the whole firmware (vector table, `.text`, `.rodata`, `.data`); the \
             scene's tables are its baked statics (`SCENE`, materials, lights, meshes \
             with their BVH, images), in `.rodata`, of which the images are the \
             `IMAGE<k>` texel tables. Every picture is byte-identical to the host's \
             render of the same file.\n"
        );
        let _ = writeln!(
            w,
            "| scene file | what it holds | size | instructions | instr/px | stack | flash | scene tables | of which images |"
        );
        let _ = writeln!(w, "|---|---|---|---|---|---|---|---|---|");
        for (run, (_, what)) in self.files.iter().zip(SCENE_FILES) {
            let (width, height) = (run.picture.width(), run.picture.height());
            let pixels = u64::from(width) * u64::from(height);
            let instructions = run.number("instructions");
            let tables: u64 = run.tables().iter().map(|t| t.size).sum();
            // Named from the repository's root.
            let scene = run.scene.strip_prefix("../../").map_or_else(
                || format!("examples/qemu-m4f/{}", run.scene),
                str::to_string,
            );
            let _ = writeln!(
                w,
                "| `{scene}` | {what} | {width}x{height} | {} | {} | {} | {} | {} | {} |",
                thousands(instructions),
                thousands(instructions / pixels.max(1)),
                thousands(run.number("stack")),
                thousands(run.sizes.flash()),
                thousands(tables),
                thousands(run.image_bytes()),
            );
        }
        let _ = writeln!(
            w,
            "\nThe images are resized at bake time to the scene's `texture_budget` and \
             stored in its `texture_format` (scenes/README.md). These figures are the \
             chip's instructions, not an estimate of a board's cycles: the cycle model \
             above runs on the test firmware's profile, which renders the built-in \
             scenes only."
        );
    }

    /// Instances against meshes baked in world space, from the scene files'
    /// runs: the same picture, the cost of each, and a frame's set-up of a
    /// moved instance.
    fn instances(&self, w: &mut String) {
        let run = |scene: &str| self.files.iter().find(|r| r.scene == scene);
        let (Some(world1), Some(once), Some(world4), Some(four)) = (
            run("../../scenes/teapot.toml"),
            run(TEAPOT_ONCE),
            run(TEAPOTS_WORLD),
            run(TEAPOTS_INSTANCED),
        ) else {
            return;
        };
        let _ = writeln!(w, "\n## Mesh instances against meshes in world space\n");
        let _ = writeln!(
            w,
            "A mesh drawn through instances (`[[instance]]`, the core's feature \
             `instances`) is searched in its own space: each instance's box in the world \
             is tested, then the ray is carried into the mesh's space and its BVH searched \
             there, and the nearest hit carried back. The same qemu example runs as above \
             (instructions around `render_tile_in`, the whole frame); the pictures of the \
             two ways are compared byte for byte here.\n"
        );
        let _ = writeln!(
            w,
            "| teapots | drawn as | instructions | instr/px | flash | scene tables | pixels that differ from world space |"
        );
        let _ = writeln!(w, "|---|---|---|---|---|---|---|");
        for (n, how, r, base) in [
            (
                1,
                "a mesh in world space (`scenes/teapot.toml`)",
                world1,
                world1,
            ),
            (1, "one instance of the mesh", once, world1),
            (4, "four meshes in world space", world4, world4),
            (4, "four instances of one mesh", four, world4),
        ] {
            let pixels = u64::from(r.picture.width()) * u64::from(r.picture.height());
            let instructions = r.number("instructions");
            let tables: u64 = r.tables().iter().map(|t| t.size).sum();
            let differ = r
                .picture
                .pixels()
                .zip(base.picture.pixels())
                .filter(|(a, b)| a != b)
                .count();
            let max = r
                .picture
                .pixels()
                .zip(base.picture.pixels())
                .flat_map(|(a, b)| a.0.iter().zip(b.0).map(|(x, y)| x.abs_diff(y)))
                .max()
                .unwrap_or(0);
            let diff = if std::ptr::eq(r, base) {
                "(the base)".to_string()
            } else {
                format!("{differ} (by at most {max} levels)")
            };
            let _ = writeln!(
                w,
                "| {n} | {how} | {} | {} | {} | {} | {diff} |",
                thousands(instructions),
                thousands(instructions / pixels.max(1)),
                thousands(r.sizes.flash()),
                thousands(tables),
            );
        }
        let moved: Vec<String> = self
            .files
            .iter()
            .filter_map(|r| {
                let line = r
                    .stdout
                    .lines()
                    .find(|l| l.starts_with("moving an instance:"))?;
                let scene = r.scene.strip_prefix("../../").unwrap_or(r.scene);
                Some(format!(
                    "| `{scene}` | {} | {} | {} | {} | {} |",
                    thousands(qemu_example::number(line, "instances")),
                    thousands(qemu_example::number(line, "copy")),
                    thousands(qemu_example::number(line, "set")),
                    thousands(qemu_example::number(line, "view")),
                    thousands(r.number("instructions")),
                ))
            })
            .collect();
        if !moved.is_empty() {
            let _ = writeln!(
                w,
                "\nA frame that moves an instance (the qemu example, after its render, with \
                 the feature `instances`): the scene's instances copied into RAM once \
                 (`Instances::of(&view)`), one moved (`set`: its transforms and its box \
                 worked out again from its rotation, scale and translation, checked) and \
                 handed to the view (`with_instances`). Instructions, beside the frame's \
                 render:\n"
            );
            let _ = writeln!(
                w,
                "| scene file | instances | `Instances::of` (once) | `set` (one moved) | `with_instances` | the frame's render |"
            );
            let _ = writeln!(w, "|---|---|---|---|---|---|");
            for row in moved {
                let _ = writeln!(w, "{row}");
            }
        }
    }

    /// A frame's set-up on each baked scene: the whole view checked again
    /// against one changed list, beside the frame's render.
    fn frame_setup(&self, w: &mut String) {
        let _ = writeln!(w, "\n## A frame's set-up: what moves\n");
        let _ = writeln!(
            w,
            "A firmware that moves something builds each frame's view. Rebuilding the whole \
             baked scene (`SCENE.view()` and its camera: every table checked, a mesh's \
             faces and BVH among them) costs what the scene holds; handing the view one \
             changed list (`view.with_lights(&lights)`, `view.with_list(&spheres)`: a RAM \
             copy of that table, changed) checks that list alone. Measured by the firmware \
             after each baked scene's run (the same clock as above; these lists unchanged, \
             so the figures are the checks' and the copy is the caller's), beside that \
             run's render at {SIZE}x{SIZE} with the scene's own settings. Instructions:\n"
        );
        let _ = writeln!(
            w,
            "| scene | lights | spheres | planes | `SCENE.view()` | `with_lights` | `with_list` (spheres) | `with_list` (planes) | the frame's render |"
        );
        let _ = writeln!(w, "|---|---|---|---|---|---|---|---|---|");
        for (r, res) in self.runs.iter().zip(&self.exact.out.runs) {
            let (SceneRef::Baked(b), Some(s)) = (r.scene, res.setup) else {
                continue;
            };
            let (lights, spheres, planes) = b
                .with_baked_scene(|v, _| (v.lights().len(), v.spheres().len(), v.planes().len()))
                .unwrap_or_default();
            let _ = writeln!(
                w,
                "| {} | {lights} | {spheres} | {planes} | {} | {} | {} | {} | {} |",
                b.name(),
                thousands(s.view),
                thousands(s.lights),
                thousands(s.spheres),
                thousands(s.planes),
                thousands(res.instructions),
            );
        }
    }

    /// How to regenerate the document.
    fn regenerate(&self, w: &mut String) {
        let Self { exact, fast, .. } = self;
        let _ = writeln!(w, "\n## Regenerate\n");
        let _ = writeln!(w, "```sh\n{COMMAND}\n```");
        let _ = writeln!(
            w,
            "\nIt needs `qemu-system-arm`, `qemu-system-riscv32` and the targets \
         `thumbv7em-none-eabihf`, `thumbv8m.main-none-eabihf` and \
         `riscv32imafc-unknown-none-elf` (`bash tests/run-all.sh` installs them). \
         ELFs: `{}` and `{}`.",
            repo_relative(&exact.elf),
            repo_relative(&fast.elf)
        );
    }
}

/// Compares the other cores' counts of the guarded runs with their baseline file
/// and prints the table; with `bless`, rewrites the file from these counts instead.
fn guard_cores(cores: &[CoreMeasure], bless: bool, qemu: &str) -> Result<(), String> {
    let mut now = Vec::new();
    for c in cores {
        for g in baseline::runs() {
            let i = core_runs()
                .iter()
                .position(|r| *r == g)
                .ok_or_else(|| format!("the guarded run {g} is not in the per-core runs"))?;
            now.push((baseline::key(&c.core, &g), c.out.runs[i].instructions));
        }
    }
    let text = bless.then(|| baseline::render_cores(&now, qemu));
    bless_or_compare(
        &baseline::cores_path(),
        text,
        qemu,
        &now,
        &format!(
            "instruction counts of the other cores against {}",
            baseline::CORES_FILE
        ),
    )
}

/// Compares the guarded runs' counts with the baseline file and prints the table;
/// with `bless`, rewrites the file from these counts instead.
fn guard(runs: &[Run], out: &Output, bless: bool, qemu: &str) -> Result<(), String> {
    let mut now = Vec::new();
    for g in baseline::runs() {
        let i = runs
            .iter()
            .position(|r| *r == g)
            .ok_or_else(|| format!("the guarded run {g} is not in the run list"))?;
        now.push((g.to_string(), out.runs[i].instructions));
    }
    let text = bless.then(|| baseline::render(&now, qemu));
    bless_or_compare(
        &baseline::path(),
        text,
        qemu,
        &now,
        &format!("instruction counts against {}", baseline::FILE),
    )
}

/// Writes `blessed` to the baseline file `path` when given (a bless run), else
/// prints `now` against the file's counts under `title` (an error when the file
/// was counted under another qemu series than `qemu`).
fn bless_or_compare(
    path: &std::path::Path,
    blessed: Option<String>,
    qemu: &str,
    now: &[(String, u64)],
    title: &str,
) -> Result<(), String> {
    if let Some(text) = blessed {
        std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
        println!(
            "wrote {} (commit it with a message that says why)",
            path.display()
        );
        return Ok(());
    }
    match std::fs::read_to_string(path) {
        Ok(text) => {
            baseline::same_qemu(&path.display().to_string(), &text, qemu)?;
            let base = baseline::parse(&text)?;
            println!(
                "{title}:\n{}",
                baseline::Comparison::new(&base, now).table()
            );
        }
        Err(e) => println!("no baseline to compare with ({}: {e})", path.display()),
    }
    Ok(())
}
