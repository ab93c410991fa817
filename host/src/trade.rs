//! The speed/accuracy trade, measured: for each setting (sampler, recursion depth,
//! tile size) the host's nanoseconds per pixel on one thread (median of several
//! runs, with the spread) and the accuracy against a converged f64 reference, for
//! the math backend this binary was built with (exact, or `fast-math`) and for the
//! f64 reference itself (the ceiling of each sampler).
//!
//! Also the chapter's interference study: Young's fringes seen through pixels
//! smaller and larger than the fringe spacing, with centre sampling, 5 random rays,
//! stratified sampling and the exact box-filtered (prefiltered) texture.

use crate::HostError;
use crate::compare;
use crate::desc::SceneDesc;
use image::RgbImage;
use std::path::Path;
use std::time::Instant;
use tessera_core::builtin::Builtin;
use tessera_core::{RenderSettings, Renderer, Sampler, SceneView, Viewport, error::MAX_DEPTH};

/// One setting of the trade.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Setting {
    /// Sampler.
    pub sampler: Sampler,
    /// Recursion depth.
    pub depth: u8,
    /// Tile size.
    pub tile: usize,
}

/// The settings measured for a scene: every sampler at every depth (0, 1, 3 and
/// the scene's own) with 16x16 tiles, the full product of the settings that change
/// pixels; a scene whose own depth is 0 has no mirror or glass, and is measured at
/// that depth only (its rays bounce off nothing: every depth is the same image).
/// Then tiles 8 and 32 with the scene's sampler and depth (a tile size changes no
/// pixel, only the cost).
#[must_use]
pub fn grid(base: RenderSettings) -> Vec<Setting> {
    let mut out: Vec<Setting> = Vec::new();
    let mut add = |s: Setting| {
        if !out.contains(&s) {
            out.push(s);
        }
    };
    for sampler in [
        Sampler::Corner,
        Sampler::Centre,
        Sampler::Prefiltered,
        Sampler::Stratified(2),
        Sampler::Stratified(3),
        Sampler::Stratified(4),
        Sampler::Random(4),
        Sampler::Random(16),
        Sampler::adaptive(4),
        Sampler::sparse(),
        Sampler::sparse_spaced(4),
    ] {
        let depths: &[u8] = if base.max_depth == 0 {
            &[0]
        } else {
            &[0, 1, 3, base.max_depth]
        };
        for &depth in depths {
            add(Setting {
                sampler,
                depth,
                tile: 16,
            });
        }
    }
    for tile in [8, 16, 32] {
        add(Setting {
            sampler: base.sampler,
            depth: base.max_depth,
            tile,
        });
    }
    out
}

/// One measured row.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// Scene name.
    pub scene: String,
    /// The math backend: [`backend`] (`exact` or `fast-math`) for the core's
    /// rows, [`REFERENCE`] for the f64 reference's. The trade report renames the
    /// core's rows of each binary it builds after its own list of backends.
    pub backend: String,
    /// The setting.
    pub setting: Setting,
    /// Median nanoseconds per pixel on one thread.
    pub ns_median: f64,
    /// Fastest run, ns per pixel.
    pub ns_min: f64,
    /// Slowest run, ns per pixel.
    pub ns_max: f64,
    /// Mean FLIP against the converged reference.
    pub flip: f64,
    /// PSNR against the converged reference, dB.
    pub psnr: f64,
    /// Largest channel difference, LSB.
    pub max_diff: u8,
    /// Share of pixels within 1 LSB of the converged reference.
    pub within1: f64,
}

impl Row {
    /// The header of [`Row::tsv`].
    pub const TSV_HEADER: &'static str = "scene\tbackend\tsampler\tdepth\ttile\tns_median\tns_min\tns_max\tflip\tpsnr\tmax_diff\twithin1";

    /// A tab-separated line.
    #[must_use]
    pub fn tsv(&self) -> String {
        format!(
            "{}\t{}\t{}\t{}\t{}\t{:.1}\t{:.1}\t{:.1}\t{:.6}\t{:.2}\t{}\t{:.5}",
            self.scene,
            self.backend,
            self.setting.sampler,
            self.setting.depth,
            self.setting.tile,
            self.ns_median,
            self.ns_min,
            self.ns_max,
            self.flip,
            self.psnr,
            self.max_diff,
            self.within1
        )
    }

