//! The bytes: the file read within its limit, the `.glb` container split, the
//! JSON parsed and validated, the buffers and images resolved (embedded, `data:`
//! URIs, files beside the model).

use super::{Cx, ImportedImage, named};
use base64::Engine as _;
use gltf::json;
use std::borrow::Cow;
use std::io::Read;
use std::path::{Path, PathBuf};

/// The extensions whose content is read (in `extensionsRequired` they are
/// accepted; `KHR_texture_transform` is accepted and warned about where used).
const READ: &[&str] = &[
    "KHR_lights_punctual",
    "KHR_materials_transmission",
    "KHR_materials_ior",
    "KHR_materials_emissive_strength",
    "KHR_texture_transform",
];

/// Extensions not read whose use is warned about where it happens (so not again
/// as an unread `extensionsUsed` entry).
const WARNED_WHERE_USED: &[&str] = &[
    "KHR_draco_mesh_compression",
    "EXT_meshopt_compression",
    "KHR_texture_basisu",
];

/// Draco's extension name.
pub(super) const DRACO: &str = "KHR_draco_mesh_compression";
/// meshoptimizer's extension name.
pub(super) const MESHOPT: &str = "EXT_meshopt_compression";
/// KTX2 textures' extension name.
pub(super) const BASISU: &str = "KHR_texture_basisu";

/// The `.glb` signature.
const GLB_MAGIC: &[u8; 4] = b"glTF";

