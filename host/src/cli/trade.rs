//! `tessera trade`: the speed/accuracy rows of this build's math backend.

use super::{Error, parse_size};
use clap::Args;
use image::RgbImage;
use std::path::PathBuf;
use tessera::Viewport;
use tessera::builtin::Builtin;
use tessera_host::{limits, trade};

#[derive(Args)]
pub struct TradeArgs {
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
    /// Folder caching the converged references (NAME-WxH-ENCODING-HASH.png, the
    /// hash of the scene and the reference's settings), shared between builds of
    /// both backends
    #[arg(long)]
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
    println!("{}", trade::Row::TSV_HEADER);
    for b in scenes {
        let truth = truth(b, vp, args.truth_dir.as_ref())?;
        for row in trade::measure_scene(b, vp, args.runs, &truth, args.reference)? {
            println!("{}", row.tsv());
        }
    }
    Ok(())
}

/// The converged reference of `b` at `vp`: read from `dir` when cached there,
/// else rendered (and cached when there is a `dir`).
fn truth(b: Builtin, vp: Viewport, dir: Option<&PathBuf>) -> Result<RgbImage, Error> {
    let desc = tessera_host::file::builtin_desc(b);
    let cached = dir.map(|d| d.join(trade::truth_file_name(b.name(), &desc, vp)));
    if let Some(img) = cached.as_ref().and_then(|p| image::open(p).ok()) {
        return Ok(img.to_rgb8());
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
