//! Baked scenes: a whole scene file written out as Rust `static` data
//! (`tessera bake`, or [`scene_source`] from a firmware's `build.rs`), so that a
//! firmware keeps the scene in flash and spends no RAM on it: the camera, the
//! size and the `[render]` settings, ambient and background, the materials
//! (each referred to by a constant `MAT_<NAME>`, never a bare index), the
//! lights, every primitive, the triangles' BVH and the meshes with theirs, in a
//! [`tessera_core::BakedScene`] `SCENE`, which checks every item once when a view is
//! taken. It also writes `SceneLoops`, the tile loops the scene needs at its
//! settings, so that a firmware links only those.
//!
//! Numbers are written in Rust's shortest form that reads back to the same
//! `f32`, each item as the host's checked constructor made it, so the baked
//! scene renders the host's image byte for byte (a test renders every scene
//! file both ways).

use crate::desc::{DescError, HostBvh, HostScene, Object, SceneDesc};
use crate::kinds::{HostKind, each_kind, type_name, type_names};
use std::fmt::Write as _;
use tessera_core::Geometry;
use tessera_core::bvh::BvhNode;
use tessera_core::light::LightKind;
use tessera_core::tile::TileLoop;

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
pub(crate) fn lit(x: f32) -> String {
    let s = format!("{x:?}");
    if s.contains(['.', 'e', 'i', 'N']) {
        s
    } else {
        format!("{s}.0")
    }
}

pub(crate) fn vec3(v: [f32; 3]) -> String {
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
        let (min, max, first, count) = node.parts();
        let _ = writeln!(s, "    n({}, {}, {first}, {count}),", vec3(min), vec3(max));
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

/// A scene file's scene as the baker reads it: the core scene and what the
/// file says around it.
pub struct Baking<'a> {
    /// The core scene (every value checked).
    pub scene: &'a HostScene,
    /// The camera's numbers.
    pub camera: tessera_core::BakedCamera,
    /// The scene's `[render]` settings.
    pub settings: tessera_core::RenderSettings,
    /// Its size.
    pub viewport: tessera_core::Viewport,
    /// Its tile size (8, 16 or 32).
    pub tile: usize,
    /// Each material's name, in the scene's order.
    pub names: Vec<String>,
    /// The scene's named objects and lights ([`SceneDesc::named`]), each
    /// written as a constant of its place in its table.
    pub objects: Vec<(String, Object)>,
    /// The animation's tracks ([`SceneDesc::tracks`]), each with the places
    /// in `INSTANCES` of the instance's parts (a track each).
    pub tracks: Vec<(Vec<usize>, crate::animation::TrackData)>,
    /// Frames a second of the animation (`[render] fps`).
    pub fps: f64,
}

/// `c` as a Rust expression of a [`tessera_core::Color`].
fn color(c: tessera_core::Color) -> String {
    format!("Color::new({}, {}, {})", lit(c.r), lit(c.g), lit(c.b))
}

pub(crate) fn v3(p: tessera_core::Vec3) -> String {
    vec3(p.to_array())
}

/// Where the core's public API puts `name` (a name the baked file uses), from
/// the crate's root: `Scene` and its like at the root, the rest in their
/// concept's module.
fn api_path(name: &str) -> String {
    let module = match name {
        _ if type_names().contains(&name) => "geometry::",
        "Material" | "MaterialId" => "material::",
        "Texture" => "texture::",
        "Image" | "TexelFormat" | "Filter" | "Wrap" => "image::",
        "Light" => "light::",
        "BakedBvh" | "BvhNode" => "bvh::",
        "Placed" | "Placement" => "instance::",
        "Animation" | "Track" | "Channel" | "Interpolation" => "animation::",
        "Mesh" => "mesh::",
        "Loops" | "TileLoop" => "tile::",
        "SubPixel" => "sample::",
        _ => "",
    };
    format!("{module}{name}")
}

/// The longest stem of a material's constant, in characters.
const STEM_MAX: usize = 32;

/// The stem of a material's constant: `name` in upper case, each run of
/// characters that are not ASCII letters or digits as one `_` (none at either
/// end), at most [`STEM_MAX`] characters of it; `None` when `name` has no ASCII
/// letter or digit. A stem is made of `A`-`Z`, `0`-`9` and `_`, neither starts
/// nor ends with `_`, and never holds two `_` in a row.
fn stem(name: &str) -> Option<String> {
    let mut stem = String::new();
    for c in name.chars() {
        if c.is_ascii_alphanumeric() {
            stem.push(c.to_ascii_uppercase());
        } else if !stem.is_empty() && !stem.ends_with('_') {
            stem.push('_');
        }
        if stem.len() == STEM_MAX {
            break;
        }
    }
    let stem = stem.trim_end_matches('_');
    (!stem.is_empty()).then(|| stem.to_string())
}

/// The constant a material called `name` has when no other material shares its
/// stem: `MAT_<STEM>` (`MAT_FLOOR` for "floor"); `None` for a name with no ASCII
/// letter or digit.
fn own_constant(name: &str) -> Option<String> {
    stem(name).map(|s| format!("MAT_{s}"))
}

/// The constant names of the materials, one per material, in their order:
/// - `MAT_<STEM>` for a material whose stem (its name in upper case, each run
///   of characters that are not ASCII letters or digits as one `_`, none at
///   either end, at most 32 characters of it) no other material has;
/// - `MAT_<STEM>__<k>` for each of the materials that share a stem (names that
///   differ only in case or punctuation, or long names alike in their first 32
///   characters), `k` = 1, 2, ... in their order: none of them is `MAT_<STEM>`,
///   so code that names such a material by its stem does not compile instead
///   of meaning one of them;
/// - `MAT__<index>` for a name with no ASCII letter or digit (its place in
///   `MATERIALS`).
///
/// No constant is another's, and none is what another material's own name
/// gives: a stem never holds `__` and neither starts nor ends with `_`, so
/// `MAT_<STEM>` has no `__`; `MAT__<index>` has `_` right after `MAT_`, which no
/// `MAT_<STEM>__<k>` has; and in `MAT_<STEM>__<k>` the first `__` comes right
/// after the stem, so the stem and `k` read back from the constant. Each is a
/// Rust identifier in upper case.
#[must_use]
pub fn material_constants(names: &[String]) -> Vec<String> {
    constants("MAT", names.iter().map(String::as_str).enumerate())
}

/// The constant names of a list's items by [`material_constants`]' rule with
/// `prefix` for `MAT`: `items` are each item's place in its table and its name
/// (those of a list that have one), and `<PREFIX>__<place>` stands for a name
/// without an ASCII letter or digit.
fn constants<'n>(prefix: &str, items: impl Iterator<Item = (usize, &'n str)>) -> Vec<String> {
    let items: Vec<(usize, Option<String>)> = items.map(|(i, n)| (i, stem(n))).collect();
    let mut sharing = std::collections::HashMap::<&str, usize>::new();
    for s in items.iter().filter_map(|(_, s)| s.as_deref()) {
        *sharing.entry(s).or_default() += 1;
    }
    let mut seen = std::collections::HashMap::<&str, usize>::new();
    items
        .iter()
        .map(|(i, s)| match s.as_deref() {
            None => format!("{prefix}__{i}"),
            Some(s) if sharing[s] == 1 => format!("{prefix}_{s}"),
            Some(s) => {
                let k = seen.entry(s).or_default();
                *k += 1;
                format!("{prefix}_{s}__{k}")
            }
        })
        .collect()
}

/// The constants of the scene's named objects and lights, each with its
/// line: `(constant, "The sphere \"red ball\"", "SPHERES", place)`, in the
/// order of `named` ([`SceneDesc::named`]: each list's items together).
fn object_constants(named: &[(String, Object)]) -> Vec<(String, String, String, usize)> {
    // Each item's kind as the line names it, its table and its place there.
    let of = |o: &Object| match *o {
        Object::Primitive(kind, i) => (kind.name(), kind.list().name().to_uppercase(), i),
        Object::Mesh(i) => ("mesh", "MESHES".into(), i),
        Object::Light(i) => ("light", "LIGHTS".into(), i),
        Object::Instance(i) => ("instance", "INSTANCES".into(), i),
    };
    let mut out = Vec::new();
    for list in named.chunk_by(|a, b| of(&a.1).1 == of(&b.1).1) {
        let (kind, table, _) = of(&list[0].1);
        let prefix = kind.to_uppercase();
        let consts = constants(&prefix, list.iter().map(|(n, o)| (of(o).2, n.as_str())));
        for (c, (n, o)) in consts.into_iter().zip(list) {
            let what = format!("The {kind} {}", rust_string(n));
            out.push((c, what, table.clone(), of(o).2));
        }
    }
    out
}

