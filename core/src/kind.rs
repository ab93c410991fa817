//! The geometry kinds, declared once, and a scene's capacities by name.
//!
//! [`__kinds!`](crate::__kinds) is the one list of the kinds (their order, which is the order
//! the searches visit their lists and the order of ties, their names, their
//! types). What is per kind is generated from it: the scene's own lists
//! (`Store`), the lists a view borrows ([`Primitives`]), the tile's candidate
//! lists (`PerKind`), the capacities ([`Capacities`], [`Counts`]) and the
//! numbering (`Kind`). A new kind is one line of that list, after the others
//! (so that the existing kinds keep their numbers and their ties).
//!
//! A scene's capacities are a type made by name with [`capacities!`](crate::capacities):
//!
//! ```
//! use tessera_core::{capacities, Scene};
//! type Chapter = Scene<capacities!(spheres: 4, planes: 1, materials: 5, lights: 1)>;
//! ```
//!
//! Names in any order; a list not named holds nothing (capacity 0: no RAM and no
//! loop for it); `..N` gives every list not named the capacity `N`. A name that
//! is not a list is a compile error naming it (``struct `Counts` has no field
//! named `sphres` ``).

use crate::primitive::Primitive;
use heapless::vec::VecView;

/// The list of the geometry kinds: `__kinds!({m} args)` calls `m! { [args]
/// rows }` with one row per kind, `(Kind variant, list name, List variant,
/// type, name in a scene file)`, in search order. Every per-kind item of the
/// core is generated from it. The kinds behind a feature (`cylinder`, `disk`)
/// join the list through one macro each, which adds its row when the feature
/// is on: a firmware without them compiles no code of theirs and tests no list
/// of theirs.
#[doc(hidden)]
#[macro_export]
macro_rules! __kinds {
    ({$($m:tt)*} $($args:tt)*) => {
        $crate::__kinds_cylinder! { {$($m)*} [$($args)*]
            (Sphere,   spheres,   Spheres,   $crate::geometry::Sphere,   "sphere"),
            (Plane,    planes,    Planes,    $crate::geometry::Plane,    "plane"),
            (Triangle, triangles, Triangles, $crate::geometry::Triangle, "triangle"),
            (Box,      boxes,     Boxes,     $crate::geometry::Aabb,     "box"),
        }
    };
}

/// [`__kinds!`](crate::__kinds)'s rows and, with the feature `cylinder`, the
/// cylinder's.
#[cfg(feature = "cylinder")]
#[doc(hidden)]
#[macro_export]
macro_rules! __kinds_cylinder {
    ({$($m:tt)*} [$($args:tt)*] $($rows:tt)*) => {
        $crate::__kinds_disk! { {$($m)*} [$($args)*] $($rows)*
            (Cylinder, cylinders, Cylinders, $crate::geometry::Cylinder, "cylinder"),
        }
    };
}

/// [`__kinds!`](crate::__kinds)'s rows (the feature `cylinder` is off).
#[cfg(not(feature = "cylinder"))]
#[doc(hidden)]
#[macro_export]
macro_rules! __kinds_cylinder {
    ({$($m:tt)*} [$($args:tt)*] $($rows:tt)*) => {
        $crate::__kinds_disk! { {$($m)*} [$($args)*] $($rows)* }
    };
}

/// The rows so far and, with the feature `disk`, the disk's: the last of the
/// list, which calls `m`.
#[cfg(feature = "disk")]
#[doc(hidden)]
#[macro_export]
macro_rules! __kinds_disk {
    ({$($m:tt)*} [$($args:tt)*] $($rows:tt)*) => {
        $($m)*! { [$($args)*] $($rows)*
            (Disk,     disks,     Disks,     $crate::geometry::Disk,     "disk"),
        }
    };
}

/// The rows so far (the feature `disk` is off): the last of the list, which
/// calls `m`.
#[cfg(not(feature = "disk"))]
#[doc(hidden)]
#[macro_export]
macro_rules! __kinds_disk {
    ({$($m:tt)*} [$($args:tt)*] $($rows:tt)*) => {
        $($m)*! { [$($args)*] $($rows)* }
    };
}

