//! A primitive, the chapter's "primitive": a geometry and the material it is made of.

use crate::material::MaterialId;

/// An object of the scene: a geometry and the material it is made of.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Primitive<G> {
    /// The shape.
    pub geometry: G,
    /// Its material, an index checked against the scene's materials when added.
    pub material: MaterialId,
}
