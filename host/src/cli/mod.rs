//! The `tessera` command line: the arguments shared by the commands, the long
//! explanations (said once, in `tessera --help` and the manual page), and a module
//! per command (`render`, `compare`, `diff`, `simulate`, `trade`, `bake`, `new`;
//! `completions` and `man` in `generate`; `scenes` is one loop). Every command
//! returns the one [`Error`] type.

mod bake;
mod compare;
mod diff;
mod error;
mod generate;
mod image_file;
mod new;
mod render;
mod simulate;
mod source;
mod trade;

use clap::{Args, Parser, Subcommand};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use tessera_core::builtin::Builtin;
use tessera_core::{RenderSettings, Viewport};
use tessera_host::limits;

pub use error::Error;
use source::Source;

/// What each command's own `--help` ends with: where the long explanations are.
const SEE_MORE: &str = "More (this command in detail, output files, inputs, limits, exit \
status): `tessera --help`, or every command on one page: `tessera man`.";

/// Each command in detail, said once: in `tessera --help` (after the list of
/// commands) and in the manual page (`tessera man`, between the command's synopsis
/// and its options). A command's own `--help` is its purpose in one line and its
/// options.
const COMMAND_DETAILS: &[(&str, &str)] = &[
    (
        "render",
        "renders the scene to a PNG, streamed a row of tiles at a time; prints a one-line \
summary (size, samples, tiles, threads, time, rays a pixel, rays a second) and where \
it wrote. `tessera` alone is `tessera render` with its defaults: the default scene \
(chapter-reflect) to tessera.png.",
    ),
    (
        "compare",
        "renders the scene with the core (f32) and with the independent reference \
(f64) and prints PSNR, mean FLIP, the largest difference and the share of pixels \
within 0/1/2 LSB outside a 1-pixel band around silhouettes (where a rounding \
difference may flip a whole sample). The accuracy bar: at least 99.5% of the pixels \
outside the band within 1 LSB, all within 2 LSB, no NaN or infinity. --heatmap \
writes the differences as a PNG (black: equal, blue: 1 LSB, green: 2, yellow: 3-4, \
red: 5+; grey: band). Two image files: diff.",
    ),
    (
        "diff",
        "compares two image files of the same size pixel for pixel, A as FLIP's \
reference: each a PNG (8-bit, opaque: what render writes) or a PPM, binary (P6) or \
plain (P3), with maxval 255 and comments in its header (what the firmware example \
examples/qemu-m4f writes). It prints compare's figures without the silhouette band, \
the number of differing pixels and the 8 largest differences ((x, y) from the top \
left, A's and B's channels); --heatmap writes them as compare's does. Exit status 0 \
when the images are identical, 1 when they differ.",
    ),
    (
        "simulate",
        "draws the scene through the core's embedded-graphics output onto a \
simulated panel (240x240 unless --size is given) and saves what the panel shows, in \
its colour type and after its dithering; --orbit N renders N frames of the camera \
circling what it looks at, and --animate plays the scene file's [[keyframes]] (or a \
glTF file's first animation) at its fps, each frame what render --frame N renders, as \
an animated GIF (each frame lasting the scene's frame time) or numbered PNGs.",
    ),
    (
        "trade",
        "one tab-separated row per setting (sampler, depth) of this build's math \
backend (exact, or fast-math): host ns/pixel on one thread, the median of --runs \
timed runs and their spread, and the accuracy against a converged f64 reference.",
    ),
    (
        "bake",
        "writes the scene as Rust `static` data for a firmware (flash, not RAM): \
`SCENE` (a `tessera_core::BakedScene`: camera, size, settings, materials, lights, \
every primitive, meshes and BVHs), a constant per material (`MAT_<NAME>`), `WIDTH`, \
`HEIGHT`, `TILE` and `SceneLoops` (the tile loops the scene needs). Render it with \
`SCENE.view()?` and `SCENE.renderer()?`. A scene with meshes or 100 triangles or \
more needs the core's feature `bvh` (the file says so).",
    ),
    (
        "new",
        "creates a firmware crate in FOLDER (which must not exist; its last part is \
the crate's name) from tessera's template: a Cortex-M4F under qemu whose build.rs \
bakes scene.toml into flash, and whose firmware renders it tile by tile and writes \
tessera.ppm to the host (`cargo run --release` in the folder; `tessera diff \
tessera.ppm` against `tessera render scene.toml` finds them identical). Its \
README lists every piece and why. It depends on tessera-core and tessera-host \
from the crate registry at this version, or with `--path CHECKOUT` on a checkout \
of tessera's repository. The files are written in a hidden folder beside it, \
then renamed: a failed run leaves nothing half-written.",
    ),
    (
        "completions",
        "writes the completion script of bash, zsh, fish, elvish or powershell to \
stdout, e.g. `tessera completions bash > ~/.local/share/bash-completion/completions/tessera`.",
    ),
    (
        "man",
        "writes the manual page (roff) to stdout: every command and option on one \
page, e.g. `tessera man > tessera.1 && man ./tessera.1`.",
    ),
];

