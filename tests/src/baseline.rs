//! The guarded instruction counts: `tests/chip-baseline.txt` holds, for a few runs
//! of the firmware, the exact instruction count (SysTick) measured when it was
//! last regenerated (`chip-report --bless-baseline`); the firmware test fails when
//! a count rises by more than [`TOLERANCE_PERCENT`] % over it.
//! `tests/chip-baseline-cores.txt` ([`CORES_FILE`]) holds the same runs on the
//! other cores with an FPU, each line prefixed by the core's name ([`key`]),
//! guarded by their tests (`tests/tests/cores.rs`).
//!
//! Each file names the qemu it was counted under (`# Counted under: QEMU emulator
//! version 7.2.22 ...`, [`COUNTED_UNDER`]). The counts are the guest's
//! instructions (SysTick under `-icount shift=0`), but a qemu of another series
//! (major.minor) is not taken on trust: [`same_qemu`] refuses it with a message
//! that says what to do, and the guards call it before comparing. Within the
//! series the guarded counts were the same to the instruction under 7.2.18
//! (Debian's 1:7.2+dfsg-7+deb12u15) and 7.2.22 (1:7.2+dfsg-7+deb12u18+b3).

use crate::firmware::{self, CORTEX_M4F, Core, Run};
use std::path::PathBuf;
use tessera_core::Sampler;
use tessera_core::builtin::Builtin;

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

/// The header line's start that names the qemu a file was counted under.
pub const COUNTED_UNDER: &str = "# Counted under: ";

/// The series (`7.2`) of a `--version` line (`QEMU emulator version 7.2.22 (...)`).
#[must_use]
pub fn qemu_series(version_line: &str) -> Option<String> {
    let rest = version_line.split("version ").nth(1)?;
    let number = rest.split_whitespace().next()?;
    let mut parts = number.split('.');
    let (major, minor) = (parts.next()?, parts.next()?);
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    (digits(major) && digits(minor)).then(|| format!("{major}.{minor}"))
}

/// The qemu `--version` line a baseline file names (after [`COUNTED_UNDER`]).
#[must_use]
pub fn counted_under(text: &str) -> Option<&str> {
    text.lines()
        .find_map(|l| l.strip_prefix(COUNTED_UNDER))
        .map(str::trim)
}

/// Whether the counts of the baseline file `text` (named `file`) may be compared
/// with counts made under the qemu whose `--version` line is `running`: the same
/// series (major.minor) as the file's. Otherwise an error that names both
/// versions and what to do.
pub fn same_qemu(file: &str, text: &str, running: &str) -> Result<(), String> {
    let blessed = counted_under(text).ok_or_else(|| {
        format!("{file} does not name the qemu it was counted under (a line `{COUNTED_UNDER}...`)")
    })?;
    let want = qemu_series(blessed)
        .ok_or_else(|| format!("{file}: no qemu version in `{COUNTED_UNDER}{blessed}`"))?;
    match qemu_series(running) {
        Some(got) if got == want => Ok(()),
        got => Err(format!(
            "{file} was counted under qemu {want} ({blessed}); this machine runs {}. \
             Instruction counts under another qemu series are not checked to be the same: \
             install qemu {want} (`bash tests/install-qemu.sh --check` prints the plan; on \
             Debian 12, `apt-get install --no-install-recommends qemu-system-arm \
             qemu-system-misc`), or measure under this one and bless its counts \
             (`{BLESS}`, with a commit that says so)",
            got.map_or_else(
                || format!("`{running}`"),
                |g| format!("qemu {g} ({running})")
            )
        )),
    }
}

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

/// The file's text for `(run line, instructions)` pairs counted under the qemu
/// whose `--version` line is `qemu`.
#[must_use]
pub fn render(entries: &[(String, u64)], qemu: &str) -> String {
    let mut s = format!(
        "# Exact instruction counts of the firmware (SysTick, inside render_tile), one run a\n\
         # line: the run-list line (<scene> <sampler> <depth> <tile> <width> <height> <seed> <encoding>)\n\
         # and its instruction count. The firmware test `instruction_counts_stay_within_the_baseline`\n\
         # fails when a count rises by more than {TOLERANCE_PERCENT}% over this file.\n\
         # Written by `{BLESS}`.\n\
         # It changes only in a commit that says why (a speed-up, or a cost accepted).\n\
         {COUNTED_UNDER}{qemu}\n",
    );
    for (line, n) in entries {
        s.push_str(&format!("{line} {n}\n"));
    }
    s
}