/// One capacity as a type ([`Cap`]): the list of that many items it stores.
pub trait Capacity: 'static {
    /// The capacity.
    const N: usize;
    /// A list of at most [`Capacity::N`] items of `T`.
    type List<T>: ListStore<T>;
}

/// The capacity `N`.
#[derive(Debug)]
pub struct Cap<const N: usize>;

impl<const N: usize> Capacity for Cap<N> {
    const N: usize = N;
    type List<T> = heapless::Vec<T, N>;
}

/// A fixed-capacity list, whatever its capacity.
pub trait ListStore<T> {
    /// The empty list.
    const EMPTY: Self;
    /// The list without its capacity in its type.
    fn view(&self) -> &VecView<T>;
    /// The same, mutable.
    fn view_mut(&mut self) -> &mut VecView<T>;
    /// A copy.
    #[must_use]
    fn clone_list(&self) -> Self
    where
        T: Clone;
}

impl<T, const N: usize> ListStore<T> for heapless::Vec<T, N> {
    const EMPTY: Self = heapless::Vec::new();
    #[inline(always)]
    fn view(&self) -> &VecView<T> {
        self.as_view()
    }
    #[inline(always)]
    fn view_mut(&mut self) -> &mut VecView<T> {
        self.as_mut_view()
    }
    #[inline]
    fn clone_list(&self) -> Self
    where
        T: Clone,
    {
        self.clone()
    }
}

/// A geometry kind's type (one of the list's, sealed): what
/// [`Scene::add`](crate::Scene::add) adds and
/// [`SceneView::list`](crate::SceneView::list) reads.
pub trait Geometry: sealed::Sealed + Copy + core::fmt::Debug + PartialEq + 'static {
    /// Its kind.
    const KIND: Kind;
    /// Its list among `primitives`.
    fn of<'a>(primitives: &Primitives<'a>) -> &'a [Primitive<Self>];
    /// Its list in a scene's own lists.
    #[doc(hidden)]
    fn list_mut<C: Capacities>(store: &mut Store<C>) -> &mut VecView<Primitive<Self>>;
    /// The points whose box holds it when it is flat and bounded by them (a
    /// triangle's vertices: the scene keeps their box as the list's hull).
    #[doc(hidden)]
    fn hull_points(&self) -> Option<[crate::Vec3; 3]>;
    /// The same geometry with every length multiplied by `f` (checked again).
    #[doc(hidden)]
    fn scaled(&self, f: f32) -> Result<Self, crate::Error>;
    /// `primitives` with `list` as its list of this kind.
    #[doc(hidden)]
    fn set<'a>(primitives: &mut Primitives<'a>, list: &'a [Primitive<Self>]);
    /// Whether the value is what its checked constructor makes of its own
    /// numbers (`Err`: numbers the constructor refuses).
    #[doc(hidden)]
    fn is_as_made(&self) -> Result<bool, crate::Error>;
}

/// The empty list of capacity `C`.
pub(crate) const fn empty<C: Capacity, T>() -> C::List<T> {
    <C::List<T> as ListStore<T>>::EMPTY
}