    /// Parses a line of [`Row::tsv`].
    pub fn parse_tsv(line: &str) -> Result<Self, String> {
        let f: Vec<&str> = line.split('\t').collect();
        let bad = || format!("not a trade row: {line:?}");
        if f.len() != 12 {
            return Err(bad());
        }
        let num = |i: usize| f[i].parse::<f64>().map_err(|_| bad());
        Ok(Self {
            scene: f[0].into(),
            backend: f[1].into(),
            setting: Setting {
                sampler: f[2].parse().map_err(|e| format!("{:?}: {e}", f[2]))?,
                depth: f[3].parse().map_err(|_| bad())?,
                tile: f[4].parse().map_err(|_| bad())?,
            },
            ns_median: num(5)?,
            ns_min: num(6)?,
            ns_max: num(7)?,
            flip: num(8)?,
            psnr: num(9)?,
            max_diff: f[10].parse().map_err(|_| bad())?,
            within1: num(11)?,
        })
    }
}

/// The backend name of the f64 reference's rows.
pub const REFERENCE: &str = "f64-reference";

/// The core's approximations this crate forwards (`--features`), in the order
/// [`backend`] names them.
const APPROXIMATIONS: [(&str, bool); 3] = [
    ("fast-rsqrt", cfg!(feature = "fast-rsqrt")),
    ("fast-recip", cfg!(feature = "fast-recip")),
    ("fast-pow", cfg!(feature = "fast-pow")),
];

/// The name of the math this binary's core was built with, as far as this crate's
/// features tell: `fast-math` with the feature `fast-math` (every approximation),
/// else the approximations it was built with joined by `+` (`fast-rsqrt+fast-pow`),
/// else `exact`. The trade report, which builds one binary per backend of its list
/// (a name and the cargo features it is built with), renames the core's rows it
/// reads from each binary after that backend ([`Row::backend`]).
#[must_use]
pub fn backend() -> String {
    if cfg!(feature = "fast-math") {
        return "fast-math".into();
    }
    let on: Vec<&str> = APPROXIMATIONS
        .iter()
        .filter(|(_, on)| *on)
        .map(|(name, _)| *name)
        .collect();
    if on.is_empty() {
        "exact".into()
    } else {
        on.join("+")
    }
}

/// The settings of the converged reference: 16x16 stratified samples per pixel,
/// the deepest recursion, sRGB-encoded (FLIP compares what a viewer sees).
pub const CONVERGED: RenderSettings = RenderSettings {
    sampler: Sampler::Stratified(16),
    max_depth: MAX_DEPTH,
    seed: 0x5eed,
    encoding: tessera_core::Encoding::Srgb,
};

/// The converged reference of a scene: the f64 renderer with [`CONVERGED`].
pub fn converged(desc: &SceneDesc, vp: Viewport) -> Result<RgbImage, HostError> {
    Ok(crate::reference::render(desc, vp, &CONVERGED)?.to_rgb8())
}

/// The file name of the converged reference of the scene `name` (described by
/// `desc`) at `vp` in a cache folder: `NAME-WxH-ENCODING-HASH.png`, the hash
/// (FNV-1a, 64 bits) of the scene's description (all but its `[render]` table,
/// which the reference does not use: it renders with [`CONVERGED`]) and of
/// [`CONVERGED`], so that a cached image made from another scene or other
/// settings (a linear one, say) is never taken for this one. (A change of the
/// reference renderer itself is not in the name: clear the folder then.)
#[must_use]
pub fn truth_file_name(name: &str, desc: &SceneDesc, vp: Viewport) -> String {
    let scene = SceneDesc {
        render: crate::desc::RenderDesc::default(),
        ..desc.clone()
    };
    let key = format!("{scene:?}|{CONVERGED:?}");
    let hash = key.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    });
    format!(
        "{name}-{}x{}-{}-{hash:016x}.png",
        vp.width, vp.height, CONVERGED.encoding
    )
}

