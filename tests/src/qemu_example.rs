//! The firmware a user copies (`examples/qemu-m4f`), built as a user builds it
//! (`cargo build --release` in its folder, a scene file named by
//! `TESSERA_SCENE`) and run under qemu: its output, picture, sections and the
//! scene's tables. The example's tests and `chip-report` (the scenes from files
//! in docs/chip-cost.md) measure it through [`build_and_run`].

use crate::firmware::{self, Sizes, Symbol, TempDir};
use image::RgbImage;
use std::path::{Path, PathBuf};

/// The default scene file, built without `TESSERA_SCENE`.
pub const DEFAULT: &str = "scene.toml";

/// The picture's file, in qemu's working folder.
pub const PICTURE: &str = "tessera.ppm";

/// The ELF, in the example's own target folder.
pub const ELF: &str = "target/thumbv7em-none-eabihf/release/qemu-m4f";

/// The prefix of the baked scene's tables among the ELF's symbols.
const TABLES: &str = "qemu_m4f::scene::";

/// The example's folder.
#[must_use]
pub fn example() -> PathBuf {
    firmware::repo_root().join("examples").join("qemu-m4f")
}

/// One scene file built and run.
pub struct Run {
    /// The scene file as `TESSERA_SCENE` names it.
    pub scene: &'static str,
    /// The firmware's output.
    pub stdout: String,
    /// The picture it wrote.
    pub picture: RgbImage,
    /// The frames of the scene's animation it wrote (`frame-NNN.ppm`), by
    /// frame number; none for a scene without an animation.
    pub frames: Vec<(u32, RgbImage)>,
    /// Its sections.
    pub sizes: Sizes,
    /// Its symbols.
    pub symbols: Vec<Symbol>,
}

impl Run {
    /// The scene's tables: the statics of the firmware's module `scene`.
    #[must_use]
    pub fn tables(&self) -> Vec<&Symbol> {
        self.symbols
            .iter()
            .filter(|s| s.name.starts_with(TABLES))
            .collect()
    }

    /// The bytes of the scene's image textures (the tables `IMAGE0`, `IMAGE1`,
    /// ... the baker writes their texels to).
    #[must_use]
    pub fn image_bytes(&self) -> u64 {
        self.tables()
            .iter()
            .filter(|t| {
                t.name
                    .strip_prefix(TABLES)
                    .and_then(|n| n.strip_prefix("IMAGE"))
                    .is_some_and(|k| !k.is_empty() && k.bytes().all(|b| b.is_ascii_digit()))
            })
            .map(|t| t.size)
            .sum()
    }

    /// The number after `key=` in the firmware's output.
    ///
    /// # Panics
    /// When the output has no such number.
    #[must_use]
    pub fn number(&self, key: &str) -> u64 {
        number(&self.stdout, key)
    }
}

/// Builds the example for `scene` (relative to the example's folder; [`DEFAULT`]
/// builds without `TESSERA_SCENE`) as a user does (`cargo build --release` in its
/// folder, its `.cargo/config.toml` naming the target, with the core's features
/// the scene's kinds need, as its build.rs asks for them) and runs it under qemu
/// in a scratch folder. Builds share the example's target folder and so its ELF:
/// the last one built is left there.
///
/// # Errors
/// A scene file that does not load, a build or run that fails, a picture that is
/// not one.
pub fn build_and_run(scene: &'static str) -> Result<Run, String> {
    let dir = example();
    let mut cmd = firmware::cargo();
    cmd.current_dir(&dir).args(["build", "--release"]);
    let desc = tessera_host::file::load(&dir.join(scene)).map_err(|e| e.to_string())?;
    let features = tessera_host::bake::kind_features(&desc);
    if !features.is_empty() {
        cmd.args(["--features", &features.join(",")]);
    }
    if scene == DEFAULT {
        cmd.env_remove("TESSERA_SCENE");
    } else {
        cmd.env("TESSERA_SCENE", scene);
    }
    firmware::checked(
        &mut cmd,
        "cargo to build examples/qemu-m4f",
        &format!(
            "building examples/qemu-m4f for {scene} failed; is the {} target installed? ({})",
            firmware::TARGET,
            firmware::INSTALL_HINT
        ),
    )?;
    let elf = dir.join(ELF);
    let scratch = TempDir::new()?;
    let stdout = firmware::run_in(scratch.path(), &elf)?;
    let path = scratch.path().join(PICTURE);
    let bytes = std::fs::read(&path).map_err(|e| format!("{scene}: no {PICTURE}: {e}"))?;
    let picture = ppm(&bytes).map_err(|e| format!("{scene}: {PICTURE}: {e}"))?;
    let frames = frames(scratch.path()).map_err(|e| format!("{scene}: {e}"))?;
    Ok(Run {
        scene,
        stdout,
        picture,
        frames,
        sizes: firmware::sections(&elf)?,
        symbols: firmware::symbols(&elf)?,
    })
}