/// The JSON text and the binary chunk of the file: a `.glb` (its signature)
/// split into its chunks, checked against its length, else the whole file as
/// JSON.
pub(super) fn split<'b>(
    bytes: &'b [u8],
    cx: &mut Cx,
) -> Result<(&'b [u8], Option<&'b [u8]>), String> {
    if !bytes.starts_with(GLB_MAGIC) {
        return Ok((bytes, None));
    }
    let word = |at: usize| -> Option<u32> {
        let b = bytes.get(at..at.checked_add(4)?)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    let n = bytes.len();
    let (Some(version), Some(length)) = (word(4), word(8)) else {
        return Err(cx.err(format!(
            "truncated .glb: {n} bytes, fewer than its 12-byte header"
        )));
    };
    if version != 2 {
        return Err(cx.err(format!(
            "a binary glTF of version {version}: only version 2 is read"
        )));
    }
    let length = length as usize;
    if length < 20 {
        return Err(cx.err(format!(
            "not a valid .glb: its header declares {length} bytes, fewer than a header and a chunk header (20)"
        )));
    }
    if length > n {
        return Err(cx.err(format!(
            "truncated .glb: its header declares {length} bytes, the file has {n}"
        )));
    }
    if length < n {
        cx.warn(format!(
            "the {} bytes after the {length} bytes the .glb header declares are ignored",
            n - length
        ));
    }
    let bytes = &bytes[..length];
    let (json_len, json_type) = (word(12), bytes.get(16..20));
    let (Some(json_len), Some(json_type)) = (json_len, json_type) else {
        return Err(cx.err("truncated .glb: no JSON chunk"));
    };
    if json_type != b"JSON" {
        return Err(cx.err("not a valid .glb: its first chunk is not JSON"));
    }
    let json_end = 20usize.saturating_add(json_len as usize);
    let Some(json) = bytes.get(20..json_end) else {
        return Err(cx.err(format!(
            "truncated .glb: its JSON chunk declares {json_len} bytes, {} follow",
            length - 20
        )));
    };
    let rest = &bytes[json_end..];
    if rest.is_empty() {
        return Ok((json, None));
    }
    let Some(header) = rest.get(..8) else {
        return Err(cx.err(format!(
            "truncated .glb: {} bytes after the JSON chunk, fewer than a chunk header (8)",
            rest.len()
        )));
    };
    let bin_len = u32::from_le_bytes([header[0], header[1], header[2], header[3]]) as usize;
    let Some(chunk) = rest.get(8..8usize.saturating_add(bin_len)) else {
        return Err(cx.err(format!(
            "truncated .glb: its second chunk declares {bin_len} bytes, {} follow",
            rest.len() - 8
        )));
    };
    if &header[4..8] == b"BIN\0" {
        Ok((json, Some(chunk)))
    } else {
        // An unknown chunk is skipped, as the specification says.
        Ok((json, None))
    }
}

/// The glTF JSON of `text`, else the message (a glTF 1.0 file said as such).
pub(super) fn parse_json(text: &[u8], cx: &mut Cx) -> Result<json::Root, String> {
    let text = text.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(text);
    json::deserialize::from_slice::<json::Root>(text).map_err(|e| {
        if let Some(version) = asset_version(text).filter(|v| !v.starts_with("2.")) {
            cx.err(format!(
                "a glTF {version} file: only glTF 2.0 is read (convert it, e.g. with a glTF 1.0 to 2.0 tool)"
            ))
        } else {
            cx.err(format!("not valid glTF JSON: {e}"))
        }
    })
}

/// `asset.version` of the JSON `text`, if it has one.
fn asset_version(text: &[u8]) -> Option<String> {
    #[derive(serde::Deserialize)]
    struct Top {
        asset: Asset,
    }
    #[derive(serde::Deserialize)]
    struct Asset {
        version: json::Value,
    }
    let top: Top = json::deserialize::from_slice(text).ok()?;
    match top.asset.version {
        json::Value::String(s) => Some(s),
        v => Some(v.to_string()),
    }
}

/// The document of `root`, checked: the asset's version, `extensionsRequired`,
/// what `gltf`'s validation would panic on, Draco data without a fallback, then
/// `gltf`'s validation. Warns about `extensionsUsed` not read and attributes
/// glTF does not name (which it then drops).
pub(super) fn validate(mut root: json::Root, cx: &mut Cx) -> Result<gltf::Document, String> {
    if !root.asset.version.starts_with("2.") {
        return Err(cx.err(format!(
            "a glTF {} file: only glTF 2.0 is read",
            crate::escape(&root.asset.version)
        )));
    }
    for ext in &root.extensions_required {
        if !READ.contains(&ext.as_str()) {
            return Err(cx.err(required(&root, ext)));
        }
    }
    for ext in &root.extensions_used {
        let ext = ext.as_str();
        if !READ.contains(&ext) && !WARNED_WHERE_USED.contains(&ext) {
            cx.warn(format!(
                "extension '{}' (extensionsUsed) is not read: what it adds is ignored",
                crate::escape(ext)
            ));
        }
    }
    let accessors = root.accessors.len();
    for (m, mesh) in root.meshes.iter_mut().enumerate() {
        let mesh_name = named("mesh", m, mesh.name.as_deref());
        for (p, prim) in mesh.primitives.iter_mut().enumerate() {
            let at = format!("{mesh_name}, primitive {p}");
            let position = prim.attributes.get(&json::validation::Checked::Valid(
                json::mesh::Semantic::Positions,
            ));
            if let Some(i) = position.filter(|i| i.value() >= accessors) {
                return Err(cx.err(format!(
                    "{at}: POSITION: accessor {} does not exist (the file has {accessors})",
                    i.value()
                )));
            }
            let before = prim.attributes.len();
            prim.attributes
                .retain(|k, _| matches!(k, json::validation::Checked::Valid(_)));
            if prim.attributes.len() < before {
                cx.warn(format!(
                    "{at}: attributes glTF does not name (custom '_NAME' ones) are ignored"
                ));
            }
        }
    }
    check_draco(&root, cx)?;
    for (v, view) in root.buffer_views.iter().enumerate() {
        let meshopt = view
            .extensions
            .as_ref()
            .is_some_and(|e| e.others.contains_key(MESHOPT));
        let fallback = root
            .buffers
            .get(view.buffer.value())
            .is_some_and(|b| b.uri.is_some() || view.buffer.value() == 0);
        if meshopt && fallback {
            cx.warn(format!(
                "buffer view {v}: {MESHOPT} ignored: its uncompressed data is read"
            ));
        }
    }
    gltf::Document::from_json(root).map_err(|e| match e {
        gltf::Error::Validation(list) => {
            let shown: Vec<String> = list
                .iter()
                .take(5)
                .map(|(path, error)| format!("{}: {error}", crate::escape(path.as_str())))
                .collect();
            let more = list.len().saturating_sub(5);
            let more = if more > 0 {
                format!(" (and {more} more)")
            } else {
                String::new()
            };
            cx.err(format!("not valid glTF: {}{more}", shown.join("; ")))
        }
        other => cx.err(format!("not valid glTF: {other}")),
    })
}

/// The message for `ext`, required by the file but not read.
fn required(root: &json::Root, ext: &str) -> String {
    let why = match ext {
        DRACO => "its meshes are Draco-compressed, which tessera does not decode (export them uncompressed)".to_string(),
        MESHOPT => "its buffers are meshoptimizer-compressed, which tessera does not decode (export them uncompressed)".to_string(),
        "KHR_mesh_quantization" => "its vertex attributes are quantized (integer positions, normals), which tessera does not read (export them as floats)".to_string(),
        BASISU => {
            let ktx2: Vec<String> = root
                .images
                .iter()
                .enumerate()
                .filter(|(_, im)| is_ktx2(im))
                .map(|(i, im)| named("image", i, im.name.as_deref()))
                .take(5)
                .collect();
            format!(
                "its textures are KTX2 images{}, which tessera does not read (export PNG or JPEG)",
                if ktx2.is_empty() { String::new() } else { format!(" ({})", ktx2.join(", ")) }
            )
        }
        _ => "tessera does not read it".to_string(),
    };
    format!(
        "extension '{}' is required (extensionsRequired): {why}",
        crate::escape(ext)
    )
}

/// Whether the JSON says `image` is a KTX2 image.
pub(super) fn is_ktx2(image: &json::Image) -> bool {
    image
        .mime_type
        .as_ref()
        .is_some_and(|m| m.0 == "image/ktx2")
        || image
            .uri
            .as_deref()
            .is_some_and(|u| u.to_ascii_lowercase().ends_with(".ktx2"))
}

/// Draco-compressed primitives, the extension not required: their accessors
/// must have their uncompressed data (a buffer view or sparse values), else the
/// primitive cannot be drawn.
fn check_draco(root: &json::Root, cx: &mut Cx) -> Result<(), String> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, prim) in mesh.primitives.iter().enumerate() {
            let draco = prim
                .extensions
                .as_ref()
                .is_some_and(|e| e.others.contains_key(DRACO));
            if !draco {
                continue;
            }
            let at = format!("{}, primitive {p}", named("mesh", m, mesh.name.as_deref()));
            let plain = prim
                .attributes
                .values()
                .chain(prim.indices.as_ref())
                .filter_map(|i| root.accessors.get(i.value()))
                .all(|a| a.buffer_view.is_some() || a.sparse.is_some());
            if !plain {
                return Err(cx.err(format!(
                    "{at}: its data is compressed with {DRACO}, which tessera does not decode, and the file has no uncompressed copy"
                )));
            }
            cx.warn(format!(
                "{at}: {DRACO} ignored: its uncompressed data is read"
            ));
        }
    }
    Ok(())
}

