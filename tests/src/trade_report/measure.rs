//! The measurements: the host's rows from `tessera trade` (every backend of
//! [`BACKENDS`] and the f64 reference), the chip's instructions and estimated
//! cycles per pixel under qemu with the instruction profiler, and the
//! interference study.

use super::entries::{Chip, ChipKey, chip_key};
use super::{
    BACKENDS, Backend, CHIP_SCENES, CHIP_SIZE, FOOTPRINTS, FRINGE_SIZE, REFERENCE, RUNS, SEED, SIZE,
};
use crate::firmware::{self, Run};
use crate::profile::{self, Markers};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;
use tessera_core::Viewport;
use tessera_core::builtin::Builtin;
use tessera_host::trade::{self, FringeResult, Row, Setting};

/// Everything the report is made of.
pub(super) struct Measured {
    /// The host's rows, scene after scene, each backend's in its grid order.
    pub(super) rows: Vec<Row>,
    /// The chip's figures by (backend, scene, sampler, depth, tile).
    pub(super) chip: HashMap<ChipKey, Chip>,
    /// How the chip was measured.
    pub(super) chip_summary: ChipSummary,
    /// The interference study.
    pub(super) fringes: Vec<FringeResult>,
}

/// The chip's figures and how they were measured.
struct ChipMeasured {
    figures: HashMap<ChipKey, Chip>,
    summary: ChipSummary,
}

/// What the document says about the chip's measurement.
pub(super) struct ChipSummary {
    /// Renders per backend.
    pub(super) runs: usize,
    /// The largest difference between the SysTick and the plugin count of a run,
    /// instructions per tile (averaged over the run's tiles).
    pub(super) worst_diff_per_tile: f64,
}

/// Measures the host first, alone on the machine, then the chip and the
/// interference study side by side.
pub(super) fn all() -> Result<Measured, String> {
    let bins = build_hosts()?;
    let rows = host_rows(&bins)?;
    let runs = chip_runs();
    let (chip, fringes) = chip_and_fringes(&runs)?;
    print_chip(&runs, &chip.figures);
    Ok(Measured {
        rows,
        chip: chip.figures,
        chip_summary: chip.summary,
        fringes,
    })
}

/// Host timing, alone on the machine: scene by scene, each backend's build in the
/// order of [`BACKENDS`] (the exact one with the f64 reference), so that a drift
/// of the machine's speed during the run hits every backend alike.
fn host_rows(bins: &[PathBuf]) -> Result<Vec<Row>, String> {
    let mut rows = Vec::new();
    for b in super::SCENES {
        for (i, (backend, bin)) in BACKENDS.iter().zip(bins).enumerate() {
            let t = Instant::now();
            eprintln!("host: {} with the {} build...", b.name(), backend.name);
            let r = relabel(host_trade(bin, i == 0, b)?, backend.name)?;
            eprintln!(
                "host: {} rows in {:.1} s",
                r.len(),
                t.elapsed().as_secs_f64()
            );
            rows.extend(r);
        }
    }
    Ok(rows)
}

/// The rows one binary printed, its core's rows renamed `name` (the backend it was
/// built as: the binary itself names only `exact` and `fast-math`); the f64
/// reference's rows keep their name. An error if the core's rows do not all carry
/// the same name (not one binary's output).
pub(super) fn relabel(rows: Vec<Row>, name: &str) -> Result<Vec<Row>, String> {
    let mut own: Option<String> = None;
    rows.into_iter()
        .map(|mut r| {
            if r.backend != REFERENCE {
                match &own {
                    Some(o) if *o != r.backend => {
                        return Err(format!(
                            "one binary printed rows of two backends, {o} and {}",
                            r.backend
                        ));
                    }
                    Some(_) => {}
                    None => own = Some(r.backend.clone()),
                }
                r.backend = name.into();
            }
            Ok(r)
        })
        .collect()
}

