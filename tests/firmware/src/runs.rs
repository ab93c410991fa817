//! The run list: one run per line,
//! `<scene>[@k] <sampler> <depth> <tile 8|16|32> <width> <height> <seed>` (`@k`
//! scales the scene by `2^k`), with the
//! sampler as `corner`, `centre`, `prefiltered`, `stratified:K` or `random:N`. Blank lines and
//! lines starting with `#` are skipped.

use tessera::builtin::Builtin;
use tessera::{RenderSettings, Sampler};

/// One render.
pub struct Run<'a> {
    /// The built-in scene.
    pub scene: Builtin,
    /// The sampler as written in the list (echoed in the result line).
    pub sampler: &'a str,
    /// Sampler, depth and seed.
    pub settings: RenderSettings,
    /// Tile size: 8, 16 or 32.
    pub tile: usize,
    /// Image width, pixels.
    pub width: u16,
    /// Image height, pixels.
    pub height: u16,
    /// The scene is scaled by `2^scale` (`Builtin::with_scaled_scene`).
    pub scale: i32,
}

/// Parses one line (already known not to be blank or a comment).
pub fn parse(line: &str) -> Result<Run<'_>, &'static str> {
    let mut f = line.split_ascii_whitespace();
    let mut next = |what| f.next().ok_or(what);
    // `name` or `name@k`: the scene scaled by 2^k (lengths; intensities by 4^k).
    let token = next("missing scene")?;
    let (scene, scale) = match token.split_once('@') {
        Some((name, k)) => (name, k.parse().map_err(|_| "bad scale after @")?),
        None => (token, 0),
    };
    let scene = Builtin::from_name(scene).ok_or("unknown scene")?;
    let sampler_text = next("missing sampler")?;
    let sampler: Sampler = sampler_text.parse().map_err(|_| "bad sampler")?;
    let max_depth = next("missing depth")?.parse().map_err(|_| "bad depth")?;
    let tile = match next("missing tile size")? {
        "8" => 8,
        "16" => 16,
        "32" => 32,
        _ => return Err("tile size is not 8, 16 or 32"),
    };
    let width = next("missing width")?.parse().map_err(|_| "bad width")?;
    let height = next("missing height")?.parse().map_err(|_| "bad height")?;
    let seed = next("missing seed")?.parse().map_err(|_| "bad seed")?;
    if f.next().is_some() {
        return Err("too many fields");
    }
    Ok(Run {
        scene,
        sampler: sampler_text,
        settings: RenderSettings {
            sampler,
            max_depth,
            seed,
        },
        tile,
        width,
        height,
        scale,
    })
}
