//! `tessera bake`: a scene's triangles and their BVH as Rust `static` data for a
//! firmware (see the host library's `bake` module).

use super::{Error, Source};
use clap::Args;
use std::io::Write as _;
use std::path::PathBuf;
use tessera_host::output::{self, Pending};

#[derive(Args)]
pub struct BakeArgs {
    /// A built-in scene name (see `tessera scenes`) or a .toml scene file with
    /// triangles or meshes
    scene: String,
    /// Output Rust file (a symbolic link is followed)
    #[arg(short, long)]
    output: PathBuf,
    /// The name the firmware gives the core crate (`crate` inside the core itself):
    /// a Rust path, identifiers joined by `::`
    #[arg(long = "crate", default_value = "tessera", value_parser = parse_path)]
    krate: String,
}

/// `--crate`: a Rust path (`tessera`, `crate`, `my_deps::tessera`).
fn parse_path(s: &str) -> Result<String, String> {
    let ident = |w: &str| {
        let mut c = w.chars();
        c.next()
            .is_some_and(|f| f == '_' || f.is_ascii_alphabetic())
            && c.all(|x| x == '_' || x.is_ascii_alphanumeric())
    };
    if s.split("::").all(ident) {
        Ok(s.to_string())
    } else {
        Err(format!(
            "expected a Rust path (identifiers joined by ::), got {s:?}"
        ))
    }
}

pub fn run(args: &BakeArgs) -> Result<(), Error> {
    let source = Source::open(Some(&args.scene))?;
    let target = source.target(&args.output)?;
    let text = tessera_host::bake::scene_source(&source.desc(), source.name(), &args.krate)
        .map_err(|e| source.error(e))?;
    let mut file = Pending::create(target)?;
    if let Err(e) = file.write_all(text.as_bytes()) {
        return Err(file.error(tessera_host::HostError::Write(e)).into());
    }
    output::commit(vec![file])?;
    println!("wrote {}", args.output.display());
    Ok(())
}
