//! `tessera new`: a firmware crate for the Cortex-M4F under qemu, from the
//! template ([`tessera_host::template`]).

use super::Error;
use clap::Args;
use std::path::{Path, PathBuf};
use tessera_host::escape_path;
use tessera_host::template::{self, Source};

#[derive(Args)]
pub struct NewArgs {
    /// The new crate's folder (must not exist); its last part is the crate's name
    folder: PathBuf,
    /// Depend on the tessera repository checked out at this folder (by path)
    /// instead of the crate registry
    #[arg(long, value_name = "CHECKOUT")]
    path: Option<PathBuf>,
}

/// A failure of `new`, naming `path`.
fn fail(path: &Path, message: impl Into<String>) -> Error {
    Error::New {
        path: path.to_path_buf(),
        message: message.into(),
    }
}

/// The checkout at `path`, absolute, once its two crates are found there.
fn checkout(path: &Path) -> Result<PathBuf, Error> {
    let abs = path
        .canonicalize()
        .map_err(|e| fail(path, format!("cannot read the checkout: {e}")))?;
    for (dir, name) in [("core", "tessera-core"), ("host", "tessera-host")] {
        let manifest =
            std::fs::read_to_string(abs.join(dir).join("Cargo.toml")).unwrap_or_default();
        if !manifest.contains(&format!("name = \"{name}\"")) {
            return Err(fail(
                path,
                format!("not a checkout of tessera: no crate {name} in its folder {dir}/"),
            ));
        }
    }
    Ok(abs)
}

pub fn run(args: &NewArgs) -> Result<(), Error> {
    let folder = &args.folder;
    let name = folder
        .file_name()
        .and_then(|n| n.to_str())
        .ok_or_else(|| fail(folder, "the folder's last part must be the crate's name"))?;
    template::check_name(name).map_err(|e| fail(folder, e.to_string()))?;
    // Never over anything: a folder, a file or a link already there is kept.
    if folder.symlink_metadata().is_ok() {
        return Err(fail(folder, "already exists: nothing was written"));
    }
    let parent = match folder.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let parent = parent
        .canonicalize()
        .map_err(|e| fail(folder, format!("cannot read the folder it goes in: {e}")))?;
    let source = match &args.path {
        None => Source::Registry(template::VERSION.to_string()),
        Some(path) => Source::Checkout(template::relative(&parent.join(name), &checkout(path)?)),
    };
    let files = template::files(name, &source).map_err(|e| fail(folder, e.to_string()))?;

    // Written in a hidden folder beside it, then renamed into place: an
    // interrupted or failed run leaves no half-written crate.
    let staging = parent.join(format!(".{name}.tessera-new-{}", std::process::id()));
    let written = (|| -> std::io::Result<()> {
        for (path, bytes) in &files {
            let path = staging.join(path);
            if let Some(dir) = path.parent() {
                std::fs::create_dir_all(dir)?;
            }
            std::fs::write(&path, bytes)?;
        }
        // Fails if the folder appeared meanwhile and is not empty.
        std::fs::rename(&staging, parent.join(name))
    })();
    if let Err(e) = written {
        let _ = std::fs::remove_dir_all(&staging);
        return Err(fail(folder, format!("cannot write the crate: {e}")));
    }
    let from = match &source {
        Source::Registry(v) => format!("tessera {v} from the crate registry"),
        Source::Checkout(p) => format!("tessera at {}", escape_path(p)),
    };
    println!(
        "created {} ({} files, {from}): cd there and `cargo run --release` (needs qemu-system-arm)",
        escape_path(folder),
        files.len()
    );
    Ok(())
}
