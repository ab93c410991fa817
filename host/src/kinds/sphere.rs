//! The sphere on the host.

use super::{HostKind, Number};
use crate::bake::{lit, v3};
use crate::desc::{DescError, Item, value_for};
use serde::Deserialize;
use tessera_core::{error::Field, geometry::Sphere};

/// A sphere.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SphereDesc {
    /// Centre.
    pub center: [f64; 3],
    /// Radius.
    pub radius: f64,
    /// Material name.
    pub material: String,
    /// Its name (`name = "red ball"`), unique among the scene's objects and
    /// lights: the baker's constant for it, the host's lookup (`SceneDesc::find`).
    #[serde(default)]
    pub name: Option<String>,
}

impl HostKind for Sphere {
    type Desc = SphereDesc;
    const TABLE: &'static str = "The spheres: centre, radius.";

    fn material(d: &SphereDesc) -> &str {
        &d.material
    }

    fn name(d: &SphereDesc) -> Option<&str> {
        d.name.as_deref()
    }

    fn numbers(d: &mut SphereDesc, f: &mut dyn FnMut(&'static str, Number, &mut [f64])) {
        f("center", Number::Position, &mut d.center);
        f(
            "radius",
            Number::Length,
            std::slice::from_mut(&mut d.radius),
        );
    }

    fn core(item: &Item, d: &SphereDesc) -> Result<Self, DescError> {
        let center = item.v3(d.center, Field::SphereCenter)?;
        let radius = item.f1(d.radius, Field::SphereRadius)?;
        Sphere::try_new(center, radius).map_err(|e| {
            let fields = [(Field::SphereCenter, &d.center[..])];
            item.core(e, value_for(e, &fields, &[d.radius]))
        })
    }

    fn baked(&self) -> String {
        format!(
            "Sphere::baked({}, {})",
            v3(self.center()),
            lit(self.radius())
        )
    }

    #[cfg(feature = "cli")]
    fn reference(d: &SphereDesc) -> crate::reference::geometry::Shape {
        crate::reference::geometry::Shape::Sphere {
            center: crate::reference::vec::V3::from_array(d.center),
            radius: d.radius,
        }
    }
}
