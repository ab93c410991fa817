//! The nearest hit resolved into the chapter's [`Hit`]: the point and its normal,
//! the material, the texture's colour there, and what a ray leaving it must not
//! test again.

use crate::color::Color;
use crate::geometry::Kinded;
#[cfg(feature = "bvh")]
use crate::geometry::Shape;
use crate::geometry::{Candidate, Locate, Surface};
use crate::kind::{Geometry, match_kind};
use crate::material::Material;
use crate::prefilter::{Footprint, uv_box};
use crate::primitive::Primitive;
use crate::ray::Ray;
#[cfg(feature = "bvh")]
use crate::search::MeshFace;
use crate::search::{Kind, Nearest, Skip};
use crate::vec::Vec3;
use crate::view::SceneView;

macro_rules! geom {
    ([] $( ($K:ident, $f:ident, $L:ident, $T:ty, $name:literal) ),* $(,)?) => {
        /// A primitive of any kind, by reference.
        #[derive(Clone, Copy, Debug)]
        pub(crate) enum Geom<'a> {
            $($K(&'a $T),)*
            /// A face of a mesh (feature `bvh`); which face, the hit's index says
            /// ([`MeshFace`]), so that a `Geom` stays a tag and a pointer.
            #[cfg(feature = "bvh")]
            Mesh(&'a crate::mesh::Mesh<'a>),
            /// A face of an instance of a mesh (feature `instances`); which
            /// face, the hit's index says.
            #[cfg(feature = "instances")]
            Placed(&'a crate::instance::Placed<'a>),
        }

        impl Geom<'_> {
            /// Its kind, and whether it is flat ([`Kinded::FLAT`]; a mesh's face
            /// is).
            #[inline(always)]
            pub(crate) fn kind(self) -> (Kind, bool) {
                match self {
                    $(Self::$K(_) => (Kind::$K, <$T as Kinded>::FLAT),)*
                    #[cfg(feature = "bvh")]
                    Self::Mesh(..) => (Kind::Mesh, true),
                    #[cfg(feature = "instances")]
                    Self::Placed(..) => (Kind::Mesh, true),
                }
            }

            /// [`Locate::error`] of whichever kind it is; `index` is the hit's (a
            /// mesh's face is the triangle its [`MeshFace`] names).
            #[inline(always)]
            pub(crate) fn error(
                self,
                #[cfg_attr(not(feature = "bvh"), allow(unused_variables))] index: usize,
                ray: &Ray,
                hit: &Candidate,
                point: Vec3,
                aux: Vec3,
            ) -> Vec3 {
                match self {
                    $(Self::$K(g) => g.error(ray, hit, point, aux),)*
                    #[cfg(feature = "bvh")]
                    Self::Mesh(m) => m
                        .triangle(MeshFace::of(index).face)
                        .map_or(Vec3::ZERO, |t| t.error(ray, hit, point, aux)),
                    #[cfg(feature = "instances")]
                    Self::Placed(p) => {
                        let _ = (point, aux);
                        p.error(MeshFace::of(index).face, ray, hit)
                    }
                }
            }
        }

        /// A primitive of a kind as a [`Geom`].
        pub(crate) trait AsGeom {
            /// `self` as a [`Geom`].
            fn geom(&self) -> Geom<'_>;
        }

        $(
            impl AsGeom for $T {
                #[inline(always)]
                fn geom(&self) -> Geom<'_> {
                    Geom::$K(self)
                }
            }
        )*
    };
}

crate::__kinds!({ geom });

