//! `tessera bake`: a whole scene as Rust `static` data for a firmware (see the
//! host library's `bake` module).

use super::{Error, Source};
use clap::{Args, ValueHint};
use std::io::Write as _;
use std::path::PathBuf;
use tessera_host::output::{self, Pending};

#[derive(Args)]
pub struct BakeArgs {
    /// A built-in scene name (see `tessera scenes`) or a .toml scene file
    scene: String,
    /// Output Rust file (a symbolic link is followed)
    #[arg(short, long, value_hint = ValueHint::FilePath)]
    output: PathBuf,
    /// The name the firmware gives the core crate (`crate` inside the core itself):
    /// a Rust path, identifiers joined by `::` (no keyword)
    #[arg(long = "crate", default_value = "tessera_core", value_parser = parse_path)]
    krate: String,
}

/// `--crate`: a Rust path of a `use` (`tessera_core`, `crate`, `my_deps::tessera_core`;
/// see [`tessera_host::bake::check_crate_path`]).
fn parse_path(s: &str) -> Result<String, String> {
    tessera_host::bake::check_crate_path(s).map(|()| s.to_string())
}

pub fn run(args: &BakeArgs) -> Result<(), Error> {
    let source = Source::open(Some(&args.scene), None)?;
    let target = source.target(&args.output)?;
    let text = tessera_host::bake::scene_source(&source.desc(), source.name(), &args.krate)
        .map_err(|e| source.error(e))?;
    let mut file = Pending::create(target)?;
    if let Err(e) = file.write_all(text.as_bytes()) {
        return Err(file.error(tessera_host::HostError::Write(e)).into());
    }
    output::commit(vec![file])?;
    println!("wrote {}", tessera_host::escape_path(&args.output));
    Ok(())
}
