//! How a 3D tool's material becomes tessera's: glTF's metallic-roughness model
//! and an MTL file's Phong terms, mapped onto the Whitted model of
//! [`MaterialDesc`] (colour, ambient, diffuse, specular and shininess, mirror
//! reflectivity, transparency and index of refraction) by one rule:
//!
//! | tessera | glTF 2.0 | MTL |
//! |---|---|---|
//! | colour | `baseColorFactor` (its alpha: a warning below 1) | `Kd` |
//! | texture | `baseColorTexture`, tinted by the factor | `map_Kd`, tinted by `Kd` |
//! | diffuse | `1 - metallic (1 - roughness)^2` (a rough metal's broad lobe is drawn as diffuse light, a polished one's as a mirror) | 1 |
//! | specular | `0.04 + 0.96 metallic` (the reflectance at normal incidence of a dielectric and a metal), times `(1 - roughness)^2` | the largest component of `Ks` |
//! | shininess | `2 / a^2 - 2`, `a = roughness^2` (the Blinn-Phong exponent of the same highlight width), within `[1, 10000]` | `Ns`, within `[1, 10000]` |
//! | reflectivity | `metallic (1 - roughness)^2` | the largest component of `Ks` when `illum` is 3, 5, 6 or 7 (ray-traced reflection), else 0 |
//! | transparency | `KHR_materials_transmission` times `1 - metallic` | `1 - d` (or `Tr`) |
//! | ior | `KHR_materials_ior` (1.5 by default) | `Ni` (1 when absent) |
//! | ambient | 1 | 1 |
//!
//! The index of refraction is kept within `[1, 4]`, and the reflectivity within
//! `1 - transparency` (tessera's rule); either change is a warning. What the
//! model has no term for (emission, other textures) is a warning by name.

use crate::desc::{FilterDesc, MaterialDesc, TextureDesc, WrapDesc};