/// The chip (instruction counts and the cycle estimate do not depend on the
/// host's load) and the interference study (untimed) side by side.
fn chip_and_fringes(runs: &[Run]) -> Result<(ChipMeasured, Vec<FringeResult>), String> {
    let t = Instant::now();
    let (chip, fringes) = std::thread::scope(|s| {
        let c = s.spawn(|| chip(runs));
        let f = s.spawn(|| {
            eprintln!("interference study...");
            trade::interference_study(&FOOTPRINTS, Viewport::new(FRINGE_SIZE.0, FRINGE_SIZE.1))
                .map_err(|e| e.to_string())
        });
        (
            c.join()
                .unwrap_or_else(|_| Err("the chip thread panicked".into())),
            f.join()
                .unwrap_or_else(|_| Err("the interference thread panicked".into())),
        )
    });
    let (chip, fringes) = (chip?, fringes?);
    eprintln!(
        "chip and interference study done in {:.0} s",
        t.elapsed().as_secs_f64()
    );
    Ok((chip, fringes))
}

/// One line per chip run on stderr: each backend's instructions and estimated
/// cycles per pixel.
fn print_chip(runs: &[Run], chip: &HashMap<ChipKey, Chip>) {
    for r in runs {
        let s = setting(r);
        let mut line = format!(
            "chip {:<16} {:<13} depth {} tile {:>2}:",
            r.scene.name(),
            r.sampler.to_string(),
            r.depth,
            r.tile,
        );
        for b in BACKENDS {
            let c = chip.get(&chip_key(b.name, r.scene.name(), &s));
            line += &format!(
                " {} {:>8.1} instr/px {:>9.1} est. cycles/px;",
                b.name,
                c.map_or(f64::NAN, |c| c.instructions),
                c.map_or(f64::NAN, |c| c.cycles)
            );
        }
        eprintln!("{}", line.trim_end_matches(';'));
    }
}

/// Runs cargo from the repository root with `args`; its output goes to stderr.
fn cargo(args: &[String]) -> Result<(), String> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.current_dir(firmware::repo_root())
        .args(args)
        .stdout(Stdio::null());
    // The binaries must land where this report looks for them.
    for var in [
        "CARGO_TARGET_DIR",
        "CARGO_BUILD_TARGET",
        "CARGO_BUILD_TARGET_DIR",
    ] {
        cmd.env_remove(var);
    }
    let status = cmd.status().map_err(|e| format!("cannot run cargo: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("`cargo {}` failed ({status})", args.join(" ")))
    }
}

/// The target folder of a backend's host build, relative to the repository root:
/// the default `target` for the exact build (no features: the `tessera` command
/// as `cargo build --release` makes it), `target/<name>` for the others.
pub(super) fn host_target_dir(b: &Backend) -> String {
    if b.features.is_empty() {
        "target".into()
    } else {
        format!("target/{}", b.name)
    }
}

/// The arguments of `cargo` that build a backend's `tessera` command.
pub(super) fn host_build_args(b: &Backend) -> Vec<String> {
    let mut args: Vec<String> = ["build", "--release", "-p", "tessera-host"]
        .map(String::from)
        .into();
    if !b.features.is_empty() {
        args.extend([
            "--features".into(),
            b.features.join(","),
            "--target-dir".into(),
            host_target_dir(b),
        ]);
    }
    args
}

/// Builds the `tessera` command once per backend; returns the binaries in the
/// order of [`BACKENDS`].
fn build_hosts() -> Result<Vec<PathBuf>, String> {
    let root = firmware::repo_root();
    let exe = format!("tessera{}", std::env::consts::EXE_SUFFIX);
    let mut bins = Vec::new();
    for b in BACKENDS {
        // A backend's name is a folder name.
        firmware::image_name(&[b.name])?;
        eprintln!("building tessera ({})...", b.name);
        cargo(&host_build_args(b))?;
        let bin = root.join(host_target_dir(b)).join("release").join(&exe);
        if !bin.is_file() {
            return Err(format!("the build left no binary at {}", bin.display()));
        }
        bins.push(bin);
    }
    Ok(bins)
}

/// The arguments of `tessera trade` for one backend.
pub(super) fn trade_args(reference: bool) -> Vec<String> {
    let truth = firmware::repo_root().join("target").join("trade-truth");
    let mut args: Vec<String> = vec![
        "trade".into(),
        "--size".into(),
        SIZE.into(),
        "--runs".into(),
        RUNS.into(),
        "--truth-dir".into(),
        truth.display().to_string(),
    ];
    if reference {
        args.push("--reference".into());
    }
    args
}

