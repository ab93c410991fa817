//! Materials: what a surface looks like (the chapter's "matériel").
//!
//! The local model is Blinn-Phong: `ambient * base * A + sum over lights of
//! E * (diffuse * base * max(0, n.l) + specular * max(0, n.h)^shininess)` with
//! `base` the texture colour, `A` the scene's ambient light and `E` the light's
//! irradiance. On top, `reflectivity` sends a mirror ray and `transparency` a
//! refracted ray (Snell's law, Fresnel by Schlick's approximation, total internal
//! reflection), each weighted, each only when its weight is non-zero.

use crate::color::Color;
use crate::error::{Error, Field, finite, flush, in_range};
use crate::texture::Texture;

/// A reference to a material of a scene (its index in the scene's material list).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct MaterialId(pub u16);

/// A material. Build with [`Material::matte`] and the `with_*` methods, which check
/// each number.
///
/// ```
/// use tessera_core::{Color, material::Material};
/// let glass = Material::matte(Color::WHITE)
///     .with_diffuse(0.0).unwrap()
///     .with_specular(0.5, 64.0).unwrap()
///     .with_transparency(0.9, 1.5).unwrap();
/// assert_eq!(glass.transparency(), 0.9);
/// assert!(Material::matte(Color::WHITE).with_reflectivity(1.5).is_err());
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Material {
    texture: Texture,
    ambient: f32,
    diffuse: f32,
    specular: f32,
    shininess: f32,
    /// `shininess` as an integer when it is one (0 otherwise): the highlight is then
    /// raised to that power by squaring instead of calling `powf`.
    power: u16,
    reflectivity: f32,
    transparency: f32,
    ior: f32,
}

const UNIT: &str = "[0, 1]";

impl Material {
    /// A diffuse material of one colour: ambient 1, diffuse 1, no specular, no
    /// mirror, opaque. Colour components are reflectances, meant to be in `[0, 1]`
    /// (above 1 a surface returns more light than it receives); what is checked,
    /// when the material is added to a scene, is only that each is finite and in
    /// `[0, `[`crate::error::MAX_COLOR`]`]`, the bound that keeps the shading finite.
    #[must_use]
    pub const fn matte(color: Color) -> Self {
        Self {
            texture: Texture::Solid(color),
            ambient: 1.0,
            diffuse: 1.0,
            specular: 0.0,
            shininess: 1.0,
            power: 1,
            reflectivity: 0.0,
            transparency: 0.0,
            ior: 1.0,
        }
    }

    /// A material of baked data (`static` tables written by `tessera bake`), in
    /// a `const` context: its numbers as [`Material::texture`],
    /// [`Material::ambient`] and the other accessors give them, not checked
    /// here; [`crate::BakedScene::view`] checks it as a scene checks a material
    /// it takes ([`Material::validate`], and the rule for subnormal numbers).
    #[must_use]
    #[allow(clippy::too_many_arguments)]
    pub const fn baked(
        texture: Texture,
        ambient: f32,
        diffuse: f32,
        specular: f32,
        shininess: f32,
        reflectivity: f32,
        transparency: f32,
        ior: f32,
    ) -> Self {
        // As with_specular: an integer exponent (any the checks accept fits
        // in u16) is raised by squaring, anything else by powf.
        let whole = shininess as u16;
        Self {
            texture,
            ambient,
            diffuse,
            specular,
            shininess,
            power: if whole as f32 == shininess { whole } else { 0 },
            reflectivity,
            transparency,
            ior,
        }
    }

    /// Replaces the colour by a texture.
    pub fn with_texture(mut self, texture: Texture) -> Result<Self, Error> {
        texture.validate()?;
        self.texture = texture;
        Ok(self)
    }

    /// Ambient weight in `[0, 1]`: how much of the scene's ambient light it returns.
    pub fn with_ambient(mut self, ambient: f32) -> Result<Self, Error> {
        self.ambient = in_range(ambient, 0.0, 1.0, Field::Ambient, UNIT)?;
        Ok(self)
    }

    /// Diffuse (Lambert) weight in `[0, 1]`.
    pub fn with_diffuse(mut self, diffuse: f32) -> Result<Self, Error> {
        self.diffuse = in_range(diffuse, 0.0, 1.0, Field::Diffuse, UNIT)?;
        Ok(self)
    }