/// What the baker cannot spell: a kind the core has and this baker does not
/// know (the core's enums are non-exhaustive), named with the item it is in.
fn unknown(item: &str, what: &str) -> DescError {
    DescError {
        item: item.into(),
        message: format!("this baker cannot write the {what} as Rust: update tessera-host"),
    }
}

/// The `Texture` expression of `t`, in `item`; an image's texels are written
/// by [`Writer::image`], which names their table.
fn texture(
    t: &tessera_core::texture::Texture,
    item: &str,
    image: &mut impl FnMut(&tessera_core::image::Image) -> String,
) -> Result<String, DescError> {
    Ok(match *t {
        tessera_core::texture::Texture::Image(ref i) => {
            use tessera_core::image::{Filter, TexelFormat, Wrap};
            let wrap = |w: Wrap| match w {
                Wrap::Repeat => "Wrap::Repeat",
                Wrap::MirroredRepeat => "Wrap::MirroredRepeat",
                _ => "Wrap::ClampToEdge",
            };
            let [wu, wv] = i.wrap().map(wrap);
            format!(
                "Texture::Image(Image::new({}, {}, TexelFormat::{}, Filter::{}, [{wu}, {wv}], &{}))",
                i.width(),
                i.height(),
                match i.format() {
                    TexelFormat::Rgb565 => "Rgb565",
                    _ => "Srgb8",
                },
                match i.filter() {
                    Filter::Nearest => "Nearest",
                    _ => "Bilinear",
                },
                image(i)
            )
        }
        tessera_core::texture::Texture::Solid(c) => format!("Texture::Solid({})", color(c)),
        tessera_core::texture::Texture::Checker { a, b, scale } => format!(
            "Texture::Checker {{ a: {}, b: {}, scale: {} }}",
            color(a),
            color(b),
            lit(scale)
        ),
        tessera_core::texture::Texture::Fringes { color: c, spacing } => format!(
            "Texture::Fringes {{ color: {}, spacing: {} }}",
            color(c),
            lit(spacing)
        ),
        _ => return Err(unknown(item, "texture")),
    })
}

/// The distinct texel tables of a scene's image textures, in the order the
/// materials name them (one table for materials that share an image).
#[derive(Default)]
struct Images(Vec<tessera_core::image::Image>);

impl Images {
    /// The table name of `img`'s texels (`IMAGE0`, ...), added if new.
    fn name(&mut self, img: &tessera_core::image::Image) -> String {
        let same = |o: &tessera_core::image::Image| {
            core::ptr::eq(o.texels(), img.texels())
                && (o.width(), o.height(), o.format()) == (img.width(), img.height(), img.format())
        };
        let k = match self.0.iter().position(same) {
            Some(k) => k,
            None => {
                self.0.push(*img);
                self.0.len() - 1
            }
        };
        format!("IMAGE{k}")
    }
}

/// The name of `e`'s variant of `Encoding`.
fn variant(e: tessera_core::Encoding) -> &'static str {
    match e {
        tessera_core::Encoding::Linear => "Linear",
        tessera_core::Encoding::Srgb => "Srgb",
    }
}

/// The `Sampler` expression of `s`.
fn sampler(s: tessera_core::Sampler) -> Result<String, DescError> {
    use tessera_core::Sampler as S;
    Ok(match s {
        S::Corner => "Sampler::Corner".into(),
        S::Centre => "Sampler::Centre".into(),
        S::Offset(p) => format!(
            "Sampler::Offset(SubPixel::baked({}, {}))",
            lit(p.x()),
            lit(p.y())
        ),
        S::Stratified(k) => format!("Sampler::Stratified({k})"),
        S::Random(n) => format!("Sampler::Random({n})"),
        S::Prefiltered => "Sampler::Prefiltered".into(),
        S::Adaptive { k, threshold } => {
            format!("Sampler::Adaptive {{ k: {k}, threshold: {threshold} }}")
        }
        S::Sparse { threshold, spacing } => {
            format!("Sampler::Sparse {{ threshold: {threshold}, spacing: {spacing} }}")
        }
        _ => return Err(unknown("render", "sampler")),
    })
}

/// A static table `name` of `items` (each a Rust expression), with `doc`.
fn table(s: &mut String, doc: &str, name: &str, ty: &str, items: &[String]) {
    let _ = writeln!(
        s,
        "/// {doc}\n#[rustfmt::skip]\npub static {name}: [{ty}; {}] = [",
        items.len()
    );
    for i in items {
        let _ = writeln!(s, "    {i},");
    }
    let _ = writeln!(s, "];\n");
}

/// The Rust source of a whole scene as `static` data, using the core crate as
/// `krate` (`tessera`, or `crate` inside the core: a path that
/// [`check_crate_path`] accepts, checked by the caller); `header`: comment
/// lines put first (without `//`; a line break or control character in them is
/// escaped: strings of the input go in as [`rust_string`] literals).
///
/// Writes a constant `MAT_<NAME>` per material (its reference: primitives use
/// these, never a bare index; see [`material_constants`], the header lists
/// the numbered ones with their names), `MATERIALS`, `LIGHTS`, `SPHERES`, `PLANES`,
/// `TRIANGLES` (with their hierarchy `NODES`, `ORDER` when there are enough
/// of them for it to pay), `BOXES`, each mesh's `MESH{i}_VERTICES`, `_FACES`,
/// `_NORMALS`, `_NODES`, `_ORDER` in `MESHES`; `WIDTH`, `HEIGHT` and `TILE`;
/// `Loops`, the tile loops the scene needs; and `SCENE`, the
/// [`tessera_core::BakedScene`] of them all.
///
/// # Errors
/// A texture, sampler or tile loop of the core that this baker cannot write.
pub fn source(b: &Baking<'_>, krate: &str, header: &[String]) -> Result<String, DescError> {
    let view = b.scene.lists().view();
    let mut w = Writer::new(b);
    w.materials(&view)?;
    w.lights(&view);
    let lists = w.primitives(&view);
    w.meshes();
    w.objects();
    w.frame(&view, &lists)?;
    Ok(w.preamble(&view, krate, header) + w.body.trim_end() + "\n")
}

/// The lengths of the tables of the scene's lists: what `SCENE` is made of.
struct Written {
    /// Each kind's table's length, in the core's order.
    lens: [usize; tessera_core::kind::KINDS],
    /// `.with_bvh(..)` when the triangles have a hierarchy, else empty.
    with_bvh: String,
}

impl Written {
    /// The arguments of `capacities!` for the tables: each list that holds
    /// something, by name.
    fn capacities(&self) -> String {
        tessera_core::kind::Kind::ALL
            .iter()
            .zip(self.lens)
            .filter(|&(_, n)| n > 0)
            .map(|(kind, n)| format!("{}: {n}", kind.list().name()))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// A baked source as it is written: its body (the tables, in order), what the
/// header will say of it, and the core's names it uses.
struct Writer<'a> {
    b: &'a Baking<'a>,
    /// Each material's constant (`MAT_FLOOR`), in the scene's order.
    consts: Vec<String>,
    body: String,
    /// Bytes of flash of the tables written.
    bytes: usize,
    /// The summary's parts beyond the plain counts (triangles, each mesh).
    parts: Vec<String>,
    /// The core's names the source uses (its `use` line).
    names: Vec<&'static str>,
    /// Whether the source needs the core's feature `bvh`.
    bvh_needed: bool,
    /// The core's features its kinds need (`cylinder`, `disk`).
    features: Vec<&'static str>,
    /// `.with_meshes(&MESHES)` when there are meshes (and
    /// `.with_instances(&INSTANCES)` when they have instances), else empty.
    with_meshes: String,
}

impl<'a> Writer<'a> {
    fn new(b: &'a Baking<'a>) -> Self {
        Self {
            b,
            consts: material_constants(&b.names),
            body: String::new(),
            bytes: 0,
            parts: Vec::new(),
            names: vec![
                "BakedCamera",
                "BakedScene",
                "capacities",
                "Primitives",
                "Color",
                "Encoding",
                "Loops",
                "TileLoop",
                "Material",
                "MaterialId",
                "Light",
                "Primitive",
                "RenderSettings",
                "Sampler",
                "Texture",
                "Viewport",
            ],
            features: Vec::new(),
            bvh_needed: false,
            with_meshes: String::new(),
        }
    }

    /// The constant a primitive's material is written with.
    fn mat(&self, m: tessera_core::material::MaterialId) -> String {
        self.consts
            .get(usize::from(m.0))
            .cloned()
            .unwrap_or_else(|| format!("MaterialId({})", m.0))
    }

