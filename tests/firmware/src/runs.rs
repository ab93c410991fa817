//! The run list: one run per line,
//! `<scene>[@k] <sampler> <depth> <tile 8|16|32> <width> <height> <seed> [<encoding>]`
//! (`@k` scales the scene by `2^k`), with the sampler in its text form (`corner`,
//! `centre`, `prefiltered`, `stratified:K`, `random:N`, ...) and the encoding
//! `linear` or `srgb` (absent: the default, srgb). Blank lines and lines starting
//! with `#` are skipped.
//!
//! One home for both sides of the line: the host-side harness
//! (`tessera_tests::firmware`, which includes this file with `#[path]`) writes a
//! [`Run`] with its `Display`, the firmware reads it back with [`parse`].

use core::fmt;
use tessera::builtin::Builtin;
use tessera::{Encoding, RenderSettings, Sampler};

/// One render on the chip.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Run {
    /// The built-in scene.
    pub scene: Builtin,
    /// The sampler.
    pub sampler: Sampler,
    /// Reflection/transmission depth.
    pub depth: u8,
    /// Tile size: 8, 16 or 32.
    pub tile: usize,
    /// Width, pixels.
    pub width: u16,
    /// Height, pixels.
    pub height: u16,
    /// Seed of the random samplers.
    pub seed: u32,
    /// The scene scaled by `2^scale` (`Builtin::with_scaled_scene`); 0 = as built.
    pub scale: i32,
    /// How the pixels become 8 bits.
    pub encoding: Encoding,
}

impl Run {
    /// The settings the firmware renders with.
    #[must_use]
    pub fn settings(&self) -> RenderSettings {
        RenderSettings {
            sampler: self.sampler,
            max_depth: self.depth,
            seed: self.seed,
            encoding: self.encoding,
        }
    }
}

/// The run's line in the run list:
/// `scene[@k] sampler depth tile width height seed encoding`.
impl fmt::Display for Run {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.scene.name())?;
        if self.scale != 0 {
            write!(f, "@{}", self.scale)?;
        }
        write!(
            f,
            " {} {} {} {} {} {} {}",
            self.sampler, self.depth, self.tile, self.width, self.height, self.seed, self.encoding
        )
    }
}

/// Parses one line (already known not to be blank or a comment).
pub fn parse(line: &str) -> Result<Run, &'static str> {
    let mut f = line.split_ascii_whitespace();
    let mut next = |what| f.next().ok_or(what);
    // `name` or `name@k`: the scene scaled by 2^k (lengths; intensities by 4^k).
    let token = next("missing scene")?;
    let (scene, scale) = match token.split_once('@') {
        Some((name, k)) => (name, k.parse().map_err(|_| "bad scale after @")?),
        None => (token, 0),
    };
    let scene = Builtin::from_name(scene).ok_or("unknown scene")?;
    let sampler = next("missing sampler")?
        .parse()
        .map_err(|_| "bad sampler")?;
    let depth = next("missing depth")?.parse().map_err(|_| "bad depth")?;
    let tile = match next("missing tile size")? {
        "8" => 8,
        "16" => 16,
        "32" => 32,
        _ => return Err("tile size is not 8, 16 or 32"),
    };
    let width = next("missing width")?.parse().map_err(|_| "bad width")?;
    let height = next("missing height")?.parse().map_err(|_| "bad height")?;
    let seed = next("missing seed")?.parse().map_err(|_| "bad seed")?;
    let encoding = match f.next() {
        Some(e) => e.parse().map_err(|_| "bad encoding: linear or srgb")?,
        None => Encoding::default(),
    };
    if f.next().is_some() {
        return Err("too many fields");
    }
    Ok(Run {
        scene,
        sampler,
        depth,
        tile,
        width,
        height,
        seed,
        scale,
        encoding,
    })
}
