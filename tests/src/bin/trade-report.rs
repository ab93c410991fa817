//! `trade-report`: measures the speed/accuracy trade and writes `docs/trade.md`, the
//! chart `docs/trade.svg` and the interference figure `docs/interference.png`.
//!
//! Builds the `tessera` command twice (exact and fast-math), runs `tessera trade` with
//! each (the exact build also measures the f64 reference, the ceiling), counts the
//! chip's instructions per pixel for the default scene and the interference screen
//! under qemu (both math backends), computes the Pareto front of each scene, and runs
//! the interference study.
//!
//! ```sh
//! cargo run -p tessera-tests --release --bin trade-report
//! ```

use plotters::prelude::*;
use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};
use std::time::Instant;
use tessera::Viewport;
use tessera::builtin::Builtin;
use tessera_host::trade::{self, FringeResult, Row, Setting};
use tessera_tests::firmware::{self, Run};

const COMMAND: &str = "cargo run -p tessera-tests --release --bin trade-report";
/// Host image size and timed runs per setting.
const SIZE: &str = "128x96";
const RUNS: &str = "7";
/// Chip image size.
const CHIP_SIZE: u16 = 64;
/// The scenes measured on the chip: the default scene and the interference screen.
const CHIP_SCENES: [Builtin; 2] = [Builtin::ChapterReflect, Builtin::Interference];
/// The seed `tessera trade` renders with (the chip uses the same).
const SEED: u32 = 1;
/// The interference study: pixel footprints (in fringe spacings) and image size.
const FOOTPRINTS: [f64; 2] = [0.3, 1.6];
const FRINGE_SIZE: (u16, u16) = (160, 120);
/// Columns of the interference figure.
const FRINGE_COLUMNS: usize = 5;

const EXACT: &str = "exact";
const FAST: &str = "fast-math";
const REFERENCE: &str = "f64-reference";