/// The converged reference cached at `path` for `vp`: `None` when there is no
/// such file or it is not a PNG of `vp`'s size (it is rendered again and
/// replaced). A file there that is not a regular file (a FIFO, a device, a
/// folder) is refused, unread: its type is checked before it is opened, and it
/// is opened without waiting ([`crate::file`]'s reader of scene files).
pub fn cached_truth(path: &Path, vp: Viewport) -> Result<Option<RgbImage>, HostError> {
    if std::fs::metadata(path).is_err_and(|e| e.kind() == std::io::ErrorKind::NotFound) {
        return Ok(None);
    }
    let file =
        crate::file::open_regular(path, "cached reference").map_err(|message| HostError::Read {
            path: path.display().to_string(),
            message,
        })?;
    let decoded =
        image::ImageReader::with_format(std::io::BufReader::new(file), image::ImageFormat::Png)
            .decode();
    Ok(decoded
        .ok()
        .map(|img| img.to_rgb8())
        .filter(|img| img.dimensions() == (u32::from(vp.width), u32::from(vp.height))))
}

fn accuracy(img: &RgbImage, truth: &RgbImage) -> Result<compare::Accuracy, HostError> {
    // No silhouette band: every pixel counts.
    let none = vec![false; img.width() as usize * img.height() as usize];
    compare::measure_with_band(img, 0, truth, 0, &none)
}

fn row(
    scene: &str,
    backend: &str,
    setting: Setting,
    times: &mut [f64],
    img: &RgbImage,
    truth: &RgbImage,
) -> Result<Row, HostError> {
    times.sort_by(f64::total_cmp);
    let acc = accuracy(img, truth)?;
    Ok(Row {
        scene: scene.into(),
        backend: backend.into(),
        setting,
        ns_median: times.get(times.len() / 2).copied().unwrap_or(0.0),
        ns_min: times.first().copied().unwrap_or(0.0),
        ns_max: times.last().copied().unwrap_or(0.0),
        flip: acc.mean_flip,
        psnr: acc.psnr_db,
        max_diff: acc.max_abs_diff,
        within1: acc.share_within_all(1),
    })
}

/// Measures every setting of [`grid`] for a built-in scene with this binary's core
/// (one thread, `runs` runs each), and, when `reference` is set, with the f64
/// reference too (one run: it is the ceiling, not a contender for speed).
pub fn measure_scene(
    b: Builtin,
    vp: Viewport,
    runs: usize,
    truth: &RgbImage,
    reference: bool,
) -> Result<Vec<Row>, HostError> {
    let desc = crate::file::builtin_desc(b);
    let pixels = f64::from(vp.width) * f64::from(vp.height);
    let mut rows = Vec::new();
    for setting in grid(b.settings()) {
        let settings = RenderSettings {
            sampler: setting.sampler,
            max_depth: setting.depth,
            seed: 1,
            encoding: CONVERGED.encoding,
        };
        let timed = b.with_scene(|view, cam| {
            let renderer = Renderer::try_new(cam, vp, settings)?;
            timed_renders(view, &renderer, setting.tile, runs, pixels)
        })?;
        let (img, mut times) = timed?;
        rows.push(row(b.name(), &backend(), setting, &mut times, &img, truth)?);
        if reference {
            let start = Instant::now();
            let r = crate::reference::render(&desc, vp, &settings)?;
            let mut t = vec![start.elapsed().as_secs_f64() * 1e9 / pixels];
            rows.push(row(
                b.name(),
                REFERENCE,
                setting,
                &mut t,
                &r.to_rgb8(),
                truth,
            )?);
        }
    }
    Ok(rows)
}

/// Renders `frame` `runs` times (at least once) with tiles of `tile` pixels, one
/// after the other on this thread: the last image and each run's ns per pixel
/// (`pixels` in the frame).
fn timed_renders(
    view: &SceneView<'_>,
    renderer: &Renderer,
    tile: usize,
    runs: usize,
    pixels: f64,
) -> Result<(RgbImage, Vec<f64>), HostError> {
    let mut times = Vec::new();
    let mut render = || {
        let start = Instant::now();
        let img = with_tile_size!(tile, |N| crate::render_tiles::<N>(view, renderer, None))?;
        times.push(start.elapsed().as_secs_f64() * 1e9 / pixels);
        Ok::<_, HostError>(img)
    };
    let mut img = render()?;
    for _ in 1..runs {
        img = render()?;
    }
    Ok((img, times))
}

