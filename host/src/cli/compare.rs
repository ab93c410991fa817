//! `tessera compare`: the core (f32) against the reference (f64), and a heat map
//! of the differences when asked for one.

use super::{Common, Error, Source, describe, threads, warn_work};
use clap::{Args, ValueHint};
use image::RgbImage;
use std::path::PathBuf;
use tessera_core::{RenderSettings, Renderer, Viewport};
use tessera_host::output::{self, Pending};
use tessera_host::{HostError, compare, limits};

#[derive(Args)]
pub struct CompareArgs {
    #[command(flatten)]
    common: Common,
    /// Also write a heat map of the differences to this PNG (none by default)
    #[arg(long, value_name = "FILE", value_hint = ValueHint::FilePath)]
    heatmap: Option<PathBuf>,
}

pub fn run(args: &CompareArgs) -> Result<(), Error> {
    let source = Source::open(args.common.scene.as_deref(), None)?;
    let (settings, vp, tile) = source.settings(&args.common)?;
    limits::measured("compare", vp)?;
    let threads = threads(args.common.threads);
    let what = format!("compare (the core on {threads} thread(s), the f64 reference on one)");
    source.with_core(|view, camera| {
        let work = limits::Work::of(view, vp, &settings);
        // The core on the threads, its check for non-finite pixels and the f64
        // reference on one thread each.
        warn_work(&source, &what, view, camera, work, |w| {
            w.core_seconds(threads) + w.core_seconds(1) + w.reference_seconds()
        })
    })?;
    // Created before the work, so an unwritable folder is known at once.
    let heatmap = match &args.heatmap {
        Some(path) => Some((path, Pending::create(source.target(path)?)?)),
        None => None,
    };
    // The reference first, and only what is measured kept of it (the silhouette
    // band and its 8-bit image: 4 bytes a pixel of its 32), each made once the
    // part it no longer needs is gone, so that the peak is the reference's own
    // 32 bytes a pixel and one more.
    let mut reference = tessera_host::reference::render(&source.desc(), vp, &settings)
        .map_err(|e| source.error(e))?;
    let (w, h) = (u32::from(vp.width), u32::from(vp.height));
    let band = compare::silhouette_band(w, h, &std::mem::take(&mut reference.signature))?;
    let ref_img = reference.to_rgb8();
    let reference_non_finite = reference.non_finite();
    drop(reference);
    let (core_img, core_non_finite) = core_image(&source, vp, settings, tile, args.common.threads)?;
    let acc = compare::measure_with_band(
        &core_img,
        core_non_finite,
        &ref_img,
        reference_non_finite,
        &band,
    )?;
    println!(
        "{}: core (f32, {}) vs reference (f64)",
        describe(&source, vp, &settings),
        match tessera_host::trade::backend().as_str() {
            "exact" => "exact math".to_string(),
            other => other.to_string(),
        },
    );
    println!("{acc}");
    if let Some((path, mut file)) = heatmap {
        let map = compare::heatmap_with_band(&core_img, &ref_img, &band);
        if let Err(e) = tessera_host::encode_png(&map, &mut file) {
            return Err(file.error(HostError::Write(e)).into());
        }
        output::commit(vec![file])?;
        println!(
            "wrote {} (black: equal, blue: 1 LSB, green: 2, yellow: 3-4, red: 5+; grey: band)",
            tessera_host::escape_path(path)
        );
    }
    if acc.meets_bar() {
        Ok(())
    } else {
        Err(Error::BelowBar {
            name: source.name().to_string(),
            shortfall: acc.shortfall(),
        })
    }
}

/// The core's image and its number of non-finite pixels.
fn core_image(
    source: &Source,
    vp: Viewport,
    settings: RenderSettings,
    tile: usize,
    threads: usize,
) -> Result<(RgbImage, usize), Error> {
    source.with_core(|view, camera| {
        let renderer = Renderer::try_new(camera, vp, settings)?;
        let (img, _) = tessera_host::render_with(view, &renderer, tile, threads, &|| {})?;
        let mut non_finite = 0;
        for y in 0..u32::from(vp.height) {
            for x in 0..u32::from(vp.width) {
                if !renderer.pixel_color(view, x, y, &mut ()).is_finite() {
                    non_finite += 1;
                }
            }
        }
        Ok((img, non_finite))
    })
}
