//! What is made from the command line's definitions: the shell completions
//! (`tessera completions SHELL`), the manual page (`tessera man`), and the help,
//! short for each command (its purpose in a line and its options) with the long
//! explanations said once, in `tessera --help` and the manual page.

use crate::common::{bin, text};
use std::process::{Command, Output, Stdio};

fn run(args: &[&str]) -> Output {
    let out = bin().args(args).output().unwrap();
    assert!(!text(&out.stderr).contains("panicked"), "{args:?}");
    out
}

/// The commands, as `tessera --help` lists them (without `help`).
fn commands() -> Vec<String> {
    let help = text(&run(&["--help"]).stdout);
    let list: Vec<String> = help
        .lines()
        .skip_while(|l| *l != "Commands:")
        .skip(1)
        .take_while(|l| !l.is_empty())
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .filter(|c| c != "help")
        .collect();
    for c in [
        "render",
        "compare",
        "diff",
        "simulate",
        "bake",
        "completions",
        "man",
    ] {
        assert!(list.iter().any(|l| l == c), "{c} not in {list:?}");
    }
    list
}

/// The long options of `tessera COMMAND --help` (`--size`, ...; `--help`
/// included): the first column of its option lines.
fn long_options(command: &str) -> Vec<String> {
    let help = text(&run(&[command, "--help"]).stdout);
    let options: Vec<String> = help
        .lines()
        .map(str::trim_start)
        .filter(|l| l.starts_with('-'))
        .filter_map(|l| {
            let column = l.split("  ").next().unwrap_or(l);
            column
                .split_whitespace()
                .find(|w| w.starts_with("--"))
                .map(|w| w.trim_end_matches(',').to_string())
        })
        .collect();
    assert!(options.len() >= 8, "{command}: {options:?}");
    options
}

#[test]
fn the_bash_completion_knows_every_command() {
    let out = run(&["completions", "bash"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let script = text(&out.stdout);
    assert!(script.contains("_tessera()"), "{script}");
    // Each command: among the words completed after `tessera`, and a case of its
    // own (`tessera,render)`) for its options.
    let first = script
        .lines()
        .find(|l| l.trim_start().starts_with("opts=\"-h -V"))
        .expect("the top level's words");
    for c in commands() {
        assert!(
            first.split_whitespace().any(|w| w == c),
            "{c} not in {first}"
        );
        assert!(
            script.contains(&format!("tessera,{c})")),
            "{c} not in the script"
        );
    }
    for o in long_options("render") {
        assert!(script.contains(&o), "{o} not in the script");
    }
    // The script is valid bash, and completes a command's name.
    if let Ok(mut bash) = Command::new("bash")
        .arg("-c")
        .arg(
            "source /dev/stdin && COMP_WORDS=(tessera di) COMP_CWORD=1 \
             COMP_LINE='tessera di' COMP_POINT=10 && _tessera tessera di tessera && \
             echo \"${COMPREPLY[@]}\"",
        )
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
    {
        use std::io::Write;
        bash.stdin
            .take()
            .unwrap()
            .write_all(script.as_bytes())
            .unwrap();
        let done = bash.wait_with_output().unwrap();
        assert!(done.status.success());
        assert_eq!(text(&done.stdout).trim(), "diff");
    }
    for shell in ["zsh", "fish", "elvish", "powershell"] {
        let out = run(&["completions", shell]);
        assert_eq!(out.status.code(), Some(0), "{shell}");
        let script = text(&out.stdout);
        assert!(
            script.contains("simulate") && script.contains("heatmap"),
            "{shell}"
        );
    }
    let out = run(&["completions", "tcsh"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("bash, elvish, fish, powershell, zsh"));
}

/// The manual page's text as a reader sees it: roff's escapes undone.
fn unescaped(roff: &str) -> String {
    roff.replace(r"\-", "-")
        .replace(r"\*(Aq", "'")
        .replace(r"\fB", "")
        .replace(r"\fI", "")
        .replace(r"\fR", "")
        .replace(r"\\", r"\")
}

#[test]
fn the_manual_page_is_roff_with_every_command_and_option() {
    let out = run(&["man"]);
    assert_eq!(out.status.code(), Some(0), "{}", text(&out.stderr));
    let page = text(&out.stdout);
    assert!(page.starts_with(".TH tessera 1 "), "{page}");
    // Every control line is a request or macro a manual page uses; no text line
    // could be taken for one.
    for line in page.lines() {
        if let Some(request) = line.strip_prefix('.') {
            let name = request.split_whitespace().next().unwrap_or("");
            assert!(
                [
                    "TH", "SH", "SS", "TP", "PP", "IP", "RS", "RE", "br", "ie", "el"
                ]
                .contains(&name),
                "{line:?}"
            );
        }
        assert!(!line.starts_with('\''), "{line:?}");
    }
    for c in commands() {
        assert!(page.contains(&format!(".SS \"tessera {c}\"")), "{c}");
    }
    let text = unescaped(&page);
    for o in long_options("render") {
        assert!(text.contains(&o), "{o} not in the page");
    }
    // The render section has each of render's options (its own `.SS` to the next).
    let render = text
        .split(".SS \"tessera render\"")
        .nth(1)
        .and_then(|s| s.split(".SS ").next())
        .unwrap();
    for o in long_options("render") {
        assert!(render.contains(&o), "{o} not in the render section");
    }
    for heading in [".SH \"OUTPUT FILES\"", ".SH LIMITS", ".SH \"EXIT STATUS\""] {
        assert!(page.contains(heading), "{heading}");
    }
    // groff, where installed, formats it without a warning.
    if let Ok(mut groff) = Command::new("groff")
        .args(["-man", "-Tutf8", "-ww", "-z"])
        .stdin(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
    {
        use std::io::Write;
        groff
            .stdin
            .take()
            .unwrap()
            .write_all(page.as_bytes())
            .unwrap();
        let done = groff.wait_with_output().unwrap();
        assert!(done.status.success());
        assert_eq!(crate::common::text(&done.stderr), "", "groff warns");
    }
}

/// A command's help is short, the same for `-h` and `--help`: its purpose in a
/// line, its options, and where the rest is. The rest, said once, is in
/// `tessera --help`.
#[test]
fn each_commands_help_is_short_and_says_where_the_rest_is() {
    let top = text(&run(&["--help"]).stdout);
    for c in commands() {
        let long = text(&run(&[&c, "--help"]).stdout);
        let short = text(&run(&[&c, "-h"]).stdout);
        assert_eq!(long, short, "{c}");
        let lines = long.lines().count();
        assert!(lines <= 26, "{c} --help has {lines} lines: {long}");
        let purpose = long.lines().next().unwrap();
        assert!(
            top.contains(&format!("  {c} ")) && top.contains(purpose),
            "{c}: {purpose:?}"
        );
        if c != "scenes" {
            assert!(
                long.contains("`tessera --help`") && long.contains("`tessera man`"),
                "{c}: {long}"
            );
            assert!(top.contains(&format!("  {c}: ")), "{c} in detail: {top}");
        }
    }
}
