//! The guarded instruction counts: `tests/chip-baseline.txt` holds, for a few runs
//! of the firmware, the exact instruction count (SysTick) measured when it was
//! last regenerated (`chip-report --bless-baseline`); the firmware test fails when
//! a count rises by more than [`TOLERANCE_PERCENT`] % over it.
//! `tests/chip-baseline-cores.txt` ([`CORES_FILE`]) holds the same runs on the
//! other cores with an FPU, each line prefixed by the core's name ([`key`]),
//! guarded by their tests (`tests/tests/cores.rs`).

use crate::firmware::{self, CORTEX_M4F, Core, Run};
use std::path::PathBuf;
use tessera::Sampler;
use tessera::builtin::Builtin;

/// A count may rise by this many percent over the baseline before the test fails
/// (and a fall by more gets a note).
pub const TOLERANCE_PERCENT: u64 = 2;
/// The file, relative to the repository root.
pub const FILE: &str = "tests/chip-baseline.txt";
/// The command that rewrites the file from a new measurement.
pub const BLESS: &str =
    "cargo run -p tessera-tests --release --bin chip-report -- --bless-baseline";

/// The other cores' file, relative to the repository root.
pub const CORES_FILE: &str = "tests/chip-baseline-cores.txt";
/// The command that rewrites the other cores' file alone.
pub const BLESS_CORES: &str =
    "cargo run -p tessera-tests --release --bin chip-report -- --bless-cores-baseline";

/// The baseline file's path.
#[must_use]
pub fn path() -> PathBuf {
    firmware::repo_root().join(FILE)
}

/// The other cores' baseline file's path.
#[must_use]
pub fn cores_path() -> PathBuf {
    firmware::repo_root().join(CORES_FILE)
}

/// A run's name in the baseline files: its run-list line, after the core's name
/// for a core other than the Cortex-M4F (`cortex-m7 chapter-direct centre ...`).
#[must_use]
pub fn key(core: &Core, run: &Run) -> String {
    if *core == CORTEX_M4F {
        run.to_string()
    } else {
        format!("{} {run}", core.name)
    }
}

/// The guarded runs: each built-in scene at 64x64 with its own settings (centre
/// sampling), and chapter-direct with stratified 4x4 sampling; tiles of 16.
#[must_use]
pub fn runs() -> Vec<Run> {
    let mut runs: Vec<Run> = Builtin::ALL.iter().map(|&b| Run::of(b, 64, 64)).collect();
    runs.push(Run {
        sampler: Sampler::Stratified(4),
        ..Run::of(Builtin::ChapterDirect, 64, 64)
    });
    runs
}

/// The file's text for `(run line, instructions)` pairs.
#[must_use]
pub fn render(entries: &[(String, u64)]) -> String {
    let mut s = format!(
        "# Exact instruction counts of the firmware (SysTick, inside render_tile), one run a\n\
         # line: the run-list line (<scene> <sampler> <depth> <tile> <width> <height> <seed> <encoding>)\n\
         # and its instruction count. The firmware test `instruction_counts_stay_within_the_baseline`\n\
         # fails when a count rises by more than {TOLERANCE_PERCENT}% over this file.\n\
         # Written by `{BLESS}`.\n\
         # It changes only in a commit that says why (a speed-up, or a cost accepted).\n",
    );
    for (line, n) in entries {
        s.push_str(&format!("{line} {n}\n"));
    }
    s
}

/// The other cores' file's text for `(core and run line, instructions)` pairs.
#[must_use]
pub fn render_cores(entries: &[(String, u64)]) -> String {
    let mut s = format!(
        "# Exact instruction counts of the firmware on the cores with an FPU other than the\n\
         # Cortex-M4F (its clock, inside render_tile), one run a line: the core's name, the\n\
         # run-list line (<scene> <sampler> <depth> <tile> <width> <height> <seed> <encoding>)\n\
         # and its instruction count. The tests `cores::*` fail when a count rises by more than\n\
         # {TOLERANCE_PERCENT}% over this file.\n\
         # Written by `{BLESS}` (with {FILE}) or `{BLESS_CORES}`.\n\
         # It changes only in a commit that says why (a speed-up, or a cost accepted).\n",
    );
    for (line, n) in entries {
        s.push_str(&format!("{line} {n}\n"));
    }
    s
}

/// Parses the file's text into `(run line, instructions)` pairs.
pub fn parse(text: &str) -> Result<Vec<(String, u64)>, String> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'))
        .map(|(n, l)| {
            let (line, count) = l
                .trim()
                .rsplit_once(' ')
                .ok_or_else(|| format!("{FILE}:{}: no count in {l:?}", n + 1))?;
            let count = count
                .parse()
                .map_err(|_| format!("{FILE}:{}: bad count in {l:?}", n + 1))?;
            Ok((line.trim().to_string(), count))
        })
        .collect()
}

