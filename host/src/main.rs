//! `tessera`: render a scene to PNG, or compare the core with the f64 reference.
//!
//! ```text
//! tessera                                   # = tessera render: the default scene -> tessera.png
//! tessera render [SCENE] -o out.png [--size WxH] [--tile N] [--sampler S] [--depth D] [--seed S] [--threads N]
//! tessera compare [SCENE] [--heatmap diff.png] ...
//! tessera simulate [SCENE] [--color rgb565] [-o panel.png] [--orbit 36 -o orbit.gif]
//! tessera scenes                            # list the built-in scenes
//! ```
//! SCENE is a built-in scene name or a `.toml` scene file.
//!
//! Outputs are written through a temporary file next to them and renamed, all at
//! once when there are several; see `OUTPUT_HELP` for what is refused.

use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;
use tessera::builtin::Builtin;
use tessera::{Frame, RenderSettings, Viewport};
use tessera_host::desc::SceneDesc;
use tessera_host::output::{self, Pending, Target};
use tessera_host::{HostError, limits};

/// How outputs are written (shown by `--help`).
const OUTPUT_HELP: &str = "\
Output files: each is written to a temporary file next to it (.tessera-PID-N.tmp) \
and renamed onto it when complete, so an existing file is replaced whole or left \
untouched; Ctrl-C, SIGTERM, SIGHUP and a file size limit leave no temporary file. \
Several outputs (orbit frames) are all or nothing. Refused before any work: an \
output that exists and is not a regular file (a folder, a device such as /dev/null, \
a FIFO), and the input scene file itself. A symbolic link is followed: the file it \
names is written (created, for a dangling link) and the link stays; a link to a \
folder is refused.

Limits, checked before any work: --threads at most 256; compare and trade at most \
about 28.5 million pixels (FLIP's work limit); simulate at most 4 GiB for its \
panel, and 3600 orbit frames. render has no size limit: it streams the PNG a row \
of tiles at a time.

Exit status: 0 on success, 1 on an error or when compare's accuracy bar is not met, \
2 on a bad command line.";

#[derive(Parser)]
#[command(
    name = "tessera",
    version,
    about = "A ray tracer for microcontrollers: host tools",
    after_long_help = OUTPUT_HELP
)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to a PNG (the default command).
    #[command(after_long_help = OUTPUT_HELP)]
    Render(RenderArgs),
    /// Render with the core (f32) and the reference (f64) and print the accuracy.
    #[command(after_long_help = OUTPUT_HELP)]
    Compare(CompareArgs),
    /// Draw a scene onto a simulated display panel (embedded-graphics-simulator) and
    /// save what the panel shows.
    #[command(after_long_help = OUTPUT_HELP)]
    Simulate(SimulateArgs),
    /// Measure the speed/accuracy trade of this build's math backend: one row per
    /// setting (tab-separated), host ns/pixel on one thread and accuracy against a
    /// converged f64 reference.
    Trade(TradeArgs),
    /// List the built-in scenes.
    Scenes,
}

#[derive(Args)]
struct TradeArgs {
    /// Built-in scenes to measure, comma-separated [default: all]
    #[arg(long, value_delimiter = ',')]
    scenes: Vec<String>,
    /// Image size
    #[arg(long, value_parser = parse_size, default_value = "128x96")]
    size: (u16, u16),
    /// Timed runs per setting (the median and the spread are reported; at most 1000)
    #[arg(long, default_value_t = 5)]
    runs: usize,
    /// Also measure the f64 reference with each setting (the ceiling)
    #[arg(long)]
    reference: bool,
    /// Folder caching the converged references (NAME-WxH.png), shared between
    /// builds of both backends
    #[arg(long)]
    truth_dir: Option<PathBuf>,
}

