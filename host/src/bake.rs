//! Baked scenes: a scene's triangles and meshes, with their BVHs, written out as
//! Rust `static` data (`tessera bake`), so that a firmware keeps them in flash and
//! spends no RAM on them. The firmware gives them to a view of the rest of its
//! scene (built in RAM as usual, with the same materials in the same order) with
//! [`tessera::SceneView::with_baked`] (the triangle list) and
//! [`tessera::SceneView::with_meshes`] (the meshes), which check them once.
//!
//! The generated file is plain Rust: `TRIANGLES` (the scene's triangles in its
//! order, each a `Primitive` of `Triangle::baked`) and `BVH` (a `BakedBvh` of the
//! `NODES` and `ORDER` the host builds for them, as [`tessera::Bvh::build`]
//! does); `MESHES` (each a `Mesh` of its `MESH{i}_VERTICES`, `_FACES`,
//! `_NORMALS` and BVH). Numbers are written in Rust's shortest form that reads
//! back to the same `f32`, so the baked scene is the host's bit for bit.

use crate::desc::{DescError, HostBvh, HostScene, SceneDesc};
use std::fmt::Write as _;
use tessera::BvhNode;

/// `s` as a Rust string literal (with its quotes) that reads back to `s` and
/// cannot leave its place in the generated file: one line of printable text,
/// whether it stands in a string literal or in a `//` comment. `"` and `\\` are
/// escaped; so is every control character (`\n`, `\r`, `\t`, `\0`, other C0, DEL
/// and C1 such as U+0085 as `\u{..}`), every whitespace but the space (U+2028
/// and U+2029 end a line for some readers), and the bidirectional-text controls
/// (U+061C, U+200E, U+200F, U+202A to U+202E, U+2066 to U+2069: the compiler's
/// deny-by-default lints `text_direction_codepoint_in_literal` and `_in_comment`
/// refuse the last two ranges). Any other non-ASCII character is written as
/// [`char::escape_debug`] writes it: as it is, or as `\u{..}` when it is not
/// printable or is a combining mark. Every escape used is a Rust string escape.
/// Every string of the input that bake writes goes through this function.
#[must_use]
pub fn rust_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            '\0' => out.push_str("\\0"),
            ' '..='~' => out.push(c),
            c if crate::text::must_escape(c) => {
                let _ = write!(out, "\\u{{{:x}}}", u32::from(c));
            }
            c => out.extend(c.escape_debug()),
        }
    }
    out.push('"');
    out
}

/// The keywords of Rust 2021 and 2024, strict and reserved: none can name a
/// crate or a module (`r#` aside).
const KEYWORDS: &[&str] = &[
    "as", "async", "await", "break", "const", "continue", "crate", "dyn", "else", "enum", "extern",
    "false", "fn", "for", "if", "impl", "in", "let", "loop", "match", "mod", "move", "mut", "pub",
    "ref", "return", "self", "Self", "static", "struct", "super", "trait", "true", "type",
    "unsafe", "use", "where", "while", // strict
    "abstract", "become", "box", "do", "final", "gen", "macro", "override", "priv", "try",
    "typeof", "unsized", "virtual", "yield", // reserved
];

