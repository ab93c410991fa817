//! `tessera simulate`: a scene drawn onto a simulated display panel, one frame,
//! an orbit of the camera or the scene file's animation, saved as PNG(s) or a GIF
//! and optionally shown in a window.

use super::{Common, Error, Source, describe, progress, warn_work};
use clap::{Args, ValueHint};
use image::RgbImage;
use std::path::PathBuf;
use std::time::Instant;
use tessera_core::{RenderSettings, Renderer, SceneView, Viewport};
use tessera_host::desc::{DescError, SceneDesc};
use tessera_host::output::{self, Pending, Target};
use tessera_host::simulate::{self as sim, PanelColor};
use tessera_host::{HostError, limits};

#[derive(Args)]
pub struct SimulateArgs {
    #[command(flatten)]
    common: Common,
    /// The panel's colour type: rgb565, rgb555, rgb888 or gray8
    #[arg(long, default_value = "rgb565")]
    color: PanelColor,
    /// How the tiles' 8-bit channels become the panel's fewer bits: none (the
    /// nearest level, as embedded-graphics converts), bayer4 or bayer8 (ordered
    /// dithering by the pixel's position in the frame)
    #[arg(long, default_value = "bayer4", value_parser = parse_dither)]
    dither: tessera_core::dither::Dither,
    /// Output: a PNG, or with --orbit or --animate an animated GIF (.gif) or
    /// numbered PNG frames (NAME-000.png, ...) [default: simulator.png,
    /// simulator-orbit.gif or simulator-animation.gif]
    #[arg(short, long, value_hint = ValueHint::FilePath)]
    output: Option<PathBuf>,
    /// Render an orbit of the camera around what it looks at, in this many frames
    /// (1 to 3600)
    #[arg(long)]
    orbit: Option<u32>,
    /// Play the scene file's animation (its [[keyframes]]): frame 0 to the last
    /// at or before its end, at its [render] fps, each frame what `tessera render
    /// --frame N` renders (1 to 3600 frames)
    #[arg(long, conflicts_with = "orbit")]
    animate: bool,
    /// Delay between frames, in milliseconds, 0 to 655350 [default: 80, or with
    /// --animate the scene's frame time, 1000 / fps]. A GIF counts in
    /// hundredths of a second: the delay is rounded to the nearest 10 ms, a delay
    /// of 1 to 4 ms up to 10 ms (many viewers show delays under 20 ms at 100 ms)
    #[arg(long, value_parser = parse_delay)]
    delay_ms: Option<u32>,
    /// Also show the frame(s) in an SDL window (build with --features sdl)
    #[arg(long)]
    window: bool,
    /// Text drawn over the bottom-left corner of each tile before it reaches the
    /// panel, as a firmware labels its frames; `{frame}` is the frame's number
    #[arg(long, value_parser = parse_label)]
    label: Option<String>,
}

/// `--label`: printable ASCII, at most [`sim::MAX_LABEL`] characters once the
/// frame's number is in.
fn parse_label(s: &str) -> Result<String, String> {
    sim::check_label(&s.replace("{frame}", "9999")).map(|()| s.to_string())
}

/// `--dither`: a [`tessera_core::dither::Dither`].
fn parse_dither(s: &str) -> Result<tessera_core::dither::Dither, String> {
    s.parse()
        .map_err(|_| format!("expected none, bayer4 or bayer8, got {s:?}"))
}

/// `--delay-ms`: at most [`limits::MAX_GIF_DELAY_MS`].
fn parse_delay(s: &str) -> Result<u32, String> {
    let ms = s.trim().parse::<u32>().map_err(|_| {
        format!(
            "expected a delay from 0 to {} ms, got {s:?}",
            limits::MAX_GIF_DELAY_MS
        )
    })?;
    limits::gif_delay(ms).map_err(|_| {
        format!(
            "expected a delay from 0 to {} ms (a GIF frame lasts at most 65535 hundredths \
             of a second), got {s:?}",
            limits::MAX_GIF_DELAY_MS
        )
    })
}

/// Where `simulate` writes, checked: one animated GIF, or one PNG per frame.
enum Outputs {
    Gif(Target),
    Pngs(Vec<Target>),
}

