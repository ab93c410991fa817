//! The measured rows in grid order, each with the chip's count for its setting and
//! whether it is on its scene's Pareto front; the look-ups the chart, the tables
//! and the conclusions make.

use super::{EXACT, FAST, REFERENCE};
use std::collections::HashMap;
use tessera::builtin::Builtin;
use tessera_host::trade::{self, Row, Setting};

/// A measured row, the chip's count for its setting and whether it is on the front.
pub(super) struct Entry {
    pub(super) row: Row,
    pub(super) chip: Option<f64>,
    pub(super) front: bool,
}

impl Entry {
    fn is(&self, sampler: &str, depth: u8, tile: usize) -> bool {
        self.row.setting.sampler.to_string() == sampler
            && self.row.setting.depth == depth
            && self.row.setting.tile == tile
    }
}

/// The chip's counts are keyed by (backend, scene, sampler, depth, tile).
pub(super) type ChipKey = (String, String, String, u8, usize);

/// The chip key of a backend, scene and setting.
pub(super) fn chip_key(backend: &str, scene: &str, s: &Setting) -> ChipKey {
    (
        backend.into(),
        scene.into(),
        s.sampler.to_string(),
        s.depth,
        s.tile,
    )
}

/// The rows in grid order, the three backends of a setting together, with their
/// chip counts and the Pareto front marked; an error if a row is not in the grid.
pub(super) fn in_grid_order(
    rows: &[Row],
    chip: &HashMap<ChipKey, f64>,
) -> Result<Vec<Entry>, String> {
    let mut entries: Vec<Entry> = Vec::new();
    for b in Builtin::ALL {
        for s in trade::grid(b.settings()) {
            for backend in [EXACT, FAST, REFERENCE] {
                if let Some(r) = rows
                    .iter()
                    .find(|r| r.scene == b.name() && r.backend == backend && r.setting == s)
                {
                    entries.push(Entry {
                        row: r.clone(),
                        chip: chip.get(&chip_key(backend, b.name(), &s)).copied(),
                        front: false,
                    });
                }
            }
        }
    }
    if entries.len() != rows.len() {
        return Err(format!(
            "{} rows measured, {} matched the grid",
            rows.len(),
            entries.len()
        ));
    }
    mark_front(&mut entries);
    Ok(entries)
}

/// Marks the Pareto front of each scene over the exact and fast-math rows: a row is
/// on it when no other row is at most as costly and at most as wrong, and better in
/// one of the two.
fn mark_front(entries: &mut [Entry]) {
    let contenders: Vec<(usize, String, f64, f64)> = entries
        .iter()
        .enumerate()
        .filter(|(_, e)| e.row.backend != REFERENCE)
        .map(|(i, e)| (i, e.row.scene.clone(), e.row.ns_median, e.row.flip))
        .collect();
    for (i, scene, ns, flip) in &contenders {
        let dominated = contenders.iter().any(|(j, s, n, f)| {
            j != i && s == scene && n <= ns && f <= flip && (n < ns || f < flip)
        });
        entries[*i].front = !dominated;
    }
}

/// The entries of `scene`.
pub(super) fn of_scene<'a>(entries: &'a [Entry], scene: &str) -> Vec<&'a Entry> {
    entries.iter().filter(|e| e.row.scene == scene).collect()
}

/// The entry of a scene, backend and setting.
pub(super) fn find<'a>(
    entries: &'a [Entry],
    scene: &str,
    backend: &str,
    sampler: &str,
    depth: u8,
    tile: usize,
) -> Result<&'a Entry, String> {
    entries
        .iter()
        .find(|e| e.row.scene == scene && e.row.backend == backend && e.is(sampler, depth, tile))
        .ok_or_else(|| format!("no {backend} row for {scene} {sampler} depth {depth} tile {tile}"))
}

/// A setting in a few characters, relative to the scene's own settings.
pub(super) fn short(scene: &str, s: &Setting) -> String {
    use std::fmt::Write as _;
    let base = Builtin::from_name(scene).map(Builtin::settings);
    let mut t = s.sampler.to_string();
    if base.is_some_and(|b| b.max_depth != s.depth) {
        let _ = write!(t, " d{}", s.depth);
    }
    if s.tile != 16 {
        let _ = write!(t, " t{}", s.tile);
    }
    t
}

/// A scene's own settings in a few words.
pub(super) fn short_base(b: Builtin) -> String {
    let s = b.settings();
    format!("{}, depth {}", s.sampler, s.max_depth)
}
