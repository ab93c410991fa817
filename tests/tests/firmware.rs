//! The core on a Cortex-M4F: the firmware test image (`tests/firmware`) under qemu
//! (`mps2-an386`) renders the built-in scenes byte for byte like the host, with
//! repeatable instruction counts.
//!
//! These tests need `qemu-system-arm` and the `thumbv7em-none-eabihf` target; without
//! them they fail and say to run `bash tests/run-all.sh`, which installs both.

use image::RgbImage;
use std::path::PathBuf;
use std::sync::OnceLock;
use tessera_core::Viewport;
use tessera_core::builtin::Builtin;
use tessera_core::testing::Extreme;
use tessera_core::{Sampler, Sampler::*};
use tessera_tests::baseline;
use tessera_tests::firmware::{self, Output, Run, SceneRef};

/// The exact-math firmware, built once for every test of this binary.
fn elf() -> PathBuf {
    static ELF: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    ELF.get_or_init(|| {
        firmware::qemu_version()?;
        firmware::build(&[])
    })
    .clone()
    .unwrap_or_else(|e| panic!("{e}"))
}

fn run(runs: &[Run]) -> Output {
    firmware::run(&elf(), runs).unwrap_or_else(|e| panic!("{e}"))
}

/// The host build of the core, same settings and tile size; a baked scene
/// (its `static` tables on the chip) as the host builds it in RAM.
pub(crate) fn host(run: &Run) -> RgbImage {
    let vp = Viewport::new(run.width, run.height);
    let scene = match run.scene {
        SceneRef::Baked(b) => SceneRef::Builtin(b),
        s => s,
    };
    scene
        .with_scaled_scene(run.scale, |view, cam| {
            tessera_host::render(view, cam, vp, run.settings(), run.tile)
        })
        .unwrap()
        .unwrap()
}

fn with(scene: Builtin, sampler: Sampler, seed: u32, width: u16, height: u16) -> Run {
    Run {
        sampler,
        seed,
        ..Run::of(scene, width, height)
    }
}

/// The renders whose pixels must equal the host's on every core: each built-in
/// scene with four samplers, every tile size, both encodings, the baked scenes,
/// the extremes battery.
pub(crate) fn identity_runs() -> Vec<Run> {
    let mut runs = Vec::new();
    for &b in Builtin::ALL {
        let adaptive = Adaptive { k: 2, threshold: 8 };
        for sampler in [
            Centre,
            Stratified(2),
            Random(3),
            adaptive,
            Sampler::sparse(),
        ] {
            runs.push(with(b, sampler, 7, 64, 64));
        }
    }
    // The two other tile sizes, at a size where the edge tiles are partial.
    runs.push(Run {
        tile: 8,
        ..with(Builtin::ChapterReflect, Stratified(2), 1, 77, 53)
    });
    runs.push(Run {
        tile: 32,
        ..with(Builtin::Showcase, Random(2), 3, 77, 53)
    });
    // Linear output (the tile loops of the other encoding), each tile size, and
    // the adaptive sampler, which compares encoded pixels.
    for (b, sampler, tile) in [
        (Builtin::ChapterReflect, Centre, 16),
        (Builtin::Showcase, Stratified(2), 8),
        (Builtin::Teapot, Centre, 32),
        (Builtin::ChapterDirect, Adaptive { k: 2, threshold: 8 }, 16),
        (Builtin::ChapterReflect, Sampler::sparse(), 8),
    ] {
        runs.push(Run {
            tile,
            encoding: tessera_core::Encoding::Linear,
            ..with(b, sampler, 5, 77, 53)
        });
    }
    // The built-in scenes from their baked `static` tables (flash), at their
    // own settings: the chip's pixels equal the host's scene built in RAM.
    for &b in Builtin::ALL {
        runs.push(Run::of(SceneRef::Baked(b), 64, 48));
    }
    // The extremes battery's scenes (cases 13 and 14): surfaces far larger than
    // their distance, whose hits take the f64 paths (software on this chip), and
    // subnormal numbers in every kind of input, read as zeros.
    for e in Extreme::ALL {
        runs.push(Run::of(e, 48, 36));
    }
    runs
}

/// The clock of `core`'s image counts instructions at the core's rate: the
/// calibration loop's known length, to a tick (and the few instructions of
/// reading the clock).
pub(crate) fn assert_clock(core: &firmware::Core, out: &Output) {
    let tick = core.tick;
    let measured = tick.instructions(out.calibration_ticks);
    assert!(
        measured.abs_diff(out.calibration_instructions)
            <= tick.instructions.div_ceil(tick.ticks) + 8,
        "{}: a loop of {} instructions took {} ticks, {} instructions at {}/{} a tick",
        core.title,
        out.calibration_instructions,
        out.calibration_ticks,
        measured,
        tick.instructions,
        tick.ticks
    );
}