/// The data of the buffers of `needed` (indices into the file's buffers),
/// resolved: the `.glb`'s binary chunk (`bin`), `data:` URIs, files beside the
/// model. Their declared sizes together are bounded before any is read; `None`
/// for a buffer not needed.
pub(super) fn buffers<'b>(
    root: &json::Root,
    bin: Option<&'b [u8]>,
    needed: &[usize],
    cx: &mut Cx,
) -> Result<Vec<Option<Cow<'b, [u8]>>>, String> {
    let mut total: u64 = 0;
    for &i in needed {
        let Some(buffer) = root.buffers.get(i) else {
            return Err(cx.err(format!("buffer {i} does not exist")));
        };
        total = total.saturating_add(buffer.byte_length.0);
    }
    let limit = cx.limits.max_buffer_bytes;
    if total > limit as u64 {
        return Err(cx.err(format!(
            "the buffers the meshes and images use declare {total} bytes together, more than the limit of {limit} bytes"
        )));
    }
    let mut out: Vec<Option<Cow<'b, [u8]>>> = vec![None; root.buffers.len()];
    for &i in needed {
        let buffer = &root.buffers[i];
        let at = named("buffer", i, buffer.name.as_deref());
        let declared = buffer.byte_length.0 as usize;
        let data =
            buffer_data(i, buffer, bin, declared, cx).map_err(|e| cx.err(format!("{at}: {e}")))?;
        if data.len() < declared {
            return Err(cx.err(format!(
                "{at}: declares {declared} bytes, its data has {}",
                data.len()
            )));
        }
        out[i] = Some(data);
    }
    Ok(out)
}

