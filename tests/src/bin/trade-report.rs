//! `trade-report`: measures the speed/accuracy trade and writes `docs/trade.md`, the
//! charts `docs/trade.svg` (host) and `docs/trade-chip.svg` (chip) and the
//! interference figure `docs/interference.png`.
//!
//! Builds the `tessera` command and the firmware once per math backend of
//! [`BACKENDS`](tessera_tests::trade_report::BACKENDS), runs `tessera trade` with
//! each build (the exact one also measures the f64 reference, the ceiling), renders
//! every setting of every built-in scene on the chip under qemu with the
//! instruction profiler (instructions and estimated Cortex-M4 cycles per pixel),
//! computes the Pareto fronts of each scene (host time, chip cycles), and runs the
//! interference study. The steps are in [`tessera_tests::trade_report`].
//!
//! ```sh
//! cargo run -p tessera-tests --release --bin trade-report
//! cargo run -p tessera-tests --release --bin trade-report -- --out-dir /tmp/trade
//! ```
//!
//! `--out-dir DIR` writes the four files to `DIR` (created if missing) instead of
//! `docs/`.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;
use tessera_tests::firmware::repo_relative;
use tessera_tests::trade_report::{docs_dir, report};

const USAGE: &str = "usage: trade-report [--out-dir DIR]";

/// The output folder from the command line: `--out-dir DIR`, or `docs/`.
fn out_dir() -> Result<PathBuf, String> {
    let mut args = std::env::args_os().skip(1);
    match (args.next(), args.next(), args.next()) {
        (None, _, _) => Ok(docs_dir()),
        (Some(flag), Some(dir), None) if flag == "--out-dir" => Ok(PathBuf::from(dir)),
        _ => Err(USAGE.into()),
    }
}

fn main() -> ExitCode {
    let start = Instant::now();
    match out_dir().and_then(|dir| report(&dir)) {
        Ok(files) => {
            for f in files {
                println!("wrote {}", repo_relative(&f));
            }
            eprintln!(
                "trade-report: done in {:.0} s",
                start.elapsed().as_secs_f64()
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("trade-report: {e}");
            ExitCode::FAILURE
        }
    }
}