/// Checks that `path` is what Rust accepts as the path of a `use` (the core
/// crate as the generated file names it, `use PATH::{...}`): segments joined by
/// `::`, with an optional leading `::`; `crate` and `self` only as the first
/// segment, `super` there or after `self` or `super` (none after a leading
/// `::`); every other segment an ASCII identifier that is neither a keyword
/// (strict or reserved, in Rust 2021 or 2024) nor `_`, or a raw identifier
/// `r#name` (not `r#crate`, `r#self`, `r#super`, `r#Self`). The error says which
/// segment is wrong and why, e.g. `"fn" is a Rust keyword, not a crate name`.
pub fn check_crate_path(path: &str) -> Result<(), String> {
    let ident = |w: &str| {
        let mut c = w.chars();
        w != "_"
            && c.next()
                .is_some_and(|f| f == '_' || f.is_ascii_alphabetic())
            && c.all(|x| x == '_' || x.is_ascii_alphanumeric())
    };
    let (global, rest) = match path.strip_prefix("::") {
        Some(rest) => (true, rest),
        None => (false, path),
    };
    let mut leading = true; // only `self` and `super` so far
    for (i, w) in rest.split("::").enumerate() {
        let what = if i == 0 {
            "a crate name"
        } else {
            "a module name"
        };
        if w.is_empty() {
            return Err(format!(
                "{path:?} has an empty segment: expected names joined by ::"
            ));
        }
        if let Some(raw) = w.strip_prefix("r#") {
            if matches!(raw, "crate" | "self" | "super" | "Self") {
                return Err(format!("{w:?} cannot be a raw identifier"));
            }
            if !ident(raw) {
                return Err(format!(
                    "{w:?} is not a raw identifier (r# and an identifier)"
                ));
            }
        } else if matches!(w, "crate" | "self") {
            if i > 0 || global {
                return Err(format!(
                    "{w:?} may only start a path (and not after a leading ::)"
                ));
            }
        } else if w == "super" {
            if global || !leading {
                return Err(format!(
                    "{w:?} may only start a path or follow self or super"
                ));
            }
        } else if KEYWORDS.contains(&w) {
            return Err(format!("{w:?} is a Rust keyword, not {what}"));
        } else if w == "_" {
            return Err(format!("\"_\" is a placeholder, not {what}"));
        } else if !ident(w) {
            return Err(format!(
                "{w:?} is not an identifier (ASCII letters, digits and _, not starting \
                 with a digit), not {what}"
            ));
        }
        leading = leading && matches!(w, "self" | "super");
    }
    Ok(())
}

/// `n` and the noun, singular for one (`1 plane`, `2 planes`).
fn count(n: usize, one: &str, many: &str) -> String {
    format!("{n} {}", if n == 1 { one } else { many })
}

/// `x` as a Rust `f32` literal that reads back to the same value.
fn lit(x: f32) -> String {
    let s = format!("{x:?}");
    if s.contains(['.', 'e', 'i', 'N']) {
        s
    } else {
        format!("{s}.0")
    }
}

fn vec3(v: [f32; 3]) -> String {
    format!("[{}, {}, {}]", lit(v[0]), lit(v[1]), lit(v[2]))
}

/// A baked hierarchy: `{name}NODES`, `{name}ORDER` and the reach, and its bytes.
fn hierarchy(s: &mut String, name: &str, nodes: &[BvhNode], order: &[u16]) -> usize {
    let _ = writeln!(
        s,
        "/// The hierarchy's nodes, the root first.\n#[rustfmt::skip]\n\
         pub static {name}NODES: [BvhNode; {}] = [",
        nodes.len()
    );
    for node in nodes {
        let (min, max, first, count, axis) = node.parts();
        let _ = writeln!(
            s,
            "    n({}, {}, {first}, {count}, {axis}),",
            vec3(min),
            vec3(max)
        );
    }
    let _ = writeln!(
        s,
        "];\n\n/// Its leaves' entries, each leaf's a contiguous range.\n#[rustfmt::skip]\n\
         pub static {name}ORDER: [u16; {}] = [",
        order.len()
    );
    for chunk in order.chunks(16) {
        let row: Vec<String> = chunk.iter().map(u16::to_string).collect();
        let _ = writeln!(s, "    {},", row.join(", "));
    }
    let _ = writeln!(s, "];\n");
    size_of_val(nodes) + size_of_val(order)
}

/// A static array of `[f32; 3]`.
fn points(s: &mut String, doc: &str, name: &str, p: &[[f32; 3]]) -> usize {
    let _ = writeln!(
        s,
        "/// {doc}\n#[rustfmt::skip]\npub static {name}: [[f32; 3]; {}] = [",
        p.len()
    );
    for v in p {
        let _ = writeln!(s, "    {},", vec3(*v));
    }
    let _ = writeln!(s, "];\n");
    size_of_val(p)
}

