//! Scene files: TOML text in the shape of [`SceneDesc`], read, checked and located.
//!
//! [`parse`] accepts a file only if it renders: after the TOML has the shape of a
//! scene, every value is checked by building the core scene, the render settings
//! and the frame. Errors say where: `FILE:LINE:COL: message` when the TOML is
//! malformed or has the wrong shape (syntax, unknown key, wrong type, missing key),
//! `FILE:LINE: item: message` when a value is refused (`sphere 2: sphere radius must
//! be > 0, got -1`, the line being where that item starts).
//!
//! Only a regular file is read, scene or OBJ file: a FIFO, a device, a socket or
//! a folder is refused before anything waits on it (its type is checked before
//! opening, and again on the handle, opened non-blocking). Before the TOML
//! parser sees the text, the file is bounded: at most [`MAX_FILE_BYTES`] are
//! read, and a pre-scan (module `prescan`) refuses arrays and inline tables nested deeper than
//! [`MAX_NESTING`], dotted keys and table headers of more than
//! [`MAX_KEY_PARTS`] parts, and lists with more items than the host scene holds
//! (counting `[[sphere]]` headers and the inline tables of a top-level
//! `sphere = [...]`), so neither the parser's memory nor its recursion depends on
//! what the file holds. [`warnings`] lists what is accepted but looks like a
//! mistake (`fovy = 1.05`, radians where degrees are meant).
//!
//! The built-in scenes exist as files too (`scenes/NAME.toml`, embedded); see
//! [`builtin_desc`].

use crate::desc::{DescError, MAX_TRIANGLES, SceneDesc, num};
use serde::Deserialize;
use std::fmt;
use std::io::Read;
use std::path::Path;
use tessera_core::builtin::Builtin;
use toml::de::{DeTable, DeValue};

mod prescan;
pub mod textures;
use prescan::prescan;

/// What kind of problem a [`FileError`] reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ErrorKind {
    /// The file could not be read (missing, unreadable, not a regular file, not
    /// UTF-8, larger than [`MAX_FILE_BYTES`]).
    Read,
    /// The text is not TOML or does not have the shape of a scene: a syntax error,
    /// an unknown key, a value of the wrong type, a missing key, a duplicate key,
    /// nesting deeper than [`MAX_NESTING`].
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

/// Control characters of the file name, item and message are escaped (see
/// [`crate::escape`]): a name from the command line or a string from the file
/// cannot drive the terminal.
impl fmt::Display for FileError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&crate::escape(&self.file))?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(column) = self.column {
                write!(f, ":{column}")?;
            }
        }
        f.write_str(": ")?;
        if let Some(item) = &self.item {
            write!(f, "{}: ", crate::escape(item))?;
        }
        f.write_str(&crate::escape(&self.message))
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

/// The largest scene file accepted, in bytes: 4 MiB. A scene that fills every
/// list of the host scene (1024 spheres, 64 planes, 8192 triangles, 1024 boxes,
/// 1024 cylinders, 1024 disks, 256 materials, 64 lights) with every number
/// written to full `f64` precision (20 characters each) is about 3 MB; the TOML parser needs up to about 80 bytes of memory a byte of
/// text (a file of `1,`), so this bounds parsing to about 330 MB (the release
/// binary's peak on 4 MiB of `1,`: 316 MiB).
pub const MAX_FILE_BYTES: usize = 4 << 20;

/// How deep arrays and inline tables may nest. A scene file needs at most 4
/// (`triangle = [{ vertices = [[0, 0, 0], ...] }]`); the bound keeps the
/// recursive TOML parser far from the end of its stack.
pub const MAX_NESTING: usize = 16;

/// The most parts of a dotted key (`a.b.c = 1`) or a table header (`[a.b.c]`).
/// A scene file needs at most 2 (`texture.kind = "checker"`); the TOML parser
/// refuses 80 or more, without saying where.
pub const MAX_KEY_PARTS: usize = 16;

/// Reads the scene file at `path` and parses it with [`parse`]; messages name the
/// file by `path` as given. At most [`MAX_FILE_BYTES`] + 1 bytes are read: a
/// larger file is refused before any parsing, with its size. A glTF file
/// (`.gltf`, `.glb`) is a scene of its own ([`load_gltf`], its first camera).
pub fn load(path: &Path) -> Result<SceneDesc, FileError> {
    if is_gltf(path) {
        return load_gltf(path, None);
    }
    load_limited(path, MAX_FILE_BYTES)
}

/// True when `path` names a glTF file (`.gltf`, `.glb`, any case).
#[must_use]
pub fn is_gltf(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}

/// A glTF file as a whole scene ([`crate::gltf::desc::scene`]: its meshes,
/// materials, lights and the camera named `camera` or its first), its images
/// read as a scene file's are, checked as a scene file is.
pub fn load_gltf(path: &Path, camera: Option<&str>) -> Result<SceneDesc, FileError> {
    let file = path.display().to_string();
    let fail = |message: String| FileError {
        kind: ErrorKind::Invalid,
        file: file.clone(),
        line: None,
        column: None,
        item: None,
        message,
    };
    let mut desc = crate::gltf::desc::scene(path, camera).map_err(fail)?;
    let base = path.parent().unwrap_or(Path::new(""));
    let images = textures::read_images(&mut desc, base).map_err(|(i, message)| FileError {
        item: Some(format!("material {}", i + 1)),
        ..fail(message)
    })?;
    desc.warnings.extend(images);
    desc.flush_subnormals();
    check(&desc).map_err(|e| FileError {
        item: Some(e.item.clone()),
        ..fail(e.message.clone())
    })?;
    Ok(desc)
}

/// [`load`] with a size limit of `limit` bytes.
fn load_limited(path: &Path, limit: usize) -> Result<SceneDesc, FileError> {
    let file = path.display().to_string();
    match read_limited(path, limit, "scene file", "") {
        Ok(text) => parse_limited(&text, &file, limit, path.parent().unwrap_or(Path::new(""))),
        Err(message) => Err(FileError {
            kind: ErrorKind::Read,
            file,
            line: None,
            column: None,
            item: None,
            message,
        }),
    }
}

