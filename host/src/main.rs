//! `tessera`: render a built-in scene to a PNG.
//!
//! ```text
//! tessera [render] [SCENE] [-o OUT.png] [--size WxH] [--tile 8|16|32]
//! ```
//! With no SCENE it renders the default scene (the chapter's second picture) at
//! 320x240 to `tessera.png`.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;
use tessera::Viewport;
use tessera::builtin::Builtin;

struct Args {
    scene: Builtin,
    out: PathBuf,
    viewport: Viewport,
    tile: usize,
}

fn usage() -> String {
    let names: Vec<&str> = Builtin::ALL.iter().map(|b| b.name()).collect();
    format!(
        "usage: tessera [render] [SCENE] [-o OUT.png] [--size WxH] [--tile 8|16|32]\n\
         scenes: {} (default {})",
        names.join(", "),
        Builtin::DEFAULT.name()
    )
}

fn parse(mut it: impl Iterator<Item = String>) -> Result<Args, String> {
    let mut args = Args {
        scene: Builtin::DEFAULT,
        out: PathBuf::from("tessera.png"),
        viewport: Viewport::new(320, 240),
        tile: 16,
    };
    let mut first = true;
    while let Some(a) = it.next() {
        let mut value = |flag: &str| it.next().ok_or(format!("{flag} needs a value"));
        match a.as_str() {
            "render" if first => {}
            "-o" | "--output" => args.out = PathBuf::from(value(&a)?),
            "--size" => {
                let v = value(&a)?;
                let (w, h) = v
                    .split_once('x')
                    .and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?)))
                    .ok_or(format!("--size: expected WxH like 320x240, got {v:?}"))?;
                args.viewport = Viewport::new(w, h);
            }
            "--tile" => {
                let v = value(&a)?;
                args.tile = v
                    .parse()
                    .map_err(|_| format!("--tile: expected 8, 16 or 32, got {v:?}"))?;
            }
            "-h" | "--help" => return Err(usage()),
            s if !s.starts_with('-') => {
                args.scene =
                    Builtin::from_name(s).ok_or(format!("unknown scene {s:?}\n{}", usage()))?;
            }
            s => return Err(format!("unknown option {s:?}\n{}", usage())),
        }
        first = false;
    }
    Ok(args)
}

fn run(args: &Args) -> Result<(), String> {
    let start = Instant::now();
    let img = args
        .scene
        .with_scene(|view, camera| {
            tessera_host::render(
                view,
                camera,
                args.viewport,
                args.scene.settings(),
                args.tile,
            )
        })
        .map_err(|e| e.to_string())?
        .map_err(|e| e.to_string())?;
    tessera_host::write_png(&img, &args.out).map_err(|e| e.to_string())?;
    println!(
        "wrote {} ({} {}x{}, {:.2} s)",
        args.out.display(),
        args.scene.name(),
        args.viewport.width,
        args.viewport.height,
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

fn main() -> ExitCode {
    match parse(std::env::args().skip(1)).and_then(|a| run(&a)) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("tessera: {e}");
            ExitCode::FAILURE
        }
    }
}
