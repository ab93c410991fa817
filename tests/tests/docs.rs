//! The docs' figures are the reports': every figure README.md and the hand-written
//! pages of `docs/` ([`PAGES`]) quote from a generated report (`docs/chip-cost.md`,
//! `docs/chip-profile.md`, `docs/trade.md`, `docs/extremes*.md`, `docs/dither.md`)
//! is read from both files and compared, so that a report regenerated without the
//! pages, or a figure edited by hand, fails here. Text only, no rendering.
//!
//! A quote is a pattern of a page's text with `{}` for its numbers, such as
//! ``"`render_tile` needs {} to {} bytes"``, paired with the page and the report's
//! figures. A page may round a figure (0.0118 for 0.01183), half up, to at least
//! two significant digits unless the rounding is exact, and must not differ
//! otherwise. Every occurrence of a pattern in its page is checked, and a pattern
//! the page no longer contains is a failure too: rewording or moving such a
//! sentence means updating it here.
//!
//! The core's doc comments (`///` and `//!` in `core/src/**/*.rs`, what rustdoc
//! shows) quote some of the same figures: `render_tile`'s stack, the tile buffers'
//! sizes, the cost of the sRGB encoding. They are checked the same way, file by
//! file, and each of their patterns must occur in some file.
//!
//! Besides figures: every relative link of README.md, ARCHITECTURE.md and the
//! pages of `docs/` leads to a file (and a `#heading` to a heading), the README
//! links every page of `docs/`, and its first section is the two commands, the
//! second of which is what CI (`.ci/run`) runs.

use std::collections::BTreeMap;
use std::fmt;
use std::path::PathBuf;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("tests/ has a parent")
        .to_path_buf()
}

fn read(rel: &str) -> String {
    let path = root().join(rel);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("cannot read {}: {e}", path.display()))
}

/// Every `docs/extremes*.md`, in name order, as one text.
fn extremes_reports() -> String {
    let mut names: Vec<PathBuf> = std::fs::read_dir(root().join("docs"))
        .expect("docs/ is readable")
        .map(|e| e.expect("docs/ entry").path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("extremes") && n.ends_with(".md"))
        })
        .collect();
    names.sort();
    assert!(!names.is_empty(), "no docs/extremes*.md");
    names
        .iter()
        .map(|p| std::fs::read_to_string(p).expect("extremes report is readable"))
        .collect::<Vec<_>>()
        .join("\n")
}

/// Whitespace runs (line breaks included) as one space: the README is wrapped.
fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// A decimal number as written: `digits x 10^exp`, with its sign.
#[derive(Clone, Debug)]
struct Dec {
    neg: bool,
    digits: Vec<u8>,
    exp: i32,
}

impl Dec {
    /// Reads `1,106`, `0.00355`, `-48`, `7.0e-4`, `1.00e5` (thousands commas ignored).
    fn parse(text: &str) -> Option<Dec> {
        let text = text.trim();
        let (neg, text) = match text.strip_prefix('-') {
            Some(rest) => (true, rest),
            None => (false, text),
        };
        let (mantissa, power) = match text.find(['e', 'E']) {
            Some(i) => (&text[..i], text[i + 1..].parse::<i32>().ok()?),
            None => (text, 0),
        };
        let mantissa = mantissa.replace(',', "");
        let (int, frac) = mantissa.split_once('.').unwrap_or((&mantissa, ""));
        if int.is_empty() && frac.is_empty() {
            return None;
        }
        let mut digits = Vec::new();
        for c in int.chars().chain(frac.chars()) {
            digits.push(u8::try_from(c.to_digit(10)?).ok()?);
        }
        Some(Dec {
            neg,
            digits,
            exp: power - i32::try_from(frac.len()).ok()?,
        })
    }

    /// An `f64` by its shortest decimal form (Rust's `Display` has no exponent).
    fn of(x: f64) -> Dec {
        Dec::parse(&x.to_string()).expect("a finite f64 prints as a decimal")
    }

    /// The same value with no leading and no trailing zeros (zero: no digits).
    fn normal(&self) -> Dec {
        let mut digits: Vec<u8> = self
            .digits
            .iter()
            .copied()
            .skip_while(|&d| d == 0)
            .collect();
        let mut exp = self.exp;
        while digits.last() == Some(&0) {
            digits.pop();
            exp += 1;
        }
        Dec {
            neg: self.neg && !digits.is_empty(),
            digits,
            exp,
        }
    }

    /// Rounded half up (away from zero) to a multiple of `10^exp`.
    fn round(&self, exp: i32) -> Dec {
        let n = self.normal();
        if n.exp >= exp {
            return n;
        }
        let drop = usize::try_from(exp - n.exp).expect("positive");
        if drop > n.digits.len() {
            return Dec {
                neg: false,
                digits: Vec::new(),
                exp,
            };
        }
        let keep = n.digits.len() - drop;
        let mut digits = n.digits[..keep].to_vec();
        if n.digits[keep] >= 5 {
            let mut i = digits.len();
            loop {
                if i == 0 {
                    digits.insert(0, 1);
                    break;
                }
                i -= 1;
                if digits[i] == 9 {
                    digits[i] = 0;
                } else {
                    digits[i] += 1;
                    break;
                }
            }
        }
        Dec {
            neg: n.neg,
            digits,
            exp,
        }
        .normal()
    }

    fn same(&self, other: &Dec) -> bool {
        let (a, b) = (self.normal(), other.normal());
        a.neg == b.neg && a.digits == b.digits && (a.digits.is_empty() || a.exp == b.exp)
    }

    /// Significant digits as written (`0.0118`: 3, `7.0e-4`: 2, `110`: 3).
    fn significant(&self) -> usize {
        self.digits.iter().skip_while(|&&d| d == 0).count()
    }

