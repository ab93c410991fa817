//! The run list: one run per line,
//! `<scene>[@k] <sampler> <depth> <tile 8|16|32> <width> <height> <seed> [<encoding>]`
//! (`@k` scales the scene by `2^k`), with the sampler in its text form (`corner`,
//! `centre`, `prefiltered`, `stratified:K`, `random:N`, `adaptive:K[,T]`, `sparse[:T[,S]]`: not
//! `offset`, see [`sampler`]) and the encoding
//! `linear` or `srgb` (absent: the default, srgb). Blank lines and lines starting
//! with `#` are skipped.
//!
//! One home for both sides of the line: the host-side harness
//! (`tessera_tests::firmware`, which includes this file with `#[path]`) writes a
//! [`Run`] with its `Display`, the firmware reads it back with [`parse`].

use core::fmt;
use tessera_core::builtin::Builtin;
use tessera_core::testing::BuiltinHooks as _;
use tessera_core::testing::Extreme;
use tessera_core::{Camera, Encoding, RenderSettings, Sampler, SceneView};

/// What a run renders: a built-in scene, built in RAM or from its `static`
/// data, or a scene of the extremes battery.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SceneRef {
    /// A built-in scene (which a run may scale).
    Builtin(Builtin),
    /// A built-in scene from its baked `static` tables
    /// (`Builtin::with_baked_scene`), named `baked-<name>`.
    Baked(Builtin),
    /// A scene of the extremes battery (`tessera_core::testing::Extreme`).
    Extreme(Extreme),
}

impl From<Builtin> for SceneRef {
    fn from(b: Builtin) -> Self {
        Self::Builtin(b)
    }
}

impl From<Extreme> for SceneRef {
    fn from(e: Extreme) -> Self {
        Self::Extreme(e)
    }
}

impl SceneRef {
    /// Its name in the run list.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Builtin(b) => b.name(),
            Self::Baked(b) => match b {
                Builtin::ChapterDirect => "baked-chapter-direct",
                Builtin::ChapterReflect => "baked-chapter-reflect",
                Builtin::Interference => "baked-interference",
                Builtin::Showcase => "baked-showcase",
                Builtin::Teapot => "baked-teapot",
                // A built-in scene the core adds later: not in this image's list.
                _ => "baked-unlisted",
            },
            Self::Extreme(e) => e.name(),
        }
    }

    /// The scene of a name.
    #[must_use]
    pub fn from_name(name: &str) -> Option<Self> {
        match name.strip_prefix("baked-") {
            Some(b) => Builtin::from_name(b).map(Self::Baked),
            None => Builtin::from_name(name)
                .map(Self::Builtin)
                .or_else(|| Extreme::from_name(name).map(Self::Extreme)),
        }
    }

    /// `f` of the scene's view and camera, a built-in scene scaled by `2^k`
    /// (`Builtin::with_scaled_scene`; a baked or an extreme scene is not
    /// scaled: `k` must be 0).
    ///
    /// # Errors
    /// The scene's own, and `Error::OutOfRange` for an extreme scene asked scaled.
    pub fn with_scaled_scene<R>(
        self,
        k: i32,
        f: impl FnOnce(&SceneView<'_>, &Camera) -> R,
    ) -> Result<R, tessera_core::Error> {
        match self {
            Self::Builtin(b) => b.with_scaled_scene(k, f),
            Self::Baked(b) if k == 0 => b.with_baked_scene(f),
            Self::Extreme(e) if k == 0 => e.with_scene(f),
            Self::Baked(_) | Self::Extreme(_) => Err(tessera_core::Error::OutOfRange {
                field: tessera_core::error::Field::CameraPosition,
                range: "a baked or extreme scene at its own scale (no @k)",
            }),
        }
    }
}

/// One render on the chip.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Run {
    /// The scene.
    pub scene: SceneRef,
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

/// A sampler in its text form, with integers only: `Sampler::from_str` also reads
/// `offset:X,Y`, whose decimal `f32`s would link `core`'s float parsing (18 KB
/// of flash, measured with llvm-size) into the image for runs that never use it.
/// Refused here: `offset`.
fn sampler(token: &str) -> Result<Sampler, &'static str> {
    fn count<T: core::str::FromStr>(n: &str) -> Result<T, &'static str> {
        n.parse().map_err(|_| "bad sample count")
    }
    let s = match token.split_once(':') {
        None => match token {
            "corner" => Sampler::Corner,
            "centre" | "center" => Sampler::Centre,
            "prefiltered" => Sampler::Prefiltered,
            "sparse" => Sampler::sparse(),
            _ => return Err("bad sampler"),
        },
        Some(("sparse", rest)) => {
            let (t, spacing) = match rest.split_once(',') {
                Some((t, s)) => (t, s.parse().map_err(|_| "bad sparse spacing")?),
                None => (rest, 2),
            };
            Sampler::Sparse {
                threshold: t.parse().map_err(|_| "bad sparse threshold")?,
                spacing,
            }
        }
        Some(("stratified", k)) => Sampler::Stratified(count(k)?),
        Some(("random", n)) => Sampler::Random(count(n)?),
        Some(("adaptive", rest)) => match rest.split_once(',') {
            Some((k, t)) => Sampler::Adaptive {
                k: count(k)?,
                threshold: t.parse().map_err(|_| "bad adaptive threshold")?,
            },
            None => Sampler::adaptive(count(rest)?),
        },
        Some(("offset", _)) => return Err("offset samplers are not read on the chip"),
        Some(_) => return Err("bad sampler"),
    };
    s.validate().map_err(|_| "bad sampler")?;
    Ok(s)
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
    let scene = SceneRef::from_name(scene).ok_or("unknown scene")?;
    let sampler = sampler(next("missing sampler")?)?;
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