/// The Rust source of a scene's baked triangles and meshes, using the core crate
/// as `krate` (`tessera`, or `crate` inside the core: a path that
/// [`check_crate_path`] accepts, checked by the caller); `header`: comment
/// lines put first (without `//`; a line break or control character in them is
/// escaped: strings of the input go in as [`rust_string`] literals). Writes
/// `TRIANGLES` (the triangle list, if any) and its hierarchy `BVH` (`NODES`,
/// `ORDER`), and for each mesh `i` its `MESH{i}_VERTICES`, `_FACES`,
/// `_NORMALS`, `_NODES`, `_ORDER`, all in `MESHES`.
#[must_use]
pub fn source(scene: &HostScene, krate: &str, header: &[String]) -> String {
    let mut body = String::new();
    let mut bytes = 0;
    let triangles = scene.lists().view().triangles();
    let mut parts = Vec::new();
    if !triangles.is_empty() {
        let mut bvh = Box::new(HostBvh::new());
        // The host scene's capacities: 2 T nodes always suffice.
        if bvh.build(triangles).is_ok() {
            let _ = writeln!(
                body,
                "/// How many triangles.\npub const TRIANGLE_COUNT: usize = {};\n\n\
                 /// The triangles, in the scene's order.\n#[rustfmt::skip]\n\
                 pub static TRIANGLES: [Primitive<Triangle>; TRIANGLE_COUNT] = [",
                triangles.len()
            );
            for t in triangles {
                let v = |p: tessera::Vec3| vec3([p.x, p.y, p.z]);
                let [a, b, c] = t.geometry.vertices();
                let m = t.material.0;
                let _ = writeln!(body, "    t({}, {}, {}, {m}),", v(a), v(b), v(c));
            }
            let _ = writeln!(body, "];\n");
            bytes += size_of_val(triangles);
            bytes += hierarchy(&mut body, "", bvh.nodes(), bvh.order());
            let _ = writeln!(
                body,
                "/// The triangles' hierarchy (`SceneView::with_baked(&TRIANGLES, &BVH)`).\n\
                 pub static BVH: BakedBvh<'static> = BakedBvh::new(&NODES, &ORDER, {});\n",
                lit(bvh.reach())
            );
            parts.push(count(triangles.len(), "triangle", "triangles"));
        }
    }
    let mut meshes = Vec::new();
    for (i, m) in scene.mesh_parts().enumerate() {
        let (vertices, faces, normals, material, bvh) =
            (m.vertices, m.faces, m.normals, m.material, m.bvh);
        let name = format!("MESH{i}_");
        bytes += points(
            &mut body,
            "The vertices.",
            &format!("{name}VERTICES"),
            vertices,
        );
        let _ = writeln!(
            body,
            "/// The faces.\n#[rustfmt::skip]\npub static {name}FACES: [[u16; 3]; {}] = [",
            faces.len()
        );
        for chunk in faces.chunks(6) {
            let row: Vec<String> = chunk
                .iter()
                .map(|[a, b, c]| format!("[{a}, {b}, {c}]"))
                .collect();
            let _ = writeln!(body, "    {},", row.join(", "));
        }
        let _ = writeln!(body, "];\n");
        bytes += size_of_val(faces);
        bytes += points(
            &mut body,
            "The vertex normals (none: flat shading).",
            &format!("{name}NORMALS"),
            normals,
        );
        bytes += hierarchy(&mut body, &name, bvh.nodes(), bvh.order());
        meshes.push(format!(
            "    Mesh::new(\n        &{name}VERTICES,\n        &{name}FACES,\n        \
             &{name}NORMALS,\n        MaterialId({}),\n        \
             BakedBvh::new(&{name}NODES, &{name}ORDER, {}),\n    ),",
            material.0,
            lit(bvh.reach())
        ));
        parts.push(format!(
            "mesh {i}: {}, {}, {}",
            count(vertices.len(), "vertex", "vertices"),
            count(faces.len(), "face", "faces"),
            count(bvh.nodes().len(), "BVH node", "BVH nodes")
        ));
    }
    if !meshes.is_empty() {
        let _ = writeln!(
            body,
            "/// The meshes (`SceneView::with_meshes(&MESHES)`).\n\
             pub static MESHES: [Mesh<'static>; {}] = [\n{}\n];",
            meshes.len(),
            meshes.join("\n")
        );
    }
    let mut s = String::new();
    for line in header {
        let _ = writeln!(s, "{}", format!("// {}", crate::escape(line)).trim_end());
    }
    let _ = writeln!(s, "//\n// {}: {bytes} bytes of flash.\n", parts.join("; "));
    let mut names = vec!["BakedBvh", "BvhNode"];
    if !triangles.is_empty() {
        names.extend(["MaterialId", "Primitive", "Triangle"]);
    }
    if !meshes.is_empty() {
        names.extend(["MaterialId", "Mesh"]);
    }
    names.sort_unstable();
    names.dedup();
    let _ = writeln!(s, "use {krate}::{{{}}};\n", names.join(", "));
    if !triangles.is_empty() {
        let _ = writeln!(
            s,
            "/// A triangle of material `m`.\n\
             const fn t(p0: [f32; 3], p1: [f32; 3], p2: [f32; 3], m: u16) -> Primitive<Triangle> {{\n    \
                 Primitive {{\n        geometry: Triangle::baked(p0, p1, p2),\n        \
                 material: MaterialId(m),\n    }}\n}}\n"
        );
    }
    let _ = writeln!(
        s,
        "/// A node of a hierarchy.\n\
         const fn n(min: [f32; 3], max: [f32; 3], first: u16, count: u16, axis: u16) -> BvhNode {{\n    \
             BvhNode::new(min, max, first, count, axis)\n}}\n"
    );
    s + body.trim_end() + "\n"
}