/// What every command shares, said once (in `tessera --help` and the manual page).
const GENERAL: &[(&str, &str)] = &[
    (
        "Scenes",
        "SCENE is a built-in scene's name (`tessera scenes` lists them) or a .toml \
scene file (the repository's scenes/README.md documents every key). render, compare \
and simulate take the scene's own size and [render] settings, or a built-in's at \
320x240, unless an option overrides them; the image is the same whatever --threads \
or --tile.",
    ),
    (
        "Output files",
        "each is written to a temporary file next to it (.tessera-PID-N.tmp) \
and renamed onto it when complete, so an existing file is replaced whole or left \
untouched; Ctrl-C, SIGTERM, SIGHUP and a file size limit leave no temporary file. \
Several outputs (orbit frames) are all or nothing. Refused before any work: an \
output that exists and is not a regular file (a folder, a device such as /dev/null, \
a FIFO), and every file the command reads: the scene file and its meshes' OBJ \
files (diff's images), also under another path or through a hard or symbolic link. \
A symbolic link is followed: the file it names is written (created, for a dangling \
link) and the link stays; a link to a folder is refused.",
    ),
    (
        "Inputs",
        "the scene file, its meshes' OBJ files and diff's images must be regular \
files: a FIFO, a device, a socket or a folder is refused at once, unread.",
    ),
    (
        "Limits",
        "checked before any work: --threads at most 256; compare, diff and trade \
at most about 28.5 million pixels (FLIP's work limit), where compare's memory peaks \
at about 950 MB (33 bytes a pixel; 2.3 GB with --sampler adaptive:K, 80 bytes a \
pixel); simulate at most 4 GiB for its panel, 3600 orbit or animation frames and a GIF delay of \
655350 ms (--delay-ms). render has no size limit: it streams the PNG a row of tiles \
at a time.",
    ),
    (
        "Work",
        "before it starts, each command bounds its work (samples a pixel, the rays \
a sample may take: each level of --depth can double them with glass, a shadow ray \
per light at each hit; the primitives) and, where that bound is above a minute on \
this machine, measures a trial of 1200 pixels; it warns (and goes on) when the \
estimate is above a minute, with what drives it.",
    ),
    (
        "Exit status",
        "0 on success, 1 on an error, when compare's accuracy bar is not met or \
when diff's images differ, 2 on a bad command line.",
    ),
];

/// The end of `tessera --help`: each command in detail, then what they share.
fn long_help() -> String {
    let commands = COMMAND_DETAILS
        .iter()
        .map(|(name, text)| format!("  {name}: {text}"))
        .collect::<Vec<_>>()
        .join("\n\n");
    let general = GENERAL
        .iter()
        .map(|(heading, text)| format!("{heading}: {text}"))
        .collect::<Vec<_>>()
        .join("\n\n");
    format!("Commands in detail:\n\n{commands}\n\n{general}")
}

#[derive(Parser)]
#[command(
    name = "tessera",
    version,
    about = "A ray tracer for microcontrollers: host tools",
    after_long_help = long_help()
)]
pub struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