/// The other cores' file's text for `(core and run line, instructions)` pairs
/// counted under the qemu whose `--version` line is `qemu`.
#[must_use]
pub fn render_cores(entries: &[(String, u64)], qemu: &str) -> String {
    let mut s = format!(
        "# Exact instruction counts of the firmware on the cores with an FPU other than the\n\
         # Cortex-M4F (its clock, inside render_tile), one run a line: the core's name, the\n\
         # run-list line (<scene> <sampler> <depth> <tile> <width> <height> <seed> <encoding>)\n\
         # and its instruction count. The tests `cores::*` fail when a count rises by more than\n\
         # {TOLERANCE_PERCENT}% over this file.\n\
         # Written by `{BLESS}` (with {FILE}) or `{BLESS_CORES}`.\n\
         # It changes only in a commit that says why (a speed-up, or a cost accepted).\n\
         {COUNTED_UNDER}{qemu}\n",
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

    const QEMU_7_2: &str = "QEMU emulator version 7.2.22 (Debian 1:7.2+dfsg-7+deb12u18+b3)";

    #[test]
    fn qemu_series_of_version_lines() {
        assert_eq!(qemu_series(QEMU_7_2).as_deref(), Some("7.2"));
        assert_eq!(
            qemu_series("QEMU emulator version 10.0.2 (Debian 1:10.0.2+ds-2)").as_deref(),
            Some("10.0")
        );
        assert_eq!(
            qemu_series("QEMU emulator version 8.2").as_deref(),
            Some("8.2")
        );
        assert_eq!(qemu_series("QEMU emulator version 9"), None);
        assert_eq!(qemu_series("qemu-system-arm: unknown"), None);
        assert_eq!(qemu_series("QEMU emulator version x.2.1"), None);
    }

    #[test]
    fn counts_are_compared_only_under_the_blessed_series() {
        let text = render(&[("a 1".to_string(), 1)], QEMU_7_2);
        assert_eq!(same_qemu(FILE, &text, QEMU_7_2), Ok(()));
        // Another point release of the series.
        assert_eq!(
            same_qemu(
                FILE,
                &text,
                "QEMU emulator version 7.2.15 (Debian 1:7.2+dfsg-7+deb12u15)"
            ),
            Ok(())
        );
        let err = same_qemu(FILE, &text, "QEMU emulator version 10.0.2 (Debian)").unwrap_err();
        assert!(
            err.contains("counted under qemu 7.2 (QEMU emulator version 7.2.22")
                && err.contains("this machine runs qemu 10.0 (QEMU emulator version 10.0.2")
                && err.contains("install qemu 7.2")
                && err.contains(BLESS),
            "{err}"
        );
        let err = same_qemu(FILE, &text, "garbage").unwrap_err();
        assert!(err.contains("this machine runs `garbage`"), "{err}");
        let err = same_qemu(FILE, "x 1\n", QEMU_7_2).unwrap_err();
        assert!(err.contains("does not name the qemu"), "{err}");
    }

    #[test]
    fn round_trip_and_comparison() {
        let entries = vec![
            ("chapter-direct centre 0 16 64 64 0".to_string(), 1000),
            ("showcase centre 5 16 64 64 0".to_string(), 5000),
        ];
        let text = render(&entries, QEMU_7_2);
        assert_eq!(parse(&text).unwrap(), entries);
        assert_eq!(counted_under(&text), Some(QEMU_7_2));
        // The committed files are what `render` and `render_cores` write for their
        // own entries under the qemu they name.
        let file = std::fs::read_to_string(path()).unwrap();
        let qemu = counted_under(&file).expect("the baseline names its qemu");
        assert_eq!(render(&parse(&file).unwrap(), qemu), file);
        let cores = std::fs::read_to_string(cores_path()).unwrap();
        let qemu = counted_under(&cores).expect("the cores' baseline names its qemu");
        assert_eq!(render_cores(&parse(&cores).unwrap(), qemu), cores);
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