    /// Specular (Blinn-Phong) weight in `[0, 1]` and shininess exponent in
    /// `[1, 10000]`.
    pub fn with_specular(mut self, specular: f32, shininess: f32) -> Result<Self, Error> {
        self.specular = in_range(specular, 0.0, 1.0, Field::Specular, UNIT)?;
        self.shininess = in_range(shininess, 1.0, 10_000.0, Field::Shininess, "[1, 10000]")?;
        // An integer in [1, 10000] converts exactly; anything else keeps powf.
        self.power = if crate::math::floor(self.shininess) == self.shininess {
            self.shininess as u16
        } else {
            0
        };
        Ok(self)
    }

    /// Mirror reflectivity in `[0, 1]`: the weight of the reflected ray. With the
    /// transparency, at most 1 ([`Error::ReflectionAndTransmissionAboveOne`]).
    pub fn with_reflectivity(mut self, reflectivity: f32) -> Result<Self, Error> {
        self.reflectivity = in_range(reflectivity, 0.0, 1.0, Field::Reflectivity, UNIT)?;
        self.check_energy()?;
        Ok(self)
    }

    /// Refuses reflectivity + transparency above 1.
    fn check_energy(&self) -> Result<(), Error> {
        // One ulp of slack: 0.2 + 0.8 written in decimal must not be refused for
        // the rounding of its two terms.
        if self.reflectivity + self.transparency > 1.0 + f32::EPSILON {
            return Err(Error::ReflectionAndTransmissionAboveOne);
        }
        Ok(())
    }

    /// Transparency in `[0, 1]` (the weight of the transmitted light before Fresnel)
    /// and index of refraction in `[1, 4]` relative to the surrounding medium. With
    /// the reflectivity, at most 1 ([`Error::ReflectionAndTransmissionAboveOne`]).
    pub fn with_transparency(mut self, transparency: f32, ior: f32) -> Result<Self, Error> {
        self.transparency = in_range(transparency, 0.0, 1.0, Field::Transparency, UNIT)?;
        self.ior = in_range(ior, 1.0, 4.0, Field::RefractiveIndex, "[1, 4]")?;
        self.check_energy()?;
        Ok(self)
    }

    /// The material with its numbers read by the rule for subnormal numbers
    /// ([`crate::error::flush`]): what a scene keeps ([`crate::Scene::add_material`]).
    #[must_use]
    pub(crate) fn flushed(self) -> Self {
        Self {
            texture: self.texture.flushed(),
            ambient: flush(self.ambient),
            diffuse: flush(self.diffuse),
            specular: flush(self.specular),
            shininess: flush(self.shininess),
            reflectivity: flush(self.reflectivity),
            transparency: flush(self.transparency),
            ior: flush(self.ior),
            ..self
        }
    }

    /// Checks every number (used when the material is added to a scene, so that a
    /// material built field by field by a parser is checked too).
    pub fn validate(&self) -> Result<(), Error> {
        self.texture.validate()?;
        in_range(self.ambient, 0.0, 1.0, Field::Ambient, UNIT)?;
        in_range(self.diffuse, 0.0, 1.0, Field::Diffuse, UNIT)?;
        in_range(self.specular, 0.0, 1.0, Field::Specular, UNIT)?;
        in_range(
            self.shininess,
            1.0,
            10_000.0,
            Field::Shininess,
            "[1, 10000]",
        )?;
        in_range(self.reflectivity, 0.0, 1.0, Field::Reflectivity, UNIT)?;
        in_range(self.transparency, 0.0, 1.0, Field::Transparency, UNIT)?;
        in_range(self.ior, 1.0, 4.0, Field::RefractiveIndex, "[1, 4]")?;
        finite(self.ior, Field::RefractiveIndex)?;
        self.check_energy()
    }