// Each command's `--help`: its purpose in one line, its options and where the rest
// is ([`SEE_MORE`]); the rest is said once, in [`COMMAND_DETAILS`] and [`GENERAL`].
#[derive(Subcommand)]
enum Command {
    /// Render a scene to a PNG (the default command)
    #[command(after_help = SEE_MORE)]
    Render(render::RenderArgs),
    /// Render with the core (f32) and the reference (f64) and print the accuracy
    #[command(after_help = SEE_MORE)]
    Compare(compare::CompareArgs),
    /// Compare two image files (PNG or PPM) pixel for pixel
    #[command(after_help = SEE_MORE)]
    Diff(diff::DiffArgs),
    /// Draw a scene onto a simulated display panel and save what it shows
    #[command(after_help = SEE_MORE)]
    Simulate(simulate::SimulateArgs),
    /// Measure this build's math backend: speed and accuracy, a row per setting
    #[command(after_help = SEE_MORE)]
    Trade(trade::TradeArgs),
    /// Write a scene as Rust `static` data for a firmware's flash
    #[command(after_help = SEE_MORE)]
    Bake(bake::BakeArgs),
    /// Create a firmware crate from tessera's template (Cortex-M4F under qemu)
    #[command(after_help = SEE_MORE)]
    New(new::NewArgs),
    /// List the built-in scenes
    Scenes,
    /// Write a shell's completion script to stdout
    #[command(after_help = SEE_MORE)]
    Completions(generate::CompletionsArgs),
    /// Write the manual page (roff, every command on one page) to stdout
    #[command(after_help = SEE_MORE)]
    Man,
}

impl Cli {
    /// Runs the command (`render` with its defaults when none is given).
    pub fn run(self) -> Result<(), Error> {
        match self.command {
            None => render::run(&render::RenderArgs::default()),
            Some(Command::Render(a)) => render::run(&a),
            Some(Command::Compare(a)) => compare::run(&a),
            Some(Command::Diff(a)) => diff::run(&a),
            Some(Command::Simulate(a)) => simulate::run(&a),
            Some(Command::Trade(a)) => trade::run(&a),
            Some(Command::Bake(a)) => bake::run(&a),
            Some(Command::New(a)) => new::run(&a),
            Some(Command::Scenes) => {
                for &b in Builtin::ALL {
                    println!("{}", b.name());
                }
                Ok(())
            }
            Some(Command::Completions(a)) => generate::completions(&a),
            Some(Command::Man) => generate::man(),
        }
    }
}

/// The scene and the render settings, common to `render`, `compare` and `simulate`.
#[derive(Args, Default)]
struct Common {
    /// A built-in scene name (see `tessera scenes`), a .toml scene file or a glTF
    /// file (.gltf, .glb) [default: the chapter's second picture, chapter-reflect]
    scene: Option<String>,
    /// Image size in pixels, WxH [default: the scene file's, or 320x240]
    #[arg(long, value_parser = parse_size)]
    size: Option<(u16, u16)>,
    /// Samples per pixel: corner, centre, prefiltered, offset:X,Y, stratified:K, random:N,
    /// adaptive:K or adaptive:K,T (K x K samples only where a pixel needs them), sparse or
    /// sparse:T (a ray through a quarter of the pixels, the others interpolated where they agree),
    /// sparse:T,4 (the same from a ray through a sixteenth first, where every primitive shows 8
    /// pixels across)
    #[arg(long)]
    sampler: Option<tessera_core::Sampler>,
    /// Reflection/refraction depth: 0 (no reflected or refracted ray) to 8
    #[arg(long, value_parser = parse_depth)]
    depth: Option<u8>,
    /// Seed of the random samplers
    #[arg(long)]
    seed: Option<u32>,
    /// How the pixels become 8 bits: srgb (what displays expect) or linear (the
    /// value itself) [default: the scene file's, or srgb]
    #[arg(long)]
    encoding: Option<tessera_core::Encoding>,
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
        Ok(d) if d <= tessera_core::error::MAX_DEPTH => Ok(d),
        _ => Err(format!(
            "expected a depth from 0 to {} (reflections and refractions), got {s:?}",
            tessera_core::error::MAX_DEPTH
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
    view: &tessera_core::SceneView<'_>,
    camera: &tessera_core::Camera,
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
        tessera_core::Sampler::Adaptive { .. } | tessera_core::Sampler::Sparse { .. }
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
