//! Light sources: point lights and, with the feature `sun`, directional lights
//! (a sun), each with a colour and an intensity.
//!
//! Without `sun`, a light is a point light only: its type holds no kind, and
//! the light loop, the shadow culling and the scene's scaling have no branch for
//! a sun (a firmware whose scene has none pays nothing for it).

use crate::color::Color;
use crate::error::{Error, Field, finite};
use crate::vec::Vec3;

/// A light. Two kinds ([`Light::point`] and, with the feature `sun`,
/// `Light::directional`), one type: a scene's light list holds both, and the
/// light loop branches once a light.
///
/// - A **point light** at `position`: at a distance `r`, a surface facing it
///   receives `color * intensity / r^2`.
/// - A **directional light** (a sun): its rays all travel one way, from
///   infinitely far; a surface facing it receives `color * intensity`, with no
///   fall-off, wherever it is.
///
/// Both cast shadows (a shadow ray per lit hit: to the point light's position,
/// or towards the sun without end).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Light {
    /// A point light's position, or a directional light's unit direction towards
    /// the light (the opposite of the way its rays travel).
    at: Vec3,
    color: Color,
    intensity: f32,
    #[cfg(feature = "sun")]
    directional: bool,
}

/// Where a light is, seen from a surface.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum LightKind {
    /// A point light at this position.
    Point(Vec3),
    /// A directional light: the unit direction towards it (the opposite of the
    /// way its rays travel).
    #[cfg(feature = "sun")]
    Directional(Vec3),
}

/// The bytes of a [`Light`] in a core built without the feature `sun` (its
/// position, colour and intensity: no kind): a baked scene without a sun states
/// its light table's size for such a firmware, whatever the baker's build has.
pub const POINT_LIGHT_BYTES: usize =
    core::mem::size_of::<Vec3>() + core::mem::size_of::<Color>() + core::mem::size_of::<f32>();

#[cfg(not(feature = "sun"))]
const _: () = assert!(core::mem::size_of::<Light>() == POINT_LIGHT_BYTES);

/// The range of a light's intensity.
const INTENSITY_RANGE: &str = "[0, inf)";

fn intensity(intensity: f32) -> Result<f32, Error> {
    let intensity = finite(intensity, Field::LightIntensity)?;
    if intensity < 0.0 {
        return Err(Error::OutOfRange {
            field: Field::LightIntensity,
            range: INTENSITY_RANGE,
        });
    }
    Ok(intensity)
}

impl Light {
    /// A point light; the colour components within `[0, `[`crate::error::MAX_COLOR`]`]`,
    /// the intensity finite and `>= 0`, the position's components within
    /// [`crate::error::MAX_EXTENT`].
    pub fn point(position: Vec3, color: Color, intensity: f32) -> Result<Self, Error> {
        Ok(Self {
            at: crate::error::position(position, Field::LightPosition)?,
            color: crate::error::color(color, Field::LightColor)?,
            intensity: self::intensity(intensity)?,
            #[cfg(feature = "sun")]
            directional: false,
        })
    }

    /// A directional light whose rays travel along `direction` (any finite,
    /// non-zero length: normalised here; a sun overhead is `-Y`); colour and
    /// intensity as for [`Light::point`], the intensity being the irradiance of a
    /// surface facing the light. With the feature `sun`.
    #[cfg(feature = "sun")]
    pub fn directional(direction: Vec3, color: Color, intensity: f32) -> Result<Self, Error> {
        let toward = -crate::error::unit(direction, Field::LightDirection)?;
        Ok(Self {
            at: toward,
            color: crate::error::color(color, Field::LightColor)?,
            intensity: self::intensity(intensity)?,
            directional: true,
        })
    }

    /// A point light of baked data (`static` tables written by `tessera bake`), not
    /// checked here, in a `const` context: [`crate::BakedScene::view`] checks it
    /// against [`Light::point`] before any render takes it.
    #[must_use]
    pub const fn baked_point(position: [f32; 3], color: Color, intensity: f32) -> Self {
        Self {
            at: Vec3::new(position[0], position[1], position[2]),
            color,
            intensity,
            #[cfg(feature = "sun")]
            directional: false,
        }
    }

