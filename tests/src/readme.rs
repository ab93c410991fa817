//! Figures read from a README (the examples' sizes, which tests check against the
//! linked ELF and the firmware's output).

/// The number at the start of `text` (after spaces): digits and thousands
/// commas (`218,688` -> 218688).
#[must_use]
pub fn number(text: &str) -> Option<u64> {
    let digits: String = text
        .trim_start()
        .chars()
        .take_while(|c| c.is_ascii_digit() || *c == ',')
        .filter(char::is_ascii_digit)
        .collect();
    digits.parse().ok()
}

/// The figure in the table row whose first cell is `` `key` ``: the number
/// starting its second cell (`` | `.text` | 218,688 | ... ``).
#[must_use]
pub fn table_figure(readme: &str, key: &str) -> Option<u64> {
    table_row(readme, key)?.get(1).and_then(|c| number(c))
}

/// The cells of the table row whose first cell is `` `key` ``, the first
/// included, each trimmed.
#[must_use]
pub fn table_row<'a>(readme: &'a str, key: &str) -> Option<Vec<&'a str>> {
    let row = format!("| `{key}` |");
    let line = readme.lines().find(|l| l.starts_with(&row))?;
    let inner = line.trim().strip_prefix('|')?.strip_suffix('|')?;
    Some(inner.split('|').map(str::trim).collect())
}

/// The figures of the table row that starts with `start`: the number starting
/// each cell after the first (a cell without one: `None` for the row).
#[must_use]
pub fn row_figures(readme: &str, start: &str) -> Option<Vec<u64>> {
    let line = readme.lines().find(|l| l.starts_with(start))?;
    let inner = line.trim().strip_prefix('|')?.strip_suffix('|')?;
    inner.split('|').skip(1).map(number).collect()
}

/// The four figures of an llvm-size row (text, data, bss, flash) the README
/// states for a build, against the truth, each as `(what, said, truth)`.
#[must_use]
pub fn llvm_size_row(
    readme: &str,
    start: &str,
    truth: [u64; 4],
) -> [(&'static str, Option<u64>, u64); 4] {
    let row = row_figures(readme, start);
    let what = ["text", "data", "bss", "flash"];
    core::array::from_fn(|i| {
        (
            what[i],
            row.as_ref().and_then(|r| r.get(i).copied()),
            truth[i],
        )
    })
}

/// The figure right after `label`.
#[must_use]
pub fn figure_after(readme: &str, label: &str) -> Option<u64> {
    let at = readme.find(label)? + label.len();
    number(&readme[at..])
}

/// Whether a README's figure is within `percent` % of the truth (a missing
/// figure is not).
#[must_use]
pub fn within(said: Option<u64>, truth: u64, percent: u64) -> bool {
    said.is_some_and(|s| s.abs_diff(truth) * 100 <= truth * percent)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_are_read_from_tables_and_text() {
        let readme = "a\n| `.text` | 218,688 | flash |\n| `x.toml` | 1 | 2,345 | n/a |\n\
                      - **Flash**: 214,000 bytes\n";
        assert_eq!(table_figure(readme, ".text"), Some(218_688));
        assert_eq!(
            table_row(readme, "x.toml"),
            Some(vec!["`x.toml`", "1", "2,345", "n/a"])
        );
        assert_eq!(table_figure(readme, ".data"), None);
        assert_eq!(figure_after(readme, "- **Flash**: "), Some(214_000));
        assert_eq!(number(" n/a"), None);
        assert!(within(Some(101), 100, 1) && !within(Some(102), 100, 1));
        assert!(!within(None, 100, 1));
    }
}