/// One image of the interference study.
#[derive(Clone, Debug)]
pub struct FringeResult {
    /// Pixel footprint on the screen divided by the fringe spacing.
    pub footprint: f64,
    /// `truth` (box-filtered f64), or the sampler's name.
    pub method: String,
    /// Root-mean-square difference from the truth, LSB (green channel).
    pub rmse: f64,
    /// Amplitude of the fringes (the component at the fringe frequency along the
    /// middle row, green channel, LSB).
    pub amplitude: f64,
    /// Standard deviation along the middle row (any pattern, true or aliased), LSB.
    pub row_std: f64,
    /// The image.
    pub image: RgbImage,
}

/// The interference screen seen head on with pixels `footprint` fringe spacings
/// wide: camera 1 m away, opening angle chosen for the footprint.
pub fn fringe_desc(footprint: f64, vp: Viewport) -> SceneDesc {
    let mut desc = crate::file::builtin_desc(Builtin::Interference);
    let spacing = 500e-9 * 3.0 / 2e-3; // the chapter's 0.75 mm
    let height = footprint * spacing * f64::from(vp.height);
    desc.camera.position = [0.0, 0.0, 1.0];
    desc.camera.forward = Some([0.0, 0.0, -1.0]);
    desc.camera.look_at = None;
    desc.camera.fovy = 2.0 * (height / 2.0).atan().to_degrees();
    desc.camera.near = 0.01;
    desc.camera.far = 10.0;
    desc
}

fn row_stats(img: &RgbImage, truth: Option<&RgbImage>, footprint: f64) -> (f64, f64, f64) {
    let (w, h) = img.dimensions();
    let g = |im: &RgbImage, x, y| f64::from(im.get_pixel(x, y).0[1]);
    let rmse = truth.map_or(0.0, |t| {
        let mut se = 0.0;
        for y in 0..h {
            for x in 0..w {
                let d = g(img, x, y) - g(t, x, y);
                se += d * d;
            }
        }
        (se / f64::from(w * h)).sqrt()
    });
    let y = h / 2;
    let row: Vec<f64> = (0..w).map(|x| g(img, x, y)).collect();
    let mean = row.iter().sum::<f64>() / row.len() as f64;
    let std = (row.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / row.len() as f64).sqrt();
    // Fringe frequency in cycles per pixel: 1 / footprint. The pixel centre x + 0.5
    // sits at screen position (x + 0.5 - w/2) * footprint spacings.
    let (mut c, mut s) = (0.0, 0.0);
    for (x, v) in row.iter().enumerate() {
        let phase = std::f64::consts::TAU * (x as f64 + 0.5 - f64::from(w) / 2.0) * footprint;
        c += (v - mean) * phase.cos();
        s += (v - mean) * phase.sin();
    }
    let n = row.len() as f64;
    let amplitude = 2.0 * ((c / n).powi(2) + (s / n).powi(2)).sqrt();
    (rmse, amplitude, std)
}

/// Renders the interference screen at each footprint with the truth (f64,
/// prefiltered: the exact box filter) and with the core using centre sampling, 5
/// random rays (the chapter's example), stratified 3x3 and the prefiltered texture.
pub fn interference_study(
    footprints: &[f64],
    vp: Viewport,
) -> Result<Vec<FringeResult>, HostError> {
    let mut out = Vec::new();
    for &fp in footprints {
        let desc = fringe_desc(fp, vp);
        let scene = desc.to_core()?;
        let truth_settings = RenderSettings {
            sampler: Sampler::Prefiltered,
            max_depth: 0,
            seed: 0,
            encoding: tessera_core::Encoding::Linear,
        };
        let truth = crate::reference::render(&desc, vp, &truth_settings)?.to_rgb8();
        let (_, amp, std) = row_stats(&truth, None, fp);
        out.push(FringeResult {
            footprint: fp,
            method: "truth".into(),
            rmse: 0.0,
            amplitude: amp,
            row_std: std,
            image: truth.clone(),
        });
        for sampler in [
            Sampler::Centre,
            Sampler::Random(5),
            Sampler::Stratified(3),
            Sampler::Prefiltered,
        ] {
            let settings = RenderSettings {
                sampler,
                max_depth: 0,
                seed: 5,
                encoding: tessera_core::Encoding::Linear,
            };
            let img = scene.with_view(|v| crate::render(v, scene.camera(), vp, settings, 16))?;
            let (rmse, amplitude, row_std) = row_stats(&img, Some(&truth), fp);
            out.push(FringeResult {
                footprint: fp,
                method: sampler.to_string(),
                rmse,
                amplitude,
                row_std,
                image: img,
            });
        }
    }
    Ok(out)
}

