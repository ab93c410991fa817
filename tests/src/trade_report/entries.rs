//! The measured rows in grid order, each with the chip's figures for its setting
//! and whether it is on its scene's Pareto fronts (host time, chip cycles); the
//! look-ups the charts, the tables and the conclusions make.

use super::{BACKENDS, REFERENCE};
use std::collections::HashMap;
use tessera_core::builtin::Builtin;
use tessera_host::trade::{self, Row, Setting};

/// What the chip costs per pixel for one backend, scene and setting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Chip {
    /// Instructions per pixel inside `render_tile` (SysTick).
    pub(super) instructions: f64,
    /// Estimated Cortex-M4 cycles per pixel ([`crate::cycles::estimate`] of the
    /// same run's profile).
    pub(super) cycles: f64,
}

/// A measured row, the chip's figures for its setting and whether it is on the
/// fronts.
pub(super) struct Entry {
    pub(super) row: Row,
    pub(super) chip: Option<Chip>,
    /// On the front of host time against error.
    pub(super) front: bool,
    /// On the front of chip cycles against error.
    pub(super) chip_front: bool,
}

impl Entry {
    fn is(&self, sampler: &str, depth: u8, tile: usize) -> bool {
        self.row.setting.sampler.to_string() == sampler
            && self.row.setting.depth == depth
            && self.row.setting.tile == tile
    }
    /// The chip's estimated cycles per pixel, if the setting ran on the chip.
    pub(super) fn cycles(&self) -> Option<f64> {
        self.chip.map(|c| c.cycles)
    }
}

/// The chip's figures are keyed by (backend, scene, sampler, depth, tile).
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

/// The names of [`BACKENDS`], in order.
pub(super) fn backend_names() -> Vec<&'static str> {
    BACKENDS.iter().map(|b| b.name).collect()
}

