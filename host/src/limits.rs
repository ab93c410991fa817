//! What each command may be asked for, checked before any work starts; a
//! request beyond a limit is refused with the figure it would need.
//!
//! - Render threads: at most [`MAX_THREADS`] (0 = one per core).
//! - `render`: no size limit: it streams the PNG a row of tiles at a time, in
//!   memory proportional to the width (see [`crate::render_png`]).
//! - `compare` and `trade`: at most [`flip_pixels`] pixels (about 28.5 million,
//!   e.g. 5,300 x 5,300): FLIP refuses more than 2^34 filter operations at its
//!   default 67 pixels per degree. They keep whole images: at its peak `compare`
//!   holds the f64 reference's colours and signature (32 bytes a pixel) and
//!   the band it makes of them (1 more), FLIP being measured in bands
//!   ([`crate::compare::mean_flip`]): 924,616 KiB at 5342x5342 (`/usr/bin/time
//!   -v tessera compare --size 5342x5342`, release build). With
//!   the adaptive sampler the reference keeps 48 bytes a pixel more:
//!   2,234,768 KiB (`--sampler adaptive:2`). `trade` holds about as much at
//!   most, 35 bytes a pixel (a reference render, its 8-bit image and the
//!   converged one; counted, not measured: at that size its converged
//!   references alone are far too much work to run). `trade` runs at most
//!   [`MAX_RUNS`] timed runs.
//! - Work: before rendering, each command bounds the work from above ([`Work`]),
//!   and where the bound is above [`WARN_SECONDS`] on this machine, measures the
//!   rays a camera ray takes on a trial of a few pixels; it warns (it does not
//!   refuse) when the work so estimated may take more than [`WARN_SECONDS`].
//! - `simulate`: the simulated panel keeps whole frames: at most
//!   [`MEMORY_LIMIT`] bytes, counted as [`SIMULATE_BYTES_PER_PIXEL`] per pixel
//!   for the frame being drawn and 3 more per pixel of each frame kept for
//!   `--window`; an orbit has at most [`MAX_ORBIT_FRAMES`] frames, its GIF at
//!   most [`MAX_GIF_DELAY_MS`] between frames.

use crate::HostError;
use tessera_core::{
    Camera, RenderSettings, Renderer, Sampler, SceneView, Viewport, trace::RayCount,
};

/// The most render threads.
pub const MAX_THREADS: usize = 256;
/// The most memory a command may plan to take (4 GiB).
pub const MEMORY_LIMIT: u64 = 4 << 30;
/// Memory per pixel of the frame `simulate` draws: the panel's buffer, its RGB
/// picture, the copy handed back, and the GIF encoder's RGBA copy and indices.
pub const SIMULATE_BYTES_PER_PIXEL: u64 = 16;
/// The most frames of an orbit (one per tenth of a degree).
pub const MAX_ORBIT_FRAMES: u32 = 3600;
/// The most timed runs per setting of `trade`.
pub const MAX_RUNS: usize = 1000;
/// The longest delay between the frames of an orbit's GIF, in milliseconds: a
/// GIF counts delays in hundredths of a second, in 16 bits (65,535).
pub const MAX_GIF_DELAY_MS: u32 = 655_350;

/// `n` with thousands separators.
#[must_use]
pub fn thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A byte count for people: `1.5 GiB`, `300.0 MiB`, `12 bytes`.
#[must_use]
pub fn bytes(n: u64) -> String {
    const UNITS: [(&str, u64); 4] = [
        ("TiB", 1 << 40),
        ("GiB", 1 << 30),
        ("MiB", 1 << 20),
        ("KiB", 1 << 10),
    ];
    UNITS.iter().find(|(_, u)| n >= *u).map_or_else(
        || format!("{n} bytes"),
        |(name, u)| format!("{:.1} {name}", n as f64 / *u as f64),
    )
}

/// Checks a thread count (0 = one per core).
pub fn threads(n: usize) -> Result<usize, String> {
    if n > MAX_THREADS {
        return Err(format!(
            "{n} render threads is more than the {MAX_THREADS} allowed (0 = one per core, {} here)",
            std::thread::available_parallelism().map_or(1, std::num::NonZero::get)
        ));
    }
    Ok(n)
}

/// The radii, in pixels, of FLIP's two filters at the default pixels per
/// degree: the spatial (colour) filter's and the feature filter's (flip-rs
/// computes them in f32 as here). A pixel's error depends on no pixel farther
/// away.
#[cfg(feature = "cli")]
#[must_use]
pub fn flip_radii() -> (u64, u64) {
    use std::f32::consts::PI;
    let ppd = flip_rs::DEFAULT_PPD;
    let radius = (3.0 * (0.04 / (2.0 * (PI * PI))).sqrt() * ppd).ceil();
    let feature_radius = (3.0 * (0.5 * 0.082 * ppd)).ceil();
    (radius as u64, feature_radius as u64)
}