    /// A directional light of baked data: `toward` is the unit direction towards
    /// the light, as [`Light::directional`] stores it (the bake writes that
    /// light's own numbers). Not checked here: [`crate::BakedScene::view`] checks
    /// that [`Light::directional`] of its opposite gives the same light. With
    /// the feature `sun`.
    #[cfg(feature = "sun")]
    #[must_use]
    pub const fn baked_directional(toward: [f32; 3], color: Color, intensity: f32) -> Self {
        Self {
            at: Vec3::new(toward[0], toward[1], toward[2]),
            color,
            intensity,
            directional: true,
        }
    }

    /// The light checked again from its own numbers, as [`Light::point`] or
    /// `Light::directional` would make it: a baked light is this light when the
    /// two are equal. A directional light's direction is taken as it is when its
    /// squared length is within 8 ulps of 1 (what normalising in `f32` leaves,
    /// as for a mesh's vertex normals; a normalised vector need not normalise to
    /// itself again).
    pub fn checked(&self) -> Result<Self, Error> {
        #[cfg(feature = "sun")]
        if self.directional {
            let made = Self::directional(-self.at, self.color, self.intensity)?;
            let off = crate::math::abs(self.at.length_squared() - 1.0);
            return if off <= 8.0 * f32::EPSILON {
                Ok(Self {
                    at: self.at,
                    ..made
                })
            } else {
                Err(Error::ZeroLength(Field::LightDirection))
            };
        }
        Self::point(self.at, self.color, self.intensity)
    }

    /// Where the light is: its position, or the direction towards it.
    #[must_use]
    pub fn kind(&self) -> LightKind {
        #[cfg(feature = "sun")]
        if self.directional {
            return LightKind::Directional(self.at);
        }
        LightKind::Point(self.at)
    }

    /// True for a directional light (always false without the feature `sun`).
    #[must_use]
    #[inline(always)]
    pub fn is_directional(&self) -> bool {
        #[cfg(feature = "sun")]
        return self.directional;
        #[cfg(not(feature = "sun"))]
        false
    }

    /// A point light's position; a directional light's unit direction towards it
    /// (see [`Light::kind`]).
    #[must_use]
    #[inline(always)]
    pub fn position(&self) -> Vec3 {
        self.at
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
            Light::point(Vec3::new(0.0, f32::NAN, 0.0), Color::WHITE, 1.0),
            Err(Error::NotFinite(Field::LightPosition))
        );
        assert_eq!(
            Light::point(p, Color::new(f32::INFINITY, 0.0, 0.0), 1.0),
            Err(Error::NotFinite(Field::LightColor))
        );
        assert!(Light::point(p, Color::new(-1.0, 0.0, 0.0), 1.0).is_err());
        assert!(Light::point(p, Color::WHITE, -1.0).is_err());
        assert_eq!(
            Light::point(p, Color::WHITE, f32::NAN),
            Err(Error::NotFinite(Field::LightIntensity))
        );
        assert!(Light::point(p, Color::WHITE, 0.0).is_ok());
    }

    #[cfg(feature = "sun")]
    #[test]
    fn a_directional_light_keeps_the_unit_direction_towards_it() {
        let sun = Light::directional(Vec3::new(0.0, -2.0, 0.0), Color::WHITE, 3.0).unwrap();
        assert_eq!(sun.kind(), LightKind::Directional(Vec3::new(0.0, 1.0, 0.0)));
        assert!(sun.is_directional());
        assert_eq!(sun.checked(), Ok(sun));
        let baked = Light::baked_directional([0.0, 1.0, 0.0], Color::WHITE, 3.0);
        assert_eq!(baked, sun);
        assert_eq!(
            Light::directional(Vec3::ZERO, Color::WHITE, 1.0),
            Err(Error::ZeroLength(Field::LightDirection))
        );
        assert_eq!(
            Light::directional(Vec3::new(f32::NAN, 1.0, 0.0), Color::WHITE, 1.0),
            Err(Error::NotFinite(Field::LightDirection))
        );
        assert!(Light::directional(Vec3::Y, Color::WHITE, -1.0).is_err());
        // A direction that is not unit length is stored normalised.
        let d = Light::directional(Vec3::new(3.0, 0.0, -4.0), Color::WHITE, 1.0).unwrap();
        let LightKind::Directional(t) = d.kind() else {
            unreachable!()
        };
        assert!((t - Vec3::new(-0.6, 0.0, 0.8)).length() < 1e-6);
    }
}