    fn to_f64(&self) -> f64 {
        let mut s = String::new();
        if self.neg {
            s.push('-');
        }
        s.extend(self.digits.iter().map(|d| char::from(b'0' + d)));
        if s.is_empty() || s == "-" {
            s.push('0');
        }
        format!("{s}e{}", self.exp)
            .parse()
            .expect("digits and an exponent")
    }
}

impl fmt::Display for Dec {
    /// Plain decimal notation, with the written number of decimals.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let decimals = usize::try_from(-self.exp.min(0)).expect("non-negative");
        write!(f, "{:.*}", decimals, self.to_f64())
    }
}

/// The number at the start of `text` (`-` only before a digit; `,` and `.` only
/// between digits, so that a sentence's comma or full stop ends it; an exponent
/// `e-4`), and the rest of `text`.
fn leading_number(text: &str) -> Option<(&str, &str)> {
    let b = text.as_bytes();
    let digit = |i: usize| b.get(i).is_some_and(u8::is_ascii_digit);
    let mut i = 0;
    if b.first() == Some(&b'-') && digit(1) {
        i = 1;
    }
    if !digit(i) {
        return None;
    }
    while digit(i) || (matches!(b.get(i), Some(b',' | b'.')) && digit(i + 1)) {
        i += 1;
    }
    if b.get(i) == Some(&b'e') {
        let sign = usize::from(matches!(b.get(i + 1), Some(b'-' | b'+')));
        if digit(i + 1 + sign) {
            i += 1 + sign;
            while digit(i) {
                i += 1;
            }
        }
    }
    Some((&text[..i], &text[i..]))
}

/// Every occurrence in `text` of `pattern` (literal text with `{}` for numbers), as
/// the numbers' texts; none is an error.
fn find(text: &str, pattern: &str) -> Result<Vec<Vec<String>>, String> {
    let parts: Vec<&str> = pattern.split("{}").collect();
    let first = parts[0];
    assert!(!first.is_empty(), "a pattern starts with text: {pattern}");
    let found: Vec<Vec<String>> = text
        .match_indices(first)
        .filter_map(|(at, _)| {
            let mut rest = &text[at + first.len()..];
            let mut numbers = Vec::new();
            for literal in &parts[1..] {
                let (number, after) = leading_number(rest)?;
                numbers.push(number.to_string());
                rest = after.strip_prefix(literal)?;
            }
            Some(numbers)
        })
        .collect();
    if found.is_empty() {
        return Err(format!("`{pattern}` is not in the text (any more)"));
    }
    Ok(found)
}

/// The numbers of the one occurrence of `pattern` in a report.
fn in_report(report: &str, name: &str, pattern: &str) -> Vec<Dec> {
    let found = find(&one_line(report), pattern).unwrap_or_else(|e| panic!("{name}: {e}"));
    assert_eq!(
        found.len(),
        1,
        "{name}: `{pattern}` occurs {} times",
        found.len()
    );
    found[0]
        .iter()
        .map(|n| Dec::parse(n).expect("a number"))
        .collect()
}

/// A Markdown table: its header cells and its rows of cells.
struct Table {
    name: String,
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

/// The cells of a table line; `\|` is a `|` inside a cell.
fn cells(line: &str) -> Vec<String> {
    let inner = line.trim().trim_start_matches('|');
    let inner = inner.strip_suffix('|').unwrap_or(inner);
    let mut out = vec![String::new()];
    let mut chars = inner.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\\' if chars.peek() == Some(&'|') => {
                out.last_mut().expect("a cell").push('|');
                chars.next();
            }
            '|' => out.push(String::new()),
            c => out.last_mut().expect("a cell").push(c),
        }
    }
    out.iter().map(|c| c.trim().to_string()).collect()
}

/// The first table after the first line of `text` that starts with `heading`.
fn table(text: &str, name: &str, heading: &str) -> Table {
    let mut lines = text.lines().skip_while(|l| !l.starts_with(heading));
    assert!(
        lines.next().is_some(),
        "{name}: no line starting with `{heading}`"
    );
    let mut rows = lines
        .skip_while(|l| !l.trim_start().starts_with('|'))
        .take_while(|l| l.trim_start().starts_with('|'))
        .map(cells);
    let header = rows
        .next()
        .unwrap_or_else(|| panic!("{name}: no table after `{heading}`"));
    let rows: Vec<Vec<String>> = rows
        .filter(|r| {
            !r.iter()
                .all(|c| !c.is_empty() && c.chars().all(|ch| matches!(ch, '-' | ':')))
        })
        .collect();
    assert!(
        !rows.is_empty(),
        "{name}: the table after `{heading}` is empty"
    );
    Table {
        name: format!("{name} ({heading})"),
        header,
        rows,
    }
}

impl Table {
    fn column(&self, name: &str) -> usize {
        self.header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("{}: no column `{name}` in {:?}", self.name, self.header))
    }

    /// The one row whose cells in the columns `key` are the given texts.
    fn row(&self, key: &[(&str, &str)]) -> &[String] {
        let columns: Vec<(usize, &str)> = key.iter().map(|&(c, v)| (self.column(c), v)).collect();
        let matching: Vec<&Vec<String>> = self
            .rows
            .iter()
            .filter(|r| {
                columns
                    .iter()
                    .all(|&(c, v)| r.get(c).is_some_and(|x| x == v))
            })
            .collect();
        assert_eq!(
            matching.len(),
            1,
            "{}: {} rows where {key:?}",
            self.name,
            matching.len()
        );
        matching[0]
    }

    /// The number that starts the cell `column` of the row `key`.
    fn figure(&self, key: &[(&str, &str)], column: &str) -> Dec {
        let cell = &self.row(key)[self.column(column)];
        number(cell)
            .unwrap_or_else(|| panic!("{}: {key:?} {column}: `{cell}` is not a number", self.name))
    }

    /// Every number of the column `column` (cells without one are skipped).
    fn all(&self, column: &str) -> Vec<Dec> {
        let c = self.column(column);
        self.rows
            .iter()
            .filter_map(|r| r.get(c).and_then(|x| number(x)))
            .collect()
    }
}