impl Outputs {
    /// The outputs asked for, checked against the input, and how they are shown in
    /// the summary: a PNG, a GIF, or `N frames, NAME-000.png ...`.
    /// `frames`: how many an orbit or the animation has (`None`: one still
    /// frame).
    fn check(
        args: &SimulateArgs,
        source: &Source,
        frames: Option<u32>,
    ) -> Result<(Self, String), Error> {
        let default = match (args.orbit, args.animate) {
            (_, true) => "simulator-animation.gif",
            (Some(_), false) => "simulator-orbit.gif",
            (None, false) => "simulator.png",
        };
        let path = args.output.clone().unwrap_or_else(|| default.into());
        let Some(n) = frames else {
            let shown = path.display().to_string();
            return Ok((Self::Pngs(vec![source.target(&path)?]), shown));
        };
        if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("gif"))
        {
            let shown = path.display().to_string();
            return Ok((Self::Gif(source.target(&path)?), shown));
        }
        let stem = path.with_extension("");
        let paths: Vec<PathBuf> = (0..n)
            .map(|i| PathBuf::from(format!("{}-{i:03}.png", stem.display())))
            .collect();
        let shown = format!(
            "{} frames, {} ...",
            paths.len(),
            paths
                .first()
                .map(|p| p.display().to_string())
                .unwrap_or_default()
        );
        Ok((Self::Pngs(source.targets(&paths)?), shown))
    }

    /// Writes `frames` (as many as the PNG targets, for PNGs) to the temporary
    /// files, returned for [`output::commit`]. Each frame is handed to `keep` once
    /// written.
    fn write(
        self,
        vp: Viewport,
        delay_ms: u32,
        frames: impl Iterator<Item = Result<RgbImage, Error>>,
        mut keep: impl FnMut(RgbImage),
    ) -> Result<Vec<Pending>, Error> {
        match self {
            Self::Gif(target) => {
                let file = Pending::create(target)?;
                let mut gif = sim::GifStream::new(file, vp.width, vp.height, delay_ms)?;
                for img in frames {
                    let img = img?;
                    if let Err(e) = gif.add(&img) {
                        return Err(gif.writer().error(e).into());
                    }
                    keep(img);
                }
                Ok(vec![gif.finish()?])
            }
            Self::Pngs(targets) => {
                let mut files = Vec::new();
                for (img, target) in frames.zip(targets) {
                    let img = img?;
                    let mut file = Pending::create(target)?;
                    if let Err(e) = tessera_host::encode_png(&img, &mut file) {
                        return Err(file.error(HostError::Write(e)).into());
                    }
                    // Closed now: an orbit may have more frames than open files.
                    file.finish()?;
                    files.push(file);
                    keep(img);
                }
                Ok(files)
            }
        }
    }
}

/// The animation `--animate` plays: the scene file's description, its frames
/// and the delay between them.
struct Animated<'s> {
    /// The scene as the file places it (each frame is [`SceneDesc::at_frame`]).
    desc: &'s SceneDesc,
    /// How many frames are played, from frame 0 (at most
    /// [`limits::MAX_ORBIT_FRAMES`]).
    frames: u32,
    /// The scene's frame time, in whole hundredths of a second, in ms.
    delay_ms: u32,
}

