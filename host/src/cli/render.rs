//! `tessera render`: a scene to a PNG, streamed a row of tiles at a time.

use super::{Common, Error, Source, describe, progress, threads, warn_work};
use clap::{Args, ValueHint};
use std::path::PathBuf;
use std::time::Instant;
use tessera_core::Renderer;
use tessera_host::limits;
use tessera_host::output::{self, Pending};

/// Where `render` writes when no `-o` is given.
const DEFAULT_OUTPUT: &str = "tessera.png";

#[derive(Args)]
pub struct RenderArgs {
    #[command(flatten)]
    common: Common,
    /// Output PNG (a symbolic link is followed)
    #[arg(short, long, default_value = DEFAULT_OUTPUT, value_hint = ValueHint::FilePath)]
    output: PathBuf,
    /// A glTF scene's camera, by its name [default: the file's first]
    #[arg(long)]
    camera: Option<String>,
    /// Frame N of the scene file's animation (its `[[keyframes]]`, at its
    /// `[render] fps`: the time N / fps) [default: the scene as the file places it]
    #[arg(long, value_name = "N")]
    frame: Option<u32>,
}

/// What `tessera` alone does: `tessera render` with its defaults.
impl Default for RenderArgs {
    fn default() -> Self {
        Self {
            common: Common::default(),
            output: PathBuf::from(DEFAULT_OUTPUT),
            camera: None,
            frame: None,
        }
    }
}

pub fn run(args: &RenderArgs) -> Result<(), Error> {
    let source = Source::open(args.common.scene.as_deref(), args.camera.as_deref())?;
    let source = match args.frame {
        Some(n) => source.at_frame(n)?,
        None => source,
    };
    let (settings, vp, tile) = source.settings(&args.common)?;
    let target = source.target(&args.output)?;
    let threads = threads(args.common.threads);
    let start = Instant::now();
    let (file, rays) = source.with_core(|view, camera| {
        let renderer = Renderer::try_new(camera, vp, settings)?;
        let work = limits::Work::of(view, vp, &settings);
        let what = format!("the render on {threads} thread(s)");
        warn_work(&source, &what, view, camera, work, |w| {
            w.core_seconds(threads)
        })?;
        // Created before the work, so an unwritable folder is known at once.
        let mut file = Pending::create(target)?;
        let (across, down) = renderer.tile_grid(tile);
        let work = u64::from(vp.width) * u64::from(vp.height) * u64::from(settings.sampler.count());
        let bar = progress(u64::from(across) * u64::from(down), work);
        let out = tessera_host::render_png(
            view,
            &renderer,
            tile,
            args.common.threads,
            &|| bar.inc(1),
            &mut file,
        );
        bar.finish_and_clear();
        match out {
            Ok((rays, _)) => Ok((file, rays)),
            Err(e) => Err(file.error(e).into()),
        }
    })?;
    let secs = start.elapsed().as_secs_f64();
    output::commit(vec![file])?;
    // Measured: what the sampler's bound does not say (an adaptive pixel, the
    // bounces and the shadow rays).
    let pixels = f64::from(vp.width) * f64::from(vp.height);
    println!(
        "{}, {tile}x{tile} tiles, {threads} thread(s): {secs:.3} s, {} rays, {:.2}/px \
         ({:.2} camera rays/px), {:.2} Mrays/s",
        describe(&source, vp, &settings),
        rays.total(),
        rays.total() as f64 / pixels,
        rays.primary as f64 / pixels,
        rays.total() as f64 / secs.max(1e-9) / 1e6,
    );
    println!("wrote {}", tessera_host::escape_path(&args.output));
    Ok(())
}
