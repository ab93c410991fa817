//! The core's modules form layers: each uses (`crate::module`) only modules below
//! it, so the graph of those uses has no cycle. This test reads `core/src`, builds
//! the graph of the top-level modules (test modules and comments left out: a test
//! may use anything, a doc link is not a dependency) and fails on a cycle, naming
//! its modules; ARCHITECTURE.md lists the layers it finds.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::Path;

/// The top-level module a file of `core/src` belongs to (`None` for lib.rs, the
/// root, which only declares and re-exports).
fn module_of(rel: &Path) -> Option<String> {
    let first = rel.components().next()?.as_os_str().to_str()?.to_owned();
    let name = first.strip_suffix(".rs").unwrap_or(&first).to_owned();
    (name != "lib").then_some(name)
}

/// `src` without its `#[cfg(test)]` modules (written last in each file, as
/// everywhere in the core, or in a file of their own: [`is_test_module`]) and
/// without comments.
fn code(src: &str) -> String {
    let body = match src.find("#[cfg(test)]\nmod ") {
        Some(i) => &src[..i],
        None => src,
    };
    body.lines()
        .map(|l| match l.find("//") {
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The module named first in a path (`vec` of `vec::Vec3`), if it starts
/// with one: a lower-case segment followed by `::`, `;`, `,`, `}` or the end
/// (`Name` alone is a re-export of the root, `name!` a macro of the root).
fn first_module(path: &str) -> Option<String> {
    let path = path.trim_start();
    let name: String = path
        .chars()
        .take_while(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || *c == '_')
        .collect();
    let after = path[name.len()..].trim_start();
    let ends = after.is_empty() || after.starts_with([':', ';', ',', '}']);
    (!name.is_empty() && ends).then_some(name)
}

/// The items of a brace group `{a, b::{c, d}, E}` that starts `text`, split at
/// its top-level commas (`None` when the group is not closed).
fn group_items(text: &str) -> Option<Vec<&str>> {
    let mut depth = 0;
    let mut start = 1;
    let mut items = Vec::new();
    for (i, c) in text.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    items.push(&text[start..i]);
                    return Some(items);
                }
            }
            ',' if depth == 1 => {
                items.push(&text[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    None
}

/// The modules `code` names as `crate::<module>`, also inside a group
/// (`crate::{vec::Vec3, error::{Error, List}}`).
fn uses(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    for (i, _) in code.match_indices("crate::") {
        let rest = &code[i + "crate::".len()..];
        if rest.starts_with('{') {
            for item in group_items(rest).unwrap_or_default() {
                out.extend(first_module(item));
            }
        } else {
            out.extend(first_module(rest));
        }
    }
    out
}

/// True when the file at `path` is a test module of its own, declared
/// `#[cfg(test)] mod <name>;` by the `mod.rs` of its folder.
fn is_test_module(path: &Path) -> bool {
    let (Some(dir), Some(stem)) = (path.parent(), path.file_stem().and_then(|s| s.to_str())) else {
        return false;
    };
    fs::read_to_string(dir.join("mod.rs"))
        .is_ok_and(|m| m.contains(&format!("#[cfg(test)]\nmod {stem};")))
}

fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut stack = vec![src.clone()];
    while let Some(dir) = stack.pop() {
        for entry in fs::read_dir(&dir).expect("core/src is readable") {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                stack.push(path);
                continue;
            }
            if path.extension().is_none_or(|e| e != "rs") {
                continue;
            }
            let rel = path.strip_prefix(&src).expect("under core/src");
            let Some(module) = module_of(rel) else {
                continue;
            };
            if is_test_module(&path) {
                continue;
            }
            let text = fs::read_to_string(&path).expect("a readable source file");
            let deps = graph.entry(module.clone()).or_default();
            deps.extend(uses(&code(&text)).into_iter().filter(|d| *d != module));
        }
    }
    // Only edges between the core's own modules.
    let names: BTreeSet<String> = graph.keys().cloned().collect();
    for deps in graph.values_mut() {
        deps.retain(|d| names.contains(d));
    }
    graph
}

/// The layers of `graph` from the bottom (modules that use none), or the modules
/// left in (or above) a cycle when no further layer can be formed.
fn layers(graph: &BTreeMap<String, BTreeSet<String>>) -> Result<Vec<Vec<String>>, Vec<String>> {
    let mut placed: BTreeSet<String> = BTreeSet::new();
    let mut out = Vec::new();
    while placed.len() < graph.len() {
        let layer: Vec<String> = graph
            .iter()
            .filter(|(m, deps)| !placed.contains(*m) && deps.iter().all(|d| placed.contains(d)))
            .map(|(m, _)| m.clone())
            .collect();
        if layer.is_empty() {
            return Err(graph
                .keys()
                .filter(|m| !placed.contains(*m))
                .cloned()
                .collect());
        }
        placed.extend(layer.iter().cloned());
        out.push(layer);
    }
    Ok(out)
}

#[test]
fn the_core_modules_use_only_modules_below_them() {
    let graph = graph();
    assert!(graph.len() > 20, "read too few modules: {:?}", graph.keys());
    match layers(&graph) {
        Ok(layers) => {
            for (i, l) in layers.iter().enumerate() {
                println!("layer {i}: {}", l.join(", "));
            }
        }
        Err(stuck) => {
            let edges: Vec<String> = stuck
                .iter()
                .map(|m| {
                    let deps: Vec<&str> = graph[m]
                        .iter()
                        .filter(|d| stuck.contains(d))
                        .map(String::as_str)
                        .collect();
                    format!("{m} -> {}", deps.join(" "))
                })
                .collect();
            panic!(
                "the core's modules import each other in a circle:\n{}",
                edges.join("\n")
            );
        }
    }
}

/// The rows of ARCHITECTURE.md's table of the core's layers, from the bottom
/// up: the modules each names in its second column (`` `name` `` or
/// `` **`name`** ``; a file of a module's folder, `` `search/bvh` ``, is not a
/// module). `None` outside the repository (a packaged crate has no
/// ARCHITECTURE.md).
fn architecture_rows() -> Option<Vec<Vec<String>>> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../ARCHITECTURE.md");
    let text = fs::read_to_string(path).ok()?;
    let table = text.split("| layer | modules | what they hold |").nth(1)?;
    let rows = table
        .lines()
        .skip(2)
        .take_while(|l| l.starts_with('|'))
        .map(|l| {
            let modules = l.split('|').nth(2).unwrap_or("");
            modules
                .split('`')
                .skip(1)
                .step_by(2)
                .filter(|m| !m.contains('/'))
                .map(String::from)
                .collect()
        })
        .collect();
    Some(rows)
}

/// ARCHITECTURE.md's claim, checked: its table names every module of the core
/// once, and a module uses only modules of its own row or of the rows before
/// it (with no cycle, which the test above checks).
#[test]
fn the_architecture_table_holds_every_module_and_its_uses() {
    let graph = graph();
    let Some(rows) = architecture_rows() else {
        println!("no ARCHITECTURE.md beside the crate: the table is not checked");
        return;
    };
    let mut row_of = BTreeMap::new();
    let mut wrong = Vec::new();
    for (r, row) in rows.iter().enumerate() {
        for m in row {
            if row_of.insert(m.clone(), r).is_some() {
                wrong.push(format!("{m} is in two rows"));
            }
        }
    }
    for (m, deps) in &graph {
        let Some(&r) = row_of.get(m) else {
            wrong.push(format!("{m} is in no row"));
            continue;
        };
        for d in deps {
            if row_of.get(d).is_some_and(|&dr| dr > r) {
                wrong.push(format!(
                    "{m} (row {r}) uses {d}, of a row above it ({})",
                    row_of[d]
                ));
            }
        }
    }
    for m in row_of.keys() {
        if !graph.contains_key(m) {
            wrong.push(format!("{m} is in the table but not a module of core/src"));
        }
    }
    assert!(
        wrong.is_empty(),
        "ARCHITECTURE.md's table of layers:\n{}",
        wrong.join("\n")
    );
}

#[test]
fn the_graph_reader_sees_a_cycle() {
    // The check itself: two modules that use each other are refused, a chain is not.
    let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    g.insert("a".into(), ["b".to_string()].into());
    g.insert("b".into(), ["c".to_string()].into());
    g.insert("c".into(), BTreeSet::new());
    assert_eq!(layers(&g).map(|l| l.len()), Ok(3));
    g.get_mut("c").expect("c").insert("a".into());
    assert!(layers(&g).is_err());
    // What counts as a use: code, not comments or tests.
    let text = "use crate::vec::Vec3;\n// crate::shade::x\nfn f() { crate::math::sqrt(1.0); }\n\
                use crate::{color::Color, error::{Error, List}, Scene};\n\
                crate::capacities!(spheres: 1);\n\
                #[cfg(test)]\nmod tests { use crate::tile::Tile; }\n";
    let found = uses(&code(text));
    assert_eq!(
        found,
        ["color", "error", "math", "vec"].map(String::from).into()
    );
}
