//! `tessera`: render a scene to PNG, or compare the core with the f64 reference.
//!
//! ```text
//! tessera                                   # = tessera render: the default scene -> tessera.png
//! tessera render [SCENE] -o out.png [--size WxH] [--tile N] [--sampler S] [--depth D] [--seed S] [--threads N]
//! tessera compare [SCENE] [--heatmap diff.png] ...
//! tessera diff A B [--heatmap diff.png]     # two image files (PNG, PPM) pixel for pixel
//! tessera simulate [SCENE] [--color rgb565] [-o panel.png] [--orbit 36 -o orbit.gif]
//! tessera trade [--scenes a,b] [--size WxH] [--runs N] [--reference] [--truth-dir DIR]
//! tessera bake SCENE -o scene.rs [--crate PATH]
//! tessera scenes                            # list the built-in scenes
//! tessera completions bash|zsh|fish|elvish|powershell
//! tessera man                               # the manual page, every command on one page
//! ```
//! SCENE is a built-in scene name or a `.toml` scene file.
//!
//! Outputs are written through a temporary file next to them and renamed, all at
//! once when there are several; `tessera --help` (from `cli::GENERAL`) says what is
//! refused. The commands live in [`cli`], one module each.

mod cli;

use clap::Parser;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = cli::Cli::try_parse().unwrap_or_else(|e| cli::escaped(e).exit());
    if let Err(e) = tessera_host::output::clean_up_on_signals() {
        eprintln!("tessera: warning: {}", tessera_host::escape(&e.to_string()));
    }
    match cli.run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // Every part of a message is escaped where it is made; this is the
            // last guard (escaping twice changes nothing).
            eprintln!("tessera: error: {}", tessera_host::escape(&e.to_string()));
            ExitCode::FAILURE
        }
    }
}