    /// The texture (or solid colour).
    #[must_use]
    pub fn texture(&self) -> &Texture {
        &self.texture
    }
    /// Ambient weight.
    #[must_use]
    pub fn ambient(&self) -> f32 {
        self.ambient
    }
    /// Diffuse weight.
    #[must_use]
    pub fn diffuse(&self) -> f32 {
        self.diffuse
    }
    /// Specular weight.
    #[must_use]
    pub fn specular(&self) -> f32 {
        self.specular
    }
    /// Blinn-Phong exponent.
    #[must_use]
    pub fn shininess(&self) -> f32 {
        self.shininess
    }
    /// Mirror reflectivity.
    #[must_use]
    pub fn reflectivity(&self) -> f32 {
        self.reflectivity
    }
    /// Transparency.
    #[must_use]
    pub fn transparency(&self) -> f32 {
        self.transparency
    }
    /// Index of refraction.
    #[must_use]
    pub fn ior(&self) -> f32 {
        self.ior
    }
    /// The Blinn-Phong highlight `x^shininess` for `x = n.h` in `(0, 1]`: by
    /// repeated squaring (`math::powi`) when the shininess is an integer, a
    /// few dozen instructions instead of a `powf` call (relative error about
    /// `2 shininess 2^-24`: at most 0.3 of an 8-bit step on a full highlight even at
    /// shininess 10000), else through `math::powf`.
    #[inline]
    #[must_use]
    pub fn highlight(&self, x: f32) -> f32 {
        if self.power == 0 {
            crate::math::powf(x, self.shininess)
        } else {
            crate::math::powi(x, u32::from(self.power))
        }
    }

    /// True when a hit on this material sends a reflected or refracted ray.
    #[inline]
    #[must_use]
    pub fn sends_rays(&self) -> bool {
        self.reflectivity > 0.0 || self.transparency > 0.0
    }

    /// True when a light can change this material's colour (diffuse or specular).
    #[must_use]
    pub fn is_lit(&self) -> bool {
        self.diffuse > 0.0 || self.specular > 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reflectivity 1 with transparency 1 would return more light than the surface
    /// receives: refused, in either order and in `validate`; a sum of exactly 1 written
    /// in decimal is accepted.
    #[test]
    fn reflectivity_plus_transparency_above_one_is_refused() {
        let m = Material::matte(Color::WHITE);
        let both = m
            .with_reflectivity(1.0)
            .unwrap()
            .with_transparency(1.0, 1.5);
        assert_eq!(both, Err(Error::ReflectionAndTransmissionAboveOne));
        let both = m
            .with_transparency(0.6, 1.5)
            .unwrap()
            .with_reflectivity(0.5);
        assert_eq!(both, Err(Error::ReflectionAndTransmissionAboveOne));
        let raw = Material {
            reflectivity: 0.7,
            transparency: 0.4,
            ..m
        };
        assert_eq!(
            raw.validate(),
            Err(Error::ReflectionAndTransmissionAboveOne)
        );
        for (r, t) in [
            (0.2f32, 0.8f32),
            (0.1, 0.9),
            (0.3, 0.7),
            (0.15, 0.85),
            (1.0, 0.0),
        ] {
            let ok = m.with_reflectivity(r).unwrap().with_transparency(t, 1.5);
            assert!(ok.is_ok(), "{r} + {t}");
            assert_eq!(ok.unwrap().validate(), Ok(()));
        }
        extern crate std;
        use std::string::ToString;
        let text = Error::ReflectionAndTransmissionAboveOne.to_string();
        assert!(text.contains("<= 1"), "{text}");
    }

    #[test]
    fn every_weight_is_checked() {
        let m = Material::matte(Color::WHITE);
        assert!(matches!(
            m.with_ambient(-0.1),
            Err(Error::OutOfRange {
                field: Field::Ambient,
                ..
            })
        ));
        assert!(matches!(
            m.with_diffuse(1.1),
            Err(Error::OutOfRange {
                field: Field::Diffuse,
                ..
            })
        ));
        assert!(matches!(
            m.with_specular(0.5, 0.5),
            Err(Error::OutOfRange {
                field: Field::Shininess,
                ..
            })
        ));
        assert_eq!(
            m.with_specular(f32::NAN, 8.0),
            Err(Error::NotFinite(Field::Specular))
        );
        assert!(matches!(
            m.with_reflectivity(2.0),
            Err(Error::OutOfRange {
                field: Field::Reflectivity,
                ..
            })
        ));
        assert!(matches!(
            m.with_transparency(0.5, 0.5),
            Err(Error::OutOfRange {
                field: Field::RefractiveIndex,
                ..
            })
        ));
        assert_eq!(
            m.with_transparency(0.5, f32::INFINITY),
            Err(Error::NotFinite(Field::RefractiveIndex))
        );
        let bad_color = Material::matte(Color::new(0.0, -1.0, 0.0));
        assert!(bad_color.validate().is_err());
        assert!(m.validate().is_ok());
    }
}
