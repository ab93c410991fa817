//! Scene files: TOML text in the shape of [`SceneDesc`], read, checked and located.
//!
//! [`parse`] accepts a file only if it renders: after the TOML has the shape of a
//! scene, every value is checked by building the core scene, the render settings
//! and the frame. Errors say where: `FILE:LINE:COL: message` when the TOML is
//! malformed or has the wrong shape (syntax, unknown key, wrong type, missing key),
//! `FILE:LINE: item: message` when a value is refused (`sphere 2: sphere radius must
//! be > 0, got -1`, the line being where that item starts).
//!
//! The built-in scenes exist as files too (`scenes/NAME.toml`, embedded); see
//! [`builtin_desc`].

use crate::desc::{DescError, SceneDesc};
use serde::Deserialize;
use serde::de::IgnoredAny;
use std::fmt;
use std::path::Path;
use tessera::builtin::Builtin;
use toml::Spanned;

/// What kind of problem a [`FileError`] reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// The file could not be read (missing, unreadable, not UTF-8).
    Read,
    /// The text is not TOML or does not have the shape of a scene: a syntax error,
    /// an unknown key, a value of the wrong type, a missing key.
    Toml,
    /// The shape is right but a value is refused (NaN, out of range, unknown
    /// material, too many primitives, ...).
    Invalid,
}

/// A problem with a scene file; its `Display` is the message a user reads, e.g.
/// `scene.toml:12: sphere 2: sphere radius must be > 0, got -1`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileError {
    /// What kind of problem.
    pub kind: ErrorKind,
    /// The file, as the caller named it (usually its path).
    pub file: String,
    /// The 1-based line, when known.
    pub line: Option<usize>,
    /// The 1-based column (in characters), for TOML errors with a position.
    pub column: Option<usize>,
    /// The item at fault (`sphere 2`, `camera`, `render`, ...), for invalid values.
    pub item: Option<String>,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for FileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.file)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(column) = self.column {
                write!(f, ":{column}")?;
            }
        }
        f.write_str(": ")?;
        if let Some(item) = &self.item {
            write!(f, "{item}: ")?;
        }
        f.write_str(&self.message)
    }
}

impl std::error::Error for FileError {}

/// The 1-based line and column (counted in characters) of byte offset `byte` of
/// `text`. An offset past the end is the position just after the last character;
/// an offset inside a multi-byte character is that character's position.
pub fn line_col(text: &str, byte: usize) -> (usize, usize) {
    let mut end = byte.min(text.len());
    while !text.is_char_boundary(end) {
        end -= 1;
    }
    let before = &text[..end];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    let column = before[line_start..].chars().count() + 1;
    (line, column)
}

/// Reads the scene file at `path` and parses it with [`parse`]; messages name the
/// file by `path` as given.
pub fn load(path: &Path) -> Result<SceneDesc, FileError> {
    let file = path.display().to_string();
    match std::fs::read_to_string(path) {
        Ok(text) => parse(&text, &file),
        Err(e) => Err(FileError {
            kind: ErrorKind::Read,
            file,
            line: None,
            column: None,
            item: None,
            message: format!("cannot read the scene file: {e}"),
        }),
    }
}

/// Parses the scene file `text` and checks that it renders (core scene, render
/// settings and frame all accepted). `name` is what messages call the file.
pub fn parse(text: &str, name: &str) -> Result<SceneDesc, FileError> {
    let desc: SceneDesc = toml::from_str(text).map_err(|e| {
        let (line, column) = match e.span() {
            Some(span) => {
                let (l, c) = line_col(text, span.start);
                (Some(l), Some(c))
            }
            None => (None, None),
        };
        FileError {
            kind: ErrorKind::Toml,
            file: name.to_string(),
            line,
            column,
            item: None,
            message: e.message().trim().to_string(),
        }
    })?;
    check(&desc).map_err(|e| FileError {
        kind: ErrorKind::Invalid,
        file: name.to_string(),
        line: item_start(text, &e.item).map(|b| line_col(text, b).0),
        column: None,
        item: Some(e.item),
        message: e.message,
    })?;
    Ok(desc)
}