impl<'s> Animated<'s> {
    /// The animation of `source` (a scene file with `[[keyframes]]`), played
    /// whole.
    fn of(source: &'s Source) -> Result<Self, Error> {
        let none = |why: &str| {
            source.error(DescError {
                item: "--animate".into(),
                message: format!(
                    "the scene has no animation ({why}): --animate plays a scene file's \
                     [[keyframes]] (or a glTF file's animation)"
                ),
            })
        };
        let desc = match source {
            Source::File(_, d) if !d.keyframes.is_empty() => &**d,
            Source::File(..) => return Err(none("no [[keyframes]]")),
            Source::Builtin(_) => return Err(none("a built-in scene")),
        };
        let fps = desc.render.fps;
        // The frames the core counts: frame 0 to the last whose time is at
        // most the end (the time of the last keyframe).
        let count = desc.frames().map_err(|e| source.error(e))?;
        if count > limits::MAX_ORBIT_FRAMES {
            return Err(Error::Host(HostError::Limit(format!(
                "--animate: the animation lasts {} s, {count} frames at {} fps: it plays \
                 at most {} frames",
                tessera_host::desc::num(desc.duration().map_err(|e| source.error(e))?),
                tessera_host::desc::num(fps),
                limits::MAX_ORBIT_FRAMES
            ))));
        }
        // The nearest hundredth of a second (a GIF's unit), at least one.
        let hundredths = (100.0 / fps).round().max(1.0);
        let most = f64::from(limits::MAX_GIF_DELAY_MS);
        if hundredths * 10.0 > most {
            return Err(Error::Host(HostError::Limit(format!(
                "--animate: at {} fps a frame lasts {} ms, more than a GIF frame's {} ms: \
                 give --delay-ms",
                tessera_host::desc::num(fps),
                tessera_host::desc::num(1000.0 / fps),
                limits::MAX_GIF_DELAY_MS
            ))));
        }
        Ok(Self {
            desc,
            frames: count,
            delay_ms: hundredths as u32 * 10,
        })
    }
}

/// One frame `k` on the panel: `view` seen through `renderer`, labelled.
fn frame(
    args: &SimulateArgs,
    k: u32,
    view: &SceneView<'_>,
    renderer: &Renderer,
    tile: usize,
) -> Result<RgbImage, Error> {
    let label = args
        .label
        .as_ref()
        .map(|l| l.replace("{frame}", &k.to_string()));
    Ok(sim::simulate_labelled(
        view,
        renderer,
        args.color,
        tile,
        Some(args.dither),
        label.as_deref(),
    )?)
}

pub fn run(args: &SimulateArgs) -> Result<(), Error> {
    let source = Source::open(args.common.scene.as_deref(), None)?;
    let (settings, mut vp, tile) = source.settings(&args.common)?;
    if args.common.size.is_none() {
        vp = Viewport::new(240, 240);
    }
    if args.orbit == Some(0) {
        return Err(Error::NoOrbitFrames);
    }
    let animated = if args.animate {
        Some(Animated::of(&source)?)
    } else {
        None
    };
    let frames = match &animated {
        Some(a) => Some(a.frames),
        None => args.orbit,
    };
    let count = frames.unwrap_or(1);
    limits::simulated(vp, count, args.window)?;
    let delay_ms = match (args.delay_ms, &animated) {
        (Some(ms), _) => ms,
        (None, Some(a)) => a.delay_ms,
        (None, None) => 80,
    };
    let (outputs, written) = Outputs::check(args, &source, frames)?;
    let start = Instant::now();
    let mut shown = Vec::new();
    let keep = |img| {
        if args.window {
            shown.push(img);
        }
    };
    let files = match &animated {
        None => still_or_orbit(args, &source, outputs, (settings, vp, tile), delay_ms, keep)?,
        Some(a) => animation(
            args,
            &source,
            a,
            outputs,
            (settings, vp, tile),
            delay_ms,
            keep,
        )?,
    };
    let secs = start.elapsed().as_secs_f64();
    output::commit(files)?;
    println!(
        "{}, {count} frame(s), panel colour {}, dither {}: {secs:.3} s",
        describe(&source, vp, &settings),
        args.color,
        args.dither,
    );
    println!("wrote {}", tessera_host::escape(&written));
    if args.window {
        show_window(&shown, delay_ms)?;
    }
    Ok(())
}

