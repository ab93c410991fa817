//! The speed/accuracy trade report (`src/bin/trade-report.rs`): measures the trade
//! and writes `docs/trade.md`, the chart `docs/trade.svg` and the interference
//! figure `docs/interference.png`.
//!
//! [`report`] runs the steps in order:
//! 1. `measure`: builds the `tessera` command twice (exact and fast-math) and runs
//!    `tessera trade` with each (the exact build also measures the f64 reference,
//!    the ceiling); then, side by side, counts the chip's instructions per pixel for
//!    the default scene and the interference screen under qemu (both math backends)
//!    and runs the interference study;
//! 2. `entries`: the measured rows in grid order with their chip counts, and the
//!    Pareto front of each scene;
//! 3. `chart`, `document` (with its conclusions from `pick`): the chart and the
//!    document, every figure taken from the entries.

mod chart;
mod document;
mod entries;
mod measure;
mod pick;

use std::path::{Path, PathBuf};
use tessera::builtin::Builtin;

/// The command that regenerates the report.
const COMMAND: &str = "cargo run -p tessera-tests --release --bin trade-report";
/// Host image size and timed runs per setting.
const SIZE: &str = "128x96";
const RUNS: &str = "7";
/// Chip image size.
const CHIP_SIZE: u16 = 64;
/// The scenes measured on the chip: the default scene and the interference screen.
const CHIP_SCENES: [Builtin; 2] = [Builtin::ChapterReflect, Builtin::Interference];
/// The seed `tessera trade` renders with (the chip uses the same).
const SEED: u32 = 1;
/// The interference study: pixel footprints (in fringe spacings) and image size.
const FOOTPRINTS: [f64; 2] = [0.3, 1.6];
const FRINGE_SIZE: (u16, u16) = (160, 120);
/// Columns of the interference figure.
const FRINGE_COLUMNS: usize = 5;

/// The backends, as the rows name them.
const EXACT: &str = "exact";
const FAST: &str = "fast-math";
const REFERENCE: &str = "f64-reference";

/// Measures everything, then writes the document, the chart and the figure under
/// `docs/`; returns their paths.
pub fn report() -> Result<Vec<PathBuf>, String> {
    let docs = crate::firmware::repo_root().join("docs");
    let m = measure::all()?;
    let entries = entries::in_grid_order(&m.rows, &m.chip)?;

    std::fs::create_dir_all(&docs).map_err(|e| format!("{}: {e}", docs.display()))?;
    let fig = docs.join("interference.png");
    tessera_host::write_png(
        &tessera_host::trade::figure(&m.fringes, FRINGE_COLUMNS),
        &fig,
    )
    .map_err(|e| format!("{}: {e}", fig.display()))?;
    let svg = docs.join("trade.svg");
    write(&svg, &chart::svg(&entries)?)?;
    let md = docs.join("trade.md");
    write(
        &md,
        &document::markdown(&entries, &m.chip, m.runs.len(), &m.fringes)?,
    )?;
    Ok(vec![md, svg, fig])
}

/// Writes `text` to `path` atomically.
fn write(path: &Path, text: &str) -> Result<(), String> {
    tessera_host::write_atomic(text.as_bytes(), path)
        .map_err(|e| format!("{}: {e}", path.display()))
}