/// The data of `buffer` (index `i`), at least `declared` bytes long if all is
/// well (the caller checks).
fn buffer_data<'b>(
    i: usize,
    buffer: &json::Buffer,
    bin: Option<&'b [u8]>,
    declared: usize,
    cx: &Cx,
) -> Result<Cow<'b, [u8]>, String> {
    let Some(uri) = buffer.uri.as_deref() else {
        let meshopt = buffer
            .extensions
            .as_ref()
            .is_some_and(|e| e.others.contains_key(MESHOPT));
        if meshopt {
            return Err(format!(
                "a placeholder for {MESHOPT} data, which tessera does not decode, and no uncompressed copy"
            ));
        }
        return match (i, bin) {
            (0, Some(bin)) => Ok(Cow::Borrowed(bin)),
            (0, None) => {
                Err("no uri, and the file has no binary chunk (.glb) to hold it".to_string())
            }
            _ => Err("no uri (only buffer 0 of a .glb can be its binary chunk)".to_string()),
        };
    };
    match Uri::parse(uri)? {
        Uri::Data { bytes, .. } => Ok(Cow::Owned(bytes)),
        Uri::File(rel) => {
            let path = cx.base.join(&rel);
            let shown = crate::escape_path(&rel);
            let file = crate::file::open_regular(&path, "buffer file")
                .map_err(|e| format!("'{shown}': {e}"))?;
            let size = file.metadata().map(|m| m.len()).unwrap_or(u64::MAX);
            if size < declared as u64 {
                return Err(format!(
                    "declares {declared} bytes, its file '{shown}' has {size}"
                ));
            }
            let mut data = Vec::new();
            file.take(declared as u64)
                .read_to_end(&mut data)
                .map_err(|e| format!("cannot read its file '{shown}': {e}"))?;
            Ok(Cow::Owned(data))
        }
    }
}

/// Standard base64, with or without its padding.
const BASE64: base64::engine::GeneralPurpose = base64::engine::GeneralPurpose::new(
    &base64::alphabet::STANDARD,
    base64::engine::GeneralPurposeConfig::new()
        .with_decode_padding_mode(base64::engine::DecodePaddingMode::Indifferent),
);

/// A URI of a buffer or an image, decoded.
enum Uri {
    /// A `data:` URI's media type and decoded bytes.
    Data { mime: String, bytes: Vec<u8> },
    /// A relative path (percent-decoded, checked: no `..`, not absolute).
    File(PathBuf),
}

