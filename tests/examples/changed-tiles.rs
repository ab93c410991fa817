//! What rendering only the tiles a moved instance can reach saves
//! (`Renderer::tile_may_change`): renders consecutive frames of an animated
//! scene file (frames 1 to 6, each after the one before) in tiles of 16, in
//! one of four modes, and prints how many tiles it rendered.
//!
//! - `all`: every tile of every frame;
//! - `changed`: the tiles `tile_may_change` does not clear;
//! - `check`: only the checks, no render;
//! - `none`: neither (the scene's set-up alone).
//!
//! Its instructions under callgrind, one mode against another, are the
//! saving: build it with `cargo build -p tessera-tests --release --example
//! changed-tiles`, run `valgrind --tool=callgrind
//! target/release/examples/changed-tiles scenes/examples/animated-pico2.toml
//! all`, then `changed`, `check` and `none`, and compare `changed` less
//! `none` with `all` less `none`.

use tessera_core::instance::Instances;
use tessera_core::{Renderer, Tile, TileCoord, moved_instances};

fn main() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let (Some(path), Some(mode)) = (args.next(), args.next()) else {
        return Err("usage: changed-tiles SCENE.toml all|changed|check|none".into());
    };
    if !["all", "changed", "check", "none"].contains(&mode.as_str()) {
        return Err(format!(
            "unknown mode {mode:?}: all, changed, check or none"
        ));
    }
    let desc = tessera_host::file::load(std::path::Path::new(&path)).map_err(|e| e.to_string())?;
    let placements = (0..7)
        .map(|n| {
            let at = desc.at_frame(n).map_err(|e| e.to_string())?;
            Ok(at
                .to_core()
                .map_err(|e| e.to_string())?
                .instances()
                .to_vec())
        })
        .collect::<Result<Vec<_>, String>>()?;
    let base = desc.to_core().map_err(|e| e.to_string())?;
    let settings = desc.settings().map_err(|e| e.to_string())?;
    let (rendered, all) = base.with_view(|v0| -> Result<(u32, u32), String> {
        let r = Renderer::try_new(base.camera(), desc.viewport(), settings)
            .map_err(|e| e.to_string())?;
        let (across, down) = r.tile_grid(16);
        let mut tile = Tile::<16>::new();
        let (mut rendered, mut all) = (0, 0);
        for pair in placements.windows(2) {
            let mut a = Box::new(Instances::<16>::new(v0));
            let mut b = Box::new(Instances::<16>::new(v0));
            a.place_all(&pair[0]).map_err(|e| e.to_string())?;
            b.place_all(&pair[1]).map_err(|e| e.to_string())?;
            let va = v0.with_instances(&a).map_err(|e| e.to_string())?;
            let vb = v0.with_instances(&b).map_err(|e| e.to_string())?;
            let moved =
                moved_instances(&va, &vb).ok_or("the frames differ in more than placements")?;
            for ty in 0..down {
                for tx in 0..across {
                    let c = TileCoord::new(tx, ty);
                    all += 1;
                    if mode == "none" {
                        continue;
                    }
                    let skip = mode != "all"
                        && !r
                            .tile_may_change::<16>(&va, &vb, moved, c)
                            .map_err(|e| e.to_string())?;
                    if mode == "check" || skip {
                        continue;
                    }
                    rendered += 1;
                    r.render_tile(&vb, c, &mut tile, &mut ())
                        .map_err(|e| e.to_string())?;
                    std::hint::black_box(&tile);
                }
            }
        }
        Ok((rendered, all))
    })?;
    println!("{mode}: rendered {rendered} of {all} tiles");
    Ok(())
}