fn number(cell: &str) -> Option<Dec> {
    leading_number(cell.trim()).and_then(|(n, _)| Dec::parse(n))
}

fn largest(values: &[Dec]) -> Dec {
    values
        .iter()
        .max_by(|a, b| a.to_f64().total_cmp(&b.to_f64()))
        .expect("values")
        .clone()
}

fn smallest(values: &[Dec]) -> Dec {
    values
        .iter()
        .min_by(|a, b| a.to_f64().total_cmp(&b.to_f64()))
        .expect("values")
        .clone()
}

/// The hand-written pages whose figures are checked, by path from the root.
const PAGES: [&str; 5] = [
    "README.md",
    "docs/accuracy.md",
    "docs/bvh.md",
    "docs/firmware.md",
    "docs/limits.md",
];

/// The pages' texts as written, by path (what [`check`] reads; the tests change
/// one figure of one page and check again).
type Texts = BTreeMap<&'static str, String>;

fn pages() -> Texts {
    PAGES.iter().map(|&p| (p, read(p))).collect()
}

/// The pages and what is wrong with them.
struct Pages {
    /// Each page's text as one line (the pages are wrapped).
    lines: BTreeMap<&'static str, String>,
    failures: Vec<String>,
}

impl Pages {
    fn new(texts: &Texts) -> Pages {
        Pages {
            lines: texts.iter().map(|(&p, t)| (p, one_line(t))).collect(),
            failures: Vec::new(),
        }
    }

    /// Every occurrence of `pattern` in `page` quotes `truths`, each from `source`;
    /// `page` must contain it.
    fn quotes(&mut self, page: &str, pattern: &str, source: &str, truths: &[Dec]) {
        let line = self
            .lines
            .get(page)
            .unwrap_or_else(|| panic!("{page} is not one of the checked pages {PAGES:?}"));
        let found = match find(line, pattern) {
            Ok(found) => found,
            Err(e) => {
                self.failures
                    .push(format!("{page}: {e} (quoting {source})"));
                return;
            }
        };
        for numbers in found {
            compare(page, pattern, &numbers, source, truths, &mut self.failures);
        }
    }
}

impl Pages {
    /// `page` says `sentence` (as one line), and what it says of `source`'s
    /// figures (`holds`) is true.
    fn claims(&mut self, page: &str, sentence: &str, source: &str, holds: bool) {
        let line = self
            .lines
            .get(page)
            .unwrap_or_else(|| panic!("{page} is not one of the checked pages {PAGES:?}"));
        if !line.contains(sentence) {
            self.failures.push(format!(
                "{page}: no `{sentence}` (any more; a claim on {source})"
            ));
        } else if !holds {
            self.failures.push(format!(
                "{page}: `{sentence}` is no longer true of {source}'s figures"
            ));
        }
    }
}

/// Whether the numbers `written` in an occurrence of `pattern` in `place` are
/// `truths` from `source`, each as written or rounded (half up, to at least two
/// significant digits unless exact); what differs goes to `failures`.
fn compare(
    place: &str,
    pattern: &str,
    written: &[String],
    source: &str,
    truths: &[Dec],
    failures: &mut Vec<String>,
) {
    assert_eq!(
        written.len(),
        truths.len(),
        "`{pattern}`: one truth per {{}}"
    );
    for (written, truth) in written.iter().zip(truths) {
        let quoted = Dec::parse(written).expect("a number");
        let rounded = truth.round(quoted.exp);
        if !quoted.same(&rounded) {
            failures.push(format!(
                "{place} `{pattern}`: says {written}, {source} says {truth} (to the text's \
                 precision: {rounded})"
            ));
        } else if !quoted.same(truth) && quoted.significant() < 2 {
            failures.push(format!(
                "{place} `{pattern}`: {written} rounds {source}'s {truth} to fewer than two \
                 significant digits"
            ));
        }
    }
}

/// The least and the most stack `render_tile` needs over every scene, exact and
/// fast-math, from `docs/chip-cost.md`.
fn render_tile_stack(cost_text: &str) -> (Dec, Dec) {
    let stack = table(cost_text, "docs/chip-cost.md", "## Stack");
    let mut render_tile = stack.all("exact: render_tile");
    render_tile.extend(stack.all("fast-math: render_tile"));
    (smallest(&render_tile), largest(&render_tile))
}

/// What is wrong with the figures the pages (`texts`, from [`pages`]) quote from
/// the generated reports.
fn check(texts: &Texts) -> Vec<String> {
    let mut pages = Pages::new(texts);
    check_chip(&mut pages);
    check_trade(&mut pages);
    check_extremes(&mut pages);
    check_dither(&mut pages);
    pages.failures
}