/// The baked source of a scene description's triangles and meshes, with a header
/// naming the scene and its materials in order (the firmware's scene must have
/// the same). Errors: the scene's own (as for rendering it), and a scene without
/// triangles or meshes (nothing to bake).
pub fn scene_source(desc: &SceneDesc, name: &str, krate: &str) -> Result<String, DescError> {
    let scene = desc.to_core()?;
    if scene.lists().view().triangles().is_empty() && scene.mesh_count() == 0 {
        return Err(DescError {
            item: "scene".to_string(),
            message: "it has no triangles or meshes: nothing to bake".to_string(),
        });
    }
    // The scene's path and its materials' names are written as Rust string
    // literals: a line break or a bidirectional-text control in them cannot
    // end the comment or reorder the code around it.
    let mut header = vec![
        format!(
            "Baked by `tessera bake` from {}: generated, do not edit.",
            rust_string(name)
        ),
        "They use the scene's materials by index:".to_string(),
    ];
    for (i, m) in desc.materials.iter().enumerate() {
        header.push(format!("  {i}: {}", rust_string(&m.name)));
    }
    let others = [
        ("sphere", "spheres", desc.spheres.len()),
        ("plane", "planes", desc.planes.len()),
        ("box", "boxes", desc.boxes.len()),
        ("light", "lights", desc.lights.len()),
    ];
    let rest: Vec<String> = others
        .iter()
        .filter(|(_, _, n)| *n > 0)
        .map(|(one, many, n)| count(*n, one, many))
        .collect();
    header.push(format!(
        "Not baked (build them in the firmware's scene): {}the camera.",
        rest.iter().map(|r| format!("{r}, ")).collect::<String>()
    ));
    Ok(source(&scene, krate, &header))
}