fn main() -> ExitCode {
    let start = Instant::now();
    match report() {
        Ok(files) => {
            for f in files {
                println!("wrote {}", rel(&f));
            }
            eprintln!(
                "trade-report: done in {:.0} s",
                start.elapsed().as_secs_f64()
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("trade-report: {e}");
            ExitCode::FAILURE
        }
    }
}

/// A measured row, the chip's count for its setting and whether it is on the front.
struct Entry {
    row: Row,
    chip: Option<f64>,
    front: bool,
}

impl Entry {
    fn is(&self, sampler: &str, depth: u8, tile: usize) -> bool {
        self.row.setting.sampler.to_string() == sampler
            && self.row.setting.depth == depth
            && self.row.setting.tile == tile
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
fn trade_args(reference: bool) -> Vec<String> {
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

type ChipKey = (String, String, String, u8, usize);

fn chip_key(backend: &str, scene: &str, s: &Setting) -> ChipKey {
    (
        backend.into(),
        scene.into(),
        s.sampler.to_string(),
        s.depth,
        s.tile,
    )
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

/// Marks the Pareto front of each scene over the exact and fast-math rows: a row is
/// on it when no other row is at most as costly and at most as wrong, and better in
/// one of the two.
fn mark_front(entries: &mut [Entry]) {
    let contenders: Vec<(usize, String, f64, f64)> = entries
        .iter()
        .enumerate()
        .filter(|(_, e)| e.row.backend != REFERENCE)
        .map(|(i, e)| (i, e.row.scene.clone(), e.row.ns_median, e.row.flip))
        .collect();
    for (i, scene, ns, flip) in &contenders {
        let dominated = contenders.iter().any(|(j, s, n, f)| {
            j != i && s == scene && n <= ns && f <= flip && (n < ns || f < flip)
        });
        entries[*i].front = !dominated;
    }
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|t| {
            t.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_else(|| "unknown (no /proc/cpuinfo)".into())
}

/// `n` rounded, with thousands separators ([`tessera_tests::thousands`]; a negative
/// or non-finite figure, which the report never has, is printed as it is).
fn thousands(n: f64) -> String {
    if n.is_finite() && n >= 0.0 {
        tessera_tests::thousands(n.round() as u64)
    } else {
        format!("{n:.0}")
    }
}

fn ns(n: f64) -> String {
    thousands(n)
}

fn psnr(p: f64) -> String {
    if p.is_finite() {
        format!("{p:.1} dB")
    } else {
        "identical".into()
    }
}

/// A setting in a few characters, relative to the scene's own settings.
fn short(scene: &str, s: &Setting) -> String {
    let base = Builtin::from_name(scene).map(Builtin::settings);
    let mut t = s.sampler.to_string();
    if base.is_some_and(|b| b.max_depth != s.depth) {
        let _ = write!(t, " d{}", s.depth);
    }
    if s.tile != 16 {
        let _ = write!(t, " t{}", s.tile);
    }
    t
}

fn pct(x: f64) -> String {
    format!("{:.1}%", 100.0 * x)
}

/// The entries of `scene`.
fn of_scene<'a>(entries: &'a [Entry], scene: &str) -> Vec<&'a Entry> {
    entries.iter().filter(|e| e.row.scene == scene).collect()
}

/// The entry of a scene, backend and setting.
fn find<'a>(
    entries: &'a [Entry],
    scene: &str,
    backend: &str,
    sampler: &str,
    depth: u8,
    tile: usize,
) -> Result<&'a Entry, String> {
    entries
        .iter()
        .find(|e| e.row.scene == scene && e.row.backend == backend && e.is(sampler, depth, tile))
        .ok_or_else(|| format!("no {backend} row for {scene} {sampler} depth {depth} tile {tile}"))
}

fn report() -> Result<Vec<PathBuf>, String> {
    let root = firmware::repo_root();
    let docs = root.join("docs");
    let (exact_bin, fast_bin) = build_hosts()?;

    // Host timing first, alone on the machine: scene by scene, the exact build
    // (with the f64 reference) then the fast-math build, so that a drift of the
    // machine's speed during the run hits both backends alike.
    let mut rows = Vec::new();
    for b in Builtin::ALL {
        for (name, bin, reference) in [(EXACT, &exact_bin, true), (FAST, &fast_bin, false)] {
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

    // The chip (instruction counts do not depend on the host's load) and the
    // interference study (untimed) side by side.
    let runs = chip_runs();
    let t = Instant::now();
    let (chip, fringes) = std::thread::scope(|s| {
        let c = s.spawn(|| chip(&runs));
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
    for r in &runs {
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

    // Rows in grid order, the three backends of a setting together.
    let mut entries: Vec<Entry> = Vec::new();
    for b in Builtin::ALL {
        for s in trade::grid(b.settings()) {
            for backend in [EXACT, FAST, REFERENCE] {
                if let Some(r) = rows
                    .iter()
                    .find(|r| r.scene == b.name() && r.backend == backend && r.setting == s)
                {
                    entries.push(Entry {
                        row: r.clone(),
                        chip: chip.get(&chip_key(backend, b.name(), &s)).copied(),
                        front: false,
                    });
                }
            }
        }
    }
    if entries.len() != rows.len() {
        return Err(format!(
            "{} rows measured, {} matched the grid",
            rows.len(),
            entries.len()
        ));
    }
    mark_front(&mut entries);

    std::fs::create_dir_all(&docs).map_err(|e| format!("{}: {e}", docs.display()))?;
    let fig = docs.join("interference.png");
    tessera_host::write_png(&trade::figure(&fringes, FRINGE_COLUMNS), &fig)
        .map_err(|e| format!("{}: {e}", fig.display()))?;
    let svg = docs.join("trade.svg");
    write_atomic(&svg, chart(&entries)?.as_bytes())?;
    let md = docs.join("trade.md");
    write_atomic(
        &md,
        document(&entries, &chip, runs.len(), &fringes)?.as_bytes(),
    )?;
    Ok(vec![md, svg, fig])
}

fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    let tmp = path.with_extension(format!("{ext}.tmp"));
    std::fs::write(&tmp, bytes).map_err(|e| format!("cannot write {}: {e}", tmp.display()))?;
    std::fs::rename(&tmp, path).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// `p` relative to the repository root.
fn rel(p: &Path) -> String {
    let root = firmware::repo_root();
    let root = root.canonicalize().unwrap_or(root);
    let p = p.canonicalize().unwrap_or_else(|_| p.to_path_buf());
    p.strip_prefix(&root).unwrap_or(&p).display().to_string()
}

// ---------------------------------------------------------------------------------
// The chart.

const EXACT_COLOUR: RGBColor = RGBColor(31, 100, 200);
const FAST_COLOUR: RGBColor = RGBColor(230, 120, 0);
const REFERENCE_COLOUR: RGBColor = RGBColor(140, 140, 140);

fn chart(entries: &[Entry]) -> Result<String, String> {
    let err = |e: &dyn std::fmt::Debug| format!("drawing the chart: {e:?}");
    let mut svg = String::new();
    {
        let area = SVGBackend::with_string(&mut svg, (1280, 980)).into_drawing_area();
        area.fill(&WHITE).map_err(|e| err(&e))?;
        let area = area
            .titled(
                &format!(
                    "Cost against error, per setting ({SIZE}, host, one thread; lower left is better)"
                ),
                ("sans-serif", 22),
            )
            .map_err(|e| err(&e))?;
        for (panel, b) in area.split_evenly((2, 2)).iter().zip(Builtin::ALL) {
            let rows = of_scene(entries, b.name());
            let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, 0.0f64, f64::MAX, 0.0f64);
            for e in &rows {
                x0 = x0.min(e.row.ns_median);
                x1 = x1.max(e.row.ns_median);
                y0 = y0.min(e.row.flip);
                y1 = y1.max(e.row.flip);
            }
            let (x0, x1) = (x0 / 1.3, x1 * 1.6);
            let (y0, y1) = (y0 / 1.4, y1 * 1.6);
            let (xk, yk) = (ticks(x0, x1), ticks(y0, y1));
            let mut c = ChartBuilder::on(panel)
                .caption(
                    format!("{} (scene settings: {})", b.name(), short_base(b)),
                    ("sans-serif", 17),
                )
                .margin(12)
                .x_label_area_size(42)
                .y_label_area_size(62)
                .build_cartesian_2d(
                    (x0..x1).log_scale().with_key_points(xk),
                    (y0..y1).log_scale().with_key_points(yk),
                )
                .map_err(|e| err(&e))?;
            c.configure_mesh()
                .x_desc("host ns per pixel (median, log scale)")
                .y_desc("mean FLIP vs converged (log scale)")
                .x_label_formatter(&|v| thousands(*v))
                .y_label_formatter(&|v| {
                    format!("{v:.4}")
                        .trim_end_matches('0')
                        .trim_end_matches('.')
                        .to_string()
                })
                .light_line_style(WHITE.mix(0.0))
                .label_style(("sans-serif", 12))
                .axis_desc_style(("sans-serif", 13))
                .draw()
                .map_err(|e| err(&e))?;
            let pts = |backend: &str| -> Vec<(f64, f64)> {
                rows.iter()
                    .filter(|e| e.row.backend == backend)
                    .map(|e| (e.row.ns_median, e.row.flip))
                    .collect()
            };
            let mut front: Vec<&&Entry> = rows.iter().filter(|e| e.front).collect();
            front.sort_by(|a, b| a.row.ns_median.total_cmp(&b.row.ns_median));
            // The front as a staircase: what the best setting up to a cost achieves.
            let mut stair = Vec::new();
            for (i, e) in front.iter().enumerate() {
                if i > 0 {
                    stair.push((e.row.ns_median, front[i - 1].row.flip));
                }
                stair.push((e.row.ns_median, e.row.flip));
            }
            c.draw_series(LineSeries::new(stair, BLACK.stroke_width(1)))
                .map_err(|e| err(&e))?
                .label("Pareto front (exact + fast-math)")
                .legend(|(x, y)| PathElement::new(vec![(x - 9, y), (x + 9, y)], BLACK));
            c.draw_series(
                pts(REFERENCE)
                    .into_iter()
                    .map(|p| Cross::new(p, 4, REFERENCE_COLOUR.stroke_width(2))),
            )
            .map_err(|e| err(&e))?
            .label("f64 reference (ceiling, 1 run)")
            .legend(|(x, y)| Cross::new((x, y), 4, REFERENCE_COLOUR.stroke_width(2)));
            c.draw_series(
                pts(EXACT)
                    .into_iter()
                    .map(|p| Circle::new(p, 4, EXACT_COLOUR.filled())),
            )
            .map_err(|e| err(&e))?
            .label("exact (f32)")
            .legend(|(x, y)| Circle::new((x, y), 4, EXACT_COLOUR.filled()));
            c.draw_series(
                pts(FAST)
                    .into_iter()
                    .map(|p| TriangleMarker::new(p, 5, FAST_COLOUR.filled())),
            )
            .map_err(|e| err(&e))?
            .label("fast-math (f32)")
            .legend(|(x, y)| TriangleMarker::new((x, y), 5, FAST_COLOUR.filled()));
            // Ring every front point; label it unless the previous one (the next
            // cheaper) has the same label.
            let mut last = String::new();
            c.draw_series(front.iter().map(|e| {
                let label = short(&e.row.scene, &e.row.setting);
                let text = if label == last {
                    String::new()
                } else {
                    label.clone()
                };
                last = label;
                EmptyElement::at((e.row.ns_median, e.row.flip))
                    + Circle::new((0, 0), 8, BLACK.stroke_width(1))
                    + Text::new(text, (7, -16), ("sans-serif", 11))
            }))
            .map_err(|e| err(&e))?;
            c.configure_series_labels()
                .position(SeriesLabelPosition::UpperRight)
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK.mix(0.4))
                .label_font(("sans-serif", 12))
                .draw()
                .map_err(|e| err(&e))?;
        }
        area.present().map_err(|e| err(&e))?;
    }
    Ok(svg)
}

/// The 1-2-5 values in `lo..hi`, the tick marks of a log axis.
fn ticks(lo: f64, hi: f64) -> Vec<f64> {
    let mut out = Vec::new();
    let mut decade = 10f64.powf(lo.log10().floor());
    while decade <= hi {
        for m in [1.0, 2.0, 5.0] {
            let v = decade * m;
            if (lo..=hi).contains(&v) {
                out.push(v);
            }
        }
        decade *= 10.0;
    }
    out
}

fn short_base(b: Builtin) -> String {
    let s = b.settings();
    format!("{}, depth {}", s.sampler, s.max_depth)
}

// ---------------------------------------------------------------------------------
// The document.

fn document(
    entries: &[Entry],
    chip: &HashMap<ChipKey, f64>,
    chip_runs: usize,
    fringes: &[FringeResult],
) -> Result<String, String> {
    let mut d = String::new();
    let w = &mut d;
    let cpu = cpu_model();
    let threads = std::thread::available_parallelism().map_or(0, usize::from);
    let _ = writeln!(w, "# The speed/accuracy trade\n");
    let _ = writeln!(
        w,
        "Generated by `{COMMAND}` (do not edit by hand; run it again after changing the \
         core). One run measures both math backends side by side, on the host and on the \
         chip, and writes this file, the chart [trade.svg](trade.svg) and the figure \
         [interference.png](interference.png).\n"
    );
    let _ = writeln!(w, "![Cost against error per setting](trade.svg)\n");
    let _ = writeln!(
        w,
        "*Host nanoseconds per pixel (log) against mean FLIP (log), one panel per scene: \
         blue dots the exact core, orange triangles fast-math, grey crosses the f64 \
         reference with the same setting (the ceiling of that sampler). The ringed, \
         labelled points are the Pareto front; the staircase is the best error reachable \
         up to each cost. Labels: sampler, `dN` a depth other than the scene's, `tN` a \
         tile size other than 16.*\n"
    );

    // How it was measured.
    let _ = writeln!(w, "## How it was measured\n");
    let _ = writeln!(
        w,
        "- **Host time.** `tessera {} --scenes NAME` with the `tessera` command built \
         with the exact core (`cargo build --release -p tessera-host`), then `tessera {} \
         --scenes NAME` built with fast-math (`--features fast-math --target-dir \
         target/fast-math`), scene after scene in this run, so both backends are timed \
         side by side under the same conditions. Each setting renders the whole {SIZE} image {RUNS} times \
         on one thread (tiles one after another); the table gives the median ns per \
         pixel and the fastest-slowest run. The f64-reference rows are one run each of \
         the independent f64 renderer (whole image, no tiles). Host CPU: {cpu} \
         ({threads} logical CPUs, one used); {}. These are wall-clock timings of short \
         renders: a difference smaller than the two rows' min-max spread is noise.",
        trade_args(true)[..5].join(" ") + " --truth-dir target/trade-truth --reference",
        trade_args(false)[..5].join(" ") + " --truth-dir target/trade-truth",
        tessera_tests::tool_version("rustc")
    );
    let _ = writeln!(
        w,
        "- **Accuracy.** Against a converged reference of each scene: the f64 renderer \
         with stratified 16x16 samples per pixel (256) and depth {} (the deepest), \
         cached in `target/trade-truth/`. Mean FLIP (lower is better), PSNR, the \
         largest channel difference (LSB of 8 bits) and the share of all pixels whose \
         channels are all within 1 LSB. Sampling error counts: a 1-sample setting is \
         compared with the box-filtered (area-averaged) picture.",
        tessera::MAX_DEPTH
    );
    let _ = writeln!(
        w,
        "- **Chip.** Instructions per pixel inside `render_tile` on qemu's `mps2-an386` \
         (Cortex-M4F, `-icount shift=0`, exact to the instruction; see \
         [chip-cost.md](chip-cost.md)), {CHIP_SIZE}x{CHIP_SIZE} pixels, the same \
         settings and seed ({SEED}), for {} and {} with the exact and the fast-math \
         firmware ({chip_runs} renders each, {}). Instructions, not cycles.",
        CHIP_SCENES[0].name(),
        CHIP_SCENES[1].name(),
        tessera_tests::tool_version(firmware::QEMU)
    );
    let _ = writeln!(
        w,
        "- **Settings.** Every sampler at the scene's depth with 16x16 tiles, then \
         depths 0, 1, 3 and tiles 8, 16, 32 with the scene's sampler (one factor at a \
         time: `tessera_host::trade::grid`)."
    );
    let _ = writeln!(
        w,
        "- **Pareto front** (**front** in the tables): among the exact and fast-math rows \
         of a scene, no other row is both at most as costly in host ns/px (median) and \
         at most as wrong in mean FLIP, and better in one. The f64-reference rows are \
         the ceiling, not contenders.\n"
    );

    // Tables.
    let _ = writeln!(w, "## Results\n");
    for b in Builtin::ALL {
        let _ = writeln!(w, "### {} (scene settings: {})\n", b.name(), short_base(b));
        let _ = writeln!(
            w,
            "| sampler | depth | tile | backend | host ns/px median (min-max) | chip instr/px | mean FLIP | PSNR | max diff | within 1 LSB | front |"
        );
        let _ = writeln!(w, "|---|---|---|---|---|---|---|---|---|---|---|");
        for e in of_scene(entries, b.name()) {
            let r = &e.row;
            let _ = writeln!(
                w,
                "| {} | {} | {} | {} | {} ({}-{}) | {} | {:.5} | {} | {} | {} | {} |",
                r.setting.sampler,
                r.setting.depth,
                r.setting.tile,
                r.backend,
                ns(r.ns_median),
                ns(r.ns_min),
                ns(r.ns_max),
                e.chip.map_or_else(|| "-".into(), thousands),
                r.flip,
                psnr(r.psnr),
                r.max_diff,
                pct(r.within1),
                if e.front { "**front**" } else { "" }
            );
        }
        let _ = writeln!(w);
    }

    // What to pick.
    let _ = writeln!(w, "## What to pick\n");
    let _ = writeln!(w, "{}\n", what_to_pick(entries, chip, fringes)?);

    // Interference study.
    let _ = writeln!(w, "## The interference study\n");
    let _ = writeln!(
        w,
        "![Young's fringes through small and large pixels](interference.png)\n"
    );
    let amplitude = |m: &str| {
        fringes
            .iter()
            .find(|f| f.footprint == FOOTPRINTS[1] && f.method == m)
            .map_or(f64::NAN, |f| f.amplitude)
    };
    let contrast = amplitude("truth") / amplitude("centre");
    let _ = writeln!(
        w,
        "*The chapter's interference screen (Young's fringes, spacing 0.75 mm) seen head \
         on at {}x{}, depth 0. Top row: each pixel covers {} of the fringe spacing; \
         bottom row: {} (pixels larger than the fringes). Columns, left to right: the \
         truth (the f64 renderer with the exact box-filtered texture: what an ideal \
         pixel sees), centre sampling (one ray per pixel), 5 random rays (the chapter's \
         example), stratified 3x3 (9 rays) and prefiltered (the core evaluates the \
         box-filtered texture once per pixel). Pixels larger than the fringes see an \
         almost even green: averaging over the pixel keeps {:.0}% of the fringes' \
         contrast; centre sampling instead shows false, aliased fringes at full \
         contrast, 5 random rays turn them into noise, and 9 stratified rays into less \
         noise. Prefiltering costs one evaluation per pixel \
         and matches the truth to rounding: the core models only what the scene \
         requires, and where the scene's texture has an exact area average it uses it \
         instead of more rays.*\n",
        FRINGE_SIZE.0,
        FRINGE_SIZE.1,
        FOOTPRINTS[0],
        FOOTPRINTS[1],
        100.0 * contrast
    );
    let _ = writeln!(
        w,
        "Per image, green channel: RMSE against the truth (LSB), amplitude of the fringes \
         at the true fringe frequency along the middle row (LSB), standard deviation \
         along the middle row (any pattern, true or aliased, LSB).\n"
    );
    let _ = writeln!(
        w,
        "| footprint / fringe spacing | column | rays per pixel | RMSE vs truth | fringe amplitude | row std |"
    );
    let _ = writeln!(w, "|---|---|---|---|---|---|");
    for f in fringes {
        let rays = match f.method.as_str() {
            "truth" => "exact area average (f64)".to_string(),
            m => m
                .parse::<tessera::Sampler>()
                .map(|s| s.count().to_string())
                .unwrap_or_default(),
        };
        let _ = writeln!(
            w,
            "| {:.1}x | {} | {} | {} | {:.1} | {:.1} |",
            f.footprint,
            f.method,
            rays,
            if f.method == "truth" {
                "-".to_string()
            } else {
                format!("{:.2}", f.rmse)
            },
            f.amplitude,
            f.row_std
        );
    }
    let _ = writeln!(w, "\n## Regenerate\n");
    let _ = writeln!(w, "```sh\n{COMMAND}\n```\n");
    let _ = writeln!(
        w,
        "It needs `qemu-system-arm` and the `thumbv7em-none-eabihf` target (`bash \
         tests/run-all.sh` installs both). Host timings change from run to run and \
         machine to machine; the accuracy columns and the chip's counts do not."
    );
    Ok(d)
}

/// The paragraph a user can act on, every figure taken from the tables.
fn what_to_pick(
    entries: &[Entry],
    chip: &HashMap<ChipKey, f64>,
    fringes: &[FringeResult],
) -> Result<String, String> {
    let mut p = String::new();
    let flip = |x: f64| format!("{x:.4}");
    let same = |a: &Entry, b: &Entry| (a.row.flip - b.row.flip).abs() < 1e-6;
    let chip_of = |e: &Entry| e.chip.map_or_else(|| "-".into(), thousands);

    // The fronts, as chains of samplers: rows with the same image (other tile
    // sizes, deeper than the scene) and both backends merged, a depth below the
    // scene's noted; each link with its best FLIP, worst (cheapest) first.
    let mut chains = Vec::new();
    let mut on_front: Vec<String> = Vec::new();
    let (mut fast_on, mut fast_noise, mut all_on) = (0, 0, 0);
    for b in Builtin::ALL {
        let mut links: Vec<(String, f64)> = Vec::new();
        for e in of_scene(entries, b.name()).into_iter().filter(|e| e.front) {
            all_on += 1;
            let mut label = e.row.setting.sampler.to_string();
            on_front.push(label.clone());
            if e.row.setting.depth < b.settings().max_depth {
                let _ = write!(label, " at depth {}", e.row.setting.depth);
            }
            match links.iter_mut().find(|(l, _)| *l == label) {
                Some((_, best)) => *best = best.min(e.row.flip),
                None => links.push((label, e.row.flip)),
            }
            if e.row.backend == FAST {
                fast_on += 1;
                let s = &e.row.setting;
                let exact = find(
                    entries,
                    b.name(),
                    EXACT,
                    &s.sampler.to_string(),
                    s.depth,
                    s.tile,
                )?;
                if exact.row.ns_min <= e.row.ns_max
                    && e.row.ns_min <= exact.row.ns_max
                    && exact.row.flip <= e.row.flip
                {
                    fast_noise += 1;
                }
            }
        }
        links.sort_by(|x, y| y.1.total_cmp(&x.1));
        let chain: Vec<String> = links
            .iter()
            .map(|(l, f)| format!("{l} ({})", flip(*f)))
            .collect();
        chains.push(format!("{}: {}", b.name(), chain.join(" > ")));
    }
    let mut never: Vec<String> = Vec::new();
    for b in Builtin::ALL {
        for s in trade::grid(b.settings()) {
            let n = s.sampler.to_string();
            if !on_front.contains(&n) && !never.contains(&n) {
                never.push(n);
            }
        }
    }
    let _ = write!(
        p,
        "**The Pareto front**, by sampler (cheapest first, best mean FLIP in \
         brackets): {}. ",
        chains.join("; ")
    );
    if fast_on > 0 {
        let _ = write!(
            p,
            "{fast_on} of its {all_on} rows are fast-math{}. ",
            if fast_noise == fast_on {
                ", each only by timing noise: within the min-max host time of the exact \
                 row with the same setting, which has the same or a lower FLIP"
                    .to_string()
            } else {
                format!(
                    "; {fast_noise} of them lie within the min-max host time of the \
                     exact row with the same setting, which has the same or a lower FLIP"
                )
            }
        );
    }
    let r = Builtin::ChapterReflect.name();
    let d = Builtin::ChapterReflect.settings().max_depth;
    if !never.is_empty() {
        let _ = write!(p, "Never on it: {}", never.join(", "));
        let r16 = find(entries, r, EXACT, "random:16", d, 16);
        let s4 = find(entries, r, EXACT, "stratified:4", d, 16);
        if let (true, Ok(r16), Ok(s4)) = (never.iter().any(|n| n == "random:16"), r16, s4) {
            let _ = write!(
                p,
                " (on {r}, random:16 costs {} instr/px on the chip for FLIP {}, \
                 stratified:4 {} for {})",
                chip_of(r16),
                flip(r16.row.flip),
                chip_of(s4),
                flip(s4.row.flip)
            );
        }
        let _ = write!(p, ". ");
    }

    // What is noise: identical images, and fast-math's host time.
    let mut ratios: Vec<f64> = Vec::new();
    for e in entries.iter().filter(|e| e.row.backend == FAST) {
        let s = &e.row.setting;
        if let Ok(x) = find(
            entries,
            &e.row.scene,
            EXACT,
            &s.sampler.to_string(),
            s.depth,
            s.tile,
        ) {
            ratios.push(e.row.ns_median / x.row.ns_median);
        }
    }
    ratios.sort_by(f64::total_cmp);
    let median = ratios.get(ratios.len() / 2).copied().unwrap_or(f64::NAN);
    let mut no_texture = Vec::new();
    let mut textured = Vec::new();
    for b in Builtin::ALL {
        let bd = b.settings().max_depth;
        let (c, pf) = (
            find(entries, b.name(), EXACT, "centre", bd, 16)?,
            find(entries, b.name(), EXACT, "prefiltered", bd, 16)?,
        );
        if same(c, pf) {
            no_texture.push(b.name());
        } else if pf.row.flip < c.row.flip {
            textured.push((b, c, pf));
        }
    }
    let _ = write!(
        p,
        "Several rows render the same image (same FLIP) and differ only by timing \
         noise, so which of them makes the front is chance: the tile size changes no \
         pixel (pick it for RAM: 3N\u{b2} + 8 bytes), nor does a depth beyond the \
         scene's reflections ({r} at depth 3: FLIP {}, as at depth {d}){}; and on the \
         host fast-math is no faster (fast/exact median time {:.2}, {:.2}-{:.2} over \
         {} settings). ",
        flip(find(entries, r, EXACT, "centre", 3, 16)?.row.flip),
        if no_texture.is_empty() {
            String::new()
        } else {
            format!(", nor prefiltered on {}", no_texture.join(" and "))
        },
        median,
        ratios.first().copied().unwrap_or(f64::NAN),
        ratios.last().copied().unwrap_or(f64::NAN),
        ratios.len()
    );
    let d0 = find(entries, r, EXACT, "centre", 0, 16)?;
    let centre = find(entries, r, EXACT, "centre", d, 16)?;
    let _ = write!(
        p,
        "A depth below the scene's costs accuracy ({r} at depth 0: FLIP {} against {}). ",
        flip(d0.row.flip),
        flip(centre.row.flip)
    );

    // Fast-math on the chip.
    let mut chip_ratios: Vec<f64> = Vec::new();
    for ((backend, scene, sampler, depth, tile), e) in chip {
        if backend != EXACT {
            continue;
        }
        let fast = (
            FAST.to_string(),
            scene.clone(),
            sampler.clone(),
            *depth,
            *tile,
        );
        if let Some(f) = chip.get(&fast) {
            chip_ratios.push(f / e);
        }
    }
    chip_ratios.sort_by(f64::total_cmp);
    let (rmin, rmax) = (
        chip_ratios.first().copied().unwrap_or(f64::NAN),
        chip_ratios.last().copied().unwrap_or(f64::NAN),
    );
    let fast_centre = find(entries, r, FAST, "centre", d, 16)?;
    let ex_s4 = find(entries, r, EXACT, "stratified:4", d, 16)?;
    let fa_s4 = find(entries, r, FAST, "stratified:4", d, 16)?;
    let i = Builtin::Interference.name();
    let same = |a: f64, b: f64| (a - b).abs() < 1e-5;
    let fringe_same = of_scene(entries, i)
        .iter()
        .filter(|e| e.row.backend == FAST)
        .all(|e| {
            let s = &e.row.setting;
            find(entries, i, EXACT, &s.sampler.to_string(), s.depth, s.tile)
                .is_ok_and(|x| same(x.row.flip, e.row.flip))
        });
    if same(fast_centre.row.flip, centre.row.flip) && same(fa_s4.row.flip, ex_s4.row.flip) {
        let _ = write!(
            p,
            "**Fast-math changes nothing here**: the built-in scenes' highlights have \
             integer shininess, raised by repeated squaring with either backend, and none \
             has a textured sphere (the other approximated calls), so both backends render \
             the same images (on {r}, mean FLIP {} with centre sampling, {} with \
             stratified 4x4) for {:.3} to {:.3} times the instructions on the chip ({} \
             settings of {r} and {i}). ",
            flip(centre.row.flip),
            flip(ex_s4.row.flip),
            rmin,
            rmax,
            chip_ratios.len(),
        );
    } else {
        let _ = write!(
            p,
            "**{}** On the chip fast-math takes {:.3} to {:.3} times the exact build's \
             instructions per pixel ({} settings of {r} and {i}), but it raises the error: \
             on {r}, mean FLIP {} instead of {} with centre sampling and {} instead of {} \
             with stratified 4x4, so it caps what more samples can buy{}. ",
            if rmax > 0.9 && fast_centre.row.flip > centre.row.flip {
                "Keep the exact math."
            } else {
                "Fast-math:"
            },
            rmin,
            rmax,
            chip_ratios.len(),
            flip(fast_centre.row.flip),
            flip(centre.row.flip),
            flip(fa_s4.row.flip),
            flip(ex_s4.row.flip),
            if fringe_same {
                format!(" ({i} is unaffected: the same FLIP with either backend)")
            } else {
                String::new()
            }
        );
    }

    // Where centre sampling fails: edges.
    let s2 = find(entries, r, EXACT, "stratified:2", d, 16)?;
    let s3 = find(entries, r, EXACT, "stratified:3", d, 16)?;
    let corner = find(entries, r, EXACT, "corner", d, 16)?;
    let _ = write!(
        p,
        "**Centre sampling is the cheapest setting but fails at edges**: on {r} it \
         reaches FLIP {} with pixels up to {} LSB off where an edge crosses them ({} \
         instr/px on the chip); stratified 2x2 brings FLIP to {} and the worst pixel to \
         {} LSB for {} instr/px, stratified 3x3 to {} and {} LSB for {} instr/px. \
         Corner sampling (the chapter's `r0`) shifts the image by half a pixel: FLIP \
         {}{}. ",
        flip(centre.row.flip),
        centre.row.max_diff,
        chip_of(centre),
        flip(s2.row.flip),
        s2.row.max_diff,
        chip_of(s2),
        flip(s3.row.flip),
        s3.row.max_diff,
        chip_of(s3),
        flip(corner.row.flip),
        if corner.row.flip > centre.row.flip {
            ", worse than centre at the same cost"
        } else {
            ""
        }
    );

    // Where centre sampling fails: textures finer than a pixel.
    let ib = Builtin::Interference.settings();
    let ic = find(entries, i, EXACT, "centre", ib.max_depth, 16)?;
    let ip = find(entries, i, EXACT, "prefiltered", ib.max_depth, 16)?;
    let is4 = find(entries, i, EXACT, "stratified:4", ib.max_depth, 16)?;
    let fr = |fp: f64, m: &str| -> Result<&FringeResult, String> {
        fringes
            .iter()
            .find(|x| x.footprint == fp && x.method == m)
            .ok_or_else(|| format!("no interference result {m} at {fp}"))
    };
    let big = FOOTPRINTS[1];
    let _ = write!(
        p,
        "**On a textured scene, prefilter instead of adding rays**: on {i}, prefiltered \
         has FLIP {} for {} instr/px on the chip, centre {} for {}, and stratified 4x4 \
         still {} for {}",
        flip(ip.row.flip),
        chip_of(ip),
        flip(ic.row.flip),
        chip_of(ic),
        flip(is4.row.flip),
        chip_of(is4),
    );
    for (b, c, pf) in textured.iter().filter(|(b, _, _)| b.name() != i) {
        let bd = b.settings().max_depth;
        let _ = write!(
            p,
            "; on {}, prefiltered has FLIP {} against centre's {}, one ray per pixel \
             either way ({} and {} ns/px){}",
            b.name(),
            flip(pf.row.flip),
            flip(c.row.flip),
            ns(pf.row.ns_median),
            ns(c.row.ns_median),
            find(entries, b.name(), EXACT, "stratified:2", bd, 16).map_or(
                String::new(),
                |s2| format!(
                    ", stratified 2x2 {} for {} ns/px",
                    flip(s2.row.flip),
                    ns(s2.row.ns_median)
                )
            )
        );
    }
    let _ = write!(
        p,
        ". With pixels {big} times the fringe spacing (the study below), centre \
         sampling shows false fringes (row std {:.1} LSB where the truth has {:.1}; RMSE \
         {:.1} LSB), 5 random rays miss by {:.1} LSB, stratified 3x3 by {:.1} LSB, and \
         prefiltered by {:.2} LSB.",
        fr(big, "centre")?.row_std,
        fr(big, "truth")?.row_std,
        fr(big, "centre")?.rmse,
        fr(big, "random:5")?.rmse,
        fr(big, "stratified:3")?.rmse,
        fr(big, "prefiltered")?.rmse
    );
    Ok(p)
}