/// Checks everything the renderer will check: the core scene, the settings, and
/// the frame at the file's viewport.
fn check(desc: &SceneDesc) -> Result<(), DescError> {
    let scene = desc.to_core()?;
    let settings = desc.settings()?;
    let vp = desc.viewport();
    tessera::Frame::try_new(scene.camera(), vp, settings).map_err(|e| {
        let c = &desc.camera;
        match e {
            tessera::Error::EmptyViewport => DescError {
                item: "render".into(),
                message: format!("{e}, got {}x{}", vp.width, vp.height),
            },
            _ => DescError {
                item: "camera".into(),
                message: format!(
                    "{e}, got near {} and fovy {} at {}x{}",
                    c.near, c.fovy, vp.width, vp.height
                ),
            },
        }
    })?;
    Ok(())
}

/// Where each item of a scene file starts (only the positions are kept).
#[derive(Deserialize)]
struct Places {
    camera: Option<Spanned<IgnoredAny>>,
    render: Option<Spanned<IgnoredAny>>,
    ambient: Option<Spanned<IgnoredAny>>,
    background: Option<Spanned<IgnoredAny>>,
    #[serde(default)]
    material: Vec<Spanned<IgnoredAny>>,
    #[serde(default)]
    light: Vec<Spanned<IgnoredAny>>,
    #[serde(default)]
    sphere: Vec<Spanned<IgnoredAny>>,
    #[serde(default)]
    plane: Vec<Spanned<IgnoredAny>>,
    #[serde(default)]
    triangle: Vec<Spanned<IgnoredAny>>,
    #[serde(default, rename = "box")]
    boxes: Vec<Spanned<IgnoredAny>>,
}

/// The byte where `item` (`camera`, `sphere 3`, `material 2 ("red")`, ...) starts
/// in `text`: its `[[sphere]]`/`[camera]` header, its inline table, or its key.
fn item_start(text: &str, item: &str) -> Option<usize> {
    let places: Places = toml::from_str(text).ok()?;
    let start = |s: &Option<Spanned<IgnoredAny>>| s.as_ref().map(|s| s.span().start);
    let mut words = item.split_whitespace();
    let kind = words.next()?;
    let list = match kind {
        "camera" => return start(&places.camera),
        "render" => return start(&places.render),
        "ambient" => return start(&places.ambient),
        "background" => return start(&places.background),
        "material" => &places.material,
        "light" => &places.light,
        "sphere" => &places.sphere,
        "plane" => &places.plane,
        "triangle" => &places.triangle,
        "box" => &places.boxes,
        _ => return None,
    };
    let n: usize = words.next()?.parse().ok()?;
    list.get(n.checked_sub(1)?).map(|s| s.span().start)
}

/// The text of the built-in scene's file, `scenes/NAME.toml` (embedded).
pub fn builtin_source(b: Builtin) -> &'static str {
    match b {
        Builtin::ChapterDirect => include_str!("../../scenes/chapter-direct.toml"),
        Builtin::ChapterReflect => include_str!("../../scenes/chapter-reflect.toml"),
        Builtin::Interference => include_str!("../../scenes/interference.toml"),
        Builtin::Showcase => include_str!("../../scenes/showcase.toml"),
    }
}