/// One run compared with its baseline.
#[derive(Clone, Debug, PartialEq)]
pub struct Row {
    /// The run-list line.
    pub line: String,
    /// The baseline count, if the baseline has the run.
    pub baseline: Option<u64>,
    /// The count now.
    pub now: u64,
}

impl Row {
    /// `now / baseline - 1`.
    #[must_use]
    pub fn change(&self) -> Option<f64> {
        self.baseline
            .map(|b| self.now as f64 / b.max(1) as f64 - 1.0)
    }
}

/// The comparison of counts now with the baseline.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// Every run.
    pub rows: Vec<Row>,
}

impl Comparison {
    /// Compares `now` (`(run line, count)`) with `baseline`.
    #[must_use]
    pub fn new(baseline: &[(String, u64)], now: &[(String, u64)]) -> Self {
        let rows = now
            .iter()
            .map(|(line, n)| Row {
                line: line.clone(),
                baseline: baseline.iter().find(|(l, _)| l == line).map(|(_, b)| *b),
                now: *n,
            })
            .collect();
        Self { rows }
    }

    /// Runs that rose by more than [`TOLERANCE_PERCENT`] %, or that the baseline
    /// lacks.
    #[must_use]
    pub fn failures(&self) -> Vec<&Row> {
        self.rows
            .iter()
            .filter(|r| {
                r.baseline.is_none_or(|b| {
                    100 * u128::from(r.now) > u128::from(b) * u128::from(100 + TOLERANCE_PERCENT)
                })
            })
            .collect()
    }

    /// Runs that fell by more than [`TOLERANCE_PERCENT`] %.
    #[must_use]
    pub fn improvements(&self) -> Vec<&Row> {
        self.rows
            .iter()
            .filter(|r| {
                r.baseline.is_some_and(|b| {
                    100 * u128::from(r.now) < u128::from(b) * u128::from(100 - TOLERANCE_PERCENT)
                })
            })
            .collect()
    }

    /// A table of baseline against now, every run, and what to do.
    #[must_use]
    pub fn table(&self) -> String {
        let mut s = format!(
            "{:<40} {:>14} {:>14} {:>8}\n",
            "run", "baseline", "now", "change"
        );
        for r in &self.rows {
            let (b, c) = match (r.baseline, r.change()) {
                (Some(b), Some(c)) => (b.to_string(), format!("{:+.2}%", 100.0 * c)),
                _ => ("missing".into(), "-".into()),
            };
            s.push_str(&format!(
                "{:<40} {:>14} {:>14} {:>8}\n",
                r.line, b, r.now, c
            ));
        }
        if !self.failures().is_empty() {
            s.push_str(&format!(
                "FAIL: a count rose by more than {TOLERANCE_PERCENT}% (or is missing from \
                 {FILE}). Find the cause (`cargo run -p tessera-tests --release --bin \
                 chip-profile` shows where the instructions go); if the cost is accepted, \
                 regenerate the baseline with `{BLESS}` in a commit that says why.\n"
            ));
        }
        if !self.improvements().is_empty() {
            s.push_str(&format!(
                "note: a count fell by more than {TOLERANCE_PERCENT}%: regenerate the baseline \
                 (`{BLESS}`) in a commit that says why, so that the guard holds the new \
                 figure.\n"
            ));
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_comparison() {
        let entries = vec![
            ("chapter-direct centre 0 16 64 64 0".to_string(), 1000),
            ("showcase centre 5 16 64 64 0".to_string(), 5000),
        ];
        let text = render(&entries);
        assert_eq!(parse(&text).unwrap(), entries);
        // The committed files are what `render` and `render_cores` write for their
        // own entries.
        let file = std::fs::read_to_string(path()).unwrap();
        assert_eq!(render(&parse(&file).unwrap()), file);
        let cores = std::fs::read_to_string(cores_path()).unwrap();
        assert_eq!(render_cores(&parse(&cores).unwrap()), cores);
        // Every other core has every guarded run.
        let cores = parse(&cores).unwrap();
        for core in firmware::FPU_CORES {
            for run in runs() {
                let k = key(&core, &run);
                assert!(
                    cores.iter().any(|(l, _)| *l == k),
                    "{k} is not in {CORES_FILE}"
                );
            }
        }
        assert_eq!(key(&CORTEX_M4F, &runs()[0]), runs()[0].to_string());
        let now = vec![
            ("chapter-direct centre 0 16 64 64 0".to_string(), 1021),
            ("showcase centre 5 16 64 64 0".to_string(), 4800),
        ];
        let c = Comparison::new(&entries, &now);
        assert_eq!(c.failures().len(), 1);
        assert_eq!(c.improvements().len(), 1);
        assert!(c.table().contains("FAIL") && c.table().contains("note:"));
        let ok = vec![("chapter-direct centre 0 16 64 64 0".to_string(), 1020)];
        assert!(Comparison::new(&entries, &ok).failures().is_empty());
        let missing = vec![("interference centre 0 16 64 64 0".to_string(), 1)];
        assert_eq!(Comparison::new(&entries, &missing).failures().len(), 1);
    }
}