/// The chapter's hit, resolved from the nearest [`Candidate`] (time `hit.t`): the
/// point and its normal, its material, the colour of the texture there (its uv
/// evaluated only if textured, box-filtered over the pixel's footprint for the
/// prefiltered sampler) and which primitive it is. The error
/// bound of the point, which only a ray leaving it needs, is computed on demand
/// ([`Hit::error`]).
pub(crate) struct Hit<'a> {
    pub(crate) point: Vec3,
    /// The outward unit normal.
    pub(crate) normal: Vec3,
    /// What the error bound needs besides the point (see `Locate`).
    pub(crate) aux: Vec3,
    pub(crate) hit: Candidate,
    pub(crate) geom: Geom<'a>,
    pub(crate) index: usize,
    pub(crate) material: &'a Material,
    pub(crate) base: Color,
    /// The error bound, once computed (shadow rays, then the bounces, share it).
    pub(crate) error: core::cell::Cell<Option<Vec3>>,
}

impl Hit<'_> {
    /// The bound on the rounding error of each component of the point (`ray` is
    /// the ray that hit it).
    ///
    /// Computed once per hit, out of line ([`Hit::compute_error`]); the check
    /// of the cached value is inlined.
    #[inline(always)]
    pub(crate) fn error(&self, ray: &Ray) -> Vec3 {
        match self.error.get() {
            Some(e) => e,
            None => self.compute_error(ray),
        }
    }

    /// [`Hit::error`] when not yet known.
    #[inline(never)]
    fn compute_error(&self, ray: &Ray) -> Vec3 {
        let e = self
            .geom
            .error(self.index, ray, &self.hit, self.point, self.aux);
        self.error.set(Some(e));
        e
    }

    /// What a ray leaving this hit in direction `w` must not test: this primitive,
    /// when `w` leaves it for good (see the module doc): always for a flat one
    /// (plane, triangle), for a closed convex one when `w . n > 0` with the outward
    /// normal `n`, which is also the side `offset_origin` moves the origin to.
    pub(crate) fn skip_for(&self, w: Vec3) -> Skip {
        let (kind, flat) = self.geom.kind();
        if flat || w.dot(self.normal) > 0.0 {
            Skip::new(kind, self.index)
        } else {
            Skip::NONE
        }
    }
}

#[inline(always)]
fn resolve_in<'a, G: Locate + AsGeom>(
    view: &SceneView<'a>,
    list: &'a [Primitive<G>],
    n: &Nearest,
    ray: &Ray,
    footprint: Option<&Footprint<'_>>,
) -> Option<Hit<'a>> {
    let prim = list.get(n.index)?;
    let material = view.materials.get(usize::from(prim.material.0))?;
    let (point, normal, aux) = prim.geometry.locate(ray, &n.hit);
    let texture = material.texture();
    let base = if texture.needs_uv() {
        // The uv need no error bound.
        let surface = Surface {
            point,
            normal,
            error: Vec3::ZERO,
        };
        let uv = prim.geometry.uv(&surface, &n.hit);
        match footprint.and_then(|f| uv_box(&prim.geometry, f, uv, own_uv)) {
            Some((lo, hi)) => texture.eval_box(lo, hi),
            None => texture.eval(uv),
        }
    } else {
        texture.eval([0.0, 0.0])
    };
    Some(Hit {
        point,
        normal,
        aux,
        hit: n.hit,
        geom: prim.geometry.geom(),
        index: n.index,
        material,
        base,
        error: core::cell::Cell::new(None),
    })
}

/// A shape's own uv as the texture's (one function, so that a triangle's and a
/// flat-mapped mesh face's footprints share one copy of `uv_box`).
#[inline(always)]
fn own_uv(uv: [f32; 2]) -> [f32; 2] {
    uv
}

