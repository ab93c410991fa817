//! What the `tessera` command says, and with what exit status (issue 23, item 6):
//! a bad command-line value is a usage error (status 2, clap's message naming
//! the range); errors name the scene, the item and the value at fault; the
//! summary lines say what was done.

mod common;

use common::{bin, scratch, text};
use std::path::Path;
use std::process::Output;

fn run(dir: &Path, args: &[&str]) -> Output {
    bin().current_dir(dir).args(args).output().unwrap()
}

/// Runs `args`: it must be a usage error (status 2) whose message contains
/// every one of `want`, and write nothing; returns stderr.
fn usage_error(args: &[&str], want: &[&str]) -> String {
    let dir = scratch("usage");
    let out = run(&dir, args);
    let e = text(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {e}");
    for w in want {
        assert!(e.contains(w), "{args:?}: {w:?} not in {e}");
    }
    assert!(common::entries(&dir).is_empty(), "{args:?} wrote files");
    e
}

#[test]
fn a_depth_beyond_the_maximum_is_a_usage_error_naming_the_range() {
    let max = tessera::MAX_DEPTH.to_string();
    for cmd in ["render", "compare", "simulate"] {
        usage_error(
            &[cmd, "--depth", "9"],
            &["--depth", "expected a depth from 0 to ", &max, "got \"9\""],
        );
        usage_error(&[cmd, "--depth=-1"], &["--depth", "got \"-1\""]);
    }
}

/// The frame delays of the GIF at `path`, in hundredths of a second.
fn gif_delays(path: &Path) -> Vec<u16> {
    let file = std::fs::File::open(path).unwrap();
    let mut decoder = gif::DecodeOptions::new().read_info(file).unwrap();
    let mut delays = Vec::new();
    while let Some(frame) = decoder.read_next_frame().unwrap() {
        delays.push(frame.delay);
    }
    delays
}

/// A GIF counts its delays in hundredths of a second, at most 65,535: a longer
/// `--delay-ms` is refused (it was clamped to 655.35 s without a word), and a
/// delay that is no multiple of 10 ms goes to the nearest hundredth, never to 0
/// (5 ms became 0, which viewers show at their own pace).
#[test]
fn orbit_delays_are_bounded_and_rounded_to_hundredths() {
    let max = tessera_host::limits::MAX_GIF_DELAY_MS.to_string();
    assert_eq!(max, "655350");
    for cmd in [&["simulate", "--orbit", "2"][..], &["simulate"]] {
        let mut args = cmd.to_vec();
        args.extend(["--delay-ms", "655351"]);
        usage_error(
            &args,
            &["--delay-ms", "from 0 to 655350 ms", "got \"655351\""],
        );
    }
    let dir = scratch("delays");
    for (ms, cs) in [
        ("80", 8),
        ("5", 1),
        ("14", 1),
        ("15", 2),
        ("0", 0),
        ("655350", 65535),
    ] {
        let name = format!("d{ms}.gif");
        let out = run(
            &dir,
            &[
                "simulate",
                "--orbit",
                "2",
                "--size",
                "8x8",
                "--delay-ms",
                ms,
                "-o",
                &name,
            ],
        );
        assert!(out.status.success(), "{ms}: {}", text(&out.stderr));
        assert_eq!(gif_delays(&dir.join(&name)), vec![cs; 2], "--delay-ms {ms}");
    }
    let help = text(&run(&dir, &["simulate", "--help"]).stdout).replace('\n', " ");
    let help = help.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        help.contains("rounded to the nearest 10 ms") && help.contains("655350"),
        "{help}"
    );
}