/// `x` within `[0, 1]`; 0 when it is not finite.
fn unit(x: f64) -> f64 {
    if x.is_finite() {
        x.clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// A glTF material's terms (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Pbr {
    /// The base colour factor, linear RGB and alpha.
    pub base_color: [f64; 4],
    /// The base colour texture's image file (relative to the scene file's
    /// folder) and sampler, or none; the factor tints it.
    pub texture: Option<(String, FilterDesc, [WrapDesc; 2])>,
    /// Metallic, in `[0, 1]`.
    pub metallic: f64,
    /// Roughness, in `[0, 1]`.
    pub roughness: f64,
    /// `KHR_materials_transmission`'s factor.
    pub transmission: f64,
    /// `KHR_materials_ior`'s index.
    pub ior: f64,
    /// The emissive factor.
    pub emissive: [f64; 3],
}

/// The material `name` of glTF terms `p`, and what the rule changed or left out
/// (each a sentence naming the material).
#[must_use]
pub fn from_pbr(name: &str, p: &Pbr) -> (MaterialDesc, Vec<String>) {
    let mut notes = Vec::new();
    let (metallic, roughness) = (unit(p.metallic), unit(p.roughness));
    let smooth = (1.0 - roughness) * (1.0 - roughness);
    let a = roughness * roughness;
    let shininess = if a > 0.0 {
        2.0 / (a * a) - 2.0
    } else {
        f64::INFINITY
    };
    let [r, g, b, alpha] = p.base_color.map(unit);
    if alpha < 1.0 {
        notes.push(format!(
            "material {name:?}: its base colour's alpha {alpha} is not modelled: drawn opaque"
        ));
    }
    if p.emissive.iter().any(|&e| e > 0.0) {
        notes.push(format!(
            "material {name:?}: emission is not modelled: its emissive colour is ignored"
        ));
    }
    let m = finish(
        name,
        Terms {
            color: [r, g, b],
            texture: p.texture.clone(),
            diffuse: 1.0 - metallic * smooth,
            specular: (0.04 + 0.96 * metallic) * smooth,
            shininess,
            reflectivity: metallic * smooth,
            transparency: unit(p.transmission) * (1.0 - metallic),
            ior: p.ior,
        },
        &mut notes,
    );
    (m, notes)
}

/// The material `name` of an MTL file's material `m`, its texture files
/// relative to `folder` (the MTL file's folder as the scene file names it), and
/// what the rule changed or left out (each a sentence naming the material).
#[must_use]
pub fn from_mtl(name: &str, m: &tobj::Material, folder: &str) -> (MaterialDesc, Vec<String>) {
    let mut notes = Vec::new();
    let kd = m.diffuse.unwrap_or([0.8; 3]).map(unit);
    let ks = m.specular.unwrap_or([0.0; 3]).map(unit);
    let ks_max = ks.iter().copied().fold(0.0, f64::max);
    let dissolve = m.dissolve.or_else(|| {
        m.unknown_param
            .get("Tr")
            .and_then(|t| t.trim().parse::<f64>().ok())
            .map(|t| 1.0 - t)
    });
    let reflective = matches!(m.illumination_model, Some(3 | 5 | 6 | 7));
    let texture = m.diffuse_texture.as_deref().map(|map| {
        // `map_Kd -o 0 0 0 file.png`: options before the file, not read.
        let file = map.split_whitespace().last().unwrap_or(map);
        if map.split_whitespace().count() > 1 {
            notes.push(format!(
                "material {name:?}: the options of map_Kd ({map:?}) are not read"
            ));
        }
        let path = if folder.is_empty() {
            file.to_string()
        } else {
            format!("{folder}/{file}")
        };
        (path, FilterDesc::Bilinear, [WrapDesc::Repeat; 2])
    });
    if m.emissive.is_some_and(|e| e.iter().any(|&x| x > 0.0)) {
        notes.push(format!(
            "material {name:?}: emission (Ke) is not modelled: it is ignored"
        ));
    }
    let others = [
        ("map_Ka", &m.ambient_texture),
        ("map_Ks", &m.specular_texture),
        ("map_Bump/norm", &m.normal_texture),
        ("map_Ns", &m.shininess_texture),
        ("map_d", &m.dissolve_texture),
    ];
    let mut unread: Vec<&str> = others
        .iter()
        .filter(|(_, t)| t.is_some())
        .map(|(k, _)| *k)
        .collect();
    let mut extra: Vec<&str> = m
        .unknown_param
        .keys()
        .map(String::as_str)
        .filter(|k| *k != "Tr")
        .collect();
    extra.sort_unstable();
    unread.extend(extra);
    if !unread.is_empty() {
        notes.push(format!(
            "material {name:?}: {} not modelled: ignored",
            unread.join(", ")
        ));
    }
    let material = finish(
        name,
        Terms {
            color: kd,
            texture,
            diffuse: 1.0,
            specular: ks_max,
            shininess: m.shininess.unwrap_or(1.0),
            reflectivity: if reflective { ks_max } else { 0.0 },
            transparency: 1.0 - unit(dissolve.unwrap_or(1.0)),
            ior: m.optical_density.unwrap_or(1.0),
        },
        &mut notes,
    );
    (material, notes)
}

/// A material's terms before tessera's ranges are applied.
struct Terms {
    color: [f64; 3],
    texture: Option<(String, FilterDesc, [WrapDesc; 2])>,
    diffuse: f64,
    specular: f64,
    shininess: f64,
    reflectivity: f64,
    transparency: f64,
    ior: f64,
}

/// The material of `t`, within tessera's ranges: shininess in `[1, 10000]`, the
/// index of refraction in `[1, 4]` (a warning when moved), the reflectivity
/// within `1 - transparency` (a warning when lowered).
fn finish(name: &str, t: Terms, notes: &mut Vec<String>) -> MaterialDesc {
    let shininess = if t.shininess.is_nan() {
        1.0
    } else {
        t.shininess.clamp(1.0, 10_000.0)
    };
    let ior = if t.ior.is_finite() { t.ior } else { 1.0 };
    let kept = ior.clamp(1.0, 4.0);
    if kept != ior {
        notes.push(format!(
            "material {name:?}: index of refraction {ior} is outside [1, 4]: {kept} is used"
        ));
    }
    let reflectivity = if t.reflectivity + t.transparency > 1.0 {
        notes.push(format!(
            "material {name:?}: reflectivity {} and transparency {} sum above 1: the \
             reflectivity is lowered to {}",
            t.reflectivity,
            t.transparency,
            1.0 - t.transparency
        ));
        1.0 - t.transparency
    } else {
        t.reflectivity
    };
    MaterialDesc {
        name: name.to_string(),
        color: t.color,
        texture: t.texture.map(|(file, filter, wrap)| TextureDesc::Image {
            file,
            filter,
            wrap,
            tint: t.color,
            image: None,
        }),
        ambient: 1.0,
        diffuse: t.diffuse.clamp(0.0, 1.0),
        specular: t.specular.clamp(0.0, 1.0),
        shininess,
        reflectivity: reflectivity.clamp(0.0, 1.0),
        transparency: t.transparency.clamp(0.0, 1.0),
        ior: kept,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pbr(metallic: f64, roughness: f64) -> Pbr {
        Pbr {
            base_color: [0.8, 0.2, 0.1, 1.0],
            texture: None,
            metallic,
            roughness,
            transmission: 0.0,
            ior: 1.5,
            emissive: [0.0; 3],
        }
    }

    /// The rule's corners, by hand: a rough dielectric is matte (diffuse 1,
    /// specular 0, shininess 1, no mirror); a polished metal is a mirror with no
    /// diffuse term; a rough metal (glTF's default material) is diffuse;
    /// roughness 0.5 gives a = 0.25, shininess 2 / 0.0625 - 2 = 30, and
    /// (1 - 0.5)^2 = 0.25 of the reflectance.
    #[test]
    fn metallic_and_roughness_map_by_the_rule() {
        let (m, notes) = from_pbr("rough", &pbr(0.0, 1.0));
        assert_eq!(
            (m.diffuse, m.specular, m.shininess, m.reflectivity),
            (1.0, 0.0, 1.0, 0.0)
        );
        assert!(notes.is_empty());
        let (m, _) = from_pbr("mirror", &pbr(1.0, 0.0));
        assert_eq!(
            (m.diffuse, m.specular, m.shininess, m.reflectivity),
            (0.0, 1.0, 10_000.0, 1.0)
        );
        let (m, _) = from_pbr("default", &pbr(1.0, 1.0));
        assert_eq!((m.diffuse, m.specular, m.reflectivity), (1.0, 0.0, 0.0));
        let (m, _) = from_pbr("half", &pbr(0.0, 0.5));
        assert_eq!(m.shininess, 30.0);
        assert!((m.specular - 0.04 * 0.25).abs() < 1e-15);
        assert_eq!(m.color, [0.8, 0.2, 0.1]);
    }

    /// Glass: transmission and ior; reflectivity kept within what transparency
    /// leaves, an ior beyond 4 kept at 4, each with a warning; emission and alpha
    /// warned about.
    #[test]
    fn glass_and_what_is_not_modelled() {
        let mut p = pbr(0.0, 0.0);
        p.transmission = 1.0;
        p.ior = 1.5;
        let (m, notes) = from_pbr("glass", &p);
        assert_eq!((m.transparency, m.ior, m.reflectivity), (1.0, 1.5, 0.0));
        assert!(notes.is_empty(), "{notes:?}");
        p.metallic = 0.5;
        p.ior = 5.0;
        p.emissive = [1.0, 0.0, 0.0];
        p.base_color[3] = 0.5;
        let (m, notes) = from_pbr("odd", &p);
        assert_eq!((m.transparency, m.ior, m.reflectivity), (0.5, 4.0, 0.5));
        let all = notes.join("\n");
        for word in ["index of refraction 5", "emission", "alpha 0.5"] {
            assert!(all.contains(word), "{all}");
        }
    }

    /// Blender's MTL terms: Kd 0.64, Ks 0.5, Ns 96.08, Ni 1, d 1, illum 2; then
    /// a mirror (illum 3) and a half-transparent texture with options.
    #[test]
    fn mtl_terms_map_by_the_rule() {
        let mut m = tobj::Material {
            name: "mat_top".into(),
            diffuse: Some([0.64; 3]),
            specular: Some([0.5; 3]),
            shininess: Some(96.078431),
            optical_density: Some(1.0),
            dissolve: Some(1.0),
            illumination_model: Some(2),
            emissive: Some([0.0; 3]),
            ..Default::default()
        };
        let (d, notes) = from_mtl("box/mat_top", &m, "");
        assert_eq!(d.color, [0.64; 3]);
        assert_eq!(
            (
                d.diffuse,
                d.specular,
                d.shininess,
                d.reflectivity,
                d.transparency,
                d.ior
            ),
            (1.0, 0.5, 96.078431, 0.0, 0.0, 1.0)
        );
        assert!(notes.is_empty(), "{notes:?}");
        m.illumination_model = Some(3);
        m.dissolve = Some(0.25);
        m.diffuse_texture = Some("-s 2 2 1 tex/wood.png".into());
        m.normal_texture = Some("n.png".into());
        let (d, notes) = from_mtl("x", &m, "models");
        assert_eq!((d.transparency, d.reflectivity), (0.75, 0.25));
        let Some(TextureDesc::Image { file, tint, .. }) = &d.texture else {
            panic!("{:?}", d.texture)
        };
        assert_eq!((file.as_str(), *tint), ("models/tex/wood.png", [0.64; 3]));
        let all = notes.join("\n");
        assert!(
            all.contains("options of map_Kd") && all.contains("map_Bump/norm"),
            "{all}"
        );
    }
}