    /// A table of `items` (see [`table`]) and its bytes of flash.
    fn table(&mut self, doc: &str, name: &str, ty: &str, items: &[String], bytes: usize) {
        table(&mut self.body, doc, name, ty, items);
        self.bytes += bytes;
    }

    /// A constant for each named object and light: its place in its table
    /// (`SPHERE_RED_BALL` for the sphere "red ball", `MESH_TEAPOT`,
    /// `LIGHT_SUN`), by [`material_constants`]' rule within each list.
    fn objects(&mut self) {
        let consts = object_constants(&self.b.objects);
        if consts.is_empty() {
            return;
        }
        let _ = writeln!(
            self.body,
            "// The named objects and lights: each constant is the item's place in its table."
        );
        for (c, what, table, place) in consts {
            let _ = writeln!(
                self.body,
                "/// {what} (its place in `{table}`).\n#[allow(dead_code)]\npub const {c}: usize = {place};"
            );
        }
        let _ = writeln!(self.body);
    }

    /// The material constants, by name, and `MATERIALS`.
    fn materials(&mut self, view: &tessera_core::SceneView<'_>) -> Result<(), DescError> {
        let _ = writeln!(
            self.body,
            "// The materials: each constant is a material's reference (its place in MATERIALS)."
        );
        for (i, (c, n)) in self.consts.iter().zip(&self.b.names).enumerate() {
            let _ = writeln!(
                self.body,
                "/// The material {}.\n#[allow(dead_code)]\npub const {c}: MaterialId = MaterialId({i});",
                rust_string(n)
            );
        }
        let _ = writeln!(self.body);
        let mut images = Images::default();
        let materials = view
            .materials()
            .iter()
            .zip(&self.consts)
            .enumerate()
            .map(|(i, (m, c))| {
                let t = texture(
                    m.texture(),
                    &format!("material {} ({:?})", i + 1, self.b.names[i]),
                    &mut |img| images.name(img),
                )?;
                Ok(format!(
                    "Material::baked( // {c}\n        {},\n        {}, {}, {}, {}, {}, {}, {},\n    )",
                    t,
                    lit(m.ambient()),
                    lit(m.diffuse()),
                    lit(m.specular()),
                    lit(m.shininess()),
                    lit(m.reflectivity()),
                    lit(m.transparency()),
                    lit(m.ior())
                ))
            })
            .collect::<Result<Vec<_>, DescError>>()?;
        if !images.0.is_empty() {
            self.names
                .extend(["Image", "TexelFormat", "Filter", "Wrap"]);
            self.features.push("image");
        }
        for (k, img) in images.0.iter().enumerate() {
            let texels = img.texels();
            let _ = writeln!(
                self.body,
                "/// Image {k}: {} x {} texels, {} ({} bytes), row 0 at the top.\n\
                 #[rustfmt::skip]\npub static IMAGE{k}: [u8; {}] = [",
                img.width(),
                img.height(),
                img.format().name(),
                texels.len(),
                texels.len()
            );
            for row in texels.chunks(24) {
                let bytes: Vec<String> = row.iter().map(|b| format!("{b}")).collect();
                let _ = writeln!(self.body, "    {},", bytes.join(","));
            }
            let _ = writeln!(self.body, "];\n");
            self.bytes += texels.len();
            self.parts.push(format!(
                "image {k}: {} x {} texels, {}, {} bytes",
                img.width(),
                img.height(),
                img.format().name(),
                texels.len()
            ));
        }
        self.table(
            "The materials: texture, ambient, diffuse, specular, shininess, \
             reflectivity, transparency, index of refraction.",
            "MATERIALS",
            "Material",
            &materials,
            size_of_val(view.materials()),
        );
        Ok(())
    }

    /// `LIGHTS`; with a sun, the core's feature `sun`. Without one, the table's
    /// size is the firmware's: its lights have no kind to store.
    fn lights(&mut self, view: &tessera_core::SceneView<'_>) {
        let sun = view
            .lights()
            .iter()
            .any(tessera_core::light::Light::is_directional);
        if sun {
            self.features.push("sun");
        }
        let lights: Vec<String> = view
            .lights()
            .iter()
            .map(|l| {
                let (kind, at) = match l.kind() {
                    LightKind::Point(at) => ("point", at),
                    LightKind::Directional(toward) => ("directional", toward),
                };
                format!(
                    "Light::baked_{kind}({}, {}, {})",
                    v3(at),
                    color(l.color()),
                    lit(l.intensity())
                )
            })
            .collect();
        self.table(
            "The lights: a point light's position (a sun's unit direction towards \
             it), colour, intensity.",
            "LIGHTS",
            "Light",
            &lights,
            if sun {
                size_of_val(view.lights())
            } else {
                view.lights().len() * tessera_core::light::POINT_LIGHT_BYTES
            },
        );
    }

    /// Each kind's table, in the core's order (`SPHERES`, `PLANES`, ...), and
    /// the triangles' hierarchy when it pays.
    fn primitives(&mut self, view: &tessera_core::SceneView<'_>) -> Written {
        let mut lens = [0; tessera_core::kind::KINDS];
        let mut with_bvh = String::new();
        each_kind!(|G| {
            let list = view.list::<G>();
            lens[G::KIND.index()] = list.len();
            if list.is_empty() {
                // No table: the scene's `..Primitives::NONE` stands for it.
            } else if G::KIND == tessera_core::kind::Kind::Triangle {
                with_bvh = self.triangles(view.triangles());
                self.names.push(type_name::<G>());
            } else {
                let items: Vec<String> = list
                    .iter()
                    .map(|p| {
                        format!(
                            "Primitive {{ geometry: {}, material: {} }}",
                            p.geometry.baked(),
                            self.mat(p.material)
                        )
                    })
                    .collect();
                self.table(
                    G::TABLE,
                    &G::KIND.list().name().to_uppercase(),
                    &format!("Primitive<{}>", type_name::<G>()),
                    &items,
                    size_of_val(list),
                );
                self.names.push(type_name::<G>());
                self.names.extend(G::NAMES);
                if let Some(feature) = G::FEATURE {
                    self.features.push(feature);
                }
            }
        });
        Written { lens, with_bvh }
    }

    /// `TRIANGLES`, and their hierarchy `NODES`, `ORDER` when there are enough
    /// of them for it to pay: returns the `.with_bvh(..)` that hands it to the
    /// scene (empty without).
    fn triangles(
        &mut self,
        triangles: &[tessera_core::Primitive<tessera_core::geometry::Triangle>],
    ) -> String {
        let tris: Vec<String> = triangles
            .iter()
            .map(|p| {
                let [a, c, d] = p.geometry.vertices();
                format!(
                    "t({}, {}, {}, {})",
                    v3(a),
                    v3(c),
                    v3(d),
                    self.mat(p.material)
                )
            })
            .collect();
        self.table(
            "The triangles, in the scene's order.",
            "TRIANGLES",
            "Primitive<Triangle>",
            &tris,
            size_of_val(triangles),
        );
        let mut with_bvh = String::new();
        if triangles.len() >= tessera_core::bvh::CROSSOVER {
            let mut bvh = Box::new(HostBvh::new());
            // The host scene's capacities: 2 T nodes always suffice.
            if bvh.build(triangles).is_ok() {
                self.bytes += hierarchy(&mut self.body, "", bvh.nodes(), bvh.order());
                with_bvh = format!(
                    "\n.with_bvh(BakedBvh::new(&NODES, &ORDER, {}))",
                    lit(bvh.reach())
                );
                self.bvh_needed = true;
            }
        }
        if !triangles.is_empty() {
            self.parts
                .push(count(triangles.len(), "triangle", "triangles"));
        }
        with_bvh
    }

