//! `tessera trade`: the speed/accuracy rows of this build's math backend.

use super::{Error, parse_size};
use clap::{Args, ValueHint};
use image::RgbImage;
use std::path::PathBuf;
use tessera_core::builtin::Builtin;
use tessera_core::{RenderSettings, Viewport};
use tessera_host::{limits, trade};

/// The image size `trade` measures at by default.
const DEFAULT_SIZE: &str = "128x96";
/// The timed runs of each setting by default.
const DEFAULT_RUNS: usize = 5;

#[derive(Args)]
pub struct TradeArgs {
    /// Built-in scenes to measure, comma-separated [default: all]
    #[arg(long, value_delimiter = ',')]
    scenes: Vec<String>,
    /// Image size
    #[arg(long, value_parser = parse_size, default_value = DEFAULT_SIZE)]
    size: (u16, u16),
    /// Timed runs per setting (the median and the spread are reported; at most 1000)
    #[arg(long, default_value_t = DEFAULT_RUNS)]
    runs: usize,
    /// Also measure the f64 reference with each setting (the ceiling)
    #[arg(long)]
    reference: bool,
    /// Folder caching the converged references (NAME-WxH-ENCODING-HASH.png, the
    /// hash of the scene and the reference's settings), shared between builds of
    /// both backends
    #[arg(long, value_hint = ValueHint::DirPath)]
    truth_dir: Option<PathBuf>,
}

pub fn run(args: &TradeArgs) -> Result<(), Error> {
    let scenes: Vec<Builtin> = if args.scenes.is_empty() {
        Builtin::ALL.to_vec()
    } else {
        args.scenes
            .iter()
            .map(|n| Builtin::from_name(n).ok_or_else(|| Error::UnknownBuiltin(n.clone())))
            .collect::<Result<_, _>>()?
    };
    let vp = Viewport::new(args.size.0, args.size.1);
    limits::measured("trade", vp)?;
    limits::runs(args.runs)?;
    warn_work(&scenes, vp, args)?;
    println!("{}", trade::Row::TSV_HEADER);
    for b in scenes {
        let truth = truth(b, vp, args.truth_dir.as_ref())?;
        for row in trade::measure_scene(b, vp, args.runs, &truth, args.reference)? {
            println!("{}", row.tsv());
        }
    }
    Ok(())
}

/// Warns on stderr when the measurements may take more than
/// [`limits::WARN_SECONDS`] and more than at the defaults: the time `tessera
/// trade` takes at its defaults ([`limits::TRADE_DEFAULT_SECONDS`], measured),
/// times the ratio of the work bounds ([`limits::Work`]) of what is asked and of
/// the defaults. (The bounds themselves are far above what the converged
/// references take: every level of their depth 8 could double the rays.)
fn warn_work(scenes: &[Builtin], vp: Viewport, args: &TradeArgs) -> Result<(), Error> {
    let asked = bound(
        scenes,
        vp,
        args.runs,
        args.reference,
        args.truth_dir.as_ref(),
    )?;
    let (w, h) = parse_size(DEFAULT_SIZE).unwrap_or((128, 96));
    let default = bound(Builtin::ALL, Viewport::new(w, h), DEFAULT_RUNS, false, None)?;
    let ratio = asked / default.max(f64::MIN_POSITIVE);
    let seconds = limits::TRADE_DEFAULT_SECONDS * ratio;
    if ratio > 1.0 && seconds > limits::WARN_SECONDS {
        eprintln!(
            "tessera: warning: trade at {}x{} with {} run(s){} may take about {} on this \
             machine: {ratio:.1} times the work of `tessera trade` at its defaults \
             ({DEFAULT_SIZE}, {DEFAULT_RUNS} runs, every scene, no cached references: {}); \
             to make it cheaper: a smaller --size, fewer --runs or --scenes, a --truth-dir \
             that keeps the converged references",
            vp.width,
            vp.height,
            args.runs,
            if args.reference {
                " and --reference"
            } else {
                ""
            },
            limits::duration(seconds),
            limits::duration(limits::TRADE_DEFAULT_SECONDS),
        );
    }
    Ok(())
}

/// An upper bound of the seconds of `trade`'s work (see [`limits::Work`]): every
/// setting's `runs` timed runs on one thread, the converged references not in
/// `truth_dir` yet and, with `reference`, a reference render per setting.
fn bound(
    scenes: &[Builtin],
    vp: Viewport,
    runs: usize,
    reference: bool,
    truth_dir: Option<&PathBuf>,
) -> Result<f64, Error> {
    let mut seconds = 0.0;
    for &b in scenes {
        let desc = tessera_host::file::builtin_desc(b);
        let cached = truth_dir.is_some_and(|d| {
            d.join(trade::truth_file_name(b.name(), &desc, vp))
                .is_file()
        });
        seconds += b.with_scene(|view, _| {
            let mut secs = 0.0;
            for s in trade::grid(b.settings()) {
                let settings = RenderSettings {
                    sampler: s.sampler,
                    max_depth: s.depth,
                    ..trade::CONVERGED
                };
                let work = limits::Work::of(view, vp, &settings);
                secs += work.core_seconds(1) * runs.max(1) as f64;
                if reference {
                    secs += work.reference_seconds();
                }
            }
            if !cached {
                secs += limits::Work::of(view, vp, &trade::CONVERGED).reference_seconds();
            }
            secs
        })?;
    }
    Ok(seconds)
}

/// The converged reference of `b` at `vp`: read from `dir` when cached there,
/// else rendered (and cached when there is a `dir`).
fn truth(b: Builtin, vp: Viewport, dir: Option<&PathBuf>) -> Result<RgbImage, Error> {
    let desc = tessera_host::file::builtin_desc(b);
    let cached = dir.map(|d| d.join(trade::truth_file_name(b.name(), &desc, vp)));
    if let Some(p) = &cached
        && let Some(img) = trade::cached_truth(p, vp)?
    {
        return Ok(img);
    }
    let t = trade::converged(&desc, vp)?;
    if let Some(p) = &cached {
        if let Some(dir) = p.parent() {
            std::fs::create_dir_all(dir).map_err(|source| Error::Folder {
                path: dir.to_path_buf(),
                source,
            })?;
        }
        tessera_host::write_png(&t, p)?;
    }
    Ok(t)
}