/// The built-in scene as a description, parsed from its embedded file (which the
/// tests check renders exactly like the core's built-in scene).
pub fn builtin_desc(b: Builtin) -> SceneDesc {
    let name = format!("scenes/{}.toml", b.name());
    parse(builtin_source(b), &name)
        .unwrap_or_else(|e| panic!("the embedded built-in scene file is broken: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;
    use tessera::Viewport;

    fn scenes_dir() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes")
    }

    fn toml_files(dir: &Path, out: &mut Vec<PathBuf>) {
        let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                toml_files(&p, out);
            } else if p.extension().is_some_and(|e| e == "toml") {
                out.push(p);
            }
        }
    }

    /// Renders a description at `vp` with its own settings and tile size.
    fn render_desc(d: &SceneDesc, vp: Viewport) -> image::RgbImage {
        let s = d.to_core().unwrap();
        crate::render(
            &s.view(),
            s.camera(),
            vp,
            d.settings().unwrap(),
            d.render.tile,
        )
        .unwrap()
    }

    #[test]
    fn every_scene_file_parses_validates_and_renders() {
        let mut files = Vec::new();
        toml_files(&scenes_dir(), &mut files);
        assert!(files.len() >= 20, "only {} scene files", files.len());
        for f in &files {
            let text = std::fs::read_to_string(f).unwrap();
            assert!(
                text.starts_with('#'),
                "{} has no header comment",
                f.display()
            );
            let d = load(f).unwrap_or_else(|e| panic!("{e}"));
            let img = render_desc(&d, Viewport::new(24, 18));
            assert_eq!(img.dimensions(), (24, 18));
        }
        for b in Builtin::ALL {
            let name = format!("{}.toml", b.name());
            assert!(files.iter().any(|f| f.ends_with(&name)), "{name} missing");
        }
    }

    #[test]
    fn builtin_files_render_exactly_like_the_core_scenes() {
        for b in Builtin::ALL {
            let d = builtin_desc(b);
            let s = d.to_core().unwrap();
            let vp = Viewport::new(96, 72);
            let from_file = crate::render(&s.view(), s.camera(), vp, b.settings(), 16).unwrap();
            let core = b
                .with_scene(|view, cam| crate::render(view, cam, vp, b.settings(), 16))
                .unwrap()
                .unwrap();
            assert!(from_file == core, "{} differs from its file", b.name());
        }
    }

    /// Stricter than the images (a one-ulp weight rarely changes an 8-bit pixel):
    /// every number of the core scene built from the file is the built-in's.
    #[test]
    fn builtin_files_build_the_same_core_scene_bit_for_bit() {
        for b in Builtin::ALL {
            let d = builtin_desc(b);
            let s = d.to_core().unwrap();
            let (file, cam) = (s.view(), *s.camera());
            b.with_scene(|core, core_cam| {
                let n = b.name();
                assert_eq!(&cam, core_cam, "{n}: camera");
                assert_eq!(file.ambient(), core.ambient(), "{n}: ambient");
                assert_eq!(file.background(), core.background(), "{n}: background");
                assert_eq!(file.materials(), core.materials(), "{n}: materials");
                assert_eq!(file.lights(), core.lights(), "{n}: lights");
                assert_eq!(file.spheres(), core.spheres(), "{n}: spheres");
                assert_eq!(file.planes(), core.planes(), "{n}: planes");
                assert_eq!(file.triangles(), core.triangles(), "{n}: triangles");
                assert_eq!(file.boxes(), core.boxes(), "{n}: boxes");
            })
            .unwrap();
        }
    }

    #[test]
    fn builtin_files_have_the_builtin_settings() {
        for b in Builtin::ALL {
            let d = builtin_desc(b);
            assert_eq!(d.settings().unwrap(), b.settings(), "{}", b.name());
            assert_eq!(
                (d.render.width, d.render.height, d.render.tile),
                (320, 240, 16)
            );
        }
    }

    #[test]
    fn line_col_counts_from_one_in_characters() {
        let t = "ab\nçd\n";
        assert_eq!(line_col(t, 0), (1, 1));
        assert_eq!(line_col(t, 1), (1, 2));
        assert_eq!(line_col(t, 3), (2, 1));
        assert_eq!(line_col(t, 4), (2, 1)); // inside `ç`
        assert_eq!(line_col(t, 5), (2, 2));
        assert_eq!(line_col(t, 7), (3, 1));
        assert_eq!(line_col(t, 99), (3, 1));
        assert_eq!(line_col("", 0), (1, 1));
    }

    const HEAD: &str = "\
[camera]
position = [0, 1, 5]
look_at = [0, 0, 0]
near = 0.1
far = 100

