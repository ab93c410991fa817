//! The `tessera` command line: the arguments shared by the commands, and a module
//! per command (`render`, `compare`, `simulate`, `trade`; `scenes` is one loop).
//! Every command returns the one [`Error`] type.

mod bake;
mod compare;
mod error;
mod render;
mod simulate;
mod source;
mod trade;

use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use tessera::builtin::Builtin;
use tessera::{RenderSettings, Viewport};
use tessera_host::limits;

pub use error::Error;
use source::Source;

/// How outputs are written (shown by `--help`).
const OUTPUT_HELP: &str = "\
Output files: each is written to a temporary file next to it (.tessera-PID-N.tmp) \
and renamed onto it when complete, so an existing file is replaced whole or left \
untouched; Ctrl-C, SIGTERM, SIGHUP and a file size limit leave no temporary file. \
Several outputs (orbit frames) are all or nothing. Refused before any work: an \
output that exists and is not a regular file (a folder, a device such as /dev/null, \
a FIFO), and every file the command reads: the scene file and its meshes' OBJ \
files, also under another path or through a hard or symbolic link. A symbolic \
link is followed: the file it names is written (created, for a dangling link) and \
the link stays; a link to a folder is refused.

Inputs (the scene file, its meshes' OBJ files) must be regular files: a FIFO, a \
device, a socket or a folder is refused at once, unread.

Limits, checked before any work: --threads at most 256; compare and trade at most \
about 28.5 million pixels (FLIP's work limit), where compare's memory peaks at \
about 950 MB (33 bytes a pixel; 2.3 GB with --sampler adaptive:K, 80 bytes a \
pixel); simulate at most 4 GiB for its panel, 3600 orbit frames and a GIF delay \
of 655350 ms (--delay-ms). render has no size limit: it streams the PNG a row of \
tiles at a time.

Work: before it starts, each command bounds its work (samples a pixel, the rays a \
sample may take: each level of --depth can double them with glass, a shadow ray \
per light at each hit; the primitives) and, where that bound is above a minute on \
this machine, measures a trial of 1200 pixels; it warns (and goes on) when the \
estimate is above a minute, with what drives it.

Exit status: 0 on success, 1 on an error or when compare's accuracy bar is not met, \
2 on a bad command line.";

#[derive(Parser)]
#[command(
    name = "tessera",
    version,
    about = "A ray tracer for microcontrollers: host tools",
    after_long_help = OUTPUT_HELP
)]
pub struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to a PNG (the default command).
    #[command(after_long_help = OUTPUT_HELP)]
    Render(render::RenderArgs),
    /// Render with the core (f32) and the reference (f64) and print the accuracy.
    #[command(after_long_help = OUTPUT_HELP)]
    Compare(compare::CompareArgs),
    /// Draw a scene onto a simulated display panel (embedded-graphics-simulator) and
    /// save what the panel shows.
    #[command(after_long_help = OUTPUT_HELP)]
    Simulate(simulate::SimulateArgs),
    /// Measure the speed/accuracy trade of this build's math backend: one row per
    /// setting (tab-separated), host ns/pixel on one thread and accuracy against a
    /// converged f64 reference.
    Trade(trade::TradeArgs),
    /// Write a whole scene as Rust `static` data for a firmware (flash, not RAM):
    /// `SCENE` (a `tessera::BakedScene`: camera, size, settings, materials, lights,
    /// every primitive, meshes and BVHs), a constant per material (`MAT_<NAME>`),
    /// `WIDTH`, `HEIGHT`, `TILE` and `SceneLoops` (the tile loops the scene needs).
    /// Render it with `SCENE.view()?` and `SCENE.renderer()?`. A scene with meshes or
    /// 100 triangles or more needs the core's feature `bvh` (the file says so).
    #[command(after_long_help = OUTPUT_HELP)]
    Bake(bake::BakeArgs),
    /// List the built-in scenes.
    Scenes,
}

impl Cli {
    /// Runs the command (`render` with its defaults when none is given).
    pub fn run(self) -> Result<(), Error> {
        match self.command {
            None => render::run(&render::RenderArgs::default()),
            Some(Command::Render(a)) => render::run(&a),
            Some(Command::Compare(a)) => compare::run(&a),
            Some(Command::Simulate(a)) => simulate::run(&a),
            Some(Command::Trade(a)) => trade::run(&a),
            Some(Command::Bake(a)) => bake::run(&a),
            Some(Command::Scenes) => {
                for &b in Builtin::ALL {
                    println!("{}", b.name());
                }
                Ok(())
            }
        }
    }
}