/// The figures of `docs/chip-cost.md` and `docs/chip-profile.md`: the README's
/// cost table and stack; the firmware page's cost table, flash, RAM, stack,
/// encoding and cycles per instruction; the teapot's on the BVH page.
fn check_chip(pages: &mut Pages) {
    let src = "docs/chip-cost.md";
    let cost_text = read(src);
    let cost = table(&cost_text, src, "## Instructions per pixel");
    let fw = "docs/firmware.md";
    let centre = |scene: &str, depth: &str| {
        cost.figure(
            &[("scene", scene), ("depth", depth), ("sampler", "centre")],
            "exact instr/px",
        )
    };
    // What the pages say of the instructions, in words that hold while the
    // figures move: hundreds for the chapter's scenes, thousands for glass and
    // the teapot, each further sample about as much again.
    let hundreds = [
        ("chapter-direct", "0"),
        ("chapter-reflect", "1"),
        ("interference", "0"),
    ];
    let thousands = [("showcase", "5"), ("teapot", "0")];
    let within = |(scene, depth): &(&str, &str), lo: f64, hi: f64| {
        let x = centre(scene, depth).to_f64();
        (lo..hi).contains(&x)
    };
    let few_hundred = hundreds.iter().all(|k| within(k, 100.0, 1000.0));
    let few_thousand = thousands.iter().all(|k| within(k, 1000.0, 10_000.0));
    for page in ["README.md", fw] {
        pages.claims(
            page,
            "a few hundred instructions a pixel for the chapter's scenes",
            src,
            few_hundred,
        );
    }
    pages.claims(
        "README.md",
        "a few thousand for glass at depth 5 and for the 1,088-face teapot",
        src,
        few_thousand,
    );
    pages.claims(
        fw,
        "a few thousand for the showcase's glass at depth 5 and for the teapot",
        src,
        few_thousand,
    );
    pages.claims(
        "docs/bvh.md",
        "it costs a few thousand instructions a pixel at 64x64",
        src,
        within(&("teapot", "0"), 1000.0, 10_000.0),
    );
    let again = hundreds.iter().chain(&thousands).all(|&(scene, depth)| {
        let key = [
            ("scene", scene),
            ("depth", depth),
            ("sampler", "stratified:4"),
        ];
        let ratio = cost.figure(&key, "exact instr/px").to_f64() / centre(scene, depth).to_f64();
        (12.0..17.0).contains(&ratio)
    });
    pages.claims(
        fw,
        "each further sample of a pixel costs about as much again",
        src,
        again,
    );
    let (_, high) = render_tile_stack(&cost_text);
    let under = high.to_f64() < 3.0 * 1024.0;
    pages.claims(
        "README.md",
        "`render_tile` needs under 3 KiB of stack",
        src,
        under,
    );
    pages.claims(fw, "`render_tile` needs under 3 KiB of stack", src, under);
    pages.claims(
        fw,
        "`render_tile` needs under 3 KiB of stack on the Cortex-M4F",
        src,
        under,
    );
    let budget = in_report(
        &cost_text,
        src,
        "mps2-an386.x`): {} KiB of flash, {} KiB of RAM",
    );
    pages.quotes(
        fw,
        "within a {} KiB flash / {} KiB RAM budget",
        src,
        &budget,
    );
    let encoding = table(&cost_text, src, "## The output encoding");
    let srgb_cost = encoding.all("srgb - linear");
    pages.quotes(
        fw,
        "that costs {} to {} instructions a pixel over writing the linear value",
        src,
        &[smallest(&srgb_cost), largest(&srgb_cost)],
    );
    let buffers = in_report(&cost_text, src, "32x32: {} + {} + {} bytes)");
    pages.quotes(fw, "(8x8: {} B, 16x16: {} B, 32x32: {} B)", src, &buffers);
}

