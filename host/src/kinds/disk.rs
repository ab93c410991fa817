//! The disk (and the ring, with an inner radius) on the host.

use super::{HostKind, Number};
use crate::bake::{lit, vec3};
use crate::desc::{DescError, Item, value_for};
use serde::Deserialize;
use tessera_core::{error::Field, geometry::Disk};

/// A disk: the points of the plane through `center` with normal `normal`
/// within `radius` of the centre, and at least `inner` from it (a ring).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DiskDesc {
    /// The centre.
    pub center: [f64; 3],
    /// Normal (any non-zero length).
    pub normal: [f64; 3],
    /// Radius.
    pub radius: f64,
    /// Inner radius, `0 <= inner < radius` (default 0: a whole disk).
    #[serde(default)]
    pub inner: f64,
    /// Material name.
    pub material: String,
    /// Its name (`name = "red ball"`), unique among the scene's objects and
    /// lights: the baker's constant for it, the host's lookup (`SceneDesc::find`).
    #[serde(default)]
    pub name: Option<String>,
}

impl HostKind for Disk {
    type Desc = DiskDesc;
    const TABLE: &'static str =
        "The disks: their plane (as the planes' table), radius, inner radius.";
    const FEATURE: Option<&'static str> = Some("disk");
    const NAMES: &'static [&'static str] = &["Plane"];

    fn material(d: &DiskDesc) -> &str {
        &d.material
    }

    fn name(d: &DiskDesc) -> Option<&str> {
        d.name.as_deref()
    }

    fn numbers(d: &mut DiskDesc, f: &mut dyn FnMut(&'static str, Number, &mut [f64])) {
        f("center", Number::Position, &mut d.center);
        f("normal", Number::Direction, &mut d.normal);
        f(
            "radius",
            Number::Length,
            std::slice::from_mut(&mut d.radius),
        );
        f("inner", Number::Length, std::slice::from_mut(&mut d.inner));
    }

    fn core(item: &Item, d: &DiskDesc) -> Result<Self, DescError> {
        let center = item.v3(d.center, Field::DiskCenter)?;
        let normal = item.v3(d.normal, Field::DiskNormal)?;
        let radius = item.f1(d.radius, Field::DiskRadius)?;
        let inner = item.f1(d.inner, Field::DiskInnerRadius)?;
        Disk::try_new(center, normal, radius, inner).map_err(|e| {
            let fields = [
                (Field::DiskCenter, &d.center[..]),
                (Field::DiskNormal, &d.normal[..]),
                (Field::DiskRadius, std::slice::from_ref(&d.radius)),
            ];
            item.core(e, value_for(e, &fields, &[d.inner]))
        })
    }

    fn baked(&self) -> String {
        let (point, normal, offset, [t, u]) = self.plane().parts();
        format!(
            "Disk::baked(Plane::baked({}, {}, {}, [{}, {}]), {}, {})",
            vec3(point),
            vec3(normal),
            lit(offset),
            vec3(t),
            vec3(u),
            lit(self.radius()),
            lit(self.inner())
        )
    }

    #[cfg(feature = "cli")]
    fn reference(d: &DiskDesc) -> crate::reference::geometry::Shape {
        let v = crate::reference::vec::V3::from_array;
        crate::reference::geometry::Shape::Disk {
            center: v(d.center),
            normal: v(d.normal).normalize(),
            radius: d.radius,
            inner: d.inner,
        }
    }
}