impl Uri {
    /// Decodes `uri`: `data:[type][;base64],DATA` (base64 or percent-encoded),
    /// or a relative path. Refuses other schemes, absolute paths, `..`
    /// components and backslashes.
    fn parse(uri: &str) -> Result<Uri, String> {
        let shown = crate::escape(&clip(uri, 60));
        if let Some(rest) = strip_prefix_ignore_case(uri, "data:") {
            let Some((header, data)) = rest.split_once(',') else {
                return Err(format!("a data: URI without a comma: '{shown}'"));
            };
            let (mime, base64) = match header.strip_suffix(";base64") {
                Some(m) => (m, true),
                None => (header, false),
            };
            let mime = mime.split(';').next().unwrap_or("").to_ascii_lowercase();
            let bytes = if base64 {
                BASE64
                    .decode(data.trim_end())
                    .map_err(|e| format!("a data: URI whose base64 is broken: {e}"))?
            } else {
                percent_decode(data.as_bytes())
                    .ok_or_else(|| format!("a data: URI with a broken %-escape: '{shown}'"))?
            };
            return Ok(Uri::Data { mime, bytes });
        }
        if has_scheme(uri) {
            return Err(format!(
                "the URI '{shown}' has a scheme: only data: URIs and paths relative to the model's folder are read"
            ));
        }
        let decoded = percent_decode(uri.as_bytes())
            .and_then(|b| String::from_utf8(b).ok())
            .ok_or_else(|| format!("the URI '{shown}' has a broken %-escape or is not UTF-8"))?;
        let path = Path::new(&decoded);
        if decoded.is_empty() {
            return Err("an empty URI".to_string());
        }
        if decoded.contains('\\') || decoded.contains('\0') {
            return Err(format!(
                "the URI '{shown}' has a backslash or a NUL: glTF separates folders with '/'"
            ));
        }
        if decoded.starts_with('/') || path.is_absolute() {
            return Err(format!(
                "the URI '{shown}' is an absolute path: only paths relative to the model's folder are read"
            ));
        }
        if decoded.split('/').any(|c| c == "..") {
            return Err(format!(
                "the URI '{shown}' leaves the model's folder ('..'): only files in it or below it are read"
            ));
        }
        Ok(Uri::File(PathBuf::from(decoded)))
    }
}

/// `s` with `prefix` (ASCII, any case) taken off its start.
fn strip_prefix_ignore_case<'s>(s: &'s str, prefix: &str) -> Option<&'s str> {
    let head = s.get(..prefix.len())?;
    head.eq_ignore_ascii_case(prefix)
        .then(|| &s[prefix.len()..])
}

/// Whether `uri` starts with a scheme (RFC 3986: a letter, then letters, digits,
/// `+`, `-`, `.`, then `:`, before any `/`, `?` or `#`).
fn has_scheme(uri: &str) -> bool {
    let Some(colon) = uri.find(':') else {
        return false;
    };
    let scheme = &uri[..colon];
    let mut chars = scheme.chars();
    chars.next().is_some_and(|c| c.is_ascii_alphabetic())
        && chars.all(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '.'))
}

/// `s`'s first `n` characters, with `...` if it had more.
fn clip(s: &str, n: usize) -> String {
    match s.char_indices().nth(n) {
        Some((at, _)) => format!("{}...", &s[..at]),
        None => s.to_string(),
    }
}

/// `bytes` with `%XX` escapes decoded; `None` if one is broken.
fn percent_decode(bytes: &[u8]) -> Option<Vec<u8>> {
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = bytes.get(i + 1..i + 3)?;
            let hex = std::str::from_utf8(hex).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    Some(out)
}

/// The PNG signature.
const PNG_MAGIC: &[u8] = b"\x89PNG\r\n\x1a\n";
/// The JPEG signature (start of image, then a marker).
const JPEG_MAGIC: &[u8] = b"\xFF\xD8\xFF";
/// The KTX2 signature's start.
const KTX2_MAGIC: &[u8] = b"\xABKTX 20";