/// The most pixels FLIP measures at the default pixels per degree: its filter
/// work, `pixels x (16 x spatial taps + 14 x feature taps)`, is at most 2^34.
#[cfg(feature = "cli")]
#[must_use]
pub fn flip_pixels() -> u64 {
    let (radius, feature_radius) = flip_radii();
    let spatial = 2 * radius + 1;
    let feature = 2 * feature_radius + 1;
    (1u64 << 34) / (16 * spatial + 14 * feature)
}

fn pixels(vp: Viewport) -> u64 {
    u64::from(vp.width) * u64::from(vp.height)
}

/// Checks that `command` (compare, trade) can measure a `vp` image with FLIP.
#[cfg(feature = "cli")]
pub fn measured(command: &str, vp: Viewport) -> Result<(), HostError> {
    let (n, max) = (pixels(vp), flip_pixels());
    if n > max {
        let side = (max as f64).sqrt().floor() as u64;
        return Err(HostError::Limit(format!(
            "{command} at {}x{}: {} pixels is more than the {} that FLIP can measure (2^34 filter operations at {:.0} pixels per degree), e.g. {side}x{side}: choose a smaller --size",
            vp.width,
            vp.height,
            thousands(n),
            thousands(max),
            flip_rs::DEFAULT_PPD,
        )));
    }
    Ok(())
}

/// Checks the memory of `simulate`: `frames` frames of `vp`, all kept when
/// `keep` (for the window).
pub fn simulated(vp: Viewport, frames: u32, keep: bool) -> Result<(), HostError> {
    if frames == 0 || frames > MAX_ORBIT_FRAMES {
        return Err(HostError::Limit(format!(
            "--orbit {frames}: an orbit has 1 to {MAX_ORBIT_FRAMES} frames"
        )));
    }
    let kept = if keep { u64::from(frames) * 3 } else { 0 };
    let need = pixels(vp) * (SIMULATE_BYTES_PER_PIXEL + kept);
    if need > MEMORY_LIMIT {
        return Err(HostError::Limit(format!(
            "simulate at {}x{}{}: the simulated panel would need {} ({} bytes), more than the limit of {}: choose a smaller --size{}",
            vp.width,
            vp.height,
            if keep {
                format!(", {frames} frame(s) kept for the window")
            } else {
                String::new()
            },
            bytes(need),
            thousands(need),
            bytes(MEMORY_LIMIT),
            if keep { " or fewer frames" } else { "" }
        )));
    }
    Ok(())
}

/// Checks a delay between GIF frames, in milliseconds (see [`MAX_GIF_DELAY_MS`]).
pub fn gif_delay(ms: u32) -> Result<u32, String> {
    if ms > MAX_GIF_DELAY_MS {
        return Err(format!(
            "expected a delay from 0 to {MAX_GIF_DELAY_MS} ms (a GIF frame lasts at most \
             65535 hundredths of a second), got {ms}"
        ));
    }
    Ok(ms)
}

/// Checks the runs of `trade`.
pub fn runs(n: usize) -> Result<usize, HostError> {
    if n > MAX_RUNS {
        return Err(HostError::Limit(format!(
            "--runs {n}: at most {MAX_RUNS} timed runs per setting"
        )));
    }
    Ok(n)
}

/// Past this many seconds of estimated work a command warns before it starts.
pub const WARN_SECONDS: f64 = 60.0;

/// Nanoseconds a ray of the core takes on one thread, before testing
/// primitives: measured on the default scene (chapter-reflect, 4 primitives)
/// with `tessera render chapter-reflect --size 1280x960 --threads 1`, release
/// build, on the 2-core machine of the measurements.
pub const CORE_NS_PER_RAY: f64 = 30.0;
/// Nanoseconds more a ray of the core takes for each primitive of a flat list
/// (tested one by one): measured on scenes of 1,024 random boxes and of 199
/// random spheres at depth 2, one thread.
pub const CORE_NS_PER_TEST: f64 = 1.2;
/// Nanoseconds more a ray of the core takes for each level of a bounding volume
/// hierarchy (`log2(n + 1)` for `n` primitives): measured on a soup of 8,192
/// random triangles, on 1,024 spheres and on the teapot (1,088 faces).
pub const CORE_NS_PER_LEVEL: f64 = 24.0;
/// Nanoseconds a ray of the f64 reference takes (one thread), before testing
/// primitives: measured on chapter-reflect and the showcase (`tessera trade
/// --reference --size 64x48`: the reference's ns a pixel over the core's rays a
/// pixel).
pub const REFERENCE_NS_PER_RAY: f64 = 300.0;
/// Nanoseconds more a ray of the reference takes per primitive (it tests every
/// one): measured on the teapot's 1,089 primitives.
pub const REFERENCE_NS_PER_TEST: f64 = 8.0;

