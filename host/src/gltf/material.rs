//! Materials: the metallic-roughness factors, the base colour texture and its
//! sampler, the extensions tessera reads, a warning for the rest.

use super::source::BASISU;
use super::{Cx, ImportedMaterial, TextureRef, Wrap, named};
use gltf::json;
use json::validation::Checked;

/// The materials of `indices` (the file's material indices, in this order),
/// and the file's image indices their base colour textures use (in order of
/// first use); each `TextureRef::image` indexes that list.
pub(super) fn materials(
    root: &json::Root,
    indices: &[usize],
    cx: &mut Cx,
) -> Result<(Vec<ImportedMaterial>, Vec<usize>), String> {
    let mut images: Vec<usize> = Vec::new();
    let mut out = Vec::with_capacity(indices.len());
    for &i in indices {
        let Some(m) = root.materials.get(i) else {
            return Err(cx.err(format!("material {i} does not exist")));
        };
        let at = named("material", i, m.name.as_deref());
        let pbr = &m.pbr_metallic_roughness;
        let ext = m.extensions.as_ref();
        let strength = ext
            .and_then(|e| e.emissive_strength.as_ref())
            .map_or(1.0, |s| f64::from(s.emissive_strength.0));
        let emissive = m.emissive_factor.0.map(|e| f64::from(e) * strength);
        let material = ImportedMaterial {
            name: m.name.clone().unwrap_or_else(|| format!("material {i}")),
            index: i,
            base_color: pbr.base_color_factor.0.map(f64::from),
            base_color_texture: None,
            metallic: f64::from(pbr.metallic_factor.0),
            roughness: f64::from(pbr.roughness_factor.0),
            transmission: ext
                .and_then(|e| e.transmission.as_ref())
                .map_or(0.0, |t| f64::from(t.transmission_factor.0)),
            ior: ext
                .and_then(|e| e.ior.as_ref())
                .map_or(1.5, |x| f64::from(x.ior.0)),
            emissive,
            double_sided: m.double_sided,
        };
        check(&material).map_err(|e| cx.err(format!("{at}: {e}")))?;
        let base_color_texture = match &pbr.base_color_texture {
            Some(info) => texture(root, info, &at, &mut images, cx)?,
            None => None,
        };
        warn_unread(m, &at, cx);
        out.push(ImportedMaterial {
            base_color_texture,
            ..material
        });
    }
    Ok((out, images))
}

/// Checks that `m`'s factors are finite and in the ranges glTF gives them.
fn check(m: &ImportedMaterial) -> Result<(), String> {
    let in01 = |x: f64| (0.0..=1.0).contains(&x);
    if !m.base_color.iter().all(|&c| in01(c)) {
        return Err(format!(
            "baseColorFactor must be in [0, 1], got [{}]",
            m.base_color.map(crate::desc::num).join(", ")
        ));
    }
    for (what, x) in [
        ("metallicFactor", m.metallic),
        ("roughnessFactor", m.roughness),
        ("transmissionFactor", m.transmission),
    ] {
        if !in01(x) {
            return Err(format!(
                "{what} must be in [0, 1], got {}",
                crate::desc::num(x)
            ));
        }
    }
    if !(m.ior.is_finite() && (m.ior == 0.0 || m.ior >= 1.0)) {
        return Err(format!(
            "ior must be 0 or >= 1, got {}",
            crate::desc::num(m.ior)
        ));
    }
    if !m.emissive.iter().all(|&e| e >= 0.0 && e.is_finite()) {
        return Err(format!(
            "the emissive factor (times its strength) must be finite and >= 0, got [{}]",
            m.emissive.map(crate::desc::num).join(", ")
        ));
    }
    Ok(())
}