/// The frames of an animation the firmware wrote in `dir`: each
/// `frame-NNN.ppm`, by its number, in order.
fn frames(dir: &Path) -> Result<Vec<(u32, RgbImage)>, String> {
    let mut out = Vec::new();
    let entries = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    for entry in entries {
        let name = entry.map_err(|e| e.to_string())?.file_name();
        let name = name.to_string_lossy();
        let Some(n) = name
            .strip_prefix("frame-")
            .and_then(|n| n.strip_suffix(".ppm"))
        else {
            continue;
        };
        let n: u32 = n
            .parse()
            .map_err(|_| format!("{name}: not a frame's number"))?;
        let bytes = std::fs::read(dir.join(&*name)).map_err(|e| format!("{name}: {e}"))?;
        out.push((n, ppm(&bytes).map_err(|e| format!("{name}: {e}"))?));
    }
    out.sort_by_key(|f| f.0);
    Ok(out)
}

/// The host's picture of the scene file `path` (its size, settings and tile
/// size), as `tessera render` makes it.
///
/// # Panics
/// When the scene file does not load or render: the example built it.
#[must_use]
pub fn host(path: &Path) -> RgbImage {
    let desc = tessera_host::file::load(path).unwrap_or_else(|e| panic!("{e}"));
    host_of(&desc)
}

/// The host's picture of the scene `desc`, as [`host`].
///
/// # Panics
/// When the scene does not render.
#[must_use]
pub fn host_of(desc: &tessera_host::desc::SceneDesc) -> RgbImage {
    let scene = desc.to_core().unwrap_or_else(|e| panic!("{e}"));
    let settings = desc.settings().unwrap_or_else(|e| panic!("{e}"));
    scene
        .with_view(|view| {
            tessera_host::render(
                view,
                scene.camera(),
                desc.viewport(),
                settings,
                desc.render.tile,
            )
        })
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The pixels of a binary PPM as the firmware writes it: the header `P6`, the
/// size, 255, each followed by one line break, then the RGB bytes.
///
/// # Errors
/// A header that is not that, or pixels that do not fill the size.
pub fn ppm(bytes: &[u8]) -> Result<RgbImage, String> {
    let mut lines = bytes.splitn(4, |&b| b == b'\n');
    let mut next = || std::str::from_utf8(lines.next().unwrap_or_default()).unwrap_or("");
    let (magic, size, max) = (next(), next(), next());
    let (w, h) = size.split_once(' ').unwrap_or_default();
    let (w, h) = (w.parse().unwrap_or(0), h.parse().unwrap_or(0));
    if magic != "P6" || max != "255" || w == 0 || h == 0 {
        return Err(format!(
            "not the header of a picture: {magic:?} {size:?} {max:?}"
        ));
    }
    let pixels = lines.next().unwrap_or_default().to_vec();
    let n = pixels.len();
    RgbImage::from_raw(w, h, pixels)
        .filter(|_| n == (w * h * 3) as usize)
        .ok_or_else(|| format!("{n} bytes of pixels for {w}x{h}"))
}

/// The value of `key=` in the firmware's output.
///
/// # Panics
/// When the output has no `key=`.
#[must_use]
pub fn field<'a>(stdout: &'a str, key: &str) -> &'a str {
    stdout
        .split_whitespace()
        .find_map(|w| w.strip_prefix(key)?.strip_prefix('='))
        .unwrap_or_else(|| panic!("no {key}= in {stdout:?}"))
}

/// The number after `key=` in the firmware's output.
///
/// # Panics
/// When the output has no such number.
#[must_use]
pub fn number(stdout: &str, key: &str) -> u64 {
    field(stdout, key)
        .parse()
        .unwrap_or_else(|_| panic!("{key}= is not a number in {stdout:?}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ppm_is_read_and_a_short_or_foreign_one_refused() {
        let mut good = b"P6\n2 1\n255\n".to_vec();
        good.extend([1, 2, 3, 4, 5, 6]);
        let img = ppm(&good).unwrap();
        assert_eq!((img.width(), img.height()), (2, 1));
        assert_eq!(img.get_pixel(1, 0).0, [4, 5, 6]);
        assert!(
            ppm(&good[..good.len() - 1])
                .unwrap_err()
                .contains("5 bytes")
        );
        assert!(ppm(b"P3\n2 1\n255\n123456").is_err());
        assert!(ppm(b"P6\n0 1\n255\n").is_err());
    }

    #[test]
    fn fields_are_read_from_the_output() {
        let out = "tessera: scene.toml, x\nsize=4x2\ninstructions=1234 (154 a pixel)\n";
        assert_eq!(field(out, "size"), "4x2");
        assert_eq!(number(out, "instructions"), 1234);
    }
}