macro_rules! define {
    ([] $( ($K:ident, $f:ident, $L:ident, $T:ty, $name:literal) ),* $(,)?) => {
        /// The geometry kinds, in the order the searches visit their lists (the
        /// meshes, feature `bvh`, last): the order of ties between equally near
        /// hits, and the numbering of the adaptive sampler's hit signatures
        /// ([`Kind::index`]), which the host's reference follows.
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        #[non_exhaustive]
        pub enum Kind {
            $(
                #[doc = concat!("The ", stringify!($f), ".")]
                $K,
            )*
            /// The faces of the meshes (feature `bvh`).
            #[cfg(feature = "bvh")]
            Mesh,
        }

        impl Kind {
            /// The kinds of the lists, in search order (the meshes' faces not
            /// among them).
            pub const ALL: [Kind; KINDS] = [$(Kind::$K),*];

            /// The kind's name in a scene file (`"sphere"`, `"box"`).
            #[must_use]
            pub const fn name(self) -> &'static str {
                match self {
                    $(Kind::$K => $name,)*
                    #[cfg(feature = "bvh")]
                    Kind::Mesh => "mesh",
                }
            }

            /// The kind's number: its place in the search order.
            #[must_use]
            pub const fn index(self) -> usize {
                self as usize
            }
        }

        /// How many geometry kinds a scene has lists of.
        pub const KINDS: usize = [$(stringify!($K)),*].len();

        /// Each kind's list, as errors name it, in search order.
        pub(crate) const LISTS: [crate::error::List; KINDS] = [$(crate::error::List::$L),*];

        impl Kind {
            /// The kind's list, as errors name it.
            #[must_use]
            pub const fn list(self) -> crate::error::List {
                match self {
                    $(Kind::$K => crate::error::List::$L,)*
                    #[cfg(feature = "bvh")]
                    Kind::Mesh => crate::error::List::Meshes,
                }
            }
        }

        /// A scene's capacities as numbers, by name: what a [`Capacities`] type
        /// holds ([`Capacities::COUNTS`]), and what
        /// [`capacities!`](crate::capacities) is written with.
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        pub struct Counts {
            $(
                #[doc = concat!("The ", stringify!($f), ".")]
                pub $f: usize,
            )*
            /// The materials.
            pub materials: usize,
            /// The lights.
            pub lights: usize,
        }

        impl Counts {
            /// Every capacity 0.
            pub const ZERO: Self = Self::splat(0);

            /// Every capacity `n`.
            #[must_use]
            pub const fn splat(n: usize) -> Self {
                Self { $($f: n,)* materials: n, lights: n }
            }

            /// The geometry kinds' capacities, in search order.
            #[must_use]
            pub const fn kinds(&self) -> [usize; KINDS] {
                [$(self.$f),*]
            }
        }

        /// A scene's capacities as a type: made by
        /// [`capacities!`](crate::capacities) (sealed: there is no other way to
        /// make one, so that a new kind changes no user's code).
        pub trait Capacities:
            sealed::Sealed + Clone + Copy + core::fmt::Debug + Default + 'static
        {
            $(
                #[doc = concat!("The capacity of the ", stringify!($f), ".")]
                type $L: Capacity;
            )*
            /// The capacity of the materials.
            type Materials: Capacity;
            /// The capacity of the lights.
            type Lights: Capacity;
            /// The capacities as numbers.
            const COUNTS: Counts = Counts {
                $($f: <Self::$L as Capacity>::N,)*
                materials: <Self::Materials as Capacity>::N,
                lights: <Self::Lights as Capacity>::N,
            };
        }

        /// The capacities, positional: spelled only by
        /// [`capacities!`](crate::capacities), whose names say which is which.
        #[doc(hidden)]
        #[allow(non_upper_case_globals)]
        #[derive(Clone, Copy, Debug, Default)]
        pub struct Caps<$(const $L: usize,)* const MATERIALS: usize, const LIGHTS: usize>;

        #[allow(non_upper_case_globals)]
        impl<$(const $L: usize,)* const MATERIALS: usize, const LIGHTS: usize> sealed::Sealed
            for Caps<$($L,)* MATERIALS, LIGHTS>
        {
        }

        #[allow(non_upper_case_globals)]
        impl<$(const $L: usize,)* const MATERIALS: usize, const LIGHTS: usize> Capacities
            for Caps<$($L,)* MATERIALS, LIGHTS>
        {
            $(type $L = Cap<$L>;)*
            type Materials = Cap<MATERIALS>;
            type Lights = Cap<LIGHTS>;
        }

        /// `N` of every list (the tile lists lent to a scene that holds few of
        /// what its capacities allow).
        #[derive(Clone, Copy, Debug, Default)]
        pub(crate) struct Uniform<const N: usize>;

        impl<const N: usize> sealed::Sealed for Uniform<N> {}

        impl<const N: usize> Capacities for Uniform<N> {
            $(type $L = Cap<N>;)*
            type Materials = Cap<N>;
            type Lights = Cap<N>;
        }

        /// A scene's primitives, one borrowed list per kind: what a view reads
        /// and what [`crate::BakedScene::new`] is given (`..Primitives::NONE` for
        /// the kinds a scene has none of).
        #[derive(Clone, Copy, Debug)]
        pub struct Primitives<'a> {
            $(
                #[doc = concat!("The ", stringify!($f), ".")]
                pub $f: &'a [Primitive<$T>],
            )*
        }

        impl<'a> Primitives<'a> {
            /// No primitive of any kind.
            pub const NONE: Self = Self { $($f: &[],)* };

            /// The length of each kind's list, in search order.
            #[must_use]
            pub const fn lens(&self) -> [usize; KINDS] {
                [$(self.$f.len()),*]
            }
        }

        $(
            impl sealed::Sealed for $T {}

            impl Geometry for $T {
                const KIND: Kind = Kind::$K;
                #[inline(always)]
                fn of<'a>(primitives: &Primitives<'a>) -> &'a [Primitive<Self>] {
                    primitives.$f
                }
                #[inline(always)]
                fn list_mut<C: Capacities>(store: &mut Store<C>) -> &mut VecView<Primitive<Self>> {
                    store.$f.view_mut()
                }
                #[inline]
                fn hull_points(&self) -> Option<[crate::Vec3; 3]> {
                    match crate::geometry::Kinded::extent(self) {
                        crate::geometry::Extent::Points(p) => Some(p),
                        _ => None,
                    }
                }
                fn scaled(&self, f: f32) -> Result<Self, crate::Error> {
                    crate::geometry::Kinded::scaled(self, f)
                }
                #[inline]
                fn set<'a>(primitives: &mut Primitives<'a>, list: &'a [Primitive<Self>]) {
                    primitives.$f = list;
                }
                fn is_as_made(&self) -> Result<bool, crate::Error> {
                    crate::geometry::Kinded::check_baked(self)
                }
            }
        )*

        /// A scene's own lists of primitives, of its capacities `C`.
        #[doc(hidden)]
        pub struct Store<C: Capacities> {
            $(pub(crate) $f: <C::$L as Capacity>::List<Primitive<$T>>,)*
        }

        impl<C: Capacities> Store<C> {
            /// Every list empty.
            pub(crate) const EMPTY: Self = Self { $($f: empty::<C::$L, Primitive<$T>>(),)* };

            /// The lists, borrowed.
            #[inline(always)]
            pub(crate) fn primitives(&self) -> Primitives<'_> {
                Primitives { $($f: self.$f.view(),)* }
            }
        }

        impl<C: Capacities> Clone for Store<C> {
            fn clone(&self) -> Self {
                Self { $($f: self.$f.clone_list(),)* }
            }
        }

        /// One list of `T` per kind, each of its kind's capacity in `C` (a tile's
        /// candidate lists).
        pub(crate) struct PerKind<C: Capacities, T> {
            $($f: <C::$L as Capacity>::List<T>,)*
        }

        impl<C: Capacities, T> PerKind<C, T> {
            /// Every list empty.
            pub(crate) const EMPTY: Self = Self { $($f: empty::<C::$L, T>(),)* };

            /// The lists, in search order.
            #[inline(always)]
            pub(crate) fn views(&mut self) -> [&mut VecView<T>; KINDS] {
                [$(self.$f.view_mut()),*]
            }
        }
    };
}

