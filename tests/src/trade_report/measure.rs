//! The measurements: the host's rows from `tessera trade` (both math backends and
//! the f64 reference), the chip's instructions per pixel under qemu, and the
//! interference study.

use super::entries::{ChipKey, chip_key};
use super::{CHIP_SCENES, CHIP_SIZE, EXACT, FAST, FOOTPRINTS, FRINGE_SIZE, RUNS, SEED, SIZE};
use crate::firmware::{self, Run};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Instant;
use tessera::Viewport;
use tessera::builtin::Builtin;
use tessera_host::trade::{self, FringeResult, Row, Setting};

/// Everything the report is made of.
pub(super) struct Measured {
    /// The host's rows, scene after scene, each backend's in its grid order.
    pub(super) rows: Vec<Row>,
    /// The chip's runs.
    pub(super) runs: Vec<Run>,
    /// Instructions per pixel by (backend, scene, sampler, depth, tile).
    pub(super) chip: HashMap<ChipKey, f64>,
    /// The interference study.
    pub(super) fringes: Vec<FringeResult>,
}

/// Measures the host first, alone on the machine, then the chip and the
/// interference study side by side.
pub(super) fn all() -> Result<Measured, String> {
    let (exact_bin, fast_bin) = build_hosts()?;
    let rows = host_rows(&exact_bin, &fast_bin)?;
    let runs = chip_runs();
    let (chip, fringes) = chip_and_fringes(&runs)?;
    print_chip(&runs, &chip);
    Ok(Measured {
        rows,
        runs,
        chip,
        fringes,
    })
}

/// Host timing, alone on the machine: scene by scene, the exact build (with the f64
/// reference) then the fast-math build, so that a drift of the machine's speed
/// during the run hits both backends alike.
fn host_rows(exact_bin: &Path, fast_bin: &Path) -> Result<Vec<Row>, String> {
    let mut rows = Vec::new();
    for b in Builtin::ALL {
        for (name, bin, reference) in [(EXACT, exact_bin, true), (FAST, fast_bin, false)] {
            let t = Instant::now();
            eprintln!("host: {} with the {name} build...", b.name());
            let r = host_trade(bin, reference, b)?;
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

/// The chip (instruction counts do not depend on the host's load) and the
/// interference study (untimed) side by side.
fn chip_and_fringes(runs: &[Run]) -> Result<(HashMap<ChipKey, f64>, Vec<FringeResult>), String> {
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

/// One line per chip run on stderr: both backends' instructions per pixel.
fn print_chip(runs: &[Run], chip: &HashMap<ChipKey, f64>) {
    for r in runs {
        let s = Setting {
            sampler: r.sampler,
            depth: r.depth,
            tile: r.tile,
        };
        eprintln!(
            "chip {:<16} {:<13} depth {} tile {:>2}: exact {:>8.1} instr/px, fast-math {:>8.1}",
            r.scene.name(),
            r.sampler.to_string(),
            r.depth,
            r.tile,
            chip.get(&chip_key(EXACT, r.scene.name(), &s))
                .copied()
                .unwrap_or(f64::NAN),
            chip.get(&chip_key(FAST, r.scene.name(), &s))
                .copied()
                .unwrap_or(f64::NAN),
        );
    }
}

/// Runs cargo from the repository root with `args`; its output goes to stderr.
fn cargo(args: &[&str]) -> Result<(), String> {
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

/// Builds the `tessera` command with the exact and the fast-math core.
fn build_hosts() -> Result<(PathBuf, PathBuf), String> {
    let root = firmware::repo_root();
    eprintln!("building tessera (exact)...");
    cargo(&["build", "--release", "-p", "tessera-host"])?;
    eprintln!("building tessera (fast-math)...");
    cargo(&[
        "build",
        "--release",
        "-p",
        "tessera-host",
        "--features",
        "fast-math",
        "--target-dir",
        "target/fast-math",
    ])?;
    let exe = format!("tessera{}", std::env::consts::EXE_SUFFIX);
    let exact = root.join("target").join("release").join(&exe);
    let fast = root
        .join("target")
        .join("fast-math")
        .join("release")
        .join(&exe);
    for p in [&exact, &fast] {
        if !p.is_file() {
            return Err(format!("the build left no binary at {}", p.display()));
        }
    }
    Ok((exact, fast))
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

/// Builds both firmware images and runs the list on each (in parallel); returns
/// instructions per pixel by (backend, scene, sampler, depth, tile).
fn chip(runs: &[Run]) -> Result<HashMap<ChipKey, f64>, String> {
    eprintln!("building the firmware (exact and fast-math)...");
    let exact = firmware::build(false)?;
    let fast = firmware::build(true)?;
    eprintln!(
        "chip: {} renders at {CHIP_SIZE}x{CHIP_SIZE} per backend under qemu...",
        runs.len()
    );
    let (e, f) = std::thread::scope(|s| {
        let e = s.spawn(|| firmware::run(&exact, runs));
        let f = s.spawn(|| firmware::run(&fast, runs));
        let join = |h: std::thread::ScopedJoinHandle<'_, Result<firmware::Output, String>>| {
            h.join()
                .unwrap_or_else(|_| Err("a qemu thread panicked".into()))
        };
        (join(e), join(f))
    });
    let mut out = HashMap::new();
    for (backend, res) in [(EXACT, e?), (FAST, f?)] {
        for (r, x) in runs.iter().zip(&res.runs) {
            let s = Setting {
                sampler: r.sampler,
                depth: r.depth,
                tile: r.tile,
            };
            out.insert(
                chip_key(backend, r.scene.name(), &s),
                x.instructions_per_pixel(),
            );
        }
    }
    Ok(out)
}
