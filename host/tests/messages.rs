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