/// Seconds `tessera trade` takes at its defaults (every built-in scene at 128x96,
/// 5 runs, the converged references rendered): measured with `/usr/bin/time -v
/// tessera trade`, release build, on the 2-core machine of the measurements.
pub const TRADE_DEFAULT_SECONDS: f64 = 62.0;

/// An upper bound of the rays a render traces and of what each costs, from what
/// drives them: the pixels, the sampler's samples a pixel, the depth (each level
/// of reflection and refraction can double the rays), the lights (a shadow ray
/// each at every hit) and the primitives a ray is tested against.
#[derive(Clone, Debug, PartialEq)]
pub struct Work {
    /// The image.
    pub viewport: Viewport,
    /// The sampler.
    pub sampler: Sampler,
    /// Camera rays a pixel, at most.
    pub samples: u64,
    /// The recursion depth.
    pub depth: u8,
    /// Rays a hit sends on, at most: 0 (no mirror or glass, or depth 0), 1
    /// (mirrors), 2 (transparent materials: a reflected and a refracted ray).
    pub branching: u8,
    /// Lights that can change a colour: a shadow ray each at every hit.
    pub lights: u64,
    /// Primitives in flat lists, tested one by one by the core.
    pub flat: u64,
    /// Levels of the core's bounding volume hierarchies (`log2(n + 1)` for `n`
    /// primitives, summed over the hierarchies).
    pub levels: f64,
    /// Every primitive, mesh faces included: what the f64 reference tests.
    pub primitives: u64,
    /// Rays a camera ray took with its bounces and shadow rays, on average, on
    /// a trial ([`Work::trial`]; `None`: not measured).
    pub measured: Option<f64>,
    /// Nanoseconds a ray of the core took on the trial, on one thread (`None`:
    /// not measured; then [`CORE_NS_PER_RAY`] and its companions).
    pub measured_ns: Option<f64>,
}

/// The most pixels of a trial ([`Work::trial`]), across and down.
pub const TRIAL: (u32, u32) = (40, 30);

impl Work {
    /// The work of rendering `view` at `viewport` with `settings`.
    #[must_use]
    pub fn of(view: &SceneView<'_>, viewport: Viewport, settings: &RenderSettings) -> Self {
        let level = |n: usize| ((n + 1) as f64).log2();
        let (spheres, triangles) = (view.spheres().len(), view.triangles().len());
        let faces: Vec<usize> = view.meshes().iter().map(|m| m.faces().len()).collect();
        let mut flat = view.planes().len() + view.boxes().len();
        let primitives = flat + spheres + triangles + faces.iter().sum::<usize>();
        let mut levels: f64 = faces.iter().map(|&n| level(n)).sum();
        // As the host's scenes take hierarchies (desc::HostScene::with_view).
        for (n, crossover) in [
            (spheres, tessera_core::bvh::SPHERE_CROSSOVER),
            (triangles, tessera_core::bvh::CROSSOVER),
        ] {
            if n < crossover {
                flat += n;
            } else {
                levels += level(n);
            }
        }
        let materials = view.materials();
        let branching = if settings.max_depth == 0 {
            0
        } else if materials.iter().any(|m| m.transparency() > 0.0) {
            2
        } else {
            u8::from(materials.iter().any(|m| m.reflectivity() > 0.0))
        };
        let lights = view
            .lights()
            .iter()
            .filter(|l| l.intensity() > 0.0 && l.color().max_component() > 0.0)
            .count();
        // The adaptive and sparse samplers also trace the centre rays of an apron
        // round each tile: fewer than one more a pixel.
        let apron = matches!(
            settings.sampler,
            Sampler::Adaptive { .. } | Sampler::Sparse { .. }
        );
        Self {
            viewport,
            sampler: settings.sampler,
            samples: u64::from(settings.sampler.count()) + u64::from(apron),
            depth: settings.max_depth,
            branching,
            lights: lights as u64,
            flat: flat as u64,
            levels,
            primitives: primitives as u64,
            measured: None,
            measured_ns: None,
        }
    }