/// The scene and the render settings, common to `render`, `compare` and `simulate`.
#[derive(Args, Default)]
struct Common {
    /// A built-in scene name (see `tessera scenes`) or a .toml scene file
    /// [default: the chapter's second picture, chapter-reflect]
    scene: Option<String>,
    /// Image size in pixels, WxH [default: the scene file's, or 320x240]
    #[arg(long, value_parser = parse_size)]
    size: Option<(u16, u16)>,
    /// Samples per pixel: corner, centre, prefiltered, offset:X,Y, stratified:K, random:N,
    /// adaptive:K or adaptive:K,T (K x K samples only where a pixel needs them), sparse or
    /// sparse:T (a ray through a quarter of the pixels, the others interpolated where they agree)
    #[arg(long)]
    sampler: Option<tessera::Sampler>,
    /// Reflection/refraction depth: 0 (no reflected or refracted ray) to 8
    #[arg(long, value_parser = parse_depth)]
    depth: Option<u8>,
    /// Seed of the random samplers
    #[arg(long)]
    seed: Option<u32>,
    /// How the pixels become 8 bits: srgb (what displays expect) or linear (the
    /// value itself) [default: the scene file's, or srgb]
    #[arg(long)]
    encoding: Option<tessera::Encoding>,
    /// Tile size: 8, 16 or 32
    #[arg(long, value_parser = parse_tile)]
    tile: Option<usize>,
    /// Render threads (0 = one per core; at most 256)
    #[arg(long, default_value_t = 0, value_parser = parse_threads)]
    threads: usize,
}

/// `e` with every value of the command line it quotes (an invalid value, an
/// unknown argument or subcommand, a suggestion or tip that repeats one) through
/// [`tessera_host::escape`]: clap echoes them as typed, and a value holding an
/// escape sequence would reach the terminal. The usage line, which clap makes
/// from the command's own definition, keeps its lines and styles; a tip loses
/// its colour.
pub fn escaped(mut e: clap::Error) -> clap::Error {
    use clap::builder::StyledStr;
    use clap::error::{ContextKind, ContextValue};
    let styled = |s: &StyledStr| StyledStr::from(tessera_host::escape(&s.to_string()));
    let quoted: Vec<_> = e
        .context()
        .filter(|(kind, _)| *kind != ContextKind::Usage)
        .filter_map(|(kind, value)| {
            let value = match value {
                ContextValue::String(s) => ContextValue::String(tessera_host::escape(s)),
                ContextValue::Strings(v) => {
                    ContextValue::Strings(v.iter().map(|s| tessera_host::escape(s)).collect())
                }
                ContextValue::StyledStr(s) => ContextValue::StyledStr(styled(s)),
                ContextValue::StyledStrs(v) => {
                    ContextValue::StyledStrs(v.iter().map(styled).collect())
                }
                _ => return None,
            };
            Some((kind, value))
        })
        .collect();
    for (kind, value) in quoted {
        e.insert(kind, value);
    }
    e
}

// The value parsers below return clap's message (a `String`): a bad value is a
// usage error, exit status 2, not an `Error`.

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

fn parse_depth(s: &str) -> Result<u8, String> {
    match s.trim().parse::<u8>() {
        Ok(d) if d <= tessera::error::MAX_DEPTH => Ok(d),
        _ => Err(format!(
            "expected a depth from 0 to {} (reflections and refractions), got {s:?}",
            tessera::error::MAX_DEPTH
        )),
    }
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

/// A progress bar of `tiles` steps, shown only on a terminal and only for renders
/// that take more than a moment (`work`: pixels times samples).
fn progress(tiles: u64, work: u64) -> ProgressBar {
    if !std::io::stderr().is_terminal() || work < (1 << 21) {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(tiles);
    if let Ok(style) = ProgressStyle::with_template("{bar:40} {pos}/{len} tiles, {eta} left") {
        bar.set_style(style);
    }
    bar
}

/// The render threads `n` asks for: itself, or for 0 one per core.
fn threads(n: usize) -> usize {
    if n == 0 {
        rayon::current_num_threads()
    } else {
        n
    }
}

/// Warns on stderr, before the work starts, when `what` (`the render on 2
/// thread(s)`) may take more than [`limits::WARN_SECONDS`]: `seconds(work)`.
/// Where the bound (see [`limits::Work`]) is above, a trial measures the rays a
/// sample takes first ([`limits::Work::trial`]), for a closer estimate.
fn warn_work(
    source: &Source,
    what: &str,
    view: &tessera::SceneView<'_>,
    camera: &tessera::Camera,
    mut work: limits::Work,
    seconds: impl Fn(&limits::Work) -> f64,
) -> Result<(), Error> {
    if seconds(&work) > limits::WARN_SECONDS {
        work.trial(view, camera)?;
    }
    if let Some(w) = limits::work_warning(what, seconds(&work), &work) {
        eprintln!(
            "tessera: warning: {}: {w}",
            tessera_host::escape(source.name())
        );
    }
    Ok(())
}

/// `NAME: WxH, N samples/px (SAMPLER), depth D`: the start of every summary line.
/// The adaptive and sparse samplers' count is the most a pixel takes (`at most
/// 17 samples/px (adaptive:4)`): most pixels take one (adaptive) or none
/// (sparse).
fn describe(source: &Source, vp: Viewport, settings: &RenderSettings) -> String {
    let n = settings.sampler.count();
    let bound = if matches!(
        settings.sampler,
        tessera::Sampler::Adaptive { .. } | tessera::Sampler::Sparse { .. }
    ) {
        "at most "
    } else {
        ""
    };
    format!(
        "{}: {}x{}, {bound}{n} sample{}/px ({}), depth {}",
        tessera_host::escape(source.name()),
        vp.width,
        vp.height,
        if n == 1 { "" } else { "s" },
        settings.sampler,
        settings.max_depth
    )
}