/// [`resolve`] for a face of a mesh (`n.index` names a [`MeshFace`]): the
/// face as a triangle, the mesh's material. (The texture lookup is `resolve`'s,
/// written again on purpose: one helper for both, even `#[inline(always)]`, makes
/// the test firmware's code larger, as llvm-size shows.)
#[cfg(feature = "bvh")]
#[inline(always)]
fn resolve_mesh<'a>(
    view: &SceneView<'a>,
    n: &Nearest,
    ray: &Ray,
    footprint: Option<&Footprint<'_>>,
) -> Option<Hit<'a>> {
    let at = MeshFace::of(n.index);
    #[cfg(feature = "instances")]
    if at.mesh >= crate::mesh::MAX_MESHES {
        return resolve_placed(view, n, ray, footprint);
    }
    let mesh = view.meshes.get(at.mesh)?;
    let face = u16::try_from(at.face).ok()?;
    let tri = mesh.triangle(usize::from(face))?;
    let material = view.materials.get(usize::from(mesh.material().0))?;
    let (point, normal, aux) = tri.locate(ray, &n.hit);
    let texture = material.texture();
    let base = if texture.needs_uv() {
        let surface = Surface {
            point,
            normal,
            error: Vec3::ZERO,
        };
        // The face's own uv (its barycentrics) through the mesh's vertex uvs.
        let own = tri.uv(&surface, &n.hit);
        let at = usize::from(face);
        let uv = mesh.uv(at, own);
        let footprint = match footprint {
            Some(f) if mesh.uvs().is_empty() => uv_box(&tri, f, uv, own_uv),
            Some(f) => uv_box(&tri, f, uv, |b| mesh.uv(at, b)),
            None => None,
        };
        match footprint {
            Some((lo, hi)) => texture.eval_box(lo, hi),
            None => texture.eval(uv),
        }
    } else {
        texture.eval([0.0, 0.0])
    };
    Some(Hit {
        point,
        normal,
        aux,
        hit: n.hit,
        geom: Geom::Mesh(mesh),
        index: n.index,
        material,
        base,
        error: core::cell::Cell::new(None),
    })
}

/// [`resolve_mesh`] for a face of an instance: the face carried into the
/// world (module `instance`), then resolved as a mesh's.
#[cfg(feature = "instances")]
#[inline(never)]
fn resolve_placed<'a>(
    view: &SceneView<'a>,
    n: &Nearest,
    ray: &Ray,
    footprint: Option<&Footprint<'_>>,
) -> Option<Hit<'a>> {
    let at = MeshFace::of(n.index);
    let placed = view.instances.get(at.mesh - crate::mesh::MAX_MESHES)?;
    let mesh = placed.mesh;
    let face = at.face;
    let material = view.materials.get(usize::from(mesh.material().0))?;
    let (own_tri, _, local, local_normal, aux) = placed.locate(face, ray, &n.hit)?;
    let (point, normal) = placed.carry(local, local_normal);
    let texture = material.texture();
    let base = if texture.needs_uv() {
        let surface = Surface {
            point: local,
            normal: local_normal,
            error: Vec3::ZERO,
        };
        let own = own_tri.uv(&surface, &n.hit);
        // The pixel's footprint is the world's: the face carried there.
        let tri = placed.triangle(face)?;
        let uv = mesh.uv(face, own);
        let footprint = match footprint {
            Some(f) if mesh.uvs().is_empty() => uv_box(&tri, f, uv, own_uv),
            Some(f) => uv_box(&tri, f, uv, |b| mesh.uv(face, b)),
            None => None,
        };
        match footprint {
            Some((lo, hi)) => texture.eval_box(lo, hi),
            None => texture.eval(uv),
        }
    } else {
        texture.eval([0.0, 0.0])
    };
    Some(Hit {
        point,
        normal,
        aux,
        hit: n.hit,
        geom: Geom::Placed(placed),
        index: n.index,
        material,
        base,
        error: core::cell::Cell::new(None),
    })
}

/// The [`Hit`] of `n` (inlined where it is called: the camera ray's shading and
/// the bounces' each have their copy).
#[inline(always)]
pub(crate) fn resolve<'a>(
    view: &SceneView<'a>,
    n: &Nearest,
    ray: &Ray,
    footprint: Option<&Footprint<'_>>,
) -> Option<Hit<'a>> {
    match_kind!(
        n.kind,
        |G| resolve_in(view, G::of(&view.primitives), n, ray, footprint),
        Mesh => resolve_mesh(view, n, ray, footprint)
    )
}