    /// Measures [`Work::measured`] and [`Work::measured_ns`]: one centre ray
    /// through each of up to [`TRIAL`] pixels spread evenly over the frame of
    /// `camera`, with this work's depth, its rays counted and timed (each pixel
    /// on its own: no tile lists, every primitive a candidate, so a ray costs
    /// rather more than in a render). At most 1,200 trees of rays: little beside
    /// the render it estimates for most scenes; the bound of the costliest (depth
    /// 8, glass, 64 lights) is 4e7 rays.
    ///
    /// # Errors
    ///
    /// The core's, if it refuses the frame.
    pub fn trial(&mut self, view: &SceneView<'_>, camera: &Camera) -> Result<(), HostError> {
        let settings = RenderSettings {
            sampler: Sampler::Centre,
            max_depth: self.depth,
            ..RenderSettings::default()
        };
        let renderer = Renderer::try_new(camera, self.viewport, settings)?;
        let (w, h) = (
            u32::from(self.viewport.width),
            u32::from(self.viewport.height),
        );
        let (across, down) = (w.min(TRIAL.0), h.min(TRIAL.1));
        let mut rays = RayCount::default();
        let start = std::time::Instant::now();
        for j in 0..down {
            for i in 0..across {
                // The middle of each of `across x down` equal cells.
                let x = ((2 * u64::from(i) + 1) * u64::from(w) / (2 * u64::from(across))) as u32;
                let y = ((2 * u64::from(j) + 1) * u64::from(h) / (2 * u64::from(down))) as u32;
                let _ = renderer.pixel_color(view, x, y, &mut rays);
            }
        }
        let ns = start.elapsed().as_secs_f64() * 1e9;
        self.measured = Some(rays.total() as f64 / f64::from(across * down).max(1.0));
        self.measured_ns = (rays.total() > 0).then(|| ns / rays.total() as f64);
        Ok(())
    }

    /// Pixels.
    #[must_use]
    pub fn pixels(&self) -> u64 {
        pixels(self.viewport)
    }

    /// Rays of a camera ray's tree, itself included, at most: 1 without
    /// bounces, `depth + 1` with mirrors, `2^(depth + 1) - 1` with glass.
    #[must_use]
    pub fn tree(&self) -> u64 {
        match self.branching {
            0 => 1,
            1 => u64::from(self.depth) + 1,
            _ => (1 << (u32::from(self.depth) + 1)) - 1,
        }
    }

    /// Rays a camera ray takes at most: its tree, and a shadow ray for each
    /// light at each hit of the tree.
    #[must_use]
    pub fn bound_per_sample(&self) -> u64 {
        self.tree() * (1 + self.lights)
    }

    /// Rays traced at most: [`Work::bound_per_sample`] for every sample.
    #[must_use]
    pub fn bound(&self) -> f64 {
        self.pixels() as f64 * self.samples as f64 * self.bound_per_sample() as f64
    }

    /// Rays traced, estimated: the bound, or with a trial ([`Work::trial`]) the
    /// rays a camera ray measured there for every sample.
    #[must_use]
    pub fn rays(&self) -> f64 {
        match self.measured {
            Some(per_sample) => self.pixels() as f64 * self.samples as f64 * per_sample,
            None => self.bound(),
        }
    }

    /// Nanoseconds a ray of the core takes on one thread: as measured on the
    /// trial, else from the measured rates ([`CORE_NS_PER_RAY`],
    /// [`CORE_NS_PER_TEST`], [`CORE_NS_PER_LEVEL`]).
    #[must_use]
    pub fn core_ns_per_ray(&self) -> f64 {
        self.measured_ns.unwrap_or(
            CORE_NS_PER_RAY + CORE_NS_PER_TEST * self.flat as f64 + CORE_NS_PER_LEVEL * self.levels,
        )
    }

    /// Seconds the core takes on `threads` threads for [`Work::rays`].
    #[must_use]
    pub fn core_seconds(&self, threads: usize) -> f64 {
        self.rays() * self.core_ns_per_ray() * 1e-9 / threads.max(1) as f64
    }

    /// Seconds the f64 reference takes for [`Work::rays`] (one thread; see
    /// [`REFERENCE_NS_PER_RAY`], [`REFERENCE_NS_PER_TEST`]).
    #[must_use]
    pub fn reference_seconds(&self) -> f64 {
        let ns = REFERENCE_NS_PER_RAY + REFERENCE_NS_PER_TEST * self.primitives as f64;
        self.rays() * ns * 1e-9
    }

