//! The pre-scan of a scene file's text, before the TOML parser sees it: in one
//! pass and constant memory, it bounds what the parser's memory and recursion
//! depend on (nesting, key parts, list lengths).

use super::{MAX_KEY_PARTS, MAX_NESTING};
use crate::desc::{LISTS, too_many};

/// What the [`prescan`] refuses: at `byte`, about `item` when it is an item too
/// many (else a nesting problem), and why.
#[derive(Debug, PartialEq)]
pub(super) struct Refusal {
    pub(super) byte: usize,
    pub(super) item: Option<String>,
    pub(super) message: String,
}

/// Scans the text before the TOML parser does, in one pass and constant memory,
/// skipping strings and comments: refuses arrays and inline tables nested deeper
/// than [`MAX_NESTING`] (at the first bracket too deep), keys and table headers of
/// more than [`MAX_KEY_PARTS`] parts (at the dot before the first part too many),
/// and the first item beyond
/// a list's capacity, counting `[[sphere]]` headers and the inline tables of a
/// top-level `sphere = [...]` (at the item; a list the scan does not recognise,
/// such as a key with escapes, is still counted after parsing, before any item is
/// converted). Malformed TOML is left for the parser to report, but a bracket the
/// parser could nest is always counted.
pub(super) fn prescan(text: &str) -> Result<(), Refusal> {
    let mut scan = Scan {
        text,
        stack: Vec::with_capacity(MAX_NESTING),
        counts: [0; LISTS.len()],
        line_start: true,
        root: true,
        key_start: None,
        key_dots: None,
        pending: None,
        open_list: None,
    };
    let mut i = 0;
    while i < text.len() {
        i = scan.step(i)?;
    }
    Ok(())
}

/// Where the [`prescan`] is in the structure of the text.
struct Scan<'t> {
    text: &'t str,
    /// The open brackets, innermost last (at most [`MAX_NESTING`]).
    stack: Vec<u8>,
    /// The items seen of each list of [`LISTS`].
    counts: [usize; LISTS.len()],
    /// Only spaces so far on this line, outside brackets: a key or a header may
    /// start.
    line_start: bool,
    /// No `[table]` header yet: keys are top-level.
    root: bool,
    /// Where the top-level key being read starts.
    key_start: Option<usize>,
    /// In a key (top-level or of an inline table, before its `=`): the dots
    /// seen so far.
    key_dots: Option<usize>,
    /// The list named by the key just before `=`, until its value starts.
    pending: Option<usize>,
    /// The list whose top-level array is open (its items are at depth 2).
    open_list: Option<usize>,
}

impl Scan<'_> {
    /// Scans the byte at `i` (with a header, a string or a comment starting there,
    /// all of it); returns where to go on.
    fn step(&mut self, i: usize) -> Result<usize, Refusal> {
        let b = self.text.as_bytes();
        let c = b[i];
        let top = self.stack.is_empty();
        match c {
            b'\n' => {
                if top {
                    self.line_start = true;
                    self.key_start = None;
                    self.key_dots = None;
                    self.pending = None;
                }
                return Ok(i + 1);
            }
            b' ' | b'\t' | b'\r' => return Ok(i + 1),
            b'#' => {
                let end = b[i..].iter().position(|&x| x == b'\n');
                return Ok(end.map_or(b.len(), |n| i + n));
            }
            _ => {}
        }
        if top && self.line_start && c == b'[' {
            // Counted also in a header that is malformed: the parser may still
            // read its key.
            header_parts(b, i)?;
        }
        if top
            && self.line_start
            && c == b'['
            && let Some((name, end)) = header(b, i)
        {
            self.root = false;
            if b[i + 1] == b'['
                && let Some(list) = list_named(&self.text[name])
            {
                self.count(list, i)?;
            }
            self.line_start = false;
            return Ok(end);
        }
        if top && self.line_start {
            self.key_start = Some(i);
            self.key_dots = Some(0);
        }
        self.line_start = false;
        match c {
            b'"' | b'\'' => {
                self.pending = None;
                return Ok(skip_string(b, i));
            }
            b'.' if self.key_dots.is_some() => {
                let dots = self.key_dots.unwrap_or(0) + 1;
                too_many_parts(dots, i)?;
                self.key_dots = Some(dots);
            }
            b'=' if top => {
                self.key_dots = None;
                let key = self.key_start.take().filter(|_| self.root);
                self.pending = key.and_then(|k| list_named(&self.text[k..i]));
            }
            b'[' | b'{' => {
                self.open(c, i)?;
                self.key_dots = (c == b'{').then_some(0);
            }
            b']' | b'}' => {
                self.close(c);
                self.key_dots = None;
            }
            // A key of an inline table follows its `{` or a `,`.
            b',' => {
                self.pending = None;
                self.key_dots = (self.stack.last() == Some(&b'{')).then_some(0);
            }
            b'=' => {
                self.pending = None;
                self.key_dots = None;
            }
            _ => self.pending = None,
        }
        Ok(i + 1)
    }

    /// The bracket `c` (`[` or `{`) at `i` opens: an item of an open list when it
    /// is an inline table in the list's array; refused one level too deep.
    fn open(&mut self, c: u8, i: usize) -> Result<(), Refusal> {
        if c == b'[' && self.stack.is_empty() {
            self.open_list = self.pending;
        } else if c == b'{'
            && self.stack.len() == 1
            && let Some(list) = self.open_list
        {
            self.count(list, i)?;
        }
        self.pending = None;
        if self.stack.len() == MAX_NESTING {
            return Err(Refusal {
                byte: i,
                item: None,
                message: format!("arrays and inline tables nested more than {MAX_NESTING} deep"),
            });
        }
        self.stack.push(c);
        Ok(())
    }

    /// The bracket `c` (`]` or `}`) closes the innermost one if it matches.
    fn close(&mut self, c: u8) {
        let opener = if c == b']' { b'[' } else { b'{' };
        if self.stack.last() == Some(&opener) {
            self.stack.pop();
        }
        if self.stack.is_empty() {
            self.open_list = None;
        }
    }

    /// One more item of list `list` (an index of [`LISTS`]) at byte `byte`;
    /// refused beyond the list's capacity.
    fn count(&mut self, list: usize, byte: usize) -> Result<(), Refusal> {
        let (kind, capacity, name) = LISTS[list];
        self.counts[list] += 1;
        if self.counts[list] > capacity {
            return Err(Refusal {
                byte,
                item: Some(format!("{kind} {}", self.counts[list])),
                message: too_many(name, capacity),
            });
        }
        Ok(())
    }
}

