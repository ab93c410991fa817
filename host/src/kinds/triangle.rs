//! The triangle on the host (the faces of the meshes are triangles too: see
//! [`crate::desc::MeshDesc`]).

use super::{HostKind, Number};
use crate::desc::{DescError, Item, core_triangle};
use serde::Deserialize;
use tessera_core::geometry::Triangle;

/// A triangle.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TriangleDesc {
    /// Its three vertices.
    pub vertices: [[f64; 3]; 3],
    /// Material name.
    pub material: String,
    /// Its name (`name = "red ball"`), unique among the scene's objects and
    /// lights: the baker's constant for it, the host's lookup (`SceneDesc::find`).
    #[serde(default)]
    pub name: Option<String>,
}

impl HostKind for Triangle {
    type Desc = TriangleDesc;
    const TABLE: &'static str = "The triangles, in the scene's order.";

    fn material(d: &TriangleDesc) -> &str {
        &d.material
    }

    fn name(d: &TriangleDesc) -> Option<&str> {
        d.name.as_deref()
    }

    fn numbers(d: &mut TriangleDesc, f: &mut dyn FnMut(&'static str, Number, &mut [f64])) {
        for v in &mut d.vertices {
            f("vertices", Number::Position, v);
        }
    }

    fn core(item: &Item, d: &TriangleDesc) -> Result<Self, DescError> {
        core_triangle(item, &d.vertices)
    }

    fn baked(&self) -> String {
        let [a, b, c] = self.vertices().map(crate::bake::v3);
        format!("Triangle::baked({a}, {b}, {c})")
    }

    #[cfg(feature = "cli")]
    fn reference(d: &TriangleDesc) -> crate::reference::geometry::Shape {
        crate::reference::geometry::Shape::Triangle {
            p: d.vertices.map(crate::reference::vec::V3::from_array),
        }
    }
}