    /// What drives the work, for a warning: `76,800 pixels (320x240) x 4096
    /// samples (random:4096) x 511 rays a sample (depth 8, transparent
    /// materials: 2 rays a hit) x 65 (64 lights: a shadow ray each a hit) =
    /// 1.0e13 rays at most, each tested against 17 primitives`.
    #[must_use]
    pub fn drivers(&self) -> String {
        let tree = match self.branching {
            0 if self.depth == 0 => "depth 0".to_string(),
            0 => format!("depth {}, no mirror or glass", self.depth),
            1 => format!("depth {}, mirrors: a ray a hit", self.depth),
            _ => format!("depth {}, transparent materials: 2 rays a hit", self.depth),
        };
        format!(
            "{} pixels ({}x{}) x {} samples ({}) x {} rays a sample ({tree}) x {} ({} lights: \
             a shadow ray each a hit) = {:.1e} rays at most, each tested against {} primitives",
            thousands(self.pixels()),
            self.viewport.width,
            self.viewport.height,
            self.samples,
            self.sampler,
            self.tree(),
            1 + self.lights,
            self.lights,
            self.bound(),
            thousands(self.primitives),
        )
    }
}

/// `seconds` for people: `45 s`, `12 minutes`, `81 hours`, `9 days`.
#[must_use]
pub fn duration(seconds: f64) -> String {
    if seconds < 120.0 {
        format!("{seconds:.0} s")
    } else if seconds < 7200.0 {
        format!("{:.0} minutes", seconds / 60.0)
    } else if seconds < 172_800.0 {
        format!("{:.0} hours", seconds / 3600.0)
    } else {
        format!("{:.0} days", seconds / 86_400.0)
    }
}

/// The warning for a command whose work may take `seconds` (from `work`'s
/// estimate), more than [`WARN_SECONDS`]; `None` below. `what` says what runs
/// (`the render on 2 thread(s)`).
#[must_use]
pub fn work_warning(what: &str, seconds: f64, work: &Work) -> Option<String> {
    (seconds > WARN_SECONDS).then(|| {
        let estimate = match work.measured {
            Some(rays) => format!(
                "about {} on this machine (a trial of {} pixels traced {rays:.0} rays a \
                 sample, {:.0} ns a ray; at most {} rays a sample: ",
                duration(seconds),
                TRIAL.0.min(u32::from(work.viewport.width))
                    * TRIAL.1.min(u32::from(work.viewport.height)),
                work.core_ns_per_ray(),
                work.bound_per_sample()
            ),
            None => format!("up to {} on this machine (", duration(seconds)),
        };
        format!(
            "{what} may take {estimate}{}); to make it cheaper: a smaller --size, fewer \
             samples (--sampler), a lower --depth",
            work.drivers()
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use tessera_core::builtin::Builtin;

    /// The bound of the costly fixture, by hand: 76,800 pixels x 4096 samples x
    /// (2^9 - 1) rays of a tree x (1 + 64) lights.
    #[test]
    fn the_bound_multiplies_pixels_samples_tree_and_lights() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/costly.toml");
        let desc = crate::file::load(std::path::Path::new(path)).unwrap();
        let scene = desc.to_core().unwrap();
        let vp = desc.viewport();
        let mut work = scene.with_view(|v| Work::of(v, vp, &desc.settings().unwrap()));
        assert_eq!((work.samples, work.tree(), work.lights), (4096, 511, 64));
        assert_eq!((work.flat, work.primitives, work.levels), (17, 17, 0.0));
        assert_eq!(work.bound(), 76_800.0 * 4096.0 * 511.0 * 65.0);
        assert!(work.core_seconds(2) > 3600.0 * 24.0);
        scene.with_view(|v| work.trial(v, scene.camera())).unwrap();
        let measured = work.measured.unwrap();
        assert!((65.0..33_215.0).contains(&measured), "{measured}");
        assert!(work.rays() < work.bound());
        // Mirrors: a ray a level; no bounces at depth 0.
        let b = Builtin::ChapterReflect;
        let reflect = b.with_scene(|v, _| Work::of(v, vp, &b.settings())).unwrap();
        assert_eq!((reflect.branching, reflect.tree()), (1, 2));
        let flat = RenderSettings {
            max_depth: 0,
            ..b.settings()
        };
        let direct = b.with_scene(|v, _| Work::of(v, vp, &flat)).unwrap();
        assert_eq!(direct.tree(), 1);
        assert_eq!(duration(59.4), "59 s");
        assert_eq!(duration(7000.0), "117 minutes");
        assert_eq!(duration(7200.0 * 10.0), "20 hours");
        assert_eq!(duration(86_400.0 * 3.0), "3 days");
    }
}