/// The text of the file at `path` if it is a regular file (following symbolic
/// links) of UTF-8 of at most `limit` bytes, else the message (`what`: `scene
/// file`, `OBJ file`; `budget`: said after the message of a file above the
/// limit). Reads at most `limit + 1` bytes (a file whose size is known to be above
/// the limit is not read at all); opens it with [`open_regular`], so that nothing
/// waits on a FIFO or a device.
pub(crate) fn read_limited(
    path: &Path,
    limit: usize,
    what: &str,
    budget: &str,
) -> Result<String, String> {
    let bytes =
        read_bounded(path, limit, what)?.map_err(|size| too_big(size, limit, what) + budget)?;
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        let text = std::str::from_utf8(&e.as_bytes()[..at]).unwrap_or_default();
        let (line, column) = line_col(text, at);
        format!("cannot read the {what}: it is not UTF-8 text (invalid byte at {line}:{column})")
    })
}

/// The bytes of the regular file at `path` (opened with [`open_regular`]), or
/// `Err(size)` if it has more than `limit` (`None`: grown while read, the size
/// not known); the outer error is the message of a file that cannot be read.
/// The size is checked from the metadata before reading, and the read stops one
/// byte past the limit.
pub(crate) fn read_bounded(
    path: &Path,
    limit: usize,
    what: &str,
) -> Result<Result<Vec<u8>, Option<u64>>, String> {
    let file = open_regular(path, what)?;
    let size = file.metadata().ok().map(|m| m.len());
    if let Some(n) = size.filter(|&n| n > limit as u64) {
        return Ok(Err(Some(n)));
    }
    let mut bytes = Vec::new();
    file.take(limit as u64 + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read the {what}: {e}"))?;
    if bytes.len() > limit {
        return Ok(Err(None));
    }
    Ok(Ok(bytes))
}

/// [`read_bounded`], a file above the limit refused with [`too_big`]'s message.
pub(crate) fn read_bytes(path: &Path, limit: usize, what: &str) -> Result<Vec<u8>, String> {
    read_bounded(path, limit, what)?.map_err(|size| too_big(size, limit, what))
}

/// The file at `path` opened for reading if it is a regular file (following
/// symbolic links), else the message naming what it is (`cannot read the OBJ
/// file: it is a FIFO (named pipe), not a regular file`). Nothing waits: the type
/// is checked before opening (opening a FIFO for reading waits for a writer; a
/// device may do anything), then the file is opened non-blocking and its type
/// checked again on the handle, so that a FIFO or a device put in its place
/// between the two is refused too, at once.
pub(crate) fn open_regular(path: &Path, what: &str) -> Result<std::fs::File, String> {
    let meta = std::fs::metadata(path).map_err(|e| format!("cannot read the {what}: {e}"))?;
    regular(&meta, what)?;
    open_checked(path, what)
}

/// The second half of [`open_regular`]: opens `path` without waiting and checks
/// the type of what it opened.
fn open_checked(path: &Path, what: &str) -> Result<std::fs::File, String> {
    let cannot = |e: std::io::Error| format!("cannot read the {what}: {e}");
    let file = open_nonblocking(path).map_err(cannot)?;
    regular(&file.metadata().map_err(cannot)?, what)?;
    Ok(file)
}

/// Nothing if `m` is a regular file's, else the message naming what it is.
fn regular(m: &std::fs::Metadata, what: &str) -> Result<(), String> {
    if m.is_file() {
        Ok(())
    } else {
        Err(format!(
            "cannot read the {what}: it is {}, not a regular file",
            crate::text::file_kind(&m.file_type())
        ))
    }
}

/// Opens `path` for reading without waiting: `O_NONBLOCK` (a FIFO opens at once,
/// with or without a writer; on a regular file it changes nothing) and
/// `O_NOCTTY` (a terminal does not become the controlling one).
#[cfg(unix)]
fn open_nonblocking(path: &Path) -> std::io::Result<std::fs::File> {
    use std::os::unix::fs::OpenOptionsExt;
    std::fs::OpenOptions::new()
        .read(true)
        .custom_flags(libc::O_NONBLOCK | libc::O_NOCTTY)
        .open(path)
}

/// Elsewhere, a plain open (after the type check).
#[cfg(not(unix))]
fn open_nonblocking(path: &Path) -> std::io::Result<std::fs::File> {
    std::fs::File::open(path)
}

/// The message for a file (`what`: `scene file`, `OBJ file`) above the limit.
pub(crate) fn too_big(size: Option<u64>, limit: usize, what: &str) -> String {
    let limit = format!(
        "the limit of {limit} bytes ({} MiB)",
        num(limit as f64 / 1_048_576.0)
    );
    match size {
        Some(n) => format!("the {what} is {n} bytes, more than {limit}"),
        None => format!("the {what} is larger than {limit}"),
    }
}

/// Parses the scene file `text` and checks that it renders (core scene, render
/// settings and frame all accepted). `name` is what messages call the file.
///
/// A text above [`MAX_FILE_BYTES`], or nesting too deep, or with too many items of
/// a list, is refused by a pre-scan (see the module doc) before the TOML parser runs.
///
/// The OBJ files of its `[[mesh]]`es are read relative to the current folder
/// ([`load`]: to the scene file's folder).
pub fn parse(text: &str, name: &str) -> Result<SceneDesc, FileError> {
    parse_limited(text, name, MAX_FILE_BYTES, Path::new(""))
}

/// [`parse`] with a size limit of `limit` bytes.
fn parse_limited(
    text: &str,
    name: &str,
    limit: usize,
    base: &Path,
) -> Result<SceneDesc, FileError> {
    let fail = |kind, line, column, item, message| FileError {
        kind,
        file: name.to_string(),
        line,
        column,
        item,
        message,
    };
    if text.len() > limit {
        let message = too_big(Some(text.len() as u64), limit, "scene file");
        return Err(fail(ErrorKind::Read, None, None, None, message));
    }
    prescan(text).map_err(|r| {
        let (line, column) = line_col(text, r.byte);
        match r.item {
            Some(item) => fail(ErrorKind::Invalid, Some(line), None, Some(item), r.message),
            None => fail(ErrorKind::Toml, Some(line), Some(column), None, r.message),
        }
    })?;
    let toml_error = |e| {
        let (line, column, message) = toml_message(text, &e);
        fail(ErrorKind::Toml, line, column, None, message)
    };
    // Parsed once: the spanned tables give the items' positions, then the scene.
    let root = DeTable::parse(text).map_err(toml_error)?;
    let places = Places::of(root.get_ref());
    let mut desc =
        SceneDesc::deserialize(toml::de::Deserializer::from(root)).map_err(toml_error)?;
    // The meshes' faces, read until the triangle list is full: no more OBJ text
    // than fits (and than `MAX_OBJ_BYTES`) is ever read.
    let mut room = MAX_TRIANGLES.saturating_sub(desc.triangles.len());
    let mut budget = crate::mesh::MAX_OBJ_BYTES;
    // Turned boxes become meshes of their triangles, after the file's meshes.
    let mut turned = Vec::new();
    let mut kept = Vec::with_capacity(desc.boxes.len());
    for (i, b) in std::mem::take(&mut desc.boxes).into_iter().enumerate() {
        let refuse = |message| {
            let item = format!("box {}", i + 1);
            let line = places.start(&item).map(|b| line_col(text, b).0);
            fail(ErrorKind::Invalid, line, None, Some(item.clone()), message)
        };
        match crate::mesh::turned_box(&b, i).map_err(refuse)? {
            Some(m) => {
                // The box's own checks (its corners, min below max) before it
                // is turned, as an axis-aligned box's.
                let item = crate::desc::Item::new(&format!("box {}", i + 1));
                <tessera_core::geometry::Aabb as crate::kinds::HostKind>::core(&item, &b)
                    .map_err(|e| refuse(e.message))?;
                turned.push(m);
            }
            None => kept.push(b),
        }
    }
    desc.boxes = kept;
    let mut meshes = Vec::with_capacity(desc.meshes.len());
    for (i, mut mesh) in std::mem::take(&mut desc.meshes).into_iter().enumerate() {
        let refuse = |message| {
            let item = format!("mesh {}", i + 1);
            let line = places.start(&item).map(|b| line_col(text, b).0);
            fail(ErrorKind::Invalid, line, None, Some(item), message)
        };
        let read = crate::mesh::read_file(&mesh, base, &mut budget, room).map_err(refuse)?;
        room -= read.faces.len();
        if mesh.material.is_none() {
            let parts =
                crate::mesh::by_material(mesh, read, &mut desc.materials, &mut desc.embedded)
                    .map_err(refuse)?;
            meshes.extend(parts);
        } else {
            mesh.normals = read.all_normals();
            mesh.uvs = read.all_uvs();
            mesh.faces = read.faces;
            mesh.degenerate = read.degenerate;
            mesh.warnings = read.warnings;
            desc.embedded.extend(read.embedded);
            meshes.push(mesh);
        }
    }
    meshes.extend(turned);
    desc.meshes = meshes;
    let images = textures::read_images(&mut desc, base).map_err(|(i, message)| {
        let item = format!("material {}", i + 1);
        let line = places.start(&item).map(|b| line_col(text, b).0);
        fail(ErrorKind::Invalid, line, None, Some(item), message)
    })?;
    desc.warnings.extend(images);
    desc.flush_subnormals();
    check(&desc).map_err(|e| {
        let line = places.start(&e.item).map(|b| line_col(text, b).0);
        // A value refused because the rule for subnormal numbers read it as 0
        // (a radius of 1e-45): say so, the message shows the 0.
        let why: Vec<String> = desc
            .flushed
            .iter()
            .filter(|f| f.item == e.item)
            .map(|f| {
                format!(
                    "{} {} is subnormal in f32 and reads as 0",
                    f.key,
                    num(f.value)
                )
            })
            .collect();
        let message = if why.is_empty() {
            e.message
        } else {
            format!("{}: the file's {}", e.message, why.join(", "))
        };
        fail(ErrorKind::Invalid, line, None, Some(e.item), message)
    })?;
    Ok(desc)
}

/// Where in `text` a TOML error is (line and column, when known) and its message
/// (a duplicate key named, control characters escaped).
fn toml_message(text: &str, e: &toml::de::Error) -> (Option<usize>, Option<usize>, String) {
    let (line, column) = e.span().map(|span| line_col(text, span.start)).unzip();
    let mut message = e.message().trim().to_string();
    if message == "duplicate key"
        && let Some(key) = e.span().and_then(|s| key_at(text, s))
    {
        message = format!("duplicate key `{key}`");
    }
    (line, column, crate::escape(&shortest_floats(&message)))
}

/// `message` with the number of each ``floating point `X` `` (serde's words for a
/// float where another type is expected, `X` in every digit: 5e-324 as 330
/// characters) in the shortest form of [`num`], marked as a float (`1e300`,
/// `-0.5`, `100000.0`).
fn shortest_floats(message: &str) -> String {
    const FLOAT: &str = "floating point `";
    let mut out = String::new();
    let mut rest = message;
    while let Some(at) = rest.find(FLOAT) {
        let start = at + FLOAT.len();
        out.push_str(&rest[..start]);
        rest = &rest[start..];
        let end = rest.find('`').unwrap_or(rest.len());
        match rest[..end].parse::<f64>() {
            Ok(x) => {
                let short = num(x);
                out.push_str(&short);
                if short.bytes().all(|b| b.is_ascii_digit() || b == b'-') {
                    out.push_str(".0");
                }
            }
            Err(_) => out.push_str(&rest[..end]),
        }
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

/// The key of a TOML error's `span` (which covers the last part of a key) as
/// written, with the dotted parts before it (`a.b`), at most 64 characters; `None`
/// if the span is not text.
fn key_at(text: &str, span: std::ops::Range<usize>) -> Option<String> {
    let end = span.end.min(text.len());
    let last = text.get(span.start..end)?;
    let before = text.get(..span.start)?;
    let dotted = before
        .char_indices()
        .rev()
        .take_while(|&(_, c)| {
            c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.' | ' ' | '\t')
        })
        .last()
        .map_or(span.start, |(i, _)| i);
    let key = format!("{}{last}", &before[dotted..]);
    let key = key.trim().trim_start_matches(['.', ' ', '\t']);
    if key.is_empty() {
        return None;
    }
    let mut shown: String = key.chars().take(64).collect();
    if shown.len() < key.len() {
        shown.push('…');
    }
    Some(shown)
}

/// What a scene file says that is accepted but looks like a mistake, one line
/// each, as `item: message` (empty for a file that looks as meant):
///
/// - `fovy` below pi (3.14159...) degrees: a value like `1.05` was most likely
///   meant in radians; the warning gives the degrees it would be. (From pi up,
///   the value read as radians would be 180 degrees or more, no field of view, so
///   a narrow angle such as the built-in `interference` scene's 4 degrees is
///   meant.)
/// - nothing lights the surfaces (no light with a non-zero intensity and colour,
///   and a black `ambient`): every surface renders black but for what it reflects
///   or transmits.
/// - a reflective or transparent material with render `depth = 0`: no reflected or
///   refracted ray is traced, the weight has no effect.
///
/// Strings from the file are escaped as in errors.
pub fn warnings(desc: &SceneDesc) -> Vec<String> {
    let mut out = Vec::new();
    let fovy = desc.camera.fovy;
    if fovy > 0.0 && fovy < std::f64::consts::PI {
        out.push(format!(
            "camera: fovy {} is less than pi degrees: it looks like radians \
             ({} radians would be fovy = {:.1}); fovy is in degrees",
            num(fovy),
            num(fovy),
            fovy.to_degrees()
        ));
    }
    out.extend(desc.warnings.iter().cloned());
    for (i, m) in desc.meshes.iter().enumerate() {
        for w in &m.warnings {
            out.push(format!("mesh {} ({:?}): {w}", i + 1, m.obj));
        }
        if m.degenerate > 0 {
            out.push(format!(
                "mesh {} ({:?}): {} of its faces left out: their vertices are collinear \
                 (zero area, nothing to hit)",
                i + 1,
                m.obj,
                m.degenerate
            ));
        }
    }
    let lit = desc
        .lights
        .iter()
        .any(|l| l.intensity > 0.0 && l.color.iter().any(|&c| c > 0.0));
    let mut has_geometry = !desc.meshes.is_empty();
    crate::kinds::each_kind!(|G| {
        has_geometry |= !<G as crate::kinds::Listed>::descs(desc).is_empty();
    });
    if has_geometry && !lit && desc.ambient.iter().all(|&c| c <= 0.0) {
        out.push(
            "scene: nothing lights the surfaces (no light with intensity > 0 and \
             ambient = [0, 0, 0]): they render black but for what they reflect or transmit"
                .to_string(),
        );
    }
    if desc.render.depth == 0 {
        for (i, m) in desc.materials.iter().enumerate() {
            let what = match (m.reflectivity > 0.0, m.transparency > 0.0) {
                (true, true) => "reflectivity and transparency have",
                (true, false) => "reflectivity has",
                (false, true) => "transparency has",
                (false, false) => continue,
            };
            out.push(format!(
                "material {} ({:?}): {what} no effect with [render] depth = 0 \
                 (no reflected or refracted ray is traced; depth >= 1 traces them)",
                i + 1,
                m.name
            ));
        }
    }
    const FLUSHED_SHOWN: usize = 4;
    out.extend(
        desc.flushed
            .iter()
            .take(FLUSHED_SHOWN)
            .map(ToString::to_string),
    );
    if desc.flushed_count > FLUSHED_SHOWN {
        out.push(format!(
            "{} more subnormal number(s) read as 0 (the first {FLUSHED_SHOWN} are named above)",
            desc.flushed_count - FLUSHED_SHOWN
        ));
    }
    out.extend(crate::precision::warnings(desc));
    out.iter().map(|w| crate::escape(w)).collect()
}

/// Checks everything the renderer will check: the core scene, the settings, and
/// the frame at the file's viewport.
fn check(desc: &SceneDesc) -> Result<(), DescError> {
    let scene = desc.to_core()?;
    let settings = desc.settings()?;
    let vp = desc.viewport();
    tessera_core::Renderer::try_new(scene.camera(), vp, settings).map_err(|e| {
        let c = &desc.camera;
        match e {
            tessera_core::Error::EmptyViewport => DescError {
                item: "render".into(),
                message: format!("{e}, got {}x{}", vp.width, vp.height),
            },
            _ => DescError {
                item: "camera".into(),
                message: format!(
                    "{e}, got near {} and fovy {} at {}x{}",
                    num(c.near),
                    num(c.fovy),
                    vp.width,
                    vp.height
                ),
            },
        }
    })?;
    Ok(())
}

/// Where each item of a scene file starts, read from the spans of the parsed
/// file: per top-level key, the byte of its value (the `[camera]` table, ...) and
/// of each element when it is an array (each `[[sphere]]` or inline table of
/// `sphere = [...]`).
struct Places(Vec<(String, usize, Vec<usize>)>);

impl Places {
    fn of(root: &DeTable<'_>) -> Self {
        let places = root.iter().map(|(key, value)| {
            let elements = match value.get_ref() {
                DeValue::Array(items) => items.iter().map(|v| v.span().start).collect(),
                _ => Vec::new(),
            };
            (key.get_ref().to_string(), value.span().start, elements)
        });
        Self(places.collect())
    }

    /// The byte where `item` (`camera`, `sphere 3`, `material 2 ("red")`, ...)
    /// starts: its `[[sphere]]`/`[camera]` header, its inline table, or its key.
    fn start(&self, item: &str) -> Option<usize> {
        let mut words = item.split_whitespace();
        let key = words.next()?;
        let (_, start, elements) = self.0.iter().find(|(k, ..)| k == key)?;
        match words.next() {
            None => Some(*start),
            Some(n) => elements
                .get(n.parse::<usize>().ok()?.checked_sub(1)?)
                .copied(),
        }
    }
}

/// The built-in scene as a description, parsed from its embedded file (which the
/// tests check renders exactly like the core's built-in scene).
pub fn builtin_desc(b: Builtin) -> SceneDesc {
    let name = format!("scenes/{}.toml", b.name());
    parse(b.source(), &name)
        .unwrap_or_else(|e| panic!("the embedded built-in scene file is broken: {e}"))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;
    #[cfg(feature = "cli")]
    use tessera_core::Viewport;

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
    #[cfg(feature = "cli")]
    fn render_desc(d: &SceneDesc, vp: Viewport) -> image::RgbImage {
        let s = d.to_core().unwrap();
        s.with_view(|v| crate::render(v, s.camera(), vp, d.settings().unwrap(), d.render.tile))
            .unwrap()
    }

    #[test]
    #[cfg(feature = "cli")] // renders
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
        for &b in Builtin::ALL {
            let name = format!("{}.toml", b.name());
            assert!(files.iter().any(|f| f.ends_with(&name)), "{name} missing");
        }
    }

    #[test]
    #[cfg(feature = "cli")] // renders
    fn builtin_files_render_exactly_like_the_core_scenes() {
        for &b in Builtin::ALL {
            let d = builtin_desc(b);
            let s = d.to_core().unwrap();
            let vp = Viewport::new(96, 72);
            let from_file = s
                .with_view(|v| crate::render(v, s.camera(), vp, b.settings(), 16))
                .unwrap();
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
        for &b in Builtin::ALL {
            let d = builtin_desc(b);
            let s = d.to_core().unwrap();
            let cam = *s.camera();
            s.with_view(|file| {
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
                    let (fm, cm) = (file.meshes(), core.meshes());
                    assert_eq!(fm.len(), cm.len(), "{n}: meshes");
                    for (f, c) in fm.iter().zip(cm) {
                        assert_eq!(f.vertices(), c.vertices(), "{n}: mesh vertices");
                        assert_eq!(f.faces(), c.faces(), "{n}: mesh faces");
                        assert_eq!(f.normals(), c.normals(), "{n}: mesh normals");
                        assert_eq!(f.material(), c.material(), "{n}: mesh material");
                    }
                })
            })
            .unwrap();
        }
    }

    #[test]
    fn builtin_files_have_the_builtin_settings() {
        for &b in Builtin::ALL {
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
        // A float where an integer is expected: in its shortest form, not all
        // its digits (5e-324 has 330 of them).
        for (written, shown) in [
            ("5e-324", "5e-324"),
            ("1e300", "1e300"),
            ("-0.5", "-0.5"),
            ("1e5", "100000.0"),
            ("2.5", "2.5"),
            ("-inf", "-inf"),
        ] {
            let m = msg(&format!("{HEAD}\n[render]\nwidth = {written}\n"));
            assert_eq!(
                m,
                format!("t.toml:12:9: invalid type: floating point `{shown}`, expected u16")
            );
        }
        let m = msg(&format!("{HEAD}\n[render]\ndepth = 1e-300\n"));
        assert_eq!(
            m,
            "t.toml:12:9: invalid type: floating point `1e-300`, expected u8"
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

    /// An image texture whose file is missing, or not an image, or of an
    /// unknown texel format: refused, naming the material, its line and the file.
    #[test]
    fn a_bad_image_texture_is_refused_by_name() {
        let dir = tempfile::tempdir().unwrap();
        let scene = |extra: &str| {
            format!(
                "{HEAD}\n{extra}[[material]]\nname = \"logo\"\ntexture = {{ kind = \"image\", file = \"logo.png\" }}\n"
            )
        };
        let path = dir.path().join("s.toml");
        std::fs::write(&path, scene("")).unwrap();
        let e = load(&path).unwrap_err().to_string();
        assert!(e.contains("material 2") && e.contains("logo.png"), "{e}");
        std::fs::write(dir.path().join("logo.png"), "not a picture").unwrap();
        let e = load(&path).unwrap_err().to_string();
        assert!(e.contains("logo.png") && e.contains("PNG and JPEG"), "{e}");
        std::fs::write(&path, scene("[render]\ntexture_format = \"rgb888\"\n")).unwrap();
        let e = load(&path).unwrap_err().to_string();
        assert!(e.contains("texture_format") && e.contains("rgb888"), "{e}");
    }

    /// A light is a point light or a sun: neither, both, or a sun without a
    /// direction are refused where they are written.
    #[test]
    fn a_light_has_a_position_or_a_direction() {
        let text = format!(
            "{HEAD}\n[[light]]\nposition = [0, 1, 0]\ndirection = [0, -1, 0]\nintensity = 1\n"
        );
        assert_eq!(
            msg(&text),
            "t.toml:11:1: a light has a position (a point light) or a direction \
             (a directional light, a sun), not both"
        );
        let text = format!("{HEAD}\n[[light]]\nintensity = 1\n");
        assert!(msg(&text).contains("a light needs a position (a point light) or a direction"));
        let text = format!("{HEAD}\n[[light]]\ndirection = [0, 0, 0]\nintensity = 1\n");
        assert_eq!(
            msg(&text),
            "t.toml:11: light 1: light direction has zero length, got [0, 0, 0]"
        );
        let text = format!("{HEAD}\n[[light]]\ndirection = [0, -2, 0]\nintensity = 3\n");
        let d = parse(&text, "t.toml").unwrap();
        let core = d.to_core().unwrap();
        let l = core.with_view(|v| v.lights()[0]);
        assert_eq!(
            l.kind(),
            tessera_core::light::LightKind::Directional(tessera_core::Vec3::Y)
        );
        assert_eq!(l.intensity(), 3.0);
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
            "t.toml:11: render: sampler \"gauss\": unknown sampler: the samplers are corner, \
             centre, prefiltered, offset:X,Y (each in [0, 1)), stratified:K (1-64), random:N \
             (1-4096), adaptive:K (2-64) or adaptive:K,T (T: 0-255), and sparse, sparse:T \
             (T: 0-255) or sparse:T,S (S: 2 or 4)"
        );
        let text = format!("{HEAD}\n[render]\nsampler = \"offset:0.5,1\"\n");
        assert_eq!(
            msg(&text),
            "t.toml:11: render: sampler \"offset:0.5,1\": sub-pixel offset must be in [0, 1) on each axis"
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
        let text = format!("{HEAD}\n[render]\nencoding = \"gamma\"\n");
        assert_eq!(
            msg(&text),
            "t.toml:11: render: encoding \"gamma\": expected an encoding: linear or srgb"
        );
        let text = format!("{HEAD}\n[render]\nencoding = \"SRGB\"\n");
        assert_eq!(
            desc(&text).settings().unwrap().encoding,
            tessera_core::Encoding::Srgb
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

    /// A directory under the system temp folder, removed with its contents when
    /// dropped (also when the test fails).
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(tag: &str) -> Self {
            use std::sync::atomic::{AtomicUsize, Ordering};
            static N: AtomicUsize = AtomicUsize::new(0);
            let n = N.fetch_add(1, Ordering::Relaxed);
            let dir =
                std::env::temp_dir().join(format!("tessera-file-{tag}-{}-{n}", std::process::id()));
            std::fs::create_dir_all(&dir).unwrap();
            Self(dir)
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    /// A valid scene padded with a comment to exactly `len` bytes.
    fn padded(len: usize) -> String {
        let mut t = format!("{HEAD}#");
        t.push_str(&"x".repeat(len - t.len()));
        t
    }

    #[test]
    fn text_above_the_limit_is_refused_with_its_size() {
        let limit = 400;
        assert!(parse_limited(&padded(limit), "t.toml", limit, Path::new("")).is_ok());
        let e = parse_limited(&padded(limit + 1), "t.toml", limit, Path::new("")).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Read);
        assert_eq!(
            e.to_string(),
            "t.toml: the scene file is 401 bytes, more than the limit of 400 bytes \
             (0.0003814697265625 MiB)"
        );
    }

    #[test]
    fn file_above_the_limit_is_refused_before_it_is_read() {
        let dir = TempDir::new("size");
        let p = dir.0.join("big.toml");
        std::fs::write(&p, padded(500)).unwrap();
        assert!(load_limited(&p, 500).is_ok());
        let e = load_limited(&p, 499).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Read);
        assert!(
            e.message
                .starts_with("the scene file is 500 bytes, more than the limit of 499 bytes"),
            "{e}"
        );
        // The real limit, with a sparse file one byte over it (nothing is written
        // to disk, nothing is read: the size alone refuses it).
        let f = std::fs::File::create(&p).unwrap();
        f.set_len(MAX_FILE_BYTES as u64 + 1).unwrap();
        drop(f);
        let e = load(&p).unwrap_err();
        assert_eq!(
            e.to_string(),
            format!(
                "{}: the scene file is 4194305 bytes, more than the limit of 4194304 bytes (4 MiB)",
                p.display()
            )
        );
    }

    /// A device, a FIFO, a socket or a folder is refused before anything is read
    /// from it or waits on it (/dev/zero would be read up to the limit, a FIFO
    /// would wait for a writer forever).
    #[cfg(unix)]
    #[test]
    fn an_input_that_is_not_a_regular_file_is_refused_unread() {
        let e = load_limited(Path::new("/dev/zero"), 1000).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Read);
        assert_eq!(
            e.to_string(),
            "/dev/zero: cannot read the scene file: it is a character device, not a regular file"
        );
        let dir = TempDir::new("kinds");
        let e = load(&dir.0).unwrap_err();
        assert!(
            e.message.ends_with("it is a folder, not a regular file"),
            "{e}"
        );
        let fifo = dir.0.join("fifo.toml");
        let made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap();
        assert!(made.success());
        let e = load(&fifo).unwrap_err();
        assert!(
            e.message
                .ends_with("it is a FIFO (named pipe), not a regular file"),
            "{e}"
        );
        // A FIFO that takes the place of a regular file after the type check is
        // opened without waiting and refused on its handle.
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let _ = tx.send(open_checked(&fifo, "OBJ file").map(drop));
        });
        let opened = rx
            .recv_timeout(std::time::Duration::from_secs(20))
            .expect("opening a FIFO waited");
        assert_eq!(
            opened,
            Err("cannot read the OBJ file: it is a FIFO (named pipe), not a regular file".into())
        );
    }

    #[test]
    fn not_utf8_says_where() {
        let dir = TempDir::new("utf8");
        let p = dir.0.join("latin1.toml");
        std::fs::write(&p, b"# ok\n# caf\xe9\n").unwrap();
        let e = load(&p).unwrap_err();
        assert_eq!(e.kind, ErrorKind::Read);
        assert_eq!(
            e.message,
            "cannot read the scene file: it is not UTF-8 text (invalid byte at 2:6)"
        );
    }

    #[test]
    fn deep_nesting_is_refused_before_parsing_with_its_place() {
        let text = format!("a = {}\n{HEAD}", "[".repeat(50_000));
        let e = parse(&text, "t.toml").unwrap_err();
        assert_eq!(e.kind, ErrorKind::Toml);
        assert_eq!(
            e.to_string(),
            "t.toml:1:21: arrays and inline tables nested more than 16 deep"
        );
        // Inline tables and arrays mixed, on a later line, closed or not.
        let deep = "{ a = [".repeat(10) + &"] }".repeat(10);
        let m = msg(&format!("{HEAD}x = {deep}\n"));
        assert_eq!(
            m,
            "t.toml:10:61: arrays and inline tables nested more than 16 deep"
        );
        // Nesting at the limit reaches the parser (and is refused for its shape).
        let ok = format!("{}{}", "[".repeat(16), "]".repeat(16));
        assert_eq!(prescan(&format!("x = {ok}\n")), Ok(()));
        // A header is no nesting, but a header that is not one is brackets.
        assert_eq!(prescan("[[sphere]]\n[camera]\n"), Ok(()));
        assert_eq!(prescan(&"[".repeat(17)).unwrap_err().byte, 16);
    }

    #[test]
    fn brackets_in_strings_and_comments_do_not_count() {
        let many = "[{".repeat(40);
        let fine = [
            format!("# {many}\n"),
            format!("a = \"{many}\" # {many}\n"),
            format!("a = \"\\\"{many}\"\n"),
            format!("a = '{many}'\n"),
            format!("a = \"\"\"\n{many}\n\\\"\"\" {many}\n\"\"\"\n"),
            format!("a = '''\n{many}''{many}\n''''\n"),
        ];
        for t in &fine {
            assert_eq!(prescan(t), Ok(()), "{t}");
        }
        // The closers in strings and in the comment do not close the array.
        let t = format!("a = [\"]]]]\", '}}}}', \"\"\"]\"\"\" # ]]]]\nb = {many}\n");
        let r = prescan(&t).unwrap_err();
        assert_eq!(line_col(&t, r.byte), (2, 20), "{t}");
        // An unclosed string ends at its line, as for the parser.
        let t = format!("a = \"x\nb = {many}\n");
        assert_eq!(line_col(&t, prescan(&t).unwrap_err().byte), (2, 21));
        // In comments, such text is no error: whole files parse.
        let text = format!("# [[sphere]] [[[[ {many}\n{HEAD}");
        assert!(parse(&text, "t.toml").is_ok());
        let text = format!(
            "{HEAD}\n[[sphere]] # {many}\ncenter = [0, 0, 0] # {many}\nradius = 1\n\
             material = \"red\"\n"
        );
        assert!(parse(&text, "t.toml").is_ok());
    }

    /// Keys and headers of more than 16 parts are refused at the dot before the
    /// 17th, wherever a key may be; dots in strings, comments and values are no
    /// parts.
    #[test]
    fn keys_of_too_many_parts_are_refused_where_keys_are() {
        let parts = |n: usize, sep: &str| vec!["k"; n].join(sep);
        let at = |t: &str| prescan(t).map_err(|r| line_col(t, r.byte));
        for fine in [
            format!("{} = 1\n", parts(16, ".")),
            format!("{} = 1\n", parts(16, " . ")),
            format!("[{}]\n[[{}]]\n", parts(16, "."), parts(16, ".")),
            format!(
                "a = {{ {} = 1, {} = [1.5, 2.5] }}\n",
                parts(16, "."),
                parts(16, ".")
            ),
            format!(
                "\"{}\".'{}' = \"{}\"\n",
                parts(40, "."),
                parts(40, "."),
                parts(40, ".")
            ),
            format!("a = [{}]\n", vec!["1.5"; 40].join(", ")),
            format!("a = 1.5 # {}\n", parts(40, ".")),
            format!("a = \"\"\"\n{}\n\"\"\"\n", parts(40, ".")),
            format!("a = [{{ b = 1 }}, 1.{}]\n", "5".repeat(40)),
        ] {
            assert_eq!(prescan(&fine), Ok(()), "{fine}");
        }
        for (text, place) in [
            (format!("{} = 1\n", parts(17, ".")), (1, 32)),
            (format!("x = 1\n{} = 1\n", parts(17, " . ")), (2, 63)),
            (format!("[{}]\n", parts(17, ".")), (1, 33)),
            (format!("[{}\n", parts(17, ".")), (1, 33)),
            (format!("[[\"a.b\".{}]]\n", parts(16, ".")), (1, 38)),
            (
                format!("a = {{ b = 1, {} = 2 }}\n", parts(17, ".")),
                (1, 45),
            ),
            (
                format!("a = [{{ b = [1.5, {{ {} = 1 }}] }}]\n", parts(17, ".")),
                (1, 51),
            ),
        ] {
            assert_eq!(at(&text), Err(place), "{text}");
        }
        let e = parse(&format!("{}{HEAD}", parts(100_000, ".")), "t.toml").unwrap_err();
        assert_eq!(
            e.to_string(),
            "t.toml:1:32: a dotted key or table header has more than 16 parts"
        );
    }

    /// 1025 bare `[[sphere]]` headers: refused at the 1025th by the pre-scan (the
    /// parser would first complain that sphere 1 has no `center`).
    #[test]
    fn too_many_items_are_refused_at_their_header_before_parsing() {
        let text = format!("{HEAD}{}", "[[sphere]]\n".repeat(1025));
        assert_eq!(
            msg(&text),
            "t.toml:1034: sphere 1025: too many spheres: the scene holds at most 1024"
        );
        let text = format!("{HEAD}{}", "[[ \"light\" ]] # a light\n".repeat(65));
        assert_eq!(
            msg(&text),
            "t.toml:74: light 65: too many lights: the scene holds at most 64"
        );
        let text = format!("{HEAD}{}", "[[triangle]]\n".repeat(8193));
        let e = parse(&text, "t.toml").unwrap_err();
        assert_eq!(e.kind, ErrorKind::Invalid);
        assert_eq!(e.item.as_deref(), Some("triangle 8193"));
        // Inline: counted at the item's `{`, on any line.
        let items = "{},\n".repeat(257);
        let text = format!("material = [\n{items}]\n{HEAD}");
        assert_eq!(
            msg(&text),
            "t.toml:258: material 257: too many materials: the scene holds at most 256"
        );
        let text = format!("'plane' = [{}]\n{HEAD}", "{ a = [{}] }, ".repeat(65));
        assert_eq!(
            msg(&text),
            "t.toml:1: plane 65: too many planes: the scene holds at most 64"
        );
        // Not lists: a key of a table, dotted headers, strings.
        let t = format!("[camera]\nsphere = [{}]\n", "{},".repeat(2000));
        assert_eq!(prescan(&t), Ok(()));
        assert_eq!(prescan(&"[[material.texture]]\n".repeat(300)), Ok(()));
        assert_eq!(
            prescan(&format!("a = \"{}\"\n", "[[box]]".repeat(2000))),
            Ok(())
        );
    }

    #[test]
    fn numbers_beyond_f32_say_too_large() {
        let text =
            format!("{HEAD}\n[[sphere]]\ncenter = [0, 0, 1e39]\nradius = 1\nmaterial = \"red\"\n");
        assert_eq!(
            msg(&text),
            "t.toml:11: sphere 1: sphere center is too large for f32 (largest 3.4e38), \
             got [0, 0, 1e39]"
        );
        assert_eq!(
            msg(&format!("{HEAD}{}", sphere("-1e300"))),
            "t.toml:11: sphere 1: sphere radius is too large for f32 (largest 3.4e38), \
             got -1e300"
        );
        assert_eq!(
            msg(&HEAD.replace("far = 100", "far = 4e38")),
            "t.toml:1: camera: camera far distance is too large for f32 (largest 3.4e38), \
             got 4e38"
        );
        let m = msg(&format!(
            "{HEAD}\n[[material]]\nname = \"y\"\ntexture = {{ kind = \"young\", \
             color = [1, 1, 1], d = 1e39, wavelength = 5e-7, distance = 3 }}\n"
        ));
        assert_eq!(
            m,
            "t.toml:11: material 2 (\"y\"): texture d is too large for f32 (largest 3.4e38), \
             got 1e39"
        );
        let m = msg(&format!(
            "{HEAD}\n[[light]]\nposition = [0, 5, 0]\nintensity = 1e40\n"
        ));
        assert_eq!(
            m,
            "t.toml:11: light 1: light intensity is too large for f32 (largest 3.4e38), \
             got 1e40"
        );
        // The largest f32, written as printed, fits (and is refused for its range).
        let m = msg(&format!("{HEAD}{}", sphere("3.4028235e38")));
        assert!(m.contains("sphere radius must be in"), "{m}");
    }

    #[test]
    fn numbers_are_printed_short() {
        assert_eq!(
            msg(&format!("{HEAD}{}", sphere("-1.5e-30"))),
            "t.toml:11: sphere 1: sphere radius must be > 0, got -1.5e-30"
        );
        let m = msg(&HEAD.replace("near = 0.1", "near = 1e-15\nfovy = 1e-20"));
        assert!(
            m.ends_with("got near 1e-15 and fovy 1e-20 at 320x240"),
            "{m}"
        );
        let m = msg(&HEAD.replace("near = 0.1", "near = 2e20"));
        assert!(m.ends_with("got near 2e20 far 100"), "{m}");
    }

    #[test]
    fn young_texture_with_a_bad_colour_shows_the_colour() {
        let young = |color: &str, wavelength: &str| {
            msg(&format!(
                "{HEAD}\n[[material]]\nname = \"y\"\ntexture = {{ kind = \"young\", \
                 color = {color}, d = 0.002, wavelength = {wavelength}, distance = 3 }}\n"
            ))
        };
        let m = young("[0.1, -1, 0]", "5e-7");
        assert!(
            m.starts_with("t.toml:11: material 2 (\"y\"): texture color must be in "),
            "{m}"
        );
        assert!(m.ends_with(", got color [0.1, -1, 0]"), "{m}");
        // Its spacing still shows the three numbers it comes from.
        let m = young("[1, 1, 1]", "-5e-7");
        assert!(
            m.ends_with("got d 0.002 wavelength -5e-7 distance 3"),
            "{m}"
        );
        // A checker's bad scale shows the scale, not the colours.
        let m = msg(&format!(
            "{HEAD}\n[[material]]\nname = \"c\"\n\
             texture = {{ kind = \"checker\", a = [1, 1, 1], b = [0, 0, 0], scale = -2 }}\n"
        ));
        assert!(
            m.ends_with("texture scale must be > 0, got scale -2"),
            "{m}"
        );
    }

    #[test]
    fn control_characters_in_echoed_strings_are_escaped() {
        let check = |m: &str, shown: &str| {
            assert!(!m.chars().any(char::is_control), "raw control in {m:?}");
            assert!(m.contains(shown), "{shown} not in {m}");
        };
        let text = format!(
            "{HEAD}\n[[material]]\nname = \"t\"\n\
             texture = {{ kind = \"\\u001b[2J\\u001b[H\", x = 1 }}\n"
        );
        check(&msg(&text), "unknown variant `\\u{1b}[2J\\u{1b}[H`");
        let text = format!("\"\\u0007\\u202e\" = 1\n{HEAD}");
        check(&msg(&text), "unknown field `\\u{7}\\u{202e}`");
        let text = format!(
            "{HEAD}\n[[sphere]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"\\u009b31m\"\n"
        );
        check(&msg(&text), "unknown material \"\\u{9b}31m\"");
        let text = format!("{HEAD}\n[render]\nsampler = \"\\r\\u001b[K\"\n");
        check(&msg(&text), "sampler \"\\r\\u{1b}[K\"");
        let e = parse("x", "evil\u{1b}]0;title\u{7}.toml").unwrap_err();
        check(&e.to_string(), "evil\\u{1b}]0;title\\u{7}.toml:");
        let e = DescError {
            item: "a\u{1b}".into(),
            message: "b\u{85}".into(),
        };
        assert_eq!(e.to_string(), "a\\u{1b}: b\\u{85}");
    }

    #[test]
    fn duplicate_key_is_named_with_its_place() {
        let m = msg(&HEAD.replace("near = 0.1", "near = 0.1\nnear = 0.2"));
        assert_eq!(m, "t.toml:5:1: duplicate key `near`");
        assert_eq!(
            msg(&format!("{HEAD}\n[camera]\n")),
            "t.toml:11:2: duplicate key `camera`"
        );
        let m = msg(&format!("a.b = 1\n a.b = 2\n{HEAD}"));
        assert_eq!(m, "t.toml:2:4: duplicate key `a.b`");
        let m = msg(&format!(
            "sphere = [{{ radius = 1, \"radius\" = 2 }}]\n{HEAD}"
        ));
        assert_eq!(m, "t.toml:1:25: duplicate key `\"radius\"`");
        let long = "k".repeat(100);
        let m = msg(&format!("{long} = 1\n{long} = 2\n{HEAD}"));
        assert_eq!(
            m,
            format!("t.toml:2:1: duplicate key `{}…`", "k".repeat(64))
        );
    }

    fn desc(text: &str) -> SceneDesc {
        parse(text, "t.toml").unwrap_or_else(|e| panic!("{e}"))
    }

    #[test]
    fn fovy_in_radians_is_warned() {
        let d = desc(&HEAD.replace("near = 0.1", "fovy = 1.05\nnear = 0.1"));
        let w = warnings(&d);
        let radians = "camera: fovy 1.05 is less than pi degrees: it looks like radians \
                       (1.05 radians would be fovy = 60.2); fovy is in degrees";
        assert_eq!(w, vec![radians.to_string()]);
        let d = desc(&HEAD.replace("near = 0.1", "fovy = 3.1\nnear = 0.1"));
        assert!(
            warnings(&d)[0].contains("would be fovy = 177.6"),
            "{:?}",
            warnings(&d)
        );
        // 3.2 radians would be more than 180 degrees: no field of view, so meant.
        for fovy in ["3.2", "4", "60", "179"] {
            let d = desc(&HEAD.replace("near = 0.1", &format!("fovy = {fovy}\nnear = 0.1")));
            assert!(!warnings(&d).iter().any(|w| w.contains("fovy")), "{fovy}");
        }
    }

    #[test]
    fn unlit_scene_is_warned() {
        let unlit = "scene: nothing lights the surfaces (no light with intensity > 0 and \
                     ambient = [0, 0, 0]): they render black but for what they reflect or \
                     transmit";
        let base = format!("{HEAD}{}", sphere("1"));
        assert_eq!(warnings(&desc(&base)), vec![unlit.to_string()]);
        let dark = format!("{base}\n[[light]]\nposition = [0, 5, 0]\nintensity = 0\n");
        assert_eq!(warnings(&desc(&dark)), vec![unlit.to_string()]);
        let lit = format!("{base}\n[[light]]\nposition = [0, 5, 0]\nintensity = 10\n");
        assert_eq!(warnings(&desc(&lit)), Vec::<String>::new());
        let ambient = format!("ambient = [0.1, 0, 0]\n{base}");
        assert_eq!(warnings(&desc(&ambient)), Vec::<String>::new());
        // Nothing to light: no warning.
        assert_eq!(warnings(&desc(HEAD)), Vec::<String>::new());
    }

    #[test]
    fn reflection_without_depth_is_warned() {
        let text = format!(
            "ambient = [0.1, 0.1, 0.1]\n{HEAD}reflectivity = 0.5\n\n[[material]]\n\
             name = \"g\\u001b\"\ntransparency = 0.9\nior = 1.5\n\n[render]\ndepth = 0\n"
        );
        let effect = "no effect with [render] depth = 0 \
                      (no reflected or refracted ray is traced; depth >= 1 traces them)";
        assert_eq!(
            warnings(&desc(&text)),
            vec![
                format!("material 1 (\"red\"): reflectivity has {effect}"),
                format!("material 2 (\"g\\u{{1b}}\"): transparency has {effect}"),
            ]
        );
        let deeper = text.replace("depth = 0", "depth = 1");
        assert_eq!(warnings(&desc(&deeper)), Vec::<String>::new());
    }

    #[test]
    fn scene_files_have_no_warnings() {
        let mut files = Vec::new();
        toml_files(&scenes_dir(), &mut files);
        for f in &files {
            let d = load(f).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(warnings(&d), Vec::<String>::new(), "{}", f.display());
        }
    }
}