#[derive(Args)]
struct SimulateArgs {
    #[command(flatten)]
    common: Common,
    /// The panel's colour type: rgb565, rgb555, rgb888 or gray8
    #[arg(long, default_value = "rgb565")]
    color: tessera_host::simulate::PanelColor,
    /// Output: a PNG, or with --orbit an animated GIF (.gif) or numbered PNG frames
    /// (NAME-000.png, ...) [default: simulator.png, or simulator-orbit.gif]
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Render an orbit of the camera around what it looks at, in this many frames
    /// (1 to 3600)
    #[arg(long)]
    orbit: Option<u32>,
    /// Delay between orbit frames in the GIF, milliseconds
    #[arg(long, default_value_t = 80)]
    delay_ms: u32,
    /// Also show the frame(s) in an SDL window (build with --features sdl)
    #[arg(long)]
    window: bool,
}

#[derive(Args, Default)]
struct Common {
    /// A built-in scene name (see `tessera scenes`) or a .toml scene file
    /// [default: the chapter's second picture, chapter-reflect]
    scene: Option<String>,
    /// Image size in pixels, WxH [default: the scene file's, or 320x240]
    #[arg(long, value_parser = parse_size)]
    size: Option<(u16, u16)>,
    /// Samples per pixel: corner, centre, prefiltered, offset:X,Y, stratified:K, random:N
    #[arg(long)]
    sampler: Option<tessera::Sampler>,
    /// Reflection/refraction depth (0 to 8)
    #[arg(long)]
    depth: Option<u8>,
    /// Seed of the random samplers
    #[arg(long)]
    seed: Option<u32>,
    /// Tile size: 8, 16 or 32
    #[arg(long, value_parser = parse_tile)]
    tile: Option<usize>,
    /// Render threads (0 = one per core; at most 256)
    #[arg(long, default_value_t = 0, value_parser = parse_threads)]
    threads: usize,
}

#[derive(Args, Default)]
struct RenderArgs {
    #[command(flatten)]
    common: Common,
    /// Output PNG (a symbolic link is followed; see below)
    #[arg(short, long, default_value = "tessera.png")]
    output: PathBuf,
}

#[derive(Args)]
struct CompareArgs {
    #[command(flatten)]
    common: Common,
    /// Where to write the difference heat-map PNG
    #[arg(long, default_value = "compare-heatmap.png")]
    heatmap: PathBuf,
}

fn parse_size(s: &str) -> Result<(u16, u16), String> {
    let bad = || format!("expected WxH with 1 to 65535 pixels each, like 320x240, got {s:?}");
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(bad)?;
    let w: u16 = w.trim().parse().map_err(|_| bad())?;
    let h: u16 = h.trim().parse().map_err(|_| bad())?;
    if w == 0 || h == 0 {
        return Err(bad());
    }
    Ok((w, h))
}

fn parse_threads(s: &str) -> Result<usize, String> {
    let n: usize = s
        .parse()
        .map_err(|_| format!("expected a number of threads (0 = one per core), got {s:?}"))?;
    limits::threads(n)
}

fn parse_tile(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(n) if tessera_host::TILE_SIZES.contains(&n) => Ok(n),
        _ => Err(format!("expected 8, 16 or 32, got {s:?}")),
    }
}

/// A scene to render: a built-in (rendered from the core's own code) or a file.
enum Source {
    Builtin(Builtin),
    File(String, Box<SceneDesc>),
}

impl Source {
    fn open(name: Option<&str>) -> Result<Self, String> {
        let Some(name) = name else {
            return Ok(Self::Builtin(Builtin::DEFAULT));
        };
        if let Some(b) = Builtin::from_name(name) {
            return Ok(Self::Builtin(b));
        }
        let path = Path::new(name);
        if !path.exists() && !name.ends_with(".toml") {
            let names: Vec<&str> = Builtin::ALL.iter().map(|b| b.name()).collect();
            return Err(format!(
                "{name:?} is neither a built-in scene ({}) nor an existing file",
                names.join(", ")
            ));
        }
        let desc = tessera_host::file::load(path).map_err(|e| e.to_string())?;
        // Accepted values that look like mistakes (fovy in radians, no light, ...).
        for w in tessera_host::file::warnings(&desc) {
            eprintln!("tessera: warning: {name}: {w}");
        }
        Ok(Self::File(name.to_string(), Box::new(desc)))
    }

