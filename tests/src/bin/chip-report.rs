//! `chip-report`: measures tessera on a Cortex-M4F and writes `docs/chip-cost.md`.
//!
//! Builds the firmware test image with both math backends, runs every built-in
//! scene with five samplers at 64x64 (chapter-reflect also at depths 0, 1 and 3)
//! under qemu, twice per backend, and writes the instructions per pixel, the ELF
//! section sizes, the peak stack and the flash/RAM budget. Fails if the two passes
//! disagree on any count or if the exact backend's pixels differ from the host's.
//!
//! ```sh
//! cargo run -p tessera-tests --release --bin chip-report
//! ```

use image::RgbImage;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;
use tessera::Viewport;
use tessera::builtin::Builtin;
use tessera::{Sampler, Sampler::*};
use tessera_tests::firmware::{self, Output, Run, Sizes};

const COMMAND: &str = "cargo run -p tessera-tests --release --bin chip-report";
const SAMPLERS: [Sampler; 5] = [Corner, Centre, Stratified(2), Stratified(4), Random(4)];
const SIZE: u16 = 64;
const TILE: usize = 16;

fn main() -> ExitCode {
    match report() {
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
/// each sampler.
fn runs() -> Vec<Run> {
    let mut runs = Vec::new();
    for b in Builtin::ALL {
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
    runs
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

fn host(run: &Run) -> Result<RgbImage, String> {
    let vp = Viewport::new(run.width, run.height);
    run.scene
        .with_scene(|view, cam| tessera_host::render(view, cam, vp, run.settings(), run.tile))
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

fn thousands(n: u64) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

fn report() -> Result<PathBuf, String> {
    let qemu = firmware::qemu_version()?;
    let rustc = tessera_tests::tool_version("rustc");
    let (flash, ram) = firmware::memory_budget()?;
    println!("building the firmware (exact and fast-math)...");
    let exact_elf = firmware::build(false)?;
    let fast_elf = firmware::build(true)?;
    let runs = runs();
    println!("running {} renders x 2 passes x 2 backends...", runs.len());
    let (exact, fast) = std::thread::scope(|s| {
        let e = s.spawn(|| measure(exact_elf, &runs));
        let f = s.spawn(|| measure(fast_elf, &runs));
        let join = |h: std::thread::ScopedJoinHandle<'_, Result<Backend, String>>| {
            h.join()
                .unwrap_or_else(|_| Err("a measuring thread panicked".into()))
        };
        (join(e), join(f))
    });
    let (exact, fast) = (exact?, fast?);

    // The exact backend is bit-identical to the host build.
    for (r, res) in runs.iter().zip(&exact.out.runs) {
        if host(r)?.as_raw() != res.pixels.as_raw() {
            return Err(format!("{r}: the chip's pixels differ from the host's"));
        }
    }

    let mut d = String::new();
    let w = &mut d;
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
        "- Budget (`tests/firmware/memory.x`): {} of flash, {} of RAM; the link fails \
         if the image does not fit.",
        kib(flash),
        kib(ram)
    );
    let _ = writeln!(
        w,
        "- Renders: {SIZE}x{SIZE} pixels, tiles of {TILE}x{TILE} in row-major order into \
         one static buffer, seed 0.\n"
    );
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
         higher.\n"
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

    let _ = writeln!(w, "## Instructions per pixel\n");
    let _ = writeln!(
        w,
        "`exact` is the default backend (libm, `vsqrt.f32`), `fast-math` the micromath \
         approximations (`--features fast-math`); the last two columns compare the \
         fast-math image with the exact one (largest channel difference in LSB, PSNR).\n"
    );
    let _ = writeln!(
        w,
        "| scene | depth | sampler | rays/px | exact instr/px | exact instr/ray | fast-math instr/px | fast/exact | max diff | PSNR |"
    );
    let _ = writeln!(w, "|---|---|---|---|---|---|---|---|---|---|");
    for ((r, e), f) in runs.iter().zip(&exact.out.runs).zip(&fast.out.runs) {
        let spp = r.sampler.count();
        let (max, psnr) = difference(&e.pixels, &f.pixels);
        let psnr = psnr.map_or_else(|| "identical".to_string(), |p| format!("{p:.1} dB"));
        let _ = writeln!(
            w,
            "| {} | {} | {} | {} | {:.0} | {:.0} | {:.0} | {:.2} | {} | {} |",
            r.scene.name(),
            r.depth,
            r.sampler_text()?,
            spp,
            e.instructions_per_pixel(),
            e.instructions_per_pixel() / f64::from(spp),
            f.instructions_per_pixel(),
            f.instructions as f64 / e.instructions.max(1) as f64,
            max,
            psnr
        );
    }

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
         `Frame`. Each figure is the largest over the scene's runs.\n"
    );
    let _ = writeln!(
        w,
        "| scene | exact: render_tile | exact: peak - harness | fast-math: render_tile | fast-math: peak - harness |"
    );
    let _ = writeln!(w, "|---|---|---|---|---|");
    for b in Builtin::ALL {
        let worst = |be: &Backend, f: &dyn Fn(&firmware::RunResult) -> u64| {
            runs.iter()
                .zip(&be.out.runs)
                .filter(|(r, _)| r.scene == b)
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
            thousands(worst(&exact, &render)),
            thousands(worst(&exact, &scene)),
            thousands(worst(&fast, &render)),
            thousands(worst(&fast, &scene))
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
        thousands(base(&exact)),
        thousands(base(&fast)),
        thousands(exact.out.stack_available)
    );
    let _ = writeln!(w, "\n## Regenerate\n");
    let _ = writeln!(w, "```sh\n{COMMAND}\n```");
    let _ = writeln!(
        w,
        "\nIt needs `qemu-system-arm` and the `thumbv7em-none-eabihf` target (`bash \
         tests/run-all.sh` installs both). ELFs: `{}` and `{}`.",
        rel(&exact.elf),
        rel(&fast.elf)
    );

    let path = firmware::repo_root().join("docs").join("chip-cost.md");
    std::fs::write(&path, d).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    Ok(path)
}

/// `p` relative to the repository root, for the document.
fn rel(p: &std::path::Path) -> String {
    let root = firmware::repo_root();
    let root = root.canonicalize().unwrap_or(root);
    let p = p.canonicalize().unwrap_or_else(|_| p.to_path_buf());
    p.strip_prefix(&root).unwrap_or(&p).display().to_string()
}