/// The runs whose chip pixels differ from the host's, one line each; both images
/// of each are saved in target/test-images as `<prefix>-<i>-chip.png` and
/// `<prefix>-<i>-host.png`.
pub(crate) fn differences(prefix: &str, runs: &[Run], out: &Output) -> Vec<String> {
    let mut bad = Vec::new();
    for (i, (r, chip)) in runs.iter().zip(&out.runs).enumerate() {
        let want = host(r);
        if want.as_raw() != chip.pixels.as_raw() {
            let differ = want
                .pixels()
                .zip(chip.pixels.pixels())
                .filter(|(a, b)| a != b)
                .count();
            let dir = tessera_tests::output_dir();
            let _ = chip.pixels.save(dir.join(format!("{prefix}-{i}-chip.png")));
            let _ = want.save(dir.join(format!("{prefix}-{i}-host.png")));
            bad.push(format!("run {i} ({r}): {differ} pixels differ"));
        }
    }
    bad
}

#[test]
fn firmware_pixels_equal_the_host_build_byte_for_byte() {
    let runs = identity_runs();
    let out = run(&runs);
    let bad = differences("firmware", &runs, &out);
    assert!(
        bad.is_empty(),
        "chip and host differ (images in target/test-images):\n{}",
        bad.join("\n")
    );
    // A frame's set-up on each baked scene: measured once a run, and a
    // changed list (lights, spheres) checks that list alone, far less than
    // the whole scene's view (its every table, the teapot's mesh and BVH).
    for (run, r) in runs.iter().zip(&out.runs) {
        match (run.scene, r.setup) {
            (SceneRef::Baked(b), Some(s)) => {
                assert!(s.view > 0 && s.lights > 0, "{}: {s:?}", run.scene.name());
                assert!(
                    4 * s.lights < s.view && 4 * s.spheres < s.view,
                    "{}: a changed list costs as much as the whole view: {s:?}",
                    run.scene.name()
                );
                if b == Builtin::Teapot {
                    assert!(100 * s.lights < s.view, "teapot: {s:?}");
                }
            }
            (SceneRef::Baked(_), None) => panic!("{}: no set-up line", run.scene.name()),
            (_, Some(s)) => panic!("{}: a set-up line {s:?}", run.scene.name()),
            (_, None) => {}
        }
    }
}

