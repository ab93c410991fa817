//! The plane on the host.

use super::{HostKind, Number};
use crate::bake::{lit, vec3};
use crate::desc::{DescError, Item, value_for};
use serde::Deserialize;
use tessera_core::{error::Field, geometry::Plane};

/// A plane.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PlaneDesc {
    /// A point of the plane.
    pub point: [f64; 3],
    /// Normal (any non-zero length).
    pub normal: [f64; 3],
    /// Material name.
    pub material: String,
    /// Its name (`name = "red ball"`), unique among the scene's objects and
    /// lights: the baker's constant for it, the host's lookup (`SceneDesc::find`).
    #[serde(default)]
    pub name: Option<String>,
}

impl HostKind for Plane {
    type Desc = PlaneDesc;
    const TABLE: &'static str = "The planes: a point, the unit normal, the offset from the origin \
                                 along it, the tangents of the texture's uv.";

    fn material(d: &PlaneDesc) -> &str {
        &d.material
    }

    fn name(d: &PlaneDesc) -> Option<&str> {
        d.name.as_deref()
    }

    fn numbers(d: &mut PlaneDesc, f: &mut dyn FnMut(&'static str, Number, &mut [f64])) {
        f("point", Number::Position, &mut d.point);
        f("normal", Number::Direction, &mut d.normal);
    }

    fn core(item: &Item, d: &PlaneDesc) -> Result<Self, DescError> {
        let point = item.v3(d.point, Field::PlanePoint)?;
        let normal = item.v3(d.normal, Field::PlaneNormal)?;
        Plane::try_new(point, normal).map_err(|e| {
            let fields = [(Field::PlanePoint, &d.point[..])];
            item.core(e, value_for(e, &fields, &d.normal))
        })
    }

    fn baked(&self) -> String {
        let (point, normal, offset, [t, u]) = self.parts();
        format!(
            "Plane::baked({}, {}, {}, [{}, {}])",
            vec3(point),
            vec3(normal),
            lit(offset),
            vec3(t),
            vec3(u),
        )
    }

    #[cfg(feature = "cli")]
    fn reference(d: &PlaneDesc) -> crate::reference::geometry::Shape {
        let v = crate::reference::vec::V3::from_array;
        crate::reference::geometry::Shape::plane(v(d.point), v(d.normal))
    }
}
