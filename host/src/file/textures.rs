//! The image files of a scene's image textures, read when the scene is loaded.

use crate::desc::{SceneDesc, TextureDesc};
use std::path::Path;
use tessera_core::image::{Image, TexelFormat};

/// The most bytes an image texture's file may have: 32 MiB (a PNG or JPEG of
/// 8192 x 8192 texels, the largest read, is rarely larger).
pub const MAX_IMAGE_FILE_BYTES: usize = 32 << 20;

/// The texel format `[render] texture_format` names.
///
/// # Errors
/// The message for a name that is not `srgb8` or `rgb565`.
pub fn texel_format(name: &str) -> Result<TexelFormat, String> {
    match name {
        "srgb8" => Ok(TexelFormat::Srgb8),
        "rgb565" => Ok(TexelFormat::Rgb565),
        other => Err(format!(
            "[render] texture_format must be \"srgb8\" or \"rgb565\", got {other:?}"
        )),
    }
}

/// Reads the image files of `desc`'s image textures (relative to `base`) into
/// texel tables in the scene's format (`[render] texture_format`), each resized
/// to an equal share of `[render] texture_budget` when it is larger, its tint
/// applied; an image named by several materials with one tint is read once.
/// Returns what was changed (images resized, alpha dropped), each a sentence;
/// or the index of the material whose image cannot be read, and why.
pub(crate) fn read_images(
    desc: &mut SceneDesc,
    base: &Path,
) -> Result<Vec<String>, (usize, String)> {
    let textured =
        |m: &crate::desc::MaterialDesc| matches!(m.texture, Some(TextureDesc::Image { .. }));
    let Some(first) = desc.materials.iter().position(textured) else {
        return Ok(Vec::new());
    };
    let format = texel_format(&desc.render.texture_format).map_err(|e| (first, e))?;
    let mut wanted: Vec<(String, [u64; 3])> = Vec::new();
    for m in &desc.materials {
        if let Some(TextureDesc::Image { file, tint, .. }) = &m.texture {
            let key = (file.clone(), tint.map(f64::to_bits));
            if !wanted.contains(&key) {
                wanted.push(key);
            }
        }
    }
    let budget = desc.render.texture_budget;
    let embedded = &desc.embedded;
    let share = budget / wanted.len();
    let mut read: Vec<((String, [u64; 3]), Image)> = Vec::new();
    let mut notes = Vec::new();
    for (i, m) in desc.materials.iter_mut().enumerate() {
        let Some(TextureDesc::Image {
            file,
            filter,
            wrap,
            tint,
            image,
        }) = &mut m.texture
        else {
            continue;
        };
        let (filter, wrap) = (filter.core(), [wrap[0].core(), wrap[1].core()]);
        let key = (file.clone(), tint.map(f64::to_bits));
        let texels = match read.iter().find(|(k, _)| *k == key) {
            Some((_, img)) => *img,
            None => {
                let inside = embedded.iter().find(|(name, _)| name == file);
                let path = match inside {
                    Some(_) => std::path::PathBuf::from(&*file),
                    None => base.join(&*file),
                };
                let loaded = match inside {
                    Some((name, bytes)) => {
                        crate::texture_image::decode_tinted(bytes, name, share, format, *tint)
                    }
                    None => crate::texture_image::load_tinted(
                        &path,
                        MAX_IMAGE_FILE_BYTES,
                        share,
                        format,
                        *tint,
                    ),
                }
                .map_err(|e| (i, e))?;
                if let Some((w, h)) = loaded.resized_from {
                    notes.push(format!(
                        "{}: resized from {w} x {h} to {} x {} texels ({} bytes in {}), its \
                         share of the scene's texture budget of {budget} bytes",
                        path.display(),
                        loaded.width,
                        loaded.height,
                        loaded.bytes(),
                        format.name(),
                    ));
                }
                notes.extend(loaded.warnings.iter().cloned());
                let img = loaded
                    .leak(filter, wrap)
                    .map_err(|e| (i, format!("{}: {e}", path.display())))?;
                read.push((key, img));
                img
            }
        };
        *image = Some(texels.with_filter(filter).with_wrap(wrap));
    }
    Ok(notes)
}