__kinds!({ define });

/// `$body` once per kind of the list, in search order, with `$G` the kind's
/// type (a block each: `return` and `?` work as in the caller).
macro_rules! each_kind {
    (|$G:ident| $body:block) => {
        $crate::__kinds!({$crate::__each_kind_blocks} $G, $body)
    };
}
pub(crate) use each_kind;

#[doc(hidden)]
#[macro_export]
macro_rules! __each_kind_blocks {
    ([$G:ident, $body:block]
        $( ($K:ident, $f:ident, $L:ident, $T:ty, $name:literal) ),* $(,)?) => {
        $(
            {
                type $G = $T;
                $body
            }
        )*
    };
}

/// `$body` with `$G` the type of the kind `$kind` (a [`Kind`] other than the
/// meshes'; `$mesh` for those): one `match` arm per kind of the list.
macro_rules! match_kind {
    ($kind:expr, |$G:ident| $body:expr, Mesh => $mesh:expr) => {
        $crate::__kinds!({$crate::__match_kind_arms} $kind, $G, $body, $mesh)
    };
}
pub(crate) use match_kind;

#[doc(hidden)]
#[macro_export]
macro_rules! __match_kind_arms {
    ([$kind:expr, $G:ident, $body:expr, $mesh:expr]
        $( ($K:ident, $f:ident, $L:ident, $T:ty, $name:literal) ),* $(,)?) => {
        match $kind {
            $(
                $crate::kind::Kind::$K => {
                    type $G = $T;
                    $body
                }
            )*
            #[cfg(feature = "bvh")]
            $crate::kind::Kind::Mesh => $mesh,
        }
    };
}