/// Runs `tessera trade` for one scene and parses its rows.
fn host_trade(bin: &Path, reference: bool, scene: Builtin) -> Result<Vec<Row>, String> {
    let out = Command::new(bin)
        .args(trade_args(reference))
        .args(["--scenes", scene.name()])
        .current_dir(firmware::repo_root())
        .stderr(Stdio::inherit())
        .output()
        .map_err(|e| format!("cannot run {}: {e}", bin.display()))?;
    if !out.status.success() {
        return Err(format!("{} trade failed ({})", bin.display(), out.status));
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let mut lines = text.lines();
    if lines.next() != Some(Row::TSV_HEADER) {
        return Err(format!("{} trade printed no TSV header", bin.display()));
    }
    lines
        .filter(|l| !l.trim().is_empty())
        .map(Row::parse_tsv)
        .collect()
}

/// The setting of a chip run.
fn setting(r: &Run) -> Setting {
    Setting {
        sampler: r.sampler,
        depth: r.depth,
        tile: r.tile,
    }
}

/// The chip's runs: every setting of the grid of each chip scene, at 64x64.
fn chip_runs() -> Vec<Run> {
    let mut runs = Vec::new();
    for b in CHIP_SCENES {
        for s in trade::grid(b.settings()) {
            if !matches!(s.tile, 8 | 16 | 32) {
                continue;
            }
            let run = Run {
                sampler: s.sampler,
                depth: s.depth,
                tile: s.tile,
                seed: SEED,
                ..Run::of(b, CHIP_SIZE, CHIP_SIZE)
            };
            runs.push(run);
        }
    }
    runs
}

/// A firmware image of one backend.
struct Image {
    backend: &'static str,
    elf: PathBuf,
    markers: Markers,
}

/// One profiled render: its SysTick and plugin counts and the cycle estimate.
struct Profiled {
    instructions: u64,
    pixels: u64,
    cycles: u64,
    diff: i64,
}

/// Renders `run` on `image` under qemu with the profiling plugin: the SysTick
/// count of that same run (the plugin changes nothing the guest executes), checked
/// against the plugin's total, and the cycle estimate of the profile.
fn profiled(image: &Image, plugin: &Path, run: &Run) -> Result<Profiled, String> {
    let (systick, profile) = profile::run(&image.elf, plugin, image.markers, run)?;
    let diff = profile::check_total(run, &systick, &profile)
        .map_err(|e| format!("{} firmware: {e}", image.backend))?;
    Ok(Profiled {
        instructions: systick.instructions,
        pixels: systick.pixels_count.max(1),
        cycles: crate::cycles::estimate(&profile.insns),
        diff,
    })
}

/// Builds one firmware image per backend and the qemu plugin, then profiles every
/// run on every image, one qemu per render, on as many threads as the machine
/// has; returns instructions (SysTick) and estimated cycles per pixel by
/// (backend, scene, sampler, depth, tile).
fn chip(runs: &[Run]) -> Result<ChipMeasured, String> {
    let mut images = Vec::new();
    for b in BACKENDS {
        eprintln!("building the firmware ({})...", b.name);
        let elf = firmware::build(b.features)?;
        let markers = profile::markers(&elf)?;
        images.push(Image {
            backend: b.name,
            elf,
            markers,
        });
    }
    let plugin = profile::build_plugin()?;
    let jobs: Vec<(&Image, &Run)> = images
        .iter()
        .flat_map(|i| runs.iter().map(move |r| (i, r)))
        .collect();
    let threads = std::thread::available_parallelism()
        .map_or(1, usize::from)
        .min(jobs.len())
        .max(1);
    eprintln!(
        "chip: {} renders at {CHIP_SIZE}x{CHIP_SIZE} for each of {} backends under qemu \
         with the profiler, {threads} at a time...",
        runs.len(),
        images.len()
    );
    let t = Instant::now();
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<Result<Profiled, String>>>> =
        Mutex::new(jobs.iter().map(|_| None).collect());
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| {
                loop {
                    let k = next.fetch_add(1, Ordering::Relaxed);
                    let Some(&(image, run)) = jobs.get(k) else {
                        break;
                    };
                    let r = profiled(image, &plugin, run);
                    if let Ok(mut v) = results.lock() {
                        v[k] = Some(r);
                    }
                }
            });
        }
    });
    let results = results
        .into_inner()
        .map_err(|_| "a qemu thread panicked".to_string())?;
    let mut out = HashMap::new();
    let mut worst: f64 = 0.0;
    for ((image, run), r) in jobs.iter().zip(results) {
        let p = r.ok_or_else(|| format!("{run}: not run (a qemu thread panicked)"))??;
        let px = p.pixels as f64;
        out.insert(
            chip_key(image.backend, run.scene.name(), &setting(run)),
            Chip {
                instructions: p.instructions as f64 / px,
                cycles: p.cycles as f64 / px,
            },
        );
        worst = worst.max(p.diff.unsigned_abs() as f64 / profile::tiles(run) as f64);
    }
    eprintln!(
        "chip: {} profiled renders in {:.0} s",
        jobs.len(),
        t.elapsed().as_secs_f64()
    );
    Ok(ChipMeasured {
        figures: out,
        summary: ChipSummary {
            runs: runs.len(),
            worst_diff_per_tile: worst,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::super::entries::tests::row;
    use super::*;
    use tessera_core::Sampler;

    #[test]
    fn each_binary_s_rows_take_its_backend_s_name() {
        let b = Builtin::ChapterReflect;
        let rows = vec![
            row(b, "exact", Sampler::Centre, 1.0, 0.1),
            row(b, REFERENCE, Sampler::Centre, 2.0, 0.1),
            row(b, "exact", Sampler::Corner, 3.0, 0.2),
        ];
        let named = relabel(rows.clone(), "fast-rsqrt").unwrap();
        let names: Vec<&str> = named.iter().map(|r| r.backend.as_str()).collect();
        assert_eq!(names, ["fast-rsqrt", REFERENCE, "fast-rsqrt"]);
        // Nothing else changes.
        for (a, b) in rows.iter().zip(&named) {
            assert_eq!(
                (&a.setting, a.ns_median, a.flip),
                (&b.setting, b.ns_median, b.flip)
            );
        }
        let mut mixed = rows;
        mixed[2].backend = "fast-math".into();
        assert!(relabel(mixed, "x").is_err());
        assert!(relabel(Vec::new(), "x").unwrap().is_empty());
    }

    #[test]
    fn each_backend_builds_in_its_own_folder() {
        let exact = Backend::new("exact", &[]);
        let fast = Backend::new("fast-math", &["fast-math"]);
        let two = Backend::new("fast-both", &["fast-rsqrt", "fast-pow"]);
        assert_eq!(
            host_build_args(&exact),
            ["build", "--release", "-p", "tessera-host"]
        );
        assert_eq!(
            host_build_args(&fast).join(" "),
            "build --release -p tessera-host --features fast-math --target-dir target/fast-math"
        );
        assert_eq!(
            host_build_args(&two).join(" "),
            "build --release -p tessera-host --features fast-rsqrt,fast-pow --target-dir \
             target/fast-both"
        );
        assert_eq!(host_target_dir(&exact), "target");
        let dirs: Vec<String> = BACKENDS.iter().map(host_target_dir).collect();
        for (i, d) in dirs.iter().enumerate() {
            assert!(!dirs[i + 1..].contains(d), "{d} twice");
        }
    }

    /// The chip renders every setting of the grid of every built-in scene.
    #[test]
    fn the_chip_runs_cover_every_scene_s_grid() {
        let runs = chip_runs();
        for b in crate::trade_report::SCENES {
            let grid = trade::grid(b.settings());
            let mine: Vec<Setting> = runs
                .iter()
                .filter(|r| r.scene == b.into())
                .map(setting)
                .collect();
            assert_eq!(mine, grid, "{}", b.name());
        }
        assert!(runs.iter().all(|r| r.seed == SEED && r.width == CHIP_SIZE));
    }
}
