//! `trade-report`: measures the speed/accuracy trade and writes `docs/trade.md`, the
//! chart `docs/trade.svg` and the interference figure `docs/interference.png`.
//!
//! Builds the `tessera` command twice (exact and fast-math), runs `tessera trade` with
//! each (the exact build also measures the f64 reference, the ceiling), counts the
//! chip's instructions per pixel for the default scene and the interference screen
//! under qemu (both math backends), computes the Pareto front of each scene, and runs
//! the interference study. The steps are in [`tessera_tests::trade_report`].
//!
//! ```sh
//! cargo run -p tessera-tests --release --bin trade-report
//! ```

use std::process::ExitCode;
use std::time::Instant;
use tessera_tests::firmware::repo_relative;
use tessera_tests::trade_report::report;

fn main() -> ExitCode {
    let start = Instant::now();
    match report() {
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