    /// Each mesh's `MESH{i}_VERTICES`, `_FACES`, `_NORMALS`, `_UVS` (when it has
    /// texture coordinates), `_NODES`, `_ORDER`, and `MESHES`.
    fn meshes(&mut self) {
        let mut meshes = Vec::new();
        for (i, m) in self.b.scene.mesh_parts().enumerate() {
            let (vertices, faces, normals, uvs, material, bvh) =
                (m.vertices, m.faces, m.normals, m.uvs, m.material, m.bvh);
            let name = format!("MESH{i}_");
            self.bytes += points(
                &mut self.body,
                "The vertices.",
                &format!("{name}VERTICES"),
                vertices,
            );
            let _ = writeln!(
                self.body,
                "/// The faces.\n#[rustfmt::skip]\npub static {name}FACES: [[u16; 3]; {}] = [",
                faces.len()
            );
            for chunk in faces.chunks(6) {
                let row: Vec<String> = chunk
                    .iter()
                    .map(|[a, b, c]| format!("[{a}, {b}, {c}]"))
                    .collect();
                let _ = writeln!(self.body, "    {},", row.join(", "));
            }
            let _ = writeln!(self.body, "];\n");
            self.bytes += size_of_val(faces);
            self.bytes += points(
                &mut self.body,
                "The vertex normals (none: flat shading).",
                &format!("{name}NORMALS"),
                normals,
            );
            let with_uvs = if uvs.is_empty() {
                String::new()
            } else {
                let _ = writeln!(
                    self.body,
                    "/// The vertex texture coordinates.\n#[rustfmt::skip]\npub static \
                     {name}UVS: [[f32; 2]; {}] = [",
                    uvs.len()
                );
                for [u, v] in uvs {
                    let _ = writeln!(self.body, "    [{}, {}],", lit(*u), lit(*v));
                }
                let _ = writeln!(self.body, "];\n");
                self.bytes += size_of_val(uvs);
                format!(".with_uvs(&{name}UVS)")
            };
            self.bytes += hierarchy(&mut self.body, &name, bvh.nodes(), bvh.order());
            meshes.push(format!(
                "    Mesh::new(\n        &{name}VERTICES,\n        &{name}FACES,\n        \
                 &{name}NORMALS,\n        {},\n        \
                 BakedBvh::new(&{name}NODES, &{name}ORDER, {}),\n    ){with_uvs},",
                self.mat(material),
                lit(bvh.reach())
            ));
            self.parts.push(format!(
                "mesh {i}: {}, {}, {}",
                count(vertices.len(), "vertex", "vertices"),
                count(faces.len(), "face", "faces"),
                count(bvh.nodes().len(), "BVH node", "BVH nodes")
            ));
        }
        if !meshes.is_empty() {
            self.names.push("Mesh");
            self.bvh_needed = true;
            let _ = writeln!(
                self.body,
                "/// The meshes.\npub static MESHES: [Mesh<'static>; {}] = [\n{}\n];\n",
                meshes.len(),
                meshes.join("\n")
            );
            self.with_meshes = "\n.with_meshes(&MESHES)".into();
        }
        self.instances();
    }

    /// `INSTANCES`, the meshes' instances placed (what
    /// `tessera_core::instance::Instances` makes of each placement, checked
    /// again by `SCENE.view()`), and the core's feature `instances`.
    fn instances(&mut self) {
        let list = self.b.scene.instances();
        if list.is_empty() {
            return;
        }
        let placed = self.b.scene.with_view(|view| {
            // Placed as the host's view places them: the same core code.
            tessera_core::instance::Instances::<'_, { crate::desc::MAX_INSTANCES }>::of(view)
                .map(|p| {
                    (0..p.len())
                        .filter_map(|i| p.get(i).zip(p.numbers(i)))
                        .collect::<Vec<_>>()
                })
                .unwrap_or_default()
        });
        let f = |xs: &[f32]| xs.iter().map(|&x| lit(x)).collect::<Vec<_>>().join(", ");
        let items: Vec<String> = placed
            .iter()
            .map(|(inst, (a, h))| {
                let p = inst.placement;
                format!(
                    "Placed::baked(\n        &MESHES[{m}],\n        {m},\n        \
                     Placement::new([{}], [{}], [{}]),\n        ([{}], [{}]),\n    )",
                    f(&p.rotation),
                    f(&p.scale),
                    f(&p.translation),
                    f(a),
                    f(h),
                    m = inst.mesh,
                )
            })
            .collect();
        let _ = writeln!(
            self.body,
            "/// The meshes' instances: each mesh drawn where they place it (copy them\n\
             /// into RAM to move them: `Instances::of(&SCENE.view()?)`, `set`, then\n\
             /// `view.with_instances(..)`).\n#[rustfmt::skip]\npub static INSTANCES: \
             [Placed<'static>; {}] = [\n    {},\n];\n",
            items.len(),
            items.join(",\n    ")
        );
        self.bytes += items.len() * size_of::<tessera_core::instance::Placed<'static>>();
        self.names.extend(["Placed", "Placement"]);
        self.features.push("instances");
        self.parts.push(count(items.len(), "instance", "instances"));
        self.with_meshes += "\n.with_instances(&INSTANCES)";
        self.animation();
    }

    /// `TRACK{k}_TIMES`, `TRACK{k}_VALUES` and `ANIMATION`, the scene's
    /// keyframe tracks (one a part of each moved instance), and the core's
    /// feature `animation`: a firmware places a frame's instances with
    /// `ANIMATION.place(t, &rest, &mut instances)`.
    fn animation(&mut self) {
        if self.b.tracks.is_empty() {
            return;
        }
        let mut tracks = Vec::new();
        for (k, (parts, t)) in self.b.tracks.iter().enumerate() {
            let _ = writeln!(
                self.body,
                "/// Track {k}'s keyframe times (seconds).\n#[allow(dead_code)]\npub static TRACK{k}_TIMES: [f32; {}] = [{}];\n",
                t.times.len(),
                t.times
                    .iter()
                    .map(|&x| lit(x))
                    .collect::<Vec<_>>()
                    .join(", ")
            );
            let _ = writeln!(
                self.body,
                "/// Track {k}'s keyframe values.\n#[rustfmt::skip]\n#[allow(dead_code)]\npub static TRACK{k}_VALUES: [[f32; 4]; {}] = [",
                t.values.len()
            );
            for v in &t.values {
                let _ = writeln!(
                    self.body,
                    "    [{}],",
                    v.iter().map(|&x| lit(x)).collect::<Vec<_>>().join(", ")
                );
            }
            let _ = writeln!(self.body, "];\n");
            self.bytes += size_of_val(t.times.as_slice()) + size_of_val(t.values.as_slice());
            let channel = match t.channel {
                tessera_core::animation::Channel::Translation => "Translation",
                tessera_core::animation::Channel::Rotation => "Rotation",
                _ => "Scale",
            };
            let interpolation = match t.interpolation {
                tessera_core::animation::Interpolation::Step => "Step",
                _ => "Linear",
            };
            for &p in parts {
                tracks.push(format!(
                    "    Track::new({p}, Channel::{channel}, Interpolation::{interpolation}, \
                     &TRACK{k}_TIMES, &TRACK{k}_VALUES),"
                ));
            }
        }
        let _ = writeln!(
            self.body,
            "/// Frames a second of the animation (the scene file's `fps`): frame n is at\n\
             /// `n as f32 / FPS` seconds.\n#[allow(dead_code)]\npub const FPS: f32 = {};\n",
            lit(self.b.fps as f32)
        );
        let _ = writeln!(
            self.body,
            "/// The scene's animation: `ANIMATION.place(t, &rest, &mut instances)` moves the\n\
             /// instances a copy of `INSTANCES` in RAM holds to where they are at `t` seconds\n\
             /// (a firmware that shows the still scene leaves it out of its flash).\n\
             #[allow(dead_code)]\npub static ANIMATION: Animation<'static> = Animation::new(&[\n{}\n]);\n",
            tracks.join("\n")
        );
        self.bytes += tracks.len() * size_of::<tessera_core::animation::Track<'static>>();
        self.names
            .extend(["Animation", "Track", "Channel", "Interpolation"]);
        self.features.push("animation");
        self.parts.push(count(tracks.len(), "track", "tracks"));
    }