/// The rows in grid order, the backends of a setting together (in the order of
/// `names`, then the f64 reference), with their chip figures and the Pareto
/// fronts marked; an error if a row is not in the grid or of another backend.
pub(super) fn in_grid_order(
    rows: &[Row],
    chip: &HashMap<ChipKey, Chip>,
    names: &[&str],
) -> Result<Vec<Entry>, String> {
    let mut entries: Vec<Entry> = Vec::new();
    let backends: Vec<&str> = names.iter().copied().chain([REFERENCE]).collect();
    for b in super::SCENES {
        for s in trade::grid(b.settings()) {
            for backend in &backends {
                if let Some(r) = rows
                    .iter()
                    .find(|r| r.scene == b.name() && r.backend == *backend && r.setting == s)
                {
                    entries.push(Entry {
                        row: r.clone(),
                        chip: chip.get(&chip_key(backend, b.name(), &s)).copied(),
                        front: false,
                        chip_front: false,
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
    mark_fronts(&mut entries);
    Ok(entries)
}

/// Which of `points` (cost, error) are on their Pareto front: no other point is
/// at most as costly and at most as wrong, and better in one of the two. Equal
/// points are all on it.
pub(super) fn pareto(points: &[(f64, f64)]) -> Vec<bool> {
    points
        .iter()
        .enumerate()
        .map(|(i, &(c, e))| {
            !points
                .iter()
                .enumerate()
                .any(|(j, &(c2, e2))| j != i && c2 <= c && e2 <= e && (c2 < c || e2 < e))
        })
        .collect()
}

/// Marks the Pareto fronts of each scene over the rows of the backends (the f64
/// reference is the ceiling, not a contender): host time (median) against mean
/// FLIP over every row, and the chip's estimated cycles against mean FLIP over
/// the rows measured on the chip.
fn mark_fronts(entries: &mut [Entry]) {
    for b in super::SCENES {
        let host: Vec<usize> = (0..entries.len())
            .filter(|&i| entries[i].row.scene == b.name() && entries[i].row.backend != REFERENCE)
            .collect();
        let points: Vec<(f64, f64)> = host
            .iter()
            .map(|&i| (entries[i].row.ns_median, entries[i].row.flip))
            .collect();
        for (&i, on) in host.iter().zip(pareto(&points)) {
            entries[i].front = on;
        }
        let chip: Vec<(usize, f64)> = host
            .iter()
            .filter_map(|&i| entries[i].cycles().map(|c| (i, c)))
            .collect();
        let points: Vec<(f64, f64)> = chip
            .iter()
            .map(|&(i, c)| (c, entries[i].row.flip))
            .collect();
        for (&(i, _), on) in chip.iter().zip(pareto(&points)) {
            entries[i].chip_front = on;
        }
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

/// The entry of `backend` with the same scene and setting as `e`.
pub(super) fn same_setting<'a>(
    entries: &'a [Entry],
    e: &Entry,
    backend: &str,
) -> Result<&'a Entry, String> {
    let s = &e.row.setting;
    find(
        entries,
        &e.row.scene,
        backend,
        &s.sampler.to_string(),
        s.depth,
        s.tile,
    )
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

#[cfg(test)]
pub(super) mod tests {
    use super::*;
    use tessera_core::Sampler;

    #[test]
    fn the_pareto_front_keeps_what_nothing_beats() {
        // (cost, error): a staircase, a dominated point, a tie and a duplicate.
        let points = [
            (1.0, 0.5), // cheapest: on
            (2.0, 0.3), // on
            (2.0, 0.4), // as costly as the one above and worse: off
            (3.0, 0.3), // costlier, same error: off
            (4.0, 0.1), // on
            (4.0, 0.1), // the same point twice: both on
            (0.5, 0.9), // cheaper than everything: on
            (5.0, 0.2), // costlier and worse than (4, 0.1): off
        ];
        assert_eq!(
            pareto(&points),
            [true, true, false, false, true, true, true, false]
        );
        assert!(pareto(&[]).is_empty());
    }

    /// A row of `scene` for `backend` with the scene's sampler replaced.
    pub(in super::super) fn row(
        scene: Builtin,
        backend: &str,
        sampler: Sampler,
        ns: f64,
        flip: f64,
    ) -> Row {
        let base = scene.settings();
        Row {
            scene: scene.name().into(),
            backend: backend.into(),
            setting: Setting {
                sampler,
                depth: base.max_depth,
                tile: 16,
            },
            ns_median: ns,
            ns_min: ns,
            ns_max: ns,
            flip,
            psnr: 30.0,
            max_diff: 10,
            within1: 0.9,
        }
    }

    /// The fronts are per scene, leave the reference out, and the chip's is on
    /// cycles: a row that is slow on the host but cheap in cycles is on the chip's
    /// front only; a row without chip figures is on no chip front.
    #[test]
    fn fronts_are_per_scene_and_per_cost() {
        let (d, r) = (Builtin::ChapterDirect, Builtin::ChapterReflect);
        let fast = "fast";
        let rows = vec![
            row(d, "exact", Sampler::Centre, 100.0, 0.02),
            row(d, fast, Sampler::Centre, 90.0, 0.03),
            row(d, REFERENCE, Sampler::Centre, 10.0, 0.001),
            row(d, "exact", Sampler::Stratified(2), 400.0, 0.01),
            row(r, "exact", Sampler::Centre, 1000.0, 0.5),
        ];
        let cycles = |backend: &str, s: Sampler, scene: Builtin, c: f64| {
            let setting = Setting {
                sampler: s,
                depth: scene.settings().max_depth,
                tile: 16,
            };
            (
                chip_key(backend, scene.name(), &setting),
                Chip {
                    instructions: c / 2.0,
                    cycles: c,
                },
            )
        };
        let chip: HashMap<ChipKey, Chip> = [
            cycles("exact", Sampler::Centre, d, 1000.0),
            cycles(fast, Sampler::Centre, d, 1200.0),
            cycles("exact", Sampler::Stratified(2), d, 3000.0),
        ]
        .into_iter()
        .collect();
        let e = in_grid_order(&rows, &chip, &["exact", fast]).unwrap();
        let at = |scene: Builtin, backend: &str, sampler: &str| {
            let depth = scene.settings().max_depth;
            find(&e, scene.name(), backend, sampler, depth, 16).unwrap()
        };
        let (ex, fa) = (at(d, "exact", "centre"), at(d, fast, "centre"));
        let (s2, refr) = (at(d, "exact", "stratified:2"), at(d, REFERENCE, "centre"));
        // Host: both centre rows (cheaper or better) and stratified:2 (best).
        assert!(ex.front && fa.front && s2.front);
        // Chip: fast is costlier and worse than exact there.
        assert!(ex.chip_front && s2.chip_front && !fa.chip_front);
        assert!(!refr.front && !refr.chip_front && refr.chip.is_none());
        assert_eq!(ex.cycles(), Some(1000.0));
        // Alone in its scene, on the host front; never measured on the chip.
        let other = at(r, "exact", "centre");
        assert!(other.front && !other.chip_front);
        // Grid order: the backends of a setting together, the reference last.
        let names: Vec<&str> = e.iter().map(|x| x.row.backend.as_str()).collect();
        assert_eq!(names, ["exact", fast, REFERENCE, "exact", "exact"]);
        // A row outside the grid, or of a backend not in the list, is an error.
        let mut odd = rows.clone();
        odd[0].setting.tile = 12;
        assert!(in_grid_order(&odd, &chip, &["exact", fast]).is_err());
        assert!(in_grid_order(&rows, &chip, &["exact"]).is_err());
    }
}
