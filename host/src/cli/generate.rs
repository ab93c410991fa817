//! `tessera completions SHELL` and `tessera man`: made from the command line's
//! own definitions (clap's `clap_complete` and `clap_mangen`), so they list every
//! command and option there is, and written to stdout.
//!
//! The manual page is one page, `tessera(1)`: the command's synopsis and options,
//! then a section per command (its synopsis, what it does in detail, its
//! options), then what the commands share ([`super::GENERAL`]): the long
//! explanations that `tessera --help` ends with.

use super::{COMMAND_DETAILS, Cli, Error, GENERAL};
use clap::{Args, CommandFactory};
use clap_complete::Shell;
use clap_mangen::Man;
use clap_mangen::roff::{Roff, roman};
use std::io::Write;

#[derive(Args)]
pub struct CompletionsArgs {
    /// The shell the script is for
    #[arg(value_enum)]
    shell: Shell,
}

/// Writes the completion script of `args.shell` to stdout.
pub fn completions(args: &CompletionsArgs) -> Result<(), Error> {
    let mut script = Vec::new();
    clap_complete::generate(args.shell, &mut Cli::command(), "tessera", &mut script);
    stdout(&script)
}

/// Writes the manual page to stdout.
pub fn man() -> Result<(), Error> {
    stdout(page().as_bytes())
}

/// `bytes` to stdout, an error (a closed pipe) reported, not a panic.
fn stdout(bytes: &[u8]) -> Result<(), Error> {
    let mut out = std::io::stdout().lock();
    out.write_all(bytes)
        .and_then(|()| out.flush())
        .map_err(Error::Stdout)
}

/// The manual page, roff: `.TH` first.
fn page() -> String {
    let mut cmd = Cli::command().disable_help_subcommand(true);
    cmd.build();
    let top = Man::new(cmd.clone());
    // Each of clap_mangen's sections comes with the preamble that defines the
    // apostrophe string (what an empty document renders to): kept once, after
    // the title.
    let preamble = Roff::new().render();
    let section = |f: &dyn Fn(&mut Vec<u8>) -> std::io::Result<()>| {
        let mut buf = Vec::new();
        // Writing to a Vec does not fail.
        let _ = f(&mut buf);
        let text = String::from_utf8_lossy(&buf).into_owned();
        match text.strip_prefix(&preamble) {
            Some(rest) => rest.to_string(),
            None => text,
        }
    };
    // A section's body: without its `.SH` heading line.
    let body = |text: String| match text.split_once('\n') {
        Some((first, rest)) if first.starts_with(".SH") => rest.to_string(),
        _ => text,
    };
    let roff = |r: &Roff| {
        let text = r.render();
        text.strip_prefix(&preamble).unwrap_or(&text).to_string()
    };
    let mut page = section(&|w| top.render_title(w));
    page.push_str(&preamble);
    page.push_str(&section(&|w| top.render_name_section(w)));
    page.push_str(&section(&|w| top.render_synopsis_section(w)));
    page.push_str(&section(&|w| top.render_description_section(w)));
    page.push_str(&section(&|w| top.render_options_section(w)));
    page.push_str(&roff(Roff::new().control("SH", ["COMMANDS"])));
    for sub in cmd.get_subcommands() {
        let name = sub.get_name();
        let man = Man::new(sub.clone());
        let mut head = Roff::new();
        head.control("SS", [format!("tessera {name}").as_str()]);
        page.push_str(&roff(&head));
        page.push_str(&body(section(&|w| man.render_synopsis_section(w))));
        let detail = COMMAND_DETAILS.iter().find(|(n, _)| *n == name);
        let text = match detail {
            Some((_, text)) => capitalised(text),
            None => sub.get_about().map(|a| a.to_string()).unwrap_or_default(),
        };
        let mut about = Roff::new();
        about.control("PP", []).text([roman(text)]);
        page.push_str(&roff(&about));
        if sub.get_arguments().any(|a| !a.is_hide_set()) {
            page.push_str(&body(section(&|w| man.render_options_section(w))));
        }
    }
    for (heading, text) in GENERAL {
        let mut r = Roff::new();
        r.control("SH", [heading.to_uppercase().as_str()])
            .text([roman(capitalised(text))]);
        page.push_str(&roff(&r));
    }
    page.push_str(&section(&|w| top.render_version_section(w)));
    page
}

/// `text` with its first letter in capitals (a sentence of its own in the page,
/// after `Heading: ` in `--help`).
fn capitalised(text: &str) -> String {
    let mut chars = text.chars();
    match chars.next() {
        Some(c) => c.to_uppercase().chain(chars).collect(),
        None => String::new(),
    }
}