/// The images of `indices` (the file's image indices, in this order), their
/// bytes from a buffer view, a `data:` URI or a file, all together at most
/// [`super::Limits::max_image_bytes`]; each must be PNG or JPEG.
pub(super) fn images(
    root: &json::Root,
    indices: &[usize],
    buffers: &[Option<Cow<[u8]>>],
    cx: &mut Cx,
) -> Result<Vec<ImportedImage>, String> {
    let mut left = cx.limits.max_image_bytes;
    let mut out = Vec::new();
    for &i in indices {
        let Some(image) = root.images.get(i) else {
            return Err(cx.err(format!("image {i} does not exist")));
        };
        let at = named("image", i, image.name.as_deref());
        let (bytes, file_name) = image_bytes(root, image, buffers, left, cx)
            .map_err(|e| cx.err(format!("{at}: {e}")))?;
        left -= bytes.len();
        let mime = if bytes.starts_with(PNG_MAGIC) {
            "image/png"
        } else if bytes.starts_with(JPEG_MAGIC) {
            "image/jpeg"
        } else if bytes.starts_with(KTX2_MAGIC) || is_ktx2(image) {
            return Err(cx.err(format!(
                "{at}: a KTX2 ({BASISU}) image, which tessera does not read (use PNG or JPEG)"
            )));
        } else {
            return Err(cx.err(format!(
                "{at}: neither PNG nor JPEG (its first bytes are {:02x?})",
                &bytes[..bytes.len().min(8)]
            )));
        };
        let name = match (&image.name, file_name) {
            (Some(n), _) if !n.is_empty() => n.clone(),
            (_, Some(f)) => f,
            _ => format!("image {i}"),
        };
        out.push(ImportedImage {
            name,
            index: i,
            mime: mime.to_string(),
            bytes,
        });
    }
    Ok(out)
}

/// The bytes of `image` (at most `left` of them) and its file's name when it is
/// a file.
fn image_bytes(
    root: &json::Root,
    image: &json::Image,
    buffers: &[Option<Cow<[u8]>>],
    left: usize,
    cx: &Cx,
) -> Result<(Vec<u8>, Option<String>), String> {
    let over = |n: Option<usize>| match n {
        Some(n) => format!(
            "{n} bytes, more than the {left} left of the limit of {} bytes for all the images",
            cx.limits.max_image_bytes
        ),
        None => format!(
            "more than the {left} bytes left of the limit of {} bytes for all the images",
            cx.limits.max_image_bytes
        ),
    };
    if let Some(view) = image.buffer_view {
        let v = view.value();
        let view = root
            .buffer_views
            .get(v)
            .ok_or_else(|| format!("buffer view {v} does not exist"))?;
        let data = buffers
            .get(view.buffer.value())
            .and_then(|b| b.as_deref())
            .ok_or_else(|| format!("buffer view {v}: its buffer was not read"))?;
        let start = view.byte_offset.map_or(0, |o| o.0);
        let end = start.checked_add(view.byte_length.0);
        let bytes = end
            .and_then(|end| data.get(usize::try_from(start).ok()?..usize::try_from(end).ok()?))
            .ok_or_else(|| {
                format!(
                    "buffer view {v} (bytes {start} + {}) lies past the end of its buffer ({} bytes)",
                    view.byte_length.0,
                    data.len()
                )
            })?;
        if bytes.len() > left {
            return Err(over(Some(bytes.len())));
        }
        return Ok((bytes.to_vec(), None));
    }
    let Some(uri) = image.uri.as_deref() else {
        return Err("neither a uri nor a buffer view".to_string());
    };
    match Uri::parse(uri)? {
        Uri::Data { bytes, mime } => {
            if bytes.len() > left {
                return Err(over(Some(bytes.len())));
            }
            if mime == "image/ktx2" {
                return Err(format!(
                    "a KTX2 ({BASISU}) image, which tessera does not read (use PNG or JPEG)"
                ));
            }
            Ok((bytes, None))
        }
        Uri::File(rel) => {
            let shown = crate::escape_path(&rel);
            let bytes = crate::file::read_bounded(&cx.base.join(&rel), left, "image file")
                .map_err(|e| format!("'{shown}': {e}"))?
                .map_err(|size| format!("'{shown}': {}", over(size.map(|n| n as usize))))?;
            let name = rel.file_name().map(|f| f.to_string_lossy().into_owned());
            Ok((bytes, name))
        }
    }
}