mod sealed {
    /// Only the core's capacity types are [`super::Capacities`].
    pub trait Sealed {}
}

#[doc(hidden)]
#[macro_export]
macro_rules! __capacities_type {
    ([$init:tt] $( ($K:ident, $f:ident, $L:ident, $T:ty, $name:literal) ),* $(,)?) => {
        $crate::kind::Caps<
            $( { $crate::__counts!($init).$f }, )*
            { $crate::__counts!($init).materials },
            { $crate::__counts!($init).lights },
        >
    };
}

/// The [`Counts`] value `Counts { .. }` of `capacities!`'s names (naming every
/// list makes the `..` that completes it needless).
#[doc(hidden)]
#[macro_export]
macro_rules! __counts {
    ($init:tt) => {{
        #[allow(clippy::needless_update)]
        let counts = $crate::kind::Counts $init;
        counts
    }};
}

/// A scene's capacities by name, as a type (see the module [`crate::kind`]):
/// `Scene<capacities!(spheres: 4, planes: 1, materials: 5, lights: 1)>`,
/// `BakedScene<'static, capacities!(spheres: 2)>`. The names are those of
/// [`Counts`](crate::kind::Counts) (`spheres`, `planes`, `triangles`, `boxes`,
/// `materials`, `lights`); a list not named holds nothing, or `N` after `..N`.
#[macro_export]
macro_rules! capacities {
    ($($name:ident : $value:expr,)* .. $rest:expr) => {
        $crate::__kinds!({$crate::__capacities_type}
            { $($name: $value,)* ..$crate::kind::Counts::splat($rest) })
    };
    ($($name:ident : $value:expr),* $(,)?) => {
        $crate::__kinds!({$crate::__capacities_type}
            { $($name: $value,)* ..$crate::kind::Counts::ZERO })
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn capacities_are_named_in_any_order_and_default_to_zero() {
        type C = crate::capacities!(lights: 3, spheres: 4, boxes: 1);
        assert_eq!(
            C::COUNTS,
            Counts {
                spheres: 4,
                boxes: 1,
                lights: 3,
                ..Counts::ZERO
            }
        );
        type H = crate::capacities!(planes: 64, triangles: 8192, ..1024);
        assert_eq!(H::COUNTS.kinds()[..4], [1024, 64, 8192, 1024]);
        assert!(H::COUNTS.kinds()[4..].iter().all(|&n| n == 1024));
        assert_eq!((H::COUNTS.materials, H::COUNTS.lights), (1024, 1024));
        assert_eq!(<crate::capacities!() as Capacities>::COUNTS, Counts::ZERO);
    }

    #[test]
    fn the_kinds_are_numbered_in_search_order() {
        // The first four keep their numbers as kinds are added after them.
        const { assert!(KINDS >= 4) };
        assert_eq!(
            [Kind::Sphere, Kind::Plane, Kind::Triangle, Kind::Box].map(|k| k as usize),
            [0, 1, 2, 3]
        );
        for (i, k) in Kind::ALL.into_iter().enumerate() {
            assert_eq!(k.index(), i);
        }
        #[cfg(feature = "bvh")]
        assert_eq!(Kind::Mesh as usize, KINDS);
    }
}