/// The core's square root (`vsqrt.f32`) is correctly rounded on the chip: hard
/// cases, special values and pseudo-random inputs (`tessera-sqrt`), the same bits
/// as the host's.
#[test]
fn sqrt_is_correctly_rounded_on_the_chip() {
    let sqrt =
        firmware::check_sqrt(&firmware::CORTEX_M4F, &elf()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(sqrt, firmware::SqrtReport::host());
}

#[test]
fn instruction_counts_repeat_exactly() {
    let runs = [
        Run::of(Builtin::ChapterReflect, 32, 32),
        with(Builtin::Showcase, Random(2), 5, 32, 24),
        Run {
            tile: 8,
            ..Run::of(Builtin::Interference, 40, 24)
        },
    ];
    let (a, b) = (run(&runs), run(&runs));
    for (i, (x, y)) in a.runs.iter().zip(&b.runs).enumerate() {
        assert_eq!(x.ticks, y.ticks, "run {i}: ticks");
        assert_eq!(x.stack, y.stack, "run {i}: stack");
        assert_eq!(x.pixels.as_raw(), y.pixels.as_raw(), "run {i}: pixels");
    }
    assert_eq!(a.calibration_ticks, b.calibration_ticks);
}

#[test]
fn counts_are_sane_and_deeper_recursion_costs_more() {
    let depth = |depth| Run {
        depth,
        ..Run::of(Builtin::ChapterReflect, 32, 32)
    };
    let runs = [
        depth(0),
        depth(1),
        depth(3),
        with(Builtin::ChapterReflect, Stratified(2), 0, 32, 32),
    ];
    let out = run(&runs);
    // SysTick ticks once every 40 instructions (the calibration loop's length is
    // known to the instruction).
    let measured = out.calibration_ticks * firmware::INSTRUCTIONS_PER_TICK;
    assert!(
        measured.abs_diff(out.calibration_instructions) <= firmware::INSTRUCTIONS_PER_TICK,
        "calibration: {} instructions took {} ticks",
        out.calibration_instructions,
        out.calibration_ticks
    );
    for (r, res) in runs.iter().zip(&out.runs) {
        assert!(res.ticks > 0, "{r}: no ticks");
        assert_eq!(res.pixels_count, 32 * 32, "{r}");
        assert_eq!(
            res.instructions,
            res.ticks * firmware::INSTRUCTIONS_PER_TICK
        );
        assert!(
            0 < res.stack_base
                && 0 < res.stack_render
                && res.stack_base + res.stack_render < res.stack
                && res.stack <= out.stack_peak,
            "{r}: stack {} base {} render {} peak {}",
            res.stack,
            res.stack_base,
            res.stack_render,
            out.stack_peak
        );
    }
    assert!(out.stack_peak < out.stack_available);
    let cost: Vec<u64> = out.runs.iter().map(|r| r.instructions).collect();
    assert!(
        cost[0] < cost[1] && cost[1] < cost[2],
        "depth 0, 1, 3: {cost:?}"
    );
    // Four samples a pixel cost more than three times one.
    assert!(cost[3] > 3 * cost[1], "centre vs stratified:2: {cost:?}");
}

/// Regression guard: the exact instruction counts of the guarded runs (each scene
/// at 64x64 with its own settings, and chapter-direct stratified 4x4) rise by at
/// most 2% over `tests/chip-baseline.txt`. A fall of more than 2% passes with a
/// note to regenerate the baseline. (The file was written by `chip-report` from
/// its own run list, where each run starts at another SysTick phase: counts differ
/// from this list's by at most a tick, 40 instructions, a tile.)
#[test]
fn instruction_counts_stay_within_the_baseline() {
    let path = baseline::path();
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()));
    let qemu = firmware::qemu_version().unwrap_or_else(|e| panic!("{e}"));
    baseline::same_qemu(baseline::FILE, &text, &qemu).unwrap_or_else(|e| panic!("{e}"));
    let base = baseline::parse(&text).unwrap_or_else(|e| panic!("{e}"));
    let runs = baseline::runs();
    let out = run(&runs);
    let now: Vec<(String, u64)> = runs
        .iter()
        .zip(&out.runs)
        .map(|(r, res)| (r.to_string(), res.instructions))
        .collect();
    let cmp = baseline::Comparison::new(&base, &now);
    let table = cmp.table();
    println!("instruction counts against {}:\n{table}", baseline::FILE);
    assert!(
        cmp.failures().is_empty(),
        "instruction counts rose over {}:\n{table}",
        baseline::FILE
    );
    // The generated page is current: its instructions per pixel are these
    // runs' (64x64 pixels), within 2 % either way.
    let page = firmware::repo_root().join("docs").join("chip-cost.md");
    let text = std::fs::read_to_string(&page).expect("docs/chip-cost.md");
    let stale: Vec<String> = runs
        .iter()
        .zip(&out.runs)
        .filter_map(|(r, res)| {
            let now = res.instructions as f64 / f64::from(r.width) / f64::from(r.height);
            let said = page_instr_per_px(&text, r.scene.name(), r.depth, &r.sampler.to_string());
            let close = said.is_some_and(|x| (x - now).abs() <= 0.02 * now + 1.0);
            (!close).then(|| format!("{r}: the page says {said:?}, the chip {now:.0}"))
        })
        .collect();
    assert!(
        stale.is_empty(),
        "docs/chip-cost.md is not current (regenerate it: cargo run -p tessera-tests \
         --release --bin chip-report): {stale:#?}"
    );
}

/// `docs/chip-cost.md`'s exact instructions per pixel of `scene` at `depth` with
/// `sampler` (its table "Instructions per pixel").
fn page_instr_per_px(text: &str, scene: &str, depth: u8, sampler: &str) -> Option<f64> {
    let table = text.split("## Instructions per pixel").nth(1)?;
    // The section's first table only.
    let mut lines = table
        .lines()
        .skip_while(|l| !l.starts_with('|'))
        .take_while(|l| l.starts_with('|'));
    let cells = |l: &str| -> Vec<String> {
        l.trim_matches('|')
            .split('|')
            .map(|c| c.trim().to_string())
            .collect()
    };
    let header = cells(lines.next()?);
    let at = |name: &str| header.iter().position(|h| h == name);
    let (s, d, p, x) = (
        at("scene")?,
        at("depth")?,
        at("sampler")?,
        at("exact instr/px")?,
    );
    lines
        .map(cells)
        .find(|c| {
            let is = |i: usize, want: &str| c.get(i).is_some_and(|x| x == want);
            is(s, scene) && is(d, &depth.to_string()) && is(p, sampler)
        })
        .and_then(|c| c.get(x)?.replace(',', "").parse().ok())
}