    /// `WIDTH`, `HEIGHT`, `TILE`, `SceneLoops` and `SCENE`.
    fn frame(
        &mut self,
        view: &tessera_core::SceneView<'_>,
        lists: &Written,
    ) -> Result<(), DescError> {
        let b = self.b;
        if self.bvh_needed {
            self.names.extend(["BakedBvh", "BvhNode"]);
        }
        if matches!(b.settings.sampler, tessera_core::Sampler::Offset(_)) {
            self.names.push("SubPixel");
        }
        let st = &b.settings;
        // The loop the core's renderer takes for these settings, spelt as code.
        let tile_loop = match TileLoop::of(st, view) {
            TileLoop::Direct(e) => format!("TileLoop::Direct(Encoding::{})", variant(e)),
            TileLoop::Bounces(e) => format!("TileLoop::Bounces(Encoding::{})", variant(e)),
            TileLoop::Adaptive { bounces } => {
                format!("TileLoop::Adaptive {{ bounces: {bounces} }}")
            }
            TileLoop::Sparse { bounces } => format!("TileLoop::Sparse {{ bounces: {bounces} }}"),
            _ => return Err(unknown("render", "tile loop")),
        };
        let _ = writeln!(
            self.body,
            "/// The width the scene is meant to be rendered at, in pixels.\n\
             #[allow(dead_code)]\npub const WIDTH: u16 = {};\n\
             /// Its height.\n#[allow(dead_code)]\npub const HEIGHT: u16 = {};\n\
             /// Its tile size (the file's `tile`: a `Tile<TILE, _>` buffer).\n\
             #[allow(dead_code)]\npub const TILE: usize = {};\n",
            b.viewport.width, b.viewport.height, b.tile
        );
        let _ = writeln!(
            self.body,
            "/// The tile loops this scene needs at its settings, for\n\
             /// `Renderer::render_tile_in::<SceneLoops, ..>`: a firmware links these alone.\n\
             #[allow(dead_code)]\npub enum SceneLoops {{}}\n\n\
             impl Loops for SceneLoops {{\n    \
                 fn links(tile_loop: TileLoop) -> bool {{\n        \
                     tile_loop == {tile_loop}\n    \
                 }}\n}}\n"
        );
        let c = &b.camera;
        let encoding = variant(st.encoding);
        let _ = writeln!(
            self.body,
            "/// The whole scene: `SCENE.view()?` and `SCENE.renderer()?` check it once and render it\n\
             /// from where it lies.\n\
             #[allow(dead_code)]\n// `..Primitives::NONE` stands for the kinds it has none of (none, with the\n// core's optional kinds off).\n#[allow(clippy::needless_update)]\npub static SCENE: BakedScene<'static, capacities!({})> = BakedScene::new(\n    \
                 BakedCamera {{\n        position: {},\n        forward: {},\n        up: {},\n        \
                 fovy_degrees: {},\n        near: {},\n        far: {},\n    }},\n    \
                 Viewport::new(WIDTH, HEIGHT),\n    \
                 RenderSettings {{\n        sampler: {},\n        max_depth: {},\n        seed: {},\n        \
                 encoding: Encoding::{encoding},\n    }},\n    \
                 {},\n    {},\n    &MATERIALS,\n    &LIGHTS,\n    \
                 Primitives {{\n{}    }},\n){}{};",
            lists.capacities(),
            vec3(c.position),
            vec3(c.forward),
            vec3(c.up),
            lit(c.fovy_degrees),
            lit(c.near),
            lit(c.far),
            sampler(st.sampler)?,
            st.max_depth,
            st.seed,
            color(view.ambient()),
            color(view.background()),
            tessera_core::kind::Kind::ALL
                .iter()
                .zip(lists.lens)
                .filter(|&(_, n)| n > 0)
                .map(|(k, _)| {
                    let list = k.list().name();
                    format!("        {list}: &{},\n", list.to_uppercase())
                })
                .chain(std::iter::once("        ..Primitives::NONE\n".to_string()))
                .collect::<String>(),
            lists.with_bvh,
            self.with_meshes,
        );
        Ok(())
    }

    /// What comes before the tables: the header's lines, the summary (what the
    /// scene holds and its bytes of flash), the numbered material constants, the
    /// `use` line and the helpers the tables call.
    fn preamble(
        &mut self,
        view: &tessera_core::SceneView<'_>,
        krate: &str,
        header: &[String],
    ) -> String {
        let mut s = String::new();
        for line in header {
            let _ = writeln!(s, "{}", format!("// {}", crate::escape(line)).trim_end());
        }
        let mut others = vec![
            count(view.materials().len(), "material", "materials"),
            count(view.lights().len(), "light", "lights"),
        ];
        each_kind!(|G| {
            if G::KIND != tessera_core::kind::Kind::Triangle {
                let kind = G::KIND;
                let n = view.list::<G>().len();
                others.push(count(n, kind.name(), kind.list().name()));
            }
        });
        let mut kinds: Vec<String> = others
            .into_iter()
            .filter(|p| !p.starts_with("0 "))
            .collect();
        kinds.extend(
            self.parts
                .iter()
                .filter(|p| !p.starts_with("mesh ") && !p.starts_with("image "))
                .cloned(),
        );
        let mut all = vec![kinds.join(", ")];
        all.extend(
            self.parts
                .iter()
                .filter(|p| p.starts_with("mesh ") || p.starts_with("image "))
                .cloned(),
        );
        let _ = writeln!(
            s,
            "//\n// {}: {} bytes of flash.",
            all.join("; "),
            self.bytes
        );
        for feature in &self.features {
            let _ = writeln!(
                s,
                "// Needs the core's feature `{feature}` (its features list in the firmware's Cargo.toml)."
            );
        }
        if self.bvh_needed {
            let _ = writeln!(
                s,
                "// Needs the core's feature `bvh` (its features list in the firmware's Cargo.toml)."
            );
        }
        self.numbered(&mut s);
        let _ = writeln!(s);
        self.names.sort_unstable();
        self.names.dedup();
        let mut paths: Vec<String> = self.names.iter().map(|n| api_path(n)).collect();
        paths.sort_unstable();
        let _ = writeln!(s, "use {krate}::{{{}}};\n", paths.join(", "));
        if !view.triangles().is_empty() {
            let _ = writeln!(
                s,
                "/// A triangle of material `m`.\n\
                 const fn t(p0: [f32; 3], p1: [f32; 3], p2: [f32; 3], m: MaterialId) -> Primitive<Triangle> {{\n    \
                     Primitive {{\n        geometry: Triangle::baked(p0, p1, p2),\n        \
                     material: m,\n    }}\n}}\n"
            );
        }
        if self.bvh_needed {
            let _ = writeln!(
                s,
                "/// A node of a hierarchy.\n\
                 const fn n(min: [f32; 3], max: [f32; 3], first: u16, count: u16) -> BvhNode {{\n    \
                     BvhNode::new(min, max, first, count)\n}}\n"
            );
        }
        s
    }

    /// The header's list of the materials whose constant their name alone does
    /// not give (see `material_constants`): names alike but for case,
    /// punctuation or what follows the 32 characters a constant keeps, and names
    /// without a letter or digit.
    fn numbered(&self, s: &mut String) {
        let numbered: Vec<String> = self
            .b
            .names
            .iter()
            .zip(&self.consts)
            .filter(|&(n, c)| own_constant(n).as_ref() != Some(c))
            .map(|(n, c)| format!("//   {c} is the material {}", rust_string(n)))
            .collect();
        if !numbered.is_empty() {
            let _ = writeln!(
                s,
                "//\n// Numbered material constants (names that give the same constant, or none):"
            );
            for line in numbered {
                let _ = writeln!(s, "{line}");
            }
        }
    }
}

/// What a firmware's `build.rs` does with its scene file: reads the file named
/// by the environment variable `TESSERA_SCENE`, else `default_scene` (relative
/// to the crate's folder, where cargo runs build scripts; mesh and image files
/// relative to it, as `tessera render` reads them), prints its warnings as
/// cargo's, asks cargo to run again when the file, its mesh files or the
/// variable change, checks that the build enables the core's features the
/// scene needs ([`missing_features`], read from cargo's `CARGO_FEATURE_*`
/// variables: the firmware forwards each to the core,
/// [`CoreFeatures::Forwarded`]), and writes the baked scene to
/// `OUT_DIR/scene.rs`, which the firmware `include!`s. It also sets
/// `TESSERA_SCENE_NAME` (the file as named) for the firmware's code, and the
/// configuration `tessera_animation` when the baked scene has an animation
/// (`ANIMATION` and `FPS`): code that plays it is `#[cfg(tessera_animation)]`,
/// compiled for the scenes that have one.
///
/// # Errors
/// The reader's message (file, line, what is wrong), the baker's, the
/// features the build lacks, or a file that cannot be written: the build
/// script prints it as `cargo::error` and fails.
pub fn build_script(default_scene: &str) -> Result<(), String> {
    build_script_for(default_scene, CoreFeatures::Forwarded).map(|_| ())
}

/// Where a firmware's build has the core's features from, which
/// [`build_script_for`] checks a scene file against.
#[derive(Clone, Copy, Debug)]
pub enum CoreFeatures<'a> {
    /// Each forwarded from a feature of the firmware's own of the same name
    /// (`bvh = ["tessera-core/bvh"]`), read from cargo's `CARGO_FEATURE_*`
    /// variables; a missing one is asked for with `--features`.
    Forwarded,
    /// Fixed in the firmware's manifest (`tessera-core = { features = [...]
    /// }`): these, each feature the manifest turns on listed, those it
    /// implies included.
    Fixed(&'a [&'a str]),
}

