//! The axis-aligned box on the host.

use super::{HostKind, Number};
use crate::bake::v3;
use crate::desc::{DescError, Item, show};
use serde::Deserialize;
use tessera_core::{error::Field, geometry::Aabb};

/// An axis-aligned box.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct BoxDesc {
    /// Min corner.
    pub min: [f64; 3],
    /// Max corner.
    pub max: [f64; 3],
    /// Material name.
    pub material: String,
    /// Its name (`name = "red ball"`), unique among the scene's objects and
    /// lights: the baker's constant for it, the host's lookup (`SceneDesc::find`).
    #[serde(default)]
    pub name: Option<String>,
    /// Turned about its centre: degrees about the fixed X, then Y, then Z axes
    /// (as a mesh's `rotate`). A turned box is no longer axis-aligned: it is
    /// read as a mesh of its 12 triangles (with the box's uv on each face).
    #[serde(default)]
    pub rotate: Option<[f64; 3]>,
    /// Turned by a quaternion `[x, y, z, w]` instead (normalised).
    #[serde(default)]
    pub quaternion: Option<[f64; 4]>,
}

impl HostKind for Aabb {
    type Desc = BoxDesc;
    const TABLE: &'static str = "The axis-aligned boxes: min and max corners.";

    fn material(d: &BoxDesc) -> &str {
        &d.material
    }

    fn name(d: &BoxDesc) -> Option<&str> {
        d.name.as_deref()
    }

    fn numbers(d: &mut BoxDesc, f: &mut dyn FnMut(&'static str, Number, &mut [f64])) {
        f("min", Number::Position, &mut d.min);
        f("max", Number::Position, &mut d.max);
    }

    fn core(item: &Item, d: &BoxDesc) -> Result<Self, DescError> {
        let min = item.v3(d.min, Field::BoxMin)?;
        let max = item.v3(d.max, Field::BoxMax)?;
        Aabb::try_new(min, max)
            .map_err(|e| item.core(e, format!("min {} max {}", show(&d.min), show(&d.max))))
    }

    fn baked(&self) -> String {
        format!("Aabb::baked({}, {})", v3(self.min()), v3(self.max()))
    }

    #[cfg(feature = "cli")]
    fn reference(d: &BoxDesc) -> crate::reference::geometry::Shape {
        let v = crate::reference::vec::V3::from_array;
        crate::reference::geometry::Shape::Box {
            min: v(d.min),
            max: v(d.max),
        }
    }
}