/// Extreme scales on the chip (case 12 of docs/extremes.md): every built-in scene
/// scaled by 2^k at the ends of the supported range gives, on the Cortex-M4F, the
/// same bits as the host build and as the unscaled scene.
#[test]
fn extreme_scales_render_the_same_bits_on_the_chip() {
    let mut runs = Vec::new();
    // The teapot scaled is a copy of its mesh and a BVH built in RAM (about 120
    // KiB of stack, more than this chip has): the host checks it (the extremes
    // battery's scales and the culling tests).
    for b in Builtin::ALL
        .iter()
        .copied()
        .filter(|&b| b != Builtin::Teapot)
    {
        // The interference screen's near distance (0.01) reaches the smallest
        // supported length (2^-52) first: its range starts at k = -45.
        let low = if b == Builtin::Interference { -45 } else { -48 };
        for scale in [0, low, -20, 20, 48] {
            runs.push(Run {
                scale,
                ..with(b, Centre, 3, 48, 36)
            });
        }
    }
    let out = run(&runs);
    for (r, got) in runs.iter().zip(&out.runs) {
        let want = host(r);
        assert!(
            got.pixels.as_raw() == want.as_raw(),
            "{} at 2^{}: chip differs from host",
            r.scene.name(),
            r.scale
        );
        let unscaled = host(&Run { scale: 0, ..*r });
        assert!(
            want.as_raw() == unscaled.as_raw(),
            "{} at 2^{}: not scale invariant",
            r.scene.name(),
            r.scale
        );
    }
}

/// The teapot alone (`tests/firmware/src/teapot.rs`, a firmware as a user would
/// write it: the whole scene baked in flash, one 16x16 tile buffer) renders the
/// host's pixels (the scene built in RAM on the host) and needs at most 8 KiB of RAM beyond its
/// tile buffer: statics (from the ELF) plus the peak stack of the whole program.
#[test]
fn the_teapot_alone_needs_under_8_kib_beyond_its_tile() {
    let exact = elf();
    let alone = exact.with_file_name("tessera-teapot");
    let out = firmware::run_alone(&alone).unwrap_or_else(|e| panic!("{e}"));
    let field = |name: &str| -> String {
        out.split_whitespace()
            .find_map(|w| w.strip_prefix(name))
            .unwrap_or_else(|| panic!("no {name} in {out:?}"))
            .to_string()
    };
    let stack: u64 = field("stack=").parse().unwrap();
    let checksum = u32::from_str_radix(&field("checksum="), 16).unwrap();
    // The host build of the core, the same tiles in the same order.
    let b = Builtin::Teapot;
    let want = b
        .with_scene(|view, cam| {
            let renderer =
                tessera_core::Renderer::try_new(cam, Viewport::new(64, 64), b.settings()).unwrap();
            let (across, down) = renderer.tile_grid(16);
            let mut tile = tessera_core::Tile::<16>::new();
            let mut hash = 0x811c_9dc5_u32;
            for ty in 0..down {
                for tx in 0..across {
                    let coord = tessera_core::TileCoord::new(tx, ty);
                    renderer
                        .render_tile(view, coord, &mut tile, &mut ())
                        .unwrap();
                    for p in tile.pixels() {
                        for byte in [p.r, p.g, p.b] {
                            hash = (hash ^ u32::from(byte)).wrapping_mul(0x0100_0193);
                        }
                    }
                }
            }
            hash
        })
        .unwrap();
    assert_eq!(
        checksum, want,
        "the teapot alone: chip pixels differ from the host"
    );
    let sizes = firmware::sections(&alone).unwrap();
    let tile = size_of::<tessera_core::Tile<16>>() as u64;
    let statics = sizes.ram() - tile;
    println!(
        "teapot alone: flash {} bytes, statics {} bytes beyond the {tile}-byte tile, stack \
         peak {stack} bytes: {} bytes of RAM beyond the tile",
        sizes.flash(),
        statics,
        statics + stack
    );
    assert!(
        statics + stack <= 8 * 1024,
        "the teapot alone needs {statics} + {stack} bytes beyond its tile, more than 8 KiB"
    );
    // The progressive first picture: one ray per 4x4 block, about a sixteenth of
    // the tiles' work.
    let preview: u64 = field("preview=").parse().unwrap();
    let render: u64 = field("render=").parse().unwrap();
    println!(
        "teapot alone, 64x64: first picture (one ray per 4x4 block) {preview} \
         instructions, the tiles {render} ({:.1} %)",
        100.0 * preview as f64 / render as f64
    );
    assert!(
        preview > 0 && preview * 10 < render,
        "{preview} vs {render}"
    );
}

