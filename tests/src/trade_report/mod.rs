//! The speed/accuracy trade report (`src/bin/trade-report.rs`): measures the trade
//! and writes `docs/trade.md`, the charts `docs/trade.svg` (host) and
//! `docs/trade-chip.svg` (chip) and the interference figure `docs/interference.png`.
//!
//! [`report`] runs the steps in order:
//! 1. `measure`: builds the `tessera` command once per backend of [`BACKENDS`] and
//!    runs `tessera trade` with each (the first, exact, build also measures the f64
//!    reference, the ceiling); then, side by side, renders every setting of the grid
//!    of every built-in scene on the chip under qemu with the instruction profiler
//!    (one firmware image per backend): instructions per pixel (SysTick) and
//!    estimated Cortex-M4 cycles per pixel ([`crate::cycles`]), and runs the
//!    interference study;
//! 2. `entries`: the measured rows in grid order with their chip figures, and the
//!    Pareto fronts of each scene (host time, chip cycles);
//! 3. `chart`, `document` (with its conclusions from `pick`): the charts and the
//!    document, every figure taken from the entries.

mod chart;
mod document;
mod entries;
mod measure;
mod pick;

use std::path::{Path, PathBuf};
use tessera_core::builtin::Builtin;

/// The command that regenerates the report.
const COMMAND: &str = "cargo run -p tessera-tests --release --bin trade-report";
/// Host image size and timed runs per setting.
const SIZE: &str = "128x96";
const RUNS: &str = "7";
/// Chip image size.
const CHIP_SIZE: u16 = 64;
/// The scenes of the report (host and chip): the built-in scenes but the teapot,
/// whose cost is that of its BVH rather than of a sampler or a backend
/// (`chip-report` measures it).
pub(crate) const SCENES: [Builtin; 4] = [
    Builtin::ChapterDirect,
    Builtin::ChapterReflect,
    Builtin::Interference,
    Builtin::Showcase,
];
/// The scenes measured on the chip.
const CHIP_SCENES: [Builtin; 4] = SCENES;
/// The seed `tessera trade` renders with (the chip uses the same).
const SEED: u32 = 1;
/// The interference study: pixel footprints (in fringe spacings) and image size.
const FOOTPRINTS: [f64; 2] = [0.3, 1.6];
const FRINGE_SIZE: (u16, u16) = (160, 120);
/// Columns of the interference figure.
const FRINGE_COLUMNS: usize = 5;

/// A math backend of the report: the name its rows carry and the cargo features
/// of the core it is built with (features of `tessera-host` and of the firmware
/// `tessera-fw`, which forward them to the core).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Backend {
    /// The name in the rows, the tables and the charts.
    pub name: &'static str,
    /// The cargo features it is built with.
    pub features: &'static [&'static str],
}

impl Backend {
    /// A backend named `name`, built with `features`.
    #[must_use]
    pub const fn new(name: &'static str, features: &'static [&'static str]) -> Self {
        Self { name, features }
    }
}

/// The backends the report measures, one line each: the exact math first (no
/// features: the default build, the baseline the others are compared with, and
/// the build that also measures the f64 reference). Each gets its own `tessera`
/// binary and firmware image.
pub const BACKENDS: &[Backend] = &[
    Backend::new("exact", &[]),
    Backend::new("fast-rsqrt", &["fast-rsqrt"]),
    Backend::new("fast-recip", &["fast-recip"]),
    Backend::new("fast-pow", &["fast-pow"]),
    Backend::new("fast-math", &["fast-math"]),
];

/// The exact backend's name.
const EXACT: &str = BACKENDS[0].name;
/// The f64 reference's rows.
const REFERENCE: &str = tessera_host::trade::REFERENCE;

/// The backends other than the exact one.
fn approximations() -> impl Iterator<Item = &'static Backend> {
    BACKENDS.iter().skip(1)
}