    /// The scene file, which no output may replace.
    fn input(&self) -> Option<&Path> {
        match self {
            Self::Builtin(_) => None,
            Self::File(n, _) => Some(Path::new(n)),
        }
    }

    /// Checks an output path against the input (see [`Target::check`]).
    fn target(&self, path: &Path) -> Result<Target, String> {
        let inputs: Vec<&Path> = self.input().into_iter().collect();
        Target::check(path, &inputs).map_err(|e| e.to_string())
    }

    fn name(&self) -> &str {
        match self {
            Self::Builtin(b) => b.name(),
            Self::File(n, _) => n,
        }
    }

    /// The scene description (for the reference).
    fn desc(&self) -> SceneDesc {
        match self {
            Self::Builtin(b) => tessera_host::file::builtin_desc(*b),
            Self::File(_, d) => (**d).clone(),
        }
    }

    /// The scene's own settings, viewport and tile size.
    fn defaults(&self) -> Result<(RenderSettings, Viewport, usize), String> {
        match self {
            Self::Builtin(b) => Ok((b.settings(), Viewport::new(320, 240), 16)),
            Self::File(name, d) => Ok((
                d.settings().map_err(|e| format!("{name}: {e}"))?,
                d.viewport(),
                d.render.tile,
            )),
        }
    }

    /// Settings, viewport and tile size after the command-line overrides.
    fn settings(&self, c: &Common) -> Result<(RenderSettings, Viewport, usize), String> {
        let (mut s, mut vp, mut tile) = self.defaults()?;
        if let Some(x) = c.sampler {
            s.sampler = x;
        }
        if let Some(d) = c.depth {
            s.max_depth = d;
        }
        if let Some(x) = c.seed {
            s.seed = x;
        }
        if let Some((w, h)) = c.size {
            vp = Viewport::new(w, h);
        }
        if let Some(t) = c.tile {
            tile = t;
        }
        s.validate().map_err(|e| e.to_string())?;
        Ok((s, vp, tile))
    }