/// [`build_script`] with the core's features from `features`; returns the
/// scene file read, for checks of the firmware's own (a firmware that plays
/// an animation refuses a scene without one).
///
/// # Errors
/// As [`build_script`].
pub fn build_script_for(
    default_scene: &str,
    features: CoreFeatures<'_>,
) -> Result<SceneDesc, String> {
    use std::env;
    println!("cargo::rerun-if-env-changed=TESSERA_SCENE");
    let scene = env::var("TESSERA_SCENE").unwrap_or_else(|_| default_scene.into());
    // The messages name the file as the user gave it.
    println!("cargo::rerun-if-changed={scene}");
    let path = std::path::Path::new(&scene);
    let desc = crate::file::load(path).map_err(|e| e.to_string())?;
    for w in crate::file::warnings(&desc) {
        println!("cargo::warning={scene}: {w}");
    }
    let base = path.parent().unwrap_or(std::path::Path::new(""));
    for mesh in &desc.meshes {
        if let Some(file) = crate::mesh::obj_file(mesh, base) {
            println!("cargo::rerun-if-changed={}", file.display());
        }
    }
    let source =
        scene_source(&desc, &scene, "tessera_core").map_err(|e| format!("{scene}: {e}"))?;
    let missing = match features {
        // Cargo's variable for feature `a-b` is `CARGO_FEATURE_A_B`.
        CoreFeatures::Forwarded => missing_features(&desc, &source, |f: &str| {
            env::var_os(format!(
                "CARGO_FEATURE_{}",
                f.to_uppercase().replace('-', "_")
            ))
            .is_some()
        }),
        CoreFeatures::Fixed(on) => missing_features(&desc, &source, |f: &str| on.contains(&f)),
    };
    if !missing.is_empty() {
        let how = match features {
            CoreFeatures::Forwarded => format!(
                "build with --features {}{}",
                missing.join(","),
                if missing.contains(&"bvh") {
                    "; `bvh`, for meshes and 100 triangles or more, is on by default: \
                     --no-default-features turns it off"
                } else {
                    ""
                }
            ),
            CoreFeatures::Fixed(_) => {
                "add them to tessera-core's `features` in the firmware's Cargo.toml".into()
            }
        };
        return Err(format!(
            "{scene} needs the core's features `{}`, which this build lacks ({how})",
            missing.join("`, `"),
        ));
    }
    println!("cargo::rustc-env=TESSERA_SCENE_NAME={scene}");
    println!("cargo::rustc-check-cfg=cfg(tessera_animation)");
    if kind_features(&desc).contains(&"animation") {
        println!("cargo::rustc-cfg=tessera_animation");
    }
    let out = env::var_os("OUT_DIR").ok_or("OUT_DIR is not set: call this from a build script")?;
    std::fs::write(std::path::Path::new(&out).join("scene.rs"), source)
        .map_err(|e| format!("cannot write scene.rs: {e}"))?;
    Ok(desc)
}

/// The core's features that the baked `source` of `desc` needs and
/// `enabled` says the build lacks: `bvh` for its hierarchies (meshes, or 100
/// triangles or more), then [`kind_features`].
pub fn missing_features(
    desc: &SceneDesc,
    source: &str,
    enabled: impl Fn(&str) -> bool,
) -> Vec<&'static str> {
    let bvh = source.contains("BakedBvh").then_some("bvh");
    bvh.into_iter()
        .chain(kind_features(desc))
        .filter(|f| !enabled(f))
        .collect()
}

/// The core's optional features that a scene needs (`cylinder`, `disk`: the
/// kinds the core compiles only with them, in the core's order; then `image`
/// for image textures, `sun` for a directional light): a firmware that bakes
/// the scene enables them.
#[must_use]
pub fn kind_features(desc: &SceneDesc) -> Vec<&'static str> {
    let mut out = Vec::new();
    each_kind!(|G| {
        if let Some(feature) = G::FEATURE
            && !<G as crate::kinds::Listed>::descs(desc).is_empty()
        {
            out.push(feature);
        }
    });
    if desc
        .materials
        .iter()
        .any(|m| matches!(m.texture, Some(crate::desc::TextureDesc::Image { .. })))
    {
        out.push("image");
    }
    if desc.lights.iter().any(|l| l.direction.is_some()) {
        out.push("sun");
    }
    if !desc.instances.is_empty() {
        out.push("instances");
    }
    if !desc.keyframes.is_empty() {
        out.push("animation");
    }
    out
}

/// The baked source of a scene description: the whole scene (see [`source`]),
/// with a header naming the scene file. Errors: the scene's own (as for
/// rendering it: its camera, settings and every item checked).
pub fn scene_source(desc: &SceneDesc, name: &str, krate: &str) -> Result<String, DescError> {
    let scene = desc.to_core()?;
    let starts = desc.instance_starts();
    let tracks = desc
        .tracks()?
        .into_iter()
        .map(|t| {
            let start = starts.get(t.instance).copied().unwrap_or(0);
            let parts = desc
                .instances
                .get(t.instance)
                .map_or(0, |d| desc.instance_parts(&d.mesh).len());
            ((start..start + parts).collect(), t)
        })
        .collect();
    let baking = Baking {
        tracks,
        fps: desc.render.fps,
        scene: &scene,
        camera: desc.camera_numbers()?,
        settings: desc.settings()?,
        viewport: desc.viewport(),
        tile: desc.render.tile,
        names: desc.materials.iter().map(|m| m.name.clone()).collect(),
        objects: {
            // An instance's constant is the place of its first part.
            let starts = desc.instance_starts();
            desc.named()
                .into_iter()
                .map(|(n, o)| match o {
                    Object::Instance(i) => (n.to_string(), Object::Instance(starts[i])),
                    o => (n.to_string(), o),
                })
                .collect()
        },
    };
    // The scene's path is written as a Rust string literal: a line break or a
    // bidirectional-text control in it cannot end the comment or reorder the
    // code around it.
    let header = vec![format!(
        "Baked by `tessera bake` from {}: generated, do not edit.",
        rust_string(name)
    )];
    source(&baking, krate, &header)
}

/// The source of a built-in scene baked for use inside the core
/// (`core/src/builtin/baked/<name>.rs`): `text`, its scene file
/// `scenes/<name>.toml`, baked with the crate path `crate`, and the text itself
/// as the constant `SOURCE` (what [`tessera_core::builtin::Builtin::source`] returns:
/// the core carries its built-in scenes' files without reading a file outside
/// its own folder).
///
/// # Errors
/// The scene file's, as for rendering it (the message names the file).
pub fn builtin_source(b: tessera_core::builtin::Builtin, text: &str) -> Result<String, String> {
    let name = format!("scenes/{}.toml", b.name());
    let desc = crate::file::parse(text, &name).map_err(|e| e.to_string())?;
    let mut out = scene_source(&desc, &name, "crate").map_err(|e| format!("{name}: {e}"))?;
    let _ = write!(
        out,
        "\n/// The scene file this module is baked from, `{name}`.\n\
         pub const SOURCE: &str = {};\n",
        raw_string(text)
    );
    Ok(out)
}