/// One still frame, or with `--orbit` the orbit's frames, written to
/// `outputs`.
fn still_or_orbit(
    args: &SimulateArgs,
    source: &Source,
    outputs: Outputs,
    (settings, vp, tile): (RenderSettings, Viewport, usize),
    delay_ms: u32,
    keep: impl FnMut(RgbImage),
) -> Result<Vec<Pending>, Error> {
    source.with_core(|view, camera| {
        // Every frame's camera is checked before any frame is drawn.
        let in_scene = |e| match e {
            HostError::Scene(e) => source.error(e),
            e => Error::Host(e),
        };
        let cameras = match args.orbit {
            None => vec![*camera],
            Some(n) => sim::pivot(view, camera)
                .and_then(|pivot| sim::orbit(camera, pivot, n))
                .map_err(in_scene)?,
        };
        let frames = cameras
            .iter()
            .map(|cam| Renderer::try_new(cam, vp, settings))
            .collect::<Result<Vec<Renderer>, _>>()?;
        let work = limits::Work::of(view, vp, &settings);
        let n = frames.len() as f64;
        let what = format!("drawing {} frame(s) on one thread", frames.len());
        warn_work(source, &what, view, camera, work, |w| w.core_seconds(1) * n)?;
        let bar = progress(
            frames.len() as u64,
            u64::from(vp.width) * u64::from(vp.height) * frames.len() as u64,
        );
        let frames = (0u32..).zip(&frames).map(|(k, renderer)| {
            let img = frame(args, k, view, renderer, tile)?;
            bar.inc(1);
            Ok(img)
        });
        let files = outputs.write(vp, delay_ms, frames, keep)?;
        bar.finish_and_clear();
        Ok(files)
    })
}

/// The frames of `animated`, each the scene at that frame (as `tessera render
/// --frame N` has it) on the panel, written to `outputs`. A frame the core
/// refuses (an instance placed out of range) is an error naming the frame.
fn animation(
    args: &SimulateArgs,
    source: &Source,
    animated: &Animated<'_>,
    outputs: Outputs,
    (settings, vp, tile): (RenderSettings, Viewport, usize),
    delay_ms: u32,
    keep: impl FnMut(RgbImage),
) -> Result<Vec<Pending>, Error> {
    let n = animated.frames;
    let at_frame = |k: u32| {
        animated
            .desc
            .at_frame(k)
            .and_then(|d| d.to_core())
            .map_err(|e| {
                source.error(DescError {
                    item: format!("frame {k}: {}", e.item),
                    message: e.message,
                })
            })
    };
    // The work of the first frame, for every frame (instances move, the
    // scene's primitives and lights stay).
    let first = at_frame(0)?;
    first.with_view(|view| {
        let work = limits::Work::of(view, vp, &settings);
        let what = format!("drawing {n} frame(s) on one thread");
        warn_work(source, &what, view, first.camera(), work, |w| {
            w.core_seconds(1) * f64::from(n)
        })
    })?;
    let bar = progress(
        u64::from(n),
        u64::from(vp.width) * u64::from(vp.height) * u64::from(n),
    );
    let mut first = Some(first);
    let frames = (0..n).map(|k| {
        let scene = match first.take() {
            Some(s) => s,
            None => at_frame(k)?,
        };
        let renderer = Renderer::try_new(scene.camera(), vp, settings)?;
        let img = scene.with_view(|view| frame(args, k, view, &renderer, tile))?;
        bar.inc(1);
        Ok(img)
    });
    let files = outputs.write(vp, delay_ms, frames, keep)?;
    bar.finish_and_clear();
    Ok(files)
}

/// Shows `frames` in an SDL window, in a loop, until it is closed.
#[cfg(feature = "sdl")]
fn show_window(frames: &[RgbImage], delay_ms: u32) -> Result<(), Error> {
    use embedded_graphics_core::pixelcolor::Rgb888;
    use embedded_graphics_core::prelude::*;
    use embedded_graphics_simulator::{OutputSettings, SimulatorDisplay, SimulatorEvent, Window};
    let Some(first) = frames.first() else {
        return Ok(());
    };
    let size = Size::new(first.width(), first.height());
    let mut display = SimulatorDisplay::<Rgb888>::with_default_color(size, Rgb888::BLACK);
    let mut window = Window::new("tessera", &OutputSettings::default());
    for f in frames.iter().cycle() {
        for (x, y, p) in f.enumerate_pixels() {
            let _ = Pixel(
                Point::new(x as i32, y as i32),
                Rgb888::new(p[0], p[1], p[2]),
            )
            .draw(&mut display);
        }
        window.update(&display);
        if window.events().any(|e| e == SimulatorEvent::Quit) {
            break;
        }
        std::thread::sleep(std::time::Duration::from_millis(u64::from(delay_ms)));
    }
    Ok(())
}

#[cfg(not(feature = "sdl"))]
fn show_window(_: &[RgbImage], _: u32) -> Result<(), Error> {
    Err(Error::NoWindow)
}