/// The figures of `docs/trade.md` on the accuracy page: the default scene
/// (chapter-reflect) and the interference screen.
fn check_trade(pages: &mut Pages) {
    let page = "docs/accuracy.md";
    let trade_text = read("docs/trade.md");
    let src = "docs/trade.md";
    let reflect = table(&trade_text, src, "### chapter-reflect");
    let interference = table(&trade_text, src, "### interference");
    let at = |t: &Table, sampler: &str, depth: &str, column: &str| {
        let key = [
            ("sampler", sampler),
            ("depth", depth),
            ("tile", "16"),
            ("backend", "exact"),
        ];
        t.figure(&key, column)
    };
    let flip = |sampler: &str, depth: &str| at(&reflect, sampler, depth, "mean FLIP");
    let chip = |sampler: &str| at(&reflect, sampler, "1", "chip instr/px");
    pages.quotes(
        page,
        "FLIP {} on the default scene against {} for centre",
        src,
        &[flip("corner", "1"), flip("centre", "1")],
    );
    pages.quotes(
        page,
        "random 16 ({} instr/px for FLIP {}, where stratified 4x4 gives {} for {})",
        src,
        &[
            chip("random:16"),
            flip("random:16", "1"),
            flip("stratified:4", "1"),
            chip("stratified:4"),
        ],
    );
    pages.quotes(
        page,
        "(default scene at depth 0: FLIP {} against {})",
        src,
        &[flip("centre", "0"), flip("centre", "1")],
    );
    pages.quotes(
        page,
        "pixels up to {} LSB off on the default scene; stratified 2x2, {} instr/px against \
         centre's {}, brings the worst to {} LSB and FLIP from {} to {})",
        src,
        &[
            at(&reflect, "centre", "1", "max diff"),
            chip("stratified:2"),
            chip("centre"),
            at(&reflect, "stratified:2", "1", "max diff"),
            flip("centre", "1"),
            flip("stratified:2", "1"),
        ],
    );
    // adaptive:4 against stratified:4 on the default scene, cycles on the chip.
    let cycles = |sampler: &str| at(&reflect, sampler, "1", "chip est. cycles/px");
    let share = Dec::of(100.0 * cycles("adaptive:4").to_f64() / cycles("stratified:4").to_f64());
    pages.quotes(
        page,
        "`adaptive:4` reaches FLIP {} for an estimated {} cycles/px on the chip, where \
         stratified 4x4 gives {} for {} ({} %",
        src,
        &[
            flip("adaptive:4", "1"),
            cycles("adaptive:4"),
            flip("stratified:4", "1"),
            cycles("stratified:4"),
            share,
        ],
    );
    // fast-math against exact, estimated cycles on the chip, over every setting of
    // every scene with both, and the largest change of mean FLIP.
    let (mut ratios, mut flips) = (Vec::new(), Vec::new());
    let direct = table(&trade_text, src, "### chapter-direct");
    let showcase = table(&trade_text, src, "### showcase");
    for t in [&direct, &reflect, &interference, &showcase] {
        let backend = t.column("backend");
        for row in t.rows.iter().filter(|r| r[backend] == "fast-math") {
            let key: Vec<(&str, &str)> = ["sampler", "depth", "tile"]
                .iter()
                .map(|&c| (c, row[t.column(c)].as_str()))
                .chain([("backend", "exact")])
                .collect();
            let figure = |column: &str| {
                let exact = t.figure(&key, column).to_f64();
                let fast = number(&row[t.column(column)]).expect("a figure");
                (fast.to_f64(), exact)
            };
            let (fast, exact) = figure("chip est. cycles/px");
            ratios.push(Dec::of(fast / exact));
            let (fast, exact) = figure("mean FLIP");
            flips.push(Dec::of((fast - exact).abs()));
        }
    }
    pages.quotes(
        page,
        "takes {} to {} times the exact build's estimated cycles per pixel on the chip",
        src,
        &[smallest(&ratios), largest(&ratios)],
    );
    pages.quotes(
        page,
        "moves no mean FLIP by more than {}",
        src,
        &[largest(&flips)],
    );
    let study = table(&trade_text, src, "## The interference study");
    let rmse = |column: &str| {
        study.figure(
            &[("footprint / fringe spacing", "1.6x"), ("column", column)],
            "RMSE vs truth",
        )
    };
    let fringes = |sampler: &str, column: &str| at(&interference, sampler, "0", column);
    pages.quotes(
        page,
        "it shows false fringes ({} LSB RMSE), 5 random rays (the chapter's example) lose the \
         pattern in noise ({} LSB), stratified 3x3 still misses by {} LSB, while the prefiltered \
         texture is exact in one evaluation ({} LSB; {} instr/px on the chip against {} for \
         stratified 4x4, which still has FLIP {} against prefiltered's {})",
        src,
        &[
            rmse("centre"),
            rmse("random:5"),
            rmse("stratified:3"),
            rmse("prefiltered"),
            fringes("prefiltered", "chip instr/px"),
            fringes("stratified:4", "chip instr/px"),
            fringes("stratified:4", "mean FLIP"),
            fringes("prefiltered", "mean FLIP"),
        ],
    );
}

/// The figures of `docs/extremes*.md` on the limits page.
fn check_extremes(pages: &mut Pages) {
    let page = "docs/limits.md";
    let extremes = extremes_reports();
    let src = "docs/extremes*.md";
    let far = table(&extremes, src, "## 1. Far spheres");
    pages.quotes(
        page,
        "a sphere up to {} radii away",
        src,
        &[largest(&far.all("distance / radius"))],
    );
    pages.quotes(
        page,
        "with the hit time within {} ulp",
        src,
        &[largest(&far.all("worst dt (ulp)"))],
    );
    let reintersection = table(&extremes, src, "## 2. Re-intersection");
    pages.quotes(
        page,
        "hit points up to {} object sizes from the origin never re-hit",
        src,
        &[largest(&reintersection.all("|p|"))],
    );
    let tiny = in_report(&extremes, src, "({} of the distance and more)");
    pages.quotes(
        page,
        "triangles down to {} of their distance are hit",
        src,
        &tiny,
    );
    let camera = table(&extremes, src, "## 6. Camera far away");
    pages.quotes(
        page,
        "a camera {} units out with near {} keeps ray directions within {} pixel",
        src,
        &[
            largest(&camera.all("|r_cam|")),
            smallest(&camera.all("near")),
            largest(&camera.all("worst direction error (px)")),
        ],
    );
    let scales = table(&extremes, src, "## 7. Scale invariance");
    let range = |scene: &str| {
        let row = scales.row(&[("scene", scene)]);
        let accepted = &row[scales.column("k accepted")];
        let identical = &row[scales.column("bit-identical for")];
        assert_eq!(
            accepted, identical,
            "{src}: {scene} is not the same bytes at every accepted k"
        );
        let [a, b] = [0, 1].map(|i| {
            accepted
                .trim_matches(|c| c == '[' || c == ']')
                .split(',')
                .nth(i)
                .and_then(number)
                .unwrap_or_else(|| panic!("{src}: {scene}: k accepted `{accepted}`"))
        });
        (a, b)
    };
    let (lo, hi) = range("chapter-direct");
    for scene in ["chapter-reflect", "showcase"] {
        let (l, h) = range(scene);
        if !l.same(&lo) || !h.same(&hi) {
            pages.failures.push(format!(
                "{page} groups chapter-direct, chapter-reflect and showcase, but {src} gives \
                 {scene} [{l}, {h}] against [{lo}, {hi}]"
            ));
        }
    }
    let (ilo, ihi) = range("interference");
    pages.quotes(
        page,
        "(from {} to {} for the chapter's two scenes and the showcase, from {} to {} for the \
         interference screen)",
        src,
        &[lo, hi, ilo, ihi],
    );
}