/// The study's images side by side: one row per footprint, one column per method
/// (truth, centre, random:5, stratified:3, prefiltered), 4-pixel white gutters.
#[must_use]
pub fn figure(results: &[FringeResult], per_row: usize) -> RgbImage {
    let Some(first) = results.first() else {
        return RgbImage::new(1, 1);
    };
    let (w, h) = first.image.dimensions();
    let gap = 4;
    let rows = results.len().div_ceil(per_row.max(1)) as u32;
    let cols = per_row as u32;
    let mut fig = RgbImage::from_pixel(
        cols * w + (cols + 1) * gap,
        rows * h + (rows + 1) * gap,
        image::Rgb([255, 255, 255]),
    );
    for (i, r) in results.iter().enumerate() {
        let (c, rr) = ((i % per_row) as u32, (i / per_row) as u32);
        let (x0, y0) = (gap + c * (w + gap), gap + rr * (h + gap));
        for (x, y, p) in r.image.enumerate_pixels() {
            fig.put_pixel(x0 + x, y0 + y, *p);
        }
    }
    fig
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cache name of a converged reference changes with the scene and the
    /// size, and names the encoding, so that a linear reference in the cache is
    /// never read as an sRGB one (which would make every FLIP of the report 0.6).
    #[test]
    fn a_cached_truth_is_named_by_everything_it_depends_on() {
        let vp = Viewport::new(128, 96);
        let desc = crate::file::builtin_desc(Builtin::ChapterReflect);
        let name = truth_file_name("chapter-reflect", &desc, vp);
        assert!(name.starts_with("chapter-reflect-128x96-srgb-"), "{name}");
        assert!(name.ends_with(".png"));
        assert_eq!(name, truth_file_name("chapter-reflect", &desc, vp));
        // The file's own [render] settings do not make the reference.
        let mut other = desc.clone();
        other.render.encoding = "linear".into();
        other.render.sampler = "stratified:4".into();
        assert_eq!(truth_file_name("chapter-reflect", &other, vp), name);
        let mut moved = desc.clone();
        moved.camera.position[0] += 1e-9;
        let mut lit = desc.clone();
        lit.ambient[1] += 0.01;
        for n in [
            truth_file_name("chapter-reflect", &lit, vp),
            truth_file_name("chapter-reflect", &moved, vp),
            truth_file_name("chapter-reflect", &desc, Viewport::new(96, 128)),
        ] {
            assert_ne!(n, name);
        }
    }

    #[test]
    fn grid_is_the_product_of_samplers_and_depths_without_duplicates() {
        // Eleven samplers at depths 0, 1 and 3 (the scene's own is 1), two more tiles.
        let g = grid(Builtin::ChapterReflect.settings());
        assert_eq!(g.len(), 11 * 3 + 2);
        // The showcase's own depth, 5, adds a fourth; a scene without bounces has one.
        assert_eq!(grid(Builtin::Showcase.settings()).len(), 11 * 4 + 2);
        assert_eq!(grid(Builtin::ChapterDirect.settings()).len(), 11 + 2);
        for (i, a) in g.iter().enumerate() {
            assert!(!g[i + 1..].contains(a));
        }
    }

    #[test]
    fn rows_round_trip_through_tsv() {
        let r = Row {
            scene: "x".into(),
            backend: "exact".into(),
            setting: Setting {
                sampler: Sampler::Stratified(3),
                depth: 1,
                tile: 8,
            },
            ns_median: 12.5,
            ns_min: 11.0,
            ns_max: 20.5,
            flip: 0.0123,
            psnr: 33.5,
            max_diff: 7,
            within1: 0.5,
        };
        assert_eq!(Row::parse_tsv(&r.tsv()).unwrap(), r);
    }
}