/// The base colour texture of `info`: its image registered in `images`, its
/// sampler read. `None` (with a warning naming the material `at`) when it reads
/// a texture coordinate set other than 0.
fn texture(
    root: &json::Root,
    info: &json::texture::Info,
    at: &str,
    images: &mut Vec<usize>,
    cx: &mut Cx,
) -> Result<Option<TextureRef>, String> {
    if info.tex_coord != 0 {
        cx.warn(format!(
            "{at}: its base colour texture reads TEXCOORD_{}: only TEXCOORD_0 is read, so the texture is dropped",
            info.tex_coord
        ));
        return Ok(None);
    }
    if info
        .extensions
        .as_ref()
        .is_some_and(|e| e.texture_transform.is_some())
    {
        cx.warn(format!(
            "{at}: KHR_texture_transform on its base colour texture ignored: the texture is drawn untransformed"
        ));
    }
    let t = info.index.value();
    let Some(tex) = root.textures.get(t) else {
        return Err(cx.err(format!("{at}: texture {t} does not exist")));
    };
    if tex
        .extensions
        .as_ref()
        .is_some_and(|e| e.others.contains_key(BASISU))
    {
        cx.warn(format!(
            "{}: its {BASISU} (KTX2) image ignored: its PNG or JPEG fallback is read",
            named("texture", t, tex.name.as_deref())
        ));
    }
    let image = tex.source.value();
    let slot = match images.iter().position(|&i| i == image) {
        Some(s) => s,
        None => {
            images.push(image);
            images.len() - 1
        }
    };
    let sampler = match tex.sampler {
        Some(s) => match root.samplers.get(s.value()) {
            Some(s) => Some(s),
            None => return Err(cx.err(format!("{at}: sampler {} does not exist", s.value()))),
        },
        None => None,
    };
    let wrap = |w: Option<&Checked<json::texture::WrappingMode>>| match w {
        Some(Checked::Valid(json::texture::WrappingMode::ClampToEdge)) => Wrap::ClampToEdge,
        Some(Checked::Valid(json::texture::WrappingMode::MirroredRepeat)) => Wrap::MirroredRepeat,
        _ => Wrap::Repeat,
    };
    Ok(Some(TextureRef {
        image: slot,
        mag_nearest: sampler
            .and_then(|s| s.mag_filter)
            .is_some_and(|f| f == Checked::Valid(json::texture::MagFilter::Nearest)),
        wrap_s: wrap(sampler.map(|s| &s.wrap_s)),
        wrap_t: wrap(sampler.map(|s| &s.wrap_t)),
    }))
}

/// Warns about what material `m` (named `at`) has that is not read: textures
/// other than the base colour's, an alpha mode other than opaque.
fn warn_unread(m: &json::Material, at: &str, cx: &mut Cx) {
    let mut ignored = Vec::new();
    if m.normal_texture.is_some() {
        ignored.push("normal");
    }
    if m.occlusion_texture.is_some() {
        ignored.push("occlusion");
    }
    if m.emissive_texture.is_some() {
        ignored.push("emissive");
    }
    if m.pbr_metallic_roughness
        .metallic_roughness_texture
        .is_some()
    {
        ignored.push("metallic-roughness");
    }
    let ext = m.extensions.as_ref();
    if ext
        .and_then(|e| e.transmission.as_ref())
        .is_some_and(|t| t.transmission_texture.is_some())
    {
        ignored.push("transmission");
    }
    if !ignored.is_empty() {
        cx.warn(format!(
            "{at}: its {} texture{} ignored: only the base colour texture is read",
            ignored.join(", "),
            if ignored.len() > 1 { "s" } else { "" }
        ));
    }
    match m.alpha_mode {
        Checked::Valid(json::material::AlphaMode::Mask) => {
            cx.warn(format!("{at}: alphaMode MASK ignored: drawn opaque"));
        }
        Checked::Valid(json::material::AlphaMode::Blend) => {
            cx.warn(format!("{at}: alphaMode BLEND ignored: drawn opaque"));
        }
        _ => {}
    }
}