/// `text` as a Rust raw string literal (`r#"..."#`), with as many `#` as it
/// takes that no `"` followed by them occurs in `text`.
fn raw_string(text: &str) -> String {
    let mut hashes = String::from("#");
    while text.contains(&format!("\"{hashes}")) {
        hashes.push('#');
    }
    format!("r{hashes}\"{text}\"{hashes}")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The core's baked built-in scenes (`core/src/builtin/baked/<name>.rs`) are
    /// what the host bakes from their scene files today (run with
    /// `TESSERA_BLESS=1` to write them after a deliberate change).
    #[test]
    fn the_cores_baked_scenes_are_current() {
        for &b in tessera_core::builtin::Builtin::ALL {
            let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(format!(
                "../core/src/builtin/baked/{}.rs",
                b.name().replace('-', "_")
            ));
            let text = std::fs::read_to_string(
                std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                    .join(format!("../scenes/{}.toml", b.name())),
            )
            .unwrap();
            let want = builtin_source(b, &text).unwrap();
            if std::env::var_os("TESSERA_BLESS").is_some() {
                std::fs::write(&path, &want).unwrap();
            }
            let have = std::fs::read_to_string(&path).unwrap_or_default();
            assert!(
                have == want,
                "{} is not what the host bakes: run `TESSERA_BLESS=1 cargo test -p \
                 tessera-host --lib bake` and rebuild",
                path.display()
            );
        }
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
    fn material_constants_are_identifiers_one_per_material() {
        let names: Vec<String> = [
            "floor",
            "Floor",
            "floor!",
            "glass pane",
            "2d",
            "",
            "--",
            "émail",
            "a\nb",
            "a very long material name that goes on and on",
        ]
        .iter()
        .map(|s| s.to_string())
        .collect();
        assert_eq!(
            material_constants(&names),
            [
                "MAT_FLOOR__1",
                "MAT_FLOOR__2",
                "MAT_FLOOR__3",
                "MAT_GLASS_PANE",
                "MAT_2D",
                "MAT__5",
                "MAT__6",
                "MAT_MAIL",
                "MAT_A_B",
                "MAT_A_VERY_LONG_MATERIAL_NAME_THAT_G",
            ]
        );
    }

    fn strings(names: &[&str]) -> Vec<String> {
        names.iter().map(|s| s.to_string()).collect()
    }

    /// A shared stem (`floor`, `Floor`) beside a name that ends in a digit:
    /// `floor_2` keeps `MAT_FLOOR_2` whatever the order, and `floor` and `Floor`
    /// (one stem) are numbered in their order, neither taking `MAT_FLOOR` nor
    /// `MAT_FLOOR_2`.
    #[test]
    fn floor_and_floor_2_keep_apart_in_every_order() {
        let orders = [
            ["floor", "Floor", "floor_2"],
            ["floor", "floor_2", "Floor"],
            ["Floor", "floor", "floor_2"],
            ["Floor", "floor_2", "floor"],
            ["floor_2", "floor", "Floor"],
            ["floor_2", "Floor", "floor"],
        ];
        for names in orders {
            let consts = material_constants(&strings(&names));
            let mut k = 0;
            for (n, c) in names.iter().zip(&consts) {
                if *n == "floor_2" {
                    assert_eq!(c, "MAT_FLOOR_2", "{names:?} -> {consts:?}");
                } else {
                    k += 1;
                    assert_eq!(*c, format!("MAT_FLOOR__{k}"), "{names:?} -> {consts:?}");
                }
            }
        }
    }

    /// Long names alike in their first 32 characters (after upper case and
    /// punctuation), and a short name that is those 32 characters, share a
    /// stem: each is numbered, and a long name that differs within them keeps
    /// its own constant.
    #[test]
    fn long_names_alike_in_their_first_32_characters_are_numbered() {
        let names = strings(&[
            "a very long material name that goes on and on",
            "a very long material name that goes elsewhere",
            "A_VERY_LONG_MATERIAL_NAME_THAT_G",
            "a very long material name that hides",
            "a very long material name thatt went",
            "a very long material name thatt",
        ]);
        assert_eq!(
            material_constants(&names),
            [
                "MAT_A_VERY_LONG_MATERIAL_NAME_THAT_G__1",
                "MAT_A_VERY_LONG_MATERIAL_NAME_THAT_G__2",
                "MAT_A_VERY_LONG_MATERIAL_NAME_THAT_G__3",
                "MAT_A_VERY_LONG_MATERIAL_NAME_THAT_H",
                "MAT_A_VERY_LONG_MATERIAL_NAME_THATT__1",
                "MAT_A_VERY_LONG_MATERIAL_NAME_THATT__2",
            ]
        );
    }

    /// A name of digits keeps its digits; a name with no letter or digit is
    /// numbered by its place in a form no name gives: the material called `5`
    /// and the sixth material, unnamed, have two constants, in either order.
    #[test]
    fn digit_names_never_meet_the_numbers_of_unnamed_materials() {
        let names = strings(&["5", "-", "", "x", "0", "!", "6"]);
        assert_eq!(
            material_constants(&names),
            [
                "MAT_5", "MAT__1", "MAT__2", "MAT_X", "MAT_0", "MAT__5", "MAT_6"
            ]
        );
        let names = strings(&["x", "y", "z", "w", "v", "", "5"]);
        assert_eq!(
            material_constants(&names),
            [
                "MAT_X", "MAT_Y", "MAT_Z", "MAT_W", "MAT_V", "MAT__5", "MAT_5"
            ]
        );
    }

    /// Every list of up to four names from a small alphabet chosen to meet
    /// (case, punctuation, digits, the numbering's own forms, no letter, 32
    /// characters): the constants are upper-case identifiers, one per material,
    /// none is what another material's name gives on its own, and a material
    /// whose stem no other has keeps what its name gives on its own.
    #[test]
    fn material_constants_keep_apart_for_every_small_list() {
        let alphabet = [
            "a",
            "A",
            "a 2",
            "a__2",
            "a_1",
            "a 2 1",
            "1",
            "2",
            "",
            "-",
            "mat",
            "MAT__1",
            "x y z x y z x y z x y z x y z x y z!",
            "x y z x y z x y z x y z x y z x y z?",
            "XYZXYZXYZXYZXYZXYZ",
        ];
        let n = alphabet.len();
        let mut lists = 0;
        for len in 1..=4u32 {
            for mut code in 0..n.pow(len) {
                let mut names = Vec::new();
                for _ in 0..len {
                    names.push(alphabet[code % n].to_string());
                    code /= n;
                }
                lists += 1;
                let consts = material_constants(&names);
                assert_eq!(consts.len(), names.len());
                let own: Vec<Option<String>> = names
                    .iter()
                    .map(|m| material_constants(std::slice::from_ref(m)))
                    .map(|c| c[0].clone())
                    .map(|c| (c != "MAT__0").then_some(c))
                    .collect();
                for (i, c) in consts.iter().enumerate() {
                    let body = c.strip_prefix("MAT_").unwrap_or_else(|| panic!("{c}"));
                    assert!(
                        body.chars()
                            .all(|x| x.is_ascii_uppercase() || x.is_ascii_digit() || x == '_'),
                        "{names:?} -> {consts:?}"
                    );
                    for j in (0..names.len()).filter(|&j| j != i) {
                        assert_ne!(c, &consts[j], "{names:?} -> {consts:?}");
                        assert_ne!(Some(c), own[j].as_ref(), "{names:?} -> {consts:?}");
                    }
                    let alone = (0..names.len()).all(|j| j == i || own[j] != own[i]);
                    if alone && own[i].is_some() {
                        assert_eq!(Some(c), own[i].as_ref(), "{names:?} -> {consts:?}");
                    }
                }
            }
        }
        assert_eq!(lists, 15 + 15 * 15 + 15 * 15 * 15 + 15 * 15 * 15 * 15);
    }

    /// The header names each material whose constant is numbered (and no
    /// other), its name as a string literal.
    #[test]
    fn the_header_lists_the_numbered_material_constants() {
        let mut text = String::from(
            "[camera]\nposition = [0, 1, 5]\nlook_at = [0, 0, 0]\nnear = 0.1\nfar = 100\n",
        );
        for (i, name) in ["floor", "Floor", "floor_2", "-", "a\\nb"]
            .iter()
            .enumerate()
        {
            text += &format!(
                "\n[[material]]\nname = \"{name}\"\n\n[[sphere]]\ncenter = [{i}, 0, 0]\n\
                 radius = 0.5\nmaterial = \"{name}\"\n"
            );
        }
        let desc = crate::file::parse(&text, "t.toml").unwrap();
        let source = scene_source(&desc, "t.toml", "crate").unwrap();
        let head: Vec<&str> = source
            .lines()
            .take_while(|l| !l.starts_with("use "))
            .collect();
        let listed: Vec<&str> = head
            .iter()
            .copied()
            .skip_while(|l| !l.starts_with("// Numbered material constants"))
            .skip(1)
            .take_while(|l| !l.is_empty())
            .collect();
        assert_eq!(
            listed,
            [
                "//   MAT_FLOOR__1 is the material \"floor\"",
                "//   MAT_FLOOR__2 is the material \"Floor\"",
                "//   MAT__3 is the material \"-\"",
            ],
            "{source}"
        );
        for (i, c) in [
            "MAT_FLOOR__1",
            "MAT_FLOOR__2",
            "MAT_FLOOR_2",
            "MAT__3",
            "MAT_A_B",
        ]
        .iter()
        .enumerate()
        {
            let line = format!("pub const {c}: MaterialId = MaterialId({i});");
            assert!(source.contains(&line), "{line} in\n{source}");
        }
        // A scene whose names all give their own constants lists none.
        let teapot = builtin_source(
            tessera_core::builtin::Builtin::Teapot,
            tessera_core::builtin::Builtin::Teapot.source(),
        )
        .unwrap();
        assert!(!teapot.contains("Numbered"), "{teapot}");
    }

    #[test]
    fn a_header_line_stays_a_comment() {
        assert_eq!(
            crate::escape("a\nb\u{202e}c \"d\""),
            "a\\u{a}b\\u{202e}c \"d\""
        );
        let desc = crate::file::builtin_desc(tessera_core::builtin::Builtin::Teapot);
        let scene = desc.to_core().unwrap();
        let baking = Baking {
            scene: &scene,
            camera: desc.camera_numbers().unwrap(),
            settings: desc.settings().unwrap(),
            viewport: desc.viewport(),
            tile: desc.render.tile,
            names: vec!["a\nb".into(), "c".into()],
            objects: Vec::new(),
            tracks: Vec::new(),
            fps: 30.0,
        };
        let text = source(&baking, "crate", &["one\npub static X: u8 = 0;".into()]).unwrap();
        assert!(
            text.contains("/// The material \"a\\nb\".\n#[allow(dead_code)]\npub const MAT_A_B"),
            "{text}"
        );
        assert!(text.starts_with("// one\\u{a}pub static X"), "{text}");
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
            (
                "tessera_core::fn",
                "\"fn\" is a Rust keyword, not a module name",
            ),
            ("::fn", "\"fn\" is a Rust keyword, not a crate name"),
            ("Self", "\"Self\" is a Rust keyword"),
            ("_", "\"_\" is a placeholder, not a crate name"),
            ("a::_", "\"_\" is a placeholder, not a module name"),
            ("tessera_core::crate", "\"crate\" may only start a path"),
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
            ("tessera_core::{X}", "\"{X}\" is not an identifier"),
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

    /// A firmware's build is told the core's features its scene needs and it
    /// lacks: `bvh` for the teapot's mesh, `image` and `sun` for the 3D tools'
    /// scene, none once they are on.
    #[test]
    fn the_features_a_build_lacks_are_named() {
        let teapot = crate::file::builtin_desc(tessera_core::builtin::Builtin::Teapot);
        let src = scene_source(&teapot, "teapot.toml", "tessera_core").unwrap();
        assert_eq!(missing_features(&teapot, &src, |_| false), ["bvh"]);
        assert!(missing_features(&teapot, &src, |f| f == "bvh").is_empty());
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data");
        let tools = crate::file::load(&dir.join("tools.toml")).unwrap();
        let src = scene_source(&tools, "tools.toml", "tessera_core").unwrap();
        assert_eq!(
            missing_features(&tools, &src, |f| f == "bvh"),
            ["image", "sun"]
        );
        assert!(missing_features(&tools, &src, |_| true).is_empty());
    }

    /// Each named object and light bakes as a constant of its place in its
    /// table, by the material constants' rule within its list (two names of
    /// one stem numbered, neither taking the plain constant); unnamed items
    /// have none.
    #[test]
    fn named_items_bake_as_constants_of_their_places() {
        let text = crate::desc::NAMED_SCENE;
        let desc = crate::file::parse(text, "named.toml").unwrap();
        let src = scene_source(&desc, "named.toml", "tessera_core").unwrap();
        for (doc, line) in [
            (
                "The light \"sun\" (its place in `LIGHTS`)",
                "LIGHT_SUN: usize = 1;",
            ),
            (
                "The sphere \"red ball\" (its place in `SPHERES`)",
                "SPHERE_RED_BALL__1: usize = 1;",
            ),
            ("The sphere \"Red-Ball\"", "SPHERE_RED_BALL__2: usize = 2;"),
            ("The sphere \"!\"", "SPHERE__3: usize = 3;"),
            (
                "The box \"crate\" (its place in `BOXES`)",
                "BOX_CRATE: usize = 0;",
            ),
            (
                "The mesh \"turned crate\" (its place in `MESHES`)",
                "MESH_TURNED_CRATE: usize = 0;",
            ),
        ] {
            let want = format!("/// {doc}");
            let at = src
                .find(&want)
                .unwrap_or_else(|| panic!("no {want:?} in {src}"));
            let rest = &src[at..];
            let next = rest.lines().nth(2).unwrap_or_default();
            assert_eq!(next, format!("pub const {line}"), "{rest:.200}");
        }
        assert!(!src.contains("SPHERE_RED_BALL:"), "{src}");
        assert_eq!(src.matches("pub const SPHERE_").count(), 3, "{src}");
        assert_eq!(src.matches("pub const LIGHT_").count(), 1, "{src}");
        // An unnamed scene has no such section.
        let plain = text.replace("name = \"", "# name = \"");
        let plain = plain.replace("# name = \"m\"", "name = \"m\"");
        let desc = crate::file::parse(&plain, "plain.toml").unwrap();
        let src = scene_source(&desc, "plain.toml", "tessera_core").unwrap();
        assert!(!src.contains("named objects"), "{src}");
    }

    /// Image textures bake as byte tables named by their materials' textures,
    /// each listed once in the header with its size and bytes, and the core's
    /// `image` feature asked for: Blender's cube (two tints of one image, two
    /// tables) and its MTL scene (RGB565).
    #[test]
    fn image_textures_bake_as_texel_tables() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/blender");
        let desc = crate::file::load(&dir.join("textured.toml")).unwrap();
        let src = scene_source(&desc, "textured.toml", "tessera_core").unwrap();
        let header: String = src.lines().take_while(|l| l.starts_with("//")).collect();
        assert_eq!(
            header
                .matches("image 0: 73 x 73 texels, srgb8, 15987 bytes")
                .count(),
            1,
            "{header}"
        );
        assert_eq!(header.matches("image 1: ").count(), 1, "{header}");
        assert!(
            header.contains("Needs the core's feature `image`"),
            "{header}"
        );
        assert!(
            src.contains("pub static IMAGE0: [u8; 15987] = ["),
            "{header}"
        );
        assert!(src.contains(
            "Texture::Image(Image::new(73, 73, TexelFormat::Srgb8, Filter::Bilinear, \
             [Wrap::Repeat, Wrap::Repeat], &IMAGE0))"
        ));
        assert!(src.contains("Filter::Nearest, [Wrap::Repeat, Wrap::MirroredRepeat], &IMAGE1)"));
        // The scene's sun asks for the core's `sun` too.
        assert_eq!(kind_features(&desc), ["image", "sun"]);
        let desc = crate::file::load(&dir.join("mtl.toml")).unwrap();
        let src = scene_source(&desc, "mtl.toml", "tessera_core").unwrap();
        assert!(src.contains("pub static IMAGE0: [u8; 16200] = ["));
        assert!(src.contains("TexelFormat::Rgb565"));
    }

    /// A sun asks for the core's feature `sun` (in the header and in
    /// [`kind_features`]) and bakes as `Light::baked_directional`; point lights
    /// alone ask for nothing, and their table's bytes are those of a core
    /// without `sun` (a position, a colour, an intensity: 28 bytes a light),
    /// whatever the baker's own build holds.
    #[test]
    fn a_sun_asks_for_its_feature_and_point_lights_take_their_own_bytes() {
        let scene = |lights: &str| {
            format!(
                "[camera]\nposition = [0, 1, 5]\nlook_at = [0, 0, 0]\nfovy = 60\nnear = 0.1\nfar = 100\n\
                 [[material]]\nname = \"m\"\ncolor = [1, 1, 1]\n\
                 [[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"m\"\n{lights}"
            )
        };
        let point = "[[light]]\nposition = [0, 5, 0]\nintensity = 10\n";
        let sun = "[[light]]\ndirection = [0, -1, 0]\nintensity = 1\n";
        let header = |text: &str| {
            let desc = crate::file::parse(text, "s.toml").unwrap();
            let src = scene_source(&desc, "s.toml", "tessera_core").unwrap();
            (kind_features(&desc), src)
        };
        let (features, src) = header(&scene(&format!("{point}{point}")));
        assert!(features.is_empty(), "{features:?}");
        assert!(!src.contains("feature `sun`"), "{src}");
        assert!(src.contains("2 lights"), "{src}");
        assert_eq!(tessera_core::light::POINT_LIGHT_BYTES, 28);
        let bytes = |src: &str| {
            let line = src.lines().find(|l| l.contains("bytes of flash")).unwrap();
            let n = line.rsplit(": ").next().unwrap().split(' ').next().unwrap();
            n.parse::<usize>().unwrap()
        };
        let (features, with_sun) = header(&scene(&format!("{point}{sun}")));
        assert_eq!(features, ["sun"]);
        assert!(
            with_sun.contains("// Needs the core's feature `sun`"),
            "{with_sun}"
        );
        assert!(
            with_sun.contains("Light::baked_directional([-0.0, 1.0, -0.0], "),
            "{with_sun}"
        );
        // The same two lights' table, with the kind each light then holds.
        let tessera = size_of::<tessera_core::light::Light>();
        assert_eq!(bytes(&with_sun) - bytes(&src), 2 * (tessera - 28));
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