    /// Runs `f` with the core scene's view and camera.
    fn with_core<R>(
        &self,
        f: impl FnOnce(&tessera::SceneView<'_>, &tessera::Camera) -> R,
    ) -> Result<R, String> {
        match self {
            Self::Builtin(b) => b.with_scene(f).map_err(|e| e.to_string()),
            Self::File(name, d) => {
                let s = d.to_core().map_err(|e| format!("{name}: {e}"))?;
                Ok(f(&s.view(), s.camera()))
            }
        }
    }
}

fn progress(tiles: u64, work: u64) -> ProgressBar {
    // Only on a terminal, and only for renders that take more than a moment.
    if !std::io::stderr().is_terminal() || work < (1 << 21) {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(tiles);
    if let Ok(style) = ProgressStyle::with_template("{bar:40} {pos}/{len} tiles, {eta} left") {
        bar.set_style(style);
    }
    bar
}

/// `NAME: WxH, N sample(s)/px (SAMPLER), depth D`: the start of every summary line.
fn describe(source: &Source, vp: Viewport, settings: &RenderSettings) -> String {
    format!(
        "{}: {}x{}, {} sample(s)/px ({}), depth {}",
        source.name(),
        vp.width,
        vp.height,
        settings.sampler.count(),
        settings.sampler,
        settings.max_depth
    )
}

fn render(args: &RenderArgs) -> Result<(), String> {
    let source = Source::open(args.common.scene.as_deref())?;
    let (settings, vp, tile) = source.settings(&args.common)?;
    let target = source.target(&args.output)?;
    let start = Instant::now();
    let (file, rays) = source.with_core(|view, camera| {
        let frame = Frame::try_new(camera, vp, settings).map_err(|e| e.to_string())?;
        // Created before the work, so an unwritable folder is known at once.
        let mut file = Pending::create(target).map_err(|e| e.to_string())?;
        let (across, down) = frame.tile_grid(tile);
        let work = u64::from(vp.width) * u64::from(vp.height) * u64::from(settings.sampler.count());
        let bar = progress(u64::from(across) * u64::from(down), work);
        let out = tessera_host::render_png(
            view,
            &frame,
            tile,
            args.common.threads,
            &|| bar.inc(1),
            &mut file,
        );
        bar.finish_and_clear();
        match out {
            Ok((rays, _)) => Ok((file, rays)),
            Err(e) => Err(file.error(e).to_string()),
        }
    })??;
    let secs = start.elapsed().as_secs_f64();
    output::commit(vec![file]).map_err(|e| e.to_string())?;
    let threads = if args.common.threads == 0 {
        rayon::current_num_threads()
    } else {
        args.common.threads
    };
    println!(
        "{}, {tile}x{tile} tiles, {threads} thread(s): {secs:.3} s, {} rays, {:.2} Mrays/s",
        describe(&source, vp, &settings),
        rays.total(),
        rays.total() as f64 / secs.max(1e-9) / 1e6,
    );
    println!("wrote {}", args.output.display());
    Ok(())
}

fn compare(args: &CompareArgs) -> Result<(), String> {
    let source = Source::open(args.common.scene.as_deref())?;
    let (settings, vp, tile) = source.settings(&args.common)?;
    limits::measured("compare", vp).map_err(|e| e.to_string())?;
    let mut heatmap = Pending::create(source.target(&args.heatmap)?).map_err(|e| e.to_string())?;
    let (core_img, core_non_finite) = source.with_core(|view, camera| {
        let frame = Frame::try_new(camera, vp, settings).map_err(|e| e.to_string())?;
        let (img, _) = tessera_host::render_with(view, &frame, tile, args.common.threads, &|| {})
            .map_err(|e| e.to_string())?;
        let mut non_finite = 0;
        for y in 0..u32::from(vp.height) {
            for x in 0..u32::from(vp.width) {
                if !frame.pixel_color(view, x, y).is_finite() {
                    non_finite += 1;
                }
            }
        }
        Ok::<_, String>((img, non_finite))
    })??;
    let desc = source.desc();
    let reference = tessera_host::reference::render(&desc, vp, &settings)
        .map_err(|e| format!("{}: {e}", source.name()))?;
    let ref_img = reference.to_rgb8();
    let acc = tessera_host::compare::measure(
        &core_img,
        core_non_finite,
        &ref_img,
        reference.non_finite(),
        &reference.signature,
    )?;
    println!(
        "{}: core (f32, {}) vs reference (f64)",
        describe(&source, vp, &settings),
        if cfg!(feature = "fast-math") {
            "fast-math"
        } else {
            "exact math"
        },
    );
    println!("{acc}");
    let map = tessera_host::compare::heatmap(&core_img, &ref_img, &reference.signature);
    if let Err(e) = tessera_host::encode_png(&map, &mut heatmap) {
        return Err(heatmap.error(HostError::Write(e)).to_string());
    }
    output::commit(vec![heatmap]).map_err(|e| e.to_string())?;
    println!(
        "wrote {} (black: equal, blue: 1 LSB, green: 2, yellow: 3-4, red: 5+; grey: band)",
        args.heatmap.display()
    );
    if acc.meets_bar() {
        Ok(())
    } else {
        Err(format!("{}: {}", source.name(), acc.shortfall()))
    }
}

/// Where `simulate` writes: one PNG, an animated GIF, or numbered PNG frames.
enum SimOutput {
    Png(PathBuf),
    Gif(PathBuf),
    Frames(Vec<PathBuf>),
}

impl SimOutput {
    fn new(args: &SimulateArgs) -> Self {
        match (args.orbit, &args.output) {
            (None, out) => Self::Png(
                out.clone()
                    .unwrap_or_else(|| PathBuf::from("simulator.png")),
            ),
            (Some(n), out) => {
                let out = out
                    .clone()
                    .unwrap_or_else(|| PathBuf::from("simulator-orbit.gif"));
                if out
                    .extension()
                    .is_some_and(|e| e.eq_ignore_ascii_case("gif"))
                {
                    Self::Gif(out)
                } else {
                    let stem = out.with_extension("");
                    Self::Frames(
                        (0..n)
                            .map(|i| PathBuf::from(format!("{}-{i:03}.png", stem.display())))
                            .collect(),
                    )
                }
            }
        }
    }

    fn paths(&self) -> Vec<PathBuf> {
        match self {
            Self::Png(p) | Self::Gif(p) => vec![p.clone()],
            Self::Frames(v) => v.clone(),
        }
    }
}

fn simulate(args: &SimulateArgs) -> Result<(), String> {
    use tessera_host::simulate as sim;
    let source = Source::open(args.common.scene.as_deref())?;
    let (settings, mut vp, tile) = source.settings(&args.common)?;
    if args.common.size.is_none() {
        vp = Viewport::new(240, 240);
    }
    if args.orbit == Some(0) {
        return Err("--orbit needs at least 1 frame".into());
    }
    let count = args.orbit.unwrap_or(1);
    limits::simulated(vp, count, args.window).map_err(|e| e.to_string())?;
    let outputs = SimOutput::new(args);
    let inputs: Vec<&Path> = source.input().into_iter().collect();
    let mut targets = Target::check_all(&outputs.paths(), &inputs)
        .map_err(|e| e.to_string())?
        .into_iter();
    let start = Instant::now();
    let (files, shown) = source.with_core(|view, camera| {
        let cameras = match args.orbit {
            None => vec![*camera],
            Some(n) => sim::pivot(view, camera)
                .and_then(|pivot| sim::orbit(camera, pivot, n))
                .map_err(|e| e.to_string())?,
        };
        let bar = progress(
            cameras.len() as u64,
            u64::from(vp.width) * u64::from(vp.height) * cameras.len() as u64,
        );
        let mut files: Vec<Pending> = Vec::new();
        let mut gif = None;
        if let SimOutput::Gif(_) = outputs {
            let target = targets.next().ok_or("no output")?;
            let file = Pending::create(target).map_err(|e| e.to_string())?;
            gif = Some(
                sim::GifStream::new(file, vp.width, vp.height, args.delay_ms)
                    .map_err(|e| e.to_string())?,
            );
        }
        let mut shown = Vec::new();
        for cam in &cameras {
            let frame = Frame::try_new(cam, vp, settings).map_err(|e| e.to_string())?;
            let img =
                sim::simulate_tiled(view, &frame, args.color, tile).map_err(|e| e.to_string())?;
            if let Some(g) = gif.as_mut() {
                if let Err(e) = g.add(&img) {
                    return Err(g.writer().error(e).to_string());
                }
            } else {
                let target = targets.next().ok_or("no output")?;
                let mut file = Pending::create(target).map_err(|e| e.to_string())?;
                if let Err(e) = tessera_host::encode_png(&img, &mut file) {
                    return Err(file.error(HostError::Write(e)).to_string());
                }
                // Closed now: an orbit may have more frames than open files.
                file.finish().map_err(|e| e.to_string())?;
                files.push(file);
            }
            if args.window {
                shown.push(img);
            }
            bar.inc(1);
        }
        bar.finish_and_clear();
        if let Some(g) = gif {
            files.push(g.finish().map_err(|e| e.to_string())?);
        }
        Ok::<_, String>((files, shown))
    })??;
    let secs = start.elapsed().as_secs_f64();
    output::commit(files).map_err(|e| e.to_string())?;
    let written = match &outputs {
        SimOutput::Png(p) | SimOutput::Gif(p) => p.display().to_string(),
        SimOutput::Frames(v) => format!(
            "{} frames, {} ...",
            v.len(),
            v.first()
                .map(|p| p.display().to_string())
                .unwrap_or_default()
        ),
    };
    println!(
        "{}, {count} frame(s) on an {} panel: {secs:.3} s",
        describe(&source, vp, &settings),
        args.color,
    );
    println!("wrote {written}");
    if args.window {
        show_window(&shown, args.delay_ms)?;
    }
    Ok(())
}

#[cfg(feature = "sdl")]
fn show_window(frames: &[image::RgbImage], delay_ms: u32) -> Result<(), String> {
    use embedded_graphics_core::pixelcolor::Rgb888;
    use embedded_graphics_core::prelude::*;
    use embedded_graphics_simulator::{OutputSettings, SimulatorDisplay, SimulatorEvent, Window};
    let Some(first) = frames.first() else {
        return Ok(());
    };
    let size = Size::new(first.width(), first.height());
    let mut display = SimulatorDisplay::<Rgb888>::with_default_color(size, Rgb888::BLACK);
    let mut window = Window::new("tessera", &OutputSettings::default());
    let mut i = 0usize;
    loop {
        if let Some(f) = frames.get(i % frames.len()) {
            for (x, y, p) in f.enumerate_pixels() {
                let _ = Pixel(
                    Point::new(x as i32, y as i32),
                    Rgb888::new(p[0], p[1], p[2]),
                )
                .draw(&mut display);
            }
        }
        window.update(&display);
        if window.events().any(|e| e == SimulatorEvent::Quit) {
            return Ok(());
        }
        std::thread::sleep(std::time::Duration::from_millis(u64::from(delay_ms)));
        i += 1;
    }
}

#[cfg(not(feature = "sdl"))]
fn show_window(_: &[image::RgbImage], _: u32) -> Result<(), String> {
    Err("this tessera was built without the SDL window: rebuild with `--features sdl` (needs libsdl2-dev)".into())
}

fn trade(args: &TradeArgs) -> Result<(), String> {
    use tessera_host::trade;
    let scenes: Vec<Builtin> = if args.scenes.is_empty() {
        Builtin::ALL.to_vec()
    } else {
        args.scenes
            .iter()
            .map(|n| Builtin::from_name(n).ok_or(format!("unknown built-in scene {n:?}")))
            .collect::<Result<_, _>>()?
    };
    let vp = Viewport::new(args.size.0, args.size.1);
    limits::measured("trade", vp).map_err(|e| e.to_string())?;
    limits::runs(args.runs).map_err(|e| e.to_string())?;
    println!("{}", trade::Row::TSV_HEADER);
    for b in scenes {
        let cached = args
            .truth_dir
            .as_ref()
            .map(|d| d.join(format!("{}-{}x{}.png", b.name(), vp.width, vp.height)));
        let truth = match cached.as_ref().and_then(|p| image::open(p).ok()) {
            Some(img) => img.to_rgb8(),
            None => {
                let t = trade::converged(&tessera_host::file::builtin_desc(b), vp)
                    .map_err(|e| e.to_string())?;
                if let Some(p) = &cached {
                    if let Some(dir) = p.parent() {
                        std::fs::create_dir_all(dir)
                            .map_err(|e| format!("{}: {e}", dir.display()))?;
                    }
                    tessera_host::write_png(&t, p).map_err(|e| e.to_string())?;
                }
                t
            }
        };
        for row in trade::measure_scene(b, vp, args.runs, &truth, args.reference)
            .map_err(|e| e.to_string())?
        {
            println!("{}", row.tsv());
        }
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Err(e) = output::clean_up_on_signals() {
        eprintln!("tessera: warning: {e}");
    }
    let result = match cli.command {
        None => render(&RenderArgs::default_for_main()),
        Some(Command::Render(a)) => render(&a),
        Some(Command::Compare(a)) => compare(&a),
        Some(Command::Simulate(a)) => simulate(&a),
        Some(Command::Trade(a)) => trade(&a),
        Some(Command::Scenes) => {
            for b in Builtin::ALL {
                println!("{}", b.name());
            }
            Ok(())
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tessera: error: {e}");
            ExitCode::FAILURE
        }
    }
}

impl RenderArgs {
    fn default_for_main() -> Self {
        Self {
            common: Common::default(),
            output: PathBuf::from("tessera.png"),
        }
    }
}
