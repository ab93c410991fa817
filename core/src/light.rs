//! Light sources: point lights with a colour and an intensity.

use crate::color::Color;
use crate::error::{Error, Field, finite};
use crate::vec::Vec3;

/// A point light: at a distance `r`, a surface facing it receives
/// `color * intensity / r^2`. It casts shadows (a shadow ray per lit hit).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct PointLight {
    position: Vec3,
    color: Color,
    intensity: f32,
}

impl PointLight {
    /// A point light; the colour components within `[0, `[`crate::error::MAX_COLOR`]`]`,
    /// the intensity finite and `>= 0`, the position's components within
    /// [`crate::error::MAX_EXTENT`].
    pub fn try_new(position: Vec3, color: Color, intensity: f32) -> Result<Self, Error> {
        let position = crate::error::position(position, Field::LightPosition)?;
        let color = crate::error::color(color, Field::LightColor)?;
        let intensity = finite(intensity, Field::LightIntensity)?;
        if intensity < 0.0 {
            return Err(Error::OutOfRange {
                field: Field::LightIntensity,
                range: "[0, inf)",
            });
        }
        Ok(Self {
            position,
            color,
            intensity,
        })
    }

    /// A light of baked data (`static` tables written by `tessera bake`), not
    /// checked here, in a `const` context: [`crate::BakedScene::view`] checks it
    /// against [`PointLight::try_new`] before any render takes it.
    #[must_use]
    pub const fn baked(position: [f32; 3], color: Color, intensity: f32) -> Self {
        Self {
            position: Vec3::new(position[0], position[1], position[2]),
            color,
            intensity,
        }
    }

    /// Position.
    #[must_use]
    pub fn position(&self) -> Vec3 {
        self.position
    }
    /// Colour.
    #[must_use]
    pub fn color(&self) -> Color {
        self.color
    }
    /// Intensity.
    #[must_use]
    pub fn intensity(&self) -> f32 {
        self.intensity
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_lights_are_rejected() {
        let p = Vec3::ZERO;
        assert_eq!(
            PointLight::try_new(Vec3::new(0.0, f32::NAN, 0.0), Color::WHITE, 1.0),
            Err(Error::NotFinite(Field::LightPosition))
        );
        assert_eq!(
            PointLight::try_new(p, Color::new(f32::INFINITY, 0.0, 0.0), 1.0),
            Err(Error::NotFinite(Field::LightColor))
        );
        assert!(PointLight::try_new(p, Color::new(-1.0, 0.0, 0.0), 1.0).is_err());
        assert!(PointLight::try_new(p, Color::WHITE, -1.0).is_err());
        assert_eq!(
            PointLight::try_new(p, Color::WHITE, f32::NAN),
            Err(Error::NotFinite(Field::LightIntensity))
        );
        assert!(PointLight::try_new(p, Color::WHITE, 0.0).is_ok());
    }
}
