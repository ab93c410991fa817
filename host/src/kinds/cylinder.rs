//! The finite cylinder on the host.

use super::{HostKind, Number};
use crate::bake::{lit, v3, vec3};
use crate::desc::{DescError, Item, value_for};
use serde::Deserialize;
use tessera_core::{error::Field, geometry::Cylinder};

/// A finite cylinder: the tube of `radius` around the segment from `base` to
/// `top`, closed by its two end caps unless `capped = false`.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CylinderDesc {
    /// The centre of the base.
    pub base: [f64; 3],
    /// The centre of the top.
    pub top: [f64; 3],
    /// Radius.
    pub radius: f64,
    /// Whether the two caps close it (default true).
    #[serde(default = "yes")]
    pub capped: bool,
    /// Material name.
    pub material: String,
    /// Its name (`name = "red ball"`), unique among the scene's objects and
    /// lights: the baker's constant for it, the host's lookup (`SceneDesc::find`).
    #[serde(default)]
    pub name: Option<String>,
}

fn yes() -> bool {
    true
}

impl HostKind for Cylinder {
    type Desc = CylinderDesc;
    const TABLE: &'static str = "The cylinders: base and top centres, radius, caps; the unit \
                                 axis, the frame's tangents, the height.";
    const FEATURE: Option<&'static str> = Some("cylinder");

    fn material(d: &CylinderDesc) -> &str {
        &d.material
    }

    fn name(d: &CylinderDesc) -> Option<&str> {
        d.name.as_deref()
    }

    fn numbers(d: &mut CylinderDesc, f: &mut dyn FnMut(&'static str, Number, &mut [f64])) {
        f("base", Number::Position, &mut d.base);
        f("top", Number::Position, &mut d.top);
        f(
            "radius",
            Number::Length,
            std::slice::from_mut(&mut d.radius),
        );
    }

    fn core(item: &Item, d: &CylinderDesc) -> Result<Self, DescError> {
        let base = item.v3(d.base, Field::CylinderBase)?;
        let top = item.v3(d.top, Field::CylinderTop)?;
        let radius = item.f1(d.radius, Field::CylinderRadius)?;
        Cylinder::try_new(base, top, radius, d.capped).map_err(|e| {
            let fields = [
                (Field::CylinderBase, &d.base[..]),
                (Field::CylinderTop, &d.top[..]),
            ];
            item.core(e, value_for(e, &fields, &[d.radius]))
        })
    }

    fn baked(&self) -> String {
        let (axis, [t, u], height) = self.parts();
        format!(
            "Cylinder::baked({}, {}, {}, {}, {}, [{}, {}], {})",
            v3(self.base()),
            v3(self.top()),
            lit(self.radius()),
            self.capped(),
            vec3(axis),
            vec3(t),
            vec3(u),
            lit(height)
        )
    }

    #[cfg(feature = "cli")]
    fn reference(d: &CylinderDesc) -> crate::reference::geometry::Shape {
        let v = crate::reference::vec::V3::from_array;
        crate::reference::geometry::Shape::Cylinder {
            base: v(d.base),
            top: v(d.top),
            radius: d.radius,
            capped: d.capped,
        }
    }
}