/// Refuses the header starting at `b[i] == b'['` (first on its line, outside any
/// bracket) if its name has more than [`MAX_KEY_PARTS`] parts, at the dot before
/// the first part too many. The name ends at `]`, or at the end of the line or a
/// comment in a malformed header.
fn header_parts(b: &[u8], i: usize) -> Result<(), Refusal> {
    let mut j = i + 1;
    let mut dots = 0;
    while let Some(&c) = b.get(j) {
        match c {
            b'"' | b'\'' => j = skip_string(b, j),
            b']' | b'\n' | b'#' => break,
            b'.' => {
                dots += 1;
                too_many_parts(dots, j)?;
                j += 1;
            }
            _ => j += 1,
        }
    }
    Ok(())
}

/// Refuses a key whose `dots`-th dot, at `byte`, starts a part beyond
/// [`MAX_KEY_PARTS`].
fn too_many_parts(dots: usize, byte: usize) -> Result<(), Refusal> {
    if dots < MAX_KEY_PARTS {
        return Ok(());
    }
    Err(Refusal {
        byte,
        item: None,
        message: format!("a dotted key or table header has more than {MAX_KEY_PARTS} parts"),
    })
}

/// The header `[name]` or `[[name]]` starting at `b[i] == b'['` (outside any
/// bracket, first on its line): the byte range of `name` and the index after the
/// header, or `None` if it is not a well-formed header (then its brackets are
/// scanned as values are).
fn header(b: &[u8], i: usize) -> Option<(std::ops::Range<usize>, usize)> {
    let double = b.get(i + 1) == Some(&b'[');
    let start = i + 1 + usize::from(double);
    let mut j = start;
    while j < b.len() {
        match b[j] {
            b'"' | b'\'' => j = skip_string(b, j),
            b']' => break,
            b'[' | b'{' | b'\n' | b'#' => return None,
            _ => j += 1,
        }
    }
    if j >= b.len() || (double && b.get(j + 1) != Some(&b']')) {
        return None;
    }
    Some((start..j, j + 1 + usize::from(double)))
}

/// The index of the list (in [`LISTS`]) a key or header names: `sphere`,
/// `"sphere"` or `'sphere'`, with spaces around.
fn list_named(key: &str) -> Option<usize> {
    let key = key.trim_matches([' ', '\t']);
    let bare = ['"', '\'']
        .iter()
        .find_map(|&q| key.strip_prefix(q)?.strip_suffix(q))
        .unwrap_or(key);
    LISTS.iter().position(|&(kind, _, _)| kind == bare)
}

/// The index just after the string starting at `b[i]` (a quote): basic `"..."`
/// with `\` escapes, literal `'...'`, and their multi-line forms `"""..."""` and
/// `'''...'''` (whose closing run may hold up to two more quotes). A single-line
/// string ends at the end of its line, as the parser ends an unclosed one.
fn skip_string(b: &[u8], i: usize) -> usize {
    let q = b[i];
    let basic = q == b'"';
    let mut j = i + 1;
    if b.get(i + 1) == Some(&q) && b.get(i + 2) == Some(&q) {
        j = i + 3;
        while j < b.len() {
            if basic && b[j] == b'\\' {
                j += 2;
            } else if b[j] == q && b.get(j + 1) == Some(&q) && b.get(j + 2) == Some(&q) {
                j += 3;
                let mut extra = 0;
                while extra < 2 && b.get(j) == Some(&q) {
                    j += 1;
                    extra += 1;
                }
                return j;
            } else {
                j += 1;
            }
        }
        return b.len();
    }
    while j < b.len() {
        match b[j] {
            b'\n' => return j,
            b'\\' if basic && b.get(j + 1) != Some(&b'\n') => j += 2,
            x if x == q => return j + 1,
            _ => j += 1,
        }
    }
    b.len()
}