/// The source of the core's baked teapot (`core/src/builtin/teapot_data.rs`):
/// the built-in scene file `scenes/teapot.toml` baked for use inside the core.
#[must_use]
pub fn teapot_source() -> String {
    let desc = crate::file::builtin_desc(tessera::builtin::Builtin::Teapot);
    scene_source(&desc, "scenes/teapot.toml", "crate")
        .unwrap_or_else(|e| panic!("the built-in teapot scene does not bake: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The core's baked teapot is what the host bakes from `scenes/teapot.toml`
    /// today (run with `TESSERA_BLESS=1` to write it after a deliberate change).
    #[test]
    fn the_cores_baked_teapot_is_current() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../core/src/builtin/teapot_data.rs");
        let want = teapot_source();
        if std::env::var_os("TESSERA_BLESS").is_some() {
            std::fs::write(&path, &want).unwrap();
        }
        let have = std::fs::read_to_string(&path).unwrap();
        assert!(
            have == want,
            "{} is not what the host bakes: run `TESSERA_BLESS=1 cargo test -p \
             tessera-host --lib bake` and rebuild",
            path.display()
        );
    }

    /// What the compiler reads from a literal that `rust_string` writes: its
    /// escapes undone (only those it writes), or `None` if it is not one such
    /// literal.
    fn unescape(lit: &str) -> Option<String> {
        let body = lit.strip_prefix('"')?.strip_suffix('"')?;
        let mut out = String::new();
        let mut c = body.chars();
        while let Some(x) = c.next() {
            if x == '"' {
                return None;
            }
            if x != '\\' {
                out.push(x);
                continue;
            }
            out.push(match c.next()? {
                'n' => '\n',
                'r' => '\r',
                't' => '\t',
                '0' => '\0',
                e @ ('\\' | '"') => e,
                'u' => {
                    let hex: String = c.by_ref().take_while(|&h| h != '}').collect();
                    char::from_u32(u32::from_str_radix(hex.strip_prefix('{')?, 16).ok()?)?
                }
                _ => return None,
            });
        }
        Some(out)
    }

    /// One line of printable text, nothing a lint or a reader takes as a line
    /// break or a change of direction, reading back to `s`.
    fn assert_inert(s: &str) {
        let lit = rust_string(s);
        assert!(!lit.contains(crate::text::must_escape), "{s:?} -> {lit}");
        assert_eq!(unescape(&lit).as_deref(), Some(s), "{s:?} -> {lit}");
        assert!(!crate::escape(&lit).contains(crate::text::must_escape));
    }

    #[test]
    fn a_rust_string_is_one_inert_line_that_reads_back() {
        for s in [
            "",
            "floor",
            "ok\npub static INJECTED: u32 = 1;",
            "a\r\nb\u{2028}c\u{2029}d\u{85}e\u{b}\u{c}",
            "\u{202a}\u{202b}\u{202c}\u{202d}\u{202e}\u{2066}\u{2067}\u{2068}\u{2069}",
            "\u{200e}\u{200f}\u{61c}",
            "*/ /* \" \\ \\\" \\u{41} '",
            "nul\0\u{1}\u{1b}[2J\u{7f}\u{9f}",
            "\u{301}combining at the start, e\u{301} inside",
            "émail ✓ 日本 \u{a0}\u{3000}\u{feff}\u{e000}\u{10ffff}",
        ] {
            assert_inert(s);
        }
        assert_eq!(rust_string("floor"), "\"floor\"");
        assert_eq!(rust_string("a\"b\\c"), r#""a\"b\\c""#);
        assert_eq!(rust_string("x\ny\u{202e}"), r#""x\ny\u{202e}""#);
        assert_eq!(rust_string("émail"), "\"émail\"");
        // Every character, one at a time and between two others.
        for c in (0..=0x10_ffff).filter_map(char::from_u32) {
            assert_inert(&format!("{c}"));
            assert_inert(&format!("a{c}\\"));
        }
    }

    #[test]
    fn a_header_line_stays_a_comment() {
        assert_eq!(
            crate::escape("a\nb\u{202e}c \"d\""),
            "a\\u{a}b\\u{202e}c \"d\""
        );
        let text = source(
            &teapot_scene(),
            "crate",
            &["one\npub static X: u8 = 0;".into()],
        );
        assert!(text.starts_with("// one\\u{a}pub static X"), "{text}");
    }

    fn teapot_scene() -> HostScene {
        crate::file::builtin_desc(tessera::builtin::Builtin::Teapot)
            .to_core()
            .unwrap()
    }

    #[test]
    fn a_crate_path_is_what_use_accepts() {
        for ok in [
            "tessera",
            "crate",
            "self",
            "super",
            "super::super::tessera",
            "self::super::deps",
            "crate::deps::tessera",
            "::tessera",
            "my_deps::tessera",
            "_tessera",
            "t3",
            "r#fn",
            "r#gen::r#async",
            "union",
            "raw",
            "safe",
            "macro_rules",
        ] {
            assert_eq!(check_crate_path(ok), Ok(()), "{ok}");
        }
        for (bad, why) in [
            ("fn", "\"fn\" is a Rust keyword, not a crate name"),
            ("tessera::fn", "\"fn\" is a Rust keyword, not a module name"),
            ("::fn", "\"fn\" is a Rust keyword, not a crate name"),
            ("Self", "\"Self\" is a Rust keyword"),
            ("_", "\"_\" is a placeholder, not a crate name"),
            ("a::_", "\"_\" is a placeholder, not a module name"),
            ("tessera::crate", "\"crate\" may only start a path"),
            ("::crate", "\"crate\" may only start a path"),
            ("::self", "\"self\" may only start a path"),
            ("a::self", "\"self\" may only start a path"),
            (
                "::super",
                "\"super\" may only start a path or follow self or super",
            ),
            (
                "crate::super",
                "\"super\" may only start a path or follow self or super",
            ),
            (
                "a::super",
                "\"super\" may only start a path or follow self or super",
            ),
            ("r#crate", "\"r#crate\" cannot be a raw identifier"),
            ("r#self", "\"r#self\" cannot be a raw identifier"),
            ("r#super", "\"r#super\" cannot be a raw identifier"),
            ("r#Self", "\"r#Self\" cannot be a raw identifier"),
            ("r#_", "\"r#_\" is not a raw identifier"),
            ("r#", "\"r#\" is not a raw identifier"),
            ("", "has an empty segment"),
            ("::", "has an empty segment"),
            ("a::", "has an empty segment"),
            ("a::::b", "has an empty segment"),
            (":::a", "\":a\" is not an identifier"),
            ("tes-sera", "\"tes-sera\" is not an identifier"),
            ("3d", "\"3d\" is not an identifier"),
            ("a:b", "\"a:b\" is not an identifier"),
            ("tessera::{X}", "\"{X}\" is not an identifier"),
            ("a b", "\"a b\" is not an identifier"),
            ("tesséra", "\"tesséra\" is not an identifier"),
            ("a\nb", "\"a\\nb\" is not an identifier"),
        ] {
            let e = check_crate_path(bad).unwrap_err();
            assert!(e.contains(why), "{bad:?}: {e}");
        }
        for k in KEYWORDS
            .iter()
            .filter(|k| !matches!(**k, "crate" | "self" | "super"))
        {
            assert!(check_crate_path(k).is_err(), "{k}");
            assert!(check_crate_path(&format!("a::{k}")).is_err(), "{k}");
        }
    }

    #[test]
    fn literals_read_back_to_the_same_f32() {
        for x in [
            0.0f32,
            -0.0,
            1.0,
            -3.0,
            0.1,
            1e-7,
            -1.234_567_9e-30,
            3.402_823_5e38,
            f32::MIN_POSITIVE,
            1.0e-45,
            16_777_216.0,
        ] {
            let s = lit(x);
            assert!(s.contains(['.', 'e']), "{s}");
            let back: f32 = s.parse().unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{s}");
        }
    }
}