[[material]]
name = \"red\"
color = [0.9, 0.1, 0.1]
";

    /// The message of parsing `text` as `t.toml`, checked for debug output.
    fn msg(text: &str) -> String {
        let e = parse(text, "t.toml").unwrap_err();
        let m = e.to_string();
        for bad in ["Error {", "Some(", "{ ", "\n"] {
            assert!(!m.contains(bad), "debug output in {m:?}");
        }
        m
    }

    #[test]
    fn syntax_error_has_line_and_column() {
        let m = msg(&format!("{HEAD}\n[[sphere]]\ncenter = [0, 0, 0\n"));
        assert_eq!(m, "t.toml:12:18: unclosed array, expected `]`");
        let m = msg("[camera\n");
        assert!(m.starts_with("t.toml:1:8: "), "{m}");
    }

    #[test]
    fn unknown_key_names_it_and_its_place() {
        let m = msg(&format!(
            "{HEAD}\n[[sphere]]\ncenter = [0, 0, 0]\nradiuss = 1\nmaterial = \"red\"\n"
        ));
        assert!(
            m.starts_with(
                "t.toml:13:1: unknown field `radiuss`, expected one of `center`, `radius`"
            ),
            "{m}"
        );
        let m = msg(&format!("spheres = []\n{HEAD}"));
        assert!(m.starts_with("t.toml:1:1: unknown field `spheres`"), "{m}");
    }

    #[test]
    fn wrong_type_points_at_the_value() {
        let m = msg(&format!(
            "{HEAD}\n[[sphere]]\ncenter = [0, 0, 0]\nradius = \"big\"\nmaterial = \"red\"\n"
        ));
        assert_eq!(
            m,
            "t.toml:13:10: invalid type: string \"big\", expected f64"
        );
        let m = msg(&format!("{HEAD}\n[render]\nwidth = -5\n"));
        assert!(
            m.starts_with("t.toml:12:9: invalid value: integer `-5`"),
            "{m}"
        );
        let m = msg(&format!("{HEAD}\n[[sphere]]\ncenter = [0, 0]\n"));
        assert_eq!(
            m,
            "t.toml:12:10: invalid length 2, expected an array of length 3"
        );
    }

    #[test]
    fn missing_key_points_at_the_table() {
        let m = msg(&format!(
            "{HEAD}\n[[sphere]]\ncenter = [0, 0, 0]\nmaterial = \"red\"\n"
        ));
        assert_eq!(m, "t.toml:11:1: missing field `radius`");
        let m = msg("ambient = [0.1, 0.1, 0.1]\n");
        assert!(
            m.starts_with("t.toml") && m.ends_with("missing field `camera`"),
            "{m}"
        );
    }

    fn sphere(radius: &str) -> String {
        format!("\n[[sphere]]\ncenter = [0, 0, 0]\nradius = {radius}\nmaterial = \"red\"\n")
    }

    #[test]
    fn nan_and_infinity_name_the_item_and_value() {
        let m = msg(&format!("{HEAD}{}", sphere("nan")));
        assert_eq!(
            m,
            "t.toml:11: sphere 1: sphere radius is NaN or infinite, got NaN"
        );
        let m = msg(&format!("{HEAD}{}", sphere("-inf")));
        assert_eq!(
            m,
            "t.toml:11: sphere 1: sphere radius is NaN or infinite, got -inf"
        );
        let m = msg(&format!(
            "{HEAD}\n[[light]]\nposition = [0, 5, 0]\nintensity = inf\n"
        ));
        assert_eq!(
            m,
            "t.toml:11: light 1: light intensity is NaN or infinite, got inf"
        );
        let m = msg(&format!("ambient = [0.1, nan, 0]\n{HEAD}"));
        assert_eq!(
            m,
            "t.toml:1: ambient: scene ambient light is NaN or infinite, got [0.1, NaN, 0]"
        );
    }

    #[test]
    fn negative_radius_names_the_right_sphere_and_line() {
        let text = format!("{HEAD}{}{}", sphere("1"), sphere("-1"));
        let e = parse(&text, "t.toml").unwrap_err();
        assert_eq!(e.kind, ErrorKind::Invalid);
        assert_eq!(e.item.as_deref(), Some("sphere 2"));
        assert_eq!(
            e.to_string(),
            "t.toml:16: sphere 2: sphere radius must be > 0, got -1"
        );
        // The same in the inline form (top-level keys come before the tables).
        let text = format!(
            "sphere = [\n  {{ center = [0, 0, 0], radius = 1, material = \"red\" }},\n  \
             {{ center = [0, 0, 0], radius = -1, material = \"red\" }},\n]\n{HEAD}"
        );
        assert_eq!(
            msg(&text),
            "t.toml:3: sphere 2: sphere radius must be > 0, got -1"
        );
    }

    #[test]
    fn items_are_located_in_any_order_and_form() {
        let text = format!(
            "[[plane]]\npoint = [0, 0, 0]\nnormal = [0, 0, 0]\nmaterial = \"red\"\n\n{HEAD}\n\
             [[plane]]\npoint = [0, 0, 0]\nnormal = [0, 1, 0]\nmaterial = \"red\"\n"
        );
        assert_eq!(
            msg(&text),
            "t.toml:1: plane 1: plane normal has zero length, got [0, 0, 0]"
        );
        let text = format!("{HEAD}\n[[material]]\nname = \"glass\"\ntransparency = 0.9\nior = 5\n");
        assert_eq!(
            msg(&text),
            "t.toml:11: material 2 (\"glass\"): material refractive index must be in [1, 4], got 5"
        );
        let text =
            format!("{HEAD}\n[[box]]\nmin = [1, 0, 0]\nmax = [0, 1, 1]\nmaterial = \"red\"\n");
        assert_eq!(
            msg(&text),
            "t.toml:11: box 1: box min corner must be <= max corner on every axis, \
             got min [1, 0, 0] max [0, 1, 1]"
        );
        let text = format!(
            "{HEAD}\n[[triangle]]\nvertices = [[0, 0, 0], [1, 1, 1], [2, 2, 2]]\nmaterial = \"red\"\n"
        );
        assert_eq!(
            msg(&text),
            "t.toml:11: triangle 1: triangle vertices are collinear (zero area), \
             got [0, 0, 0], [1, 1, 1], [2, 2, 2]"
        );
    }

    #[test]
    fn unknown_material_is_named() {
        let text = format!(
            "{HEAD}{}\n[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"gold\"\n",
            sphere("1")
        );
        assert_eq!(msg(&text), "t.toml:16: sphere 2: unknown material \"gold\"");
    }

    #[test]
    fn duplicate_material_is_named() {
        let text = format!("{HEAD}\n[[material]]\nname = \"red\"\n");
        assert_eq!(
            msg(&text),
            "t.toml:11: material 2 (\"red\"): a material of the same name comes earlier"
        );
    }

    #[test]
    fn too_many_spheres_says_the_limit() {
        let mut text = HEAD.to_string();
        for i in 0..1025 {
            text.push_str(&format!(
                "[[sphere]]\ncenter = [{i}, 0, 0]\nradius = 0.5\nmaterial = \"red\"\n"
            ));
        }
        // The 1025th `[[sphere]]` header: 9 lines of HEAD, then 4 lines a sphere.
        assert_eq!(
            msg(&text),
            format!(
                "t.toml:{}: sphere 1025: too many spheres: the scene holds at most 1024",
                9 + 1024 * 4 + 1
            )
        );
    }

    #[test]
    fn bad_sampler_is_a_render_error() {
        let text = format!("{HEAD}\n[render]\nsampler = \"gauss\"\n");
        assert_eq!(
            msg(&text),
            "t.toml:11: render: sampler \"gauss\" is not one of corner, centre, prefiltered, offset:X,Y, \
             stratified:K (1-64), random:N (1-4096)"
        );
        let text = format!("{HEAD}\n[render]\nsampler = \"offset:0.5,1\"\n");
        assert_eq!(
            msg(&text),
            "t.toml:11: render: sub-pixel offset must be in [0, 1) on each axis"
        );
        let text = format!("{HEAD}\n[render]\ndepth = 9\n");
        assert_eq!(
            msg(&text),
            "t.toml:11: render: recursion depth 9 is above the maximum 8"
        );
        let text = format!("{HEAD}\n[render]\ntile = 12\n");
        assert_eq!(
            msg(&text),
            "t.toml:11: render: tile must be 8, 16 or 32, got 12"
        );
        let text = format!("{HEAD}\n[render]\nwidth = 0\n");
        assert_eq!(
            msg(&text),
            "t.toml:11: render: viewport must be at least 1x1 pixel, got 0x240"
        );
    }

    #[test]
    fn forward_and_look_at_together_are_refused() {
        let text = HEAD.replace(
            "look_at = [0, 0, 0]",
            "look_at = [0, 0, 0]\nforward = [0, 0, -1]",
        );
        assert_eq!(
            msg(&text),
            "t.toml:1: camera: give exactly one of `forward` and `look_at`"
        );
        let text = HEAD.replace("look_at = [0, 0, 0]\n", "");
        assert_eq!(
            msg(&text),
            "t.toml:1: camera: give exactly one of `forward` and `look_at`"
        );
        let text = HEAD.replace("near = 0.1", "near = 200");
        assert_eq!(
            msg(&text),
            "t.toml:1: camera: camera near distance must be smaller than the far distance, \
             got near 200 far 100"
        );
    }

    #[test]
    fn missing_file_names_the_path_and_reason() {
        let p = scenes_dir().join("no-such-scene.toml");
        let e = load(&p).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Read);
        let m = e.to_string();
        assert!(
            m.starts_with(&format!("{}: cannot read the scene file: ", p.display())),
            "{m}"
        );
        assert!(m.contains("No such file or directory"), "{m}");
    }
}
