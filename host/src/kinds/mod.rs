//! The geometry kinds on the host, one file each: a kind's item of a scene
//! file, its conversion to the core's geometry (every value checked, refused
//! with its item and the value at fault), the literal `tessera bake` writes for
//! it and its shape in the `f64` reference. Everything the host does per kind
//! (the scene file's lists, their counts, the subnormal rule, the bake tables,
//! the reference's objects) loops over the core's one list of kinds
//! ([`each_kind!`]) through [`HostKind`].

use crate::desc::{DescError, Item, SceneDesc};
use serde::de::DeserializeOwned;
use std::fmt;

mod aabb;
mod cylinder;
mod disk;
mod plane;
mod sphere;
mod triangle;

pub use aabb::BoxDesc;
pub use cylinder::CylinderDesc;
pub use disk::DiskDesc;
pub use plane::PlaneDesc;
pub use sphere::SphereDesc;
pub use triangle::TriangleDesc;

/// What a number of an item is, for what moves it: a position or a length
/// scales with the scene, a direction does not.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Number {
    /// A point (three numbers).
    Position,
    /// A length (a radius, a height).
    Length,
    /// A direction (three numbers, any length).
    Direction,
}

/// A geometry kind of the core, on the host.
pub trait HostKind: tessera_core::Geometry {
    /// Its item of a scene file (`[[sphere]]`).
    type Desc: DeserializeOwned + Clone + fmt::Debug + PartialEq;

    /// The doc line of its table in a baked file (what each entry holds).
    const TABLE: &'static str;

    /// The core's feature that compiles the kind in (none: always there): a
    /// baked file that holds some says it needs it.
    const FEATURE: Option<&'static str> = None;

    /// The core's names its baked literal uses beside its own type.
    const NAMES: &'static [&'static str] = &[];

    /// The item's material name.
    fn material(d: &Self::Desc) -> &str;

    /// The item's name, if the scene file gives it one.
    fn name(d: &Self::Desc) -> Option<&str>;

    /// Each of the item's numbers, by key (as messages name them) and what it
    /// is: `f(key, what, numbers)`, in the order of the item's fields.
    fn numbers(d: &mut Self::Desc, f: &mut dyn FnMut(&'static str, Number, &mut [f64]));

    /// The core's geometry of the item, every value checked; refused with the
    /// item and the value at fault.
    ///
    /// # Errors
    /// What the core (or `f32`) refuses of the item.
    fn core(item: &Item, d: &Self::Desc) -> Result<Self, DescError>;

    /// The expression `tessera bake` writes for it (`Sphere::baked([0.0, 1.0,
    /// 0.0], 0.5)`): its constructor for baked data, with the values it holds.
    fn baked(&self) -> String;

    /// Its shape in the `f64` reference, from the description's own numbers.
    #[cfg(feature = "cli")]
    fn reference(d: &Self::Desc) -> crate::reference::geometry::Shape;
}

/// A kind's list in a scene description (generated for every kind, with
/// [`SceneDesc`]).
pub trait Listed: HostKind {
    /// The kind's items of `s`.
    fn descs(s: &SceneDesc) -> &[Self::Desc];
    /// The same, to change.
    fn descs_mut(s: &mut SceneDesc) -> &mut Vec<Self::Desc>;
}

/// `$body` once per geometry kind of the core's list, in search order, with
/// `$G` the kind's core type (a block each: `return` and `?` work as in the
/// caller).
#[macro_export]
#[doc(hidden)]
macro_rules! __host_each_kind {
    (|$G:ident| $body:block) => {
        tessera_core::__kinds!({tessera_core::__each_kind_blocks} $G, $body)
    };
}
pub use crate::__host_each_kind as each_kind;

/// The name of a kind's core type (`Sphere`, `Aabb`), as a baked file spells it.
#[must_use]
pub fn type_name<G: tessera_core::Geometry>() -> &'static str {
    let full = std::any::type_name::<G>();
    full.rsplit("::").next().unwrap_or(full)
}

/// The names of every kind's core type, in search order.
#[must_use]
pub fn type_names() -> Vec<&'static str> {
    let mut out = Vec::new();
    each_kind!(|G| {
        out.push(type_name::<G>());
    });
    out
}