/// The output files under `dir`: the document, the host and chip charts, the
/// interference figure.
pub struct Outputs {
    /// `trade.md`.
    pub document: PathBuf,
    /// `trade.svg`.
    pub host_chart: PathBuf,
    /// `trade-chip.svg`.
    pub chip_chart: PathBuf,
    /// `interference.png`.
    pub figure: PathBuf,
}

impl Outputs {
    /// The files of the report in `dir`.
    #[must_use]
    pub fn in_dir(dir: &Path) -> Self {
        Self {
            document: dir.join("trade.md"),
            host_chart: dir.join(chart::Cost::Host.file()),
            chip_chart: dir.join(chart::Cost::Chip.file()),
            figure: dir.join("interference.png"),
        }
    }
}

/// The folder the report is written to by default: the repository's `docs/`.
#[must_use]
pub fn docs_dir() -> PathBuf {
    crate::firmware::repo_root().join("docs")
}

/// Measures everything, then writes the document, the charts and the figure in
/// `dir` (created if missing; `docs/` for the committed report); returns their
/// paths.
pub fn report(dir: &Path) -> Result<Vec<PathBuf>, String> {
    let out = Outputs::in_dir(dir);
    let m = measure::all()?;
    let entries = entries::in_grid_order(&m.rows, &m.chip, &entries::backend_names())?;

    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    tessera_host::write_png(
        &tessera_host::trade::figure(&m.fringes, FRINGE_COLUMNS),
        &out.figure,
    )
    .map_err(|e| format!("{}: {e}", out.figure.display()))?;
    write(&out.host_chart, &chart::svg(&entries, chart::Cost::Host)?)?;
    write(&out.chip_chart, &chart::svg(&entries, chart::Cost::Chip)?)?;
    write(
        &out.document,
        &document::markdown(&entries, &m.chip_summary, &m.fringes)?,
    )?;
    Ok(vec![
        out.document,
        out.host_chart,
        out.chip_chart,
        out.figure,
    ])
}

/// Writes `text` to `path` atomically.
fn write(path: &Path, text: &str) -> Result<(), String> {
    tessera_host::write_atomic(text.as_bytes(), path)
        .map_err(|e| format!("{}: {e}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The names of `[features]` in a Cargo manifest.
    fn features_of(manifest: &str) -> Vec<String> {
        let path = crate::firmware::repo_root().join(manifest);
        let text = std::fs::read_to_string(&path).expect("the manifest");
        text.lines()
            .skip_while(|l| l.trim() != "[features]")
            .skip(1)
            .take_while(|l| !l.trim_start().starts_with('['))
            .filter_map(|l| l.split_once('=').map(|(k, _)| k.trim().to_string()))
            .filter(|k| !k.is_empty() && !k.starts_with('#'))
            .collect()
    }

    /// The list the report builds from: the exact backend first and without
    /// features, unique names that are not the reference's, every feature one
    /// that the host and the firmware both accept, each feature set different.
    #[test]
    fn the_backends_are_buildable_and_distinct() {
        assert_eq!(BACKENDS[0], Backend::new("exact", &[]));
        assert_eq!(EXACT, "exact");
        let host = features_of("host/Cargo.toml");
        let fw = features_of("tests/firmware/Cargo.toml");
        assert!(host.iter().any(|f| f == "fast-math"), "{host:?}");
        for (i, b) in BACKENDS.iter().enumerate() {
            assert_ne!(b.name, REFERENCE);
            assert!(crate::firmware::image_name(&[b.name]).is_ok(), "{}", b.name);
            for f in b.features {
                assert!(
                    host.iter().any(|h| h == f),
                    "{f} is not a tessera-host feature"
                );
                assert!(fw.iter().any(|h| h == f), "{f} is not a tessera-fw feature");
            }
            for o in &BACKENDS[i + 1..] {
                assert_ne!(b.name, o.name);
                let (mut x, mut y) = (b.features.to_vec(), o.features.to_vec());
                x.sort_unstable();
                y.sort_unstable();
                assert_ne!(x, y, "{} and {} are the same build", b.name, o.name);
            }
        }
        assert_eq!(approximations().count(), BACKENDS.len() - 1);
    }
}