/// The figures of `docs/dither.md` on the firmware page: the mean FLIP of the
/// panel without dithering and with bayer4.
fn check_dither(pages: &mut Pages) {
    let src = "docs/dither.md";
    let dither = table(&read(src), src, "# Dithering to a 16-bit panel");
    let flip = |scene: &str, column: &str| dither.figure(&[("scene", scene)], column);
    pages.quotes(
        "docs/firmware.md",
        "chapter-direct {} nearest, {} bayer4; showcase {} and {}; the teapot {} and {}.",
        src,
        &[
            flip("chapter-direct", "none"),
            flip("chapter-direct", "bayer4"),
            flip("showcase", "none"),
            flip("showcase", "bayer4"),
            flip("teapot", "none"),
            flip("teapot", "bayer4"),
        ],
    );
}

/// Every `.rs` file under `core/src`, in path order: its path from the root and
/// its doc comments (`///`, `//!`; not `////`) as one line.
fn core_docs() -> Vec<(String, String)> {
    fn walk(dir: &std::path::Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).expect("core/src is readable") {
            let path = entry.expect("a core/src entry").path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    let mut paths = Vec::new();
    walk(&root().join("core").join("src"), &mut paths);
    paths.sort();
    assert!(paths.len() > 10, "core/src: {paths:?}");
    paths
        .iter()
        .map(|path| {
            let source = std::fs::read_to_string(path).expect("a core source is readable");
            let docs: Vec<&str> = source
                .lines()
                .filter_map(|line| {
                    let line = line.trim_start();
                    let doc = line
                        .strip_prefix("///")
                        .or_else(|| line.strip_prefix("//!"))?;
                    (!line.starts_with("////")).then_some(doc)
                })
                .collect();
            let name = path
                .strip_prefix(root())
                .expect("under the root")
                .display()
                .to_string();
            (name, one_line(&docs.join("\n")))
        })
        .collect()
}

/// What is wrong with the figures the core's doc comments (`files`, from
/// [`core_docs`]) quote from the reports.
fn check_rustdoc(files: &[(String, String)]) -> Vec<String> {
    let src = "docs/chip-cost.md";
    let cost_text = read(src);
    let (_, high) = render_tile_stack(&cost_text);
    let buffers = in_report(&cost_text, src, "32x32: {} + {} + {} bytes)");
    let mut failures = Vec::new();
    let (file, stack) = (
        "core/src/tile/mod.rs",
        "`render_tile` needs under 3 KiB below its caller",
    );
    if !files
        .iter()
        .any(|(p, docs)| p == file && docs.contains(stack))
    {
        failures.push(format!("{file}: no doc comment says `{stack}` (any more)"));
    } else if high.to_f64() >= 3.0 * 1024.0 {
        failures.push(format!(
            "{file}: `{stack}` is no longer true of {src} ({high})"
        ));
    }
    let quotes: [(&str, Vec<Dec>); 5] = [
        ("| 8x8 | {} bytes |", vec![buffers[0].clone()]),
        ("| 16x16 | {} bytes |", vec![buffers[1].clone()]),
        ("| 32x32 | {} bytes |", vec![buffers[2].clone()]),
        (
            "A tile of 16x16 pixels is {} bytes",
            vec![buffers[1].clone()],
        ),
        ("a tile of 16x16 is {} bytes", vec![buffers[1].clone()]),
    ];
    for (pattern, truths) in &quotes {
        let mut quoted = false;
        for (path, docs) in files {
            if let Ok(found) = find(docs, pattern) {
                quoted = true;
                for numbers in found {
                    compare(path, pattern, &numbers, src, truths, &mut failures);
                }
            }
        }
        if !quoted {
            failures.push(format!(
                "core/src: no doc comment has `{pattern}` (any more; quoting {src})"
            ));
        }
    }
    failures
}

#[test]
fn rustdoc_figures_are_the_reports() {
    let failures = check_rustdoc(&core_docs());
    assert!(
        failures.is_empty(),
        "{} figure(s) of the core's doc comments differ from the reports (update the doc \
         comment, or tests/tests/docs.rs if a sentence was reworded):\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The check of the doc comments is not vacuous either.
#[test]
fn a_wrong_rustdoc_figure_fails() {
    let files = core_docs();
    assert_eq!(check_rustdoc(&files), Vec::<String>::new());
    for (file, right, wrong, figure) in [
        // The claim on the stack reworded: it is gone.
        (
            "core/src/tile/mod.rs",
            "needs under 3 KiB",
            "needs under 2 KiB",
            "under 3 KiB",
        ),
        (
            "core/src/tile/mod.rs",
            "| 16x16 | 776 bytes",
            "| 16x16 | 768 bytes",
            "768",
        ),
        (
            "core/src/lib.rs",
            "pixels is 776 bytes",
            "pixels is 768 bytes",
            "768",
        ),
        (
            "core/src/display.rs",
            "16x16 is 776 bytes",
            "16x16 is 768 bytes",
            "768",
        ),
    ] {
        let mut changed = files.clone();
        let (_, docs) = changed
            .iter_mut()
            .find(|(path, _)| path == file)
            .unwrap_or_else(|| panic!("no {file}"));
        assert!(
            docs.contains(right),
            "{file}'s doc comments no longer contain `{right}`: update this test"
        );
        *docs = docs.replacen(right, wrong, 1);
        let failures = check_rustdoc(&changed);
        assert!(
            failures
                .iter()
                .any(|f| f.contains(file) && f.contains(figure)),
            "`{wrong}` for `{right}` in {file} was not caught as {figure}: {failures:?}"
        );
    }
}

#[test]
fn page_figures_are_the_reports() {
    let failures = check(&pages());
    assert!(
        failures.is_empty(),
        "{} figure(s) of the pages differ from the reports (docs/chip-cost.md and the other \
         reports are generated: update the page, or tests/tests/docs.rs if a sentence was \
         reworded or moved):\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The check is not vacuous: a wrong figure anywhere it looks is caught, and so is
/// a quoted sentence that is gone.
#[test]
fn a_wrong_figure_fails() {
    let texts = pages();
    // The controls start from pages that pass, so each failure below is the one
    // figure changed, named in the message with its page.
    assert_eq!(check(&texts), Vec::<String>::new());
    for (page, right, wrong, figure) in [
        // A claim on the chip's figures reworded: it is gone.
        (
            "README.md",
            "a few hundred instructions",
            "a few dozen instructions",
            "a few hundred instructions",
        ),
        (
            "docs/firmware.md",
            "needs under 3 KiB of stack on the",
            "needs under 2 KiB of stack on the",
            "under 3 KiB of stack on the",
        ),
        (
            "docs/bvh.md",
            "it costs a few thousand",
            "it costs a few hundred",
            "a few thousand",
        ),
        (
            "docs/firmware.md",
            "costs 7 to 9 instructions",
            "costs 7 to 12 instructions",
            "12",
        ),
        (
            "docs/firmware.md",
            "0.0178 bayer4",
            "0.0187 bayer4",
            "0.0187",
        ),
        ("docs/limits.md", "within 2.66 ulp", "within 2.5 ulp", "2.5"),
        (
            "docs/limits.md",
            "(from -48 to 53",
            "(from -47 to 53",
            "-47",
        ),
        (
            "docs/accuracy.md",
            "FLIP 0.045 on the default",
            "FLIP 0.04 on the default",
            "0.04",
        ),
        (
            "docs/accuracy.md",
            "(0.00 LSB; 943",
            "(0.00 LSB; 966",
            "966",
        ),
        (
            "docs/accuracy.md",
            "(36 % of the cost",
            "(35 % of the cost",
            "35",
        ),
        (
            "docs/accuracy.md",
            "0.94 to 0.97 times",
            "0.90 to 0.97 times",
            "0.90",
        ),
        // A quoted sentence reworded: its pattern is gone.
        (
            "docs/accuracy.md",
            "moves no mean FLIP by more than",
            "changes no mean FLIP by more than",
            "moves no mean FLIP",
        ),
    ] {
        let text = &texts[page];
        assert!(
            text.contains(right),
            "{page} no longer contains `{right}`: update this test"
        );
        let mut changed = texts.clone();
        changed.insert(page, text.replacen(right, wrong, 1));
        let failures = check(&changed);
        assert!(
            failures
                .iter()
                .any(|f| f.starts_with(page) && f.contains(figure)),
            "`{wrong}` for `{right}` in {page} was not caught as {figure}: {failures:?}"
        );
    }
    // Rounding: half up, and at least two significant digits unless exact.
    let q = |s: &str| Dec::parse(s).unwrap();
    assert!(q("0.0036").same(&q("0.00355").round(-4)));
    assert!(q("0.044").same(&q("0.04366").round(-3)));
    assert!(q("1.3").same(&Dec::of(1328.0 / 1024.0).round(-1)));
    assert!(q("7.0e-4").same(&q("7.0e-4").round(q("7.0e-4").exp)));
    assert!(q("1e6").same(&q("1.00e6").round(6)));
    assert_eq!(q("0.04").significant(), 1);
}

/// The Markdown files whose links are checked, by path from the root: README.md,
/// ARCHITECTURE.md and every page of `docs/` (the generated reports too).
fn markdown_files() -> Vec<String> {
    let mut docs: Vec<String> = std::fs::read_dir(root().join("docs"))
        .expect("docs/ is readable")
        .map(|e| e.expect("docs/ entry").file_name())
        .filter_map(|n| n.to_str().map(str::to_string))
        .filter(|n| n.ends_with(".md"))
        .map(|n| format!("docs/{n}"))
        .collect();
    docs.sort();
    let mut files = vec!["README.md".to_string(), "ARCHITECTURE.md".to_string()];
    files.extend(docs);
    files
}

/// The lines of a Markdown text outside its fenced code blocks.
fn prose(text: &str) -> Vec<&str> {
    let mut fenced = false;
    text.lines()
        .filter(|line| {
            if line.trim_start().starts_with("```") {
                fenced = !fenced;
                return false;
            }
            !fenced
        })
        .collect()
}

/// The targets of the links and images of a Markdown text (`[text](target)`,
/// `![alt](target)`), outside code blocks and inline code.
fn links(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in prose(text) {
        // Inline code (between backticks) is not a link.
        let outside: String = line
            .split('`')
            .enumerate()
            .map(|(i, part)| if i % 2 == 0 { part } else { "" })
            .collect::<Vec<_>>()
            .join(" ");
        let mut rest = outside.as_str();
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(end) = after.find(')') else { break };
            out.push(after[..end].trim().to_string());
            rest = &after[end..];
        }
    }
    out
}

/// The anchors GitHub gives the headings of a Markdown text: lower case, spaces
/// as `-`, punctuation other than `-` and `_` dropped, `-1`, `-2` ... after a
/// repeated one.
fn anchors(text: &str) -> Vec<String> {
    let mut seen: Vec<String> = Vec::new();
    for line in prose(text) {
        let Some(heading) = line.strip_prefix('#') else {
            continue;
        };
        let heading = heading.trim_start_matches('#');
        if !heading.starts_with(' ') {
            continue;
        }
        let slug: String = heading
            .trim()
            .to_lowercase()
            .chars()
            .filter_map(|c| match c {
                ' ' => Some('-'),
                c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
                _ => None,
            })
            .collect();
        let repeats = seen.iter().filter(|s| **s == slug).count();
        let anchor = if repeats == 0 {
            slug.clone()
        } else {
            format!("{slug}-{repeats}")
        };
        seen.push(slug);
        if repeats > 0 {
            seen.push(anchor);
        }
    }
    seen
}

/// What is wrong with the relative links of `files` (paths from the root, and
/// their texts): a target that is no file or folder, or an anchor that is no
/// heading of the Markdown file it names (`file` itself for `#anchor`).
fn broken_links(files: &[(String, String)]) -> Vec<String> {
    let mut broken = Vec::new();
    for (file, text) in files {
        let dir = root().join(file).parent().expect("a folder").to_path_buf();
        for target in links(text) {
            if ["http://", "https://", "mailto:"]
                .iter()
                .any(|s| target.starts_with(s))
            {
                continue;
            }
            let (path, anchor) = target.split_once('#').unwrap_or((&target, ""));
            let linked = if path.is_empty() {
                root().join(file)
            } else {
                dir.join(path)
            };
            if !linked.exists() {
                broken.push(format!(
                    "{file}: `{target}`: {} does not exist",
                    linked.display()
                ));
                continue;
            }
            if !anchor.is_empty() && linked.extension().is_some_and(|e| e == "md") {
                let heads = if path.is_empty() {
                    anchors(text)
                } else {
                    anchors(&std::fs::read_to_string(&linked).expect("a readable page"))
                };
                if !heads.iter().any(|h| h == anchor) {
                    broken.push(format!(
                        "{file}: `{target}`: no heading of {} has the anchor `{anchor}` \
                         (it has {heads:?})",
                        linked.display()
                    ));
                }
            }
        }
    }
    broken
}

#[test]
fn relative_links_lead_to_files() {
    let files: Vec<(String, String)> = markdown_files()
        .into_iter()
        .map(|f| {
            let text = read(&f);
            (f, text)
        })
        .collect();
    assert!(files.len() > 10, "{:?}", files.iter().map(|f| &f.0));
    let broken = broken_links(&files);
    assert!(
        broken.is_empty(),
        "{} broken link(s):\n{}",
        broken.len(),
        broken.join("\n")
    );
    // Not vacuous: a wrong file and a wrong anchor in the README are caught, and
    // the anchors are GitHub's.
    let readme = read("README.md");
    assert!(links(&readme).len() > 10);
    for (right, wrong) in [
        ("(docs/cli.md)", "(docs/cli.txt)"),
        (
            "(docs/firmware.md#what-it-costs-on-a-cortex-m4f)",
            "(docs/firmware.md#what-it-costs)",
        ),
    ] {
        assert!(
            readme.contains(right),
            "README.md lacks `{right}`: update this test"
        );
        let changed = [("README.md".to_string(), readme.replacen(right, wrong, 1))];
        let broken = broken_links(&changed);
        let target = wrong.trim_matches(|c| c == '(' || c == ')');
        assert!(
            broken.len() == 1 && broken[0].contains(target),
            "`{wrong}` was not caught: {broken:?}"
        );
    }
    assert_eq!(
        anchors("# A\n## The scene, baked in `build.rs`\n```sh\n# not a heading\n```\n## A"),
        ["a", "the-scene-baked-in-buildrs", "a", "a-1"]
    );
}

/// A newcomer reaches every page of `docs/` from the README.
#[test]
fn every_docs_page_is_linked_from_the_readme() {
    let linked: Vec<String> = links(&read("README.md"))
        .into_iter()
        .map(|t| t.split('#').next().unwrap_or_default().to_string())
        .collect();
    let missing: Vec<String> = markdown_files()
        .into_iter()
        .filter(|f| f.starts_with("docs/") && !linked.contains(f))
        .collect();
    assert!(missing.is_empty(), "README.md links to none of {missing:?}");
}

/// The README's first section is the two commands, the set-up and the test
/// command, and the test command is the one CI runs.
#[test]
fn the_two_commands_come_first() {
    let readme = read("README.md");
    let first = readme
        .lines()
        .find(|l| l.starts_with("## "))
        .expect("README.md has sections");
    assert_eq!(first, "## Two commands", "README.md's first section");
    let commands: Vec<&str> = readme
        .lines()
        .skip_while(|l| *l != first)
        .skip_while(|l| !l.starts_with("```"))
        .skip(1)
        .take_while(|l| !l.starts_with("```"))
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.split('#').next().unwrap_or_default().trim())
        .collect();
    assert_eq!(
        commands,
        ["cargo run --release", "bash tests/run-all.sh"],
        "README.md's two commands"
    );
    let ci = read(".ci/run");
    let run: Vec<&str> = ci
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#'))
        .filter(|l| l.contains("run-all.sh"))
        .collect();
    assert_eq!(
        run,
        ["exec bash tests/run-all.sh"],
        ".ci/run runs the README's test command"
    );
}

/// The minimum supported Rust the pages name is `Cargo.toml`'s `rust-version`,
/// which the test command installs and checks.
#[test]
fn the_minimum_rust_is_cargo_tomls() {
    let manifest = read("Cargo.toml");
    let msrv = manifest
        .lines()
        .find_map(|l| l.strip_prefix("rust-version = \""))
        .and_then(|v| v.strip_suffix('"'))
        .expect("Cargo.toml has a rust-version");
    for (page, quote) in [
        ("README.md", format!("Rust {msrv} first)")),
        (
            "README.md",
            format!("Rust {msrv}, the minimum supported version"),
        ),
        ("ARCHITECTURE.md", format!("rust-version {msrv}")),
        ("docs/contributing.md", format!("`Cargo.toml`, {msrv}:")),
        ("docs/contributing.md", format!("`cargo +{msrv} check`")),
    ] {
        let text = one_line(&read(page));
        assert!(
            text.contains(&quote),
            "{page} should say `{quote}` (Cargo.toml's rust-version {msrv})"
        );
    }
}