/// The staleness check reads the page's table by scene, depth and sampler
/// (columns found by their headers), and finds nothing where the page has no row.
#[test]
fn the_cost_pages_figures_are_read_by_scene_depth_and_sampler() {
    let text = "# x\n## Instructions per pixel\n\ntext\n\n\
                | scene | depth | sampler | rays/px | exact instr/px | est. |\n\
                |---|---|---|---|---|---|\n\
                | a | 0 | centre | 1 | 458 | 847 |\n\
                | a | 1 | centre | 1 | 1,545 | 1001 |\n\
                | b | 0 | stratified:4 | 16 | 7203 | 9 |\n\n## Next\n| a | 0 | centre | 1 | 9 |\n";
    assert_eq!(page_instr_per_px(text, "a", 0, "centre"), Some(458.0));
    assert_eq!(page_instr_per_px(text, "a", 1, "centre"), Some(1545.0));
    assert_eq!(
        page_instr_per_px(text, "b", 0, "stratified:4"),
        Some(7203.0)
    );
    assert_eq!(page_instr_per_px(text, "b", 0, "centre"), None);
    assert_eq!(page_instr_per_px("no table", "a", 0, "centre"), None);
    // A row of a later table is not the section's.
    let later = text.replace("| a | 1 | centre | 1 | 1,545 | 1001 |\n", "");
    let later = later.replace("## Next\n", "## Next\n| a | 1 | centre | 1 | 77 | 0 |\n");
    assert_eq!(page_instr_per_px(&later, "a", 1, "centre"), None);
}

/// The memory model's address stream (`tests/profiler/mem_trace.c`, read by
/// `tessera_tests::memory::trace`) covers the render that SysTick counts: its
/// fetch runs add up to the same instructions (within the markers' calls, as
/// the instruction profile's do), it was armed once a tile, the frame is the
/// host's; and the boards' paths make of it what their layouts say: nothing to
/// wait for with everything in RAM, stalls from flash, all of them in the
/// image's symbols.
#[test]
fn the_memory_models_stream_counts_what_systick_counts() {
    use tessera_tests::memory::{self, Image, Layout, Sink, board};
    use tessera_tests::profile;
    let elf = elf();
    let plugin = memory::build_plugin().unwrap_or_else(|e| panic!("{e}"));
    let markers = profile::markers(&elf).unwrap();
    let image = Image::of(&elf).unwrap();
    let run = Run::of(Builtin::ChapterReflect, 64, 64);
    let path = || Box::new(board::Stm32f411::new());
    let mut sinks = vec![
        Sink::new(&image, Layout::Flash, board::Stm32f411::FLASH, path()),
        Sink::new(&image, Layout::AllInRam, board::Stm32f411::FLASH, path()),
        Sink::new(
            &image,
            Layout::crates(&image, &["tessera_core", "libm"]),
            board::Stm32f411::FLASH,
            path(),
        ),
    ];
    let res = memory::trace(
        &firmware::CORTEX_M4F,
        &elf,
        &plugin,
        markers,
        &run,
        &mut sinks,
    )
    .unwrap_or_else(|e| panic!("{e}"));
    assert!(
        res.pixels == host(&run),
        "{run}: the traced frame is not the host's"
    );
    let [flash, ram, crates] = &sinks[..] else {
        unreachable!()
    };
    profile::agree(&run, res.instructions, flash.tally.instructions)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(ram.tally.instructions, flash.tally.instructions);
    assert_eq!((ram.tally.stalls, ram.tally.flash_events), (0, 0));
    assert!(
        flash.tally.stalls > 0 && flash.tally.flash_events > 0,
        "{:?}",
        flash.tally
    );
    assert_eq!(
        flash.tally.stalls,
        flash.tally.fetch_stalls + flash.tally.load_stalls,
        "the F411's stores to flash cost nothing"
    );
    assert_eq!(flash.tally.by_span.iter().sum::<u64>(), flash.tally.stalls);
    assert_eq!(
        flash.tally.by_span.last(),
        Some(&0),
        "a stall outside the image's symbols"
    );
    // The renderer's code in RAM: fewer stalls, and RAM accesses met while
    // running from it.
    assert!(
        crates.tally.stalls < flash.tally.stalls && crates.tally.shared_bus > 0,
        "{:?}",
        crates.tally
    );
}
